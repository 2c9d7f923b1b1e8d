/* gl_programs.c - OpenGL programs from embedded SPIR-V (ARB_gl_spirv): each shader stage specialized with
 * the constants the Vulkan pipelines get, and linked; compile and link logs become the error message. */
#include "gl_programs.h"

#include "gbuffer_frag_gl.h"
#include "gbuffer_vert_gl.h"
#include "ownership_comp_gl.h"
#include "projection_frag_gl.h"
#include "projection_vert_gl.h"
#include "scatter_comp_gl.h"
#include "shadow_vert_gl.h"

#include <stdio.h>
#include <string.h>

struct spirv {
    const uint32_t *words;
    GLsizei size;
    const char *name;
};
#define SPIRV(n) ((struct spirv){n, (GLsizei)sizeof n, #n})

struct stage {
    GLenum type;
    struct spirv code;
    GLuint constants;              /* the first `constants` constant_ids ... */
    const int32_t *values;         /* ... take these values */
};

static lucent_status make_shader(const struct gl_programs *p, const struct stage *s, GLuint *out, lucent_error *err)
{
    GLuint ids[SCATTER_CONSTANTS];
    for (GLuint i = 0; i < s->constants; i++)
        ids[i] = i;
    GLuint sh = glCreateShader(s->type);
    glShaderBinary(1, &sh, GL_SHADER_BINARY_FORMAT_SPIR_V_ARB, s->code.words, s->code.size);
    p->specialize(sh, "main", s->constants, ids, (const GLuint *)s->values);
    GLint ok = GL_FALSE;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[240] = "";
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        glDeleteShader(sh);
        return lucent_fail(err, LUCENT_E_GPU, "", "glSpecializeShader(%s) failed: %s", s->code.name, log);
    }
    *out = sh;
    return gl_check(s->code.name, err);
}

static lucent_status make_program(const struct gl_programs *p, const struct stage *stages, int count, GLuint *out,
                                  lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    GLuint shaders[2] = {0, 0};
    GLuint prog = glCreateProgram();
    for (int i = 0; i < count && st == LUCENT_OK; i++)
        if ((st = make_shader(p, &stages[i], &shaders[i], err)) == LUCENT_OK)
            glAttachShader(prog, shaders[i]);
    if (st == LUCENT_OK) {
        glLinkProgram(prog);
        GLint ok = GL_FALSE;
        glGetProgramiv(prog, GL_LINK_STATUS, &ok);
        if (!ok) {
            char log[240] = "";
            glGetProgramInfoLog(prog, sizeof log, NULL, log);
            st = lucent_fail(err, LUCENT_E_GPU, "", "glLinkProgram(%s) failed: %s", stages[0].code.name, log);
        }
    }
    for (int i = 0; i < count; i++)
        if (shaders[i])
            glDeleteShader(shaders[i]);   /* flagged: freed with the program */
    if (st != LUCENT_OK) {
        glDeleteProgram(prog);
        return st;
    }
    *out = prog;
    return LUCENT_OK;
}

static void destroy_program(void *owner, uint64_t program)
{
    (void)owner;
    glDeleteProgram((GLuint)program);
}

/* The kept program for key in *out, or 0 in *out and in *slot where a new one goes. */
static lucent_status find_or_make_room(struct pipeline_lru *lru, uint64_t key, uint64_t frame, const char *kind,
                                       GLuint *out, int *slot, lucent_error *err)
{
    uint64_t found, evicted;
    lucent_status st = pipeline_lru_get(lru, key, frame, kind, &found, slot, &evicted, err);
    if (evicted)
        destroy_program(NULL, evicted);
    *out = (GLuint)found;
    return st;
}

lucent_status gl_programs_create(struct gl_programs *p, lucent_error *err)
{
    memset(p, 0, sizeof *p);
    p->specialize = (PFNGLSPECIALIZESHADERPROC)eglGetProcAddress("glSpecializeShaderARB");
    if (!p->specialize)
        p->specialize = (PFNGLSPECIALIZESHADERPROC)eglGetProcAddress("glSpecializeShader");
    if (!p->specialize)
        return lucent_fail(err, LUCENT_E_GPU, "", "the OpenGL driver has no glSpecializeShader (ARB_gl_spirv)");
    struct stage shadow = {GL_VERTEX_SHADER, SPIRV(shadow_vert_gl), 0, NULL};
    struct stage gbuffer[2] = {{GL_VERTEX_SHADER, SPIRV(gbuffer_vert_gl), 0, NULL},
                               {GL_FRAGMENT_SHADER, SPIRV(gbuffer_frag_gl), 0, NULL}};
    struct stage ownership = {GL_COMPUTE_SHADER, SPIRV(ownership_comp_gl), 0, NULL};
    lucent_status st;
    if ((st = make_program(p, &shadow, 1, &p->shadow, err)) || (st = make_program(p, gbuffer, 2, &p->gbuffer, err)) ||
        (st = make_program(p, &ownership, 1, &p->ownership, err)))
        gl_programs_destroy(p);
    return st;
}

void gl_programs_begin_frame(struct gl_programs *p)
{
    p->frame++;
}

lucent_status gl_programs_projection(struct gl_programs *p, int lights, uint32_t shadow_mask, GLuint *out,
                                     lucent_error *err)
{
    uint64_t key;
    int slot;
    lucent_status st = projection_variant_key(PROJECTION_FRONT, lights, shadow_mask, 0, &key, err);
    if (st == LUCENT_OK)
        st = find_or_make_room(&p->projection, key, p->frame, "projection", out, &slot, err);
    if (st != LUCENT_OK || *out)
        return st;
    int32_t values[PROJECTION_CONSTANTS];
    projection_variant_constants(lights, shadow_mask, values);
    struct stage stages[2] = {{GL_VERTEX_SHADER, SPIRV(projection_vert_gl), 0, NULL},
                              {GL_FRAGMENT_SHADER, SPIRV(projection_frag_gl), PROJECTION_CONSTANTS, values}};
    if ((st = make_program(p, stages, 2, out, err)) == LUCENT_OK)
        pipeline_lru_put(&p->projection, slot, key, *out, p->frame);
    return st;
}

lucent_status gl_programs_scatter(struct gl_programs *p, const struct scatter_variant *v, GLuint *out,
                                  lucent_error *err)
{
    uint64_t key;
    int slot;
    lucent_status st = scatter_variant_key(v, &key, err);
    if (st == LUCENT_OK)
        st = find_or_make_room(&p->scatter, key, p->frame, "scatter", out, &slot, err);
    if (st != LUCENT_OK || *out)
        return st;
    int32_t values[SCATTER_CONSTANTS];
    scatter_variant_constants(v, values);
    struct stage stage = {GL_COMPUTE_SHADER, SPIRV(scatter_comp_gl), SCATTER_CONSTANTS, values};
    if ((st = make_program(p, &stage, 1, out, err)) == LUCENT_OK)
        pipeline_lru_put(&p->scatter, slot, key, *out, p->frame);
    return st;
}

void gl_programs_destroy(struct gl_programs *p)
{
    pipeline_lru_clear(&p->projection, destroy_program, NULL);
    pipeline_lru_clear(&p->scatter, destroy_program, NULL);
    glDeleteProgram(p->shadow);
    glDeleteProgram(p->gbuffer);
    glDeleteProgram(p->ownership);
    p->shadow = p->gbuffer = p->ownership = 0;
}
