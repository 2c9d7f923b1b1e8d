/* mesh_thickness.h - the curvature the sphere factor takes at each vertex of a mesh: limited where the part under
 * the vertex is thinner than its radius of curvature, measured with one ray inward (mesh_thickness.c). */
#ifndef LUCENT_MESH_THICKNESS_H
#define LUCENT_MESH_THICKNESS_H

#include "lucent.h"
#include "mesh.h"

/* Turns mesh_vertex_curvature's values into the curvature the sphere factor takes: each convex vertex's
 * curvature c times min(thickness x c, 1), the thickness being how far the ray inward along its normal runs to
 * the mesh. Builds a BVH over the mesh for the while (about 270 bytes a triangle); a mesh flagged convex (a
 * builtin sphere) keeps its curvature. */
lucent_status mesh_ball_curvature(const struct lucent_mesh *m, float *curvature, lucent_error *err);

#endif
