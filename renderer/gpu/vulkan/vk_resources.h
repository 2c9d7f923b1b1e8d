/* vk_resources.h - buffers and images with their memory and views, created and destroyed in pairs.
 * Each struct owns everything it points to; destroy is safe on a zeroed struct. */
#ifndef LUCENT_VK_RESOURCES_H
#define LUCENT_VK_RESOURCES_H

#include "vk_context.h"

struct vk_buffer {
    VkBuffer buffer;
    VkDeviceMemory memory;
    void *mapped;             /* host-visible buffers stay mapped for their lifetime */
    VkDeviceSize size;
    VkDeviceSize bytes;       /* of memory allocated */
};

struct vk_image {
    VkImage image;
    VkDeviceMemory memory;
    VkImageView view;         /* all layers and mip levels */
    VkFormat format;
    uint32_t width, height, layers, levels;
    VkDeviceSize bytes;       /* of memory allocated */
};

/* Host-visible, coherent buffer, mapped. */
lucent_status vk_buffer_create(struct vk_context *ctx, VkDeviceSize size, VkBufferUsageFlags usage,
                               struct vk_buffer *out, lucent_error *err);
void vk_buffer_destroy(struct vk_context *ctx, struct vk_buffer *b);

/* 2D image (array when layers > 1) in device-local memory with a view over every layer. */
lucent_status vk_image_create(struct vk_context *ctx, uint32_t width, uint32_t height, uint32_t layers,
                              VkFormat format, VkImageUsageFlags usage, struct vk_image *out,
                              lucent_error *err);
/* The same with a chain of `levels` mip levels (the view covers them all). */
lucent_status vk_image_create_mipped(struct vk_context *ctx, uint32_t width, uint32_t height, uint32_t layers,
                                     uint32_t levels, VkFormat format, VkImageUsageFlags usage,
                                     struct vk_image *out, lucent_error *err);
void vk_image_destroy(struct vk_context *ctx, struct vk_image *img);

/* A view of every layer's first mip level, for storage writes into a mipped array. */
lucent_status vk_image_base_view(struct vk_context *ctx, const struct vk_image *img, VkImageView *out,
                                 lucent_error *err);

/* A view of one layer's first mip level, for framebuffers that draw one array layer at a time. */
lucent_status vk_image_layer_view(struct vk_context *ctx, const struct vk_image *img, uint32_t layer,
                                  VkImageView *out, lucent_error *err);

#endif
