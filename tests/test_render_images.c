/* test_render_images.c - renders the sphere and the protrusion shape lit from the camera's right at
 * 90 degrees, with both methods, and checks what any correct translucent image must show, and that
 * frames of other sizes in between change nothing. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define SIZE 96

/* Mean luminance of covered pixels whose normal's x lies in [lo, hi). */
static double band_mean(const lucent_image *img, double lo, double hi, int *count)
{
    double sum = 0.0;
    int n = 0;
    for (int i = 0; i < img->width * img->height; i++) {
        double nx = img->normal[i * 3];
        if (img->rgba[i * 4 + 3] > 0.0f && nx >= lo && nx < hi) {
            sum += test_luminance(&img->rgba[i * 4]);
            n++;
        }
    }
    *count = n;
    return n ? sum / n : 0.0;
}

static void check_finite_and_alpha(const char *name, const lucent_image *img)
{
    int nonfinite = 0, bad_background = 0, bad_cover = 0, covered = 0;
    for (int i = 0; i < img->width * img->height; i++) {
        const float *p = &img->rgba[i * 4];
        for (int c = 0; c < 4; c++)
            nonfinite += !isfinite(p[c]);
        if (img->view[i] < 0.0f)
            bad_background += p[3] != 0.0f || p[0] != 0.0f || p[1] != 0.0f || p[2] != 0.0f;
        else {
            covered++;
            bad_cover += p[3] != 1.0f;
        }
    }
    test_check(nonfinite == 0, "%s: every value finite (%d non-finite)", name, nonfinite);
    test_check(bad_background == 0 && covered > SIZE * SIZE / 8,
               "%s: background alpha 0 and black (%d bad), %d covered pixels", name, bad_background, covered);
    test_check(bad_cover == 0, "%s: covered pixels have alpha 1 (%d bad)", name, bad_cover);
}

static void check_lighting(const char *name, const lucent_image *img)
{
    int n_lit, n_dark;
    double lit = band_mean(img, 0.3, 1.01, &n_lit);
    double dark = band_mean(img, -1.01, -0.3, &n_dark);
    test_check(lit > 2.0 * dark && n_lit > 0 && n_dark > 0,
               "%s: lit side (n.x > 0.3) mean %.4g brighter than unlit side (n.x < -0.3) mean %.4g", name, lit, dark);
    /* Past the terminator (n.x = 0) only scattered light arrives, decaying with distance. */
    int a, b, c;
    double near = band_mean(img, -0.15, -0.02, &a);
    double mid = band_mean(img, -0.45, -0.25, &b);
    double far = band_mean(img, -1.01, -0.8, &c);
    test_check(near > 0.0 && a > 0, "%s: light bleeds past the terminator (mean %.4g just past it)", name, near);
    test_check(near > mid && mid > far, "%s: bleeding decays away from the terminator: %.4g > %.4g > %.4g", name,
               near, mid, far);
}

static void check_exr_aovs(const char *name, const lucent_image *img, int five)
{
    char path[96];
    snprintf(path, sizeof path, "/tmp/lucent-images-%d.exr", (int)getpid());
    lucent_error err = {0};
    const double bg[4] = {0, 0, 0, 0};
    lucent_image back = {0};
    int ok = lucent_image_write(path, img, LUCENT_FORMAT_EXR, 0.0, bg, &err) == LUCENT_OK &&
             lucent_image_load(path, &back, &err) == LUCENT_OK;
    unlink(path);
    if (!test_check(ok && back.depth && back.normal && back.view && back.facing,
                    "%s: EXR has Z, N.X/N.Y/N.Z, view and facing channels %s",
                    name, err.message))
        return;
    int bad = 0, side_views = 0, views_seen = 0;
    for (int i = 0; i < back.width * back.height; i++) {
        int view = (int)back.view[i];
        if (back.rgba[i * 4 + 3] == 0.0f) {
            bad += view != -1 || back.depth[i] != 0.0f;
            continue;
        }
        const float *n = &back.normal[i * 3];
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        bad += fabs(len - 1.0) > 1e-3 || back.depth[i] <= 0.0f || view < 0 || view > 4 || (!five && view != 0) ||
               !(back.facing[i] > -0.05f && back.facing[i] <= 1.0f);
        side_views += view > 0;
        views_seen |= 1 << view;
    }
    test_check(bad == 0, "%s: AOVs sane (unit normals, positive depth, view in range, facing in [0,1]) - %d bad pixels",
               name, bad);
    if (five)
        test_check(side_views > 0, "%s: five-view uses side images (%d pixels, views mask 0x%x)", name,
                   side_views, views_seen);
    lucent_image_free(&back);
}

/* On the sphere every point is visible in the image facing it: a normal pointing to the camera's
 * right must use the right image (2), left the left (1), up the top (3), down the bottom (4). */
static void check_view_choice(const lucent_image *img)
{
    int expected = 0, matched = 0;
    for (int i = 0; i < img->width * img->height; i++) {
        const float *n = &img->normal[i * 3];
        int want = n[0] > 0.8f ? 2 : n[0] < -0.8f ? 1 : n[1] > 0.8f ? 3 : n[1] < -0.8f ? 4 : -1;
        if (img->view[i] < 0.0f || want < 0)
            continue;
        expected++;
        matched += (int)img->view[i] == want;
    }
    test_check(expected > 0 && matched == expected,
               "sphere/five: side-facing pixels use the image facing them (%d of %d)", matched, expected);
}

static void scene_json(char *json, size_t cap, const char *mesh, const char *method, int size, int projection)
{
    snprintf(json, cap,
             "{\"mesh\":{\"builtin\":\"%s\"},\"material\":{\"preset\":\"marble\"},"
             "\"lights\":[{\"type\":\"directional\",\"direction\":[-1,0,0],\"intensity\":3}],"
             ""
             "\"camera\":{\"direction\":[0,0,-1]},"
             "\"width\":%d,\"height\":%d,\"method\":\"%s\",\"projection_size\":%d,\"format\":\"exr\"}",
             mesh, size, size, method, projection);
}

/* The renderer keeps its targets between frames and re-creates only the group whose size changed: a
 * frame after frames of another image size, then another projection size, is the same as the first. */
static void check_size_changes(lucent_renderer *r)
{
    char json[800];
    lucent_image first, img;
    scene_json(json, sizeof json, "sphere", "five", SIZE, 128);
    test_render(r, json, &first, NULL);
    const int sizes[][2] = {{SIZE + 8, 128}, {SIZE, 128}, {SIZE, 64}, {SIZE + 8, 64}, {SIZE, 128}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        scene_json(json, sizeof json, "sphere", "five", sizes[i][0], sizes[i][1]);
        test_render(r, json, &img, NULL);
        if (i + 1 < sizeof sizes / sizeof sizes[0])
            lucent_image_free(&img);
    }
    size_t differ = 0;
    for (size_t k = 0; k < (size_t)SIZE * SIZE * 4; k++)
        differ += memcmp(&first.rgba[k], &img.rgba[k], sizeof(float)) != 0;
    test_check(differ == 0, "sphere/five at %d^2, projection 128, again after %d^2, then projection 64 and "
                            "back: %zu of %d values differ", SIZE, SIZE + 8, differ, SIZE * SIZE * 4);
    lucent_image_free(&img);
    lucent_image_free(&first);
}

static void run(lucent_renderer *r, const char *mesh, const char *method)
{
    char json[800], name[64];
    snprintf(name, sizeof name, "%s/%s", mesh, method);
    scene_json(json, sizeof json, mesh, method, SIZE, 128);
    lucent_image img;
    lucent_stats stats;
    test_render(r, json, &img, &stats);
    printf("     %s: scatter %.2f ms, projection %.2f ms, total %.2f ms\n", name, stats.ms_scatter,
           stats.ms_projection, stats.ms_total);
    check_finite_and_alpha(name, &img);
    check_lighting(name, &img);
    check_exr_aovs(name, &img, strcmp(method, "five") == 0);
    if (strcmp(mesh, "sphere") == 0 && strcmp(method, "five") == 0)
        check_view_choice(&img);
    lucent_image_free(&img);
}

int main(void)
{
    lucent_renderer *r = test_renderer();
    const char *meshes[] = {"sphere", "protrusion"};
    for (int m = 0; m < 2; m++) {
        run(r, meshes[m], "five");
        run(r, meshes[m], "single");
    }
    check_size_changes(r);
    lucent_renderer_destroy(r);
    return test_finish();
}
