/* mesh_closed.c - recognizes closed, consistently wound meshes and turns inside-out ones outward, so
 * the raster passes may cull back faces (half the triangle setup on CPU drivers) without losing any. */
#include "mesh.h"

#include <stdlib.h>

static int compare_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static int contains(const uint64_t *sorted, size_t n, uint64_t key)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (sorted[mid] < key)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && sorted[lo] == key;
}

/* Closed and consistent: every directed edge a->b appears once and its twin b->a appears too. */
static int is_closed(const struct lucent_mesh *m, int *closed, lucent_error *err)
{
    size_t n = (size_t)m->triangle_count * 3;
    uint64_t *edges = malloc(n * sizeof *edges);
    if (!edges)
        return lucent_fail(err, LUCENT_E_NOMEM, "mesh", "out of memory checking the mesh"), -1;
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint64_t a = m->indices[t * 3 + k], b = m->indices[t * 3 + (k + 1) % 3];
            edges[t * 3 + k] = a << 32 | b;
        }
    qsort(edges, n, sizeof *edges, compare_u64);
    *closed = 1;
    for (size_t i = 0; i < n && *closed; i++) {
        uint64_t twin = edges[i] << 32 | edges[i] >> 32;
        *closed = (i == 0 || edges[i] != edges[i - 1]) && contains(edges, n, twin);
    }
    free(edges);
    return 0;
}

/* Six times the signed volume: positive when the triangles wind counter-clockwise from outside. */
static double signed_volume(const struct lucent_mesh *m)
{
    double v = 0.0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        const float *a = &m->positions[m->indices[t * 3] * 3];
        const float *b = &m->positions[m->indices[t * 3 + 1] * 3];
        const float *c = &m->positions[m->indices[t * 3 + 2] * 3];
        v += (double)a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) -
             (double)a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
             (double)a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0]);
    }
    return v;
}

lucent_status mesh_orient_closed(struct lucent_mesh *m, lucent_error *err)
{
    int closed = 0;
    if (is_closed(m, &closed, err) != 0)
        return err ? err->status : LUCENT_E_NOMEM;
    m->closed = closed;
    if (!closed || signed_volume(m) >= 0.0)
        return LUCENT_OK;
    /* Inside out: reverse every triangle, and the normals, which were built from (or agree with)
     * the inward winding. */
    for (size_t t = 0; t < m->triangle_count; t++) {
        uint32_t tmp = m->indices[t * 3 + 1];
        m->indices[t * 3 + 1] = m->indices[t * 3 + 2];
        m->indices[t * 3 + 2] = tmp;
    }
    for (size_t i = 0; i < (size_t)m->vertex_count * 3; i++)
        m->normals[i] = -m->normals[i];
    return LUCENT_OK;
}
