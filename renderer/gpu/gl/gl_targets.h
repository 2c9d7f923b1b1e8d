/* gl_targets.h - the OpenGL textures, framebuffers and buffers whose size depends on the request, as
 * render_targets.h keeps them for Vulkan: kept between frames, a group rebuilt only when its size changes. */
#ifndef LUCENT_GL_TARGETS_H
#define LUCENT_GL_TARGETS_H

#include "frame_passes.h"
#include "gl_check.h"

struct gl_targets {
    uint32_t width, height, projection_size, side_size;
    /* made once */
    GLuint shadow_depth;                       /* SHADOW_MAP_SIZE^2 x LUCENT_MAX_LIGHTS layers */
    GLuint shadow_fb[LUCENT_MAX_LIGHTS];
    GLuint blit_fb[2];                         /* read and draw framebuffers of the mip chains' blits */
    GLuint nearest, filtered, shadow_compare;  /* samplers, as pipelines.c makes them */
    /* sized by projection_size and side_size */
    GLuint projection, normals, owned;         /* FRAME_MAX_VIEWS layers; projection and owned mipped */
    GLuint front_depth, side_depth;            /* the side and light views draw one at a time, into the
                                                * side_size^2 corner of their layers */
    GLuint view_fb[FRAME_MAX_VIEWS];           /* view k: layer k of projection and normals, and depth */
    uint32_t projection_levels, owned_levels;
    /* sized by width and height */
    GLuint gbuffer_position, gbuffer_normal, gbuffer_depth, gbuffer_fb;
    GLuint output;                             /* color, normal+view, depth arrays, mapped for reading */
    const unsigned char *output_mapped;
    GLintptr color_offset, normal_offset, depth_offset;
    GLuint far;                                /* the far annulus per block, then filtered */
    GLsizeiptr far_bytes;
    GLintptr far_filtered_offset;
    uint64_t bytes;                            /* of device memory these hold */
};

/* Makes t fit a frame of these sizes (t starts zeroed; on failure it is destroyed, zeroed again). */
lucent_status gl_targets_fit(uint32_t width, uint32_t height, uint32_t projection_size, uint32_t side_size,
                             struct gl_targets *t, lucent_error *err);
void gl_targets_destroy(struct gl_targets *t);

#endif
