/* test_render_modelled.c - what the renderer chooses to model, and that each choice shows in the image:
 * shadow maps and their skip rules, self-shadowing, method auto's choices, the paper's front fallback,
 * the point light's 1/d^2 falloff and the far annulus's block size, each against what `modelled`
 * reports or a closed form. */
#include "dipole.h"
#include "profile.h"
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PI 3.14159265358979323846

/* The number after "key": in a modelled report; NAN when absent. */
static double report_number(const char *modelled, const char *key)
{
    char pattern[64];
    snprintf(pattern, sizeof pattern, "\"%s\":", key);
    const char *at = strstr(modelled, pattern);
    double v = NAN;
    return at && sscanf(at + strlen(pattern), "%lf", &v) == 1 ? v : NAN;
}

static const float *pixel(const lucent_image *img, int x, int y)
{
    return &img->rgba[((size_t)y * img->width + x) * 4];
}

/* The array `key` of modelled (e.g. "\"shadows\":") names `phrase` in one of its entries; *at: the
 * array, for the message (NULL when modelled has no such key). */
static int reports(const char *modelled, const char *key, const char *phrase, const char **at)
{
    const char *array = strstr(modelled, key), *found = array ? strstr(array, phrase) : NULL;
    *at = array;
    return found && found < strstr(array, "]");
}

/* ---- shadow maps: which lights get one, as reported ---- */

static void check_shadow_rule(lucent_renderer *r, const char *mesh, const char *lights, int maps, const char *reason)
{
    char json[600];
    snprintf(json, sizeof json, "{\"mesh\":{\"builtin\":\"%s\"},\"lights\":[%s],"
             "\"camera\":{\"direction\":[0,0,-1]},\"width\":16,\"height\":16}", mesh,
             lights);
    lucent_image img;
    lucent_stats stats;
    test_render(r, json, &img, &stats);
    const char *shadows;
    int said = reports(stats.modelled, "\"shadows\":", reason, &shadows);
    test_check(stats.shadow_maps == maps && said, "%-10s lights %s: %d shadow maps (expected %d), reported %.90s",
               mesh, lights, stats.shadow_maps, maps, shadows ? shadows : "(no shadows key)");
    lucent_image_free(&img);
}

/* ---- transmission: which lights get a light view, as reported ---- */

/* mesh: a mesh object; views: what stats.views must be (5 camera views plus the light views); reason:
 * a phrase of modelled.transmission. */
static void check_light_views(lucent_renderer *r, const char *mesh, const char *method, const char *lights, int views,
                              const char *reason)
{
    char json[700];
    snprintf(json, sizeof json, "{\"mesh\":%s,\"method\":\"%s\",\"lights\":[%s],"
             "\"camera\":{\"direction\":[0,0,-1]},\"width\":32,\"height\":32}", mesh,
             method, lights);
    lucent_image img;
    lucent_stats stats;
    test_render(r, json, &img, &stats);
    const char *through;
    int said = reports(stats.modelled, "\"transmission\":", reason, &through);
    test_check(stats.views == views && said, "%.40s %-6s lights %s: %d views (expected %d), reported %.110s", mesh,
               method, lights, stats.views, views, through ? through : "(no transmission key)");
    lucent_image_free(&img);
}

/* An open sheet (the square, normal towards the camera) lit from behind: the reference lights the side
 * its normals give, so it is black; a light view sees the sheet's back, which it must not light. */
static void check_sheet_from_behind(lucent_renderer *r, const char *sheet)
{
    char json[400];
    snprintf(json, sizeof json, "{\"mesh\":%s,\"lights\":[{\"direction\":[0,0,1]}],"
             "\"camera\":{\"direction\":[0,0,-1]},\"width\":32,\"height\":32}",
             sheet);
    lucent_image img;
    lucent_stats stats;
    test_render(r, json, &img, &stats);
    float peak = 0.0f;
    for (size_t i = 0; i < (size_t)img.width * img.height; i++)
        for (int c = 0; c < 3; c++)
            peak = fmaxf(peak, img.rgba[i * 4 + c]);
    test_check(peak == 0.0f && stats.views == 6, "open sheet lit from behind, five: peak radiance %g (expected 0), %d views",
               peak, stats.views);
    lucent_image_free(&img);
}

/* ---- self-shadowing: a shelf over a floor ---- */

/* Floor [-1,1]^2 at z = 0 and a shelf x in [0.1, 0.6] at z = 0.5, both facing +z. Light travelling
 * along (-1, 0, -1) puts the shelf's shadow on the floor at x in [-0.4, 0.1]. */
static const char *write_shelf_obj(void)
{
    static char path[64];
    test_write_obj(path, sizeof path, "shelf",
                   "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                   "v 0.1 -1 0.5\nv 0.6 -1 0.5\nv 0.6 1 0.5\nv 0.1 1 0.5\nvn 0 0 1\n"
                   "f 1//1 2//1 3//1\nf 1//1 3//1 4//1\nf 5//1 6//1 7//1\nf 5//1 7//1 8//1\n");
    return path;
}

/* Camera at z = 5 looking down -z, 40 degrees: a floor point x maps to column W/2 (1 + x / 1.82). */
static int floor_column(double x, int width)
{
    return (int)lround(width / 2.0 * (1.0 + x / (5.0 * tan(20.0 * PI / 180.0))) - 0.5);
}

/* Measured: shadowed/lit 0 in every method (skin1's kernel is ~1/20 of the shadow's half width). */
#define SHADOW_RATIO_BOUND 0.02
/* Lit floor against E cos45 Rd Ft^2 / pi: measured 8.2e-3 (every method). */
#define LIT_TOL 0.015

static void check_self_shadow(lucent_renderer *r, const char *shelf)
{
    static const char *const methods[] = {"five", "single", "auto", "reference"};
    const int side = 64;
    int in_shadow = floor_column(-0.15, side), lit = floor_column(-0.7, side), row = side / 2;
    lucent_material m;
    lucent_material_preset("skin1", &m);
    double ft = fresnel_transmittance(m.eta, 1.0), cos_i = sqrt(0.5);
    for (int k = 0; k < 4; k++) {
        char json[700];
        snprintf(json, sizeof json,
                 "{\"mesh\":{\"file\":\"%s\"},\"scale_mm\":100,\"material\":{\"preset\":\"skin1\"},"
                 "\"lights\":[{\"direction\":[-1,0,-1]}],\"camera\":{\"position\":[0,0,5],\"target\":[0,0,0]},"
                 "\"width\":%d,\"height\":%d,\"method\":\"%s\"}",
                 shelf, side, side, methods[k]);
        lucent_image img;
        lucent_stats stats;
        test_render(r, json, &img, &stats);
        double dark = test_luminance(pixel(&img, in_shadow, row)), bright = test_luminance(pixel(&img, lit, row));
        double got_red = pixel(&img, lit, row)[0];
        double want = cos_i * test_profile_total(&m, test_reported_profile(&stats), 0) * ft * ft * diffuse_exit_weight(m.eta);
        double rel = fabs(got_red - want) / want;
        int mapped = k == 3 || stats.shadow_maps == 1;
        test_check(mapped && bright > 0.0 && dark <= SHADOW_RATIO_BOUND * bright && rel < LIT_TOL,
                   "shelf over a floor, %-9s: shadowed floor (column %d) %.4g vs lit floor (column %d) %.4g, ratio %.3g "
                   "(bound %.2g); lit red %.5g vs E cos Rd Ft^2 / (pi Ft_diffuse) %.5g (rel.err %.2e, tol %.2g); %d shadow maps",
                   methods[k], in_shadow, dark, lit, bright, dark / bright, SHADOW_RATIO_BOUND, got_red, want, rel,
                   LIT_TOL, stats.shadow_maps);
        lucent_image_free(&img);
    }
}

/* ---- point light: irradiance I cos / d^2 ---- */

/* At 1e6 mm per unit every kernel is far below a texel: the centre is the diffuse limit of the
 * point's own irradiance. Measured: five 2.9e-4, reference 4.1e-5. Method auto sums the diffuse
 * limit from the nearest texel, up to half a texel from the point: under the oblique light (a 75%
 * per unit gradient, 64^2 projection) that is 1.7% measured, allowed 3%. */
#define FALLOFF_TOL 1e-3
#define FALLOFF_NEAREST_TEXEL_TOL 3e-2

static void check_point_falloff(lucent_renderer *r, const char *square)
{
    static const char *const methods[] = {"five\",\"sampling\":\"per_channel", "auto", "reference"};
    static const char *const names[] = {"five", "auto", "reference"};
    static const double tolerances[] = {FALLOFF_TOL, FALLOFF_NEAREST_TEXEL_TOL, FALLOFF_TOL};
    static const double positions[][3] = {{0, 0, 2}, {0, 0, 4}, {2, 0, 2}};
    lucent_material m;
    lucent_material_preset("marble", &m);
    double ft_out = fresnel_transmittance(m.eta, 1.0);
    for (int k = 0; k < 3; k++) {
        double centre[3] = {0};
        for (int p = 0; p < 3; p++) {
            const double *pos = positions[p];
            char json[700];
            snprintf(json, sizeof json,
                     "{\"mesh\":{\"file\":\"%s\"},\"scale_mm\":1e6,\"lights\":[{\"type\":\"point\",\"position\":[%g,%g,%g],"
                     "\"intensity\":5}],\"camera\":{\"position\":[0,0,6],\"target\":[0,0,0]},\"width\":33,\"height\":33,"
                     "\"method\":\"%s\"}",
                     square, pos[0], pos[1], pos[2], methods[k]);
            lucent_image img;
            lucent_stats stats;
            test_render(r, json, &img, &stats);
            double d2 = pos[0] * pos[0] + pos[1] * pos[1] + pos[2] * pos[2], cos_i = pos[2] / sqrt(d2);
            centre[p] = pixel(&img, 16, 16)[1];
            double ft_in = fresnel_transmittance(m.eta, cos_i), rd = test_profile_total(&m, test_reported_profile(&stats), 1);
            double want = 5.0 * cos_i / d2 * ft_in * rd * ft_out * diffuse_exit_weight(m.eta), rel = fabs(centre[p] - want) / want;
            double tol = pos[0] == 0.0 ? FALLOFF_TOL : tolerances[k];   /* on the axis the gradient is 0 */
            test_check(rel < tol, "point light at (%g,%g,%g), %-9s: centre green %.6g vs I cos/d^2 Ft Rd Ft / (pi Ft_diffuse) %.6g "
                                  "(rel.err %.2e, tol %.0e)",
                       pos[0], pos[1], pos[2], names[k], centre[p], want, rel, tol);
            lucent_image_free(&img);
        }
        double ratio = centre[0] / centre[1];
        test_check(fabs(ratio - 4.0) < 4.0 * FALLOFF_TOL, "%-9s: twice the distance, a quarter of the light: ratio %.5f "
                                                           "(expected 4)", names[k], ratio);
    }
}

/* ---- method auto's choices ---- */

struct auto_report {
    double object_pixels, kernel_texels, projection, samples, views;
    int per_channel, single_view;
};

/* scale_mm 0: the default (the object 50 mm across). The profile is given (the dipole), as when the
 * sizing rules below were measured; check_auto_profile tests auto's own choice. */
static struct auto_report render_auto(lucent_renderer *r, const char *mesh, const char *preset, int side,
                                      double scale_mm)
{
    char json[800], scale[40] = "";
    if (scale_mm > 0.0)
        snprintf(scale, sizeof scale, "\"scale_mm\":%g,", scale_mm);
    snprintf(json, sizeof json,
             "{\"mesh\":%s,%s\"material\":{\"preset\":\"%s\",\"profile\":\"dipole\"},\"lights\":[{\"direction\":[-1,-0.3,-0.5]}],"
             "\"camera\":{\"direction\":[0,0,-1]},\"width\":%d,\"height\":%d,\"method\":\"auto\"}",
             mesh, scale, preset, side, side);
    lucent_image img;
    lucent_stats stats;
    test_render(r, json, &img, &stats);
    struct auto_report a = {
        .object_pixels = report_number(stats.modelled, "object_pixels"),
        .kernel_texels = report_number(stats.modelled, "kernel_radius_texels"),
        .projection = report_number(stats.modelled, "projection_size"),
        .samples = report_number(stats.modelled, "samples_per_channel"),
        .views = report_number(stats.modelled, "views"),
        .per_channel = strstr(stats.modelled, "\"sampling\":\"per_channel\"") != NULL,
        .single_view = strstr(stats.modelled, "the front view sees where the light enters") != NULL,
    };
    lucent_image_free(&img);
    return a;
}

/* The README's rules: two texels per pixel of the object's size (the next power of two, 64..512),
 * samples the power of two covering the kernel's pi r^2 texels within 4..64. */
static void check_auto_sizes(lucent_renderer *r, int side, double scale_mm)
{
    struct auto_report a = render_auto(r, "{\"builtin\":\"sphere\"}", "marble", side, scale_mm);
    double covered = PI * a.kernel_texels * a.kernel_texels;
    int sized = (a.projection == 512 || a.projection + 0.5 >= 2.0 * a.object_pixels) &&
                (a.projection == 64 || a.projection / 2 < 2.0 * a.object_pixels);
    int sampled = a.samples >= 4 && a.samples <= 64 && (a.samples == 64 || a.samples >= covered) &&
                  (a.samples == 4 || a.samples / 2 < covered);
    test_check(sized && sampled && !a.per_channel && a.views == 5,
               "auto, marble sphere %g mm across at %dx%d: object %.1f px -> projection %.0f; kernel %.3g texels "
               "(pi r^2 = %.3g) -> %.0f shared samples; %.0f views", scale_mm > 0.0 ? 2.0 * scale_mm : 50.0, side, side,
               a.object_pixels, a.projection, a.kernel_texels, covered, a.samples, a.views);
}

static void check_auto_choices(lucent_renderer *r, const char *square)
{
    check_auto_sizes(r, 48, 0.0);
    check_auto_sizes(r, 160, 0.0);
    check_auto_sizes(r, 512, 0.0);
    check_auto_sizes(r, 48, 400.0);   /* kernels of a few texels */
    check_auto_sizes(r, 48, 600.0);
    struct auto_report ketchup = render_auto(r, "{\"builtin\":\"sphere\"}", "ketchup", 96, 0.0);
    test_check(ketchup.per_channel && ketchup.samples >= 4,
               "auto, ketchup (channel kernels tenfold apart): per-channel sampling, %.0f samples a channel",
               ketchup.samples);
    char mesh[200];
    snprintf(mesh, sizeof mesh, "{\"file\":\"%s\"}", square);
    struct auto_report flat = render_auto(r, mesh, "marble", 96, 0.0);
    test_check(flat.single_view && flat.views == 1,
               "auto, a square facing the camera (the front view sees where the light enters): %.0f view", flat.views);
}

/* ---- the paper's fallback for hidden points ---- */

/* "front" is the paper's rule: one view a pixel, the front image where the best-facing one hides the
 * point. "next_best" gathers the far part from every view's share of the surface (and takes the near
 * part from the next view that sees the point, blending the two best), so the two differ almost
 * everywhere (measured: 99.8% of the bunny's pixels), and the paper's rule is farther from the
 * reference (0.082 vs 0.063). */
static void check_fallback(lucent_renderer *r, const char *bunny)
{
    char base[1200];
    snprintf(base, sizeof base, "{\"mesh\":{\"file\":\"%s\"},\"lights\":[{\"direction\":[-1,0,0]}],"
             "\"camera\":{\"direction\":[0,0,-1]},\"width\":128,\"height\":128,\"format\":\"exr\",", bunny);
    static const char *const rules[] = {"\"fallback\":\"next_best\"", "\"fallback\":\"front\"",
                                        "\"method\":\"reference\""};
    lucent_image img[3];
    lucent_stats stats[3];
    for (int k = 0; k < 3; k++) {
        char json[1300];
        snprintf(json, sizeof json, "%s%s}", base, rules[k]);
        test_render(r, json, &img[k], &stats[k]);
    }
    int covered = 0, differ = 0;
    for (int i = 0; i < 128 * 128; i++) {
        covered += img[0].rgba[i * 4 + 3] > 0.0f;
        differ += memcmp(&img[0].rgba[i * 4], &img[1].rgba[i * 4], 12) != 0;
    }
    lucent_image_error next_best, front;
    lucent_image_compare(&img[0], &img[2], &next_best, NULL);
    lucent_image_compare(&img[1], &img[2], &front, NULL);
    int reported = strstr(stats[1].modelled, "\"hidden_point_fallback\":\"front\"") &&
                   strstr(stats[0].modelled, "\"hidden_point_fallback\":\"far part gathered from every view");
    test_check(reported && differ > covered / 10 && front.object.rel_l2 > next_best.object.rel_l2,
               "bunny fallback front vs next_best: %d of %d covered pixels differ (%.2f%%), rel L2 vs reference "
               "%.5f vs %.5f, reported %s", differ, covered, 100.0 * differ / covered, front.object.rel_l2,
               next_best.object.rel_l2, reported ? "yes" : "NO");
    for (int k = 0; k < 3; k++)
        lucent_image_free(&img[k]);
}

/* ---- the far annulus per block of pixels: block size by image size, the near disc one block wide ---- */

static void check_far_blocks(lucent_renderer *r)
{
    const int sides[] = {96, 200, 400}, blocks[] = {1, 2, 4};
    double disc[3];
    for (int i = 0; i < 3; i++) {
        char json[300];
        snprintf(json, sizeof json, "{\"mesh\":{\"builtin\":\"sphere\"},"
                 "\"camera\":{\"direction\":[0,0,-1]},\"width\":%d,\"height\":%d}", sides[i],
                 sides[i]);
        lucent_image img;
        lucent_stats stats;
        test_render(r, json, &img, &stats);
        double block = report_number(stats.modelled, "far_block_pixels");
        disc[i] = report_number(stats.modelled, "near_disc_mm");
        test_check(block == blocks[i] && (i == 0 ? disc[i] == 0.0 : disc[i] > 0.0),
                   "%dx%d: far annulus per block of %g pixels (want %d), near disc %g mm", sides[i], sides[i], block,
                   blocks[i], disc[i]);
        lucent_image_free(&img);
    }
    /* A block of 4 at 400 px and of 2 at 200 px cover the same area: the same disc. */
    test_check(fabs(disc[2] / disc[1] - 1.0) < 1e-6, "near disc at 400 px / at 200 px: %.6f (want 1)",
               disc[2] / disc[1]);
}

/* Method auto's profile when none is given: the asymptotic dipole under every light (README: against method
 * path, with R between points of the surface it is the nearest under side and back light), and the one given when
 * one is. Its single scattering: on where light enters behind a strongly absorbing object (against path, the
 * dipole alone misses ketchup's light scattered once or not at all on its way through), off behind a scattering
 * one (skin1, marble: diffusion already has about all of it) and elsewhere, as given when given. */
static void check_auto_profile(lucent_renderer *r)
{
    static const struct { const char *preset, *light, *want, *given, *single_reason; int single; } cases[] = {
        {"skin1", "[-1,0,0]", "asymptotic_dipole", "", "no light enters behind", 0},
        {"skin1", "[0,0,-1]", "asymptotic_dipole", "", "no light enters behind", 0},
        {"ketchup", "[0,0,1]", "asymptotic_dipole", "", "light enters behind an absorbing medium", 1},
        {"ketchup", "[-0.766,0,0.643]", "asymptotic_dipole", "", "light enters behind an absorbing medium", 1},
        {"skin1", "[0,0,1]", "asymptotic_dipole", "", "light enters behind a scattering medium", 0},
        {"marble", "[0,0,1]", "asymptotic_dipole", "", "light enters behind a scattering medium", 0},
        {"skin1", "[-1,0,0]", "burley", ",\"profile\":\"burley\"", "no light enters behind", 0},
        {"skin1", "[0,0,1]", "dipole", ",\"profile\":\"dipole\"", "light enters behind a scattering medium", 0}};
    for (int i = 0; i < (int)(sizeof cases / sizeof cases[0]); i++) {
        char json[300], want[64];
        snprintf(json, sizeof json,
                 "{\"mesh\":{\"builtin\":\"sphere\"},\"material\":{\"preset\":\"%s\"%s},\"lights\":[{\"direction\":%s}],"
                 "\"camera\":{\"direction\":[0,0,-1]},\"width\":24,\"height\":24,\"method\":\"auto\"}",
                 cases[i].preset, cases[i].given, cases[i].light);
        snprintf(want, sizeof want, "\"profile\":\"%s\"", cases[i].want);
        lucent_image img;
        lucent_stats stats;
        test_render(r, json, &img, &stats);
        const char *share = strstr(stats.modelled, "\"hidden_light_share\":");
        const char *reason = cases[i].given[0] ? "\"profile_reason\":\"given\"" : "\"profile_reason\":\"asymptotic_dipole: nearest";
        test_check(strstr(stats.modelled, want) && strstr(stats.modelled, reason) && share,
                   "auto, %s, light travelling along %s: %s (%.28s)", cases[i].preset, cases[i].light, cases[i].want,
                   share ? share : "");
        char single[96];
        snprintf(single, sizeof single, "\"single_scattering_reason\":\"%s", cases[i].single_reason);
        test_check(stats.single_scattering == cases[i].single && strstr(stats.modelled, single) &&
                       strstr(stats.modelled, cases[i].single ? "\"single_scattering\":true" : "\"single_scattering\":false"),
                   "auto, %s, light travelling along %s: single scattering %s", cases[i].preset, cases[i].light,
                   stats.single_scattering ? "on" : "off");
        lucent_image_free(&img);
    }
    lucent_image img;
    lucent_stats stats;
    test_render(r,
                "{\"mesh\":{\"builtin\":\"sphere\"},\"material\":{\"preset\":\"ketchup\"},\"lights\":[{\"direction\":[0,0,1]}],"
                "\"camera\":{\"direction\":[0,0,-1]},\"width\":24,\"height\":24,\"method\":\"auto\","
                "\"single_scattering\":false}",
                &img, &stats);
    test_check(!stats.single_scattering && strstr(stats.modelled, "\"single_scattering_reason\":\"given\""),
               "auto, back light, single_scattering false given: kept (%s)", stats.single_scattering ? "on" : "off");
    lucent_image_free(&img);
}

/* The profile a render integrated is named in what it modelled, by the image-space and the CPU methods. */
static void check_profile_reported(lucent_renderer *r)
{
    static const char *const methods[] = {"five", "auto", "reference"};
    for (int m = 0; m < 3; m++) {
        char json[300];
        snprintf(json, sizeof json,
                 "{\"mesh\":{\"builtin\":\"sphere\"},\"material\":{\"preset\":\"skin1\",\"profile\":\"better_dipole\"},"
                 "\"width\":24,\"height\":24,\"method\":\"%s\"%s}",
                 methods[m], m == 2 ? ",\"reference\":{\"points\":2000}" : "");
        lucent_image img;
        lucent_stats stats;
        test_render(r, json, &img, &stats);
        test_check(strstr(stats.modelled, "\"profile\":\"better_dipole\"") != NULL,
                   "method %s names the profile it integrated (better_dipole) in modelled", methods[m]);
        lucent_image_free(&img);
    }
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s BUNNY.obj\n", argv[0]);
        return 2;
    }
    lucent_renderer *r = test_renderer();
    const char *square = test_write_square_obj(), *shelf = write_shelf_obj();
    const char *light = "{\"direction\":[-1,-0.3,-0.5]}";
    char lights[300];
    check_profile_reported(r);
    check_auto_profile(r);
    check_shadow_rule(r, "sphere", light, 0, "skipped: mesh is convex");
    check_shadow_rule(r, "protrusion", light, 1, "\"shadow map\"");
    check_shadow_rule(r, "protrusion", "{\"direction\":[-1,0,0],\"intensity\":0}", 0, "skipped: light is black");
    check_shadow_rule(r, "protrusion", "{\"direction\":[-1,0,0],\"color\":[0,0,0]}", 0, "skipped: light is black");
    check_shadow_rule(r, "protrusion", "{\"type\":\"point\",\"position\":[0.1,0,0]}", 0,
                      "skipped: point light inside the bounding sphere");
    check_shadow_rule(r, "protrusion", "{\"type\":\"point\",\"position\":[5,0,0]}", 1, "\"shadow map\"");
    snprintf(lights, sizeof lights, "%s,{\"direction\":[0,-1,0],\"intensity\":0},%s", light, light);
    check_shadow_rule(r, "torus", lights, 2, "skipped: light is black");
    const char *back = "{\"direction\":[0,0,1]}", *rim = "{\"direction\":[-0.766,0,0.643]}";
    const char *sphere = "{\"builtin\":\"sphere\"}";
    char sheet[200];
    snprintf(sheet, sizeof sheet, "{\"file\":\"%s\"}", square);
    check_light_views(r, sphere, "five", back, 6, "\"light view\"");
    check_light_views(r, sphere, "five", rim, 6, "\"light view\"");
    check_light_views(r, sphere, "five", "{\"direction\":[-1,0,0]}", 5, "the camera's views see where its light enters");
    check_light_views(r, sphere, "five", "{\"type\":\"point\",\"position\":[0,0,-3]}", 6, "\"light view\"");
    check_light_views(r, sphere, "five", "{\"type\":\"point\",\"position\":[0,0,-0.5]}", 5,
                      "a point light within the object's bounds");
    check_light_views(r, sphere, "single", back, 1, "only the gathered five-view integration");
    snprintf(lights, sizeof lights, "%s,{\"direction\":[0.3,0,1]},{\"direction\":[0,0.2,1],\"intensity\":0.5}", back);
    check_light_views(r, sphere, "five", lights, 7, "went to lights with more light entering unseen");
    check_sheet_from_behind(r, sheet);
    check_self_shadow(r, shelf);
    check_point_falloff(r, square);
    check_auto_choices(r, square);
    check_fallback(r, argv[1]);
    check_far_blocks(r);
    lucent_renderer_destroy(r);
    unlink(square);
    unlink(shelf);
    return test_finish();
}
