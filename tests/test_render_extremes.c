/* test_render_extremes.c - renders at the edges of every material, scale, light and camera parameter
 * with every method: each value finite and non-negative, no pixel brighter than the diffuse exit lets all
 * the light that enters leave (E / (pi F_t,diffuse), with an allowance for sampling noise), and the image-space
 * methods' error against "reference" printed where the reference says it has converged. */
#include "dipole.h"
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PI 3.14159265358979323846
/* Sampling noise at 16 samples lets single pixels overshoot the diffuse bound; 7% was measured on
 * Spectralon (R_d total 1). One sample a channel overshoots up to 4x (measured 3.7x on the torus). */
#define NOISE_ALLOWANCE 1.25
#define ONE_SAMPLE_ALLOWANCE 5.0
/* The reference integrator cannot resolve kernels far below its point spacing; it says so in its
 * report, and beyond this estimated error it is not a ground truth for the case. */
#define REFERENCE_TRUSTED 0.1

/* Sphere meshes written as OBJ files for the mesh cases: unusual coordinates and broken topology. */
enum sphere_variant { SPHERE_PLAIN, SPHERE_BROKEN, SPHERE_OPEN, SPHERE_INSIDE_OUT, SPHERE_FLIPPED_NORMALS };
#define RINGS 12
#define SEGMENTS 24

static int vertex_index(int ring, int seg)
{
    return 1 + ring * SEGMENTS + seg % SEGMENTS;
}

/* UV sphere of the given radius centred at (offset, offset, offset). BROKEN adds a zero-area
 * triangle, a repeated-index one and a duplicate of every tenth face; OPEN keeps the half facing +z
 * (the camera); INSIDE_OUT reverses every face; FLIPPED_NORMALS writes inward vertex normals. */
static void write_sphere_obj(const char *path, double radius, double offset, enum sphere_variant variant)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        perror(path);
        exit(1);
    }
    for (int i = 0; i <= RINGS; i++)
        for (int j = 0; j < SEGMENTS; j++) {
            double th = 3.14159265358979 * i / RINGS, ph = 2.0 * 3.14159265358979 * j / SEGMENTS;
            double ring = i == 0 || i == RINGS ? 0.0 : sin(th);   /* exact poles: a closed mesh */
            double n[3] = {ring * cos(ph), i == RINGS ? -1.0 : cos(th), ring * sin(ph)};
            double k = variant == SPHERE_FLIPPED_NORMALS ? -1.0 : 1.0;
            fprintf(f, "v %.17g %.17g %.17g\nvn %g %g %g\n", offset + radius * n[0], offset + radius * n[1],
                    offset + radius * n[2], k * n[0], k * n[1], k * n[2]);
        }
    int faces = 0;
    for (int i = 0; i < RINGS; i++)
        for (int j = 0; j < SEGMENTS; j++) {
            int a = vertex_index(i, j), b = vertex_index(i, j + 1), c = vertex_index(i + 1, j + 1),
                d = vertex_index(i + 1, j);
            if (variant == SPHERE_OPEN && sin(2.0 * 3.14159265358979 * (j + 0.5) / SEGMENTS) < 0.0)
                continue;
            for (int t = 0; t < (variant == SPHERE_BROKEN && faces % 10 == 0 ? 2 : 1); t++) {
                if (variant == SPHERE_INSIDE_OUT)
                    fprintf(f, "f %d//%d %d//%d %d//%d\nf %d//%d %d//%d %d//%d\n", a, a, c, c, b, b, a, a, d, d, c, c);
                else
                    fprintf(f, "f %d//%d %d//%d %d//%d\nf %d//%d %d//%d %d//%d\n", a, a, b, b, c, c, a, a, c, c, d, d);
            }
            faces++;
        }
    if (variant == SPHERE_BROKEN)   /* on the pole row every ring vertex coincides: zero area */
        fprintf(f, "f 1//1 2//2 3//3\nf 30//30 30//30 31//31\n");
    fclose(f);
}

struct extreme {
    const char *fields;
    double irradiance;   /* largest irradiance any surface can receive; < 0: unbounded (light inside) */
    double allowance;    /* 0: NOISE_ALLOWANCE */
    /* rel L2 against the converged reference measured when the case was written, for five, single
     * (per channel) and auto; the bound is ERROR_MARGIN times it. NAN: not compared. */
    double measured[3];
    int empty;           /* the object is below a pixel: nothing may be covered */
    int mesh;            /* 0: as in fields; else 1 + enum sphere_variant, written to a file */
    double mesh_radius, mesh_offset;
    int side;            /* image side; 0: 48 */
};

/* Renders are deterministic, so the margin only has to absorb another device's rounding and
 * rasterization; a black image (rel L2 exactly 1) fails every bound, the largest being 0.90. */
#define ERROR_MARGIN 1.5
#define SIDE_LIGHT "\"lights\":[{\"direction\":[-1,-0.3,-0.5]}]"
/* The view every case (bar the camera ones) is measured from: straight down -Z, as the light directions assume. */
#define FRONT_VIEW "\"camera\":{\"direction\":[0,0,-1]}"
#define SPHERE_CASE(variant, radius, offset, e5, e1, ea) \
    {.fields = SIDE_LIGHT, .irradiance = 1.0, .measured = {e5, e1, ea}, .mesh = 1 + (variant), \
     .mesh_radius = (radius), .mesh_offset = (offset)}
static const struct extreme cases[] = {
    /* Without absorption R between points of the curved surface gathers a little more than a plane's total
     * (the better dipole's five: 1.27x white at its brightest pixel, 2026-12-03). */
    {.fields = "\"material\":{\"preset\":\"spectralon\"}", .irradiance = 1.0, .allowance = 1.35,
     .measured = {0.0253, 0.0251, 0.0223}},
    /* radiance ~1e-10: the fast methods' error is large on these tiny values, but not black's 1.0.
     * Kernels flat over the whole object (this and ketchup at 1e-6 mm): auto's 64 samples come out
     * 11% bright where 32 were within 1% (auto was 0.068 and 0.070 with 32). */
    {.fields = "\"material\":{\"sigma_a\":[0,0,0],\"sigma_s_prime\":[1e-6,1e-6,1e-6],\"eta\":1.0}", .irradiance = 1.0,
     .measured = {0.308, 0.255, 0.117}},
    {.fields = "\"material\":{\"sigma_a\":[1e5,1e5,1e5],\"sigma_s_prime\":[1e-6,1e-6,1e-6]}", .irradiance = 1.0,
     .measured = {0.0235, 0.025, 0.0171}},
    {.fields = "\"material\":{\"sigma_a\":[0.01,0.01,0.01],\"sigma_s_prime\":[1e4,1e4,1e4],\"eta\":3.0}",
     .irradiance = 1.0, .measured = {0.0238, 0.0265, 0.017}},
    {.fields = "\"material\":{\"sigma_a\":[1e-4,1,1e4],\"sigma_s_prime\":[1e-4,1,1e4],\"eta\":1.0001}",
     .irradiance = 1.0, .measured = {0.0992, 0.0246, 0.0219}},
    {.fields = "\"scale_mm\":1e-6,\"material\":{\"preset\":\"ketchup\"}", .irradiance = 1.0,
     .measured = {0.314, 0.248, 0.115}},
    {.fields = "\"scale_mm\":1e9,\"material\":{\"preset\":\"cream\"}", .irradiance = 1.0,
     .measured = {0.0241, 0.0242, 0.0171}},
    {.fields = "\"lights\":[{\"direction\":[-1,0,0],\"intensity\":1e12}]", .irradiance = 1e12,
     .measured = {0.0397, 0.0512, 0.0204}},
    {.fields = "\"lights\":[{\"direction\":[0,0,-1],\"intensity\":1e-6,\"color\":[1e-6,0,1e6]}]", .irradiance = 1.0,
     .measured = {0.0141, 0.0168, 0.00847}},
    /* grazing on the camera-facing side */
    {.fields = "\"lights\":[{\"direction\":[-1,0,0.02]}]", .irradiance = 1.0, .measured = {0.0401, 0.0526, 0.0206}},
    {.fields = "\"lights\":[{\"type\":\"point\",\"position\":[0,0,0]},{\"type\":\"point\",\"position\":[1e6,0,0],"
               "\"intensity\":1e12},{\"direction\":[1,-1,0]},{\"direction\":[0,1e-300,-1]}]",
     .irradiance = -1.0, .measured = {0.0255, 0.0238, 0.0137}},
    /* from behind (transmission through light views): long reach with sigma_a 0 (the owned images'
     * depth weights at their lowest rate), none at all (skin1 a kilometre wide: their highest), and a
     * point light 0.05 radii behind an object 1 mm wide, where the light views' image is nearly all
     * the lit cap (irradiance up to 1 / 0.05^2; five 1.5x bright on average, 1.9x on the axis: point
     * lights close behind are the light views' worst case, README). `single` has no light views: black,
     * rel L2 1 (still run: finite, bounded, covering what the reference covers). */
    {.fields = "\"material\":{\"sigma_a\":[0,0,0],\"sigma_s_prime\":[1,1,1]},\"lights\":[{\"direction\":[0,0,1]}]",
     .irradiance = 1.0, .measured = {0.113, 1.0, 0.0804}},
    {.fields = "\"scale_mm\":1e6,\"material\":{\"preset\":\"skin1\"},\"lights\":[{\"direction\":[0,0,1]}]",
     .irradiance = 1.0, .measured = {0, 0, 0}},
    {.fields = "\"scale_mm\":0.5,\"lights\":[{\"type\":\"point\",\"position\":[0,0,-1.05]}]",
     .irradiance = 400.0, .measured = {0.581, 1.0, 0.256}},
    /* inside, the fast methods shade the inner faces and the reference does not: not compared */
    {.fields = "\"camera\":{\"position\":[0,0,0.1],\"target\":[0,0,-1]}", .irradiance = 1.0,
     .measured = {NAN, NAN, NAN}},
    {.fields = "\"camera\":{\"position\":[0,0,1e6],\"target\":[0,0,0],\"fov_deg\":1.0001}", .irradiance = 1.0,
     .measured = {0, 0, 0}, .empty = 1},
    {.fields = "\"single_scattering\":true,\"material\":{\"preset\":\"marble\",\"g\":0.95}," SIDE_LIGHT,
     .irradiance = 1.0, .measured = {0.0306, 0.0319, 0.0158}},
    /* back-scattering lobe: single scattering retro-reflects up to p_HG(-0.95, -1) = 62/sr, far
     * above a diffuse surface's 1/pi; the bound is that lobe's (x Ft^2 / 2 at normal incidence) */
    {.fields = "\"single_scattering\":true,\"material\":{\"preset\":\"skin1\",\"g\":-0.95},"
               "\"lights\":[{\"direction\":[0,0,-1]}]",
     .irradiance = 1.0, .allowance = 100.0, .measured = {0.0159, 0.0159, 0.0159}},
    /* forward-scattering lobe from behind: light through the sphere scattered once towards the camera
     * (single scattering through a light view), up to p_HG(0.95, 1) = 62/sr; bounded as above */
    {.fields = "\"single_scattering\":true,\"material\":{\"preset\":\"skin1\",\"g\":0.95},"
               "\"lights\":[{\"direction\":[0,0,1]}]",
     .irradiance = 1.0, .allowance = 100.0, .measured = {0.348, 1.0, 0.28}},
    /* the generated spheres' values rose with diffusion in a sphere (2026-12-06; before five 0.035-0.041,
     * single 0.038-0.046, auto 0.026-0.034) */
    SPHERE_CASE(SPHERE_PLAIN, 1e-6, 0.0, 0.0465, 0.045, 0.0292),          /* coordinates around 1e-6 */
    SPHERE_CASE(SPHERE_PLAIN, 1.0, 1e6, 0.0573, 0.0553, 0.0429),           /* coordinates around 1e6 */
    /* coordinates around 1e-20 (squared texel steps near fp32's smallest). The object is 2e-14 mm across,
     * 1e13 times below a mean free path: its light is 3e-29. Until the profile's disc integrals were
     * written not to cancel (2026-12-03) every method returned their rounding noise instead, 5e-18,
     * and agreed on it to 4%. Against the true value the fast methods are off as for any object far
     * inside a flat kernel (the builtin sphere at 2e-4 mm: single's mean 0.71, five's 1.24). */
    {.fields = "\"scale_mm\":1e6," SIDE_LIGHT, .irradiance = 1.0, .measured = {0.269, 0.33, 0.103},
     .mesh = 1 + SPHERE_PLAIN, .mesh_radius = 1e-20, .mesh_offset = 0.0},
    /* distances of 1e21 mm: their squares overflow fp32 (five was NaN in every pixel) */
    {.fields = "\"scale_mm\":1e9," SIDE_LIGHT, .irradiance = 1.0, .measured = {0.0401, 0.0421, 0.0345},
     .mesh = 1 + SPHERE_PLAIN, .mesh_radius = 1e12, .mesh_offset = 0.0},
    SPHERE_CASE(SPHERE_BROKEN, 1.0, 0.0, 0.0465, 0.045, 0.0292),         /* degenerate and duplicate faces */
    SPHERE_CASE(SPHERE_OPEN, 1.0, 0.0, 0.0511, 0.0453, 0.032), /* open: half a sphere */
    SPHERE_CASE(SPHERE_INSIDE_OUT, 1.0, 0.0, 0.0465, 0.045, 0.0292),     /* every face wound inward */
    SPHERE_CASE(SPHERE_FLIPPED_NORMALS, 1.0, 0.0, 0.0465, 0.045, 0.0292),
    /* one pixel, whose centre ray once slipped through the BVH; auto 0.031 while the fast methods took the
     * curvature from G-buffer neighbours (a single pixel has none), now the mesh's as the reference does */
    {.fields = SIDE_LIGHT, .irradiance = 1.0, .measured = {0.0484, 0.0587, 0.00371}, .side = 1},
    /* method auto chooses its own samples: not run */
    {.fields = "\"mesh\":{\"builtin\":\"torus\",\"triangles\":1000},\"samples\":1,\"projection_size\":16",
     .irradiance = 1.0, .allowance = ONE_SAMPLE_ALLOWANCE, .measured = {0.522, 0.601, NAN}},
};
#define CASES (sizeof cases / sizeof cases[0])

struct scan {
    int bad, covered;
    double peak;
};

static struct scan scan_image(const lucent_image *img)
{
    struct scan s = {0, 0, 0.0};
    for (int i = 0; i < img->width * img->height * 4; i++) {
        float v = img->rgba[i];
        s.bad += !isfinite(v) || v < 0.0f;
        if (isfinite(v) && i % 4 != 3)
            s.peak = fmax(s.peak, v);
        s.covered += i % 4 == 3 && v > 0.0f;
    }
    return s;
}

/* The brightest the diffuse exit can be a unit of irradiance (sr^-1): all the light that enters leaves,
 * spread as F_t / (pi F_t,diffuse) (reference.c, scatter.comp), which is at most 1 / (pi F_t,diffuse). */
static double exit_peak(const char *json)
{
    lucent_scene scene;
    lucent_error err = {0};
    if (lucent_scene_parse(json, strlen(json), 1, &scene, &err) != LUCENT_OK)
        test_die("scene", &err);
    return diffuse_exit_weight(scene.material.eta);
}

/* Method auto's choice of profile is pinned to the dipole's here, and its single scattering to the case's, so
 * that its error is measured against the same reference as the other methods' (the choices themselves: test
 * render_modelled); the other profiles
 * are rendered by five at every extreme too, checked finite and bounded. Returns the case's peak bound:
 * the diffuse exit F_t / (pi F_t,diffuse) of all the light that can enter, with its allowance. */
static double render_case(lucent_renderer *r, const struct extreme *c, const char *mode, lucent_profile profile,
                          lucent_image *out, lucent_stats *stats)
{
    char json[1600], mesh[160] = "";
    /* The torus case and method auto choose their own projection size. */
    int own_projection = strstr(c->fields, "projection_size") || strstr(mode, "auto");
    int side = c->side ? c->side : 48;
    const char *pinned =
        strstr(mode, "auto") && !strstr(c->fields, "single_scattering") ? ",\"single_scattering\":false" : "";
    if (c->mesh) {
        snprintf(mesh, sizeof mesh, "/tmp/lucent-extreme-%d.obj", (int)getpid());
        write_sphere_obj(mesh, c->mesh_radius, c->mesh_offset, (enum sphere_variant)(c->mesh - 1));
    }
    snprintf(json, sizeof json, "{%s%s%s%s,%s\"width\":%d,\"height\":%d,%s%s%s,\"format\":\"exr\"}",
             c->mesh ? "\"mesh\":{\"file\":\"" : "", mesh, c->mesh ? "\"}," : "", c->fields,
             strstr(c->fields, "\"camera\"") ? "" : FRONT_VIEW ",", side, side,
             own_projection ? "" : "\"projection_size\":64,", mode, pinned);
    double bound = c->irradiance * exit_peak(json) * (c->allowance > 0.0 ? c->allowance : NOISE_ALLOWANCE);
    test_render_profile(r, json, profile, out, stats);
    if (c->mesh)
        unlink(mesh);
    return bound;
}

/* The reference's own estimate of its error, from the report in stats->modelled; NAN when the report
 * lacks it (a renamed key must fail the comparison, not skip it). */
static double reference_error(const lucent_stats *stats)
{
    const char *at = strstr(stats->modelled, "\"estimated_rel_error\":");
    double e = NAN;
    return at && sscanf(at + strlen("\"estimated_rel_error\":"), "%lf", &e) == 1 ? e : NAN;
}

static const char *const mesh_names[] = {"", "sphere", "broken sphere", "open sphere", "inside-out sphere",
                                         "sphere, flipped normals"};

static void describe_case(const struct extreme *c, char *buf, size_t cap)
{
    if (c->mesh)
        snprintf(buf, cap, "%s r=%g at %g", mesh_names[c->mesh], c->mesh_radius, c->mesh_offset);
    else
        snprintf(buf, cap, "%.44s%s", c->fields, c->side ? " 1x1" : "");
}

/* The fast image covers what the reference covers: rasterization and ray casting may disagree on
 * a few silhouette pixels (1% and one pixel allowed); nothing is covered where the case is empty. */
static int coverage_agrees(const struct extreme *c, int covered, int ref_covered)
{
    if (c->empty)
        return covered == 0 && ref_covered == 0;
    return ref_covered > 0 && abs(covered - ref_covered) <= 1 + ref_covered / 100;
}

static void check_case(lucent_renderer *r, const struct extreme *c)
{
    static const char *const modes[] = {"\"method\":\"reference\"", "\"method\":\"five\"",
                                        "\"method\":\"single\",\"sampling\":\"per_channel\"", "\"method\":\"auto\""};
    lucent_image ref;
    int ref_covered = 0;
    int compared = isfinite(c->measured[0]);
    char what[64];
    describe_case(c, what, sizeof what);
    for (int m = 0; m < 4; m++) {
        if (m > 0 && isnan(c->measured[m - 1]) && compared)
            continue;   /* method auto chooses the samples itself */
        lucent_image img;
        lucent_stats stats;
        double bound = render_case(r, c, modes[m], LUCENT_PROFILE_DIPOLE, m == 0 ? &ref : &img, &stats);
        const lucent_image *shown = m == 0 ? &ref : &img;
        struct scan s = scan_image(shown);
        int bounded = c->irradiance < 0.0 || s.peak <= bound;
        char versus[128], peak_bound[24] = "none";
        int ok;
        if (c->irradiance >= 0.0)
            snprintf(peak_bound, sizeof peak_bound, "%.3g", bound);
        if (m == 0) {
            double ref_error = reference_error(&stats);
            ref_covered = s.covered;
            /* Every compared case needs a ground truth: an unconverged (or unreported) one fails. */
            int trusted = ref_error <= REFERENCE_TRUSTED;
            ok = !compared || (trusted && coverage_agrees(c, s.covered, s.covered));
            snprintf(versus, sizeof versus, "its estimated error %.3g (%s %.2g)%s", ref_error,
                     trusted ? "within" : "NOT within", REFERENCE_TRUSTED, compared ? "" : ", not compared");
        } else if (compared) {
            lucent_image_error e = {0};
            double max_rel_l2 = ERROR_MARGIN * c->measured[m - 1];
            lucent_image_compare(&img, &ref, &e, NULL);
            ok = coverage_agrees(c, s.covered, ref_covered) && (c->empty ? e.object.pixels == 0 : e.object.pixels > 0) &&
                 e.object.rel_l2 <= max_rel_l2;
            snprintf(versus, sizeof versus, "rel L2 vs reference %.3g over %d px (measured %.3g, bound %.3g)",
                     e.object.rel_l2, e.object.pixels, c->measured[m - 1], max_rel_l2);
        } else {
            ok = 1;
            snprintf(versus, sizeof versus, "not compared");
        }
        test_check(s.bad == 0 && bounded && ok, "{%s} %-34.34s: %d bad, %d covered (reference %d), peak %.3g (bound %s), %s",
                   what, modes[m], s.bad, s.covered, ref_covered, s.peak, peak_bound, versus);
        if (m > 0)
            lucent_image_free(&img);
    }
    lucent_image_free(&ref);
    for (int p = LUCENT_PROFILE_BETTER_DIPOLE; p < LUCENT_PROFILE_DEFAULT; p++) {
        lucent_image img;
        lucent_stats stats;
        double bound = render_case(r, c, "\"method\":\"five\"", (lucent_profile)p, &img, &stats);
        struct scan s = scan_image(&img);
        test_check(s.bad == 0 && (c->irradiance < 0.0 || s.peak <= bound) && coverage_agrees(c, s.covered, ref_covered),
                   "{%s} five, profile %-13s: %d bad, %d covered (reference %d), peak %.3g", what,
                   lucent_profile_name((lucent_profile)p), s.bad, s.covered, ref_covered, s.peak);
        lucent_image_free(&img);
    }
}

/* Scenes built by hand skip the parser: the renderer itself must refuse non-finite coefficients. */
static void check_hand_built(lucent_renderer *r)
{
    lucent_scene scene;
    lucent_scene_defaults(&scene);
    scene.width = scene.height = 16;
    scene.material.sigma_a[1] = NAN;
    lucent_image img = {0};
    lucent_error err = {0};
    lucent_status st = lucent_render(r, &scene, &img, NULL, &err);
    test_check(st == LUCENT_E_LIMIT, "hand-built scene with NaN sigma_a refused: [%s] %s", err.field, err.message);
    lucent_scene_defaults(&scene);
    scene.material.eta = 0.5;
    st = lucent_render(r, &scene, &img, NULL, &err);
    test_check(st == LUCENT_E_LIMIT, "hand-built scene with eta 0.5 refused: [%s] %s", err.field, err.message);
    /* what the parser refuses and the plan would turn into inf or NaN */
    static const char *const what[] = {"g = 1", "fov 0", "light direction NaN", "light direction zero",
                                       "point light at 1e300", "light colour inf", "intensity -1",
                                       "camera position = target", "light type 7", "profile 9",
                                       "single_scattering 2", "single_scattering left to auto with method five"};
    for (int i = 0; i < (int)(sizeof what / sizeof what[0]); i++) {
        lucent_scene_defaults(&scene);
        scene.width = scene.height = 16;
        lucent_light *l = &scene.lights[0];
        switch (i) {
        case 0: scene.material.g = 1.0; break;
        case 1: scene.camera = (lucent_camera){.given = 1, .position = {0, 0, 5}, .up = {0, 1, 0}, .fov_deg = 0}; break;
        case 2: l->direction[1] = NAN; break;
        case 3: l->direction[0] = l->direction[1] = l->direction[2] = 0; break;
        case 4: l->type = LUCENT_LIGHT_POINT, l->position[0] = 1e300; break;
        case 5: l->color[2] = INFINITY; break;
        case 6: l->intensity = -1; break;
        case 7: scene.camera = (lucent_camera){.given = 1, .up = {0, 1, 0}, .fov_deg = 40}; break;
        case 8: l->type = (lucent_light_type)7; break;
        case 9: scene.material.profile = (lucent_profile)9; break;
        case 10: scene.single_scattering = 2; break;
        default: scene.method = LUCENT_METHOD_FIVE, scene.single_scattering = LUCENT_CHOSEN; break;
        }
        st = lucent_render(r, &scene, &img, NULL, &err);
        test_check(st == LUCENT_E_LIMIT, "hand-built scene with %s refused: [%s] %s", what[i], err.field, err.message);
    }
    lucent_image_free(&img);
}

/* Mean radiance over covered pixels and the covered share of the frame. */
static void coverage_and_mean(const lucent_image *img, double *share, double *mean)
{
    double sum = 0.0;
    size_t covered = 0, n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++)
        if (img->rgba[i * 4 + 3] > 0.0f) {
            covered++;
            sum += test_luminance(&img->rgba[i * 4]);
        }
    *share = (double)covered / (double)n;
    *mean = covered ? sum / (double)covered : 0.0;
}

/* The largest image accepted renders, finite and bounded, and agrees with a small one on what is
 * covered and how bright it is on average (the reference is not run at millions of pixels). The
 * parser allows 4096^2; a device whose storage-buffer range is smaller refuses it naming that limit,
 * and renders the largest square it allows. */
/* Measured at 2896^2: covered shares 0.0016 apart (the 64x64 silhouette is coarse), means 0.39% (the
 * far part per block of 4 pixels is the closer to the reference: mean ratio 1.0049 at 400^2 against
 * 1.0074 per pixel at 64^2, side-lit sphere). */
#define MAX_IMAGE_SHARE_TOL 0.003
#define MAX_IMAGE_MEAN_TOL 0.006
static void check_max_image(lucent_renderer *r)
{
    static const char scene[] = "{\"mesh\":{\"builtin\":\"protrusion\"}," SIDE_LIGHT "," FRONT_VIEW ",\"width\":%d,\"height\":%d}";
    char json[300];
    uint64_t max_pixels = lucent_renderer_max_pixels(r);
    int side = LUCENT_MAX_IMAGE_SIDE;
    if ((uint64_t)side * side > max_pixels) {
        lucent_scene s;
        lucent_image img = {0};
        lucent_error err = {0};
        snprintf(json, sizeof json, scene, side, side);
        lucent_scene_parse(json, strlen(json), 0, &s, NULL);
        lucent_status st = lucent_render(r, &s, &img, NULL, &err);
        const char *limit = strcmp(lucent_renderer_backend(r), "gl") == 0 ? "GL_MAX_SHADER_STORAGE_BLOCK_SIZE"
                                                                           : "maxStorageBufferRange";
        test_check(st == LUCENT_E_LIMIT && strcmp(err.field, "width") == 0 && strstr(err.message, limit),
                   "%dx%d beyond this device's %llu pixels refused: [%s] %s", side, side,
                   (unsigned long long)max_pixels, err.field, err.message);
        lucent_image_free(&img);
        while ((uint64_t)side * side > max_pixels)
            side--;
    }
    lucent_image big, small;
    lucent_stats stats;
    snprintf(json, sizeof json, scene, side, side);
    test_render(r, json, &big, &stats);
    snprintf(json, sizeof json, scene, 64, 64);
    test_render(r, json, &small, NULL);
    struct scan s = scan_image(&big);
    double share_big, mean_big, share_small, mean_small;
    coverage_and_mean(&big, &share_big, &mean_big);
    coverage_and_mean(&small, &share_small, &mean_small);
    double mean_diff = fabs(mean_big - mean_small) / mean_small;
    test_check(s.bad == 0 && s.peak <= NOISE_ALLOWANCE * exit_peak(json) && fabs(share_big - share_small) < MAX_IMAGE_SHARE_TOL &&
                   mean_diff < MAX_IMAGE_MEAN_TOL,
               "%dx%d five (the largest this device takes): %d bad, peak %.3g, covered %.4f vs %.4f at 64x64 (tol %.3g), mean "
               "radiance %.4g vs %.4g (%.2g apart, tol %.2g), %.0f ms", side, side, s.bad, s.peak, share_big,
               share_small, MAX_IMAGE_SHARE_TOL, mean_big, mean_small, mean_diff, MAX_IMAGE_MEAN_TOL, stats.ms_total);
    lucent_image_free(&big);
    lucent_image_free(&small);
}

int main(void)
{
    lucent_renderer *r = test_renderer();
    check_hand_built(r);
    for (size_t i = 0; i < CASES; i++)
        check_case(r, &cases[i]);
    check_max_image(r);
    lucent_renderer_destroy(r);
    return test_finish();
}
