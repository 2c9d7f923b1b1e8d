/* vk_context.h - what one renderer holds of Vulkan: a shared device (vk_device.h) plus its own command
 * buffer and fence. */
#ifndef LUCENT_VK_CONTEXT_H
#define LUCENT_VK_CONTEXT_H

#include "vk_device.h"

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
};

/* device_name (or $LUCENT_DEVICE) as for vk_device_acquire. */
lucent_status vk_context_create(struct vk_context *ctx, const char *device_name, int verbose,
                                lucent_error *err);
void vk_context_destroy(struct vk_context *ctx);

/* Memory type with all of `want` among `type_bits`, or UINT32_MAX. */
uint32_t vk_memory_type(const struct vk_context *ctx, uint32_t type_bits, VkMemoryPropertyFlags want);

/* Submits ctx->cmd and waits for it. */
lucent_status vk_submit_and_wait(struct vk_context *ctx, lucent_error *err);

#endif
