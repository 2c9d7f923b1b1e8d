/* mesh_thickness.c - the curvature the sphere factor takes at each vertex: the surface's, limited where the part
 * under the vertex is thinner than its radius of curvature (an ear is a slab, not a ball), as the reference takes
 * it per visible point (reference.c, exit_point_at). One ray inward per convex vertex over the BVH. */
#include "mesh_thickness.h"
#include "bvh.h"
#include "linalg.h"
#include "parallel.h"
#include "sphere_diffusion.h"

#include <math.h>

/* Rays start this far (times the bounding radius) inside the vertex so they miss its own triangles. */
#define START_DEPTH 1e-6
#define VERTICES_PER_CHUNK 4096

struct rays {
    const struct lucent_mesh *mesh;
    const struct bvh *bvh;
    float *curvature;
};

static void limit_vertices(void *arg, size_t begin, size_t end)
{
    struct rays *r = arg;
    const struct lucent_mesh *m = r->mesh;
    double depth = START_DEPTH * m->radius;
    for (size_t v = begin; v < end; v++) {
        double c = r->curvature[v], inward[3], start[3];
        if (!(c > 0.0))
            continue;
        for (int a = 0; a < 3; a++)
            inward[a] = -m->normals[v * 3 + a];
        if (v3_normalize(inward) == 0.0)
            continue;
        for (int a = 0; a < 3; a++)
            start[a] = m->positions[v * 3 + a] + inward[a] * depth;
        /* Only a part thinner than the radius of curvature limits it: the ray need not go further. */
        struct bvh_hit hit;
        if (bvh_closest(r->bvh, start, inward, 1.0 / c, &hit))
            r->curvature[v] = (float)sphere_factor_curvature(c, hit.t + depth);
    }
}

lucent_status mesh_ball_curvature(const struct lucent_mesh *m, float *curvature, lucent_error *err)
{
    /* A known convex builtin is a sphere, as thick as its diameter everywhere: twice its radius of curvature. */
    if (m->convex)
        return LUCENT_OK;
    int any = 0;
    for (size_t v = 0; v < m->vertex_count && !any; v++)
        any = curvature[v] > 0.0f;
    struct bvh *bvh = NULL;
    lucent_status st = any ? bvh_build(m, &bvh, err) : LUCENT_OK;
    if (!bvh)
        return st;
    struct rays r = {m, bvh, curvature};
    parallel_run(&r, parallel_threads(0), m->vertex_count, VERTICES_PER_CHUNK, limit_vertices, NULL);
    bvh_free(bvh);
    return LUCENT_OK;
}
