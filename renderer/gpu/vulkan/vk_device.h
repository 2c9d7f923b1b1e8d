/* vk_device.h - the Vulkan instance, device and queue, shared by every renderer of the process that
 * asks for the same device, and kept until lucent_shutdown(): devices are expensive to create and
 * lavapipe does not return the memory of a destroyed device (about 25 MB each). */
#ifndef LUCENT_VK_DEVICE_H
#define LUCENT_VK_DEVICE_H

#include "lucent.h"
#include "vk_check.h"

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

/* Finds or creates the device for a request: a discrete GPU, else an integrated one, else any
 * (lavapipe); a non-empty request forces the first device whose name contains it. */
lucent_status vk_device_acquire(const char *request, int verbose, struct vk_device **out, lucent_error *err);
void vk_device_release(struct vk_device *dev);
/* A device lost (or hung) is taken out of the registry: the next acquire for its request creates another. */
void vk_device_mark_lost(struct vk_device *dev);

#endif
