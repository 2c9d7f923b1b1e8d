/* gl_programs.h - the OpenGL programs of the passes, from the SPIR-V glslang built for OpenGL (LUCENT_GL),
 * specialized like the Vulkan pipelines (frame_passes.h); the fixed ones made once, variants on first use. */
#ifndef LUCENT_GL_PROGRAMS_H
#define LUCENT_GL_PROGRAMS_H

#include "frame_passes.h"
#include "gl_check.h"
#include "pipeline_lru.h"

/* Binding of the uniform block holding what Vulkan passes as push constants (shaders/backend.glsl). */
#define GL_PUSH_BINDING 12

struct gl_programs {
    GLuint shadow, gbuffer, ownership;
    struct pipeline_lru projection, scatter;
    uint64_t frame;   /* frames begun: a frame's own programs are never evicted under it */
    PFNGLSPECIALIZESHADERPROC specialize;   /* glSpecializeShader(ARB) */
};

lucent_status gl_programs_create(struct gl_programs *p, lucent_error *err);
void gl_programs_begin_frame(struct gl_programs *p);
/* The projection program for 1..LUCENT_MAX_LIGHTS lights and a shadow mask (culling is raster state here). */
lucent_status gl_programs_projection(struct gl_programs *p, int lights, uint32_t shadow_mask, GLuint *out,
                                     lucent_error *err);
lucent_status gl_programs_scatter(struct gl_programs *p, const struct scatter_variant *v, GLuint *out,
                                  lucent_error *err);
void gl_programs_destroy(struct gl_programs *p);

#endif
