/* gl_frame.h - draws one frame with OpenGL: the passes frame_passes.h decides, in Vulkan's order, each
 * view of the side and light passes drawn on its own (no multiview), then waits for it. */
#ifndef LUCENT_GL_FRAME_H
#define LUCENT_GL_FRAME_H

#include "gl_programs.h"
#include "gl_targets.h"
#include "gpu.h"

/* A frame that takes minutes means a hung device, not a slow one (as VK_CONTEXT_WAIT_S). */
#define GL_FRAME_WAIT_NS (120ull * 1000000000ull)

/* A mesh on this backend (gpu.h): its buffers and the vertex array drawing them. */
struct gpu_geometry {
    GLuint positions, normals, indices, vertex_array;
    uint64_t bytes;
};

/* What drawing touches; all of it owned by the backend's renderer, its context current. */
struct gl_frame_gpu {
    struct gl_programs *programs;      /* variants are made here on first use, the least used deleted */
    const struct gl_targets *targets;
    GLuint uniforms;                   /* struct frame_uniforms, binding 0 */
    GLuint push;                       /* what Vulkan pushes, binding GL_PUSH_BINDING */
    GLuint queries[TS_COUNT];          /* 0: no timestamps */
};

/* Draws the frame and waits for it, at most GL_FRAME_WAIT_NS (LUCENT_E_DEVICE_LOST past that). */
lucent_status gl_frame_draw(const struct gl_frame_gpu *gpu, const struct gpu_frame *frame, lucent_error *err);

#endif
