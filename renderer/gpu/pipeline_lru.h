/* pipeline_lru.h - a bounded set of specialized pipelines, keyed by variant number, the least recently
 * used one destroyed first: a CPU driver keeps megabytes of generated code for each pipeline. */
#ifndef LUCENT_PIPELINE_LRU_H
#define LUCENT_PIPELINE_LRU_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#define PIPELINE_LRU_SLOTS 16

struct pipeline_lru {
    uint64_t key[PIPELINE_LRU_SLOTS];
    VkPipeline pipeline[PIPELINE_LRU_SLOTS];
    uint64_t used[PIPELINE_LRU_SLOTS];  /* the frame that last asked for it */
};

/* The pipeline kept for key, marked used by frame; VK_NULL_HANDLE when none is. */
VkPipeline pipeline_lru_find(struct pipeline_lru *lru, uint64_t key, uint64_t frame);
/* A slot for a new pipeline: an empty one, else the least recently used one not used by frame, whose
 * pipeline is destroyed (the caller guarantees no earlier frame is still executing). -1 when every slot
 * is used by frame. */
int pipeline_lru_make_room(struct pipeline_lru *lru, VkDevice device, uint64_t frame);
void pipeline_lru_put(struct pipeline_lru *lru, int slot, uint64_t key, VkPipeline pipeline, uint64_t frame);
/* Pipelines kept. */
int pipeline_lru_count(const struct pipeline_lru *lru);
void pipeline_lru_destroy(struct pipeline_lru *lru, VkDevice device);

#endif
