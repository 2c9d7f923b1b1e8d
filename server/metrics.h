/* metrics.h - Prometheus counters, gauges and histograms of the daemon, written as text for /metrics.
 * Thread-safe; updates are a few additions under one mutex. */
#ifndef LUCENTD_METRICS_H
#define LUCENTD_METRICS_H

#include "lucent.h"

#include <stddef.h>
#include <stdint.h>

enum metric_histogram { HIST_QUEUE_WAIT = 0, HIST_RENDER, HIST_ENCODE, HIST_COUNT };

struct metrics;

/* route_names: the label of each route index (kept, not copied). */
struct metrics *metrics_create(const char *const *route_names, int route_count);
void metrics_destroy(struct metrics *m);
void metrics_request(struct metrics *m, int route, unsigned http_status);
void metrics_observe(struct metrics *m, enum metric_histogram h, lucent_method method, double seconds);
void metrics_cache(struct metrics *m, int hit);
void metrics_device_lost(struct metrics *m);

/* Values sampled when /metrics is scraped. */
struct metrics_gauges {
    int queue_depth, in_flight, ready;
    uint64_t cache_bytes, store_bytes;
    uint64_t body_bytes;
    uint64_t slow_closed;
    uint64_t abandoned; /* queued renders skipped: their client had gone */ /* connections closed past --request-timeout */ /* request bodies in flight, as charged against --max-body-total */
    uint64_t import_violations; /* importers the sandbox stopped */
    const char *backend, *device, *version;
};

/* The exposition text (malloc'd); NULL when out of memory. */
char *metrics_text(struct metrics *m, const struct metrics_gauges *g, size_t *len);

#endif
