/* renderer.c - the warm renderer: one Vulkan context, fixed pipelines, size-dependent targets and
 * cached meshes, and lucent_render(), which records and runs the four passes of one frame. */
#include "frame_plan.h"
#include "mesh_cache.h"
#include "pipelines.h"
#include "render_targets.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { TS_START, TS_SHADOW, TS_PROJECTION, TS_GBUFFER, TS_SCATTER, TS_COUNT };

struct lucent_renderer {
    struct vk_context ctx;
    struct pipelines pipes;
    struct render_targets targets;
    struct vk_buffer uniforms;
    struct mesh_cache meshes;
    VkQueryPool queries;
    struct frame_plan plan;   /* rebuilt every frame; lives here to keep 4 KB of samples off the stack */
    int verbose;
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

lucent_renderer *lucent_renderer_create(const lucent_renderer_desc *desc, lucent_error *err)
{
    lucent_status st;
    lucent_renderer *r = calloc(1, sizeof *r);
    if (!r) {
        lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory creating the renderer");
        return NULL;
    }
    r->verbose = desc ? desc->verbose : 0;
    if ((st = vk_context_create(&r->ctx, desc ? desc->device_name : NULL, r->verbose, err)) != LUCENT_OK) {
        free(r);
        return NULL;
    }
    if ((st = pipelines_create(&r->ctx, &r->pipes, err)) ||
        (st = vk_buffer_create(&r->ctx, sizeof(struct frame_uniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                               &r->uniforms, err)))
        goto fail;
    if (r->ctx.timestamp_ns > 0.0) {
        VkQueryPoolCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                     .queryType = VK_QUERY_TYPE_TIMESTAMP, .queryCount = TS_COUNT};
        VK_TRY(vkCreateQueryPool(r->ctx.device, &qci, NULL, &r->queries), err);
    }
    return r;
fail:
    lucent_renderer_destroy(r);
    return NULL;
}

void lucent_renderer_destroy(lucent_renderer *r)
{
    if (!r)
        return;
    /* Frames are synchronous: once lucent_render returned, the GPU holds none of our resources. */
    if (r->ctx.device) {
        mesh_cache_destroy(&r->ctx, &r->meshes);
        render_targets_destroy(&r->ctx, &r->targets);
        vk_buffer_destroy(&r->ctx, &r->uniforms);
        vkDestroyQueryPool(r->ctx.device, r->queries, NULL);
        pipelines_destroy(&r->ctx, &r->pipes);
    }
    vk_context_destroy(&r->ctx);
    free(r);
}

/* Library callers may build scenes by hand: the limits the GPU side relies on are checked again. */
static lucent_status check_scene(const lucent_scene *s, lucent_error *err)
{
    if (s->width < 1 || s->height < 1 || s->width > LUCENT_MAX_IMAGE_SIDE || s->height > LUCENT_MAX_IMAGE_SIDE)
        return lucent_fail(err, LUCENT_E_LIMIT, "width", "image size %dx%d outside 1..%d", s->width, s->height,
                           LUCENT_MAX_IMAGE_SIDE);
    if (s->projection_size < LUCENT_MIN_PROJECTION_SIZE || s->projection_size > LUCENT_MAX_PROJECTION_SIZE)
        return lucent_fail(err, LUCENT_E_LIMIT, "projection_size", "must be %d..%d", LUCENT_MIN_PROJECTION_SIZE,
                           LUCENT_MAX_PROJECTION_SIZE);
    if (s->side_projection_size < 0 || s->side_projection_size > s->projection_size ||
        (s->side_projection_size && s->side_projection_size < LUCENT_MIN_PROJECTION_SIZE))
        return lucent_fail(err, LUCENT_E_LIMIT, "side_projection_size", "must be 0 or %d..projection_size",
                           LUCENT_MIN_PROJECTION_SIZE);
    if (s->samples < 1 || s->samples > LUCENT_MAX_SAMPLES)
        return lucent_fail(err, LUCENT_E_LIMIT, "samples", "must be 1..%d", LUCENT_MAX_SAMPLES);
    if (s->light_count < 1 || s->light_count > LUCENT_MAX_LIGHTS)
        return lucent_fail(err, LUCENT_E_LIMIT, "lights", "must hold 1..%d lights", LUCENT_MAX_LIGHTS);
    return LUCENT_OK;
}

static lucent_status ensure_targets(lucent_renderer *r, const lucent_scene *s, int side_size, lucent_error *err)
{
    struct render_targets *t = &r->targets;
    if (t->width == (uint32_t)s->width && t->height == (uint32_t)s->height &&
        t->projection_size == (uint32_t)s->projection_size && t->side_size == (uint32_t)side_size)
        return LUCENT_OK;
    render_targets_destroy(&r->ctx, t);
    if (r->verbose)
        fprintf(stderr, "lucent: render targets %dx%d, projection %d, sides %d\n", s->width, s->height,
                s->projection_size, side_size);
    return render_targets_create(&r->ctx, &r->pipes, &r->uniforms, (uint32_t)s->width, (uint32_t)s->height,
                                 (uint32_t)s->projection_size, (uint32_t)side_size, t, err);
}

static void set_viewport(VkCommandBuffer cmd, uint32_t w, uint32_t h)
{
    VkViewport vp = {0.0f, 0.0f, (float)w, (float)h, 0.0f, 1.0f};
    VkRect2D sc = {{0, 0}, {w, h}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
}

static void draw(VkCommandBuffer cmd, const struct gpu_geometry *g, int with_normals)
{
    VkBuffer vbs[2] = {g->positions.buffer, g->normals.buffer};
    VkDeviceSize offsets[2] = {0, 0};
    vkCmdBindVertexBuffers(cmd, 0, with_normals ? 2 : 1, vbs, offsets);
    vkCmdBindIndexBuffer(cmd, g->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, g->index_count, 1, 0, 0, 0);
}

static void begin_pass(VkCommandBuffer cmd, VkRenderPass pass, VkFramebuffer fb, uint32_t w, uint32_t h,
                       const VkClearValue *clears, uint32_t clear_count)
{
    VkRenderPassBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO, .renderPass = pass,
                                .framebuffer = fb, .renderArea = {{0, 0}, {w, h}},
                                .clearValueCount = clear_count, .pClearValues = clears};
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    set_viewport(cmd, w, h);
}

static void stamp(lucent_renderer *r, uint32_t query)
{
    if (r->queries)
        vkCmdWriteTimestamp(r->ctx.cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, r->queries, query);
}

static void record_shadows(lucent_renderer *r, const struct frame_plan *plan, const struct gpu_geometry *g,
                           int cull)
{
    VkCommandBuffer cmd = r->ctx.cmd;
    VkClearValue clear = {.depthStencil = {1.0f, 0}};
    for (int s = 0; s < plan->shadow_count; s++) {
        begin_pass(cmd, r->pipes.shadow_pass, r->targets.shadow_fb[s], SHADOW_MAP_SIZE, SHADOW_MAP_SIZE, &clear, 1);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r->pipes.shadow[cull]);
        vkCmdPushConstants(cmd, r->pipes.shadow_layout, VK_SHADER_STAGE_VERTEX_BIT, 0, 64, plan->shadow_clip[s]);
        draw(cmd, g, 0);
        vkCmdEndRenderPass(cmd);
    }
}

static void record_projection_pass(lucent_renderer *r, int which, const struct gpu_geometry *g, VkPipeline pipeline)
{
    VkCommandBuffer cmd = r->ctx.cmd;
    const struct render_targets *t = &r->targets;
    /* Depth -1 marks texels no surface covers. */
    VkClearValue clears[2] = {{.color = {{0.0f, 0.0f, 0.0f, -1.0f}}}, {.depthStencil = {1.0f, 0}}};
    uint32_t side = which == PROJECTION_FRONT ? t->projection_size : t->side_size;
    int32_t view_base = which == PROJECTION_FRONT ? 0 : 1;
    begin_pass(cmd, r->pipes.projection_pass[which], which == PROJECTION_FRONT ? t->front_fb : t->sides_fb, side,
               side, clears, 2);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r->pipes.projection_layout, 0, 1,
                            &t->projection_set, 0, NULL);
    vkCmdPushConstants(cmd, r->pipes.projection_layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                       0, sizeof view_base, &view_base);
    draw(cmd, g, 1);
    vkCmdEndRenderPass(cmd);
}

/* The side images go into the top-left side_size^2 corner of layers 1-4 of the sampled array,
 * where the scatter pass's texel coordinates for those views point. */
static void copy_sides(lucent_renderer *r)
{
    VkCommandBuffer cmd = r->ctx.cmd;
    const struct render_targets *t = &r->targets;
    VkImageMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_SHADER_READ_BIT,
                              .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
                              .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                              .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED, .image = t->projection.image,
                              .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 1, SIDE_VIEWS}};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0,
                         NULL, 1, &b);
    VkImageCopy region = {.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, SIDE_VIEWS},
                          .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, SIDE_VIEWS},
                          .extent = {t->side_size, t->side_size, 1}};
    vkCmdCopyImage(cmd, t->sides.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, t->projection.image,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
    b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, NULL, 0,
                         NULL, 1, &b);
}

static void record_gbuffer(lucent_renderer *r, const struct frame_plan *plan, const struct gpu_geometry *g,
                           int cull)
{
    VkCommandBuffer cmd = r->ctx.cmd;
    VkClearValue clears[3] = {{.color = {{0}}}, {.color = {{0}}}, {.depthStencil = {1.0f, 0}}};
    begin_pass(cmd, r->pipes.gbuffer_pass, r->targets.gbuffer_fb, r->targets.width, r->targets.height, clears, 3);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r->pipes.gbuffer[cull]);
    struct gbuffer_push push;
    memcpy(push.clip_from_world, plan->camera_clip, sizeof push.clip_from_world);
    memcpy(push.eye, plan->camera_eye, sizeof push.eye);
    vkCmdPushConstants(cmd, r->pipes.gbuffer_layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                       0, sizeof push, &push);
    draw(cmd, g, 1);
    vkCmdEndRenderPass(cmd);
}

static void record_scatter(lucent_renderer *r, VkPipeline pipeline)
{
    VkCommandBuffer cmd = r->ctx.cmd;
    int32_t size[2] = {(int32_t)r->targets.width, (int32_t)r->targets.height};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->pipes.scatter_layout, 0, 1,
                            &r->targets.scatter_set, 0, NULL);
    vkCmdPushConstants(cmd, r->pipes.scatter_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof size, size);
    vkCmdDispatch(cmd, (r->targets.width + 7) / 8, (r->targets.height + 7) / 8, 1);
    VkMemoryBarrier to_host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                               .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT, .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host,
                         0, NULL, 0, NULL);
}

static lucent_status record_frame(lucent_renderer *r, const lucent_scene *s, const struct frame_plan *plan,
                                  const struct gpu_mesh *gm, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkCommandBuffer cmd = r->ctx.cmd;
    const struct gpu_geometry *front_mesh = gpu_mesh_geometry(gm, PROXY_FRONT);
    const struct gpu_geometry *side_mesh = gpu_mesh_geometry(gm, PROXY_SIDES);
    VkPipeline front, sides = VK_NULL_HANDLE, scatter;
    int five = plan->view_count > 1;
    /* Projection and shadow views look from outside the bounding sphere: on a closed mesh their
     * back faces are always hidden. The camera may be inside. */
    int cull = gm->mesh->closed, cull_camera = cull && plan->camera_outside;
    st = pipelines_projection(&r->ctx, &r->pipes, PROJECTION_FRONT, plan->light_count, plan->shadow_mask, cull,
                              &front, err);
    if (st == LUCENT_OK && five)
        st = pipelines_projection(&r->ctx, &r->pipes, PROJECTION_SIDES, plan->light_count, plan->shadow_mask, cull,
                                  &sides, err);
    if (st == LUCENT_OK)
        st = pipelines_scatter(&r->ctx, &r->pipes, s->samples, plan->view_count, s->sampling, &scatter, err);
    if (st != LUCENT_OK)
        return st;
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    VK_TRY(vkBeginCommandBuffer(cmd, &bi), err);
    if (r->queries)
        vkCmdResetQueryPool(cmd, r->queries, 0, TS_COUNT);
    stamp(r, TS_START);
    record_shadows(r, plan, side_mesh, cull);
    stamp(r, TS_SHADOW);
    record_projection_pass(r, PROJECTION_FRONT, front_mesh, front);
    if (five) {
        record_projection_pass(r, PROJECTION_SIDES, side_mesh, sides);
        copy_sides(r);
    }
    stamp(r, TS_PROJECTION);
    record_gbuffer(r, plan, &gm->full, cull_camera);
    stamp(r, TS_GBUFFER);
    record_scatter(r, scatter);
    stamp(r, TS_SCATTER);
    VK_TRY(vkEndCommandBuffer(cmd), err);
fail:
    return st;
}

static void read_pass_times(lucent_renderer *r, lucent_stats *stats)
{
    uint64_t ts[TS_COUNT];
    if (!r->queries || vkGetQueryPoolResults(r->ctx.device, r->queries, 0, TS_COUNT, sizeof ts, ts,
                                             sizeof ts[0], VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
        return;
    double k = r->ctx.timestamp_ns * 1e-6;
    stats->ms_shadow = (double)(ts[TS_SHADOW] - ts[TS_START]) * k;
    stats->ms_projection = (double)(ts[TS_PROJECTION] - ts[TS_SHADOW]) * k;
    stats->ms_gbuffer = (double)(ts[TS_GBUFFER] - ts[TS_PROJECTION]) * k;
    stats->ms_scatter = (double)(ts[TS_SCATTER] - ts[TS_GBUFFER]) * k;
}

/* AOVs only travel in EXR; a PNG request skips copying them. */
static lucent_status read_image(lucent_renderer *r, int with_aovs, lucent_image *out, lucent_error *err)
{
    const struct render_targets *t = &r->targets;
    lucent_status st = lucent_image_alloc(out, (int)t->width, (int)t->height, with_aovs, err);
    if (st != LUCENT_OK)
        return st;
    size_t pixels = (size_t)t->width * t->height;
    const unsigned char *base = t->output.mapped;
    const float *normal_view = (const float *)(base + t->normal_offset);
    memcpy(out->rgba, base + t->color_offset, pixels * 16);
    if (!with_aovs)
        return LUCENT_OK;
    memcpy(out->depth, base + t->depth_offset, pixels * 4);
    for (size_t i = 0; i < pixels; i++) {
        memcpy(&out->normal[i * 3], &normal_view[i * 4], 12);
        out->view[i] = normal_view[i * 4 + 3];
    }
    return LUCENT_OK;
}

static void describe(const lucent_scene *s, const struct frame_plan *plan, const struct gpu_mesh *gm,
                     lucent_stats *stats)
{
    char lights[512] = "";
    size_t n = 0;
    int shared = s->sampling == LUCENT_SAMPLING_SHARED;
    for (int l = 0; l < s->light_count && n < sizeof lights; l++)
        n += (size_t)snprintf(lights + n, sizeof lights - n, "%s\"%s\"", l ? "," : "", plan->shadow_reason[l]);
    snprintf(stats->modelled, sizeof stats->modelled,
             "{\"method\":\"%s\",\"views\":%d,\"samples_per_channel\":%d,\"sampling\":\"%s\","
             "\"texel_fetches_per_pixel\":%d,\"projection_size\":%d,\"side_projection_size\":%d,"
             "\"scale_mm\":%.9g,\"shadows\":[%s],"
             "\"projection_triangles\":{\"front\":%u,\"sides_and_shadows\":%u},"
             "\"hidden_point_fallback\":\"next best-facing visible view, then front\","
             "\"single_scattering\":false}",
             s->method == LUCENT_METHOD_SINGLE ? "single" : "five", plan->view_count, s->samples,
             shared ? "shared" : "per_channel", shared ? s->samples : 3 * s->samples, s->projection_size,
             plan->view_count > 1 ? plan->side_projection_size : 0, plan->scale_mm, lights,
             gpu_mesh_geometry(gm, PROXY_FRONT)->index_count / 3, gpu_mesh_geometry(gm, PROXY_SIDES)->index_count / 3);
    stats->triangles = gm->mesh->triangle_count;
    stats->proxy_triangles = gm->proxies[PROXY_FRONT].triangles;
    stats->shadow_maps = plan->shadow_count;
    stats->views = plan->view_count;
}

lucent_status lucent_render(lucent_renderer *r, const lucent_scene *scene, lucent_image *out,
                            lucent_stats *stats, lucent_error *err)
{
    lucent_stats local;
    if (!stats)
        stats = &local;
    memset(stats, 0, sizeof *stats);
    memset(out, 0, sizeof *out);
    snprintf(stats->device, sizeof stats->device, "%s", r->ctx.device_name);
    double t0 = now_ms();
    struct gpu_mesh *gm;
    struct frame_plan *plan = &r->plan;
    lucent_status st;
    if ((st = check_scene(scene, err)) ||
        (st = mesh_cache_get(&r->ctx, &r->meshes, &scene->mesh, scene->projection_size,
                                    frame_side_projection_size(scene), &gm, &stats->ms_mesh_load, err)))
        return st;
    int proxied = gm->proxies[PROXY_FRONT].triangles || gm->proxies[PROXY_SIDES].triangles;
    double tolerance = proxied ? PROXY_TOLERANCE * gm->mesh->radius : 0.0;
    if ((st = frame_plan_build(scene, gm->mesh, tolerance, plan, err)) ||
        (st = ensure_targets(r, scene, plan->side_projection_size, err)))
        return st;
    memcpy(r->uniforms.mapped, &plan->uniforms, sizeof plan->uniforms);
    if ((st = record_frame(r, scene, plan, gm, err)) || (st = vk_submit_and_wait(&r->ctx, err)))
        return st;
    read_pass_times(r, stats);
    double t1 = now_ms();
    if ((st = read_image(r, scene->format == LUCENT_FORMAT_EXR, out, err)))
        return st;
    stats->ms_readback = now_ms() - t1;
    stats->ms_total = now_ms() - t0;
    describe(scene, plan, gm, stats);
    return LUCENT_OK;
}

int lucent_stats_json(const lucent_stats *s, char *buf, size_t cap)
{
    int n = snprintf(buf, cap,
                     "{\"device\":\"%s\",\"triangles\":%u,\"proxy_triangles\":%u,\"shadow_maps\":%d,\"views\":%d,"
                     "\"ms\":{\"mesh_load\":%.3f,\"shadow\":%.3f,\"projection\":%.3f,\"gbuffer\":%.3f,"
                     "\"scatter\":%.3f,\"readback\":%.3f,\"total\":%.3f},\"modelled\":%s}",
                     s->device, s->triangles, s->proxy_triangles, s->shadow_maps, s->views, s->ms_mesh_load,
                     s->ms_shadow, s->ms_projection, s->ms_gbuffer, s->ms_scatter, s->ms_readback, s->ms_total,
                     s->modelled[0] ? s->modelled : "{}");
    return n < 0 || (size_t)n >= cap ? -1 : n;
}
