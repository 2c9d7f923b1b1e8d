/* vk_device.h - the Vulkan instance, device and queue, shared by every renderer of the process that
 * asks for the same device, and kept until lucent_shutdown(): devices are expensive to create and
 * lavapipe does not return the memory of a destroyed device (about 25 MB each). */
#ifndef LUCENT_VK_DEVICE_H
#define LUCENT_VK_DEVICE_H

#include "lucent.h"

#include <pthread.h>
#include <vulkan/vulkan.h>

struct vk_device {
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;   /* $LUCENT_VALIDATION=1 only */
    VkPhysicalDevice physical;
    VkDevice device;
    VkQueue queue;
    uint32_t queue_family;
    VkPhysicalDeviceMemoryProperties memory;
    VkPhysicalDeviceLimits limits;
    double timestamp_ns;         /* nanoseconds per timestamp tick; 0 = no timestamps */
    char device_name[VK_MAX_PHYSICAL_DEVICE_NAME_SIZE];
    char driver[2 * VK_MAX_DRIVER_NAME_SIZE + 2];
    uint32_t api_version;
    char request[128];           /* the device name asked for ("" = automatic) */
    int users;
    int lost;                    /* no more renderers get it; destroyed when the last one releases it */
    pthread_mutex_t queue_lock;  /* vkQueueSubmit needs external synchronization */
};

const char *vk_result_name(VkResult r);

/* VK_TRY is the one way a VkResult becomes a lucent_error. Needs `lucent_status st` and a
 * `fail:` label in the caller. */
#define VK_TRY(call, err)                                                                       \
    do {                                                                                        \
        VkResult vk_try_r_ = (call);                                                            \
        if (vk_try_r_ != VK_SUCCESS) {                                                          \
            st = lucent_fail((err), LUCENT_E_VULKAN, "", "%s failed: %s (%s:%d)", #call,        \
                             vk_result_name(vk_try_r_), __FILE__, __LINE__);                    \
            goto fail;                                                                          \
        }                                                                                       \
    } while (0)


/* Finds or creates the device for a request: a discrete GPU, else an integrated one, else any
 * (lavapipe); a non-empty request forces the first device whose name contains it. */
lucent_status vk_device_acquire(const char *request, int verbose, struct vk_device **out, lucent_error *err);
void vk_device_release(struct vk_device *dev);
/* A device lost (or hung) is taken out of the registry: the next acquire for its request creates another. */
void vk_device_mark_lost(struct vk_device *dev);

#endif
