/* gl_check.h - the OpenGL and EGL headers as the OpenGL backend uses them, and their errors turned into
 * lucent_errors naming the call; with $LUCENT_VALIDATION=1, KHR_debug's messages go to stderr. */
#ifndef LUCENT_GL_CHECK_H
#define LUCENT_GL_CHECK_H

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include "lucent.h"

/* The first OpenGL error raised since the last check (all of them are drained), as LUCENT_E_GPU naming
 * `where`, the pass or call that ran since. */
lucent_status gl_check(const char *where, lucent_error *err);
/* An EGL failure of `call`, with eglGetError()'s name. */
lucent_status egl_fail(const char *call, lucent_error *err);
const char *egl_error_name(EGLint e);
/* $LUCENT_VALIDATION=1: the context is made with EGL_CONTEXT_OPENGL_DEBUG and every KHR_debug message of
 * type error, undefined or deprecated behaviour, portability or performance is printed as "lucent:
 * opengl validation <type>: ..." (the tests fail on that line, as on Vulkan's validation layer). */
int gl_validation_enabled(void);
void gl_validation_install(void);

#endif
