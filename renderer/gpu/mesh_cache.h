/* mesh_cache.h - meshes loaded once and kept warm between renders, keyed by where they came from, and
 * uploaded to the GPU when a pass draws them; a dense mesh also keeps a simplified proxy for the
 * projection and shadow passes. */
#ifndef LUCENT_MESH_CACHE_H
#define LUCENT_MESH_CACHE_H

#include "gpu.h"
#include "mesh.h"

#define MESH_CACHE_SLOTS 16
/* What the cached meshes may hold (GPU buffers plus the CPU copy) unless the renderer is told. */
#define MESH_CACHE_DEFAULT_BYTES (512ull << 20)
/* The projection and shadow passes draw a simplified proxy when the mesh has more triangles than
 * a projection image can use: irradiance and depth are smooth, so about 8 texels per triangle
 * (side^2 / 8 triangles, at least PROXY_MIN_TRIANGLES) loses little, and those passes cost per
 * triangle on CPU drivers. One proxy serves the front image, one the smaller side images (and the
 * soft-filtered shadow maps). Meshes within 1.5x of a target draw in full. */
#define PROXY_TEXELS_PER_TRIANGLE 8u
#define PROXY_MIN_TRIANGLES 8192u
/* How far the proxy may stray from the mesh, as a fraction of the bounding radius. */
#define PROXY_TOLERANCE 0.01

/* A mesh's buffers on the renderer's device (gpu.h), once uploaded. */
struct cached_geometry {
    struct gpu_geometry *gpu;   /* NULL: not uploaded */
    uint32_t index_count;
    uint64_t bytes;
};

struct gpu_mesh {
    char key[1200];
    struct lucent_mesh *mesh;
    struct cached_geometry full;
    struct mesh_proxy {
        struct cached_geometry geometry;  /* not uploaded: that pass draws `full` */
        uint32_t target;               /* triangle budget it was built for */
        uint32_t triangles;
    } proxies[2];                      /* PROXY_FRONT, PROXY_SIDES */
    uint64_t last_used;
};

struct mesh_cache {
    struct gpu_mesh slots[MESH_CACHE_SLOTS];
    uint64_t clock;
    uint64_t budget;   /* bytes; least recently used meshes go first */
};

enum { PROXY_FRONT = 0, PROXY_SIDES = 1 };

void mesh_cache_init(struct mesh_cache *cache, uint64_t budget_bytes);
/* Bytes the cached meshes hold (GPU buffers and CPU copies). */
uint64_t mesh_cache_bytes(const struct mesh_cache *cache);
/* Finds or loads (imports or builds, load_ms) the mesh a scene names, on the CPU only: the reference
 * draws nothing. Older meshes are evicted to keep within the budget; a mesh that alone exceeds it is
 * refused with LUCENT_E_LIMIT. */
lucent_status mesh_cache_get(struct gpu *gpu, struct mesh_cache *cache, const lucent_mesh_ref *ref,
                             struct gpu_mesh **out, double *load_ms, lucent_error *err);
/* Uploads the mesh, and the proxies the front and side image sizes call for, unless already there;
 * then evicts as mesh_cache_get does, now counting the GPU buffers too. */
lucent_status mesh_cache_upload(struct gpu *gpu, struct mesh_cache *cache, struct gpu_mesh *m,
                                int projection_size, int side_size, lucent_error *err);
/* What a pass drawing for PROXY_FRONT or PROXY_SIDES draws: the proxy, or the full mesh. */
struct gpu_draw gpu_mesh_geometry(const struct gpu_mesh *m, int which);
void mesh_cache_destroy(struct gpu *gpu, struct mesh_cache *cache);

#endif
