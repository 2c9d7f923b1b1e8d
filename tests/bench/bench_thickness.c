/* bench_thickness.c - a game engine's "thickness" transmission (Jimenez et al. 2010) added to method single,
 * scored against method "reference" beside method five's light views, on back- and rim-lit thin parts.
 *
 * Per covered pixel p and light not reaching p's side, the light is taken to enter at q, the last surface
 * a ray from p toward the light crosses (what a shadow map stores), and to come out at p attenuated by the
 * dipole integrated over a whole plane at depth s = |p - q|:
 *     L(p) = Ft(eta, n_p.eye) / pi * E(q) * T(s),  T(s) = alpha'/2 sum_{z in z_r, z_v} z e^(-sigma_tr D) / D,
 *     D = sqrt(s^2 + z^2), E(q) = light * falloff * cos_q * Ft(eta, cos_q).
 * The thickness is exact here (ray cast, not read from a shadow map): the best case of a shadow-map
 * thickness, so the error measured is the model's own, not the shadow map's. */
#include "bench_host.h"
#include "bench_median.h"
#include "bench_scene.h"
#include "bvh.h"
#include "dipole.h"
#include "profile.h"
#include "flat_cube.h"
#include "frame_plan.h"
#include "linalg.h"
#include "lucent.h"
#include "mesh.h"
#include "view_frame.h"

#include <float.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N(a) (sizeof(a) / sizeof((a)[0]))
#define PI 3.14159265358979323846
/* Rays start this far (times the mesh radius) past the surface they leave, as the reference's shadow
 * rays do, so they do not hit that surface again. */
#define RAY_OFFSET 1e-6
/* Surfaces one thickness ray may cross; far above any of these meshes', it only bounds the loop. */
#define MAX_CROSSINGS 4096


/* The slab, 50 x 50 x 3 mm and seen face-on, is the thin part a thickness model is made for. */
enum { MESH_SPHERE, MESH_TORUS, MESH_BUNNY, MESH_SLAB, MESH_COUNT };
static const struct mesh_case meshes[] = {
    [MESH_SPHERE] = {"sphere", "{\"builtin\":\"sphere\"}", ""},
    [MESH_TORUS] = {"torus", "{\"builtin\":\"torus\"}", ""},
    [MESH_BUNNY] = {"bunny", NULL, ""},
    [MESH_SLAB] = {"slab", NULL, "\"scale_mm\":50,"},
};
enum { LIGHT_BACK, LIGHT_RIM, LIGHT_COUNT };
static const struct light_case lights[] = {[LIGHT_BACK] = {"back", "[0,0,1]"},
                                           [LIGHT_RIM] = {"rim", "[-0.766,0,0.643]"}};
static const char *const materials[] = {"marble", "skin1", "skimmilk", "ketchup"};

/* The images scored against the reference. */
enum { IMG_FIVE, IMG_THICKNESS, IMG_SINGLE, IMG_COUNT };
static const char *const image_names[] = {"five", "thickness", "single"};

enum { CASES = (int)(N(meshes) * N(lights) * N(materials)) };

struct options {
    const char *prefix;
    const char *mesh_file[MESH_COUNT];
    char slab_path[4096];
    int size, images;
};

struct case_id {
    int mesh, light, material;
};

struct result {
    lucent_image_error e[IMG_COUNT];
    int mask_mismatch;   /* pixels the thickness rays and the reference disagree on covering */
    double term_share;   /* the thickness term's summed RGB over the reference's */
};

/* One mesh as the renderer loads it (mesh-centred), with its ray-casting tree. */
struct geometry {
    struct lucent_mesh *mesh;
    struct bvh *bvh;
};

/* What the per-pixel thickness term needs of one case. */
struct thickness_ctx {
    const lucent_scene *scene;
    const struct geometry *geo;
    struct view_frame camera;
    double scale_mm;
    struct profile profile[3];
};

struct outputs {
    FILE *csv, *md;
};

static struct case_id case_of(int index)
{
    struct case_id c;
    c.material = index % (int)N(materials);
    index /= (int)N(materials);
    c.light = index % (int)N(lights);
    c.mesh = index / (int)N(lights);
    return c;
}

static void case_label(int index, char *buf, size_t cap)
{
    struct case_id c = case_of(index);
    snprintf(buf, cap, "%s %s %s", meshes[c.mesh].name, lights[c.light].name, materials[c.material]);
}

static int usage(void)
{
    fprintf(stderr, "usage: bench_thickness [--size N] [--images] BUNNY.obj OUT_PREFIX\n"
                    "  writes OUT_PREFIX.md, OUT_PREFIX.csv and OUT_PREFIX_slab.obj (the slab it renders);\n"
                    "  N: image side (default 256); --images: also OUT_PREFIX_<case>_<image>.png (exposed for\n"
                    "  the reference's brightest channel)\n");
    return 2;
}

static int parse_options(int argc, char **argv, struct options *o)
{
    *o = (struct options){.size = 256};
    int positional = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--size") == 0 && i + 1 < argc) {
            char *end;
            long n = strtol(argv[++i], &end, 10);
            if (*end || n < 16 || n > LUCENT_MAX_IMAGE_SIDE)
                return -1;
            o->size = (int)n;
        } else if (strcmp(argv[i], "--images") == 0) {
            o->images = 1;
        } else if (positional == 0) {
            o->mesh_file[MESH_BUNNY] = argv[i], positional++;
        } else if (positional == 1) {
            o->prefix = argv[i], positional++;
        } else {
            return -1;
        }
    }
    return positional == 2 ? 0 : -1;
}

/* The scene of one case with the given fragment ("method", "format"). */
static lucent_status make_scene(const struct options *o, struct case_id c, const char *fragment, lucent_scene *s,
                                lucent_error *err)
{
    return bench_scene(&meshes[c.mesh], o->mesh_file[c.mesh], materials[c.material], &lights[c.light], o->size,
                       fragment, s, err);
}

/* Loads the mesh the way the renderer's cache does, so camera rays land on the renderer's triangles. */
static lucent_status load_geometry(const lucent_mesh_ref *ref, struct geometry *g, lucent_error *err)
{
    *g = (struct geometry){0};
    lucent_status st = ref->source == LUCENT_MESH_BUILTIN ? lucent_mesh_builtin(ref->builtin, ref->triangles, &g->mesh, err)
                                                          : lucent_mesh_import_file(ref->file, &g->mesh, err);
    if (st == LUCENT_OK)
        st = bvh_build(g->mesh, &g->bvh, err);
    return st;
}

static void free_geometry(struct geometry *g)
{
    bvh_free(g->bvh);
    lucent_mesh_free(g->mesh);
    *g = (struct geometry){0};
}

/* Unit direction from p (mesh-centred) toward light l, its falloff there and the distance to it
 * (infinite for directional lights), as the reference's irradiance() has them. */
static void toward_light(const struct thickness_ctx *ctx, int l, const double p[3], double dir[3], double *falloff,
                         double *t_max)
{
    const lucent_light *light = &ctx->scene->lights[l];
    if (light->type == LUCENT_LIGHT_POINT) {
        for (int a = 0; a < 3; a++)
            dir[a] = light->position[a] - ctx->geo->mesh->center[a] - p[a];
        *t_max = v3_normalize(dir);
        *falloff = 1.0 / fmax(*t_max * *t_max, DBL_MIN);
        return;
    }
    for (int a = 0; a < 3; a++)
        dir[a] = -light->direction[a];
    v3_normalize(dir);
    *falloff = 1.0;
    *t_max = INFINITY;
}

/* The last surface the ray from p along dir crosses within t_max: the first one the light meets coming
 * the other way. Returns its distance from p (scene units) and fills hit, or returns -1 on a miss. */
static double last_crossing(const struct geometry *g, const double p[3], const double dir[3], double t_max,
                            struct bvh_hit *last)
{
    double eps = RAY_OFFSET * g->mesh->radius, travelled = eps, origin[3], found = -1.0;
    v3_scale_add(p, dir, eps, origin);
    struct bvh_hit hit;
    for (int k = 0; k < MAX_CROSSINGS && travelled < t_max; k++) {
        if (!bvh_closest(g->bvh, origin, dir, t_max - travelled, &hit))
            break;
        *last = hit;
        found = travelled + hit.t;
        /* Restart just past this crossing; its own triangle is then behind the ray. */
        travelled = found + eps;
        v3_scale_add(p, dir, travelled, origin);
    }
    return found;
}

/* Light l's thickness term at p (normal n facing the eye, facing = n . to_eye), added to rgb. */
static void add_light(const struct thickness_ctx *ctx, int l, const double p[3], const double n[3], double facing,
                      double rgb[3])
{
    double dir[3], falloff, t_max, q[3], n_q[3], g_q[3];
    toward_light(ctx, l, p, dir, &falloff, &t_max);
    if (v3_dot(n, dir) > 0.0)
        return;  /* lit side: the reflectance part's business */
    struct bvh_hit hit = {0};
    double s = last_crossing(ctx->geo, p, dir, t_max, &hit);
    if (s < 0.0)
        return;
    mesh_surface_at(ctx->geo->mesh, hit.triangle, hit.u, hit.v, q, n_q, g_q);
    const lucent_light *light = &ctx->scene->lights[l];
    if (light->type == LUCENT_LIGHT_POINT) {
        double unused[3], dist;
        toward_light(ctx, l, q, unused, &falloff, &dist);
    }
    double eta = ctx->scene->material.eta, cos_q = fmax(v3_dot(n_q, dir), 0.0);
    double k = falloff * cos_q * fresnel_transmittance(eta, cos_q) * fresnel_transmittance(eta, facing) / PI;
    for (int c = 0; c < 3; c++)
        rgb[c] += light->color[c] * light->intensity * k * profile_tail(&ctx->profile[c], s * ctx->scale_mm);
}

/* The thickness term of pixel (x, y), the camera ray cast as the reference casts it; returns 0 where the
 * pixel is uncovered. */
static int thickness_pixel(const struct thickness_ctx *ctx, int x, int y, double rgb[3])
{
    const struct view_frame *cam = &ctx->camera;
    double dir[3], p[3], n[3], g[3];
    struct bvh_hit hit;
    rgb[0] = rgb[1] = rgb[2] = 0.0;
    view_frame_pixel_ray(cam, x, y, ctx->scene->width, ctx->scene->height, dir);
    if (!bvh_closest(ctx->geo->bvh, cam->eye, dir, INFINITY, &hit))
        return 0;
    mesh_surface_at(ctx->geo->mesh, hit.triangle, hit.u, hit.v, p, n, g);
    /* A back face in view: shade the side facing the camera, as the reference does. */
    if (v3_dot(g, dir) > 0.0)
        for (int a = 0; a < 3; a++)
            n[a] = -n[a];
    double facing = -v3_dot(n, dir);
    for (int l = 0; l < ctx->scene->light_count; l++)
        add_light(ctx, l, p, n, facing, rgb);
    return 1;
}

/* out = single + the thickness term (premultiplied by single's coverage, the renderer's convention).
 * Counts the pixels whose coverage disagrees with the reference's, and the term's share of its energy. */
static lucent_status thickness_image(const struct thickness_ctx *ctx, const lucent_image *single,
                                     const lucent_image *ref, lucent_image *out, struct result *res, lucent_error *err)
{
    int w = ctx->scene->width, h = ctx->scene->height;
    lucent_status st = lucent_image_alloc(out, w, h, 0, err);
    if (st != LUCENT_OK)
        return st;
    double term_sum = 0.0, ref_sum = 0.0;
    res->mask_mismatch = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            double rgb[3];
            int covered = thickness_pixel(ctx, x, y, rgb);
            float alpha = single->rgba[i * 4 + 3];
            res->mask_mismatch += covered != (ref->rgba[i * 4 + 3] > 0.0f);
            for (int c = 0; c < 3; c++) {
                out->rgba[i * 4 + c] = single->rgba[i * 4 + c] + (float)(rgb[c] * alpha);
                term_sum += rgb[c] * alpha;
                ref_sum += ref->rgba[i * 4 + c];
            }
            out->rgba[i * 4 + 3] = alpha;
        }
    res->term_share = ref_sum > 0.0 ? term_sum / ref_sum : 0.0;
    return LUCENT_OK;
}

/* The millimetres per scene unit the renderer reported ("scale_mm" of stats.modelled), or -1. */
static double modelled_scale_mm(const lucent_stats *stats)
{
    const char *at = strstr(stats->modelled, "\"scale_mm\":");
    return at ? strtod(at + strlen("\"scale_mm\":"), NULL) : -1.0;
}

static lucent_status set_up_thickness(const lucent_scene *s, const struct geometry *geo, const lucent_stats *ref_stats,
                                      struct thickness_ctx *ctx, lucent_error *err)
{
    *ctx = (struct thickness_ctx){.scene = s, .geo = geo, .scale_mm = frame_scale_mm(s, geo->mesh)};
    lucent_status st = frame_camera(s, geo->mesh, &ctx->camera, err);
    if (st != LUCENT_OK)
        return st;
    /* A different mesh than the renderer's would show here first (the scale follows its bounding sphere). */
    double reported = modelled_scale_mm(ref_stats);
    if (!(fabs(reported - ctx->scale_mm) <= 1e-6 * ctx->scale_mm))
        return lucent_fail(err, LUCENT_E_INTERNAL, "scale_mm", "the reference used %.9g mm per unit, this bench %.9g",
                           reported, ctx->scale_mm);
    for (int c = 0; c < 3; c++)
        profile_init(&ctx->profile[c], s->material.profile, s->material.sigma_a[c], s->material.sigma_s_prime[c],
                     s->material.g, s->material.eta);
    return LUCENT_OK;
}

static lucent_status render(lucent_renderer *r, const struct options *o, int index, const char *fragment,
                            lucent_scene *s, lucent_image *img, lucent_stats *stats, lucent_error *err)
{
    lucent_status st = make_scene(o, case_of(index), fragment, s, err);
    if (st == LUCENT_OK)
        st = lucent_render(r, s, img, stats, err);
    return st;
}

/* Stops that bring the reference's brightest channel to 1: back-lit objects are far darker than 8 bits
 * resolve at exposure 0. */
static double auto_exposure(const lucent_image *ref)
{
    float peak = 0.0f;
    for (size_t i = 0; i < (size_t)ref->width * ref->height; i++)
        for (int c = 0; c < 3; c++)
            peak = fmaxf(peak, ref->rgba[i * 4 + c]);
    return peak > 0.0f ? fmin(fmax(-log2(peak), -LUCENT_MAX_EXPOSURE), LUCENT_MAX_EXPOSURE) : 0.0;
}

/* PREFIX_<mesh>_<light>_<material>_<name>.png, for looking at what a row measured. */
static lucent_status write_png(const struct options *o, int index, const char *name, const lucent_image *img,
                               double exposure, lucent_error *err)
{
    struct case_id c = case_of(index);
    char path[4096];
    static const double background[4] = {0.0, 0.0, 0.0, 1.0};
    snprintf(path, sizeof path, "%s_%s_%s_%s_%s.png", o->prefix, meshes[c.mesh].name, lights[c.light].name,
             materials[c.material], name);
    return lucent_image_write(path, img, LUCENT_FORMAT_PNG, exposure, background, err);
}

/* All four at the reference's exposure, so they compare by eye. */
static lucent_status write_pngs(const struct options *o, int index, const lucent_image *ref, const lucent_image *img,
                                lucent_error *err)
{
    double exposure = auto_exposure(ref);
    lucent_status st = write_png(o, index, "reference", ref, exposure, err);
    for (int k = 0; k < IMG_COUNT && st == LUCENT_OK; k++)
        st = write_png(o, index, image_names[k], &img[k], exposure, err);
    return st;
}

/* Renders the reference, five and single of one case, builds the thickness image, scores all three. */
static lucent_status run_case(lucent_renderer *r, const struct options *o, int index, const struct geometry *geo,
                              struct result *res, char *device, size_t device_cap, lucent_error *err)
{
    lucent_scene ref_scene, fast_scene;
    lucent_stats ref_stats, stats;
    lucent_image ref = {0}, img[IMG_COUNT] = {{0}};
    struct thickness_ctx ctx;
    char label[128];
    case_label(index, label, sizeof label);
    lucent_status st;
    if ((st = render(r, o, index, "\"method\":\"reference\",\"format\":\"exr\"", &ref_scene, &ref, &ref_stats,
                     err)) != LUCENT_OK ||
        (st = set_up_thickness(&ref_scene, geo, &ref_stats, &ctx, err)) != LUCENT_OK ||
        (st = render(r, o, index, "\"method\":\"five\"", &fast_scene, &img[IMG_FIVE], &stats, err)) != LUCENT_OK ||
        (st = render(r, o, index, "\"method\":\"single\"", &fast_scene, &img[IMG_SINGLE], &stats, err)) != LUCENT_OK ||
        (st = thickness_image(&ctx, &img[IMG_SINGLE], &ref, &img[IMG_THICKNESS], res, err)) != LUCENT_OK)
        goto done;
    snprintf(device, device_cap, "%s", stats.device);
    for (int k = 0; k < IMG_COUNT && st == LUCENT_OK; k++)
        st = lucent_image_compare(&img[k], &ref, &res->e[k], err);
    if (st == LUCENT_OK && o->images)
        st = write_pngs(o, index, &ref, img, err);
    if (st != LUCENT_OK)
        goto done;
    fprintf(stderr, "bench_thickness: %s: reference %.0f ms; thickness term %.3f of the reference's energy\n", label,
            ref_stats.ms_total, res->term_share);
    /* The camera rays are the reference's own: any disagreement means a different mesh or camera. */
    if (res->mask_mismatch)
        fprintf(stderr, "bench_thickness: %s: %d pixels covered by the thickness rays or the reference only\n",
                label, res->mask_mismatch);
done:
    lucent_image_free(&ref);
    for (int k = 0; k < IMG_COUNT; k++)
        lucent_image_free(&img[k]);
    return st;
}

static void write_csv_rows(FILE *csv, int size, int index, const struct result *x)
{
    struct case_id c = case_of(index);
    for (int k = 0; k < IMG_COUNT; k++) {
        const lucent_image_error *e = &x->e[k];
        fprintf(csv, "%s,%s,%s,%d,%s,%d,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%.6g\n", meshes[c.mesh].name,
                lights[c.light].name, materials[c.material], size, image_names[k], e->object.pixels,
                e->coverage_mismatch, e->object.rel_l2, e->band.rel_l2, e->noise, e->low_frequency_rel_l2,
                e->mean_ratio, x->mask_mismatch, k == IMG_THICKNESS ? x->term_share : 0.0);
    }
}

/* The table's columns, as read from one result. */
enum { COL_FIVE_L2, COL_FIVE_MEAN, COL_THICK_L2, COL_THICK_MEAN, COL_SINGLE_L2, COLS };

static void columns(const struct result *x, double v[COLS])
{
    v[COL_FIVE_L2] = x->e[IMG_FIVE].object.rel_l2;
    v[COL_FIVE_MEAN] = x->e[IMG_FIVE].mean_ratio;
    v[COL_THICK_L2] = x->e[IMG_THICKNESS].object.rel_l2;
    v[COL_THICK_MEAN] = x->e[IMG_THICKNESS].mean_ratio;
    v[COL_SINGLE_L2] = x->e[IMG_SINGLE].object.rel_l2;
}

/* One row of medians over the cases lit by `light` (-1: all). */
static void write_median(const struct result *res, int light, const char *label, FILE *md)
{
    double v[COLS][CASES], row[COLS];
    int n = 0;
    for (int i = 0; i < CASES; i++) {
        if (light >= 0 && case_of(i).light != light)
            continue;
        columns(&res[i], row);
        for (int k = 0; k < COLS; k++)
            v[k][n] = row[k];
        n++;
    }
    emit(md, "| **median, %s (%d)** |", label, n);
    for (int k = 0; k < COLS; k++)
        emit(md, " **%.4f** |", bench_median(v[k], n));
    emit(md, "\n");
}

static void write_report(const struct options *o, const struct result *res, const char *device, FILE *md)
{
    char cpu[256];
    cpu_model(cpu, sizeof cpu);
    emit(md, "## Thickness transmission against method \"reference\"\n\n"
             "CPU: %s; device: %s; %dx%d. \"thickness\" = method single plus an engine's thickness transmission "
             "(Jimenez et al. 2010): per pixel facing away from the light, the light entering where a ray toward "
             "it last leaves the mesh, times the dipole integrated over a plane at that depth. The thickness is "
             "ray cast (a perfect shadow map). five = method five (light views). rel L2 over the covered pixels; "
             "mean = mean ratio (test's summed radiance over the reference's). Slab: 50 x 50 x 3 mm, face-on; "
             "rim light 130 degrees from the view direction.\n\n"
             "| case | five rel L2 | five mean | thickness rel L2 | thickness mean | single rel L2 |\n"
             "|---|---|---|---|---|---|\n",
         cpu, device, o->size, o->size);
    for (int i = 0; i < CASES; i++) {
        char label[128];
        double v[COLS];
        case_label(i, label, sizeof label);
        columns(&res[i], v);
        emit(md, "| %s | %.4f | %.4f | %.4f | %.4f | %.4f |\n", label, v[COL_FIVE_L2], v[COL_FIVE_MEAN],
             v[COL_THICK_L2], v[COL_THICK_MEAN], v[COL_SINGLE_L2]);
    }
    write_median(res, -1, "all", md);
    for (int l = 0; l < (int)N(lights); l++)
        write_median(res, l, lights[l].name, md);
}

static int open_outputs(const char *prefix, struct outputs *out)
{
    static const char *const suffix[2] = {".csv", ".md"};
    FILE *f[2] = {NULL, NULL};
    int rc = bench_open_files(prefix, suffix, f, 2);
    out->csv = f[0], out->md = f[1];
    if (rc != 0)
        return -1;
    fprintf(out->csv, "scene,light,material,size,image,pixels,coverage_mismatch,rel_l2,band_rel_l2,noise,"
                      "low_frequency_rel_l2,mean_ratio,ray_coverage_mismatch,term_share\n");
    return 0;
}

/* Closes every output; -1 if any failed to open or write. */
static int close_outputs(struct outputs *out)
{
    FILE *f[2] = {out->csv, out->md};
    return bench_close_files(f, 2);
}

/* Cases run mesh by mesh, so each mesh and its tree are built once. */
static int run(lucent_renderer *r, const struct options *o, struct result *res, const struct outputs *out)
{
    lucent_error err = {0};
    struct geometry geo = {0};
    char device[256] = "";
    int i;
    for (i = 0; i < CASES; i++) {
        lucent_scene s;
        if (case_of(i).light == 0 && case_of(i).material == 0) {
            free_geometry(&geo);
            if (make_scene(o, case_of(i), "\"method\":\"reference\"", &s, &err) != LUCENT_OK || load_geometry(&s.mesh, &geo, &err) != LUCENT_OK)
                goto fail;
        }
        if (run_case(r, o, i, &geo, &res[i], device, sizeof device, &err) != LUCENT_OK)
            goto fail;
        write_csv_rows(out->csv, o->size, i, &res[i]);
        fflush(out->csv);
    }
    free_geometry(&geo);
    write_report(o, res, device, out->md);
    return 0;
fail:
    free_geometry(&geo);
    char label[128];
    case_label(i, label, sizeof label);
    fprintf(stderr, "bench_thickness: %s: %s%s%s\n", label, err.field, err.field[0] ? ": " : "", err.message);
    return -1;
}

int main(int argc, char **argv)
{
    struct options o;
    if (parse_options(argc, argv, &o) != 0)
        return usage();
    if (bench_write_obj(o.prefix, "slab", flat_slab_obj, o.slab_path, sizeof o.slab_path) != 0)
        return 2;
    o.mesh_file[MESH_SLAB] = o.slab_path;
    if (bench_paths_fit(o.mesh_file, MESH_COUNT, "bench_thickness") != 0)
        return 2;
    struct outputs out = {0};
    struct result *res = calloc(CASES, sizeof *res);
    lucent_error err = {0};
    lucent_renderer_desc desc = {.verbose = 0};
    lucent_renderer *r = NULL;
    int rc = 1;
    if (!res)
        fprintf(stderr, "bench_thickness: out of memory\n");
    else if (!(r = lucent_renderer_create(&desc, &err)))
        fprintf(stderr, "bench_thickness: %s\n", err.message);
    else if (open_outputs(o.prefix, &out) == 0 && run(r, &o, res, &out) == 0)
        rc = 0;
    if (close_outputs(&out) != 0 && rc == 0) {
        fprintf(stderr, "bench_thickness: writing %s.* failed\n", o.prefix);
        rc = 1;
    }
    lucent_renderer_destroy(r);
    free(res);
    lucent_shutdown();
    return rc;
}
