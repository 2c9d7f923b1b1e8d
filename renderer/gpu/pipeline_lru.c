/* pipeline_lru.c - the bounded pipeline set of pipeline_lru.h. Linear scans: the set is small, and a
 * miss costs a pipeline compile, which dwarfs them. */
#include "pipeline_lru.h"

#include <string.h>

uint64_t pipeline_lru_find(struct pipeline_lru *lru, uint64_t key, uint64_t frame)
{
    for (int i = 0; i < PIPELINE_LRU_SLOTS; i++)
        if (lru->pipeline[i] && lru->key[i] == key) {
            lru->used[i] = frame;
            return lru->pipeline[i];
        }
    return 0;
}

int pipeline_lru_make_room(struct pipeline_lru *lru, uint64_t frame, uint64_t *evicted)
{
    int oldest = -1;
    *evicted = 0;
    for (int i = 0; i < PIPELINE_LRU_SLOTS; i++) {
        if (!lru->pipeline[i])
            return i;
        if (lru->used[i] != frame && (oldest < 0 || lru->used[i] < lru->used[oldest]))
            oldest = i;
    }
    if (oldest >= 0) {
        *evicted = lru->pipeline[oldest];
        lru->pipeline[oldest] = 0;
    }
    return oldest;
}

void pipeline_lru_put(struct pipeline_lru *lru, int slot, uint64_t key, uint64_t pipeline, uint64_t frame)
{
    lru->key[slot] = key;
    lru->pipeline[slot] = pipeline;
    lru->used[slot] = frame;
}

lucent_status pipeline_lru_get(struct pipeline_lru *lru, uint64_t key, uint64_t frame, const char *kind,
                               uint64_t *found, int *slot, uint64_t *evicted, lucent_error *err)
{
    *evicted = 0;
    if ((*found = pipeline_lru_find(lru, key, frame)))
        return LUCENT_OK;
    if ((*slot = pipeline_lru_make_room(lru, frame, evicted)) < 0)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "more than %d %s pipelines in one frame", PIPELINE_LRU_SLOTS,
                           kind);
    return LUCENT_OK;
}

int pipeline_lru_count(const struct pipeline_lru *lru)
{
    int n = 0;
    for (int i = 0; i < PIPELINE_LRU_SLOTS; i++)
        n += lru->pipeline[i] != 0;
    return n;
}

void pipeline_lru_clear(struct pipeline_lru *lru, void (*destroy)(void *owner, uint64_t pipeline), void *owner)
{
    for (int i = 0; i < PIPELINE_LRU_SLOTS; i++)
        if (lru->pipeline[i])
            destroy(owner, lru->pipeline[i]);
    memset(lru, 0, sizeof *lru);
}
