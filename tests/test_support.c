/* test_support.c - shared test plumbing; see test_support.h. Failures to set up (no device, bad
 * scene) end the run at once with a message, since every later check would be meaningless. */
#include "test_support.h"
#include "frame_plan.h"
#include "profile.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int test_passed, test_failed;

int test_check(int ok, const char *fmt, ...)
{
    va_list ap;
    printf("%-4s ", ok ? "ok" : "FAIL");
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    putchar('\n');
    ok ? test_passed++ : test_failed++;
    return ok;
}

int test_finish(void)
{
    lucent_shutdown();
    printf("%d passed, %d failed\n", test_passed, test_failed);
    return test_failed != 0;
}

void test_die(const char *what, const lucent_error *err)
{
    if (err)
        fprintf(stderr, "FAIL %s: [%s] %s: %s\n", what, lucent_status_name(err->status), err->field, err->message);
    else
        fprintf(stderr, "FAIL %s\n", what);
    printf("%d passed, %d failed\n", test_passed, test_failed + 1);
    exit(1);
}

lucent_renderer *test_renderer(void)
{
    lucent_error err = {0};
    lucent_renderer_desc desc = {.verbose = 1};
    lucent_renderer *r = lucent_renderer_create(&desc, &err);
    if (!r)
        test_die("renderer", &err);
    /* The OpenGL runs of the image tests (tests/CMakeLists.txt) get there by Vulkan's absence: make sure. */
    const char *expect = getenv("LUCENT_EXPECT_BACKEND");
    printf("renderer: backend %s, device \"%s\"\n", lucent_renderer_backend(r), lucent_renderer_device(r));
    if (expect && strcmp(expect, lucent_renderer_backend(r)) != 0) {
        lucent_fail(&err, LUCENT_E_INTERNAL, "", "expected backend %s, got %s", expect, lucent_renderer_backend(r));
        test_die("renderer", &err);
    }
    return r;
}

/* profile < 0: as parsed. */
static void render_json(lucent_renderer *r, const char *json, int profile, lucent_image *out, lucent_stats *stats)
{
    lucent_scene scene;
    lucent_error err = {0};
    if (lucent_scene_parse(json, strlen(json), 1, &scene, &err) != LUCENT_OK)
        test_die("scene", &err);
    if (profile >= 0)
        scene.material.profile = (lucent_profile)profile;
    if (lucent_render(r, &scene, out, stats, &err) != LUCENT_OK)
        test_die("render", &err);
}

void test_render(lucent_renderer *r, const char *json, lucent_image *out, lucent_stats *stats)
{
    render_json(r, json, -1, out, stats);
}

void test_render_profile(lucent_renderer *r, const char *json, lucent_profile profile, lucent_image *out,
                         lucent_stats *stats)
{
    render_json(r, json, (int)profile, out, stats);
}

lucent_profile test_reported_profile(const lucent_stats *stats)
{
    char key[64];
    snprintf(key, sizeof key, "\"profile\":\"%s\"", lucent_profile_name(stats->profile));
    if (stats->profile == LUCENT_PROFILE_DEFAULT || !strstr(stats->modelled, key))
        test_die("the render reports no profile, or modelled does not name it", NULL);
    return stats->profile;
}

double test_profile_total(const lucent_material *m, lucent_profile p, int c)
{
    struct profile d;
    profile_init(&d, p, m->sigma_a[c], m->sigma_s_prime[c], m->g, m->eta);
    return profile_total(&d);
}

void test_write_obj(char *path, size_t cap, const char *name, const char *text)
{
    snprintf(path, cap, "/tmp/lucent-%s-%d.obj", name, (int)getpid());
    FILE *f = fopen(path, "w");
    if (!f || fputs(text, f) < 0 || fclose(f) != 0) {
        perror(path);
        exit(1);
    }
}

const char *test_write_square_obj(void)
{
    static char path[64];
    test_write_obj(path, sizeof path, "square",
                   "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n");
    return path;
}

void test_fixture_open(struct test_fixture *f, const char *json)
{
    lucent_error err = {0};
    if (lucent_scene_parse(json, strlen(json), 1, &f->scene, &err) != LUCENT_OK)
        test_die("scene", &err);
    const lucent_mesh_ref *m = &f->scene.mesh;
    lucent_status st = m->source == LUCENT_MESH_FILE ? lucent_mesh_import_file(m->file, &f->mesh, &err)
                                                     : lucent_mesh_builtin(m->builtin, m->triangles, &f->mesh, &err);
    if (st != LUCENT_OK)
        test_die("mesh", &err);
    if (frame_camera(&f->scene, f->mesh, &f->camera, &err) != LUCENT_OK)
        test_die("camera", &err);
    f->scale_mm = frame_scale_mm(&f->scene, f->mesh);
}
