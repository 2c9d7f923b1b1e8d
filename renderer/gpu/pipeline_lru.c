/* pipeline_lru.c - the bounded pipeline set of pipeline_lru.h. Linear scans: the set is small, and a
 * miss costs a pipeline compile, which dwarfs them. */
#include "pipeline_lru.h"

#include <string.h>

VkPipeline pipeline_lru_find(struct pipeline_lru *lru, uint64_t key, uint64_t frame)
{
    for (int i = 0; i < PIPELINE_LRU_SLOTS; i++)
        if (lru->pipeline[i] && lru->key[i] == key) {
            lru->used[i] = frame;
            return lru->pipeline[i];
        }
    return VK_NULL_HANDLE;
}

int pipeline_lru_make_room(struct pipeline_lru *lru, VkDevice device, uint64_t frame)
{
    int oldest = -1;
    for (int i = 0; i < PIPELINE_LRU_SLOTS; i++) {
        if (!lru->pipeline[i])
            return i;
        if (lru->used[i] != frame && (oldest < 0 || lru->used[i] < lru->used[oldest]))
            oldest = i;
    }
    if (oldest >= 0) {
        vkDestroyPipeline(device, lru->pipeline[oldest], NULL);
        lru->pipeline[oldest] = VK_NULL_HANDLE;
    }
    return oldest;
}

void pipeline_lru_put(struct pipeline_lru *lru, int slot, uint64_t key, VkPipeline pipeline, uint64_t frame)
{
    lru->key[slot] = key;
    lru->pipeline[slot] = pipeline;
    lru->used[slot] = frame;
}

int pipeline_lru_count(const struct pipeline_lru *lru)
{
    int n = 0;
    for (int i = 0; i < PIPELINE_LRU_SLOTS; i++)
        n += lru->pipeline[i] != VK_NULL_HANDLE;
    return n;
}

void pipeline_lru_destroy(struct pipeline_lru *lru, VkDevice device)
{
    for (int i = 0; i < PIPELINE_LRU_SLOTS; i++)
        vkDestroyPipeline(device, lru->pipeline[i], NULL);
    memset(lru, 0, sizeof *lru);
}
