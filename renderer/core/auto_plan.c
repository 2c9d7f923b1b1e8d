/* auto_plan.c - method "auto": sizes the projection images to the object's pixel footprint, picks samples
 * from how many texels the kernel covers, and draws the side views only where light enters unseen. */
#include "auto_plan.h"

#include "profile.h"
#include "frame_plan.h"
#include "linalg.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define KERNEL_ENERGY 0.95
#define AUTO_MIN_PROJECTION 64
#define AUTO_MAX_PROJECTION 512
/* Below this reduced albedo in some channel diffusion misses most of the light through thin parts, which
 * single scattering (and the light crossing unscattered) brings: added when light enters behind. Against
 * method path, ketchup (0.02) is far nearer with it; skin1 (0.68) and marble are nearer without. */
#define AUTO_SINGLE_ALBEDO 0.5

static double lowest_reduced_albedo(const lucent_material *m)
{
    double lowest = 1.0;
    for (int c = 0; c < 3; c++)
        lowest = fmin(lowest, m->sigma_s_prime[c] / (m->sigma_s_prime[c] + m->sigma_a[c]));
    return lowest;
}

static int next_pow2(double x, int lo, int hi)
{
    int p = lo;
    while (p < hi && p < x)
        p *= 2;
    return p;
}

/* Radius (mm) holding KERNEL_ENERGY of the profile's integral out to r_max: bisection on the closed-form disc. */
static double kernel_radius(const struct profile *d, double r_max)
{
    double target = KERNEL_ENERGY * profile_disc(d, r_max), lo = 0.0, hi = r_max;
    for (int i = 0; i < 60; i++) {
        double mid = 0.5 * (lo + hi);
        if (profile_disc(d, mid) < target)
            lo = mid;
        else
            hi = mid;
    }
    return hi;
}

/* The bounding sphere's diameter in pixels; the camera inside it sees it larger than any image. */
static double object_pixels(const lucent_scene *s, const struct view_frame *cam, double radius)
{
    double depth = -v3_dot(cam->forward, cam->eye);
    if (depth <= radius)
        return INFINITY;
    double t = tan(asin(radius / depth));
    return fmax(s->height * t / cam->half_h, s->width * t / cam->half_w);
}

lucent_status auto_plan_choose(const lucent_scene *scene, const struct lucent_mesh *mesh, struct auto_plan *out,
                               lucent_error *err)
{
    struct view_frame cam;
    lucent_status st = frame_camera(scene, mesh, &cam, err);
    if (st != LUCENT_OK)
        return st;
    lucent_scene *s = &out->scene;
    *s = *scene;
    double radius = mesh->radius * FRAME_FIT_MARGIN;
    out->object_pixels = object_pixels(scene, &cam, radius);
    /* Where the front image holds all the light there is to diffuse, one view integrates it as well as
     * five (measured: better, with the samples the side views would cost). */
    double hidden[LUCENT_MAX_LIGHTS], entering[LUCENT_MAX_LIGHTS], hidden_sum = 0.0, entering_sum = 0.0;
    frame_light_shares(scene, mesh, cam.forward, 0.0, hidden, entering);
    for (int l = 0; l < scene->light_count; l++) {
        hidden_sum += hidden[l];
        entering_sum += entering[l];
    }
    out->hidden_light_share = entering_sum > 0.0 ? hidden_sum / entering_sum : 0.0;
    /* With R taken between points of the surface the dipole is the nearest profile to method "path" under
     * side and back light alike (README, Diffusion profiles), and with the transport equation's decay rate
     * (asymptotic_dipole) nearer still through thick absorbing parts (the same where the albedo is near 1);
     * before R between points, normalized diffusion was under side light. */
    int chosen = scene->material.profile == LUCENT_PROFILE_DEFAULT;
    if (chosen)
        s->material.profile = LUCENT_PROFILE_ASYMPTOTIC_DIPOLE;
    out->profile = s->material.profile;
    double scale_mm = frame_scale_mm(scene, mesh), r_max = 2.0 * mesh->radius * scale_mm;
    double widest = 0.0, narrowest = INFINITY;
    for (int c = 0; c < 3; c++) {
        struct profile d;
        profile_init(&d, s->material.profile, scene->material.sigma_a[c], scene->material.sigma_s_prime[c],
                     scene->material.g, scene->material.eta);
        double r = kernel_radius(&d, r_max);
        widest = fmax(widest, r);
        narrowest = fmin(narrowest, r);
    }
    /* Two texels per pixel of the object, up to AUTO_MAX_PROJECTION: measured on the trade's side-lit
     * cases, five views at 512 beat 256 at 256^2 (rel L2 0.010-0.028 lower) and 1024 at 512^2. */
    double object_mm = 2.0 * radius * scale_mm;
    s->projection_size = next_pow2(2.0 * out->object_pixels - 0.5, AUTO_MIN_PROJECTION, AUTO_MAX_PROJECTION);
    s->side_projection_size = 0;
    out->kernel_texels = widest / (object_mm / s->projection_size);
    out->diffuse_limit = out->kernel_texels < AUTO_DIFFUSE_LIMIT_TEXELS;
    double covered = PI * out->kernel_texels * out->kernel_texels;
    s->samples = next_pow2(covered, AUTO_MIN_SAMPLES, AUTO_MAX_SAMPLES);
    int per_channel = !out->diffuse_limit && widest > AUTO_PER_CHANNEL_SPREAD * narrowest;
    /* Per-channel sampling fetches three times per sample: half the samples keep it near the budget. */
    if (per_channel)
        s->samples = s->samples / 2 > AUTO_MIN_SAMPLES ? s->samples / 2 : AUTO_MIN_SAMPLES;
    s->sampling = per_channel ? LUCENT_SAMPLING_PER_CHANNEL : LUCENT_SAMPLING_SHARED;
    int sides = out->hidden_light_share > AUTO_HIDDEN_LIGHT_SHARE;
    s->method = sides ? LUCENT_METHOD_FIVE : LUCENT_METHOD_SINGLE;
    /* Against method path (64 walks): with light entering behind, single scattering brings absorbing
     * media nearer (back-lit ketchup 0.47 -> 0.25 rel L2, skin1 0.25 -> 0.21), while white ones, whose
     * diffusion is already 1.2-1.8x too bright there, get worse (marble 0.18 -> 0.22); lit from the
     * side, it adds 10-50% the walks do not have. */
    int single_chosen = scene->single_scattering == LUCENT_CHOSEN;
    int behind = sides && frame_light_enters_behind(scene, mesh, cam.forward);
    int absorbing = lowest_reduced_albedo(&scene->material) < AUTO_SINGLE_ALBEDO;
    if (single_chosen)
        s->single_scattering = behind && absorbing;
    snprintf(out->decisions, sizeof out->decisions,
             "\"object_pixels\":%.1f,\"kernel_radius_texels\":%.3g,\"kernel_spread\":%.3g,"
             "\"hidden_light_share\":%.3g,\"views_reason\":\"%s\",\"sampling_reason\":\"%s\",\"profile_reason\":\"%s\","
             "\"single_scattering_reason\":\"%s\"",
             isfinite(out->object_pixels) ? out->object_pixels : -1.0, out->kernel_texels, widest / narrowest,
             out->hidden_light_share,
             sides ? "light enters surface the front view does not see" : "the front view sees where the light enters",
             out->diffuse_limit ? "diffuse limit: 95% of R_d within half a texel"
             : per_channel      ? "channel kernels differ over 3x: per channel"
                                : "samples cover the kernel's texels, shared by the channels",
             chosen ? "asymptotic_dipole: nearest method path under side and back light" : "given",
             !single_chosen           ? "given"
             : !behind                ? "no light enters behind the object: diffusion alone"
             : absorbing              ? "light enters behind an absorbing medium: scattered once or not at all"
                                      : "light enters behind a scattering medium (albedo >= 0.5): diffusion alone");
    return LUCENT_OK;
}
