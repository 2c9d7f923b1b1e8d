/* test_path.c - method "path" (random walks in the medium) against radiative transfer's exact half-space
 * answers (Chandrasekhar's H-function for isotropic scattering, index-matched boundary), for both boundary
 * conventions; its own noise estimate against the error it makes; determinism; cancel and time budget; the
 * profiles' diffuse exit against the walks on a half-space; Cycles' shading-normal correction at grazing views;
 * the box pixel filter's coverage. */
#include "frame_plan.h"
#include "half_space.h"
#include "path.h"
#include "test_support.h"
#include "valid_reflection.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PI 3.14159265358979323846

static lucent_status fixture_render(const struct test_fixture *f, const struct path_options *o, lucent_image *img,
                                    struct path_report *report, lucent_error *err)
{
    return path_render(&f->scene, f->mesh, &f->camera, f->scale_mm, o, 1, img, report, err);
}

/* A 200 mm square of index-matched medium (eta 1, g 0) seen and lit straight down, one pixel: mean free path
 * 1 mm, albedos 0.5, 0.9 and 0.99 in the three channels. The walk from the eye estimates, by reciprocity,
 * the share of light entering (collimated for "fresnel", whose camera ray refracts straight in; diffusely
 * for "cycles") that comes back out, times E / pi. */
static void check_half_space(const char *square, const char *boundary, uint32_t samples)
{
    const double w[3] = {0.5, 0.9, 0.99};
    char json[1024];
    snprintf(json, sizeof json,
             "{\"mesh\":{\"file\":\"%s\"},\"scale_mm\":100,\"width\":1,\"height\":1,\"method\":\"path\","
             "\"material\":{\"sigma_a\":[%.17g,%.17g,%.17g],\"sigma_s_prime\":[%.17g,%.17g,%.17g],\"eta\":1},"
             "\"camera\":{\"direction\":[0,0,-1]},\"lights\":[{\"direction\":[0,0,-1]}],"
             "\"path\":{\"boundary\":\"%s\"}}",
             square, 1.0 - w[0], 1.0 - w[1], 1.0 - w[2], w[0], w[1], w[2], boundary);
    struct test_fixture f;
    test_fixture_open(&f, json);
    struct path_options o = {.samples = samples, .boundary = f.scene.path_boundary, .seed = 1};
    lucent_image img;
    struct path_report report;
    lucent_error err = {0};
    if (fixture_render(&f, &o, &img, &report, &err) != LUCENT_OK)
        test_die("path_render", &err);
    int ok = img.rgba[3] == 1.0f;
    double worst = 0.0;
    for (int c = 0; c < 3; c++) {
        double normal, diffuse;
        half_space_albedo(w[c], &normal, &diffuse);
        double expect = (strcmp(boundary, "cycles") == 0 ? diffuse : normal) / PI, got = img.rgba[c];
        /* a channel's standard error: the image's relative one is over all three, so bound it by the channel */
        double sigma = report.rel_std_error * sqrt(img.rgba[0] * img.rgba[0] + img.rgba[1] * img.rgba[1] +
                                                   img.rgba[2] * img.rgba[2]);
        double z = fabs(got - expect) / sigma;
        worst = fmax(worst, z);
        ok = ok && fabs(got - expect) <= 4.0 * sigma + 2e-3 * expect;
        printf("     %s, albedo %.2f: %.5f against %.5f (H-function), %.2f standard errors\n", boundary, w[c], got,
               expect, z);
    }
    test_check(ok, "%s boundary, half-space albedos 0.5/0.9/0.99 from %u walks a channel: within 4 standard "
               "errors + 0.2%% (worst %.2f; image's own relative standard error %.4f), %.1f steps a walk, %.0f ms",
               boundary, samples, worst, report.rel_std_error, report.mean_steps, report.ms);
    lucent_image_free(&img);
    lucent_mesh_free(f.mesh);
}

/* The same image twice, and on one thread against two: identical bytes (seeds per pixel, pass, channel). */
static void check_determinism(void)
{
    struct test_fixture f;
    test_fixture_open(&f, "{\"mesh\":{\"builtin\":\"protrusion\"},\"width\":24,\"height\":20,\"method\":\"path\","
                     "\"material\":{\"preset\":\"skin1\"},\"lights\":[{\"direction\":[-1,0,-0.5]}]}");
    lucent_image a, b, c;
    struct path_report ra, rb, rc;
    lucent_error err = {0};
    struct path_options o = {.samples = 2, .threads = 1};
    if (fixture_render(&f, &o, &a, &ra, &err) || fixture_render(&f, &o, &b, &rb, &err))
        test_die("path_render", &err);
    o.threads = 2;
    if (fixture_render(&f, &o, &c, &rc, &err))
        test_die("path_render", &err);
    size_t bytes = (size_t)a.width * a.height * 4 * sizeof(float);
    int finite = 1, lit = 0;
    for (size_t i = 0; i < (size_t)a.width * a.height * 4; i++) {
        finite = finite && isfinite(a.rgba[i]) && a.rgba[i] >= 0.0f;
        lit += i % 4 == 0 && a.rgba[i] > 0.0f;
    }
    test_check(memcmp(a.rgba, b.rgba, bytes) == 0 && memcmp(a.rgba, c.rgba, bytes) == 0 && finite && lit > 30,
               "skin protrusion: two renders and one on two threads byte-identical, every value finite and >= 0, "
               "%d pixels lit, %.1f steps a walk", lit, ra.mean_steps);
    o.seed = 99;
    lucent_image d;
    if (fixture_render(&f, &o, &d, &rc, &err))
        test_die("path_render", &err);
    test_check(memcmp(a.rgba, d.rgba, bytes) != 0, "another seed, other noise");
    lucent_image_free(&a);
    lucent_image_free(&b);
    lucent_image_free(&c);
    lucent_image_free(&d);
    lucent_mesh_free(f.mesh);
}

/* A cancel stops it with LUCENT_E_CANCELLED; a time budget ends it after the pass that exceeds it. */
static void check_cancel_and_budget(void)
{
    struct test_fixture f;
    test_fixture_open(&f, "{\"mesh\":{\"builtin\":\"sphere\"},\"width\":32,\"height\":32,\"method\":\"path\"}");
    atomic_int cancel = 1;
    struct path_options o = {.samples = 1000, .cancel = &cancel};
    lucent_image img;
    struct path_report report;
    lucent_error err = {0};
    lucent_status st = fixture_render(&f, &o, &img, &report, &err);
    test_check(st == LUCENT_E_CANCELLED && img.rgba == NULL, "cancelled: %s, no image", lucent_status_name(st));
    o.cancel = NULL;
    o.time_s = 1e-6;
    st = fixture_render(&f, &o, &img, &report, &err);
    test_check(st == LUCENT_OK && report.samples == 2, "time budget 1 us: one batch, %u passes of the 1000 asked (%s)",
               report.samples, lucent_status_name(st));
    if (st == LUCENT_OK)
        lucent_image_free(&img);
    o.time_s = NAN;
    st = fixture_render(&f, &o, &img, &report, &err);
    test_check(st == LUCENT_E_LIMIT && strcmp(err.field, "path.time_s") == 0, "time budget NaN refused: [%s] %s",
               err.field, err.message);
    lucent_mesh_free(f.mesh);
}

static double seconds_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void *cancel_soon(void *arg)
{
    nanosleep(&(struct timespec){0, 300000000L}, NULL);
    atomic_store((atomic_int *)arg, 1);
    return NULL;
}

/* A white medium 100 m across with a 1 mm mean free path, 65536 walks a pixel and channel: hours of walks,
 * whose longest ones run to millions of steps. A cancel 0.3 s in returns within a few seconds. (Walks also
 * look at the flag every 65536 steps, for a walk that alone would outlast a deadline; which walk that is
 * is up to chance, so no test can pin it.) */
static void check_cancel_mid_walk(void)
{
    struct test_fixture f;
    test_fixture_open(&f, "{\"mesh\":{\"builtin\":\"sphere\"},\"scale_mm\":100000,\"width\":32,\"height\":32,"
                          "\"method\":\"path\",\"material\":{\"sigma_a\":[0,0,0],\"sigma_s_prime\":[1,1,1]}}");
    atomic_int cancel = 0;
    struct path_options o = {.samples = LUCENT_MAX_PATH_SAMPLES, .cancel = &cancel};
    lucent_image img;
    struct path_report report;
    lucent_error err = {0};
    pthread_t tid;
    double t0 = seconds_now();
    int started = pthread_create(&tid, NULL, cancel_soon, &cancel) == 0;
    lucent_status st = path_render(&f.scene, f.mesh, &f.camera, f.scale_mm, &o, 0, &img, &report, &err);
    double took = seconds_now() - t0;
    if (started)
        pthread_join(tid, NULL);
    test_check(started && st == LUCENT_E_CANCELLED && took < 5.0,
               "hours of walks (white medium 10^5 mean free paths across) cancelled 0.3 s in: %s after %.2f s (< 5)",
               lucent_status_name(st), took);
    if (st == LUCENT_OK)
        lucent_image_free(&img);
    lucent_mesh_free(f.mesh);
}

/* The scene `base` (a JSON object left open after a comma) by method reference, then by path with `walks`. */
static void render_reference_and_path(lucent_renderer *r, const char *base, const char *walks, lucent_image *ref,
                                      lucent_image *path, lucent_stats *st_path)
{
    char json[1600];
    lucent_stats st_ref;
    snprintf(json, sizeof json, "%s\"method\":\"reference\"}", base);
    test_render(r, json, ref, &st_ref);
    snprintf(json, sizeof json, "%s\"method\":\"path\",\"path\":{%s}}", base, walks);
    test_render(r, json, path, st_path);
}

/* The walks against the dipole's ground truth on the side-lit marble sphere: the same object, brighter
 * (the dipole's semi-infinite flat medium misses light that comes round), never wildly apart. */
static void check_against_dipole(lucent_renderer *r)
{
    const char *base = "{\"mesh\":{\"builtin\":\"sphere\"},\"material\":{\"preset\":\"marble\"},\"width\":32,"
                       "\"height\":32,\"format\":\"exr\",\"camera\":{\"direction\":[0,0,-1]},"
                       "\"lights\":[{\"direction\":[-1,0,-0.3],\"intensity\":3}],";
    lucent_image ref, path;
    lucent_stats st_path;
    render_reference_and_path(r, base, "\"samples\":16", &ref, &path, &st_path);
    lucent_image_error e;
    lucent_error err = {0};
    if (lucent_image_compare(&path, &ref, &e, &err) != LUCENT_OK)
        test_die("compare", &err);
    test_check(e.mean_ratio > 0.9 && e.mean_ratio < 1.6 && e.coverage_mismatch == 0 &&
                   strstr(st_path.modelled, "\"rel_std_error\"") && strstr(st_path.modelled, "\"boundary\":\"fresnel\""),
               "marble sphere, side light: path / dipole reference mean ratio %.3f (0.9..1.6), rel L2 %.3f, "
               "coverage equal; modelled %s", e.mean_ratio, e.object.rel_l2, st_path.modelled);
    lucent_image_free(&ref);
    lucent_image_free(&path);
}

/* The diffuse exit against the walks: a 200 mm square of marble (eta 1.5) and of skim milk (eta 1.3), lit and
 * seen head-on, one pixel. The profiles give the light leaving the surface; spread as Ft / (pi Ft_diffuse) the
 * dipole's reference meets the walks within diffusion's own error here (measured 3.2% at most, skim milk's
 * blue), where Jensen et al.'s Ft / pi kept only Ft_diffuse of it (0.89-0.93 of the walks). */
#define EXIT_TOL 0.05
static void check_exit_against_walks(lucent_renderer *r, const char *square)
{
    const char *presets[] = {"marble", "skimmilk"};
    for (int i = 0; i < 2; i++) {
        char base[1400];
        snprintf(base, sizeof base,
                 "{\"mesh\":{\"file\":\"%s\"},\"scale_mm\":100,\"width\":1,\"height\":1,\"format\":\"exr\","
                 "\"material\":{\"preset\":\"%s\"},\"camera\":{\"direction\":[0,0,-1]},"
                 "\"lights\":[{\"direction\":[0,0,-1]}],", square, presets[i]);
        lucent_image ref, walks;
        lucent_stats st_walks;
        render_reference_and_path(r, base, "\"samples\":12000,\"seed\":1", &ref, &walks, &st_walks);
        const char *at = strstr(st_walks.modelled, "\"rel_std_error\":");
        double noise = NAN, worst = 0.0;
        if (at)
            sscanf(at + strlen("\"rel_std_error\":"), "%lf", &noise);
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(ref.rgba[c] / walks.rgba[c] - 1.0));
        test_check(worst < EXIT_TOL && noise < EXIT_TOL / 4.0,
                   "%-8s half-space head-on: dipole reference / path %.4f %.4f %.4f, worst %.4f off (tol %.3g; the "
                   "walks' relative standard error %.4f)", presets[i], ref.rgba[0] / walks.rgba[0],
                   ref.rgba[1] / walks.rgba[1], ref.rgba[2] / walks.rgba[2], worst, EXIT_TOL, noise);
        lucent_image_free(&ref);
        lucent_image_free(&walks);
    }
}

/* Cycles' correction (boundary "cycles"): a normal whose mirror image of the view clears the surface is kept;
 * else the result is the unit normal in the plane of n and g, turned towards g, whose mirror image sits
 * exactly at the threshold min(0.9 g.i, 0.01). 2000 grazing views of normals leaning up to 30 degrees. */
static void check_valid_reflection(void)
{
    const double g[3] = {0.0, 0.0, 1.0};
    double worst_unit = 0.0, worst_plane = 0.0, worst_level = 0.0, out[3];
    int kept = 0, turned = 0, wrong_way = 0, changed_valid = 0;
    uint64_t state = 12345;
    for (int k = 0; k < 2000; k++) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        double u1 = (double)(state >> 11) * 0x1.0p-53;
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        double u2 = (double)(state >> 11) * 0x1.0p-53;
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        double u3 = (double)(state >> 11) * 0x1.0p-53;
        double lean = u1 * 30.0 * PI / 180.0, view = (0.05 + 89.8 * u2) * PI / 180.0, phi = 2.0 * PI * u3;
        double n[3] = {sin(lean), 0.0, cos(lean)};              /* leans towards +x */
        double i[3] = {cos(view) * cos(phi), cos(view) * sin(phi), sin(view)};   /* view above the surface */
        valid_reflection_normal(g, i, n, out);
        double threshold = fmin(0.9 * i[2], 0.01);
        double before = 2.0 * (n[0] * i[0] + n[1] * i[1] + n[2] * i[2]) * n[2] - i[2];
        double on = out[0] * i[0] + out[1] * i[1] + out[2] * i[2], after = 2.0 * on * out[2] - i[2];
        if (before >= threshold) {
            kept++;
            changed_valid += out[0] != n[0] || out[1] != n[1] || out[2] != n[2];
            continue;
        }
        turned++;
        worst_unit = fmax(worst_unit, fabs(sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]) - 1.0));
        worst_plane = fmax(worst_plane, fabs(out[1]));            /* the plane of n and g is y = 0 */
        worst_level = fmax(worst_level, fabs(after - threshold));
        wrong_way += out[2] < n[2] - 1e-12;
    }
    printf("valid reflection: %d kept, %d turned; worst |len - 1| %.2g, off-plane %.2g, |R.g - threshold| %.2g\n",
           kept, turned, worst_unit, worst_plane, worst_level);
    test_check(kept > 100 && turned > 100, "both cases drawn (%d kept, %d turned)", kept, turned);
    test_check(changed_valid == 0, "a valid normal is returned unchanged (%d changed)", changed_valid);
    test_check(worst_unit < 1e-9 && worst_plane < 1e-12, "turned normals are unit and in the plane of n and g");
    test_check(worst_level < 1e-6, "the view's mirror image sits at the threshold (worst %.2g)", worst_level);
    test_check(wrong_way == 0, "normals turn towards g (%d turned away)", wrong_way);
}

/* Box filter: a pixel's coverage is the share of it the mesh covers, against the point filter's coverage at 8 x 8
 * times the resolution, over the pixels a slanted square's edges cross; radiance premultiplied (a miss adds 0). */
static void check_box_filter(const char *square)
{
    const int side = 16, fine = 8;
    char json[2048];
    lucent_image img[2];
    for (int k = 0; k < 2; k++) {
        snprintf(json, sizeof json,
                 "{\"mesh\":{\"file\":\"%s\"},\"scale_mm\":100,\"width\":%d,\"height\":%d,\"method\":\"path\","
                 "\"material\":{\"sigma_a\":[5,5,5],\"sigma_s_prime\":[0.5,0.5,0.5],\"eta\":1},"
                 "\"camera\":{\"direction\":[0.35,0.2,-1]},\"lights\":[{\"direction\":[0,0,-1]}],"
                 "\"path\":{\"boundary\":\"cycles\",\"filter\":\"%s\"}}",
                 square, k ? side * fine : side, k ? side * fine : side, k ? "point" : "box");
        struct test_fixture f;
        test_fixture_open(&f, json);
        struct path_options o = {.samples = k ? 1 : 256, .boundary = f.scene.path_boundary,
                                 .filter = f.scene.path_filter, .seed = 3};
        struct path_report report;
        lucent_error err = {0};
        if (fixture_render(&f, &o, &img[k], &report, &err) != LUCENT_OK)
            test_die("path_render", &err);
        lucent_mesh_free(f.mesh);
    }
    int edge = 0, wrong_premultiplied = 0;
    double worst = 0.0, box_sum = 0.0, fine_sum = 0.0;
    for (int y = 0; y < side; y++)
        for (int x = 0; x < side; x++) {
            int hit = 0;
            for (int v = 0; v < fine; v++)
                for (int u = 0; u < fine; u++)
                    hit += img[1].rgba[((size_t)(y * fine + v) * side * fine + x * fine + u) * 4 + 3] > 0.0f;
            double share = (double)hit / (fine * fine), alpha = img[0].rgba[((size_t)y * side + x) * 4 + 3];
            box_sum += alpha;
            fine_sum += share;
            if (hit > 0 && hit < fine * fine) {
                edge++;
                worst = fmax(worst, fabs(alpha - share));
            }
            /* light only where it hit: black where nothing was */
            wrong_premultiplied += alpha == 0.0f && img[0].rgba[((size_t)y * side + x) * 4] != 0.0f;
        }
    printf("     box filter: %d edge pixels, worst |coverage - 8x8 share| %.3f, coverage summed %.2f against %.2f\n",
           edge, worst, box_sum, fine_sum);
    /* 256 passes: a coverage's standard error is at most 0.031; the 8 x 8 share is within 1/8 along an edge */
    test_check(edge >= 8 && worst < 0.2 && fabs(box_sum - fine_sum) < 0.01 * fine_sum + 1.0 && !wrong_premultiplied,
               "box filter: coverage is the share of the pixel hit (%d edge pixels, worst %.3f; summed %.2f vs %.2f)",
               edge, worst, box_sum, fine_sum);
    lucent_image_free(&img[0]);
    lucent_image_free(&img[1]);
}

int main(void)
{
    char square[1024];
    snprintf(square, sizeof square, "%s", test_write_square_obj());
    check_valid_reflection();
    check_half_space(square, "fresnel", 40000);
    check_half_space(square, "cycles", 40000);
    check_box_filter(square);
    check_determinism();
    check_cancel_and_budget();
    check_cancel_mid_walk();
    lucent_renderer *r = test_renderer();
    check_against_dipole(r);
    check_exit_against_walks(r, square);
    lucent_renderer_destroy(r);
    remove(square);
    return test_finish();
}
