/* test_support.h - helpers the renderer tests share: render a scene given as JSON, image statistics,
 * and the "N passed, N failed" bookkeeping every test prints. */
#ifndef LUCENT_TEST_SUPPORT_H
#define LUCENT_TEST_SUPPORT_H

#include "lucent.h"
#include "view_frame.h"

#include <stddef.h>

extern int test_passed, test_failed;

/* Prints "ok"/"FAIL" with the description and counts it. Returns ok. */
int test_check(int ok, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Releases the shared device, prints the closing line and returns the process exit code. */
int test_finish(void);

/* Prints the failure (err may be NULL), the closing line with it counted, and ends the run (set-up that
 * cannot go on). */
void test_die(const char *what, const lucent_error *err);

/* A scene with its mesh loaded and its camera and scale resolved, for the CPU integrators' own tests. */
struct test_fixture {
    lucent_scene scene;
    lucent_mesh *mesh;
    struct view_frame camera;
    double scale_mm;
};
/* Parses json (files allowed) and loads its mesh; aborts the run on any error. */
void test_fixture_open(struct test_fixture *f, const char *json);

/* Parses json (files allowed) and renders it; aborts the test run on any error. */
void test_render(lucent_renderer *r, const char *json, lucent_image *out, lucent_stats *stats);
/* The same with material.profile set to `profile` after parsing (the JSON may hold a material of its own). */
void test_render_profile(lucent_renderer *r, const char *json, lucent_profile profile, lucent_image *out,
                         lucent_stats *stats);
/* The profile a render reports it integrated (stats->profile, named in modelled too); aborts when none. */
lucent_profile test_reported_profile(const lucent_stats *stats);
/* Channel c's total diffuse reflectance under profile p: what a plane lit head-on reflects. */
double test_profile_total(const lucent_material *m, lucent_profile p, int c);
lucent_renderer *test_renderer(void);

/* Writes text as /tmp/lucent-NAME-PID.obj into path; aborts the run on failure. */
void test_write_obj(char *path, size_t cap, const char *name, const char *text);
/* Writes a flat square [-1,1]^2 at z = 0 facing +z as an OBJ file; returns its path (static buffer). */
const char *test_write_square_obj(void);

static inline float test_luminance(const float *rgba)
{
    return 0.2126f * rgba[0] + 0.7152f * rgba[1] + 0.0722f * rgba[2];
}

#endif
