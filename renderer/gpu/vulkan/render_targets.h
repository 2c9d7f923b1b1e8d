/* render_targets.h - the images, framebuffers, output buffer and descriptor sets whose size depends
 * on the request (image size, projection size). Kept between frames; a group is rebuilt only when its
 * size changes. */
#ifndef LUCENT_RENDER_TARGETS_H
#define LUCENT_RENDER_TARGETS_H

#include "frame_plan.h"
#include "pipelines.h"
#include "vk_resources.h"

struct render_targets {
    uint32_t width, height, projection_size, side_size;
    /* made once */
    struct vk_image shadow_depth;                 /* SHADOW_MAP_SIZE^2 x LUCENT_MAX_LIGHTS layers */
    VkImageView shadow_layer[LUCENT_MAX_LIGHTS];
    VkFramebuffer shadow_fb[LUCENT_MAX_LIGHTS];
    VkDescriptorPool pool;
    VkDescriptorSet projection_set, scatter_set;  /* rewritten whenever a group below is re-created */
    /* sized by projection_size and side_size */
    struct vk_image projection;                   /* projection_size^2 x FRAME_MAX_VIEWS layers, sampled */
    VkImageView front_layer;
    struct vk_image normals;                      /* the projection images' surface normals, same layout */
    VkImageView front_normals;
    struct vk_image owned;                        /* each view's share of the flux (ownership.comp), side
                                                   * projection_size >> frame_owned_shift(), mipped */
    VkImageView owned_base;                       /* its level 0, written as a storage image */
    struct vk_image front_depth;
    VkFramebuffer front_fb;
    struct vk_image sides, side_normals, sides_depth;  /* side_size^2 x 4 layers, copied into the arrays */
    VkFramebuffer sides_fb;
    struct vk_image lights, light_normals, lights_depth;  /* side_size^2 x FRAME_LIGHT_VIEWS, likewise */
    VkFramebuffer lights_fb;
    /* sized by width and height */
    struct vk_image gbuffer_position, gbuffer_normal, gbuffer_depth;
    VkFramebuffer gbuffer_fb;
    struct vk_buffer output;                      /* color, normal+view, depth arrays */
    VkDeviceSize color_offset, normal_offset, depth_offset;
    struct vk_buffer far;                         /* the far annulus per frame_far_block() block, then filtered */
    VkDeviceSize far_bytes, far_filtered_offset;  /* offset 0: the filtered samples are the samples */
};

/* Makes t fit a frame of these sizes, re-creating only what depends on a size that changed: the shadow
 * maps are made once, the projection images when projection_size or side_size change, the G-buffer and
 * output when width or height do. t starts zeroed; on failure it is destroyed (zeroed again). */
lucent_status render_targets_fit(struct vk_context *ctx, const struct pipelines *p, const struct vk_buffer *uniforms,
                                 uint32_t width, uint32_t height, uint32_t projection_size, uint32_t side_size,
                                 struct render_targets *t, lucent_error *err);
void render_targets_destroy(struct vk_context *ctx, struct render_targets *t);

#endif
