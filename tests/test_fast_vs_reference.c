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
/* The mean ratio's distance from 1 gets the error margin, at least 0.01. */
#define MEAN_FLOOR 0.01

enum { MODES = 3 };
static const char *const modes[MODES] = {"\"method\":\"single\"", "\"method\":\"five\"",
                                         "\"method\":\"five\",\"sampling\":\"per_channel\""};

struct measures {
    double rel_l2, band_rel_l2, p99_rel, share_over_10pct, noise, mean_ratio;
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

static const struct scored_case cases[] = {
    {BUILTIN, "sphere", DIR("[0,0,-1]"), "skin1", 64,
     {{0.03438, 0.06305, 0.1217, 0.03, 0.03001, 1.0025},
      {0.03494, 0.0479, 0.1044, 0.01, 0.03089, 1.0032},
      {0.0179, 0.02527, 0.04771, 0.00, 0.01477, 1.0037}}, 0},
    {BUILTIN, "sphere", DIR("[-1,0,0]"), "marble", 64,
     {{0.0498, 0.04697, 2.324, 0.62, 0.04248, 1.0189},
      {0.03844, 0.02802, 2.276, 0.59, 0.03528, 1.0120},
      {0.03069, 0.02559, 3.991, 0.58, 0.02684, 1.0057}}, 1},
    {BUILTIN, "protrusion", DIR("[-1,0,0]"), "marble", 64,
     {{0.05967, 0.05934, 3.21, 0.59, 0.05036, 1.0165},
      {0.03296, 0.0271, 1.813, 0.48, 0.02802, 1.0022},
      {0.02877, 0.02429, 1.357, 0.52, 0.02367, 0.9995}}, 1},
    /* ketchup's kernels differ tenfold: 16 shared samples cover red thinly */
    {BUILTIN, "protrusion", DIR("[-1,0,0]"), "ketchup", 64,
     {{0.1581, 0.1448, 3.544, 0.72, 0.1387, 1.0337},
      {0.09068, 0.07796, 1.867, 0.60, 0.07992, 0.9950},
      {0.03112, 0.02937, 1.44, 0.37, 0.02849, 0.9963}}, 0},
    {BUNNY, "bunny", DIR("[-1,0,0]"), "marble", 96,
     {{0.1056, 0.2033, 2.478, 0.65, 0.05416, 0.9574},
      {0.06272, 0.05363, 1.821, 0.58, 0.0431, 0.9727},
      {0.05798, 0.04933, 1.729, 0.60, 0.03759, 0.9696}}, 1},
    /* the +X face lit, the top and front faces lit only by light diffusing around their edges */
    {CUBE, "cube", DIR("[-1,0,0]"), "marble", 96,
     {{0.06601, 0.04975, 3.167, 0.70, 0.06151, 1.0051},
      {0.04168, 0.0362, 1, 0.62, 0.03287, 1.0015},
      {0.03876, 0.03334, 0.9593, 0.70, 0.02911, 0.9953}}, 0},
    {CUBE, "cube", DIR("[-1,0,0]"), "skin1", 96,
     {{0.1001, 0.08472, 3.863, 0.75, 0.09395, 1.0027},
      {0.05685, 0.04841, 0.9757, 0.63, 0.04756, 1.0001},
      {0.03894, 0.03555, 0.9465, 0.56, 0.02682, 1.0006}}, 0},
    /* larger images integrate the far part once per block of 2x2 (256^2) and 4x4 (512^2) pixels */
    {BUNNY, "bunny", DIR("[-1,0,0]"), "marble", 256,
     {{0.08072, 0.1583, 0.9593, 0.50, 0.02038, 0.9667},
      {0.04413, 0.05421, 0.618, 0.45, 0.01493, 0.9723},
      {0.04363, 0.05287, 0.5466, 0.44, 0.01487, 0.9698}}, 1},
    {CUBE, "cube", DIR("[-1,0,0]"), "marble", 256,
     {{0.05962, 0.04581, 1.209, 0.63, 0.02908, 1.0328},
      {0.04331, 0.04129, 0.6416, 0.44, 0.02239, 0.9976},
      {0.04286, 0.04077, 0.4996, 0.51, 0.02243, 0.9950}}, 0},
    /* lit from behind: single sees none of it (black, rel L2 1); five gathers it through the object
     * from a light view. Blocks of one pixel here: the far filter is off, hence the sphere's noise. */
    {BUILTIN, "sphere", DIR("[0,0,1]"), "marble", 128,
     {{1, 1, 1, 1.00, 0.003099, 0.0000},
      {0.1951, 0.1924, 0.4375, 0.72, 0.1467, 0.8680},
      {0.1827, 0.1667, 0.4222, 0.71, 0.134, 0.8645}}, 0},
    {BUNNY, "bunny", DIR("[0,0,1]"), "marble", 128,
     {{0.9857, 0.9725, 1, 1.00, 0.03744, 0.0091},
      {0.09478, 0.1106, 0.3176, 0.44, 0.06332, 0.9960},
      {0.09916, 0.126, 0.2565, 0.45, 0.07459, 0.9829}}, 0},
    {BUNNY, "bunny", DIR("[0,0,1]"), "skin1", 128,
     {{0.985, 0.9762, 1, 1.00, 0.03875, 0.0132},
      {0.1054, 0.1514, 0.4609, 0.53, 0.06472, 0.9957},
      {0.08117, 0.1122, 0.3024, 0.41, 0.05039, 0.9795}}, 0},
    /* a rim light, 130 degrees from the view direction: lit partly where the camera sees */
    {BUNNY, "bunny", DIR("[-0.766,0,0.643]"), "marble", 128,
     {{0.3835, 0.3535, 1.049, 0.97, 0.1359, 0.6559},
      {0.1257, 0.1019, 0.9268, 0.69, 0.09312, 0.9805},
      {0.1281, 0.1041, 0.9368, 0.83, 0.1003, 0.9692}}, 0},
    /* point lights (positions in the mesh's coordinates; the bunny's centre is near [0,4.8,0], its radius
     * about 6): behind the sphere 3 radii from its centre, behind the bunny, and two lights on the bunny,
     * one from behind and one a point in front */
    {BUILTIN, "sphere", "{\"type\":\"point\",\"position\":[0,0,-3],\"intensity\":27}", "skin1", 128,
     {{1, 1, 1, 1.00, 0.01591, 0.0000},
      {0.1712, 0.1716, 0.376, 0.69, 0.1558, 0.9511},
      {0.1309, 0.1278, 0.3364, 0.64, 0.1195, 0.9509}}, 0},
    {BUNNY, "bunny", DIR("[0,0,1]") ",{\"type\":\"point\",\"position\":[8,10,12],\"intensity\":600}", "skin1", 128,
     {{0.09815, 0.2257, 0.8267, 0.36, 0.04961, 0.9586},
      {0.04465, 0.0606, 0.2497, 0.11, 0.03217, 0.9934},
      {0.03575, 0.04506, 0.1591, 0.06, 0.02115, 0.9907}}, 0},
    {BUNNY, "bunny", "{\"type\":\"point\",\"position\":[-4,6,-12],\"intensity\":600}", "marble", 128,
     {{0.9927, 0.9826, 1, 1.00, 0.03894, 0.0103},
      {0.1512, 0.1802, 0.3712, 0.47, 0.07516, 0.9921},
      {0.1607, 0.2328, 0.3563, 0.44, 0.08582, 0.9811}}, 0},
    {BUNNY, "bunny", DIR("[-1,0,0]"), "marble", 512,
     {{0.07996, 0.1505, 0.9508, 0.51, 0.01806, 0.9660},
      {0.04491, 0.05392, 0.6109, 0.45, 0.01307, 0.9717},
      {0.04433, 0.05256, 0.535, 0.44, 0.01307, 0.9694}}, 1},
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
