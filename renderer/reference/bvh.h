/* bvh.h - a bounding volume hierarchy over a mesh's triangles in double precision, for the reference
 * integrator's camera rays (closest hit) and shadow rays (any hit). Nothing is culled: open meshes work. */
#ifndef LUCENT_BVH_H
#define LUCENT_BVH_H

#include "lucent.h"
#include "mesh.h"

#include <stdint.h>

struct bvh;

/* The hit point is (1 - u - v) a + u b + v c of triangle `triangle` (the mesh's index), at distance t
 * along the ray (in units of the direction's length). */
struct bvh_hit {
    uint32_t triangle;
    double t, u, v;
};

/* Builds the tree over all triangles of mesh (mesh-centred coordinates). */
lucent_status bvh_build(const struct lucent_mesh *mesh, struct bvh **out, lucent_error *err);
void bvh_free(struct bvh *bvh);

/* Closest hit with 0 < t < t_max; returns 1 and fills hit, or 0 on a miss. */
int bvh_closest(const struct bvh *bvh, const double origin[3], const double dir[3], double t_max,
                struct bvh_hit *hit);
/* 1 when any triangle is hit with 0 < t < t_max. */
int bvh_occluded(const struct bvh *bvh, const double origin[3], const double dir[3], double t_max);

/* Median split shared by the BVH and the reference's point tree: moves the id whose point (3 doubles
 * per id in xyz) is k-th smallest along axis to ids[k], smaller ones before it (quickselect). */
void bvh_select_nth(uint32_t *ids, int64_t n, int64_t k, const double *xyz, int axis);

#endif
