/* gl_frame.c - one frame through OpenGL, pass for pass as frame_record.c records it for Vulkan: shadow maps,
 * projection images (each side and light view into its layer's corner), their mip chains and the owned
 * images, the camera G-buffer and the scatter dispatches. OpenGL orders the passes itself; only what
 * shaders write through images and storage buffers needs glMemoryBarrier. */
#include "gl_frame.h"

#include <string.h>

static void push(const struct gl_frame_gpu *gpu, const void *data, GLsizeiptr size)
{
    glNamedBufferSubData(gpu->push, 0, size, data);
}

static void stamp(const struct gl_frame_gpu *gpu, int query)
{
    if (gpu->queries[0])
        glQueryCounter(gpu->queries[query], GL_TIMESTAMP);
}

static void draw(const struct gpu_draw *d)
{
    glBindVertexArray(d->geometry->vertex_array);
    glDrawElements(GL_TRIANGLES, (GLsizei)d->index_count, GL_UNSIGNED_INT, NULL);
}

static void set_cull(int cull)
{
    if (cull)
        glEnable(GL_CULL_FACE);
    else
        glDisable(GL_CULL_FACE);
}

static void bind_texture(GLuint unit, GLuint texture, GLuint sampler)
{
    glBindTextureUnit(unit, texture);
    glBindSampler(unit, sampler);
}

static void draw_shadows(const struct gl_frame_gpu *gpu, const struct frame_plan *plan, const struct gpu_draw *d)
{
    const float far = 1.0f;
    glUseProgram(gpu->programs->shadow);
    glViewport(0, 0, SHADOW_MAP_SIZE, SHADOW_MAP_SIZE);
    set_cull(plan->cull_back_faces);
    for (int s = 0; s < plan->shadow_count; s++) {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gpu->targets->shadow_fb[s]);
        glClearBufferfv(GL_DEPTH, 0, &far);
        push(gpu, plan->shadow_clip[s], 64);
        draw(d);
    }
}

/* The views of one projection pass, each into the size^2 corner of its layer (depth -1 marks texels no
 * surface covers). */
static void draw_projection(const struct gl_frame_gpu *gpu, const struct frame_passes *passes, int which,
                            GLuint program, const struct gpu_draw *d, int cull)
{
    const struct gl_targets *t = gpu->targets;
    const float empty[4] = {0.0f, 0.0f, 0.0f, -1.0f}, zero[4] = {0}, far = 1.0f;
    GLsizei size = (GLsizei)(which == PROJECTION_FRONT ? t->projection_size : t->side_size);
    glUseProgram(program);
    bind_texture(1, t->shadow_depth, t->shadow_compare);
    set_cull(cull);
    glViewport(0, 0, size, size);
    glScissor(0, 0, size, size);
    glEnable(GL_SCISSOR_TEST);
    for (int v = 0; v < passes->views[which]; v++) {
        int32_t view = passes->first_view[which] + v;
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->view_fb[view]);
        glClearBufferfv(GL_COLOR, 0, empty);
        glClearBufferfv(GL_COLOR, 1, zero);
        glClearBufferfv(GL_DEPTH, 0, &far);
        push(gpu, &view, sizeof view);
        draw(d);
    }
    glDisable(GL_SCISSOR_TEST);
}

/* Level `level` of one layer from level - 1 (a 2x2 mean, as vkCmdBlitImage's linear filter makes it). */
static void blit_level(const struct gl_targets *t, GLuint texture, uint32_t level, uint32_t size, GLint layer)
{
    GLint src = (GLint)(size >> (level - 1)), dst = (GLint)(size >> level);
    glNamedFramebufferTextureLayer(t->blit_fb[0], GL_COLOR_ATTACHMENT0, texture, (GLint)level - 1, layer);
    glNamedFramebufferTextureLayer(t->blit_fb[1], GL_COLOR_ATTACHMENT0, texture, (GLint)level, layer);
    glNamedFramebufferReadBuffer(t->blit_fb[0], GL_COLOR_ATTACHMENT0);
    glNamedFramebufferDrawBuffer(t->blit_fb[1], GL_COLOR_ATTACHMENT0);
    glBlitNamedFramebuffer(t->blit_fb[0], t->blit_fb[1], 0, 0, src, src, 0, 0, dst, dst, GL_COLOR_BUFFER_BIT,
                           GL_LINEAR);
}

/* The mip chain of the projection or owned images, as frame_record.c's record_mips: the front layer whole,
 * the side layers' corners (side_size) and the light layers' (light_size) only. */
static void make_mips(const struct gl_targets *t, GLuint texture, uint32_t levels, uint32_t size, uint32_t side_size,
                      uint32_t light_size, int side_views)
{
    for (uint32_t level = 1; level < levels; level++) {
        blit_level(t, texture, level, size, 0);
        for (int layer = 1; layer <= side_views; layer++) {
            uint32_t corner = layer <= SIDE_VIEWS ? side_size : light_size;
            if (corner >> level)
                blit_level(t, texture, level, corner, layer);
        }
    }
}

static void draw_ownership(const struct gl_frame_gpu *gpu, struct owned_sides o, int side_views)
{
    const struct gl_targets *t = gpu->targets;
    glUseProgram(gpu->programs->ownership);
    bind_texture(1, t->projection, t->filtered);
    bind_texture(9, t->normals, t->nearest);
    glBindImageTexture(10, t->owned, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    int32_t first_view[2] = {0, 0};
    push(gpu, first_view, sizeof first_view);
    glDispatchCompute((o.front + 7) / 8, (o.front + 7) / 8, 1);
    first_view[0] = 1;
    push(gpu, first_view, sizeof first_view);
    if (side_views)
        glDispatchCompute((o.sides + 7) / 8, (o.sides + 7) / 8, (GLuint)(side_views < SIDE_VIEWS ? side_views : SIDE_VIEWS));
    if (side_views > SIDE_VIEWS) {
        first_view[0] = 1 + SIDE_VIEWS;
        push(gpu, first_view, sizeof first_view);
        glDispatchCompute((o.lights + 7) / 8, (o.lights + 7) / 8, (GLuint)(side_views - SIDE_VIEWS));
    }
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT);
}

static void draw_gbuffer(const struct gl_frame_gpu *gpu, const struct frame_plan *plan, const struct gpu_draw *d)
{
    const struct gl_targets *t = gpu->targets;
    const float zero[4] = {0}, far = 1.0f;
    float block[20];
    memcpy(block, plan->camera_clip, sizeof plan->camera_clip);
    memcpy(block + 16, plan->camera_eye, sizeof plan->camera_eye);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->gbuffer_fb);
    glViewport(0, 0, (GLsizei)t->width, (GLsizei)t->height);
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearBufferfv(GL_COLOR, 1, zero);
    glClearBufferfv(GL_DEPTH, 0, &far);
    glUseProgram(gpu->programs->gbuffer);
    push(gpu, block, sizeof block);
    set_cull(plan->cull_camera);
    draw(d);
}

static void draw_scatter(const struct gl_frame_gpu *gpu, const struct frame_plan *plan, const GLuint program[3])
{
    const struct gl_targets *t = gpu->targets;
    GLuint w = t->width, h = t->height, block = (GLuint)plan->far_block;
    GLsizeiptr pixels = (GLsizeiptr)w * h;
    bind_texture(1, t->projection, t->filtered);
    bind_texture(2, t->gbuffer_position, t->nearest);
    bind_texture(3, t->gbuffer_normal, t->nearest);
    bind_texture(8, t->owned, t->filtered);
    bind_texture(9, t->normals, t->nearest);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 4, t->output, t->color_offset, pixels * 16);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 5, t->output, t->normal_offset, pixels * 16);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 6, t->output, t->depth_offset, pixels * 4);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 7, t->far, 0, t->far_bytes);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 11, t->far, t->far_filtered_offset, t->far_bytes);
    int32_t size[2] = {(int32_t)w, (int32_t)h};
    push(gpu, size, sizeof size);
    const int block_passes[2] = {SCATTER_FAR, SCATTER_FAR_FILTER};
    for (int i = 0; i < 2 && program[block_passes[i]]; i++) {
        glUseProgram(program[block_passes[i]]);
        glDispatchCompute((frame_far_blocks(w, block) + 7) / 8, (frame_far_blocks(h, block) + 7) / 8, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    glUseProgram(program[SCATTER_COMPOSE]);
    glDispatchCompute((w + 7) / 8, (h + 7) / 8, 1);
    glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
}

static lucent_status wait_for_frame(lucent_error *err)
{
    GLsync done = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    if (!done)
        return gl_check("glFenceSync", err);
    GLenum waited = glClientWaitSync(done, GL_SYNC_FLUSH_COMMANDS_BIT, GL_FRAME_WAIT_NS);
    glDeleteSync(done);
    if (waited == GL_TIMEOUT_EXPIRED)
        return lucent_fail(err, LUCENT_E_DEVICE_LOST, "", "the OpenGL frame did not finish within %llu s",
                           GL_FRAME_WAIT_NS / 1000000000ull);
    if (waited == GL_WAIT_FAILED)
        return gl_check("glClientWaitSync", err);
    return LUCENT_OK;
}

lucent_status gl_frame_draw(const struct gl_frame_gpu *gpu, const struct gpu_frame *frame, lucent_error *err)
{
    const struct frame_plan *plan = frame->plan;
    const struct gl_targets *t = gpu->targets;
    struct frame_passes passes;
    GLuint projection = 0, scatter[3] = {0};
    lucent_status st = LUCENT_OK;
    frame_passes_plan(plan, &passes);
    gl_programs_begin_frame(gpu->programs);
    st = gl_programs_projection(gpu->programs, plan->light_count, plan->shadow_mask, &projection, err);
    for (int pass = 0; st == LUCENT_OK && pass < 3; pass++)
        if (passes.scatter[pass])
            st = gl_programs_scatter(gpu->programs, &passes.variant[pass], &scatter[pass], err);
    if (st != LUCENT_OK)
        return st;
    glNamedBufferSubData(gpu->uniforms, 0, sizeof plan->uniforms, &plan->uniforms);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, gpu->uniforms);
    glBindBufferBase(GL_UNIFORM_BUFFER, GL_PUSH_BINDING, gpu->push);
    stamp(gpu, TS_START);
    draw_shadows(gpu, plan, &frame->sides);
    stamp(gpu, TS_SHADOW);
    draw_projection(gpu, &passes, PROJECTION_FRONT, projection, &frame->front, plan->cull_back_faces);
    for (int which = PROJECTION_SIDES; which < PROJECTION_PASSES; which++)
        if (passes.projection[which])
            draw_projection(gpu, &passes, which, projection, &frame->sides, plan->cull_back_faces);
    int side_views = plan->view_count - 1;
    if (plan->gather_owned) {   /* the owned images are read instead of the projection images' mips, which are not made */
        struct owned_sides o = frame_owned_sides(t->projection_size, t->side_size);
        draw_ownership(gpu, o, side_views);
        make_mips(t, t->owned, t->owned_levels, o.front, o.sides, o.lights, side_views);
    } else {
        make_mips(t, t->projection, t->projection_levels, t->projection_size, t->side_size, t->side_size, side_views);
    }
    stamp(gpu, TS_PROJECTION);
    if ((st = gl_check("the shadow and projection passes", err)))
        return st;
    draw_gbuffer(gpu, plan, &frame->full);
    stamp(gpu, TS_GBUFFER);
    draw_scatter(gpu, plan, scatter);
    stamp(gpu, TS_SCATTER);
    if ((st = gl_check("the G-buffer and scatter passes", err)))
        return st;
    return wait_for_frame(err);
}
