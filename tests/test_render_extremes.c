/* test_render_extremes.c - renders at the edges of every material and scale parameter, with both
 * methods and samplings: every value must be finite and non-negative. (The error of each case
 * against the reference integrator is the next issue's matrix.) */
#include "test_support.h"

#include <math.h>
#include <stdio.h>

static const char *const cases[] = {
    "\"material\":{\"preset\":\"spectralon\"}",
    "\"material\":{\"sigma_a\":[0,0,0],\"sigma_s_prime\":[1e-6,1e-6,1e-6],\"eta\":1.0}",
    "\"material\":{\"sigma_a\":[1e5,1e5,1e5],\"sigma_s_prime\":[1e-6,1e-6,1e-6]}",
    "\"material\":{\"sigma_a\":[0.01,0.01,0.01],\"sigma_s_prime\":[1e4,1e4,1e4],\"eta\":3.0}",
    "\"material\":{\"sigma_a\":[1e-4,1,1e4],\"sigma_s_prime\":[1e-4,1,1e4],\"eta\":1.0001}",
    "\"scale_mm\":1e-6,\"material\":{\"preset\":\"ketchup\"}",
    "\"scale_mm\":1e9,\"material\":{\"preset\":\"cream\"}",
    "\"lights\":[{\"direction\":[-1,0,0],\"intensity\":1e12}]",
    "\"lights\":[{\"direction\":[0,0,-1],\"intensity\":1e-6,\"color\":[1e-6,0,1e6]}]",
    "\"lights\":[{\"type\":\"point\",\"position\":[0,0,0]},{\"type\":\"point\",\"position\":[1e6,0,0],"
    "\"intensity\":1e12},{\"direction\":[1,-1,0]},{\"direction\":[0,1e-300,-1]}]",
    "\"camera\":{\"position\":[0,0,0.1],\"target\":[0,0,-1]}",
    "\"camera\":{\"position\":[0,0,1e6],\"target\":[0,0,0],\"fov_deg\":1.0001}",
    "\"mesh\":{\"builtin\":\"torus\",\"triangles\":1000},\"samples\":1,\"projection_size\":16",
};

static void check_case(lucent_renderer *r, const char *fields, const char *method, const char *sampling)
{
    char json[1024];
    snprintf(json, sizeof json, "{%s,\"width\":48,\"height\":48,\"projection_size\":%s,\"method\":\"%s\","
             "\"sampling\":\"%s\"}", fields, "64", method, sampling);
    /* The last case sets its own projection size. */
    if (fields == cases[sizeof cases / sizeof cases[0] - 1])
        snprintf(json, sizeof json, "{%s,\"width\":48,\"height\":48,\"method\":\"%s\",\"sampling\":\"%s\"}",
                 fields, method, sampling);
    lucent_image img;
    test_render(r, json, &img, NULL);
    int bad = 0, covered = 0;
    double peak = 0.0;
    for (int i = 0; i < img.width * img.height * 4; i++) {
        float v = img.rgba[i];
        bad += !isfinite(v) || v < 0.0f;
        if (isfinite(v) && i % 4 != 3)
            peak = fmax(peak, v);
        covered += i % 4 == 3 && v > 0.0f;
    }
    test_check(bad == 0, "%-6s %-11s {%.60s...}: %d bad values, %d covered pixels, peak %.3g", method, sampling,
               fields, bad, covered, peak);
    lucent_image_free(&img);
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
    lucent_image_free(&img);
}

int main(void)
{
    lucent_renderer *r = test_renderer();
    check_hand_built(r);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        check_case(r, cases[i], "five", "shared");
        check_case(r, cases[i], "single", "per_channel");
    }
    lucent_renderer_destroy(r);
    return test_finish();
}
