/* vk_backend.c - the Vulkan half of a renderer behind gpu.h: a context on a shared device, fixed pipelines,
 * size-dependent targets, a uniform buffer and timestamp queries; one frame recorded, submitted, waited for. */
#include "frame_record.h"
#include "gpu.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct vk_gpu {
    struct gpu base;
    struct vk_context ctx;
    struct pipelines pipes;
    struct render_targets targets;
    struct vk_buffer uniforms;
    VkQueryPool queries;
    int verbose;
};

static void vk_gpu_close(struct gpu *base)
{
    struct vk_gpu *g = (struct vk_gpu *)base;
    /* Frames are synchronous: once a frame returned, the GPU holds none of our resources, unless its
     * wait timed out. Work of a hung device may still write them: they are left, not freed. */
    if (g->ctx.device && vk_context_settle(&g->ctx, NULL) == LUCENT_E_DEVICE_LOST && g->ctx.in_flight) {
        fprintf(stderr, "lucent: device \"%s\" hung; its renderer's GPU memory is left allocated\n",
                g->ctx.device_name);
        free(g);
        return;
    }
    if (g->ctx.device) {
        render_targets_destroy(&g->ctx, &g->targets);
        vk_buffer_destroy(&g->ctx, &g->uniforms);
        vkDestroyQueryPool(g->ctx.device, g->queries, NULL);
        pipelines_destroy(&g->ctx, &g->pipes);
    }
    vk_context_destroy(&g->ctx);
    free(g);
}

static lucent_status vk_gpu_settle(struct gpu *base, lucent_error *err)
{
    return vk_context_settle(&((struct vk_gpu *)base)->ctx, err);
}

static lucent_status upload(struct vk_context *ctx, const void *data, VkDeviceSize size, VkBufferUsageFlags usage,
                            struct vk_buffer *out, lucent_error *err)
{
    lucent_status st = vk_buffer_create(ctx, size, usage, out, err);
    if (st == LUCENT_OK)
        memcpy(out->mapped, data, size);
    return st;
}

/* Buffers a hung device's work may still read are left allocated, as vk_gpu_close leaves the rest. */
static void vk_geometry_free(struct gpu *base, struct gpu_geometry *geo)
{
    struct vk_context *ctx = &((struct vk_gpu *)base)->ctx;
    if (ctx->in_flight) {
        free(geo);
        return;
    }
    vk_buffer_destroy(ctx, &geo->positions);
    vk_buffer_destroy(ctx, &geo->normals);
    vk_buffer_destroy(ctx, &geo->indices);
    free(geo);
}

static lucent_status vk_geometry_upload(struct gpu *base, const float *positions, const float *shading,
                                        uint32_t vertex_count, const uint32_t *indices, uint32_t index_count,
                                        struct gpu_geometry **out, lucent_error *err)
{
    struct vk_gpu *g = (struct vk_gpu *)base;
    VkDeviceSize vbytes = (VkDeviceSize)vertex_count * 3 * sizeof(float);
    struct gpu_geometry *geo = calloc(1, sizeof *geo);
    if (!geo)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory uploading the mesh");
    lucent_status st;
    if ((st = upload(&g->ctx, positions, vbytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, &geo->positions, err)) ||
        (st = upload(&g->ctx, shading, vbytes / 3 * 4, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, &geo->normals, err)) ||
        (st = upload(&g->ctx, indices, (VkDeviceSize)index_count * 4, VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                     &geo->indices, err))) {
        vk_geometry_free(base, geo);
        return st;
    }
    *out = geo;
    return LUCENT_OK;
}

static lucent_status ensure_targets(struct vk_gpu *g, const struct gpu_frame *f, lucent_error *err)
{
    const struct render_targets *t = &g->targets;
    if (g->verbose && (t->width != f->width || t->height != f->height || t->projection_size != f->projection_size ||
                       t->side_size != f->side_size))
        fprintf(stderr, "lucent: render targets %ux%u, projection %u, sides %u\n", f->width, f->height,
                f->projection_size, f->side_size);
    return render_targets_fit(&g->ctx, &g->pipes, &g->uniforms, f->width, f->height, f->projection_size,
                              f->side_size, &g->targets, err);
}

static void read_pass_times(struct vk_gpu *g, struct gpu_result *out)
{
    uint64_t ts[TS_COUNT];
    if (!g->queries || vkGetQueryPoolResults(g->ctx.device, g->queries, 0, TS_COUNT, sizeof ts, ts, sizeof ts[0],
                                             VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
        return;
    double k = g->ctx.timestamp_ns * 1e-6;
    out->ms_shadow = (double)(ts[TS_SHADOW] - ts[TS_START]) * k;
    out->ms_projection = (double)(ts[TS_PROJECTION] - ts[TS_SHADOW]) * k;
    out->ms_gbuffer = (double)(ts[TS_GBUFFER] - ts[TS_PROJECTION]) * k;
    out->ms_scatter = (double)(ts[TS_SCATTER] - ts[TS_GBUFFER]) * k;
}

static lucent_status vk_gpu_render(struct gpu *base, const struct gpu_frame *f, struct gpu_result *out,
                                   lucent_error *err)
{
    struct vk_gpu *g = (struct vk_gpu *)base;
    lucent_status st;
    if ((st = ensure_targets(g, f, err)))
        return st;
    g->base.memory_bytes = g->ctx.memory_bytes;
    memcpy(g->uniforms.mapped, &f->plan->uniforms, sizeof f->plan->uniforms);
    struct frame_gpu gpu = {&g->ctx, &g->pipes, &g->targets, g->queries};
    if ((st = frame_record(&gpu, f, err)))
        return st;
    g->ctx.fault = gpu_fault_next_frame();
    if ((st = vk_submit_and_wait(&g->ctx, err)))
        return st;
    read_pass_times(g, out);
    const unsigned char *mapped = g->targets.output.mapped;
    out->rgba = (const float *)(mapped + g->targets.color_offset);
    out->normal_view = (const float *)(mapped + g->targets.normal_offset);
    out->depth = (const float *)(mapped + g->targets.depth_offset);
    return LUCENT_OK;
}

static const struct gpu_ops vk_gpu_ops = {vk_gpu_close, vk_gpu_settle, vk_geometry_upload, vk_geometry_free,
                                          vk_gpu_render};

lucent_status vk_gpu_open(const char *device_name, int verbose, struct gpu **out, lucent_error *err)
{
    lucent_status st;
    struct vk_gpu *g = calloc(1, sizeof *g);
    if (!g)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory creating the renderer");
    g->base.ops = &vk_gpu_ops;
    g->base.backend = "vulkan";
    g->verbose = verbose;
    if ((st = vk_context_create(&g->ctx, device_name, verbose, err)) != LUCENT_OK) {
        free(g);
        return st;
    }
    snprintf(g->base.device, sizeof g->base.device, "%s", g->ctx.device_name);
    g->base.max_pixels = g->ctx.limits.maxStorageBufferRange / 16u;
    snprintf(g->base.max_pixels_why, sizeof g->base.max_pixels_why,
             "its maxStorageBufferRange of %u bytes over 16 bytes a pixel", g->ctx.limits.maxStorageBufferRange);
    if ((st = pipelines_create(&g->ctx, &g->pipes, err)) ||
        (st = vk_buffer_create(&g->ctx, sizeof(struct frame_uniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                               &g->uniforms, err)))
        goto fail;
    if (g->ctx.timestamp_ns > 0.0) {
        VkQueryPoolCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                     .queryType = VK_QUERY_TYPE_TIMESTAMP, .queryCount = TS_COUNT};
        VK_TRY(vkCreateQueryPool(g->ctx.device, &qci, NULL, &g->queries), err);
    }
    g->base.memory_bytes = g->ctx.memory_bytes;
    *out = &g->base;
    return LUCENT_OK;
fail:
    vk_gpu_close(&g->base);
    return st;
}
