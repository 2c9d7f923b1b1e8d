/* scene_canonical.c - canonical serialization of a lucent_scene (every field, fixed order, exact numbers)
 * and the strong ETag: sha256 over the renderer build hash, the device and that text. */
#include "scene_canonical.h"

#include "lucentd_build.h"

#include <openssl/evp.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* A field added to lucent_scene must be added to scene_canonical() too, or two scenes that differ in
 * it would share an ETag and a cached image. This size check makes that impossible to miss. */
_Static_assert(sizeof(lucent_scene) == 1848,
               "lucent_scene changed: serialize the new field in server/scene_canonical.c, then update this size");

struct out {
    char *buf;
    size_t cap, used;
    int overflow;
};

static void put(struct out *o, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(o->buf + o->used, o->cap - o->used, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= o->cap - o->used)
        o->overflow = 1;
    else
        o->used += (size_t)n;
}

/* %.17g round-trips every double; -0 prints as 0 because it renders the same. */
static void num(struct out *o, const char *key, double v)
{
    put(o, "%s=%.17g;", key, v == 0.0 ? 0.0 : v);
}

static void vec(struct out *o, const char *key, const double *v, int n)
{
    put(o, "%s=", key);
    for (int i = 0; i < n; i++)
        put(o, "%.17g%s", v[i] == 0.0 ? 0.0 : v[i], i + 1 < n ? "," : ";");
}

int scene_canonical(const lucent_scene *s, char *buf, size_t cap)
{
    struct out o = {buf, cap, 0, cap == 0};
    if (o.overflow)
        return -1;
    buf[0] = 0;
    put(&o, "mesh.source=%d;", (int)s->mesh.source);
    if (s->mesh.source == LUCENT_MESH_BUILTIN)
        put(&o, "mesh.builtin=%s;mesh.triangles=%u;", s->mesh.builtin, s->mesh.triangles);
    else if (s->mesh.source == LUCENT_MESH_FILE)
        put(&o, "mesh.file=%s;", s->mesh.file);
    else
        put(&o, "mesh.id=%s;", s->mesh.id);
    num(&o, "scale_mm", s->scale_mm);
    put(&o, "material.preset=%s;", s->material.preset);
    vec(&o, "material.sigma_a", s->material.sigma_a, 3);
    vec(&o, "material.sigma_s_prime", s->material.sigma_s_prime, 3);
    num(&o, "material.eta", s->material.eta);
    num(&o, "material.g", s->material.g);
    put(&o, "material.profile=%d;", (int)s->material.profile);
    put(&o, "lights=%d;", s->light_count);
    for (int i = 0; i < s->light_count; i++) {
        const lucent_light *l = &s->lights[i];
        put(&o, "light.type=%d;", (int)l->type);
        vec(&o, "light.direction", l->direction, 3);
        vec(&o, "light.position", l->position, 3);
        vec(&o, "light.color", l->color, 3);
        num(&o, "light.intensity", l->intensity);
    }
    put(&o, "camera.given=%d;", s->camera.given);
    vec(&o, "camera.position", s->camera.position, 3);
    vec(&o, "camera.target", s->camera.target, 3);
    vec(&o, "camera.up", s->camera.up, 3);
    vec(&o, "camera.direction", s->camera.direction, 3);
    num(&o, "camera.fov_deg", s->camera.fov_deg);
    put(&o, "width=%d;height=%d;method=%d;samples=%d;sampling=%d;", s->width, s->height, (int)s->method,
        s->samples, (int)s->sampling);
    put(&o, "fallback=%d;single_scattering=%d;", (int)s->fallback, s->single_scattering);
    put(&o, "projection_size=%d;side_projection_size=%d;", s->projection_size, s->side_projection_size);
    vec(&o, "background", s->background, 4);
    num(&o, "exposure", s->exposure);
    put(&o, "format=%d;reference.points=%u;", (int)s->format, s->reference_points);
    num(&o, "reference.threshold", s->reference_threshold);
    put(&o, "path.samples=%u;path.boundary=%d;path.filter=%d;path.seed=%u;", s->path_samples, (int)s->path_boundary,
        (int)s->path_filter, s->path_seed);
    num(&o, "path.time_s", s->path_time_s);
    return o.overflow ? -1 : (int)o.used;
}

int scene_etag(const lucent_scene *scene, const char *device, char out[65])
{
    /* NUL separators keep the build hash, the device and the scene from running into each other. */
    char text[4096 + 512];
    size_t head = (size_t)snprintf(text, sizeof text, "%s%c%.255s%c", LUCENTD_RENDERER_HASH, 0, device, 0);
    int n = scene_canonical(scene, text + head, sizeof text - head);
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int digest_len = 0;
    if (n < 0 || !EVP_Digest(text, head + (size_t)n, digest, &digest_len, EVP_sha256(), NULL) || digest_len != 32)
        return -1;
    for (unsigned i = 0; i < digest_len; i++)
        snprintf(out + 2 * i, 3, "%02x", digest[i]);
    return 0;
}
