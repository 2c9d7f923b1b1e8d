/* egl_device.h - headless EGL displays (no window system, no surface), one per requested device, shared by
 * the renderers of a process and kept until lucent_shutdown(); each renderer makes its own context on one. */
#ifndef LUCENT_EGL_DEVICE_H
#define LUCENT_EGL_DEVICE_H

#include "gl_check.h"

struct egl_device {
    EGLDisplay display;
    char name[256];       /* GL_RENDERER of a context on it */
    char version[128];    /* GL_VERSION */
    char request[128];    /* the device name asked for ("" = automatic) */
    const char *platform; /* "device" (EGL_EXT_platform_device) or "surfaceless" (EGL_MESA_platform_surfaceless) */
    int users;
};

/* Finds or opens the display for a request: among the EGL devices (EGL_EXT_platform_device), a GPU before
 * Mesa's software device, else Mesa's surfaceless platform ($LUCENT_EGL_PLATFORM=device or surfaceless: that
 * one only); a non-empty request (NULL: $LUCENT_DEVICE) takes the first whose GL_RENDERER contains it. The device must make an OpenGL 4.5 core context and
 * read SPIR-V shaders (ARB_gl_spirv). */
lucent_status egl_device_acquire(const char *request, int verbose, struct egl_device **out, lucent_error *err);
void egl_device_release(struct egl_device *dev);
/* A new OpenGL 4.5 core context on the device, current on no thread (a debug context under
 * $LUCENT_VALIDATION=1). */
lucent_status egl_context_create(const struct egl_device *dev, EGLContext *out, lucent_error *err);

#endif
