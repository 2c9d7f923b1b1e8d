/* gpu_faults.h - GPU faults injected on purpose, for tests of what a renderer and the daemon do when a
 * submission fails, the device is lost or a fence times out. Built only with LUCENT_FAULT_INJECTION. */
#ifndef LUCENT_GPU_FAULTS_H
#define LUCENT_GPU_FAULTS_H

enum gpu_fault {
    GPU_FAULT_NONE = 0,
    GPU_FAULT_SUBMIT,    /* vkQueueSubmit fails (VK_ERROR_OUT_OF_DEVICE_MEMORY), nothing is submitted */
    GPU_FAULT_LOST,      /* vkQueueSubmit reports VK_ERROR_DEVICE_LOST, nothing is submitted */
    GPU_FAULT_TIMEOUT,   /* the work is submitted, but the wait reports VK_TIMEOUT at once */
    GPU_FAULT_HANG       /* the work is submitted, and the wait never returns (a driver stuck in a call) */
};

#ifdef LUCENT_FAULT_INJECTION
/* The fault planned for the next frame, counting the frames of every renderer of the process from 1.
 * The plan is $LUCENT_FAULTS, read once: KIND@FRAME,... with KIND submit, lost, timeout or hang. */
enum gpu_fault gpu_fault_next_frame(void);
#else
static inline enum gpu_fault gpu_fault_next_frame(void)
{
    return GPU_FAULT_NONE;
}
#endif

#endif
