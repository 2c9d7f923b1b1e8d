/* vk_context.c - a renderer's own command pool, command buffer and fence on top of a shared device;
 * submission is serialized on the device's queue lock. */
#include "vk_context.h"

#include <stdlib.h>
#include <string.h>

lucent_status vk_context_create(struct vk_context *ctx, const char *device_name, int verbose,
                                lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    memset(ctx, 0, sizeof *ctx);
    if (!device_name || !*device_name)
        device_name = getenv("LUCENT_DEVICE");
    if ((st = vk_device_acquire(device_name, verbose, &ctx->shared, err)) != LUCENT_OK)
        return st;
    ctx->device = ctx->shared->device;
    ctx->memory = ctx->shared->memory;
    ctx->limits = ctx->shared->limits;
    ctx->timestamp_ns = ctx->shared->timestamp_ns;
    ctx->device_name = ctx->shared->device_name;

    VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = ctx->shared->queue_family};
    VK_TRY(vkCreateCommandPool(ctx->device, &pci, NULL, &ctx->command_pool), err);
    VkCommandBufferAllocateInfo cai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                       .commandPool = ctx->command_pool,
                                       .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY, .commandBufferCount = 1};
    VK_TRY(vkAllocateCommandBuffers(ctx->device, &cai, &ctx->cmd), err);
    /* Signaled until the first submission, so waiting on it never blocks on work never sent. */
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, .flags = VK_FENCE_CREATE_SIGNALED_BIT};
    VK_TRY(vkCreateFence(ctx->device, &fci, NULL, &ctx->fence), err);
    return LUCENT_OK;
fail:
    vk_context_destroy(ctx);
    return st;
}

void vk_context_destroy(struct vk_context *ctx)
{
    if (ctx->device) {
        if (ctx->fence) {
            /* Other renderers may use the device: wait for our own work only. */
            vkWaitForFences(ctx->device, 1, &ctx->fence, VK_TRUE, UINT64_MAX);
            vkDestroyFence(ctx->device, ctx->fence, NULL);
        }
        vkDestroyCommandPool(ctx->device, ctx->command_pool, NULL);
    }
    if (ctx->shared)
        vk_device_release(ctx->shared);
    memset(ctx, 0, sizeof *ctx);
}

uint32_t vk_memory_type(const struct vk_context *ctx, uint32_t type_bits, VkMemoryPropertyFlags want)
{
    for (uint32_t i = 0; i < ctx->memory.memoryTypeCount; i++)
        if ((type_bits & (1u << i)) && (ctx->memory.memoryTypes[i].propertyFlags & want) == want)
            return i;
    return UINT32_MAX;
}

lucent_status vk_submit_and_wait(struct vk_context *ctx, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1,
                       .pCommandBuffers = &ctx->cmd};
    VK_TRY(vkResetFences(ctx->device, 1, &ctx->fence), err);
    pthread_mutex_lock(&ctx->shared->queue_lock);
    VkResult submitted = vkQueueSubmit(ctx->shared->queue, 1, &si, ctx->fence);
    pthread_mutex_unlock(&ctx->shared->queue_lock);
    VK_TRY(submitted, err);
    /* A render that takes minutes means a lost device, not a slow one. */
    VK_TRY(vkWaitForFences(ctx->device, 1, &ctx->fence, VK_TRUE, 120ull * 1000000000ull), err);
fail:
    return st;
}
