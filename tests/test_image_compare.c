/* test_image_compare.c - the error measures on images whose error is known by construction: equal
 * images, a uniform 20% gain, an error confined to the silhouette band, coverage differences. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>

#define W 40
#define H 30

/* A covered disc of radiance (1, 0.5, 0.25); facing falls to 0 at the rim, so the outer ring is
 * the silhouette band. */
static void make_reference(lucent_image *img)
{
    lucent_error err = {0};
    if (lucent_image_alloc(img, W, H, 1, &err) != LUCENT_OK) {
        printf("FAIL alloc: %s\n", err.message);
        return;
    }
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double dx = (x + 0.5 - W / 2.0) / 14.0, dy = (y + 0.5 - H / 2.0) / 14.0, d2 = dx * dx + dy * dy;
            size_t i = (size_t)y * W + x;
            if (d2 >= 1.0)
                continue;
            float *p = &img->rgba[i * 4];
            p[0] = 1.0f, p[1] = 0.5f, p[2] = 0.25f, p[3] = 1.0f;
            img->facing[i] = (float)sqrt(1.0 - d2);
            img->view[i] = 0.0f;
        }
}

static void copy_image(const lucent_image *src, lucent_image *dst)
{
    lucent_error err = {0};
    lucent_image_alloc(dst, src->width, src->height, 1, &err);
    for (int i = 0; i < src->width * src->height; i++) {
        for (int c = 0; c < 4; c++)
            dst->rgba[i * 4 + c] = src->rgba[i * 4 + c];
        dst->facing[i] = src->facing[i];
    }
}

int main(void)
{
    lucent_image ref, test;
    lucent_image_error e;
    lucent_error err = {0};
    make_reference(&ref);
    copy_image(&ref, &test);

    lucent_image_compare(&test, &ref, &e, &err);
    test_check(e.object.pixels > 500 && e.object.rel_l2 == 0.0 && e.object.max_abs == 0.0 && e.band.pixels > 0 && e.band.rel_l2 == 0.0,
               "identical: %d pixels (%d in the band), rel L2 %g, max abs %g", e.object.pixels, e.band.pixels, e.object.rel_l2,
               e.object.max_abs);

    for (int i = 0; i < W * H * 4; i++)
        if (i % 4 != 3)
            test.rgba[i] = ref.rgba[i] * 1.2f;
    lucent_image_compare(&test, &ref, &e, &err);
    test_check(fabs(e.object.rel_l2 - 0.2) < 1e-6 && fabs(e.object.p99_rel - 0.2) < 1e-6 && e.object.share_over_10pct == 1.0 &&
                   fabs(e.object.max_abs - 0.2) < 1e-6 && fabs(e.band.rel_l2 - 0.2) < 1e-6,
               "20%% gain: rel L2 %.6f, p99 %.6f, share >10%% %.3f, max abs %.6f, band rel L2 %.6f", e.object.rel_l2,
               e.object.p99_rel, e.object.share_over_10pct, e.object.max_abs, e.band.rel_l2);

    int band = 0;
    for (int i = 0; i < W * H; i++) {
        for (int c = 0; c < 3; c++)
            test.rgba[i * 4 + c] = ref.rgba[i * 4 + c];
        if (ref.rgba[i * 4 + 3] > 0.0f && ref.facing[i] < 0.342f) {
            test.rgba[i * 4] = 0.0f;   /* the single-image failure: red lost at the silhouette */
            band++;
        }
    }
    lucent_image_compare(&test, &ref, &e, &err);
    test_check(e.band.pixels == band && e.band.share_over_10pct == 1.0 && e.band.rel_l2 > e.object.rel_l2 &&
                   e.object.share_over_10pct < 1.0 && e.object.share_over_10pct > 0.0,
               "error only in the band (%d px): band rel L2 %.4f > whole %.4f; share >10%% band %.2f, whole %.3f",
               band, e.band.rel_l2, e.object.rel_l2, e.band.share_over_10pct, e.object.share_over_10pct);

    test.rgba[3] = 1.0f;              /* corner covered in the test only */
    test.rgba[(W * H / 2 + W / 2) * 4 + 3] = 0.0f;   /* centre uncovered in the test only */
    lucent_image_compare(&test, &ref, &e, &err);
    test_check(e.coverage_mismatch == 2, "coverage differs in %d pixels (2 made)", e.coverage_mismatch);

    char json[1024];
    test_check(lucent_image_error_json(&e, json, sizeof json) > 0 && json[0] == '{', "JSON: %s", json);

    lucent_image small = {0};
    lucent_image_alloc(&small, 8, 8, 0, &err);
    test_check(lucent_image_compare(&small, &ref, &e, &err) == LUCENT_E_INVALID, "size mismatch refused: %s",
               err.message);
    lucent_image_free(&small);
    lucent_image_free(&test);
    lucent_image_free(&ref);
    return test_finish();
}
