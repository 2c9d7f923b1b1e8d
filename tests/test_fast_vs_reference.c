/* test_fast_vs_reference.c - the image-space methods scored against method "reference" on small images
 * (the builtins, the bunny and a flat-faced cube lit on one face): every error measure, noise and the
 * mean ratio bounded at the measured value times a margin, and the paper's claim checked: under a
 * side light, five projection images beat one in the silhouette band. */
#include "flat_cube.h"
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* Renders are deterministic; the margins absorb another device's rounding and rasterization. The
 * relative measures are dominated by the dimly lit far side, so their share gets an absolute margin. */
#define ERROR_MARGIN 1.5
#define SHARE_MARGIN 0.1
/* Mottle, set on images above 128^2 whose far part is filtered per block (0 below: blocks of one pixel, whose
 * speckle is noise's), is the far samples' pattern and moves little between devices: the interleaved turns
 * (scatter.comp, pixel_rotation) cut it 1.2-2.7x, and a closer margin keeps that. */
#define MOTTLE_MARGIN 1.2
/* The mean ratio's distance from 1 gets the error margin, at least 0.01. */
#define MEAN_FLOOR 0.01

enum { MODES = 3 };
static const char *const modes[MODES] = {"\"method\":\"single\"", "\"method\":\"five\"",
                                         "\"method\":\"five\",\"sampling\":\"per_channel\""};

struct measures {
    double rel_l2, band_rel_l2, p99_rel, share_over_10pct, noise, mean_ratio, mottle;
};

enum mesh_source { BUILTIN, BUNNY, CUBE };

struct scored_case {
    enum mesh_source source;
    const char *mesh, *lights, *material;   /* lights: the members of the "lights" array */
    int side;
    struct measures measured[MODES];   /* when written, per mode */
    int claim;                         /* five's band error must be below single's */
};

/* One directional light travelling along V (a JSON array). */
#define DIR(v) "{\"direction\":" v ",\"intensity\":3}"

/* Every bunny case measured again 2026-12-06 with the reference's thin parts (thin_part.c), which the fast
 * methods do not have: lit from behind, the reference's marble ear is brighter (five's mean 0.96 -> 0.93 of
 * it); under side light its ear is darker and five nearer (0.081 -> 0.078 at 96^2). The bunny and protrusion
 * cases measured again 2026-12-07 once the fast methods' sphere factor took the curvature limited by the part's
 * thickness as the reference does (mesh_ball_curvature): lit from behind, five 0.148 -> 0.122 (mean 0.93 ->
 * 0.96), the point light behind 0.194 -> 0.172; the rest within 0.001 (the protrusion's rows were stale). */
static const struct scored_case cases[] = {
    {BUILTIN, "sphere", DIR("[0,0,-1]"), "skin1", 64,
     {{0.03539, 0.0669, 0.1266, 0.05, 0.03104, 1.0002, 0},
      {0.03609, 0.04999, 0.106, 0.01, 0.0321, 1.0011, 0},
      {0.01857, 0.0264, 0.04914, 0.00, 0.01566, 1.0027, 0}}, 0},
    /* measured again 2026-12-06 with diffusion in a sphere (sphere_factor) in both */
    {BUILTIN, "sphere", DIR("[-1,0,0]"), "marble", 64,
     {{0.05333, 0.04913, 1.71, 0.64, 0.04715, 1.0117, 0},
      {0.04174, 0.03056, 1.66, 0.61, 0.03912, 1.0067, 0},
      {0.03368, 0.0284, 2.132, 0.58, 0.02997, 0.9997, 0}}, 1},
    {BUILTIN, "protrusion", DIR("[-1,0,0]"), "marble", 64,
     {{0.06817, 0.06514, 2.602, 0.60, 0.06149, 1.0105, 0},
      {0.0379, 0.03107, 1.244, 0.49, 0.03308, 0.9992, 0},
      {0.03293, 0.02839, 0.965, 0.53, 0.02754, 0.9953, 0}}, 1},
    /* ketchup's kernels differ tenfold: 16 shared samples cover red thinly */
    {BUILTIN, "protrusion", DIR("[-1,0,0]"), "ketchup", 64,
     {{0.3681, 0.3057, 3.346, 0.83, 0.3726, 1.0076, 0},
      {0.1841, 0.159, 1.479, 0.71, 0.1741, 0.9790, 0},
      {0.06933, 0.06291, 0.8954, 0.46, 0.06224, 0.9814, 0}}, 0},
    {BUNNY, "bunny", DIR("[-1,0,0]"), "marble", 96,
     {{0.1306, 0.2118, 2.251, 0.68, 0.05848, 0.9497, 0},
      {0.078, 0.05411, 1.909, 0.59, 0.05443, 0.9766, 0},
      {0.07274, 0.05114, 1.803, 0.64, 0.04594, 0.9720, 0}}, 1},
    /* the +X face lit, the top and front faces lit only by light diffusing around their edges */
    {CUBE, "cube", DIR("[-1,0,0]"), "marble", 96,
     {{0.1063, 0.06574, 3.665, 0.73, 0.1005, 1.0007, 0},
      {0.05332, 0.04861, 1, 0.58, 0.03966, 1.0005, 0},
      {0.05266, 0.04453, 0.9931, 0.67, 0.03829, 0.9937, 0}}, 0},
    {CUBE, "cube", DIR("[-1,0,0]"), "skin1", 96,
     {{0.2196, 0.1441, 2.288, 0.79, 0.2009, 0.9802, 0},
      {0.07705, 0.07274, 0.9897, 0.58, 0.05854, 0.9969, 0},
      {0.05904, 0.05711, 0.949, 0.54, 0.03817, 0.9991, 0}}, 0},
    /* larger images integrate the far part once per block of 2x2 (256^2) and 4x4 (512^2) pixels and have a near
     * disc; re-measured with the disc beside the exit point counted at its distance (the bunny's p99 1.13 -> 0.50:
     * the bluish spots on its shaded chest; the cube 0.063 -> 0.057), and again (these rows and the 256^2
     * sphere's, 2026-12-07) with their far samples reading mip levels half as coarse (LOD_BIAS -1 where
     * blocks are filtered: the bunny 0.060 -> 0.056, the sphere 0.0123 -> 0.0107, mottle up to 4%) */
    {BUNNY, "bunny", DIR("[-1,0,0]"), "marble", 256,
     {{0.1002, 0.1665, 0.8835, 0.57, 0.02089, 0.9386, 0.01917},
      {0.05579, 0.06246, 0.4917, 0.34, 0.01631, 0.9682, 0.01727},
      {0.05686, 0.06297, 0.4322, 0.33, 0.01628, 0.9691, 0.01717}}, 1},
    {CUBE, "cube", DIR("[-1,0,0]"), "marble", 256,
     {{0.0744, 0.05446, 1, 0.60, 0.02514, 1.0212, 0.05583},
      {0.05604, 0.05233, 0.7499, 0.23, 0.02067, 1.0087, 0.0349},
      {0.05667, 0.05271, 0.5295, 0.15, 0.02078, 1.0091, 0.03573}}, 0},
    /* lit from behind: single sees none of it (black, rel L2 1); five gathers it through the object
     * from a light view. Blocks of one pixel here: the far filter is off, hence the sphere's noise. The rows
     * with light views measured again 2026-12-07 with the owned blocks' own depths and the light views' owned
     * images at the front's resolution (bunny back marble five 0.122 -> 0.107, rim 0.2005 -> 0.184; the
     * sphere's rows were stale: 0.1427 stored, 0.1558 before this change, 0.1552 after). */
    {BUILTIN, "sphere", DIR("[0,0,1]"), "marble", 128,
     {{1, 1, 1, 1.00, 0.0015, 0.0000, 0},
      {0.1552, 0.1624, 0.3639, 0.59, 0.1134, 0.8954, 0},
      {0.1489, 0.146, 0.3476, 0.57, 0.1096, 0.8963, 0}}, 0},
    /* measured again with sphere_factor, both taking the exit's curvature from mesh_vertex_curvature (with the
     * fast one from G-buffer neighbours and the reference's per triangle: five 0.1305, per channel 0.1348) */
    {BUNNY, "bunny", DIR("[0,0,1]"), "marble", 128,
     {{0.9853, 0.9694, 1, 1.00, 0.03058, 0.0067, 0},
      {0.1069, 0.1471, 0.3491, 0.52, 0.08326, 0.9837, 0},
      {0.1143, 0.1704, 0.3331, 0.66, 0.08786, 0.9681, 0}}, 0},
    {BUNNY, "bunny", DIR("[0,0,1]"), "skin1", 128,
     {{0.9936, 0.9876, 1, 1.00, 0.0449, 0.0061, 0},
      {0.1291, 0.2432, 0.4625, 0.57, 0.09226, 0.9758, 0},
      {0.09351, 0.1672, 0.3019, 0.43, 0.06258, 0.9682, 0}}, 0},
    /* a rim light, 130 degrees from the view direction: lit partly where the camera sees */
    {BUNNY, "bunny", DIR("[-0.766,0,0.643]"), "marble", 128,
     {{0.4253, 0.3621, 1, 0.98, 0.1329, 0.5583, 0},
      {0.1838, 0.1404, 0.8629, 0.71, 0.1462, 0.9722, 0},
      {0.191, 0.1513, 0.8274, 0.90, 0.162, 0.9583, 0}}, 0},
    /* point lights (positions in the mesh's coordinates; the bunny's centre is near [0,4.8,0], its radius
     * about 6): behind the sphere 3 radii from its centre, behind the bunny, and two lights on the bunny,
     * one from behind and one a point in front */
    {BUILTIN, "sphere", "{\"type\":\"point\",\"position\":[0,0,-3],\"intensity\":27}", "skin1", 128,
     {{1, 1, 1, 1.00, 0.006858, 0.0000, 0},
      {0.1273, 0.1201, 0.3077, 0.57, 0.1142, 0.9382, 0},
      {0.1179, 0.1124, 0.2913, 0.56, 0.1016, 0.9372, 0}}, 0},
    {BUNNY, "bunny", DIR("[0,0,1]") ",{\"type\":\"point\",\"position\":[8,10,12],\"intensity\":600}", "skin1", 128,
     {{0.2161, 0.3765, 0.8986, 0.48, 0.064, 0.9129, 0},
      {0.06013, 0.1144, 0.3464, 0.19, 0.04379, 0.9943, 0},
      {0.04613, 0.07849, 0.2151, 0.11, 0.0287, 0.9925, 0}}, 0},
    {BUNNY, "bunny", "{\"type\":\"point\",\"position\":[-4,6,-12],\"intensity\":600}", "marble", 128,
     {{0.9944, 0.9878, 1, 1.00, 0.0322, 0.0070, 0},
      {0.1716, 0.1956, 0.4742, 0.54, 0.08331, 0.9703, 0},
      {0.1731, 0.1866, 0.5099, 0.67, 0.09224, 0.9599, 0}}, 0},
    /* the sphere shows the far samples' mottle alone: 0.0129 (five) before their turns were interleaved */
    {BUILTIN, "sphere", DIR("[-1,0,0]"), "marble", 256,
     {{0.01974, 0.03133, 1, 0.47, 0.002467, 1.0117, 0.00592},
      {0.01066, 0.01233, 0.816, 0.44, 0.002377, 0.9954, 0.004453},
      {0.01003, 0.01232, 0.7208, 0.35, 0.002375, 0.9992, 0.004525}}, 1},
    {BUNNY, "bunny", DIR("[-1,0,0]"), "marble", 512,
     {{0.1, 0.1637, 0.8886, 0.57, 0.01748, 0.9373, 0.01964},
      {0.05629, 0.06182, 0.4896, 0.33, 0.01308, 0.9674, 0.01662},
      {0.05771, 0.0628, 0.4213, 0.33, 0.01307, 0.9688, 0.01665}}, 1},
};

static int within(const char *name, double got, double bound, char *buf, size_t cap)
{
    size_t n = strlen(buf);
    snprintf(buf + n, cap - n, " %s %.4g (bound %.4g)", name, got, bound);
    return got <= bound;
}

static void score(lucent_renderer *r, const struct scored_case *c, const char *mesh)
{
    char base[900], json[1000];
    snprintf(base, sizeof base,
             "\"mesh\":{\"%s\":\"%s\"},\"material\":{\"preset\":\"%s\"},\"lights\":[%s],"
             "\"width\":%d,\"height\":%d,\"format\":\"exr\"%s",
             c->source == BUILTIN ? "builtin" : "file", mesh, c->material, c->lights, c->side, c->side,
             c->source == CUBE ? ",\"camera\":{\"position\":[1.3,1,2.2],\"target\":[0,0,0]}"
                               : ",\"camera\":{\"direction\":[0,0,-1]}");
    snprintf(json, sizeof json, "{%s,\"method\":\"reference\"}", base);
    lucent_image ref;
    test_render(r, json, &ref, NULL);
    double band[MODES] = {0};
    const char *name = c->mesh;
    for (int m = 0; m < MODES; m++) {
        snprintf(json, sizeof json, "{%s,%s}", base, modes[m]);
        lucent_image img;
        lucent_image_error e;
        lucent_error err = {0};
        test_render(r, json, &img, NULL);
        lucent_status st = lucent_image_compare(&img, &ref, &e, &err);
        const struct measures *w = &c->measured[m];
        char line[600] = "";
        int ok = st == LUCENT_OK && e.object.pixels > 0 && e.band.pixels > 0 &&
                 e.coverage_mismatch <= e.object.pixels / 50;
        ok &= within("rel L2", e.object.rel_l2, ERROR_MARGIN * w->rel_l2, line, sizeof line);
        ok &= within("band rel L2", e.band.rel_l2, ERROR_MARGIN * w->band_rel_l2, line, sizeof line);
        ok &= within("p99 rel", e.object.p99_rel, ERROR_MARGIN * w->p99_rel, line, sizeof line);
        ok &= within(">10%", e.object.share_over_10pct, w->share_over_10pct + SHARE_MARGIN, line, sizeof line);
        ok &= within("noise", e.noise, ERROR_MARGIN * w->noise, line, sizeof line);
        if (w->mottle > 0.0)
            ok &= within("mottle", e.mottle, MOTTLE_MARGIN * w->mottle, line, sizeof line);
        size_t used = strlen(line);
        snprintf(line + used, sizeof line - used, " mean ratio %.4f", e.mean_ratio);
        ok &= within("|mean ratio - 1|", fabs(e.mean_ratio - 1.0),
                     fmax(ERROR_MARGIN * fabs(w->mean_ratio - 1.0), MEAN_FLOOR), line, sizeof line);
        test_check(ok, "%-10s %3d %-7s lights %s {%s}:%s; band %d px, coverage mismatch %d", name, c->side,
                   c->material, c->lights, modes[m], line, e.band.pixels, e.coverage_mismatch);
        band[m] = e.band.rel_l2;
        lucent_image_free(&img);
    }
    if (c->claim)
        test_check(band[1] < band[0], "%s %d %s lights %s: five views beat one in the silhouette band, rel L2 %.4f vs "
                                      "%.4f (ratio %.2f)", name, c->side, c->material, c->lights, band[1], band[0],
                   band[1] / band[0]);
    lucent_image_free(&ref);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s BUNNY.obj\n", argv[0]);
        return 2;
    }
    lucent_renderer *r = test_renderer();
    char cube[64];
    test_write_obj(cube, sizeof cube, "cube", flat_cube_obj);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        score(r, &cases[i], cases[i].source == BUILTIN ? cases[i].mesh : cases[i].source == BUNNY ? argv[1] : cube);
    unlink(cube);
    lucent_renderer_destroy(r);
    return test_finish();
}
