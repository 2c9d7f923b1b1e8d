/* test_reference.c - the CPU reference integrator: the diffuse limit on a flat square, the hierarchical
 * sum against brute force, bit-for-bit determinism across thread counts, and the extremes sigma_a = 0, eta = 1. */
#include "dipole.h"
#include "profile.h"
#include "frame_plan.h"
#include "reference.h"
#include "test_support.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define PI 3.14159265358979323846

static void fixture_render(const struct test_fixture *f, const struct reference_options *o, lucent_image *img,
                           struct reference_report *report)
{
    lucent_error err = {0};
    if (reference_render(&f->scene, f->mesh, &f->camera, f->scale_mm, o, 1, img, report, &err) != LUCENT_OK)
        test_die("reference_render", &err);
}

/* (a) A 200 mm square lit head-on is a half-space for every kernel here (marble red, the widest,
 * falls by e^-12 at its edge): the centre must be E Rd_total Ft(1)^2 / pi. The points' spacing is a
 * fraction of z_r = 1 mfp so the quadrature of R_d's peak is good to 0.16% (measured, skin1 red). */
#define SQUARE_TOL 3e-3
static void check_square(const char *square, const char *preset, const char *profile, uint32_t points)
{
    char json[1400];
    snprintf(json, sizeof json,
             "{\"mesh\":{\"file\":\"%s\"},\"scale_mm\":100,\"material\":{\"preset\":\"%s\",\"profile\":\"%s\"},"
             "\"lights\":[{\"type\":\"directional\",\"direction\":[0,0,-1]}],"
             "\"camera\":{\"direction\":[0,0,-1]},\"width\":33,\"height\":33}",
             square, preset, profile);
    struct test_fixture f;
    test_fixture_open(&f, json);
    lucent_image img;
    struct reference_report rep;
    fixture_render(&f, &(struct reference_options){.points = points}, &img, &rep);
    const float *centre = &img.rgba[((size_t)16 * 33 + 16) * 4];
    for (int c = 0; c < 3; c++) {
        const lucent_material *m = &f.scene.material;
        struct profile d;
        profile_init(&d, m->profile, m->sigma_a[c], m->sigma_s_prime[c], m->g, m->eta);
        double ft = fresnel_transmittance(m->eta, 1.0);
        double want = profile_total(&d) * ft * ft * diffuse_exit_weight(m->eta), rel = fabs(centre[c] - want) / want;
        test_check(rel < SQUARE_TOL, "square %-7s %-13s ch%d: centre %.6g, analytic %.6g, rel.err %.2e (tol %.0e; "
                               "%u points, spacing %.3f mm, mfp %.3f mm, estimated %.1e, %.0f + %.0f ms)",
                   preset, profile, c, centre[c], want, rel, SQUARE_TOL, rep.points, rep.point_spacing_mm,
                   1.0 / d.sigma_t_prime, rep.estimated_rel_error, rep.ms_points, rep.ms_pixels);
    }
    lucent_image_free(&img);
    lucent_mesh_free(f.mesh);
}

/* ||a - b|| / ||b|| over the RGB of pixels covered in b; -1 when coverage differs. */
static double rel_l2(const lucent_image *a, const lucent_image *b)
{
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
        if (a->rgba[i * 4 + 3] != b->rgba[i * 4 + 3])
            return -1.0;
        for (int c = 0; c < 3; c++) {
            double d = (double)a->rgba[i * 4 + c] - b->rgba[i * 4 + c];
            num += d * d;
            den += (double)b->rgba[i * 4 + c] * b->rgba[i * 4 + c];
        }
    }
    return den > 0.0 ? sqrt(num / den) : -1.0;
}

/* (b) The hierarchical sum (default threshold) against every point summed, with the same points. */
/* Measured: 0.036-0.12% (the README's "within 0.12%"). */
#define HIERARCHY_TOL 2e-3
static void check_hierarchy(const char *mesh, const char *preset, int side, uint32_t points, double tolerance)
{
    char json[600];
    snprintf(json, sizeof json,
             "{\"mesh\":{\"builtin\":\"%s\"},\"material\":{\"preset\":\"%s\"},"
             "\"lights\":[{\"direction\":[-1,0,0]}],\"camera\":{\"direction\":[0,0,-1]},\"width\":%d,\"height\":%d}",
             mesh, preset, side, side);
    struct test_fixture f;
    test_fixture_open(&f, json);
    lucent_image brute, tree;
    struct reference_report rb, rt;
    fixture_render(&f, &(struct reference_options){.points = points, .brute_force = 1}, &brute, &rb);
    fixture_render(&f, &(struct reference_options){.points = points}, &tree, &rt);
    double err = rel_l2(&tree, &brute);
    test_check(err >= 0.0 && err < tolerance,
               "%-10s %-7s %dx%d, %u points: hierarchical (threshold %.2f) vs brute force rel.L2 %.2e "
               "(tol %.0e; estimated total error %.1e); brute %.0f + %.0f ms, hierarchical %.0f + %.0f ms",
               mesh, preset, side, side, points, rt.threshold, err, tolerance, rt.estimated_rel_error,
               rb.ms_points, rb.ms_pixels, rt.ms_points, rt.ms_pixels);
    lucent_image_free(&brute);
    lucent_image_free(&tree);
    lucent_mesh_free(f.mesh);
}

static int same_image(const lucent_image *a, const lucent_image *b)
{
    size_t n = (size_t)a->width * a->height;
    return memcmp(a->rgba, b->rgba, n * 4 * sizeof(float)) == 0 && memcmp(a->depth, b->depth, n * sizeof(float)) == 0 &&
           memcmp(a->normal, b->normal, n * 3 * sizeof(float)) == 0 && memcmp(a->view, b->view, n * sizeof(float)) == 0;
}

/* (c) The same frame with one and two threads, twice, must not differ in a single bit. */
static void check_determinism(void)
{
    struct test_fixture f;
    test_fixture_open(&f, "{\"mesh\":{\"builtin\":\"protrusion\"},\"material\":{\"preset\":\"skin1\"},"
                     "\"lights\":[{\"direction\":[-1,-0.3,-0.5]}],"
                     "\"camera\":{\"direction\":[0,0,-1]},\"width\":32,\"height\":32}");
    lucent_image a, b, c;
    struct reference_report rep;
    fixture_render(&f, &(struct reference_options){.points = 30000, .threads = 2}, &a, &rep);
    fixture_render(&f, &(struct reference_options){.points = 30000, .threads = 2}, &b, &rep);
    fixture_render(&f, &(struct reference_options){.points = 30000, .threads = 1}, &c, &rep);
    test_check(same_image(&a, &b) && same_image(&a, &c),
               "protrusion skin1 32x32: two 2-thread renders and a 1-thread render identical bit for bit");
    lucent_image_free(&a);
    lucent_image_free(&b);
    lucent_image_free(&c);
    lucent_mesh_free(f.mesh);
}

/* (d) sigma_a = 0 makes sigma_tr = 0 (R_d ~ 1/r^3, no exponential decay) and eta = 1 removes the
 * boundary's reflection: the image must stay finite, and lit pixels positive. Spectralon's mean free
 * path (0.05 mm) is below what the automatic point cap resolves at this scale; the report says so. */
static void check_extreme(const char *material)
{
    char json[600];
    snprintf(json, sizeof json,
             "{\"mesh\":{\"builtin\":\"sphere\"},\"material\":%s,\"lights\":[{\"direction\":[0,0,-1]}],"
             "\"camera\":{\"direction\":[0,0,-1]},\"width\":24,\"height\":24}",
             material);
    struct test_fixture f;
    test_fixture_open(&f, json);
    lucent_image img;
    struct reference_report rep;
    fixture_render(&f, &(struct reference_options){0}, &img, &rep);
    int finite = 1;
    double peak = 0.0;
    for (size_t i = 0; i < (size_t)img.width * img.height; i++)
        for (int c = 0; c < 3; c++) {
            finite &= isfinite(img.rgba[i * 4 + c]) != 0;
            peak = fmax(peak, img.rgba[i * 4 + c]);
        }
    const float *centre = &img.rgba[((size_t)12 * 24 + 12) * 4];
    test_check(finite && centre[0] > 0.0f && centre[1] > 0.0f && centre[2] > 0.0f,
               "sphere %s: finite, centre (%.4g, %.4g, %.4g), peak %.4g (automatic %u points, spacing %.3f mm "
               "vs mfp %.3f mm: estimated error %.1e)",
               material, centre[0], centre[1], centre[2], peak, rep.points, rep.point_spacing_mm,
               rep.min_mean_free_path_mm, rep.estimated_rel_error);
    lucent_image_free(&img);
    lucent_mesh_free(f.mesh);
}

/* Bad requests fail with a status and a message, and leave nothing allocated. */
static void check_rejects(void)
{
    struct test_fixture f;
    test_fixture_open(&f, "{\"mesh\":{\"builtin\":\"sphere\"},\"camera\":{\"direction\":[0,0,-1]},\"width\":8,\"height\":8}");
    lucent_image img;
    struct reference_report rep;
    lucent_error err = {0};
    lucent_status st = reference_render(&f.scene, f.mesh, &f.camera, f.scale_mm,
                                        &(struct reference_options){.points = LUCENT_MAX_REFERENCE_POINTS + 1}, 1,
                                        &img, &rep, &err);
    test_check(st == LUCENT_E_LIMIT && img.rgba == NULL, "too many points: %s (%s)", lucent_status_name(st),
               err.message);
    f.scene.width = 0;
    st = reference_render(&f.scene, f.mesh, &f.camera, f.scale_mm, &(struct reference_options){0}, 1, &img, &rep,
                          &err);
    test_check(st == LUCENT_E_LIMIT && img.rgba == NULL, "width 0: %s (%s)", lucent_status_name(st), err.message);
    lucent_mesh_free(f.mesh);
}

static double seconds_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

struct canceller {
    lucent_renderer *renderer;
    long delay_ms;
    double cancelled_at;
};

static void *cancel_later(void *arg)
{
    struct canceller *c = arg;
    nanosleep(&(struct timespec){c->delay_ms / 1000, c->delay_ms % 1000 * 1000000L}, NULL);
    c->cancelled_at = seconds_now();
    lucent_render_cancel(c->renderer);
    return NULL;
}

/* Every phase of the reference is cancellable within a chunk (1024 points or one row): cancelled
 * while it places points (0.2 s in) and while it shades rows (1.5 s in), a 512x512 render that
 * takes ~10 s returns CANCELLED. The time from the cancel to the return is printed; its bound is
 * generous because the machine is shared (measured: 0.004 and 0.11 s). */
#define CANCEL_LATENCY_BOUND 3.0
static void check_cancel(void)
{
    lucent_renderer *r = test_renderer();
    const char *json = "{\"mesh\":{\"builtin\":\"sphere\"},"
        "\"camera\":{\"direction\":[0,0,-1]},\"width\":512,\"height\":512,\"method\":\"reference\"}";
    lucent_scene scene;
    lucent_scene_parse(json, strlen(json), 0, &scene, NULL);
    const long delays_ms[] = {200, 1500};
    for (int i = 0; i < 2; i++) {
        lucent_image img = {0};
        lucent_error err = {0};
        lucent_stats stats;
        pthread_t thread;
        struct canceller c = {.renderer = r, .delay_ms = delays_ms[i]};
        pthread_create(&thread, NULL, cancel_later, &c);
        lucent_status st = lucent_render(r, &scene, &img, &stats, &err);
        double returned = seconds_now();
        pthread_join(thread, NULL);
        double latency = returned - c.cancelled_at;
        test_check(st == LUCENT_E_CANCELLED && latency < CANCEL_LATENCY_BOUND,
                   "512x512 reference cancelled after %.1f s: status %s, returned %.3f s after the cancel (bound %.0f s): %s",
                   delays_ms[i] / 1000.0, lucent_status_name(st), latency, CANCEL_LATENCY_BOUND, err.message);
        lucent_image_free(&img);
    }
    lucent_image img = {0};
    lucent_error err = {0};
    scene.width = scene.height = 32;
    lucent_status st = lucent_render(r, &scene, &img, NULL, &err);
    test_check(st == LUCENT_OK, "the next render is not cancelled: status %s", lucent_status_name(st));
    lucent_image_free(&img);
    lucent_renderer_destroy(r);
}

int main(void)
{
    const char *square = test_write_square_obj();
    check_square(square, "marble", "dipole", 2000000);
    check_square(square, "skin1", "dipole", 2000000);
    /* normalized diffusion's 1/r peak at the exit point through the near disc (the better dipole's sum is
     * the classic one's code; test profiles checks its closed forms) */
    check_square(square, "skin1", "burley", 2000000);
    const char *meshes[] = {"sphere", "protrusion"}, *presets[] = {"marble", "ketchup"};
    for (int m = 0; m < 2; m++)
        for (int p = 0; p < 2; p++)
            check_hierarchy(meshes[m], presets[p], 32, 30000, HIERARCHY_TOL);
    check_determinism();
    check_extreme("{\"preset\":\"spectralon\"}");
    check_extreme("{\"sigma_a\":[0.0021,0.0041,0.0071],\"sigma_s_prime\":[2.19,2.62,3.0],\"eta\":1}");
    check_rejects();
    check_cancel();
    unlink(square);
    return test_finish();
}
