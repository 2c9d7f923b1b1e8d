/* mesh_proxy.c - coarse stand-ins for dense meshes in the projection passes (meshoptimizer).
 * A proxy reuses its source's centre, radius and exact vertex positions, so the two line up. */
#include "mesh.h"
#include "mesh_normals.h"

#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

/* Largest geometric error a proxy may introduce, as a fraction of the bounding radius: about one
 * texel of a 200-texel projection image. Both simplifiers stop there even short of the target. */
#define PROXY_ERROR_OF_RADIUS 1e-2

/* Writes the simplified index list to kept (room for all source indices) and returns its length.
 * Topology-preserving simplification first; the sloppy one only when that stalls above the target
 * and does better. sloppy is scratch of the same size. */
static size_t simplify_indices(const struct lucent_mesh *src, size_t target_indices,
                               uint32_t *kept, uint32_t *sloppy)
{
    const size_t stride = 3 * sizeof(float);
    size_t index_count = 3 * (size_t)src->triangle_count;
    float scale = meshopt_simplifyScale(src->positions, src->vertex_count, stride);
    float error = (float)(PROXY_ERROR_OF_RADIUS * src->radius / scale);

    size_t n = meshopt_simplify(kept, src->indices, index_count, src->positions, src->vertex_count,
                                stride, target_indices, error, 0, NULL);
    if (n <= target_indices)
        return n;
    size_t n_sloppy = meshopt_simplifySloppy(sloppy, src->indices, index_count, src->positions,
                                             src->vertex_count, stride, target_indices, error, NULL);
    if (n_sloppy > 0 && n_sloppy < n) {
        memcpy(kept, sloppy, n_sloppy * sizeof *kept);
        n = n_sloppy;
    }
    return n;
}

/* The mesh made of src's vertices that `indices` use, renumbered densely; NULL if out of memory. */
static struct lucent_mesh *proxy_from_indices(const struct lucent_mesh *src, const uint32_t *indices,
                                              size_t index_count)
{
    struct lucent_mesh *proxy = NULL;
    uint32_t *remap = malloc((src->vertex_count ? src->vertex_count : 1) * sizeof *remap);
    if (!remap)
        return NULL;
    for (uint32_t v = 0; v < src->vertex_count; v++)
        remap[v] = UINT32_MAX;
    uint32_t used = 0;
    for (size_t i = 0; i < index_count; i++)
        if (remap[indices[i]] == UINT32_MAX)
            remap[indices[i]] = used++;

    proxy = mesh_alloc(used, (uint32_t)(index_count / 3), 0);
    if (!proxy)
        goto fail;
    for (uint32_t v = 0; v < src->vertex_count; v++)
        if (remap[v] != UINT32_MAX)
            memcpy(proxy->positions + 3 * (size_t)remap[v], src->positions + 3 * (size_t)v,
                   3 * sizeof(float));
    for (size_t i = 0; i < index_count; i++)
        proxy->indices[i] = remap[indices[i]];
    memcpy(proxy->center, src->center, sizeof proxy->center);
    proxy->radius = src->radius;
    proxy->convex = src->convex;
    proxy->closed = src->closed;
    if (mesh_fill_normals(proxy, NULL) != LUCENT_OK)
        goto fail;
    free(remap);
    return proxy;

fail:
    lucent_mesh_free(proxy);
    free(remap);
    return NULL;
}

struct lucent_mesh *mesh_simplify(const struct lucent_mesh *src, uint32_t target_triangles)
{
    struct lucent_mesh *proxy = NULL;
    size_t index_count = 3 * (size_t)src->triangle_count;
    uint32_t *kept = malloc(index_count * sizeof *kept);
    uint32_t *sloppy = malloc(index_count * sizeof *sloppy);
    if (!kept || !sloppy)
        goto done;

    size_t n = 0;
    if (target_triangles < src->triangle_count)
        n = simplify_indices(src, 3 * (size_t)target_triangles, kept, sloppy);
    /* nothing to gain, or nothing left: the proxy is a plain copy */
    if (n == 0) {
        memcpy(kept, src->indices, index_count * sizeof *kept);
        n = index_count;
    }
    proxy = proxy_from_indices(src, kept, n);

done:
    free(kept);
    free(sloppy);
    return proxy;
}
