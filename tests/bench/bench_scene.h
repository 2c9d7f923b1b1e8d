/* bench_scene.h - the cases the accuracy benchmarks share: a scene document per mesh, material and
 * directional light, the OBJ files they write, and tables printed and written at once. Header-only. */
#ifndef LUCENT_BENCH_SCENE_H
#define LUCENT_BENCH_SCENE_H

#include "lucent.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

struct mesh_case {
    const char *name;
    const char *json;      /* mesh object; NULL: an OBJ file, given to bench_scene */
    const char *fragment;  /* scene fragment ending in a comma ("\"scale_mm\":50,"), or "" */
};
struct light_case {
    const char *name;
    const char *direction;  /* the way the light travels; the camera looks along -Z from +Z (but the cube's) */
};

/* The scene of mesh m (or the OBJ at `file` when m->json is NULL) in a material preset under one
 * directional light of intensity 3, size x size pixels, plus `fragment` ("method" and knobs). The
 * file's path is set after parsing, so no path needs JSON escaping. */
static lucent_status bench_scene(const struct mesh_case *m, const char *file, const char *material,
                                 const struct light_case *light, int size, const char *fragment, lucent_scene *s,
                                 lucent_error *err)
{
    char json[1024];
    int n = snprintf(json, sizeof json,
                     "{\"mesh\":%s,\"material\":{\"preset\":\"%s\"},\"lights\":[{\"direction\":%s,\"intensity\":3}],"
                     "%s\"width\":%d,\"height\":%d,%s%s}",
                     m->json ? m->json : "{\"builtin\":\"sphere\"}", material, light->direction,
                     strstr(m->fragment, "\"camera\"") ? "" : "\"camera\":{\"direction\":[0,0,-1]},", size, size,
                     m->fragment, fragment);
    if (n < 0 || (size_t)n >= sizeof json)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "scene document too long");
    lucent_status st = lucent_scene_parse(json, (size_t)n, 1, s, err);
    if (st != LUCENT_OK || m->json)
        return st;
    s->mesh.source = LUCENT_MESH_FILE;
    snprintf(s->mesh.file, sizeof s->mesh.file, "%s", file);
    return LUCENT_OK;
}

/* Writes `text` beside the outputs as PREFIX_NAME.obj, its path in path (kept: it is the mesh the
 * report's rows rendered); -1 with the reason on stderr. */
static int bench_write_obj(const char *prefix, const char *name, const char *text, char *path, size_t cap)
{
    snprintf(path, cap, "%s_%s.obj", prefix, name);
    FILE *f = fopen(path, "w");
    if (!f || fputs(text, f) == EOF || fclose(f) != 0) {
        perror(path);
        return -1;
    }
    return 0;
}

/* Opens PREFIX + suffix[i] for writing into files[i], i < n; -1 with the reason on stderr. */
static int bench_open_files(const char *prefix, const char *const *suffix, FILE **files, int n)
{
    char path[4096];
    for (int i = 0; i < n; i++) {
        snprintf(path, sizeof path, "%s%s", prefix, suffix[i]);
        if (!(files[i] = fopen(path, "w"))) {
            perror(path);
            return -1;
        }
    }
    return 0;
}

/* Closes every file opened (NULL: skipped); -1 if any failed to write or close. */
static int bench_close_files(FILE *const *files, int n)
{
    int rc = 0;
    for (int i = 0; i < n; i++)
        if (files[i] && (ferror(files[i]) | fclose(files[i])))
            rc = -1;
    return rc;
}

/* -1 (with the path on stderr) when a mesh file's path does not fit a scene's mesh reference. */
static int bench_paths_fit(const char *const *files, int n, const char *program)
{
    for (int i = 0; i < n; i++)
        if (files[i] && strlen(files[i]) >= sizeof(((lucent_mesh_ref *)0)->file)) {
            fprintf(stderr, "%s: mesh path too long: %s\n", program, files[i]);
            return -1;
        }
    return 0;
}

/* Prints to stdout and writes to md. */
#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static void emit(FILE *md, const char *fmt, ...)
{
    va_list a, b;
    va_start(a, fmt);
    va_copy(b, a);
    vfprintf(stdout, fmt, a);
    vfprintf(md, fmt, b);
    va_end(b);
    va_end(a);
}

#endif
