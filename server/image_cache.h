/* image_cache.h - an in-memory LRU of encoded images keyed by their ETag, bounded by a byte budget.
 * Thread-safe: the HTTP thread reads it, the render worker fills it. */
#ifndef LUCENTD_IMAGE_CACHE_H
#define LUCENTD_IMAGE_CACHE_H

#include <stddef.h>
#include <stdint.h>

struct image_cache;

/* budget 0 gives a cache that stores nothing (every get misses). NULL when out of memory. */
struct image_cache *image_cache_create(uint64_t budget);
void image_cache_destroy(struct image_cache *c);
/* On a hit returns 1 and a malloc'd copy of the bytes (the caller frees it) plus the metadata
 * stored with them (a NUL-terminated string, copied into meta up to meta_cap). */
int image_cache_get(struct image_cache *c, const char *key, unsigned char **bytes, size_t *len, char *meta,
                    size_t meta_cap);
/* Stores a copy; an entry costs its bytes, its metadata and its bookkeeping (about 150 bytes), and one
 * costing more than the whole budget is not stored. */
void image_cache_put(struct image_cache *c, const char *key, const unsigned char *bytes, size_t len,
                     const char *meta);
/* What the entries cost, as counted against the budget. */
uint64_t image_cache_bytes(struct image_cache *c);

#endif
