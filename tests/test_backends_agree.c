/* test_backends_agree.c - the OpenGL backend renders what the Vulkan backend renders: every shader variant
 * the test scenes reach (single, five, auto, light views, proxies, block sizes, fallbacks, single scattering,
 * per-channel sampling, open and culled meshes), within relative L2 0.5% of the Vulkan image, AOVs alike. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Same algorithm, same LLVM underneath on a CPU: only rounding differs (issue 15's bar). */
#define MAX_REL_L2 0.005
/* The AOVs come from the same G-buffer pass: depth and normals to float rounding. */
#define MAX_AOV_DIFF 1e-3

static lucent_renderer *open_backend(const char *backend)
{
    lucent_error err = {0};
    lucent_renderer_desc desc = {.backend = backend};
    lucent_renderer *r = lucent_renderer_create(&desc, &err);
    if (!r) {
        printf("FAIL cannot open backend %s: %s\n", backend, err.message);
        printf("%d passed, %d failed\n", test_passed, test_failed + 1);
        exit(1);
    }
    printf("%s: %s\n", backend, lucent_renderer_device(r));
    return r;
}

/* Largest difference of the depth and normal AOVs over pixels both cover. */
static double aov_difference(const lucent_image *a, const lucent_image *b)
{
    double worst = 0.0;
    size_t pixels = (size_t)a->width * a->height;
    for (size_t i = 0; i < pixels; i++) {
        if (a->view[i] < 0.0f || b->view[i] < 0.0f)
            continue;
        double d = fabs(a->depth[i] - b->depth[i]) / fmax(fabs(a->depth[i]), 1.0);
        for (int c = 0; c < 3; c++)
            d = fmax(d, fabs(a->normal[i * 3 + c] - b->normal[i * 3 + c]));
        worst = fmax(worst, d);
    }
    return worst;
}

static void agree(lucent_renderer *vk, lucent_renderer *gl, const char *name, const char *json)
{
    lucent_image a = {0}, b = {0};
    lucent_stats sa, sb;
    lucent_error err = {0};
    lucent_image_error e;
    test_render(vk, json, &a, &sa);
    test_render(gl, json, &b, &sb);
    if (lucent_image_compare(&b, &a, &e, &err) != LUCENT_OK) {
        test_check(0, "%s: compare: %s", name, err.message);
    } else {
        double aov = aov_difference(&a, &b);
        test_check(e.object.rel_l2 <= MAX_REL_L2 && e.coverage_mismatch <= a.width * a.height / 1000 &&
                       aov <= MAX_AOV_DIFF && strcmp(sa.backend, "vulkan") == 0 && strcmp(sb.backend, "gl") == 0,
                   "%-34s rel L2 %.2e (<= %.3f), max abs %.2e, mean ratio %.6f, %d pixels covered in one only, "
                   "AOVs %.1e; ms %.0f (vulkan) %.0f (gl)",
                   name, e.object.rel_l2, MAX_REL_L2, e.object.max_abs, e.mean_ratio, e.coverage_mismatch, aov,
                   sa.ms_total, sb.ms_total);
    }
    lucent_image_free(&a);
    lucent_image_free(&b);
}

int main(void)
{
    char square[1024], json[2048];
    snprintf(square, sizeof square, "%s", test_write_square_obj());
    lucent_renderer *vk = open_backend("vulkan");
    lucent_renderer *gl = open_backend("gl");
    static const struct {
        const char *name, *json;
    } scenes[] = {
        {"five, bunny, side light", "{\"mesh\":{\"builtin\":\"bunny\"},\"material\":{\"preset\":\"skin1\"},"
                                    "\"width\":200,\"height\":200,\"format\":\"exr\",\"lights\":[{\"direction\":"
                                    "[-1,0,-0.3],\"intensity\":3}]}"},
        {"single, sphere", "{\"mesh\":{\"builtin\":\"sphere\"},\"material\":{\"preset\":\"marble\"},\"width\":160,"
                           "\"height\":120,\"method\":\"single\",\"format\":\"exr\"}"},
        {"auto, back and point light", "{\"mesh\":{\"builtin\":\"bunny\"},\"material\":{\"preset\":\"ketchup\"},"
                                       "\"width\":256,\"height\":256,\"method\":\"auto\",\"format\":\"exr\",\"lights\":"
                                       "[{\"direction\":[0,0,1],\"intensity\":2},{\"type\":\"point\",\"position\":"
                                       "[0.5,1,1],\"intensity\":3}],\"camera\":{\"direction\":[0,0,-1]}}"},
        {"five, two light views", "{\"mesh\":{\"builtin\":\"protrusion\"},\"material\":{\"preset\":\"skimmilk\"},"
                                  "\"width\":128,\"height\":128,\"format\":\"exr\",\"camera\":{\"direction\":[0,0,-1]},"
                                  "\"lights\":[{\"direction\":[0.2,0,1],\"intensity\":2},{\"direction\":[-0.2,0.1,1],"
                                  "\"intensity\":2}]}"},
        {"per-channel samples, projection 256", "{\"mesh\":{\"builtin\":\"protrusion\"},\"material\":{\"preset\":"
                                                "\"wholemilk\"},\"width\":96,\"height\":64,\"format\":\"exr\","
                                                "\"projection_size\":256,\"samples\":8,\"sampling\":\"per_channel\"}"},
        {"single scattering, two lights", "{\"mesh\":{\"builtin\":\"torus\"},\"material\":{\"preset\":\"apple\"},"
                                          "\"width\":128,\"height\":128,\"format\":\"exr\",\"single_scattering\":true,"
                                          "\"lights\":[{\"direction\":[0.3,-1,0.5],\"intensity\":2},{\"direction\":"
                                          "[0,0,1],\"intensity\":2}]}"},
        {"front fallback", "{\"mesh\":{\"builtin\":\"torus\"},\"material\":{\"preset\":\"skin2\"},\"width\":120,"
                           "\"height\":120,\"format\":\"exr\",\"fallback\":\"front\"}"},
        {"dense sphere (proxies), blocks of 4", "{\"mesh\":{\"builtin\":\"sphere\",\"triangles\":300000},\"material\":"
                                                "{\"preset\":\"marble\"},\"width\":400,\"height\":340,\"format\":\"exr\","
                                                "\"projection_size\":256}"},
        {"blocks of 1, four lights", "{\"mesh\":{\"builtin\":\"protrusion\"},\"material\":{\"preset\":\"chicken1\"},"
                                     "\"width\":64,\"height\":64,\"format\":\"exr\",\"lights\":[{\"direction\":[1,0,0]},"
                                     "{\"direction\":[0,-1,0]},{\"type\":\"point\",\"position\":[0,0,2],\"intensity\":4},"
                                     "{\"direction\":[-1,-1,-1],\"color\":[1,0.5,0.2]}]}"},
    };
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++)
        agree(vk, gl, scenes[i].name, scenes[i].json);
    /* An open sheet, lit from behind and from the front: no culling, back faces drawn and flipped. */
    snprintf(json, sizeof json,
             "{\"mesh\":{\"file\":\"%s\"},\"material\":{\"preset\":\"skin1\"},\"width\":96,\"height\":96,"
             "\"format\":\"exr\",\"camera\":{\"direction\":[0.3,0.2,-1]},\"lights\":[{\"direction\":[0,0,1]},"
             "{\"direction\":[0.2,0,-1]}]}",
             square);
    agree(vk, gl, "open square, both sides lit", json);
    lucent_renderer_destroy(vk);
    lucent_renderer_destroy(gl);
    remove(square);
    return test_finish();
}
