/* vk_context.c - a renderer's own command pool, command buffer and fence on top of a shared device;
 * submission is serialized on the device's queue lock. */
#include "vk_context.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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
            /* Other renderers may use the device: wait for our own work only; a lost device has none. */
            if (ctx->in_flight && !ctx->lost)
                vkWaitForFences(ctx->device, 1, &ctx->fence, VK_TRUE, VK_CONTEXT_WAIT_NS);
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

static lucent_status lose(struct vk_context *ctx, const char *call, VkResult r, lucent_error *err)
{
    ctx->lost = 1;
    vk_device_mark_lost(ctx->shared);
    return lucent_fail(err, LUCENT_E_DEVICE_LOST, "", "device \"%s\" lost: %s returned %s", ctx->device_name, call,
                       vk_result_name(r));
}

lucent_status vk_context_settle(struct vk_context *ctx, lucent_error *err)
{
    if (ctx->lost)
        return lucent_fail(err, LUCENT_E_DEVICE_LOST, "", "device \"%s\" was lost; the renderer must be re-created",
                           ctx->device_name);
    if (!ctx->in_flight)
        return LUCENT_OK;
    VkResult r = vkWaitForFences(ctx->device, 1, &ctx->fence, VK_TRUE, VK_CONTEXT_WAIT_NS);
    if (r != VK_SUCCESS)
        return lose(ctx, "vkWaitForFences on the frame that timed out", r, err);
    ctx->in_flight = 0;
    return LUCENT_OK;
}

lucent_status vk_submit_and_wait(struct vk_context *ctx, lucent_error *err)
{
    lucent_status st = vk_context_settle(ctx, err);
    if (st != LUCENT_OK)
        return st;
    enum gpu_fault fault = ctx->fault;
    ctx->fault = GPU_FAULT_NONE;
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1,
                       .pCommandBuffers = &ctx->cmd};
    VK_TRY(vkResetFences(ctx->device, 1, &ctx->fence), err);
    VkResult submitted;
    if (fault == GPU_FAULT_SUBMIT) {
        submitted = VK_ERROR_OUT_OF_DEVICE_MEMORY;
    } else if (fault == GPU_FAULT_LOST) {
        submitted = VK_ERROR_DEVICE_LOST;
    } else {
        pthread_mutex_lock(&ctx->shared->queue_lock);
        submitted = vkQueueSubmit(ctx->shared->queue, 1, &si, ctx->fence);
        pthread_mutex_unlock(&ctx->shared->queue_lock);
    }
    if (submitted == VK_ERROR_DEVICE_LOST)
        return lose(ctx, "vkQueueSubmit", submitted, err);
    if (submitted != VK_SUCCESS)  /* nothing submitted: the fence stays unsignaled and nobody waits on it */
        return lucent_fail(err, LUCENT_E_GPU, "", "vkQueueSubmit failed: %s", vk_result_name(submitted));
    ctx->in_flight = 1;
    while (fault == GPU_FAULT_HANG)
        sleep(60);
    VkResult waited = fault == GPU_FAULT_TIMEOUT
                          ? VK_TIMEOUT
                          : vkWaitForFences(ctx->device, 1, &ctx->fence, VK_TRUE, VK_CONTEXT_WAIT_NS);
    if (waited == VK_TIMEOUT)
        return lucent_fail(err, LUCENT_E_GPU, "", "the frame did not finish within %d s on device \"%s\"",
                           VK_CONTEXT_WAIT_S, ctx->device_name);
    if (waited != VK_SUCCESS)
        return lose(ctx, "vkWaitForFences", waited, err);
    ctx->in_flight = 0;
fail:
    return st;
}
