/* gpu.h - the boundary between liblucent and a GPU backend (gpu/vulkan/, gpu/gl/): everything the renderer
 * asks of one, and through the frame plan (core/frame_plan.h) everything a backend needs of the rest. */
#ifndef LUCENT_GPU_H
#define LUCENT_GPU_H

#include "frame_plan.h"

struct gpu;            /* an open device of one backend, with its pipelines and render targets */
struct gpu_geometry;   /* one mesh's vertex and index buffers on that device */

/* What one pass draws: a mesh, or a simplified proxy of it. */
struct gpu_draw {
    const struct gpu_geometry *geometry;
    uint32_t index_count;
};

struct gpu_frame {
    const struct frame_plan *plan;
    uint32_t width, height, projection_size, side_size;
    struct gpu_draw full;    /* the camera's G-buffer */
    struct gpu_draw front;   /* the front projection image */
    struct gpu_draw sides;   /* the side and light views and the shadow maps */
};

/* A frame's results, in memory the backend owns, valid until its next frame or gpu_close. */
struct gpu_result {
    const float *rgba;          /* width x height x 4 */
    const float *normal_view;   /* per pixel: the normal, then the distance to the eye (-1: not covered) */
    const float *depth;
    double ms_shadow, ms_projection, ms_gbuffer, ms_scatter;   /* device time per pass; 0: not measured */
};

struct gpu_ops {
    void (*close)(struct gpu *gpu);
    /* Waits for work an earlier frame left running (a timed-out wait) before its resources are touched. */
    lucent_status (*settle)(struct gpu *gpu, lucent_error *err);
    lucent_status (*geometry_upload)(struct gpu *gpu, const float *positions, const float *shading,
                                     uint32_t vertex_count, const uint32_t *indices, uint32_t index_count,
                                     struct gpu_geometry **out, lucent_error *err);
    void (*geometry_free)(struct gpu *gpu, struct gpu_geometry *g);
    /* Draws one planned frame and waits for it. */
    lucent_status (*render)(struct gpu *gpu, const struct gpu_frame *frame, struct gpu_result *out,
                            lucent_error *err);
};

struct gpu {
    const struct gpu_ops *ops;
    const char *backend;           /* "vulkan" or "gl" */
    char device[256];              /* the device's name as its driver gives it */
    uint64_t max_pixels;           /* the largest width x height the image-space passes render */
    char max_pixels_why[160];      /* the device limit that sets max_pixels, in words */
    uint64_t memory_bytes;         /* device memory held now: meshes, targets, buffers */
};

/* Opens a device: backend "vulkan", "gl" or "auto" (NULL: $LUCENT_BACKEND, else "auto", which takes Vulkan
 * and falls back to OpenGL through EGL, saying why on stderr); device_name as lucent_renderer_desc's. */
lucent_status gpu_open(const char *backend, const char *device_name, int verbose, struct gpu **out,
                       lucent_error *err);
void gpu_close(struct gpu *gpu);
lucent_status gpu_settle(struct gpu *gpu, lucent_error *err);
/* Uploads a mesh's arrays (positions: 3 floats a vertex; shading: 4, the normal and mesh_ball_curvature);
 * *bytes: what they hold. */
lucent_status gpu_geometry_upload(struct gpu *gpu, const float *positions, const float *shading, uint32_t vertex_count,
                                  const uint32_t *indices, uint32_t index_count, struct gpu_geometry **out,
                                  uint64_t *bytes, lucent_error *err);
void gpu_geometry_free(struct gpu *gpu, struct gpu_geometry *g);
lucent_status gpu_render(struct gpu *gpu, const struct gpu_frame *frame, struct gpu_result *out, lucent_error *err);

/* Each backend's own opening, for gpu_open. */
lucent_status vk_gpu_open(const char *device_name, int verbose, struct gpu **out, lucent_error *err);
lucent_status gl_gpu_open(const char *device_name, int verbose, struct gpu **out, lucent_error *err);
/* Each backend's devices or displays that no renderer uses any more, released (lucent_shutdown). */
void vk_gpu_release_idle(void);
void gl_gpu_release_idle(void);

#endif
