/* mesh_cache.c - a small LRU of GPU-resident meshes. A file's key includes its size and mtime so an
 * edited file is reloaded; builtins are keyed by name and triangle count. */
#include "mesh_cache.h"
#include "clock_ms.h"
#include "mesh_thickness.h"

#include <meshoptimizer.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

static lucent_status mesh_key(const lucent_mesh_ref *ref, char *key, size_t cap, lucent_error *err)
{
    if (ref->source == LUCENT_MESH_BUILTIN) {
        snprintf(key, cap, "builtin:%s:%u", ref->builtin, ref->triangles);
        return LUCENT_OK;
    }
    if (ref->source == LUCENT_MESH_STORED)
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.id",
                           "stored meshes are resolved to a file by the daemon before rendering");
    struct stat sb;
    if (stat(ref->file, &sb) != 0)
        return lucent_fail(err, LUCENT_E_IO, "mesh.file", "cannot read \"%s\"", ref->file);
    snprintf(key, cap, "file:%s:%lld:%lld.%09ld", ref->file, (long long)sb.st_size,
             (long long)sb.st_mtim.tv_sec, (long)sb.st_mtim.tv_nsec);
    return LUCENT_OK;
}

static void geometry_destroy(struct gpu *gpu, struct cached_geometry *g)
{
    gpu_geometry_free(gpu, g->gpu);
    memset(g, 0, sizeof *g);
}

/* Each vertex's normal and, in the geometry the camera's G-buffer draws, the curvature the sphere factor takes
 * (the projection passes, which draw the proxies, do not read it): *out, 4 floats a vertex, malloc'd. */
static lucent_status shading_stream(const struct lucent_mesh *m, int camera, float **out, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    float *curvature = camera ? mesh_vertex_curvature(m) : NULL;
    float *shading = malloc((size_t)m->vertex_count * 4 * sizeof *shading);
    if (!shading || (camera && !curvature)) {
        st = lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory preparing the mesh for the device");
        goto fail;
    }
    if (camera && (st = mesh_ball_curvature(m, curvature, err)) != LUCENT_OK)
        goto fail;
    for (size_t v = 0; v < m->vertex_count; v++) {
        memcpy(&shading[v * 4], &m->normals[v * 3], 3 * sizeof *shading);
        shading[v * 4 + 3] = camera ? curvature[v] : 0.0f;
    }
    free(curvature);
    *out = shading;
    return LUCENT_OK;
fail:
    free(curvature);
    free(shading);
    return st;
}

static lucent_status geometry_create(struct gpu *gpu, const struct lucent_mesh *m, int camera,
                                     struct cached_geometry *g, lucent_error *err)
{
    size_t index_count = (size_t)m->triangle_count * 3;
    uint32_t *ordered = malloc(index_count * sizeof *ordered);
    float *shading = NULL;
    lucent_status st = ordered ? shading_stream(m, camera, &shading, err)
                               : lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory preparing the mesh for the device");
    if (st == LUCENT_OK) {
        meshopt_optimizeVertexCache(ordered, m->indices, index_count, m->vertex_count);
        st = gpu_geometry_upload(gpu, m->positions, shading, m->vertex_count, ordered, (uint32_t)index_count,
                                 &g->gpu, &g->bytes, err);
    }
    free(ordered);
    free(shading);
    if (st != LUCENT_OK) {
        memset(g, 0, sizeof *g);
        return st;
    }
    g->index_count = (uint32_t)index_count;
    return LUCENT_OK;
}

static void slot_clear(struct gpu *gpu, struct gpu_mesh *s)
{
    geometry_destroy(gpu, &s->full);
    geometry_destroy(gpu, &s->proxies[PROXY_FRONT].geometry);
    geometry_destroy(gpu, &s->proxies[PROXY_SIDES].geometry);
    lucent_mesh_free(s->mesh);
    memset(s, 0, sizeof *s);
}

static lucent_status slot_load(const lucent_mesh_ref *ref, struct gpu_mesh *s, lucent_error *err)
{
    return ref->source == LUCENT_MESH_BUILTIN ? lucent_mesh_builtin(ref->builtin, ref->triangles, &s->mesh, err)
                                              : lucent_mesh_import_file(ref->file, &s->mesh, err);
}

static uint32_t proxy_target(int image_size)
{
    uint32_t target = (uint32_t)image_size * (uint32_t)image_size / PROXY_TEXELS_PER_TRIANGLE;
    return target > PROXY_MIN_TRIANGLES ? target : PROXY_MIN_TRIANGLES;
}

/* (Re)builds a proxy when the image size calls for a different one. */
static lucent_status ensure_proxy(struct gpu *gpu, const struct lucent_mesh *mesh, struct mesh_proxy *p,
                                  int image_size, lucent_error *err)
{
    uint32_t target = proxy_target(image_size);
    int wanted = mesh->triangle_count > target + target / 2;
    if ((!wanted && !p->geometry.gpu) || (wanted && p->target == target))
        return LUCENT_OK;
    geometry_destroy(gpu, &p->geometry);
    p->target = p->triangles = 0;
    if (!wanted)
        return LUCENT_OK;
    struct lucent_mesh *proxy = mesh_simplify(mesh, target);
    if (!proxy)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory simplifying the mesh");
    lucent_status st = geometry_create(gpu, proxy, 0, &p->geometry, err);
    if (st == LUCENT_OK) {
        p->target = target;
        p->triangles = proxy->triangle_count;
    }
    lucent_mesh_free(proxy);
    return st;
}

void mesh_cache_init(struct mesh_cache *cache, uint64_t budget_bytes)
{
    memset(cache, 0, sizeof *cache);
    cache->budget = budget_bytes;
}

static uint64_t slot_bytes(const struct gpu_mesh *s)
{
    if (!s->mesh)
        return 0;
    uint64_t cpu = (uint64_t)s->mesh->vertex_count * 24 + (uint64_t)s->mesh->triangle_count * 12;
    return cpu + s->full.bytes + s->proxies[PROXY_FRONT].geometry.bytes + s->proxies[PROXY_SIDES].geometry.bytes;
}

uint64_t mesh_cache_bytes(const struct mesh_cache *cache)
{
    uint64_t total = 0;
    for (int i = 0; i < MESH_CACHE_SLOTS; i++)
        total += slot_bytes(&cache->slots[i]);
    return total;
}

/* Evicts least recently used meshes other than `keep` until the cache fits its budget; fails when
 * `keep` alone does not fit (it is evicted too). */
static lucent_status trim(struct gpu *gpu, struct mesh_cache *cache, struct gpu_mesh *keep, lucent_error *err)
{
    while (mesh_cache_bytes(cache) > cache->budget) {
        struct gpu_mesh *oldest = NULL;
        for (int i = 0; i < MESH_CACHE_SLOTS; i++) {
            struct gpu_mesh *s = &cache->slots[i];
            if (s->mesh && s != keep && (!oldest || s->last_used < oldest->last_used))
                oldest = s;
        }
        if (!oldest) {
            uint64_t need = slot_bytes(keep);
            slot_clear(gpu, keep);
            return lucent_fail(err, LUCENT_E_LIMIT, "mesh", "the mesh needs %.1f MB in the renderer; its mesh cache "
                               "holds at most %.1f MB", need / 1048576.0, cache->budget / 1048576.0);
        }
        slot_clear(gpu, oldest);
    }
    return LUCENT_OK;
}

lucent_status mesh_cache_upload(struct gpu *gpu, struct mesh_cache *cache, struct gpu_mesh *s,
                                int projection_size, int side_size, lucent_error *err)
{
    lucent_status st = s->full.gpu ? LUCENT_OK : geometry_create(gpu, s->mesh, 1, &s->full, err);
    if (st == LUCENT_OK)
        st = ensure_proxy(gpu, s->mesh, &s->proxies[PROXY_FRONT], projection_size, err);
    if (st == LUCENT_OK)
        st = ensure_proxy(gpu, s->mesh, &s->proxies[PROXY_SIDES], side_size, err);
    return st == LUCENT_OK ? trim(gpu, cache, s, err) : st;
}

struct gpu_draw gpu_mesh_geometry(const struct gpu_mesh *m, int which)
{
    const struct cached_geometry *g = m->proxies[which].geometry.gpu ? &m->proxies[which].geometry : &m->full;
    return (struct gpu_draw){g->gpu, g->index_count};
}

lucent_status mesh_cache_get(struct gpu *gpu, struct mesh_cache *cache, const lucent_mesh_ref *ref,
                             struct gpu_mesh **out, double *load_ms, lucent_error *err)
{
    char key[sizeof cache->slots[0].key];
    lucent_status st = mesh_key(ref, key, sizeof key, err);
    if (st != LUCENT_OK)
        return st;
    *load_ms = 0.0;
    struct gpu_mesh *victim = &cache->slots[0];
    for (int i = 0; i < MESH_CACHE_SLOTS; i++) {
        struct gpu_mesh *s = &cache->slots[i];
        if (s->mesh && strcmp(s->key, key) == 0) {
            s->last_used = ++cache->clock;
            *out = s;
            return LUCENT_OK;
        }
        if (!s->mesh || (victim->mesh && s->last_used < victim->last_used))
            victim = s;
    }
    double t0 = now_ms();
    /* The GPU may still read the evicted buffers only if a frame were in flight; frames are
     * synchronous, so none is. */
    slot_clear(gpu, victim);
    st = slot_load(ref, victim, err);
    if (st != LUCENT_OK) {
        slot_clear(gpu, victim);
        return st;
    }
    snprintf(victim->key, sizeof victim->key, "%s", key);
    victim->last_used = ++cache->clock;
    if ((st = trim(gpu, cache, victim, err)) != LUCENT_OK)
        return st;
    *load_ms = now_ms() - t0;
    *out = victim;
    return LUCENT_OK;
}

void mesh_cache_destroy(struct gpu *gpu, struct mesh_cache *cache)
{
    for (int i = 0; i < MESH_CACHE_SLOTS; i++)
        slot_clear(gpu, &cache->slots[i]);
}
