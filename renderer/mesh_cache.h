/* mesh_cache.h - meshes uploaded to the GPU once and kept warm between renders, keyed by where they
 * came from; a dense mesh also keeps a simplified proxy for the projection and shadow passes. */
#ifndef LUCENT_MESH_CACHE_H
#define LUCENT_MESH_CACHE_H

#include "mesh.h"
#include "vk_resources.h"

#define MESH_CACHE_SLOTS 4
/* Meshes above PROXY_THRESHOLD triangles get a proxy of PROXY_TRIANGLES for the projection
 * images: a 512^2 projection image cannot resolve more, and those passes cost per triangle. */
#define PROXY_TRIANGLES 65536u
#define PROXY_THRESHOLD (2u * PROXY_TRIANGLES)
/* How far the proxy may stray from the mesh, as a fraction of the bounding radius. */
#define PROXY_TOLERANCE 0.01

struct gpu_geometry {
    struct vk_buffer positions, normals, indices;
    uint32_t index_count;
};

struct gpu_mesh {
    char key[1200];
    struct lucent_mesh *mesh;
    struct gpu_geometry full;
    struct gpu_geometry proxy;     /* index_count 0: the projection passes draw `full` */
    uint32_t proxy_triangles;
    uint64_t last_used;
};

struct mesh_cache {
    struct gpu_mesh slots[MESH_CACHE_SLOTS];
    uint64_t clock;
};

/* Finds or loads the mesh a scene names. load_ms is the import + upload time (0 on a hit). */
lucent_status mesh_cache_get(struct vk_context *ctx, struct mesh_cache *cache, const lucent_mesh_ref *ref,
                             struct gpu_mesh **out, double *load_ms, lucent_error *err);
void mesh_cache_destroy(struct vk_context *ctx, struct mesh_cache *cache);

#endif
