/* fuzz_lmesh.c - libFuzzer target: the compact .lmesh reader the store's meshes are loaded with. The
 * checksum is made to match first (a random input would stop there), so the fuzzer reaches the
 * validation behind it: counts, sizes, finite values, indices, radius, normals. A mesh read must be
 * sound. */
#include "mesh_compact.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy)
        return 0;
    memcpy(copy, data, size);
    if (size >= 8) {
        uint64_t sum = mesh_compact_checksum(copy, size - 8);
        memcpy(copy + size - 8, &sum, 8);   /* little-endian, as the writer stores it */
    }
    struct lucent_mesh *m = NULL;
    lucent_error err = {0};
    if (mesh_compact_read(copy, size, &m, &err) == LUCENT_OK) {
        for (uint32_t i = 0; i < 3 * m->triangle_count; i++)
            if (m->indices[i] >= m->vertex_count)
                abort();
        if (!(m->radius > 0) || !isfinite(m->radius))
            abort();
        lucent_mesh_free(m);
    }
    free(copy);
    return 0;
}
