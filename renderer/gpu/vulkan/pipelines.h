/* pipelines.h - render passes, layouts and pipelines of the four passes (shadow, projection,
 * camera G-buffer, scatter), from the SPIR-V embedded at build time; each renderer keeps its own. */
#ifndef LUCENT_PIPELINES_H
#define LUCENT_PIPELINES_H

#include "frame_passes.h"
#include "pipeline_lru.h"
#include "vk_context.h"

#define PROJECTION_FORMAT VK_FORMAT_R32G32B32A32_SFLOAT  /* flux + depth: fp16 over/underflows */
#define GBUFFER_FORMAT VK_FORMAT_R32G32B32A32_SFLOAT
#define DEPTH_FORMAT VK_FORMAT_D32_SFLOAT

/* Projection pipelines are also specialized by culling and pass (render pass), scatter pipelines as
 * frame_passes.h says; built on first use, the most recently used PIPELINE_LRU_SLOTS kept (pipeline_lru.h). */
/* The scatter set: frame uniforms, projection images, G-buffer position and normal, the output
 * color, normal and depth buffers, the far samples, the owned images (sampled), the projection
 * normals, the owned images' level 0 (storage) and the filtered far samples. */
#define SCATTER_BINDINGS 12

struct pipelines {
    VkRenderPass shadow_pass;
    VkRenderPass projection_pass[PROJECTION_PASSES];
    VkRenderPass gbuffer_pass;
    VkDescriptorSetLayout projection_set_layout;
    VkDescriptorSetLayout scatter_set_layout;
    VkPipelineLayout shadow_layout, projection_layout, gbuffer_layout, scatter_layout;
    VkPipeline shadow[2], gbuffer[2];   /* index: cull back faces (closed meshes) */
    struct pipeline_lru projection, scatter;
    uint64_t frame;             /* frames begun: a frame's own pipelines are never evicted under it */
    VkPipeline ownership;       /* each view's share of the surface, over the scatter set */
    VkSampler nearest;
    VkSampler filtered;         /* bilinear within a mip level, for the prefiltered projection images */
    VkSampler shadow_compare;   /* depth comparison with 2x2 filtering (PCF) */
};

struct gbuffer_push {
    float clip_from_world[16];
    float eye[4];
};

lucent_status pipelines_create(struct vk_context *ctx, struct pipelines *p, lucent_error *err);
/* Starts a frame's requests for pipelines. Pipelines requested by earlier frames may be destroyed from
 * here on: call it only when no earlier frame is executing. */
void pipelines_begin_frame(struct pipelines *p);
/* The projection pipeline for `which` (PROJECTION_FRONT/SIDES/LIGHTS), 1..LUCENT_MAX_LIGHTS lights, a
 * shadow mask (bit l: light l is shadowed) and back-face culling, created on first use. */
lucent_status pipelines_projection(struct vk_context *ctx, struct pipelines *p, int which, int lights,
                                   uint32_t shadow_mask, int cull, VkPipeline *out, lucent_error *err);
/* The scatter pipeline for a variant (0..LUCENT_MAX_SAMPLES samples, 1 or 5..FRAME_MAX_VIEWS views; a far pass needs
 * samples), created on first use. */
lucent_status pipelines_scatter(struct vk_context *ctx, struct pipelines *p, const struct scatter_variant *v,
                                VkPipeline *out, lucent_error *err);
void pipelines_destroy(struct vk_context *ctx, struct pipelines *p);

#endif
