/* vk_context.h - what one renderer holds of Vulkan: a shared device (vk_device.h) plus its own command
 * buffer and fence. */
#ifndef LUCENT_VK_CONTEXT_H
#define LUCENT_VK_CONTEXT_H

#include "gpu_faults.h"
#include "vk_device.h"

/* A frame that takes minutes means a lost device, not a slow one. */
#define VK_CONTEXT_WAIT_S 120
#define VK_CONTEXT_WAIT_NS (VK_CONTEXT_WAIT_S * 1000000000ull)

struct vk_context {
    struct vk_device *shared;
    /* Copies of the shared device's handles and properties, for brevity at every call site. */
    VkDevice device;
    VkPhysicalDeviceMemoryProperties memory;
    VkPhysicalDeviceLimits limits;
    double timestamp_ns;
    const char *device_name;
    VkCommandPool command_pool;
    VkCommandBuffer cmd;
    VkFence fence;
    uint64_t memory_bytes;    /* device memory allocated through vk_resources.h and not yet freed */
    int in_flight;            /* submitted work whose fence has not been seen signaled (a wait timed out) */
    int lost;                 /* the device was lost or hung: no more submissions */
    enum gpu_fault fault;     /* injected into the next submission (tests; gpu_faults.h) */
};

/* device_name (or $LUCENT_DEVICE) as for vk_device_acquire. */
lucent_status vk_context_create(struct vk_context *ctx, const char *device_name, int verbose,
                                lucent_error *err);
void vk_context_destroy(struct vk_context *ctx);

/* Memory type with all of `want` among `type_bits`, or UINT32_MAX. */
uint32_t vk_memory_type(const struct vk_context *ctx, uint32_t type_bits, VkMemoryPropertyFlags want);

/* Submits ctx->cmd and waits for it, at most VK_CONTEXT_WAIT_S. A wait that times out leaves the work in
 * flight (LUCENT_E_GPU); a lost device marks the context lost (LUCENT_E_DEVICE_LOST). */
lucent_status vk_submit_and_wait(struct vk_context *ctx, lucent_error *err);
/* Waits for work a timed-out wait left in flight, before anything it may use is touched or freed.
 * LUCENT_E_DEVICE_LOST on a lost context, or when that work does not finish either (a hung device:
 * the context is then lost and the work stays in flight). */
lucent_status vk_context_settle(struct vk_context *ctx, lucent_error *err);

#endif
