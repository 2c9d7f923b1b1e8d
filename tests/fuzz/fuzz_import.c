/* fuzz_import.c - libFuzzer target: hostile mesh bytes through the importer in-process (format pre-checks,
 * assimp from memory, the validation of its output), as lucent-import runs it; a mesh it returns must be sound. */
#include "mesh.h"
#include "mesh_bundle.h"
#include "mesh_compact.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The limits the sandbox puts on lucent-import (server/mesh_import_sandbox.c, lucentd's defaults in
 * server/config.c): --max-triangles (max-triangles, 2000000) is applied here as lucent_import.c applies
 * it. The rlimits are not set in-process: address space (import-memory-bytes, 2 GiB) is stood in for by
 * sandbox_new.cpp (operator new fails past 1 GiB live, so assimp sees bad_alloc as it does there) and
 * libFuzzer's -rss_limit_mb, CPU time (import-cpu, 30 s) by -timeout, both given by run.sh; file size,
 * descriptors and core dumps do not apply (nothing is written or opened here). */
#define MAX_TRIANGLES 2000000u

/* The first byte picks the format, the rest is the file. '0'..'4' (any byte, modulo 11): as is;
 * '5'..'9': the same formats with the binary ones' size fields made to match the input's size (as the
 * lmesh target fixes its checksum), which a mutation that changes the length would otherwise break;
 * ':': a multi-file upload's bundle (server/mesh_bundle.h), as lucent-import --format bundle reads it. */
static const char *const FORMATS[] = {"obj", "ply", "stl", "gltf", "glb"};

static void put_le32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> 8 * i);
}

static uint32_t get_le32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Binary STL: 80-byte header, u32 count, 50 bytes a triangle. GLB: "glTF", version, total length,
 * a JSON chunk (length, type), then a BIN chunk (length, type) after the JSON padded to 4. Returns the
 * length to import (STL drops a partial last triangle). */
static size_t fix_sizes(const char *ext, uint8_t *data, size_t len)
{
    if (strcmp(ext, "stl") == 0 && len >= 84) {
        uint32_t count = (uint32_t)((len - 84) / 50);
        put_le32(data + 80, count);
        return 84 + 50 * (size_t)count;
    }
    if (strcmp(ext, "glb") == 0 && len >= 20) {
        put_le32(data + 8, (uint32_t)len);
        uint32_t json = get_le32(data + 12);
        if (json > len - 20)
            put_le32(data + 12, json = (uint32_t)(len - 20));
        size_t body = 20 + (((size_t)json + 3) & ~(size_t)3);
        if (body <= len && len - body >= 8)
            put_le32(data + body, (uint32_t)(len - body - 8));
    }
    return len;
}

/* What mesh_finish promises and mesh_compact_read checks again when the store loads the mesh. */
static void check_mesh(const struct lucent_mesh *m)
{
    if (m->triangle_count < 1 || m->triangle_count > LUCENT_MAX_TRIANGLES || m->vertex_count < 1 ||
        m->vertex_count > 3 * (uint64_t)m->triangle_count || !m->positions || !m->normals || !m->indices)
        abort();
    if (!isfinite(m->center[0]) || !isfinite(m->center[1]) || !isfinite(m->center[2]) ||
        !(m->radius > 0) || !isfinite(m->radius))
        abort();
    unsigned char *used = calloc(m->vertex_count, 1);
    if (!used)
        abort();
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->indices + 3 * t;
        for (int k = 0; k < 3; k++) {
            if (tri[k] >= m->vertex_count)
                abort();
            used[tri[k]] = 1;
        }
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) /* degenerate: dropped */
            abort();
    }
    for (size_t v = 0; v < m->vertex_count; v++) {
        const float *p = m->positions + 3 * v, *n = m->normals + 3 * v;
        double dist = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        /* negated so that NaN fails; the tolerances are mesh_compact.c's */
        if (!used[v] || !(dist <= m->radius * (1 + 1e-5) + FLT_TRUE_MIN) || !(fabs(len - 1) <= 1e-3))
            abort();
    }
    free(used);
}

/* lucent-import writes the mesh in compact form and the store reads it back for every render:
 * what the importer accepts, the reader must accept too. */
static void check_round_trip(const struct lucent_mesh *m)
{
    char *bytes = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&bytes, &len);
    if (!f)
        abort();
    lucent_error err = {0};
    lucent_status st = mesh_compact_write(m, f, &err);
    if (fclose(f) != 0 || st != LUCENT_OK)
        abort();
    struct lucent_mesh *back = NULL;
    if (mesh_compact_read(bytes, len, &back, &err) != LUCENT_OK || back->vertex_count != m->vertex_count ||
        back->triangle_count != m->triangle_count)
        abort();
    lucent_mesh_free(back);
    free(bytes);
}

/* A refusal names a status the daemon maps to 4xx/413/503 and a message of Lucent's own words:
 * assimp's error text (which can quote the file) goes only to the log. A bundle's refusals may also be
 * LUCENT_E_INVALID and quote its file names, which are checked UTF-8 without control characters. */
static void check_refusal(lucent_status st, const lucent_error *err, int bundle)
{
    if (st != err->status || !err->message[0] ||
        (st != LUCENT_E_MESH && st != LUCENT_E_LIMIT && st != LUCENT_E_NOMEM && !(bundle && st == LUCENT_E_INVALID)))
        abort();
    for (const char *c = err->message; *c; c++)
        if ((unsigned char)*c < 0x20 || (unsigned char)*c == 0x7f || (!bundle && (unsigned char)*c > 0x7e))
            abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    unsigned pick = (uint8_t)(data[0] - '0') % 11;
    const char *ext = FORMATS[pick % 5];
    size_t len = size - 1;
    /* a copy of exactly len bytes, so that AddressSanitizer sees any read past the end */
    uint8_t *copy = malloc(len ? len : 1);
    if (!copy)
        return 0;
    memcpy(copy, data + 1, len);
    if (pick >= 5 && pick < 10)
        len = fix_sizes(ext, copy, len);
    struct lucent_mesh *m = NULL;
    lucent_error err = {0};
    lucent_status st = pick == 10 ? mesh_bundle_import(copy, len, &m, &err)
                                  : lucent_mesh_import_memory(copy, len, ext, &m, &err);
    if (st == LUCENT_OK) {
        check_mesh(m);
        /* lucent_import.c refuses a larger mesh (LUCENT_E_LIMIT) and writes the others */
        if (m->triangle_count <= MAX_TRIANGLES)
            check_round_trip(m);
        lucent_mesh_free(m);
    } else {
        if (m)
            abort(); /* *out is set only on success */
        check_refusal(st, &err, pick == 10);
    }
    free(copy);
    return 0;
}
