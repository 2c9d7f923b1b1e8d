/* mesh.h - the in-memory triangle mesh every importer and generator produces.
 * Positions are stored relative to the bounding-sphere centre so huge coordinates keep float precision. */
#ifndef LUCENT_MESH_H
#define LUCENT_MESH_H

#include "lucent.h"

struct lucent_mesh {
    float *positions;         /* 3 floats per vertex, relative to center */
    float *normals;           /* 3 floats per vertex, unit length, outward for closed meshes */
    uint32_t *indices;        /* 3 per triangle, counter-clockwise seen from outside */
    uint32_t vertex_count;
    uint32_t triangle_count;
    double center[3];         /* bounding-sphere centre in the source's own coordinates */
    double radius;            /* bounding-sphere radius, scene units, > 0 */
    int convex;               /* 1 only when known convex: no self-shadowing possible */
    int closed;               /* 1 when closed and wound outward: back faces are always hidden
                               * (generators that guarantee it set it before mesh_finish) */
};

/* Completes a mesh whose positions/indices (absolute coordinates, malloc'd) are filled in:
 * rejects non-finite coordinates and out-of-range indices, drops degenerate triangles
 * (repeated index or zero area), repeated faces and unused vertices, recentres, computes smooth area-weighted
 * normals when normals == NULL, and sets center/radius. Fails with LUCENT_E_MESH when no
 * usable triangle is left. On failure the mesh is left for the caller to free. */
lucent_status mesh_finish(struct lucent_mesh *m, lucent_error *err);

/* Sets m->closed and, for a closed mesh wound inside out, reverses its triangles and normals.
 * Called by mesh_finish; fails only with LUCENT_E_NOMEM. */
lucent_status mesh_orient_closed(struct lucent_mesh *m, lucent_error *err);

/* Allocates an empty mesh with room for the given counts (normals allocated too when with_normals). */
struct lucent_mesh *mesh_alloc(uint32_t vertex_count, uint32_t triangle_count, int with_normals);

/* A simplified copy with about target_triangles triangles (meshoptimizer), for projection passes
 * on meshes far denser than a projection image. Returns NULL on allocation failure. */
struct lucent_mesh *mesh_simplify(const struct lucent_mesh *src, uint32_t target_triangles);

/* The box around every vertex, in the source's coordinates (center added back). */
void mesh_bounds(const struct lucent_mesh *m, double lo[3], double hi[3]);
/* Vertex k (0..2) of triangle t, mesh-centred. */
void mesh_vertex(const struct lucent_mesh *m, uint32_t t, int k, double out[3]);
/* Point, unit interpolated normal (turned to the side the winding calls outside) and unit geometric
 * normal at barycentrics (b1, b2) of triangle t. */
void mesh_surface_at(const struct lucent_mesh *m, uint32_t t, double b1, double b2, double p[3], double n[3],
                     double g[3]);
/* How fast triangle t's vertex normals turn along its edges, (n_j - n_i) . e / |e|^2 averaged over the three
 * edges (1 / scene units): 1 / radius on a sphere, 0 on a flat face, negative where the surface is concave. */
double mesh_curvature(const struct lucent_mesh *m, uint32_t t);
/* mesh_curvature spread to the vertices (area-weighted) and averaged over the surface within about a tenth of
 * the bounding radius of each: one value per vertex, smooth across triangles (malloc'd; NULL when out of memory). */
float *mesh_vertex_curvature(const struct lucent_mesh *m);
/* Curvature at barycentrics (b1, b2) of triangle t, interpolated from mesh_vertex_curvature's values. */
double mesh_curvature_at(const struct lucent_mesh *m, const float *vertex_curvature, uint32_t t, double b1, double b2);

#endif
