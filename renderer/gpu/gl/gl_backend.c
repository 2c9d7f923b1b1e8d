/* gl_backend.c - the OpenGL half of a renderer behind gpu.h: its own OpenGL 4.5 context on a shared EGL
 * display, made current on whichever thread calls, the limits the passes need checked, programs, targets. */
#include "egl_device.h"
#include "gl_frame.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct gl_gpu {
    struct gpu base;
    struct egl_device *device;
    EGLContext context;
    struct gl_programs programs;
    struct gl_targets targets;
    GLuint uniforms, push;
    GLuint queries[TS_COUNT];
    uint64_t geometry_bytes;
    GLint max_texture_size;
    int lost;       /* a frame timed out or the context was lost: no more frames */
    int verbose;
};

static lucent_status make_current(struct gl_gpu *g, lucent_error *err)
{
    if (!eglBindAPI(EGL_OPENGL_API) ||
        !eglMakeCurrent(g->device->display, EGL_NO_SURFACE, EGL_NO_SURFACE, g->context))
        return egl_fail("eglMakeCurrent", err);
    return LUCENT_OK;
}

/* Renderers move between threads (a daemon's workers): none keeps its context current after a call. */
static void release_current(struct gl_gpu *g)
{
    eglMakeCurrent(g->device->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

static void gl_gpu_close(struct gpu *base)
{
    struct gl_gpu *g = (struct gl_gpu *)base;
    if (g->context != EGL_NO_CONTEXT && make_current(g, NULL) == LUCENT_OK) {
        gl_targets_destroy(&g->targets);
        gl_programs_destroy(&g->programs);
        GLuint buffers[2] = {g->uniforms, g->push};
        glDeleteBuffers(2, buffers);
        glDeleteQueries(TS_COUNT, g->queries);
        release_current(g);
    }
    if (g->context != EGL_NO_CONTEXT)
        eglDestroyContext(g->device->display, g->context);
    if (g->device)
        egl_device_release(g->device);
    free(g);
}

static lucent_status gl_gpu_settle(struct gpu *base, lucent_error *err)
{
    struct gl_gpu *g = (struct gl_gpu *)base;
    if (g->lost)
        return lucent_fail(err, LUCENT_E_DEVICE_LOST, "", "the OpenGL device \"%s\" hung or was lost; this renderer "
                           "renders no more frames", g->base.device);
    return LUCENT_OK;
}

static GLuint buffer_with(const void *data, GLsizeiptr size)
{
    GLuint b;
    glCreateBuffers(1, &b);
    glNamedBufferStorage(b, size, data, 0);
    return b;
}

static void delete_geometry(struct gpu_geometry *geo)
{
    GLuint buffers[3] = {geo->positions, geo->normals, geo->indices};
    glDeleteBuffers(3, buffers);
    glDeleteVertexArrays(1, &geo->vertex_array);
    free(geo);
}

static void gl_geometry_free(struct gpu *base, struct gpu_geometry *geo)
{
    struct gl_gpu *g = (struct gl_gpu *)base;
    g->geometry_bytes -= geo->bytes;
    if (make_current(g, NULL) != LUCENT_OK) {
        free(geo);   /* the context is gone, and its objects with it */
        return;
    }
    delete_geometry(geo);
    release_current(g);
}

static lucent_status gl_geometry_upload(struct gpu *base, const float *positions, const float *shading,
                                        uint32_t vertex_count, const uint32_t *indices, uint32_t index_count,
                                        struct gpu_geometry **out, lucent_error *err)
{
    struct gl_gpu *g = (struct gl_gpu *)base;
    struct gpu_geometry *geo = calloc(1, sizeof *geo);
    if (!geo)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory uploading the mesh");
    lucent_status st = make_current(g, err);
    if (st != LUCENT_OK) {
        free(geo);
        return st;
    }
    GLsizeiptr vbytes = (GLsizeiptr)vertex_count * 12;
    geo->positions = buffer_with(positions, vbytes);
    geo->normals = buffer_with(shading, vbytes / 3 * 4);
    geo->indices = buffer_with(indices, (GLsizeiptr)index_count * 4);
    glCreateVertexArrays(1, &geo->vertex_array);
    GLuint streams[2] = {geo->positions, geo->normals};
    for (GLuint i = 0; i < 2; i++) {
        glVertexArrayVertexBuffer(geo->vertex_array, i, streams[i], 0, i == 0 ? 12 : 16);
        glEnableVertexArrayAttrib(geo->vertex_array, i);
        glVertexArrayAttribFormat(geo->vertex_array, i, i == 0 ? 3 : 4, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(geo->vertex_array, i, i);
    }
    glVertexArrayElementBuffer(geo->vertex_array, geo->indices);
    if ((st = gl_check("uploading the mesh", err)) != LUCENT_OK) {
        delete_geometry(geo);
        release_current(g);
        return st;
    }
    geo->bytes = (uint64_t)vbytes / 3 * 7 + (uint64_t)index_count * 4;
    g->geometry_bytes += geo->bytes;
    release_current(g);
    *out = geo;
    return LUCENT_OK;
}

static lucent_status gl_gpu_render(struct gpu *base, const struct gpu_frame *f, struct gpu_result *out,
                                   lucent_error *err)
{
    struct gl_gpu *g = (struct gl_gpu *)base;
    lucent_status st;
    if ((st = gl_gpu_settle(base, err)))
        return st;
    if (f->width > (uint32_t)g->max_texture_size || f->height > (uint32_t)g->max_texture_size)
        return lucent_fail(err, LUCENT_E_LIMIT, "width", "a %ux%u image exceeds this device's (%s) "
                           "GL_MAX_TEXTURE_SIZE of %d", f->width, f->height, g->base.device, g->max_texture_size);
    if ((st = make_current(g, err)))
        return st;
    const struct gl_targets *t = &g->targets;
    if (g->verbose && (t->width != f->width || t->height != f->height || t->projection_size != f->projection_size ||
                       t->side_size != f->side_size))
        fprintf(stderr, "lucent: render targets %ux%u, projection %u, sides %u\n", f->width, f->height,
                f->projection_size, f->side_size);
    struct gl_frame_gpu gpu = {&g->programs, &g->targets, g->uniforms, g->push, {0}};
    if (g->queries[0])
        memcpy(gpu.queries, g->queries, sizeof gpu.queries);
    if ((st = gl_targets_fit(f->width, f->height, f->projection_size, f->side_size, &g->targets, err)) == LUCENT_OK)
        st = gl_frame_draw(&gpu, f, err);
    if (st == LUCENT_E_DEVICE_LOST)
        g->lost = 1;
    g->base.memory_bytes = g->geometry_bytes + g->targets.bytes;
    if (st == LUCENT_OK && g->queries[0]) {
        GLuint64 ts[TS_COUNT];
        for (int i = 0; i < TS_COUNT; i++)
            glGetQueryObjectui64v(g->queries[i], GL_QUERY_RESULT, &ts[i]);
        out->ms_shadow = (double)(ts[TS_SHADOW] - ts[TS_START]) * 1e-6;
        out->ms_projection = (double)(ts[TS_PROJECTION] - ts[TS_SHADOW]) * 1e-6;
        out->ms_gbuffer = (double)(ts[TS_GBUFFER] - ts[TS_PROJECTION]) * 1e-6;
        out->ms_scatter = (double)(ts[TS_SCATTER] - ts[TS_GBUFFER]) * 1e-6;
    }
    release_current(g);
    if (st != LUCENT_OK)
        return st;
    out->rgba = (const float *)(t->output_mapped + t->color_offset);
    out->normal_view = (const float *)(t->output_mapped + t->normal_offset);
    out->depth = (const float *)(t->output_mapped + t->depth_offset);
    return LUCENT_OK;
}

/* The limits the passes rely on, each refused with its name when the device falls short. */
static lucent_status check_limits(struct gl_gpu *g, lucent_error *err)
{
    static const struct {
        GLenum name;
        const char *text;
        GLint need;
    } limits[] = {
        {GL_MAX_ARRAY_TEXTURE_LAYERS, "GL_MAX_ARRAY_TEXTURE_LAYERS", FRAME_MAX_VIEWS},
        {GL_MAX_TEXTURE_SIZE, "GL_MAX_TEXTURE_SIZE", SHADOW_MAP_SIZE > LUCENT_MAX_PROJECTION_SIZE
                                                       ? SHADOW_MAP_SIZE : LUCENT_MAX_PROJECTION_SIZE},
        {GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, "GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS", 64},
        {GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, "GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS", 12},
        {GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS", 5},
        {GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, "GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS", 10},
        {GL_MAX_IMAGE_UNITS, "GL_MAX_IMAGE_UNITS", 11},
        {GL_MAX_UNIFORM_BUFFER_BINDINGS, "GL_MAX_UNIFORM_BUFFER_BINDINGS", GL_PUSH_BINDING + 1},
        {GL_MAX_UNIFORM_BLOCK_SIZE, "GL_MAX_UNIFORM_BLOCK_SIZE", (GLint)sizeof(struct frame_uniforms)},
    };
    for (size_t i = 0; i < sizeof limits / sizeof limits[0]; i++) {
        GLint have = 0;
        glGetIntegerv(limits[i].name, &have);
        if (have < limits[i].need)
            return lucent_fail(err, LUCENT_E_LIMIT, "", "OpenGL device \"%s\" has %s %d; Lucent needs %d",
                               g->base.device, limits[i].text, have, limits[i].need);
    }
    GLint64 ssbo = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &ssbo);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &g->max_texture_size);
    g->base.max_pixels = (uint64_t)ssbo / 16u;
    snprintf(g->base.max_pixels_why, sizeof g->base.max_pixels_why,
             "its GL_MAX_SHADER_STORAGE_BLOCK_SIZE of %lld bytes over 16 bytes a pixel", (long long)ssbo);
    return LUCENT_OK;
}

/* Vulkan's conventions, so that one set of matrices and shaders serves both: depth 0..1, and clip y -1 on
 * the first row in memory, where Vulkan's counter-clockwise front faces wind clockwise in OpenGL's terms. */
static void set_conventions(void)
{
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glFrontFace(GL_CW);
    glCullFace(GL_BACK);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
}

static const struct gpu_ops gl_gpu_ops = {gl_gpu_close, gl_gpu_settle, gl_geometry_upload, gl_geometry_free,
                                          gl_gpu_render};

lucent_status gl_gpu_open(const char *device_name, int verbose, struct gpu **out, lucent_error *err)
{
    struct gl_gpu *g = calloc(1, sizeof *g);
    if (!g)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory creating the renderer");
    g->base.ops = &gl_gpu_ops;
    g->base.backend = "gl";
    g->verbose = verbose;
    g->context = EGL_NO_CONTEXT;
    lucent_status st;
    if ((st = egl_device_acquire(device_name, verbose, &g->device, err)) ||
        (st = egl_context_create(g->device, &g->context, err)) || (st = make_current(g, err)))
        goto fail;
    snprintf(g->base.device, sizeof g->base.device, "%s", g->device->name);
    if (gl_validation_enabled())
        gl_validation_install();
    set_conventions();
    if ((st = check_limits(g, err)) || (st = gl_programs_create(&g->programs, err)))
        goto fail;
    glCreateBuffers(1, &g->uniforms);
    glNamedBufferStorage(g->uniforms, sizeof(struct frame_uniforms), NULL, GL_DYNAMIC_STORAGE_BIT);
    glCreateBuffers(1, &g->push);
    glNamedBufferStorage(g->push, 80, NULL, GL_DYNAMIC_STORAGE_BIT);   /* the largest: gbuffer's mat4 + vec4 */
    GLint bits = 0;
    glGetQueryiv(GL_TIMESTAMP, GL_QUERY_COUNTER_BITS, &bits);
    if (bits > 0)
        glCreateQueries(GL_TIMESTAMP, TS_COUNT, g->queries);
    if ((st = gl_check("creating the renderer", err)))
        goto fail;
    release_current(g);
    *out = &g->base;
    return LUCENT_OK;
fail:
    if (g->context != EGL_NO_CONTEXT)
        release_current(g);
    gl_gpu_close(&g->base);
    return st;
}
