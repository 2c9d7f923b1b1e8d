/* metrics.c - the daemon's Prometheus metrics: requests by route and status, queue-wait, render and encode
 * latency histograms by method, cache hits and misses, and gauges sampled at scrape time. */
#include "metrics.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define STATUS_MIN 100
#define STATUS_COUNT 500
#define METHOD_COUNT 6  /* five, single, reference, auto, path, other */

/* Seconds: from a cached small render (ms) to a slow reference render (a minute). */
static const double bounds[] = {0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60};
#define BUCKETS (sizeof bounds / sizeof bounds[0])

struct histogram {
    uint64_t bucket[BUCKETS], count;
    double sum;
};

struct metrics {
    pthread_mutex_t lock;
    const char *const *routes;
    int route_count;
    uint64_t *requests;  /* [route][status - STATUS_MIN] */
    struct histogram hist[HIST_COUNT][METHOD_COUNT];
    uint64_t cache_hits, cache_misses;
    uint64_t devices_lost;
};

static const char *const hist_names[HIST_COUNT] = {"lucentd_queue_wait_seconds", "lucentd_render_seconds",
                                                   "lucentd_encode_seconds"};
static const char *const hist_help[HIST_COUNT] = {
    "Time a render request waited in the queue.", "Time the renderer took for one frame.",
    "Time encoding one image to PNG or EXR took."};

static int method_index(lucent_method m)
{
    switch (m) {
    case LUCENT_METHOD_FIVE: return 0;
    case LUCENT_METHOD_SINGLE: return 1;
    case LUCENT_METHOD_REFERENCE: return 2;
    case LUCENT_METHOD_AUTO: return 3;
    case LUCENT_METHOD_PATH: return 4;
    default: return 5;
    }
}
static const char *const method_labels[METHOD_COUNT] = {"five", "single", "reference", "auto", "path", "other"};

struct metrics *metrics_create(const char *const *route_names, int route_count)
{
    struct metrics *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    m->requests = calloc((size_t)route_count * STATUS_COUNT, sizeof *m->requests);
    if (!m->requests) {
        free(m);
        return NULL;
    }
    pthread_mutex_init(&m->lock, NULL);
    m->routes = route_names;
    m->route_count = route_count;
    return m;
}

void metrics_destroy(struct metrics *m)
{
    if (!m)
        return;
    pthread_mutex_destroy(&m->lock);
    free(m->requests);
    free(m);
}

void metrics_request(struct metrics *m, int route, unsigned status)
{
    if (route < 0 || route >= m->route_count || status < STATUS_MIN || status >= STATUS_MIN + STATUS_COUNT)
        return;
    pthread_mutex_lock(&m->lock);
    m->requests[(size_t)route * STATUS_COUNT + (status - STATUS_MIN)]++;
    pthread_mutex_unlock(&m->lock);
}

void metrics_observe(struct metrics *m, enum metric_histogram h, lucent_method method, double seconds)
{
    pthread_mutex_lock(&m->lock);
    struct histogram *hg = &m->hist[h][method_index(method)];
    for (size_t i = 0; i < BUCKETS; i++)
        if (seconds <= bounds[i])
            hg->bucket[i]++;
    hg->count++;
    hg->sum += seconds;
    pthread_mutex_unlock(&m->lock);
}

void metrics_cache(struct metrics *m, int hit)
{
    pthread_mutex_lock(&m->lock);
    if (hit)
        m->cache_hits++;
    else
        m->cache_misses++;
    pthread_mutex_unlock(&m->lock);
}

void metrics_device_lost(struct metrics *m)
{
    pthread_mutex_lock(&m->lock);
    m->devices_lost++;
    pthread_mutex_unlock(&m->lock);
}

struct text {
    char *buf;
    size_t len, cap;
    int failed;
};

static void add(struct text *t, const char *fmt, ...)
{
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = t->failed ? 0 : vsnprintf(t->buf + t->len, t->cap - t->len, fmt, ap);
        va_end(ap);
        if (t->failed || n < 0) {
            t->failed = 1;
            return;
        }
        if ((size_t)n < t->cap - t->len) {
            t->len += (size_t)n;
            return;
        }
        char *grown = realloc(t->buf, t->cap * 2 + (size_t)n);
        if (!grown) {
            t->failed = 1;
            return;
        }
        t->buf = grown;
        t->cap = t->cap * 2 + (size_t)n;
    }
}

/* Label values are ours or the Vulkan driver's; quotes and backslashes are escaped anyway. */
static void label_value(const char *in, char *out, size_t cap)
{
    size_t o = 0;
    for (; *in && o + 2 < cap; in++) {
        if (*in == '"' || *in == '\\')
            out[o++] = '\\';
        out[o++] = *in == '\n' ? ' ' : *in;
    }
    out[o] = 0;
}

char *metrics_text(struct metrics *m, const struct metrics_gauges *g, size_t *len)
{
    struct text t = {malloc(16384), 0, 16384, 0};
    if (!t.buf)
        return NULL;
    char backend[64], device[512], version[128];
    label_value(g->backend ? g->backend : "", backend, sizeof backend);
    label_value(g->device ? g->device : "", device, sizeof device);
    label_value(g->version, version, sizeof version);
    add(&t, "# HELP lucentd_build_info Build, GPU backend and device of this daemon.\n# TYPE lucentd_build_info gauge\n"
            "lucentd_build_info{version=\"%s\",backend=\"%s\",device=\"%s\"} 1\n", version, backend, device);
    add(&t, "# HELP lucentd_ready 1 when the renderer is warm and the daemon is not draining.\n"
            "# TYPE lucentd_ready gauge\nlucentd_ready %d\n", g->ready);
    add(&t, "# HELP lucentd_queue_depth Render requests waiting or running.\n# TYPE lucentd_queue_depth gauge\n"
            "lucentd_queue_depth %d\n", g->queue_depth);
    add(&t, "# HELP lucentd_renders_in_flight Renders running now.\n# TYPE lucentd_renders_in_flight gauge\n"
            "lucentd_renders_in_flight %d\n", g->in_flight);
    add(&t, "# HELP lucentd_image_cache_bytes Bytes of encoded images cached.\n# TYPE lucentd_image_cache_bytes gauge\n"
            "lucentd_image_cache_bytes %llu\n", (unsigned long long)g->cache_bytes);
    add(&t, "# HELP lucentd_request_body_bytes Request bodies being received or held (declared lengths in full).\n"
            "# TYPE lucentd_request_body_bytes gauge\nlucentd_request_body_bytes %llu\n", (unsigned long long)g->body_bytes);
    add(&t, "# HELP lucentd_renders_abandoned_total Queued renders skipped because their client had closed its "
            "connection.\n# TYPE lucentd_renders_abandoned_total counter\nlucentd_renders_abandoned_total %llu\n",
        (unsigned long long)g->abandoned);
    add(&t, "# HELP lucentd_slow_requests_closed_total Connections closed for taking over --request-timeout to "
            "send a request.\n# TYPE lucentd_slow_requests_closed_total counter\nlucentd_slow_requests_closed_total %llu\n",
        (unsigned long long)g->slow_closed);
    add(&t, "# HELP lucentd_mesh_store_bytes Bytes of uploaded meshes stored.\n# TYPE lucentd_mesh_store_bytes gauge\n"
            "lucentd_mesh_store_bytes %llu\n", (unsigned long long)g->store_bytes);
    add(&t, "# HELP lucentd_import_sandbox_violations_total Mesh importers killed by their sandbox (a hostile "
            "file made one attempt a forbidden system call).\n# TYPE lucentd_import_sandbox_violations_total counter\n"
            "lucentd_import_sandbox_violations_total %llu\n", (unsigned long long)g->import_violations);
    pthread_mutex_lock(&m->lock);
    add(&t, "# HELP lucentd_image_cache_hits_total Renders answered from the image cache.\n"
            "# TYPE lucentd_image_cache_hits_total counter\nlucentd_image_cache_hits_total %llu\n"
            "# HELP lucentd_image_cache_misses_total Renders not in the image cache.\n"
            "# TYPE lucentd_image_cache_misses_total counter\nlucentd_image_cache_misses_total %llu\n",
        (unsigned long long)m->cache_hits, (unsigned long long)m->cache_misses);
    add(&t, "# HELP lucentd_devices_lost_total GPU devices lost (the renderer was re-created on a new one).\n"
            "# TYPE lucentd_devices_lost_total counter\nlucentd_devices_lost_total %llu\n",
        (unsigned long long)m->devices_lost);
    add(&t, "# HELP lucentd_http_requests_total HTTP requests answered, by route and status.\n"
            "# TYPE lucentd_http_requests_total counter\n");
    for (int r = 0; r < m->route_count; r++)
        for (int s = 0; s < STATUS_COUNT; s++)
            if (m->requests[(size_t)r * STATUS_COUNT + (size_t)s])
                add(&t, "lucentd_http_requests_total{route=\"%s\",code=\"%d\"} %llu\n", m->routes[r], s + STATUS_MIN,
                    (unsigned long long)m->requests[(size_t)r * STATUS_COUNT + (size_t)s]);
    for (int h = 0; h < HIST_COUNT; h++) {
        add(&t, "# HELP %s %s\n# TYPE %s histogram\n", hist_names[h], hist_help[h], hist_names[h]);
        for (int k = 0; k < METHOD_COUNT; k++) {
            const struct histogram *hg = &m->hist[h][k];
            for (size_t i = 0; i < BUCKETS; i++)
                add(&t, "%s_bucket{method=\"%s\",le=\"%g\"} %llu\n", hist_names[h], method_labels[k], bounds[i],
                    (unsigned long long)hg->bucket[i]);
            add(&t, "%s_bucket{method=\"%s\",le=\"+Inf\"} %llu\n%s_sum{method=\"%s\"} %.6f\n%s_count{method=\"%s\"} %llu\n",
                hist_names[h], method_labels[k], (unsigned long long)hg->count, hist_names[h], method_labels[k],
                hg->sum, hist_names[h], method_labels[k], (unsigned long long)hg->count);
        }
    }
    pthread_mutex_unlock(&m->lock);
    if (t.failed) {
        free(t.buf);
        return NULL;
    }
    *len = t.len;
    return t.buf;
}
