/* gpu.c - chooses the backend a renderer opens (Vulkan, OpenGL through EGL, or Vulkan falling back to
 * OpenGL) and forwards the calls of gpu.h to it. */
#include "gpu.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int lucent_backend_valid(const char *name)
{
    return strcmp(name, "vulkan") == 0 || strcmp(name, "gl") == 0 || strcmp(name, "auto") == 0;
}

lucent_status gpu_open(const char *backend, const char *device_name, int verbose, struct gpu **out,
                       lucent_error *err)
{
    *out = NULL;
    const char *from_env = getenv("LUCENT_BACKEND");
    if (!backend)
        backend = from_env && from_env[0] ? from_env : "auto";
    if (strcmp(backend, "vulkan") == 0)
        return vk_gpu_open(device_name, verbose, out, err);
    if (strcmp(backend, "gl") == 0)
        return gl_gpu_open(device_name, verbose, out, err);
    if (!lucent_backend_valid(backend))
        return lucent_fail(err, LUCENT_E_INVALID, "backend", "unknown backend \"%.40s\" (vulkan, gl or auto)", backend);
    lucent_error vk_err;
    if (vk_gpu_open(device_name, verbose, out, &vk_err) == LUCENT_OK)
        return LUCENT_OK;
    fprintf(stderr, "lucent: no Vulkan device (%s); trying OpenGL through EGL\n", vk_err.message);
    lucent_error gl_err;
    lucent_status st = gl_gpu_open(device_name, verbose, out, &gl_err);
    if (st != LUCENT_OK)
        return lucent_fail(err, st, "", "no Vulkan device (%.120s), and OpenGL failed too: %.160s", vk_err.message,
                           gl_err.message);
    return LUCENT_OK;
}

void gpu_close(struct gpu *gpu)
{
    if (gpu)
        gpu->ops->close(gpu);
}

lucent_status gpu_settle(struct gpu *gpu, lucent_error *err)
{
    return gpu->ops->settle(gpu, err);
}

lucent_status gpu_geometry_upload(struct gpu *gpu, const float *positions, const float *shading, uint32_t vertex_count,
                                  const uint32_t *indices, uint32_t index_count, struct gpu_geometry **out,
                                  uint64_t *bytes, lucent_error *err)
{
    *bytes = (uint64_t)vertex_count * 28 + (uint64_t)index_count * 4;
    return gpu->ops->geometry_upload(gpu, positions, shading, vertex_count, indices, index_count, out, err);
}

void gpu_geometry_free(struct gpu *gpu, struct gpu_geometry *g)
{
    if (g)
        gpu->ops->geometry_free(gpu, g);
}

lucent_status gpu_render(struct gpu *gpu, const struct gpu_frame *frame, struct gpu_result *out, lucent_error *err)
{
    memset(out, 0, sizeof *out);
    return gpu->ops->render(gpu, frame, out, err);
}

void lucent_shutdown(void)
{
    vk_gpu_release_idle();
    gl_gpu_release_idle();
}
