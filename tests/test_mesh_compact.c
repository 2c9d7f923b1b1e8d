/* test_mesh_compact.c - the compact mesh form: bit-exact round trips (in memory and through
 * lucent_mesh_import_file), and damaged files refused with a message, never a crash. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* open_memstream */
#endif

#include "lucent.h"
#include "mesh.h"
#include "mesh_compact.h"
#include "test_support.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define HEADER 56 /* offsets from the layout in mesh_compact.h */
#define OFF_VERSION 8
#define OFF_FLAGS 12
#define OFF_VERTICES 16
#define OFF_TRIANGLES 20
#define OFF_RADIUS 48

static double seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The compact bytes of m in a malloc'd buffer. */
static unsigned char *encode(const struct lucent_mesh *m, size_t *len)
{
    char *buf = NULL;
    FILE *f = open_memstream(&buf, len);
    lucent_error err = {0};
    lucent_status st = f ? mesh_compact_write(m, f, &err) : LUCENT_E_IO;
    if (f)
        fclose(f);
    if (st != LUCENT_OK) {
        test_check(0, "encode: %s", err.message);
        free(buf);
        return NULL;
    }
    return (unsigned char *)buf;
}

static void reseal(unsigned char *buf, size_t len)
{
    uint64_t sum = mesh_compact_checksum(buf, len - 8);
    memcpy(buf + len - 8, &sum, 8);
}

static int same_mesh(const struct lucent_mesh *a, const struct lucent_mesh *b)
{
    size_t vb = 12 * (size_t)a->vertex_count, ib = 12 * (size_t)a->triangle_count;
    return a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count &&
           memcmp(a->positions, b->positions, vb) == 0 && memcmp(a->normals, b->normals, vb) == 0 &&
           memcmp(a->indices, b->indices, ib) == 0 && memcmp(a->center, b->center, sizeof a->center) == 0 &&
           memcmp(&a->radius, &b->radius, sizeof a->radius) == 0 && a->convex == b->convex &&
           a->closed == b->closed;
}

static void check_round_trip(const char *what, struct lucent_mesh *m)
{
    size_t len = 0;
    double t0 = seconds();
    unsigned char *buf = encode(m, &len);
    double t1 = seconds();
    if (!buf)
        return;
    struct lucent_mesh *back = NULL;
    lucent_error err = {0};
    lucent_status st = mesh_compact_read(buf, len, &back, &err);
    double t2 = seconds();
    test_check(st == LUCENT_OK && back && same_mesh(m, back) && len == mesh_compact_size(m->vertex_count, m->triangle_count),
               "%s: %u triangles, %u vertices, convex %d, closed %d -> %zu bytes (%.1f per triangle), bit-exact "
               "round trip; write %.1f ms, read+validate %.1f ms %s",
               what, m->triangle_count, m->vertex_count, m->convex, m->closed, len,
               (double)len / m->triangle_count, 1e3 * (t1 - t0), 1e3 * (t2 - t1), err.message);
    lucent_mesh_free(back);
    free(buf);
}

static void check_round_trips(void)
{
    static const struct {
        const char *name;
        uint32_t triangles;
    } builtins[] = {{"sphere", 0}, {"torus", 0}, {"protrusion", 0}, {"sphere", 1000000}};
    for (size_t i = 0; i < sizeof builtins / sizeof builtins[0]; i++) {
        struct lucent_mesh *m = NULL;
        lucent_error err = {0};
        char what[64];
        snprintf(what, sizeof what, "builtin %s/%u", builtins[i].name, builtins[i].triangles);
        if (!test_check(lucent_mesh_builtin(builtins[i].name, builtins[i].triangles, &m, &err) == LUCENT_OK,
                        "%s builds: %s", what, err.message))
            continue;
        check_round_trip(what, m);
        lucent_mesh_free(m);
    }
    /* an open mesh from an importer, far from the origin */
    static const char quad[] = "v 1000 0 5\nv 1001 0 5\nv 1001 1 5\nv 1000 1 5\nf 1 2 3 4\n";
    struct lucent_mesh *m = NULL;
    lucent_error err = {0};
    if (test_check(lucent_mesh_import_memory(quad, strlen(quad), "obj", &m, &err) == LUCENT_OK, "OBJ quad imports"))
        check_round_trip("OBJ quad", m);
    lucent_mesh_free(m);
    /* Coordinates of subnormal size (multiples of FLT_TRUE_MIN): centring rounds them by up to half that
     * spacing, more than any relative tolerance allows, and the reader refused what lucent-import had
     * written (found by fuzz_import; tests/fuzz/corpus/import/subnormal_extent.stl). */
    const float u = FLT_TRUE_MIN, tiny[9] = {256 * u, 0, 7 * u, 0, 0, 0, 0, 0, 63 * u};
    if (!(m = mesh_alloc(3, 1, 0)))
        return (void)test_check(0, "out of memory");
    memcpy(m->positions, tiny, sizeof tiny);
    for (uint32_t k = 0; k < 3; k++)
        m->indices[k] = k;
    if (test_check(mesh_finish(m, &err) == LUCENT_OK, "a triangle of subnormal size finishes: %s", err.message))
        check_round_trip("subnormal triangle", m);
    lucent_mesh_free(m);
}

/* lucent_mesh_import_file recognizes the magic, whatever the extension; .lmesh needs the magic. */
static void check_import_file(void)
{
    struct lucent_mesh *m = NULL, *back = NULL;
    lucent_error err = {0};
    size_t len = 0;
    if (lucent_mesh_builtin("torus", 0, &m, &err) != LUCENT_OK)
        return (void)test_check(0, "torus: %s", err.message);
    unsigned char *buf = encode(m, &len);
    char path[2][64];
    snprintf(path[0], sizeof path[0], "/tmp/lucent_compact_%ld.lmesh", (long)getpid());
    snprintf(path[1], sizeof path[1], "/tmp/lucent_compact_%ld.obj", (long)getpid());
    for (int i = 0; buf && i < 2; i++) {
        FILE *f = fopen(path[i], "wb");
        int written = f && fwrite(buf, 1, len, f) == len;
        if (f)
            fclose(f);
        lucent_status st = written ? lucent_mesh_import_file(path[i], &back, &err) : LUCENT_E_IO;
        test_check(st == LUCENT_OK && same_mesh(m, back), "lucent_mesh_import_file(%s) reads the compact form: %s",
                   path[i], st == LUCENT_OK ? "identical" : err.message);
        lucent_mesh_free(back);
        back = NULL;
    }
    FILE *f = fopen(path[0], "wb");
    if (f) {
        fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", f);
        fclose(f);
    }
    lucent_status st = lucent_mesh_import_file(path[0], &back, &err);
    test_check(st == LUCENT_E_MESH && !back && strstr(err.message, "magic"), "an OBJ named .lmesh: %s: %s",
               lucent_status_name(st), err.message);
    unlink(path[0]);
    unlink(path[1]);
    free(buf);
    lucent_mesh_free(m);
}

/* ---- damage ---- */

static void expect_refused(const char *what, const unsigned char *buf, size_t len, lucent_status status,
                           const char *message_part)
{
    struct lucent_mesh *m = NULL;
    lucent_error err = {0};
    lucent_status st = mesh_compact_read(buf, len, &m, &err);
    test_check(st == status && !m && strstr(err.message, message_part) && strcmp(err.field, "mesh.file") == 0,
               "%s: %s, \"%s\"", what, lucent_status_name(st), err.message);
    lucent_mesh_free(m);
}

static void put_u32(unsigned char *buf, size_t off, uint32_t v)
{
    memcpy(buf + off, &v, 4);
}

static void put_f32(unsigned char *buf, size_t off, float v)
{
    memcpy(buf + off, &v, 4);
}

static void put_f64(unsigned char *buf, size_t off, double v)
{
    memcpy(buf + off, &v, 8);
}

/* Applies edit to a copy, reseals it, and expects the reader to refuse it. */
#define EXPECT_EDITED(what, status, part, edit)               \
    do {                                                      \
        memcpy(copy, good, len);                              \
        edit;                                                 \
        reseal(copy, len);                                    \
        expect_refused(what, copy, len, status, part);        \
    } while (0)

static void check_damage(void)
{
    struct lucent_mesh *m = NULL;
    lucent_error err = {0};
    size_t len = 0;
    if (lucent_mesh_builtin("sphere", 1000, &m, &err) != LUCENT_OK)
        return (void)test_check(0, "sphere: %s", err.message);
    unsigned char *good = encode(m, &len), *copy = malloc(len + 1);
    size_t positions = HEADER, normals = HEADER + 12 * (size_t)m->vertex_count;
    size_t indices = HEADER + 24 * (size_t)m->vertex_count;
    if (!good || !copy)
        goto done;
    printf("     damaging a %zu-byte compact sphere (%u vertices, %u triangles)\n", len, m->vertex_count,
           m->triangle_count);

    size_t cuts[] = {0, 7, 8, 40, HEADER + 7, len / 2, len - 8, len - 1};
    for (size_t i = 0; i < sizeof cuts / sizeof cuts[0]; i++) {
        char what[64];
        snprintf(what, sizeof what, "truncated to %zu bytes", cuts[i]);
        expect_refused(what, good, cuts[i], LUCENT_E_IO, cuts[i] < 8 ? "magic" : cuts[i] < 64 ? "shorter" : "bytes");
    }
    memcpy(copy, good, len);
    copy[len] = 0;
    expect_refused("one byte appended", copy, len + 1, LUCENT_E_IO, "take");

    memcpy(copy, good, len);
    copy[positions + 5] ^= 0x10;
    expect_refused("one position byte flipped", copy, len, LUCENT_E_IO, "checksum");
    memcpy(copy, good, len);
    copy[len - 1] ^= 0x01;
    expect_refused("checksum byte flipped", copy, len, LUCENT_E_IO, "checksum");
    memcpy(copy, good, len);
    copy[0] = 'X';
    expect_refused("wrong magic", copy, len, LUCENT_E_IO, "magic");

    EXPECT_EDITED("version 2", LUCENT_E_IO, "version 2", put_u32(copy, OFF_VERSION, 2));
    EXPECT_EDITED("unknown flag bit", LUCENT_E_IO, "flags", put_u32(copy, OFF_FLAGS, 4));
    EXPECT_EDITED("index out of range", LUCENT_E_IO, "refers to vertex",
                  put_u32(copy, indices + 4 * 7, m->vertex_count));
    EXPECT_EDITED("index 0xffffffff", LUCENT_E_IO, "refers to vertex", put_u32(copy, indices, UINT32_MAX));
    EXPECT_EDITED("4294967295 triangles", LUCENT_E_LIMIT, "at most", put_u32(copy, OFF_TRIANGLES, UINT32_MAX));
    EXPECT_EDITED("LUCENT_MAX_TRIANGLES + 1 triangles", LUCENT_E_LIMIT, "at most",
                  put_u32(copy, OFF_TRIANGLES, LUCENT_MAX_TRIANGLES + 1));
    EXPECT_EDITED("4294967295 vertices", LUCENT_E_IO, "vertices for", put_u32(copy, OFF_VERTICES, UINT32_MAX));
    EXPECT_EDITED("LUCENT_MAX_TRIANGLES triangles in a small file", LUCENT_E_IO, "take",
                  put_u32(copy, OFF_TRIANGLES, LUCENT_MAX_TRIANGLES));
    EXPECT_EDITED("zero triangles", LUCENT_E_IO, "vertices for", put_u32(copy, OFF_TRIANGLES, 0));
    EXPECT_EDITED("NaN coordinate", LUCENT_E_IO, "not a finite point", put_f32(copy, positions + 4 * 4, NAN));
    EXPECT_EDITED("infinite coordinate", LUCENT_E_IO, "not a finite point",
                  put_f32(copy, positions, INFINITY));
    EXPECT_EDITED("vertex outside the radius", LUCENT_E_IO, "inside", put_f64(copy, OFF_RADIUS, 0.5 * m->radius));
    EXPECT_EDITED("radius 0", LUCENT_E_IO, "positive radius", put_f64(copy, OFF_RADIUS, 0));
    EXPECT_EDITED("radius NaN", LUCENT_E_IO, "positive radius", put_f64(copy, OFF_RADIUS, NAN));
    EXPECT_EDITED("zero normal", LUCENT_E_IO, "unit vector",
                  put_f32(copy, normals, 0); put_f32(copy, normals + 4, 0); put_f32(copy, normals + 8, 0));
    EXPECT_EDITED("NaN normal", LUCENT_E_IO, "unit vector", put_f32(copy, normals + 12, NAN));
done:
    free(good);
    free(copy);
    lucent_mesh_free(m);
}

/* ---- random byte flips ---- */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint64_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

/* Whether an accepted mesh keeps every promise the reader makes. */
static int sound(const struct lucent_mesh *m)
{
    if (!(m->radius > 0) || !isfinite(m->radius))
        return 0;
    for (size_t i = 0; i < 3 * (size_t)m->triangle_count; i++)
        if (m->indices[i] >= m->vertex_count)
            return 0;
    for (size_t i = 0; i < 3 * (size_t)m->vertex_count; i++)
        if (!isfinite(m->positions[i]) || !isfinite(m->normals[i]))
            return 0;
    return 1;
}

static void check_random_flips(void)
{
    enum { ROUNDS = 4000 };
    struct lucent_mesh *m = NULL;
    lucent_error err = {0};
    size_t len = 0;
    if (lucent_mesh_builtin("torus", 1000, &m, &err) != LUCENT_OK)
        return (void)test_check(0, "torus: %s", err.message);
    unsigned char *good = encode(m, &len), *copy = malloc(len);
    int refused_unsealed = 0, accepted_sealed = 0, refused_sealed = 0, unsound = 0, no_message = 0;
    for (int round = 0; good && copy && round < ROUNDS; round++) {
        memcpy(copy, good, len);
        int flips = 1 + (int)(rng() % 4), sealed = round % 2;
        /* half of the flips land in the header, where the counts and the sphere are */
        for (int i = 0; i < flips; i++) {
            size_t at = rng() % 2 ? rng() % HEADER : rng() % len;
            copy[at] ^= (unsigned char)(1 + rng() % 255);
        }
        if (sealed)
            reseal(copy, len);
        struct lucent_mesh *back = NULL;
        memset(&err, 0, sizeof err);
        lucent_status st = mesh_compact_read(copy, len, &back, &err);
        if (st == LUCENT_OK) {
            accepted_sealed += sealed;
            unsound += !sound(back) || !sealed;
        } else {
            no_message += !err.message[0] || back != NULL;
            refused_unsealed += !sealed;
            refused_sealed += sealed;
        }
        lucent_mesh_free(back);
    }
    test_check(refused_unsealed == ROUNDS / 2 && unsound == 0 && no_message == 0,
               "%d rounds of 1-4 random byte flips: all %d without a valid checksum refused; with the checksum "
               "recomputed %d refused by the value checks, %d accepted (all sound: %s); refusals without a "
               "message: %d",
               ROUNDS, refused_unsealed, refused_sealed, accepted_sealed, unsound ? "no" : "yes", no_message);
    free(good);
    free(copy);
    lucent_mesh_free(m);
}

int main(void)
{
    check_round_trips();
    check_import_file();
    check_damage();
    check_random_flips();
    return test_finish();
}
