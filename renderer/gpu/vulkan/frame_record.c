/* frame_record.c - turns a frame plan into commands. Pass order matters: shadow maps feed the
 * projection images, each view's share of them (the owned images) and their mip chain, which with the
 * G-buffer feed the scatter pass; render-pass dependencies and the barriers around the side-image copy,
 * the ownership pass and the mip blits carry the data between them. */
#include "frame_record.h"

#include <string.h>

static void set_viewport(VkCommandBuffer cmd, uint32_t w, uint32_t h)
{
    VkViewport vp = {0.0f, 0.0f, (float)w, (float)h, 0.0f, 1.0f};
    VkRect2D sc = {{0, 0}, {w, h}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
}

static void draw(VkCommandBuffer cmd, const struct gpu_draw *d, int with_normals)
{
    VkBuffer vbs[2] = {d->geometry->positions.buffer, d->geometry->normals.buffer};
    VkDeviceSize offsets[2] = {0, 0};
    vkCmdBindVertexBuffers(cmd, 0, with_normals ? 2 : 1, vbs, offsets);
    vkCmdBindIndexBuffer(cmd, d->geometry->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, d->index_count, 1, 0, 0, 0);
}

static void begin_pass(VkCommandBuffer cmd, VkRenderPass pass, VkFramebuffer fb, uint32_t w, uint32_t h,
                       const VkClearValue *clears, uint32_t clear_count)
{
    VkRenderPassBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
                                .renderPass = pass,
                                .framebuffer = fb,
                                .renderArea = {{0, 0}, {w, h}},
                                .clearValueCount = clear_count,
                                .pClearValues = clears};
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    set_viewport(cmd, w, h);
}

static void stamp(const struct frame_gpu *gpu, uint32_t query)
{
    if (gpu->queries)
        vkCmdWriteTimestamp(gpu->ctx->cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, gpu->queries, query);
}

static void record_shadows(const struct frame_gpu *gpu, const struct frame_plan *plan,
                           const struct gpu_draw *g, int cull)
{
    VkCommandBuffer cmd = gpu->ctx->cmd;
    VkClearValue clear = {.depthStencil = {1.0f, 0}};
    for (int s = 0; s < plan->shadow_count; s++) {
        begin_pass(cmd, gpu->pipes->shadow_pass, gpu->targets->shadow_fb[s], SHADOW_MAP_SIZE, SHADOW_MAP_SIZE,
                   &clear, 1);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gpu->pipes->shadow[cull]);
        vkCmdPushConstants(cmd, gpu->pipes->shadow_layout, VK_SHADER_STAGE_VERTEX_BIT, 0, 64,
                           plan->shadow_clip[s]);
        draw(cmd, g, 0);
        vkCmdEndRenderPass(cmd);
    }
}

static void record_projection_pass(const struct frame_gpu *gpu, int which, int32_t view_base,
                                   const struct gpu_draw *g, VkPipeline pipeline)
{
    VkCommandBuffer cmd = gpu->ctx->cmd;
    const struct render_targets *t = gpu->targets;
    /* Depth -1 marks texels no surface covers. */
    VkClearValue clears[3] = {{.color = {{0.0f, 0.0f, 0.0f, -1.0f}}}, {.color = {{0}}}, {.depthStencil = {1.0f, 0}}};
    uint32_t side = which == PROJECTION_FRONT ? t->projection_size : t->side_size;
    VkFramebuffer fb[PROJECTION_PASSES] = {t->front_fb, t->sides_fb, t->lights_fb};
    begin_pass(cmd, gpu->pipes->projection_pass[which], fb[which], side, side, clears, 3);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gpu->pipes->projection_layout, 0, 1,
                            &t->projection_set, 0, NULL);
    vkCmdPushConstants(cmd, gpu->pipes->projection_layout,
                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof view_base,
                       &view_base);
    draw(cmd, g, 1);
    vkCmdEndRenderPass(cmd);
}

/* The side or light images (flux and depth, and normals: `flux`, `normals`, `count` layers) go into the
 * top-left side_size^2 corner of layers first..first + count - 1 of the sampled arrays, where the
 * scatter pass's texel coordinates for those views point. */
static void copy_sides(const struct frame_gpu *gpu, const struct vk_image *flux, const struct vk_image *normals,
                       uint32_t first, uint32_t count)
{
    VkCommandBuffer cmd = gpu->ctx->cmd;
    const struct render_targets *t = gpu->targets;
    VkImage from[2] = {flux->image, normals->image}, to[2] = {t->projection.image, t->normals.image};
    VkImageMemoryBarrier b[2];
    for (int i = 0; i < 2; i++)
        b[i] = (VkImageMemoryBarrier){.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                                      .srcAccessMask = VK_ACCESS_SHADER_READ_BIT,
                                      .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                      .oldLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,   /* keeps the cleared rest */
                                      .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                      .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                      .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                      .image = to[i],
                                      .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, first, count}};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                         NULL, 0, NULL, 2, b);
    VkImageCopy region = {.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, count},
                          .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, first, count},
                          .extent = {t->side_size, t->side_size, 1}};
    for (int i = 0; i < 2; i++) {
        vkCmdCopyImage(cmd, from[i], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, to[i], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                       1, &region);
        b[i].srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b[i].dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
        b[i].oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        b[i].newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    }
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0,
                         NULL, 0, NULL, 2, b);
}

static VkImageMemoryBarrier level_barrier(const struct vk_image *img, uint32_t level, uint32_t levels,
                                         VkImageLayout from, VkImageLayout to, VkAccessFlags src, VkAccessFlags dst)
{
    return (VkImageMemoryBarrier){.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER, .srcAccessMask = src,
                                  .dstAccessMask = dst, .oldLayout = from, .newLayout = to,
                                  .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                  .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED, .image = img->image,
                                  .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, level, levels, 0, FRAME_MAX_VIEWS}};
}

/* Each view's share of the flux it shows, into level 0 of the owned images (ownership.comp, from level 0 of
 * the projection images, which the projection passes and copy_sides leave readable by compute): every
 * texel of every view's square (the side layers' corners only), the front view, and the side and light
 * views, in one dispatch each. */
static void record_ownership(const struct frame_gpu *gpu, struct owned_sides o, uint32_t side_views)
{
    VkCommandBuffer cmd = gpu->ctx->cmd;
    const struct render_targets *t = gpu->targets;
    VkImageMemoryBarrier b = level_barrier(&t->owned, 0, 1, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                           VK_IMAGE_LAYOUT_GENERAL, VK_ACCESS_SHADER_READ_BIT,
                                           VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, NULL,
                         0, NULL, 1, &b);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, gpu->pipes->ownership);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, gpu->pipes->scatter_layout, 0, 1, &t->scatter_set,
                            0, NULL);
    int32_t first_view[2] = {0, 0};
    vkCmdPushConstants(cmd, gpu->pipes->scatter_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof first_view, first_view);
    vkCmdDispatch(cmd, (o.front + 7) / 8, (o.front + 7) / 8, 1);
    first_view[0] = 1;
    vkCmdPushConstants(cmd, gpu->pipes->scatter_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof first_view, first_view);
    vkCmdDispatch(cmd, (o.sides + 7) / 8, (o.sides + 7) / 8, side_views < SIDE_VIEWS ? side_views : SIDE_VIEWS);
    if (side_views > SIDE_VIEWS) {
        first_view[0] = 1 + SIDE_VIEWS;
        vkCmdPushConstants(cmd, gpu->pipes->scatter_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof first_view,
                           first_view);
        vkCmdDispatch(cmd, (o.lights + 7) / 8, (o.lights + 7) / 8, side_views - SIDE_VIEWS);
    }
}

/* Level i of a layer is the 2x2 mean of level i-1: flux per unit of image area, averaged, so a texel
 * of level i holds the mean of the 4^i texels it covers (uncovered ones add no flux). The side views
 * fill a side_size^2 corner of their layers, and only that corner is reduced: what lies outside it
 * keeps the clear of render_targets.c (no flux). The depth in alpha is averaged too; the scatter pass
 * reads depth from level 0 only. */
static void blit_level(VkCommandBuffer cmd, const struct vk_image *img, uint32_t level, uint32_t size,
                       uint32_t first, uint32_t layers)
{
    int32_t src = (int32_t)(size >> (level - 1)), dst = (int32_t)(size >> level);
    VkImageBlit blit = {.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level - 1, first, layers},
                        .srcOffsets = {{0, 0, 0}, {src, src, 1}},
                        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level, first, layers},
                        .dstOffsets = {{0, 0, 0}, {dst, dst, 1}}};
    vkCmdBlitImage(cmd, img->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, img->image,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
}

/* The mip chain of the projection or the owned images, `levels` levels of it, whose level 0 (of side
 * `size`; the `side_views` layers after it, side views of `side_size` and then light views of
 * `light_size`) was just written in layout `written_as`. */
static void record_mips(const struct frame_gpu *gpu, const struct vk_image *img, VkImageLayout written_as,
                        uint32_t levels, uint32_t size, uint32_t side_size, uint32_t light_size, uint32_t side_views)
{
    VkCommandBuffer cmd = gpu->ctx->cmd;
    VkPipelineStageFlags drawn = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    VkAccessFlags written = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                            VK_ACCESS_SHADER_WRITE_BIT;
    VkImageMemoryBarrier b = level_barrier(img, 0, 1, written_as, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, written,
                                           VK_ACCESS_TRANSFER_READ_BIT);
    vkCmdPipelineBarrier(cmd, drawn, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0, NULL, 1, &b);
    for (uint32_t level = 1; level < levels; level++) {
        b = level_barrier(img, level, 1, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                          VK_ACCESS_SHADER_READ_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL,
                             0, NULL, 1, &b);
        blit_level(cmd, img, level, size, 0, 1);
        if (side_views && side_size >> level)
            blit_level(cmd, img, level, side_size, 1, side_views < SIDE_VIEWS ? side_views : SIDE_VIEWS);
        if (side_views > SIDE_VIEWS && light_size >> level)
            blit_level(cmd, img, level, light_size, 1 + SIDE_VIEWS, side_views - SIDE_VIEWS);
        b = level_barrier(img, level, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                          VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT);
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0,
                             NULL, 1, &b);
    }
    b = level_barrier(img, 0, levels, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT);
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, NULL, 0,
                         NULL, 1, &b);
}

static void record_gbuffer(const struct frame_gpu *gpu, const struct frame_plan *plan,
                           const struct gpu_draw *g, int cull)
{
    VkCommandBuffer cmd = gpu->ctx->cmd;
    VkClearValue clears[3] = {{.color = {{0}}}, {.color = {{0}}}, {.depthStencil = {1.0f, 0}}};
    begin_pass(cmd, gpu->pipes->gbuffer_pass, gpu->targets->gbuffer_fb, gpu->targets->width,
               gpu->targets->height, clears, 3);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gpu->pipes->gbuffer[cull]);
    struct gbuffer_push push;
    memcpy(push.clip_from_world, plan->camera_clip, sizeof push.clip_from_world);
    memcpy(push.eye, plan->camera_eye, sizeof push.eye);
    vkCmdPushConstants(cmd, gpu->pipes->gbuffer_layout,
                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push, &push);
    draw(cmd, g, 1);
    vkCmdEndRenderPass(cmd);
}

static void compute_to_compute(VkCommandBuffer cmd)
{
    VkMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                         .dstAccessMask = VK_ACCESS_SHADER_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &b, 0,
                         NULL, 0, NULL);
}

/* The far annulus per block of pixels and its filter (when the profile is sampled; no filter for blocks
 * of one pixel), then the compose pass per pixel. */
static void record_scatter(const struct frame_gpu *gpu, VkPipeline far, VkPipeline filter, VkPipeline compose,
                           uint32_t block)
{
    VkCommandBuffer cmd = gpu->ctx->cmd;
    uint32_t w = gpu->targets->width, h = gpu->targets->height;
    int32_t size[2] = {(int32_t)w, (int32_t)h};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, gpu->pipes->scatter_layout, 0, 1,
                            &gpu->targets->scatter_set, 0, NULL);
    vkCmdPushConstants(cmd, gpu->pipes->scatter_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof size, size);
    VkPipeline block_passes[2] = {far, filter};
    for (int i = 0; i < 2 && block_passes[i]; i++) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, block_passes[i]);
        vkCmdDispatch(cmd, (frame_far_blocks(w, block) + 7) / 8, (frame_far_blocks(h, block) + 7) / 8, 1);
        compute_to_compute(cmd);
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, compose);
    vkCmdDispatch(cmd, (w + 7) / 8, (h + 7) / 8, 1);
    VkMemoryBarrier to_host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                               .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                               .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                         &to_host, 0, NULL, 0, NULL);
}

lucent_status frame_record(const struct frame_gpu *gpu, const struct gpu_frame *frame, lucent_error *err)
{
    const struct frame_plan *plan = frame->plan;
    lucent_status st = LUCENT_OK;
    VkCommandBuffer cmd = gpu->ctx->cmd;
    const struct gpu_draw *front_mesh = &frame->front, *side_mesh = &frame->sides;
    VkPipeline projection[PROJECTION_PASSES] = {0}, scatter[3] = {0};
    int owned = plan->gather_owned, cull = plan->cull_back_faces;
    struct frame_passes passes;
    frame_passes_plan(plan, &passes);
    pipelines_begin_frame(gpu->pipes);
    for (int which = 0; st == LUCENT_OK && which < PROJECTION_PASSES; which++)
        if (passes.projection[which])
            st = pipelines_projection(gpu->ctx, gpu->pipes, which, plan->light_count, plan->shadow_mask, cull,
                                      &projection[which], err);
    for (int pass = 0; st == LUCENT_OK && pass < 3; pass++)
        if (passes.scatter[pass])
            st = pipelines_scatter(gpu->ctx, gpu->pipes, &passes.variant[pass], &scatter[pass], err);
    if (st != LUCENT_OK)
        return st;
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    VK_TRY(vkBeginCommandBuffer(cmd, &bi), err);
    if (gpu->queries)
        vkCmdResetQueryPool(cmd, gpu->queries, 0, TS_COUNT);
    stamp(gpu, TS_START);
    record_shadows(gpu, plan, side_mesh, cull);
    stamp(gpu, TS_SHADOW);
    record_projection_pass(gpu, PROJECTION_FRONT, 0, front_mesh, projection[PROJECTION_FRONT]);
    uint32_t side_views = (uint32_t)plan->view_count - 1;
    if (passes.projection[PROJECTION_SIDES]) {
        record_projection_pass(gpu, PROJECTION_SIDES, passes.first_view[PROJECTION_SIDES], side_mesh, projection[PROJECTION_SIDES]);
        copy_sides(gpu, &gpu->targets->sides, &gpu->targets->side_normals, 1, SIDE_VIEWS);
    }
    if (passes.projection[PROJECTION_LIGHTS]) {
        record_projection_pass(gpu, PROJECTION_LIGHTS, passes.first_view[PROJECTION_LIGHTS], side_mesh, projection[PROJECTION_LIGHTS]);
        copy_sides(gpu, &gpu->targets->lights, &gpu->targets->light_normals, (uint32_t)passes.first_view[PROJECTION_LIGHTS],
                   (uint32_t)passes.views[PROJECTION_LIGHTS]);
    }
    const struct render_targets *t = gpu->targets;
    VkImageLayout drawn = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    if (owned) {   /* the owned images are read instead of the projection images' mips, which are not made */
        struct owned_sides o = frame_owned_sides(t->projection_size, t->side_size);
        record_ownership(gpu, o, side_views);
        record_mips(gpu, &t->owned, VK_IMAGE_LAYOUT_GENERAL, t->owned.levels, o.front, o.sides, o.lights, side_views);
    } else {
        record_mips(gpu, &t->projection, drawn, t->projection.levels, t->projection_size, t->side_size, t->side_size,
                    side_views);
    }
    stamp(gpu, TS_PROJECTION);
    record_gbuffer(gpu, plan, &frame->full, plan->cull_camera);
    stamp(gpu, TS_GBUFFER);
    record_scatter(gpu, scatter[SCATTER_FAR], scatter[SCATTER_FAR_FILTER], scatter[SCATTER_COMPOSE],
                   (uint32_t)plan->far_block);
    stamp(gpu, TS_SCATTER);
    VK_TRY(vkEndCommandBuffer(cmd), err);
fail:
    return st;
}
