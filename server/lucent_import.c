/* lucent_import.c - lucent-import: converts one mesh upload (bytes on stdin) to the compact form on
 * fd 3. It runs assimp on hostile bytes: the daemon starts it limited, and it seals itself in seccomp. */
#include "importer_seccomp.h"
#include "lucent.h"
#include "mesh_bundle.h"
#include "mesh.h"
#include "mesh_compact.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define USAGE "usage: lucent-import --format obj|ply|stl|gltf|glb|bundle [--max-triangles N] < MESH 3> OUT.lmesh"
#define OUT_FD 3
#define EXIT_REFUSED 2

/* One JSON line on stdout: the failure, then exit status 2. */
static int refuse(const lucent_error *e)
{
    json_t *doc = json_pack("{s:s, s:s, s:s}", "status", lucent_status_name(e->status), "field", e->field,
                            "message", e->message);
    char *line = doc ? json_dumps(doc, JSON_COMPACT) : NULL;
    /* json_pack refuses text that is not UTF-8; the status alone still tells the caller what failed */
    printf("%s\n", line ? line : "{\"status\":\"internal\",\"field\":\"\",\"message\":\"unprintable error\"}");
    free(line);
    json_decref(doc);
    return EXIT_REFUSED;
}

typedef struct options {
    const char *format;
    unsigned long max_triangles;
} options;

static lucent_status parse_args(int argc, char **argv, options *o, lucent_error *err)
{
    *o = (options){NULL, LUCENT_MAX_TRIANGLES};
    for (int i = 1; i < argc; i += 2) {
        if (i + 1 >= argc)
            return lucent_fail(err, LUCENT_E_INVALID, argv[i], "missing value; " USAGE);
        const char *name = argv[i], *value = argv[i + 1];
        char *end;
        if (strcmp(name, "--format") == 0) {
            o->format = value;
        } else if (strcmp(name, "--max-triangles") == 0) {
            o->max_triangles = strtoul(value, &end, 10);
            if (o->max_triangles == 0 || *end)
                return lucent_fail(err, LUCENT_E_INVALID, name, "must be a positive integer");
        } else {
            return lucent_fail(err, LUCENT_E_INVALID, name, "unknown option; " USAGE);
        }
    }
    if (!o->format)
        return lucent_fail(err, LUCENT_E_INVALID, "", USAGE);
    return LUCENT_OK;
}

/* The whole of stdin in a malloc'd buffer; its size is bounded by the caller's address-space limit. */
static lucent_status read_stdin(unsigned char **data, size_t *len, lucent_error *err)
{
    size_t cap = 1 << 16, n = 0;
    unsigned char *buf = malloc(cap);
    for (;;) {
        if (buf && n == cap) {
            unsigned char *bigger = cap <= SIZE_MAX / 2 ? realloc(buf, cap * 2) : NULL;
            if (!bigger)
                free(buf);
            buf = bigger;
            cap *= 2;
        }
        if (!buf)
            return lucent_fail(err, LUCENT_E_NOMEM, "mesh", "out of memory reading the upload");
        size_t got = fread(buf + n, 1, cap - n, stdin);
        n += got;
        if (got == 0)
            break;
    }
    if (ferror(stdin)) {
        free(buf);
        return lucent_fail(err, LUCENT_E_IO, "mesh", "could not read the upload from standard input");
    }
    *data = buf;
    *len = n;
    return LUCENT_OK;
}

static lucent_status write_compact(const struct lucent_mesh *m, FILE *f, lucent_error *err)
{
    lucent_status st = mesh_compact_write(m, f, err);
    if (fflush(f) != 0 && st == LUCENT_OK)
        st = lucent_fail(err, lucent_io_status(errno), "", "could not write the mesh to fd 3: %s", strerror(errno));
    return st;
}

/* Whatever would open a file or ask the kernel for more than the filter allows is done first: the
 * output stream (fdopen checks the descriptor's mode) and jansson's hash seed (read from /dev/urandom). */
static lucent_status seal(FILE **out, lucent_error *err)
{
    *out = fdopen(OUT_FD, "wb");
    if (!*out)
        return lucent_fail(err, LUCENT_E_INVALID, "", "fd 3 is not open for writing; " USAGE);
    json_object_seed(0);
    return importer_seccomp_enter(err);
}

/* A bundle is decoded and checked again here (mesh_bundle_import): the daemon's encoding is not trusted. */
static lucent_status import_upload(const unsigned char *data, size_t len, const char *format, lucent_mesh **m,
                                   lucent_error *err)
{
    return strcmp(format, "bundle") == 0 ? mesh_bundle_import(data, len, m, err)
                                         : lucent_mesh_import_memory(data, len, format, m, err);
}

/* Prints the success line; bounds are put back into the upload's coordinates. */
static lucent_status report(const struct lucent_mesh *m, lucent_error *err)
{
    double lo[3], hi[3];
    mesh_bounds(m, lo, hi);
    json_t *doc = json_pack("{s:I, s:I, s:{s:[fff], s:[fff]}}", "triangles", (json_int_t)m->triangle_count,
                            "vertices", (json_int_t)m->vertex_count, "bounds", "min", lo[0], lo[1], lo[2], "max",
                            hi[0], hi[1], hi[2]);
    char *line = doc ? json_dumps(doc, JSON_COMPACT | JSON_REAL_PRECISION(17)) : NULL;
    int printed = line && printf("%s\n", line) > 0;
    free(line);
    json_decref(doc);
    return printed ? LUCENT_OK : lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory writing the answer");
}

int main(int argc, char **argv)
{
    options o;
    lucent_error err = {0};
    unsigned char *data = NULL;
    size_t len = 0;
    lucent_mesh *m = NULL;
    FILE *out = NULL;
    if (parse_args(argc, argv, &o, &err) != LUCENT_OK || seal(&out, &err) != LUCENT_OK ||
        read_stdin(&data, &len, &err) != LUCENT_OK)
        return refuse(&err);
    lucent_status st = import_upload(data, len, o.format, &m, &err);
    free(data);
    if (st == LUCENT_OK && m->triangle_count > o.max_triangles)
        st = lucent_fail(&err, LUCENT_E_LIMIT, "mesh", "the mesh has %u triangles; at most %lu are accepted",
                         m->triangle_count, o.max_triangles);
    if (st == LUCENT_OK)
        st = write_compact(m, out, &err);
    if (st == LUCENT_OK)
        st = report(m, &err);
    lucent_mesh_free(m);
    return st == LUCENT_OK ? 0 : refuse(&err);
}
