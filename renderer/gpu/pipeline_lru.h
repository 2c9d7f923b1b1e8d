/* pipeline_lru.h - a bounded set of specialized pipelines (Vulkan pipelines, OpenGL programs), keyed by
 * variant number, the least recently used one evicted first: a CPU driver keeps megabytes of code for each. */
#ifndef LUCENT_PIPELINE_LRU_H
#define LUCENT_PIPELINE_LRU_H

#include "lucent.h"

#include <stdint.h>

#define PIPELINE_LRU_SLOTS 16

/* Handles are the backend's, widened to 64 bits; 0 is no pipeline. */
struct pipeline_lru {
    uint64_t key[PIPELINE_LRU_SLOTS];
    uint64_t pipeline[PIPELINE_LRU_SLOTS];
    uint64_t used[PIPELINE_LRU_SLOTS];  /* the frame that last asked for it */
};

/* The pipeline kept for key, marked used by frame; 0 when none is. */
uint64_t pipeline_lru_find(struct pipeline_lru *lru, uint64_t key, uint64_t frame);
/* A slot for a new pipeline: an empty one, else that of the least recently used one not used by frame,
 * which is taken out and left in *evicted for the caller to destroy (0: none; the caller guarantees no
 * earlier frame is still executing). -1 when every slot is used by frame. */
int pipeline_lru_make_room(struct pipeline_lru *lru, uint64_t frame, uint64_t *evicted);
void pipeline_lru_put(struct pipeline_lru *lru, int slot, uint64_t key, uint64_t pipeline, uint64_t frame);
/* The pipeline kept for key in *found (marked used by frame), or 0 there and in *slot where a new one goes
 * (pipeline_lru_make_room; *evicted is the caller's to destroy); `kind` names the set in the error. */
lucent_status pipeline_lru_get(struct pipeline_lru *lru, uint64_t key, uint64_t frame, const char *kind,
                               uint64_t *found, int *slot, uint64_t *evicted, lucent_error *err);
/* Pipelines kept. */
int pipeline_lru_count(const struct pipeline_lru *lru);
/* Empties the set, handing each pipeline to destroy. */
void pipeline_lru_clear(struct pipeline_lru *lru, void (*destroy)(void *owner, uint64_t pipeline), void *owner);

#endif
