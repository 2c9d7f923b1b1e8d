/* image_cache.c - LRU of encoded images keyed by ETag under a byte budget: a doubly linked list in recency
 * order and a hash index on the key. Every byte an entry holds counts: image, metadata and bookkeeping. */
#include "image_cache.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#define ALLOCATION_OVERHEAD 16 /* glibc's per-block header, twice an entry (entry, metadata) */
#define FIRST_BUCKETS 256

struct entry {
    struct entry *prev, *next;   /* recency */
    struct entry *chain;         /* the next entry in its hash bucket */
    uint64_t hash;
    uint64_t cost;               /* what it holds, as counted against the budget */
    char key[65];
    char *meta;
    size_t len;
    unsigned char bytes[];
};

struct image_cache {
    pthread_mutex_t lock;
    struct entry *head, *tail;   /* head: most recently used */
    struct entry **buckets;
    size_t bucket_count, count;  /* bucket_count: a power of two */
    uint64_t budget, used;
};

/* FNV-1a of the key: ETags are already hashes, but the cache takes any string. */
static uint64_t key_hash(const char *key)
{
    uint64_t h = 0xcbf29ce484222325u;
    for (; *key; key++)
        h = (h ^ (unsigned char)*key) * 0x100000001b3u;
    return h;
}

static uint64_t entry_cost(size_t len, const char *meta)
{
    return sizeof(struct entry) + len + strlen(meta) + 1 + 2 * ALLOCATION_OVERHEAD;
}

struct image_cache *image_cache_create(uint64_t budget)
{
    struct image_cache *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->buckets = calloc(FIRST_BUCKETS, sizeof *c->buckets);
    if (!c->buckets) {
        free(c);
        return NULL;
    }
    c->bucket_count = FIRST_BUCKETS;
    pthread_mutex_init(&c->lock, NULL);
    c->budget = budget;
    return c;
}

static struct entry **bucket_of(struct image_cache *c, uint64_t hash)
{
    return &c->buckets[hash & (c->bucket_count - 1)];
}

/* Twice the buckets once there are more entries than buckets; on no memory the chains just grow. */
static void grow_index(struct image_cache *c)
{
    size_t n = c->bucket_count * 2;
    struct entry **grown = calloc(n, sizeof *grown);
    if (!grown)
        return;
    for (struct entry *e = c->head; e; e = e->next) {
        struct entry **b = &grown[e->hash & (n - 1)];
        e->chain = *b;
        *b = e;
    }
    free(c->buckets);
    c->buckets = grown;
    c->bucket_count = n;
}

static void unlink_entry(struct image_cache *c, struct entry *e)
{
    if (e->prev)
        e->prev->next = e->next;
    else
        c->head = e->next;
    if (e->next)
        e->next->prev = e->prev;
    else
        c->tail = e->prev;
    e->prev = e->next = NULL;
}

static void push_front(struct image_cache *c, struct entry *e)
{
    e->next = c->head;
    if (c->head)
        c->head->prev = e;
    c->head = e;
    if (!c->tail)
        c->tail = e;
}

static void drop(struct image_cache *c, struct entry *e)
{
    struct entry **p = bucket_of(c, e->hash);
    while (*p != e)
        p = &(*p)->chain;
    *p = e->chain;
    unlink_entry(c, e);
    c->used -= e->cost;
    c->count--;
    free(e->meta);
    free(e);
}

void image_cache_destroy(struct image_cache *c)
{
    if (!c)
        return;
    while (c->head)
        drop(c, c->head);
    pthread_mutex_destroy(&c->lock);
    free(c->buckets);
    free(c);
}

static struct entry *find(struct image_cache *c, const char *key, uint64_t hash)
{
    for (struct entry *e = *bucket_of(c, hash); e; e = e->chain)
        if (e->hash == hash && strcmp(e->key, key) == 0)
            return e;
    return NULL;
}

int image_cache_get(struct image_cache *c, const char *key, unsigned char **bytes, size_t *len, char *meta,
                    size_t meta_cap)
{
    int hit = 0;
    uint64_t hash = key_hash(key);
    pthread_mutex_lock(&c->lock);
    struct entry *e = find(c, key, hash);
    if (e && (*bytes = malloc(e->len)) != NULL) {
        memcpy(*bytes, e->bytes, e->len);
        *len = e->len;
        if (meta_cap) {
            strncpy(meta, e->meta, meta_cap - 1);
            meta[meta_cap - 1] = 0;
        }
        unlink_entry(c, e);
        push_front(c, e);
        hit = 1;
    }
    pthread_mutex_unlock(&c->lock);
    return hit;
}

void image_cache_put(struct image_cache *c, const char *key, const unsigned char *bytes, size_t len,
                     const char *meta)
{
    uint64_t cost = entry_cost(len, meta);
    if (cost > c->budget || strlen(key) >= sizeof ((struct entry *)0)->key)
        return;
    struct entry *e = malloc(sizeof *e + len);
    char *m = strdup(meta);
    if (!e || !m) {
        free(e);
        free(m); /* the cache is an optimization: on no memory, skip storing */
        return;
    }
    memset(e, 0, sizeof *e);
    strcpy(e->key, key);
    e->hash = key_hash(key);
    e->cost = cost;
    e->meta = m;
    e->len = len;
    memcpy(e->bytes, bytes, len);
    pthread_mutex_lock(&c->lock);
    struct entry *old = find(c, key, e->hash);
    if (old)
        drop(c, old);
    while (c->tail && c->used + cost > c->budget)
        drop(c, c->tail);
    if (c->count >= c->bucket_count)
        grow_index(c);
    struct entry **b = bucket_of(c, e->hash);
    e->chain = *b;
    *b = e;
    push_front(c, e);
    c->used += cost;
    c->count++;
    pthread_mutex_unlock(&c->lock);
}

uint64_t image_cache_bytes(struct image_cache *c)
{
    pthread_mutex_lock(&c->lock);
    uint64_t u = c->used;
    pthread_mutex_unlock(&c->lock);
    return u;
}
