/* gl_targets.c - creates the per-size OpenGL textures, framebuffers and buffers, re-creating only the group
 * whose size changed. Everything here is owned by struct gl_targets. */
#include "gl_targets.h"

#include <string.h>

static void texture_2d(GLenum target, GLenum format, uint32_t w, uint32_t h, uint32_t layers, uint32_t levels,
                       GLuint *out)
{
    glCreateTextures(target, 1, out);
    if (target == GL_TEXTURE_2D_ARRAY)
        glTextureStorage3D(*out, (GLsizei)levels, format, (GLsizei)w, (GLsizei)h, (GLsizei)layers);
    else
        glTextureStorage2D(*out, (GLsizei)levels, format, (GLsizei)w, (GLsizei)h);
}

static lucent_status complete(GLuint fb, const char *what, lucent_error *err)
{
    GLenum status = glCheckNamedFramebufferStatus(fb, GL_DRAW_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return lucent_fail(err, LUCENT_E_GPU, "", "the %s framebuffer is incomplete (0x%04x)", what, (unsigned)status);
    return LUCENT_OK;
}

static void sampler(GLenum min, GLenum mag, int compare, GLuint *out)
{
    glCreateSamplers(1, out);
    glSamplerParameteri(*out, GL_TEXTURE_MIN_FILTER, (GLint)min);
    glSamplerParameteri(*out, GL_TEXTURE_MAG_FILTER, (GLint)mag);
    glSamplerParameteri(*out, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(*out, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(*out, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    if (compare) {
        glSamplerParameteri(*out, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glSamplerParameteri(*out, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    }
}

static lucent_status make_fixed(struct gl_targets *t, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    texture_2d(GL_TEXTURE_2D_ARRAY, GL_DEPTH_COMPONENT32F, SHADOW_MAP_SIZE, SHADOW_MAP_SIZE, LUCENT_MAX_LIGHTS, 1,
               &t->shadow_depth);
    glCreateFramebuffers(LUCENT_MAX_LIGHTS, t->shadow_fb);
    for (int l = 0; l < LUCENT_MAX_LIGHTS && st == LUCENT_OK; l++) {
        glNamedFramebufferTextureLayer(t->shadow_fb[l], GL_DEPTH_ATTACHMENT, t->shadow_depth, 0, l);
        glNamedFramebufferDrawBuffer(t->shadow_fb[l], GL_NONE);
        st = complete(t->shadow_fb[l], "shadow map", err);
    }
    glCreateFramebuffers(2, t->blit_fb);
    /* Vulkan's samplers (pipelines.c): mip levels chosen nearest, texels filtered within a level. */
    sampler(GL_NEAREST_MIPMAP_NEAREST, GL_NEAREST, 0, &t->nearest);
    sampler(GL_LINEAR_MIPMAP_NEAREST, GL_LINEAR, 0, &t->filtered);
    sampler(GL_LINEAR, GL_LINEAR, 1, &t->shadow_compare);
    return st == LUCENT_OK ? gl_check("creating the shadow maps", err) : st;
}

/* The projection, normal and owned images start with no flux and depth -1 everywhere: frames write only
 * the side views' corners of layers 1-6, and a bilinear read at a corner's edge touches the texels beside it. */
static lucent_status make_projection(struct gl_targets *t, lucent_error *err)
{
    uint32_t s = t->projection_size, side = t->side_size;
    uint32_t shift = (uint32_t)frame_owned_shift((int)s);
    t->projection_levels = frame_mip_levels(s);
    t->owned_levels = frame_mip_levels(s >> shift);
    texture_2d(GL_TEXTURE_2D_ARRAY, GL_RGBA32F, s, s, FRAME_MAX_VIEWS, t->projection_levels, &t->projection);
    texture_2d(GL_TEXTURE_2D_ARRAY, GL_RGBA32F, s, s, FRAME_MAX_VIEWS, 1, &t->normals);
    texture_2d(GL_TEXTURE_2D_ARRAY, GL_RGBA32F, s >> shift, s >> shift, FRAME_MAX_VIEWS, t->owned_levels, &t->owned);
    texture_2d(GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, s, s, 1, 1, &t->front_depth);
    texture_2d(GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, side, side, 1, 1, &t->side_depth);
    const float empty[4] = {0.0f, 0.0f, 0.0f, -1.0f};
    GLuint cleared[3] = {t->projection, t->normals, t->owned};
    uint32_t levels[3] = {t->projection_levels, 1, t->owned_levels};
    for (int i = 0; i < 3; i++)
        for (uint32_t level = 0; level < levels[i]; level++)
            glClearTexImage(cleared[i], (GLint)level, GL_RGBA, GL_FLOAT, empty);
    glCreateFramebuffers(FRAME_MAX_VIEWS, t->view_fb);
    const GLenum draw[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    for (int k = 0; k < FRAME_MAX_VIEWS; k++) {
        glNamedFramebufferTextureLayer(t->view_fb[k], GL_COLOR_ATTACHMENT0, t->projection, 0, k);
        glNamedFramebufferTextureLayer(t->view_fb[k], GL_COLOR_ATTACHMENT1, t->normals, 0, k);
        glNamedFramebufferTexture(t->view_fb[k], GL_DEPTH_ATTACHMENT, k ? t->side_depth : t->front_depth, 0);
        glNamedFramebufferDrawBuffers(t->view_fb[k], 2, draw);
        lucent_status st = complete(t->view_fb[k], "projection", err);
        if (st != LUCENT_OK)
            return st;
    }
    return gl_check("creating the projection images", err);
}

static GLintptr align_up(GLintptr v, GLintptr a)
{
    return a > 1 ? (v + a - 1) / a * a : v;
}

static lucent_status make_image_sized(struct gl_targets *t, lucent_error *err)
{
    uint32_t w = t->width, h = t->height;
    texture_2d(GL_TEXTURE_2D, GL_RGBA32F, w, h, 1, 1, &t->gbuffer_position);
    texture_2d(GL_TEXTURE_2D, GL_RGBA32F, w, h, 1, 1, &t->gbuffer_normal);
    texture_2d(GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, w, h, 1, 1, &t->gbuffer_depth);
    glCreateFramebuffers(1, &t->gbuffer_fb);
    glNamedFramebufferTexture(t->gbuffer_fb, GL_COLOR_ATTACHMENT0, t->gbuffer_position, 0);
    glNamedFramebufferTexture(t->gbuffer_fb, GL_COLOR_ATTACHMENT1, t->gbuffer_normal, 0);
    glNamedFramebufferTexture(t->gbuffer_fb, GL_DEPTH_ATTACHMENT, t->gbuffer_depth, 0);
    const GLenum draw[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(t->gbuffer_fb, 2, draw);
    lucent_status st = complete(t->gbuffer_fb, "G-buffer", err);
    if (st != LUCENT_OK)
        return st;
    GLint a = 1;
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &a);
    GLintptr pixels = (GLintptr)w * h;
    t->color_offset = 0;
    t->normal_offset = align_up(pixels * 16, a);
    t->depth_offset = align_up(t->normal_offset + pixels * 16, a);
    GLsizeiptr out_bytes = t->depth_offset + pixels * 4;
    GLbitfield map = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    glCreateBuffers(1, &t->output);
    glNamedBufferStorage(t->output, out_bytes, NULL, map);
    t->output_mapped = glMapNamedBufferRange(t->output, 0, out_bytes, map);
    uint32_t b = (uint32_t)frame_far_block((int)w, (int)h);
    t->far_bytes = (GLsizeiptr)frame_far_blocks(w, b) * frame_far_blocks(h, b) * FRAME_FAR_SAMPLE_BYTES;
    /* Blocks of one pixel are not filtered (frame_passes.h): the compose pass reads the far samples. */
    t->far_filtered_offset = b > 1 ? align_up(t->far_bytes, a) : 0;
    glCreateBuffers(1, &t->far);
    glNamedBufferStorage(t->far, t->far_filtered_offset + t->far_bytes, NULL, 0);
    if ((st = gl_check("creating the G-buffer and output buffers", err)) == LUCENT_OK && !t->output_mapped)
        st = lucent_fail(err, LUCENT_E_GPU, "", "glMapNamedBufferRange of the %lld-byte output buffer failed",
                         (long long)out_bytes);
    return st;
}

static void destroy_projection(struct gl_targets *t)
{
    glDeleteFramebuffers(FRAME_MAX_VIEWS, t->view_fb);
    GLuint textures[5] = {t->projection, t->normals, t->owned, t->front_depth, t->side_depth};
    glDeleteTextures(5, textures);
    memset(t->view_fb, 0, sizeof t->view_fb);
    t->projection = t->normals = t->owned = t->front_depth = t->side_depth = 0;
    t->projection_size = t->side_size = 0;
}

static void destroy_image_sized(struct gl_targets *t)
{
    if (t->output_mapped)
        glUnmapNamedBuffer(t->output);
    t->output_mapped = NULL;
    GLuint buffers[2] = {t->output, t->far};
    glDeleteBuffers(2, buffers);
    glDeleteFramebuffers(1, &t->gbuffer_fb);
    GLuint textures[3] = {t->gbuffer_position, t->gbuffer_normal, t->gbuffer_depth};
    glDeleteTextures(3, textures);
    t->output = t->far = t->gbuffer_fb = t->gbuffer_position = t->gbuffer_normal = t->gbuffer_depth = 0;
    t->width = t->height = 0;
}

/* Device memory the targets hold (mip chains a third more than their first level). */
static uint64_t held_bytes(const struct gl_targets *t)
{
    uint64_t b = (uint64_t)SHADOW_MAP_SIZE * SHADOW_MAP_SIZE * LUCENT_MAX_LIGHTS * 4;
    uint64_t s = t->projection_size, side = t->side_size, shift = (uint64_t)frame_owned_shift((int)s);
    uint64_t px = (uint64_t)t->width * t->height;
    b += s * s * FRAME_MAX_VIEWS * 16 * 4 / 3 * 2 + (s >> shift) * (s >> shift) * FRAME_MAX_VIEWS * 16 * 4 / 3;
    b += s * s * 4 + side * side * 4 + px * (16 + 16 + 4) + (uint64_t)t->depth_offset + px * 4;
    return b + (uint64_t)(t->far_filtered_offset + t->far_bytes);
}

lucent_status gl_targets_fit(uint32_t width, uint32_t height, uint32_t projection_size, uint32_t side_size,
                             struct gl_targets *t, lucent_error *err)
{
    int new_fixed = t->shadow_depth == 0;
    int new_projection = t->projection_size != projection_size || t->side_size != side_size;
    int new_image = t->width != width || t->height != height;
    if (!new_fixed && !new_projection && !new_image)
        return LUCENT_OK;
    if (new_projection)
        destroy_projection(t);
    if (new_image)
        destroy_image_sized(t);
    t->projection_size = projection_size;
    t->side_size = side_size;
    t->width = width;
    t->height = height;
    lucent_status st;
    if ((new_fixed && (st = make_fixed(t, err))) || (new_projection && (st = make_projection(t, err))) ||
        (new_image && (st = make_image_sized(t, err)))) {
        gl_targets_destroy(t);
        return st;
    }
    t->bytes = held_bytes(t);
    return LUCENT_OK;
}

void gl_targets_destroy(struct gl_targets *t)
{
    destroy_image_sized(t);
    destroy_projection(t);
    glDeleteFramebuffers(LUCENT_MAX_LIGHTS, t->shadow_fb);
    glDeleteFramebuffers(2, t->blit_fb);
    glDeleteTextures(1, &t->shadow_depth);
    GLuint samplers[3] = {t->nearest, t->filtered, t->shadow_compare};
    glDeleteSamplers(3, samplers);
    memset(t, 0, sizeof *t);
}
