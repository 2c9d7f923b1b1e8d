/* mesh_compact.c - writes and reads the compact binary mesh form (layout in mesh_compact.h).
 * The reader treats the bytes as untrusted: every count, size, value and the checksum is checked. */
#include "mesh_compact.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <errno.h>
#include <string.h>

/* Arrays are written and read as they lie in memory. */
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the compact mesh form is little-endian; add byte swapping for this host"
#endif

#define HEADER_BYTES 56u
#define TRAILER_BYTES 8u
#define FLAG_CONVEX 1u
#define FLAG_CLOSED 2u
/* mesh_finish drops unused vertices, so a triangle brings at most three */
#define MAX_VERTICES (3 * (uint64_t)LUCENT_MAX_TRIANGLES)
/* Vertices may lie past the radius by float rounding of their centred coordinates, no more: relative
 * for normal floats; below FLT_MIN floats are FLT_TRUE_MIN apart whatever their size, so a subnormal
 * mesh's vertices may lie up to sqrt(3)/2 of that past (fuzz_import found one refused after import). */
#define RADIUS_TOLERANCE 1e-5
#define RADIUS_SLACK ((double)FLT_TRUE_MIN)
#define NORMAL_TOLERANCE 1e-3

/* ---- checksum ---- */

typedef struct checksum {
    uint64_t h, total;
    unsigned char tail[8];
    unsigned tail_len;
} checksum;

static uint64_t rotl64(uint64_t x, int r)
{
    return x << r | x >> (64 - r);
}

/* For a fixed state this is a bijection of w (xor, odd multiplies, rotation), and for a fixed w a
 * bijection of the state: one changed word always yields a different result. */
static void checksum_word(checksum *c, uint64_t w)
{
    c->h = rotl64((c->h ^ w) * 0x9e3779b97f4a7c15ull, 31) * 0xc2b2ae3d27d4eb4full;
}

static void checksum_init(checksum *c)
{
    memset(c, 0, sizeof *c);
    c->h = 0x4c4d455348000001ull;
}

static void checksum_update(checksum *c, const void *data, size_t len)
{
    const unsigned char *p = data;
    uint64_t w;
    c->total += len;
    while (len > 0 && c->tail_len > 0) {
        c->tail[c->tail_len++] = *p++;
        len--;
        if (c->tail_len == 8) {
            memcpy(&w, c->tail, 8);
            checksum_word(c, w);
            c->tail_len = 0;
        }
    }
    for (; len >= 8; p += 8, len -= 8) {
        memcpy(&w, p, 8);
        checksum_word(c, w);
    }
    memcpy(c->tail, p, len);
    c->tail_len += (unsigned)len;
}

static uint64_t checksum_final(checksum *c)
{
    if (c->tail_len > 0) {
        uint64_t w = 0;
        memcpy(&w, c->tail, c->tail_len);
        checksum_word(c, w);
    }
    checksum_word(c, c->total);
    uint64_t h = c->h; /* murmur3's finalizer: spreads every bit over the whole word */
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    return h ^ (h >> 33);
}

uint64_t mesh_compact_checksum(const void *data, size_t len)
{
    checksum c;
    checksum_init(&c);
    checksum_update(&c, data, len);
    return checksum_final(&c);
}

/* ---- writing ---- */

uint64_t mesh_compact_size(uint32_t vertex_count, uint32_t triangle_count)
{
    return HEADER_BYTES + 24 * (uint64_t)vertex_count + 12 * (uint64_t)triangle_count + TRAILER_BYTES;
}

int mesh_compact_detect(const void *data, size_t len)
{
    return len >= MESH_COMPACT_MAGIC_LEN && memcmp(data, MESH_COMPACT_MAGIC, MESH_COMPACT_MAGIC_LEN) == 0;
}

static int write_hashed(FILE *f, checksum *c, const void *data, size_t len)
{
    checksum_update(c, data, len);
    return fwrite(data, 1, len, f) == len;
}

lucent_status mesh_compact_write(const struct lucent_mesh *m, FILE *f, lucent_error *err)
{
    if (!m->normals || m->triangle_count == 0 || m->triangle_count > LUCENT_MAX_TRIANGLES ||
        m->vertex_count > MAX_VERTICES)
        return lucent_fail(err, LUCENT_E_INTERNAL, "mesh",
                           "only a finished mesh within the limits can be written in compact form");
    unsigned char header[HEADER_BYTES];
    uint32_t words[4] = {MESH_COMPACT_VERSION,
                         (m->convex ? FLAG_CONVEX : 0) | (m->closed ? FLAG_CLOSED : 0),
                         m->vertex_count, m->triangle_count};
    double sphere[4] = {m->center[0], m->center[1], m->center[2], m->radius};
    memcpy(header, MESH_COMPACT_MAGIC, MESH_COMPACT_MAGIC_LEN);
    memcpy(header + 8, words, sizeof words);
    memcpy(header + 24, sphere, sizeof sphere);

    size_t vertex_floats = 3 * (size_t)m->vertex_count, index_count = 3 * (size_t)m->triangle_count;
    checksum c;
    checksum_init(&c);
    int ok = write_hashed(f, &c, header, sizeof header) &&
             write_hashed(f, &c, m->positions, vertex_floats * sizeof *m->positions) &&
             write_hashed(f, &c, m->normals, vertex_floats * sizeof *m->normals) &&
             write_hashed(f, &c, m->indices, index_count * sizeof *m->indices);
    uint64_t sum = checksum_final(&c);
    if (!ok || fwrite(&sum, sizeof sum, 1, f) != 1 || fflush(f) != 0)
        return lucent_fail(err, lucent_io_status(errno), "mesh.file", "could not write the compact mesh: %s",
                           strerror(errno));
    return LUCENT_OK;
}

/* ---- reading ---- */

static lucent_status damaged(lucent_error *err, const char *what)
{
    return lucent_fail(err, LUCENT_E_IO, "mesh.file", "the compact mesh file is damaged: %s", what);
}

static lucent_status check_header(const unsigned char *data, size_t len, uint32_t *vertices,
                                  uint32_t *triangles, lucent_error *err)
{
    uint32_t words[4];
    if (!mesh_compact_detect(data, len))
        return damaged(err, "it does not start with the compact mesh magic");
    if (len < HEADER_BYTES + TRAILER_BYTES)
        return lucent_fail(err, LUCENT_E_IO, "mesh.file",
                           "the compact mesh file is damaged: it is %zu bytes, shorter than its %u-byte "
                           "header and checksum", len, HEADER_BYTES + TRAILER_BYTES);
    memcpy(words, data + 8, sizeof words);
    if (words[0] != MESH_COMPACT_VERSION)
        return lucent_fail(err, LUCENT_E_IO, "mesh.file",
                           "the compact mesh file has version %u; this build reads version %u", words[0],
                           MESH_COMPACT_VERSION);
    if (words[1] & ~(FLAG_CONVEX | FLAG_CLOSED))
        return damaged(err, "its flags have unknown bits set");
    *vertices = words[2];
    *triangles = words[3];
    if (*triangles == 0 || *vertices == 0 || *vertices > 3 * (uint64_t)*triangles)
        return lucent_fail(err, LUCENT_E_IO, "mesh.file",
                           "the compact mesh file is damaged: %u vertices for %u triangles", *vertices,
                           *triangles);
    if (*triangles > LUCENT_MAX_TRIANGLES)
        return lucent_fail(err, LUCENT_E_LIMIT, "mesh.file",
                           "the compact mesh file claims %u triangles; at most %u are allowed",
                           *triangles, LUCENT_MAX_TRIANGLES);
    uint64_t expected = mesh_compact_size(*vertices, *triangles);
    if (expected != len)
        return lucent_fail(err, LUCENT_E_IO, "mesh.file",
                           "the compact mesh file is damaged: it is %zu bytes, but %u vertices and %u "
                           "triangles take %llu", len, *vertices, *triangles, (unsigned long long)expected);
    uint64_t stored;
    memcpy(&stored, data + len - TRAILER_BYTES, sizeof stored);
    if (stored != mesh_compact_checksum(data, len - TRAILER_BYTES))
        return damaged(err, "its checksum does not match its contents");
    return LUCENT_OK;
}

static lucent_status check_values(const struct lucent_mesh *m, lucent_error *err)
{
    if (!isfinite(m->center[0]) || !isfinite(m->center[1]) || !isfinite(m->center[2]) ||
        !(m->radius > 0) || !isfinite(m->radius))
        return damaged(err, "its bounding sphere is not finite with a positive radius");
    for (size_t i = 0; i < 3 * (size_t)m->triangle_count; i++)
        if (m->indices[i] >= m->vertex_count)
            return lucent_fail(err, LUCENT_E_IO, "mesh.file",
                               "the compact mesh file is damaged: triangle %zu refers to vertex %u of %u",
                               i / 3, m->indices[i], m->vertex_count);
    double reach = m->radius * (1 + RADIUS_TOLERANCE) + RADIUS_SLACK;
    for (size_t v = 0; v < m->vertex_count; v++) {
        const float *p = m->positions + 3 * v, *n = m->normals + 3 * v;
        double dist = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        /* written so that NaN fails both tests */
        if (!(dist <= reach))
            return lucent_fail(err, LUCENT_E_IO, "mesh.file",
                               "the compact mesh file is damaged: vertex %zu is not a finite point "
                               "inside the bounding sphere", v);
        if (!(fabs(len - 1) <= NORMAL_TOLERANCE))
            return lucent_fail(err, LUCENT_E_IO, "mesh.file",
                               "the compact mesh file is damaged: the normal of vertex %zu is not a "
                               "unit vector", v);
    }
    return LUCENT_OK;
}

lucent_status mesh_compact_read(const void *data, size_t len, struct lucent_mesh **out, lucent_error *err)
{
    const unsigned char *bytes = data;
    uint32_t vertices = 0, triangles = 0, flags;
    *out = NULL;
    lucent_status st = check_header(bytes, len, &vertices, &triangles, err);
    if (st != LUCENT_OK)
        return st;
    struct lucent_mesh *m = mesh_alloc(vertices, triangles, 1);
    if (!m)
        return lucent_fail(err, LUCENT_E_NOMEM, "mesh.file",
                           "out of memory for a mesh of %u vertices and %u triangles", vertices, triangles);
    size_t vertex_bytes = 12 * (size_t)vertices, index_bytes = 12 * (size_t)triangles;
    const unsigned char *p = bytes + HEADER_BYTES;
    memcpy(&flags, bytes + 12, sizeof flags);
    memcpy(m->center, bytes + 24, sizeof m->center);
    memcpy(&m->radius, bytes + 48, sizeof m->radius);
    memcpy(m->positions, p, vertex_bytes);
    memcpy(m->normals, p + vertex_bytes, vertex_bytes);
    memcpy(m->indices, p + 2 * vertex_bytes, index_bytes);
    m->convex = (flags & FLAG_CONVEX) != 0;
    m->closed = (flags & FLAG_CLOSED) != 0;
    if ((st = check_values(m, err)) != LUCENT_OK) {
        lucent_mesh_free(m);
        return st;
    }
    *out = m;
    return LUCENT_OK;
}
