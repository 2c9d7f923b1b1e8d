/* vk_resources.c - allocation of buffers and images: one VkDeviceMemory each, which is plenty for
 * the handful of long-lived resources a warm renderer holds. */
#include "vk_resources.h"

#include <string.h>

/* Counted in ctx->memory_bytes, which free_memory takes back. */
static lucent_status allocate(struct vk_context *ctx, VkMemoryRequirements req,
                              VkMemoryPropertyFlags want, VkDeviceMemory *out, VkDeviceSize *bytes,
                              lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    uint32_t type = vk_memory_type(ctx, req.memoryTypeBits, want);
    if (type == UINT32_MAX)
        return lucent_fail(err, LUCENT_E_GPU, "", "no memory type with flags 0x%x", (unsigned)want);
    VkMemoryAllocateInfo mai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                .allocationSize = req.size, .memoryTypeIndex = type};
    VK_TRY(vkAllocateMemory(ctx->device, &mai, NULL, out), err);
    *bytes = req.size;
    ctx->memory_bytes += req.size;
fail:
    return st;
}

static void free_memory(struct vk_context *ctx, VkDeviceMemory memory, VkDeviceSize bytes)
{
    if (!memory)
        return;
    vkFreeMemory(ctx->device, memory, NULL);
    ctx->memory_bytes -= bytes;
}

lucent_status vk_buffer_create(struct vk_context *ctx, VkDeviceSize size, VkBufferUsageFlags usage,
                               struct vk_buffer *out, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    memset(out, 0, sizeof *out);
    out->size = size;
    VkBufferCreateInfo bci = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO, .size = size,
                              .usage = usage, .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
    VK_TRY(vkCreateBuffer(ctx->device, &bci, NULL, &out->buffer), err);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx->device, out->buffer, &req);
    st = allocate(ctx, req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                  &out->memory, &out->bytes, err);
    if (st != LUCENT_OK)
        goto fail;
    VK_TRY(vkBindBufferMemory(ctx->device, out->buffer, out->memory, 0), err);
    VK_TRY(vkMapMemory(ctx->device, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped), err);
    return LUCENT_OK;
fail:
    vk_buffer_destroy(ctx, out);
    return st;
}

void vk_buffer_destroy(struct vk_context *ctx, struct vk_buffer *b)
{
    if (b->buffer)
        vkDestroyBuffer(ctx->device, b->buffer, NULL);
    free_memory(ctx, b->memory, b->bytes);
    memset(b, 0, sizeof *b);
}

static VkImageAspectFlags aspect_of(VkFormat format)
{
    return format == VK_FORMAT_D32_SFLOAT ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

static lucent_status create_view(struct vk_context *ctx, const struct vk_image *img, uint32_t first,
                                 uint32_t count, uint32_t levels, VkImageView *out, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkImageViewCreateInfo vci = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO, .image = img->image,
        .viewType = count > 1 || img->layers > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D,
        .format = img->format,
        .subresourceRange = {aspect_of(img->format), 0, levels, first, count}};
    VK_TRY(vkCreateImageView(ctx->device, &vci, NULL, out), err);
fail:
    return st;
}

lucent_status vk_image_create(struct vk_context *ctx, uint32_t width, uint32_t height, uint32_t layers,
                              VkFormat format, VkImageUsageFlags usage, struct vk_image *out,
                              lucent_error *err)
{
    return vk_image_create_mipped(ctx, width, height, layers, 1, format, usage, out, err);
}

lucent_status vk_image_create_mipped(struct vk_context *ctx, uint32_t width, uint32_t height, uint32_t layers,
                                     uint32_t levels, VkFormat format, VkImageUsageFlags usage,
                                     struct vk_image *out, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    memset(out, 0, sizeof *out);
    out->format = format;
    out->width = width;
    out->height = height;
    out->layers = layers;
    out->levels = levels;
    VkImageCreateInfo ici = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO, .imageType = VK_IMAGE_TYPE_2D, .format = format,
        .extent = {width, height, 1}, .mipLevels = levels, .arrayLayers = layers,
        .samples = VK_SAMPLE_COUNT_1_BIT, .tiling = VK_IMAGE_TILING_OPTIMAL, .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE, .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED};
    VK_TRY(vkCreateImage(ctx->device, &ici, NULL, &out->image), err);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx->device, out->image, &req);
    st = allocate(ctx, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, &out->memory, &out->bytes, err);
    if (st != LUCENT_OK)
        goto fail;
    VK_TRY(vkBindImageMemory(ctx->device, out->image, out->memory, 0), err);
    st = create_view(ctx, out, 0, layers, levels, &out->view, err);
    if (st != LUCENT_OK)
        goto fail;
    return LUCENT_OK;
fail:
    vk_image_destroy(ctx, out);
    return st;
}

void vk_image_destroy(struct vk_context *ctx, struct vk_image *img)
{
    if (img->view)
        vkDestroyImageView(ctx->device, img->view, NULL);
    if (img->image)
        vkDestroyImage(ctx->device, img->image, NULL);
    free_memory(ctx, img->memory, img->bytes);
    memset(img, 0, sizeof *img);
}

lucent_status vk_image_layer_view(struct vk_context *ctx, const struct vk_image *img, uint32_t layer,
                                  VkImageView *out, lucent_error *err)
{
    return create_view(ctx, img, layer, 1, 1, out, err);
}

lucent_status vk_image_base_view(struct vk_context *ctx, const struct vk_image *img, VkImageView *out,
                                 lucent_error *err)
{
    return create_view(ctx, img, 0, img->layers, 1, out, err);
}
