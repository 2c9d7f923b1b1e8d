/* egl_device.c - chooses and opens EGL displays for the OpenGL backend and keeps them in a small
 * process-wide registry (eglTerminate would end a display under every renderer using it). */
#include "egl_device.h"
#include "gpu.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DISPLAYS 4
#define MAX_CANDIDATES 8

static struct egl_device registry[MAX_DISPLAYS];
static pthread_mutex_t registry_lock = PTHREAD_MUTEX_INITIALIZER;

static int has_extension(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return 1;
    return 0;
}

lucent_status egl_context_create(const struct egl_device *dev, EGLContext *out, lucent_error *err)
{
    /* The debug attribute is EGL 1.5's: asked for only when wanted, so an EGL 1.4 display still works. */
    EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE, EGL_TRUE, EGL_NONE};
    if (gl_validation_enabled())
        attrs[6] = EGL_CONTEXT_OPENGL_DEBUG;
    if (!eglBindAPI(EGL_OPENGL_API))
        return egl_fail("eglBindAPI(EGL_OPENGL_API)", err);
    *out = eglCreateContext(dev->display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attrs);
    if (*out == EGL_NO_CONTEXT)
        return egl_fail("eglCreateContext (OpenGL 4.5 core, no config)", err);
    return LUCENT_OK;
}

/* Initializes a display and reads its renderer's name from a probe context; refuses one that lacks what
 * the backend needs. */
static lucent_status probe_display(struct egl_device *d, lucent_error *err)
{
    if (!eglInitialize(d->display, NULL, NULL))
        return egl_fail("eglInitialize", err);
    const char *exts = eglQueryString(d->display, EGL_EXTENSIONS);
    if (!has_extension(exts, "EGL_KHR_no_config_context") || !has_extension(exts, "EGL_KHR_surfaceless_context"))
        return lucent_fail(err, LUCENT_E_GPU, "", "the EGL display lacks EGL_KHR_no_config_context or "
                           "EGL_KHR_surfaceless_context (a context without a window)");
    EGLContext ctx;
    lucent_status st = egl_context_create(d, &ctx, err);
    if (st != LUCENT_OK)
        return st;
    if (!eglMakeCurrent(d->display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        st = egl_fail("eglMakeCurrent", err);
        eglDestroyContext(d->display, ctx);
        return st;
    }
    snprintf(d->name, sizeof d->name, "%s", (const char *)glGetString(GL_RENDERER));
    snprintf(d->version, sizeof d->version, "%s", (const char *)glGetString(GL_VERSION));
    int spirv = 0;
    GLint n = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &n);
    for (GLint i = 0; i < n && !spirv; i++)
        spirv = strcmp((const char *)glGetStringi(GL_EXTENSIONS, (GLuint)i), "GL_ARB_gl_spirv") == 0;
    eglMakeCurrent(d->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(d->display, ctx);
    if (!spirv)
        return lucent_fail(err, LUCENT_E_GPU, "", "OpenGL device \"%s\" (%s) cannot read SPIR-V shaders "
                           "(no GL_ARB_gl_spirv)", d->name, d->version);
    return LUCENT_OK;
}

/* Two requests may name one device: its display is initialized once and terminated after both. */
static int is_registered(EGLDisplay display, const struct egl_device *besides)
{
    for (int i = 0; i < MAX_DISPLAYS; i++)
        if (&registry[i] != besides && registry[i].display == display)
            return 1;
    return 0;
}

/* The displays to try: one per EGL device, software last, then the surfaceless platform (or only the
 * platform $LUCENT_EGL_PLATFORM names). */
static int candidate_displays(EGLDisplay out[MAX_CANDIDATES], const char *platform[MAX_CANDIDATES])
{
    const char *only = getenv("LUCENT_EGL_PLATFORM");
    int devices_ok = !only || !only[0] || strcmp(only, "device") == 0;
    int surfaceless_ok = !only || !only[0] || strcmp(only, "surfaceless") == 0;
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    PFNEGLQUERYDEVICESEXTPROC query_devices = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
    PFNEGLQUERYDEVICESTRINGEXTPROC device_string =
        (PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
    int n = 0;
    EGLint count = 0;
    EGLDeviceEXT devices[MAX_CANDIDATES];
    if (devices_ok && has_extension(client, "EGL_EXT_platform_device") && query_devices && device_string &&
        query_devices(MAX_CANDIDATES - 1, devices, &count)) {
        for (int pass = 0; pass < 2; pass++)   /* GPUs first, then Mesa's software device */
            for (EGLint i = 0; i < count; i++) {
                int software = has_extension(device_string(devices[i], EGL_EXTENSIONS), "EGL_MESA_device_software");
                if (software != pass)
                    continue;
                EGLDisplay d = eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL);
                if (d != EGL_NO_DISPLAY)
                    platform[n] = "device", out[n++] = d;
            }
    }
    if (surfaceless_ok && has_extension(client, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
        if (d != EGL_NO_DISPLAY)
            platform[n] = "surfaceless", out[n++] = d;
    }
    return n;
}

static lucent_status open_display(struct egl_device *slot, const char *request, lucent_error *err)
{
    EGLDisplay candidates[MAX_CANDIDATES];
    const char *platform[MAX_CANDIDATES];
    int n = candidate_displays(candidates, platform);
    lucent_error last = {.message = "no EGL device and no surfaceless platform; install libegl-mesa0 and "
                                    "libgl1-mesa-dri for the CPU renderer"};
    char seen[512] = "";
    size_t used = 0;
    for (int i = 0; i < n; i++) {
        struct egl_device d = {.display = candidates[i], .platform = platform[i]};
        int in_use = is_registered(d.display, slot);
        if (probe_display(&d, &last) == LUCENT_OK) {
            if (!request[0] || strstr(d.name, request)) {
                *slot = d;
                snprintf(slot->request, sizeof slot->request, "%s", request);
                return LUCENT_OK;
            }
            used += (size_t)snprintf(seen + used, used < sizeof seen ? sizeof seen - used : 0, "%s\"%s\"",
                                     used ? ", " : "", d.name);
        }
        if (!in_use)
            eglTerminate(d.display);
    }
    if (request[0])
        return lucent_fail(err, LUCENT_E_GPU, "device", "no OpenGL device named like \"%s\" (found: %s)", request,
                           used ? seen : "none");
    return lucent_fail(err, LUCENT_E_GPU, "", "no usable OpenGL device through EGL: %s", last.message);
}

lucent_status egl_device_acquire(const char *request, int verbose, struct egl_device **out, lucent_error *err)
{
    const char *platform = getenv("LUCENT_EGL_PLATFORM");
    if (platform && platform[0] && strcmp(platform, "device") != 0 && strcmp(platform, "surfaceless") != 0)
        return lucent_fail(err, LUCENT_E_INVALID, "", "LUCENT_EGL_PLATFORM must be device or surfaceless (got \"%.40s\")",
                           platform);
    if (!request)
        request = getenv("LUCENT_DEVICE");
    if (!request)
        request = "";
    if (strlen(request) >= sizeof registry[0].request)
        return lucent_fail(err, LUCENT_E_LIMIT, "device", "a device name of at most %zu bytes (got %zu)",
                           sizeof registry[0].request - 1, strlen(request));
    pthread_mutex_lock(&registry_lock);
    struct egl_device *found = NULL, *free_slot = NULL;
    for (int i = 0; i < MAX_DISPLAYS; i++) {
        if (registry[i].display && strcmp(registry[i].request, request) == 0)
            found = &registry[i];
        else if (!registry[i].display && !free_slot)
            free_slot = &registry[i];
    }
    lucent_status st = LUCENT_OK;
    if (!found && !free_slot)
        st = lucent_fail(err, LUCENT_E_LIMIT, "", "more than %d different OpenGL devices requested", MAX_DISPLAYS);
    else if (!found && (st = open_display(free_slot, request, err)) == LUCENT_OK)
        found = free_slot;
    if (found) {
        found->users++;
        *out = found;
        if (verbose)
            fprintf(stderr, "lucent: OpenGL device \"%s\" (%s, through EGL, platform %s)\n", found->name,
                    found->version, found->platform);
    }
    pthread_mutex_unlock(&registry_lock);
    return st;
}

void egl_device_release(struct egl_device *dev)
{
    pthread_mutex_lock(&registry_lock);
    dev->users--;
    pthread_mutex_unlock(&registry_lock);
}

void gl_gpu_release_idle(void)
{
    pthread_mutex_lock(&registry_lock);
    for (int i = 0; i < MAX_DISPLAYS; i++)
        if (registry[i].display && registry[i].users == 0) {
            if (!is_registered(registry[i].display, &registry[i]))
                eglTerminate(registry[i].display);
            memset(&registry[i], 0, sizeof registry[i]);
        }
    eglReleaseThread();
    pthread_mutex_unlock(&registry_lock);
}
