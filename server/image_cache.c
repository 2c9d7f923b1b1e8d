/* image_cache.c - LRU of encoded images keyed by ETag under a byte budget: a doubly linked list in recency
 * order, scanned on lookup (cheap next to a render for the few thousand entries a budget allows). */
#include "image_cache.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

struct entry {
    struct entry *prev, *next;
    char key[65];
    char *meta;
    size_t len;
    unsigned char bytes[];
};

struct image_cache {
    pthread_mutex_t lock;
    struct entry *head, *tail;   /* head: most recently used */
    uint64_t budget, used;
};

struct image_cache *image_cache_create(uint64_t budget)
{
    struct image_cache *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    pthread_mutex_init(&c->lock, NULL);
    c->budget = budget;
    return c;
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
    unlink_entry(c, e);
    c->used -= e->len;
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
    free(c);
}

static struct entry *find(struct image_cache *c, const char *key)
{
    for (struct entry *e = c->head; e; e = e->next)
        if (strcmp(e->key, key) == 0)
            return e;
    return NULL;
}

int image_cache_get(struct image_cache *c, const char *key, unsigned char **bytes, size_t *len, char *meta,
                    size_t meta_cap)
{
    int hit = 0;
    pthread_mutex_lock(&c->lock);
    struct entry *e = find(c, key);
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
    if (len > c->budget || strlen(key) >= sizeof ((struct entry *)0)->key)
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
    e->meta = m;
    e->len = len;
    memcpy(e->bytes, bytes, len);
    pthread_mutex_lock(&c->lock);
    struct entry *old = find(c, key);
    if (old)
        drop(c, old);
    while (c->tail && c->used + len > c->budget)
        drop(c, c->tail);
    push_front(c, e);
    c->used += len;
    pthread_mutex_unlock(&c->lock);
}

uint64_t image_cache_bytes(struct image_cache *c)
{
    pthread_mutex_lock(&c->lock);
    uint64_t u = c->used;
    pthread_mutex_unlock(&c->lock);
    return u;
}
