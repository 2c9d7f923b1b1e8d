/* rate_limit.c - the token buckets of --rate-limit, by client address (IPv4 and IPv6; clients behind
 * one proxy or NAT share a bucket). A fixed table bounds the memory whatever the number of clients. */
#include "rate_limit.h"

#include <netinet/in.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Buckets tracked, and slots probed for an address. When all probed slots hold other clients, the one
 * seen longest ago is given to the new client (a client forgotten so starts with a full bucket). */
#define RATE_BUCKETS 4096
#define RATE_PROBES 8

struct bucket {
    unsigned char addr[16];   /* IPv6, or IPv4-mapped */
    int used;
    double tokens, last;
};

struct rate_limit {
    pthread_mutex_t lock;
    double rate, burst;
    struct bucket buckets[RATE_BUCKETS];
};

struct rate_limit *rate_limit_new(double rate, double burst)
{
    struct rate_limit *rl = calloc(1, sizeof *rl);
    if (!rl)
        return NULL;
    if (pthread_mutex_init(&rl->lock, NULL) != 0) {
        free(rl);
        return NULL;
    }
    rl->rate = rate;
    rl->burst = burst;
    return rl;
}

void rate_limit_free(struct rate_limit *rl)
{
    if (!rl)
        return;
    pthread_mutex_destroy(&rl->lock);
    free(rl);
}

/* The address as 16 bytes: IPv6 as is, IPv4 mapped (::ffff:a.b.c.d); other families share one key. */
static void address_key(const struct sockaddr *addr, unsigned char key[16])
{
    memset(key, 0, 16);
    if (addr && addr->sa_family == AF_INET6) {
        memcpy(key, &((const struct sockaddr_in6 *)(const void *)addr)->sin6_addr, 16);
    } else if (addr && addr->sa_family == AF_INET) {
        key[10] = key[11] = 0xff;
        memcpy(key + 12, &((const struct sockaddr_in *)(const void *)addr)->sin_addr, 4);
    }
}

static uint32_t key_hash(const unsigned char key[16])
{
    uint32_t h = 2166136261u;   /* FNV-1a */
    for (int i = 0; i < 16; i++)
        h = (h ^ key[i]) * 16777619u;
    return h;
}

/* The bucket of key: its own, else a free slot, else the probed slot seen longest ago, refilled. */
static struct bucket *find_bucket(struct rate_limit *rl, const unsigned char key[16], double now)
{
    uint32_t h = key_hash(key);
    struct bucket *victim = NULL;
    for (int i = 0; i < RATE_PROBES; i++) {
        struct bucket *b = &rl->buckets[(h + (uint32_t)i) % RATE_BUCKETS];
        if (b->used && memcmp(b->addr, key, 16) == 0)
            return b;
        if (!victim || (victim->used && (!b->used || b->last < victim->last)))
            victim = b;
    }
    memcpy(victim->addr, key, 16);
    victim->used = 1;
    victim->tokens = rl->burst;
    victim->last = now;
    return victim;
}

double rate_limit_take(struct rate_limit *rl, const struct sockaddr *addr, double now)
{
    unsigned char key[16];
    address_key(addr, key);
    pthread_mutex_lock(&rl->lock);
    struct bucket *b = find_bucket(rl, key, now);
    if (now > b->last) {
        b->tokens += (now - b->last) * rl->rate;
        if (b->tokens > rl->burst)
            b->tokens = rl->burst;
        b->last = now;
    }
    double wait = 0.0;
    if (b->tokens >= 1.0)
        b->tokens -= 1.0;
    else
        wait = (1.0 - b->tokens) / rl->rate;
    pthread_mutex_unlock(&rl->lock);
    return wait;
}
