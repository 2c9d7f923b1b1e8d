/* frame_record.h - records one frame's command buffer: shadow maps, the projection images (front
 * pass, side pass, copy), the camera G-buffer and the scatter dispatch, with timestamps between. */
#ifndef LUCENT_FRAME_RECORD_H
#define LUCENT_FRAME_RECORD_H

#include "gpu.h"
#include "pipelines.h"
#include "render_targets.h"

/* A mesh on this backend (gpu.h). */
struct gpu_geometry {
    struct vk_buffer positions, normals, indices;
};

/* What recording touches; all of it owned by the renderer. */
struct frame_gpu {
    struct vk_context *ctx;
    struct pipelines *pipes;          /* variants are created here on first use, the least used evicted */
    const struct render_targets *targets;
    VkQueryPool queries;              /* VK_NULL_HANDLE: no timestamps */
};

/* Records into gpu->ctx->cmd (not submitted). No earlier frame may still be executing: pipelines it
 * used may be destroyed to make room for this frame's. */
lucent_status frame_record(const struct frame_gpu *gpu, const struct gpu_frame *frame, lucent_error *err);

#endif
