/* test_fast_vs_reference.c - the image-space methods scored against method "reference" on small
 * images: the error measures are printed, and a loose bound catches a method that goes wrong. */
#include "test_support.h"

#include <stdio.h>

/* Relative L2 over the object. Measured when this test was written: 0.02-0.09, but 0.18-0.19 for
 * ketchup with shared sampling (its channels' kernels differ tenfold; 16 shared samples cover red
 * thinly). A regression guard, not the accuracy claim: that is the trade benchmark's. */
#define BOUND 0.25

static void score(lucent_renderer *r, const char *mesh, const char *light, const char *material)
{
    char base[600], json[800];
    snprintf(base, sizeof base,
             "\"mesh\":{\"builtin\":\"%s\"},\"material\":{\"preset\":\"%s\"},\"lights\":[{\"direction\":%s,"
             "\"intensity\":3}],\"width\":64,\"height\":64,\"format\":\"exr\"",
             mesh, material, light);
    snprintf(json, sizeof json, "{%s,\"method\":\"reference\"}", base);
    lucent_image ref;
    test_render(r, json, &ref, NULL);
    const char *modes[] = {"\"method\":\"single\"", "\"method\":\"five\"",
                           "\"method\":\"five\",\"sampling\":\"per_channel\""};
    for (int m = 0; m < 3; m++) {
        snprintf(json, sizeof json, "{%s,%s}", base, modes[m]);
        lucent_image img;
        lucent_image_error e;
        lucent_error err = {0};
        test_render(r, json, &img, NULL);
        lucent_status st = lucent_image_compare(&img, &ref, &e, &err);
        test_check(st == LUCENT_OK && e.object.rel_l2 < BOUND && e.coverage_mismatch <= e.object.pixels / 50,
                   "%-10s %-8s light %-9s {%s}: rel L2 %.4f (band %.4f over %d px), p99 rel %.3f, "
                   ">10%% %.2f, coverage mismatch %d",
                   mesh, material, light, modes[m], e.object.rel_l2, e.band.rel_l2, e.band.pixels, e.object.p99_rel,
                   e.object.share_over_10pct, e.coverage_mismatch);
        lucent_image_free(&img);
    }
    lucent_image_free(&ref);
}

int main(void)
{
    lucent_renderer *r = test_renderer();
    score(r, "sphere", "[0,0,-1]", "skin1");
    score(r, "sphere", "[-1,0,0]", "marble");
    score(r, "protrusion", "[-1,0,0]", "marble");
    score(r, "protrusion", "[-1,0,0]", "ketchup");
    lucent_renderer_destroy(r);
    return test_finish();
}
