/* path.c - method "path": per pixel and colour channel, random walks from the visible point into the medium
 * until they leave it, each exit connected to the lights with a shadow ray (the adjoint of light's walk).
 *
 * Boundary conventions (path.boundary):
 * - "fresnel" (default): the camera's ray refracts into the medium through the smooth dielectric (eta),
 *   weighted by its Fresnel transmittance Ft(eta, cos_o); a walk reaching the boundary from inside is
 *   reflected specularly with probability F (total internal reflection included), else it leaves at that
 *   point y, spread over the outside hemisphere as transmitted light is spread, Ft(cos) cos / (pi (1 -
 *   F_ext)), with F_ext the hemispherical Fresnel reflectance from outside: each light adds E cos_l
 *   Ft(eta, cos_l) / (pi (1 - F_ext)). Energy is conserved: a white medium returns all light that enters.
 * - "cycles" (Blender Cycles' random walk): the walk enters in a cosine-distributed direction about the
 *   shading normal as Cycles corrects it at grazing views (valid_reflection.h), weight 1, and leaves at the
 *   first boundary hit; each light adds E cos_l / pi. No Fresnel anywhere.
 * Free flights are exponential in sigma_t = sigma_a + sigma_s' / (1 - g) (mm^-1), directions after a
 * scattering event Henyey-Greenstein with g. Absorption multiplies the weight by the albedo; below
 * ROULETTE_WEIGHT a walk survives with probability weight / ROULETTE_WEIGHT at that weight (Russian roulette:
 * unbiased, no step limit). A walk that strays ESCAPE_RADII bounding radii from the mesh (only possible
 * through an open mesh) is counted and ends dark. */
#include "path.h"
#include "bvh.h"
#include "clock_ms.h"
#include "dipole.h"
#include "linalg.h"
#include "parallel.h"
#include "ref_lights.h"
#include "valid_reflection.h"
#include "visible_point.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define ROULETTE_WEIGHT 0.1
#define ESCAPE_RADII 4.0
/* A walk in a medium that barely absorbs, far larger than its mean free path, may take billions of steps:
 * it looks at the cancel flag this often, so a render's deadline still stops it. */
#define CANCEL_CHECK_STEPS 65536
/* Rays leave a surface this far (times the mesh radius) along its normal so they miss their own triangle. */
#define SURFACE_OFFSET 1e-7

struct counters {
    atomic_ullong walks, steps, escaped;
};

struct context {
    const lucent_scene *scene;
    const struct lucent_mesh *mesh;
    const struct view_frame *camera;
    struct bvh *bvh;
    struct ref_light lights[LUCENT_MAX_LIGHTS];
    int light_count, shadows;
    lucent_path_boundary boundary;
    lucent_path_filter filter;
    double scale_mm, eta, g, exit_norm;     /* exit_norm: 1 / (pi (1 - F_ext)), or 1 / pi */
    double sigma_t[3], albedo[3];
    double offset;                          /* SURFACE_OFFSET x radius */
    uint64_t seed;
    uint32_t pass, batch;                   /* the passes [pass, pass + batch) run now, row by row */
    double *sum, *sum_sq;                   /* per pixel and channel, over passes */
    uint32_t *hits;                         /* per pixel: passes whose ray hit the mesh (box filter only) */
    const atomic_int *cancel;
    lucent_image *out;
    struct counters counters;
};

/* ---- random numbers: SplitMix64, seeded per pixel, pass and channel (thread-count independent) ---- */

static uint64_t next_u64(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1). */
static double uniform(uint64_t *s)
{
    return (double)(next_u64(s) >> 11) * 0x1.0p-53;
}

static uint64_t walk_seed(const struct context *ctx, size_t pixel, uint32_t pass, int channel)
{
    uint64_t s = ctx->seed ^ ((uint64_t)pixel * 0x2545f4914f6cdd1dull);
    s = next_u64(&s) ^ ((uint64_t)pass << 2 | (uint64_t)channel);
    return next_u64(&s);
}

/* ---- directions ---- */

/* An orthonormal basis (t, b) around unit n. */
static void basis(const double n[3], double t[3], double b[3])
{
    double a[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    v3_cross(n, a, t);
    v3_normalize(t);
    v3_cross(n, t, b);
}

/* The direction at cosine `c` from unit axis and azimuth 2 pi u. */
static void around(const double axis[3], double c, double u, double out[3])
{
    double t[3], b[3], s = sqrt(fmax(0.0, 1.0 - c * c)), phi = 2.0 * PI * u;
    basis(axis, t, b);
    for (int a = 0; a < 3; a++)
        out[a] = c * axis[a] + s * (cos(phi) * t[a] + sin(phi) * b[a]);
    v3_normalize(out);
}

/* Henyey-Greenstein: the new direction's cosine to the old one (Pharr, Jakob and Humphreys, 11.3.1). */
static double hg_cosine(double g, double u)
{
    if (fabs(g) < 1e-3)
        return 1.0 - 2.0 * u;
    double k = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    return fmin(fmax((1.0 + g * g - k * k) / (2.0 * g), -1.0), 1.0);
}

/* F_ext: the hemispherical average of the Fresnel reflectance from outside, 2 int F(mu) mu dmu. */
static double external_diffuse_reflectance(double eta)
{
    const int n = 4096;
    double sum = 0.0;
    for (int i = 0; i < n; i++) {
        double mu = (i + 0.5) / n;
        sum += (1.0 - fresnel_transmittance(eta, mu)) * mu;
    }
    return 2.0 * sum / n;
}

/* ---- the walk ---- */

/* Light arriving at exit point y (outward shading normal n, geometric g) in channel c, as the boundary
 * convention passes it into the medium. */
static double light_at(const struct context *ctx, const double y[3], const double n[3], const double g[3], int c)
{
    double origin[3], sum = 0.0;
    v3_scale_add(y, g, ctx->offset, origin);
    for (int l = 0; l < ctx->light_count; l++) {
        double cos_l, arrival = ctx->lights[l].rgb[c] == 0.0 ? 0.0
                                : ref_light_arrival(&ctx->lights[l], ctx->bvh, ctx->shadows, y, n, origin, &cos_l);
        if (arrival > 0.0)
            sum += ctx->lights[l].rgb[c] * arrival *
                   (ctx->boundary == LUCENT_PATH_FRESNEL ? fresnel_transmittance(ctx->eta, cos_l) : 1.0);
    }
    return sum * ctx->exit_norm;
}

/* The direction the walk starts in, and its weight: refraction of the camera ray (fresnel), or a
 * cosine-distributed direction into the medium about Cycles' shading normal (cycles). n and g face the
 * camera. */
static double enter(const struct context *ctx, const double dir[3], const double n[3], const double g[3],
                    uint64_t *rng, double d[3])
{
    double w = 1.0;
    if (ctx->boundary == LUCENT_PATH_FRESNEL) {
        double cos_i = fmin(fmax(-v3_dot(n, dir), 0.0), 1.0), k = 1.0 / ctx->eta;
        double cos_t = sqrt(fmax(0.0, 1.0 - k * k * (1.0 - cos_i * cos_i)));
        w = fresnel_transmittance(ctx->eta, cos_i);
        for (int a = 0; a < 3; a++)
            d[a] = k * dir[a] + (k * cos_i - cos_t) * n[a];
        v3_normalize(d);
    } else {
        double eye[3] = {-dir[0], -dir[1], -dir[2]}, shading[3];
        valid_reflection_normal(g, eye, n, shading);
        double inward[3] = {-shading[0], -shading[1], -shading[2]};
        around(inward, sqrt(uniform(rng)), uniform(rng), d);
    }
    if (v3_dot(d, g) >= 0.0)   /* a shading normal far from the geometric one */
        for (int a = 0; a < 3; a++)
            d[a] = -g[a];
    return w;
}

/* One walk in channel c from surface point p (normals facing the camera ray dir): its estimate of the
 * radiance leaving p towards the eye. */
static double walk(struct context *ctx, int c, const double p0[3], const double n0[3], const double g0[3],
                   const double dir[3], uint64_t *rng, unsigned long long *steps, unsigned long long *escaped)
{
    double d[3], p[3];
    double w = enter(ctx, dir, n0, g0, rng, d);
    if (w <= 0.0)
        return 0.0;
    double escape = ESCAPE_RADII * ctx->mesh->radius, mfp = 1.0 / (ctx->sigma_t[c] * ctx->scale_mm);
    v3_scale_add(p0, g0, -ctx->offset, p);
    for (unsigned long long taken = 1;; taken++) {
        ++*steps;
        if (taken % CANCEL_CHECK_STEPS == 0 && ctx->cancel && atomic_load(ctx->cancel))
            return 0.0;   /* the render is being cancelled: this value is never shown */
        double t = -log(1.0 - uniform(rng)) * mfp;
        struct bvh_hit hit;
        if (bvh_closest(ctx->bvh, p, d, t, &hit)) {
            double y[3], n[3], g[3];
            mesh_surface_at(ctx->mesh, hit.triangle, hit.u, hit.v, y, n, g);
            if (v3_dot(g, d) < 0.0)   /* outward is the way the walk goes */
                for (int a = 0; a < 3; a++)
                    n[a] = -n[a], g[a] = -g[a];
            double cos_i = v3_dot(d, n) > 0.0 ? v3_dot(d, n) : v3_dot(d, g);
            if (ctx->boundary == LUCENT_PATH_FRESNEL && uniform(rng) < fresnel_internal_reflectance(ctx->eta, cos_i)) {
                double k = 2.0 * v3_dot(d, g);
                for (int a = 0; a < 3; a++)
                    d[a] -= k * g[a];
                v3_scale_add(y, g, -ctx->offset, p);
                continue;
            }
            return w * light_at(ctx, y, n, g, c);
        }
        v3_scale_add(p, d, t, p);
        if (v3_length(p) > escape) {
            ++*escaped;
            return 0.0;
        }
        w *= ctx->albedo[c];
        if (w < ROULETTE_WEIGHT) {
            if (uniform(rng) >= w / ROULETTE_WEIGHT)
                return 0.0;
            w = ROULETTE_WEIGHT;
        }
        double old[3] = {d[0], d[1], d[2]};
        around(old, hg_cosine(ctx->g, uniform(rng)), uniform(rng), d);
    }
}

/* One pass of a pixel: one walk per channel from the pixel centre's ray (point filter) or from a ray through
 * a uniform random point of the pixel (box; a miss adds 0); the first hit also writes coverage and AOVs. */
static void shade_pixel(struct context *ctx, int x, int y, uint32_t pass, unsigned long long *walks,
                        unsigned long long *steps, unsigned long long *escaped)
{
    lucent_image *img = ctx->out;
    size_t i = (size_t)y * img->width + x;
    double px = x + 0.5, py = y + 0.5;
    if (ctx->filter == LUCENT_PATH_FILTER_BOX) {
        uint64_t rng = walk_seed(ctx, i, pass, 3);   /* channels are 0..2 */
        px = x + uniform(&rng);
        py = y + uniform(&rng);
    }
    struct visible_point vp;   /* a back face in view: the medium is on the camera's far side of it */
    if (!visible_point_at(ctx->camera, ctx->bvh, ctx->mesh, NULL, px, py, img->width, img->height, &vp))
        return;
    int first_hit = ctx->filter == LUCENT_PATH_FILTER_BOX ? ctx->hits[i]++ == 0 : pass == 0;
    for (int c = 0; c < 3; c++) {
        uint64_t rng = walk_seed(ctx, i, pass, c);
        double v = walk(ctx, c, vp.p, vp.n, vp.g, vp.dir, &rng, steps, escaped);
        ctx->sum[i * 3 + c] += v;
        ctx->sum_sq[i * 3 + c] += v * v;
    }
    *walks += 3;
    if (first_hit)
        visible_point_write_aovs(img, i, &vp);
}

static void shade_rows(void *arg, size_t begin, size_t end)
{
    struct context *ctx = arg;
    unsigned long long walks = 0, steps = 0, escaped = 0;
    for (size_t y = begin; y < end; y++)
        for (uint32_t pass = ctx->pass; pass < ctx->pass + ctx->batch; pass++)
            for (int x = 0; x < ctx->out->width; x++)
                shade_pixel(ctx, x, (int)y, pass, &walks, &steps, &escaped);
    atomic_fetch_add(&ctx->counters.walks, walks);
    atomic_fetch_add(&ctx->counters.steps, steps);
    atomic_fetch_add(&ctx->counters.escaped, escaped);
}

/* ---- set-up ---- */

static lucent_status set_up(struct context *ctx, lucent_error *err)
{
    const lucent_material *m = &ctx->scene->material;
    ctx->light_count = ctx->scene->light_count;
    ctx->g = m->g;
    for (int c = 0; c < 3; c++) {
        double sigma_s = m->sigma_s_prime[c] / (1.0 - m->g);
        ctx->sigma_t[c] = m->sigma_a[c] + sigma_s;
        ctx->albedo[c] = sigma_s / ctx->sigma_t[c];
    }
    ctx->exit_norm = ctx->boundary == LUCENT_PATH_FRESNEL
                         ? 1.0 / (PI * (1.0 - external_diffuse_reflectance(ctx->eta)))
                         : 1.0 / PI;
    ctx->offset = SURFACE_OFFSET * ctx->mesh->radius;
    ctx->shadows = !ctx->mesh->convex;
    return ref_lights_from_scene(ctx->scene, ctx->mesh, ctx->lights, err);
}

/* The image from the sums, and the image's relative standard error. */
static double finish_image(struct context *ctx, uint32_t passes)
{
    lucent_image *img = ctx->out;
    size_t pixels = (size_t)img->width * img->height;
    double var = 0.0, power = 0.0;
    for (size_t i = 0; i < pixels; i++) {
        if (img->rgba[i * 4 + 3] == 0.0f)
            continue;
        for (int c = 0; c < 3; c++) {
            double mean = ctx->sum[i * 3 + c] / passes;
            double spread = passes > 1 ? (ctx->sum_sq[i * 3 + c] / passes - mean * mean) * passes / (passes - 1) : 0.0;
            img->rgba[i * 4 + c] = (float)mean;
            var += fmax(spread, 0.0) / passes;
            power += mean * mean;
        }
        if (ctx->filter == LUCENT_PATH_FILTER_BOX)   /* premultiplied, as the radiance (a miss added 0) */
            img->rgba[i * 4 + 3] = (float)ctx->hits[i] / (float)passes;
    }
    return power > 0.0 && passes > 1 ? sqrt(var / power) : 0.0;
}

lucent_status path_render(const lucent_scene *scene, const struct lucent_mesh *mesh, const struct view_frame *camera,
                          double scale_mm, const struct path_options *options, int with_aovs, lucent_image *out,
                          struct path_report *report, lucent_error *err)
{
    struct context ctx = {.scene = scene, .mesh = mesh, .camera = camera, .scale_mm = scale_mm,
                          .eta = scene->material.eta, .boundary = options->boundary, .filter = options->filter,
                          .seed = options->seed,
                          .cancel = options->cancel, .out = out};
    *report = (struct path_report){0};
    *out = (lucent_image){0};
    if (!mesh || mesh->triangle_count == 0)
        return lucent_fail(err, LUCENT_E_MESH, "mesh", "the mesh has no triangles to render");
    if (options->samples < 1 || options->samples > LUCENT_MAX_PATH_SAMPLES)
        return lucent_fail(err, LUCENT_E_LIMIT, "path.samples", "must be 1..%u", LUCENT_MAX_PATH_SAMPLES);
    if (!(options->time_s >= 0.0 && options->time_s <= LUCENT_MAX_PATH_TIME_S))
        return lucent_fail(err, LUCENT_E_LIMIT, "path.time_s", "must be 0..%g", LUCENT_MAX_PATH_TIME_S);
    lucent_status st = lucent_image_alloc(out, scene->width, scene->height, with_aovs, err);
    if (st != LUCENT_OK)
        return st;
    size_t pixels = (size_t)scene->width * scene->height;
    ctx.sum = calloc(pixels * 3, sizeof *ctx.sum);
    ctx.sum_sq = calloc(pixels * 3, sizeof *ctx.sum_sq);
    ctx.hits = ctx.filter == LUCENT_PATH_FILTER_BOX ? calloc(pixels, sizeof *ctx.hits) : NULL;
    if (!ctx.sum || !ctx.sum_sq || (ctx.filter == LUCENT_PATH_FILTER_BOX && !ctx.hits)) {
        st = lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory for %zu pixels' sums", pixels);
        goto fail;
    }
    if ((st = bvh_build(mesh, &ctx.bvh, err)) != LUCENT_OK || (st = set_up(&ctx, err)) != LUCENT_OK)
        goto fail;
    int threads = parallel_threads(options->threads);
    double t0 = now_ms();
    /* Passes run in batches of at least 64 rows' worth, so that a small image does not start threads for
     * every pass; the time budget is checked between batches. */
    uint32_t passes = 0, batch = scene->height >= 64 ? 1 : (uint32_t)((64 + scene->height - 1) / scene->height);
    while (passes < options->samples) {
        ctx.pass = passes;
        ctx.batch = batch < options->samples - passes ? batch : options->samples - passes;
        parallel_run(&ctx, threads, (size_t)scene->height, 1, shade_rows, options->cancel);
        if (options->cancel && atomic_load(options->cancel)) {
            st = lucent_fail(err, LUCENT_E_CANCELLED, "", "the path render was cancelled");
            goto fail;
        }
        passes += ctx.batch;
        if (options->time_s > 0.0 && now_ms() - t0 > options->time_s * 1e3)
            break;
    }
    unsigned long long walks = atomic_load(&ctx.counters.walks);
    report->samples = passes;
    report->rel_std_error = finish_image(&ctx, passes);
    report->mean_steps = walks ? (double)atomic_load(&ctx.counters.steps) / (double)walks : 0.0;
    report->escaped_share = walks ? (double)atomic_load(&ctx.counters.escaped) / (double)walks : 0.0;
    report->ms = now_ms() - t0;
    bvh_free(ctx.bvh);
    free(ctx.sum);
    free(ctx.sum_sq);
    free(ctx.hits);
    return LUCENT_OK;
fail:
    bvh_free(ctx.bvh);
    free(ctx.sum);
    free(ctx.sum_sq);
    free(ctx.hits);
    lucent_image_free(out);
    return st;
}
