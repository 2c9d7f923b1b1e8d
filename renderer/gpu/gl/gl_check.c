/* gl_check.c - OpenGL and EGL errors as lucent_errors, and the KHR_debug message callback of
 * $LUCENT_VALIDATION=1. */
#include "gl_check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *gl_error_name(GLenum e)
{
    switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_CONTEXT_LOST: return "GL_CONTEXT_LOST";
    default: return "unknown GL error";
    }
}

lucent_status gl_check(const char *where, lucent_error *err)
{
    GLenum first = glGetError();
    if (first == GL_NO_ERROR)
        return LUCENT_OK;
    for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; i++)
        ;   /* each flag reports once; a lost context may keep one set */
    return lucent_fail(err, first == GL_OUT_OF_MEMORY ? LUCENT_E_NOMEM : first == GL_CONTEXT_LOST ? LUCENT_E_DEVICE_LOST
                                                                                                  : LUCENT_E_GPU,
                       "", "%s failed: %s (0x%04x)", where, gl_error_name(first), (unsigned)first);
}

const char *egl_error_name(EGLint e)
{
    switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return "unknown EGL error";
    }
}

lucent_status egl_fail(const char *call, lucent_error *err)
{
    EGLint e = eglGetError();
    return lucent_fail(err, e == EGL_BAD_ALLOC ? LUCENT_E_NOMEM : LUCENT_E_GPU, "", "%s failed: %s (0x%04x)", call,
                       egl_error_name(e), (unsigned)e);
}

int gl_validation_enabled(void)
{
    const char *v = getenv("LUCENT_VALIDATION");
    return v && strcmp(v, "1") == 0;
}

static const char *debug_type(GLenum type)
{
    switch (type) {
    case GL_DEBUG_TYPE_ERROR: return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR: return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR: return "undefined";
    case GL_DEBUG_TYPE_PORTABILITY: return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE: return "performance";
    default: return NULL;   /* markers, groups and "other" notes are not findings */
    }
}

static void APIENTRY on_debug_message(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                                        const GLchar *message, const void *user)
{
    (void)source;
    (void)severity;
    (void)user;
    const char *kind = debug_type(type);
    if (kind)
        fprintf(stderr, "lucent: opengl validation %s: [%u] %.*s\n", kind, id, length < 0 ? 1000 : (int)length,
                message);
}

void gl_validation_install(void)
{
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(on_debug_message, NULL);
}
