/* server.h - the daemon's shared state: settings, life-cycle phase and the modules every request uses.
 * Created by lucentd.c before the HTTP daemon starts and destroyed after it stops. */
#ifndef LUCENTD_SERVER_H
#define LUCENTD_SERVER_H

#include "config.h"

#include <stdatomic.h>

struct render_queue;
struct image_cache;
struct metrics;
struct mesh_store;
struct upload_queue;

/* starting: the renderer is warming up; serving; draining: SIGTERM received. */
enum server_phase { PHASE_STARTING = 0, PHASE_SERVING, PHASE_DRAINING };

struct server {
    struct config cfg;
    atomic_int phase;
    struct render_queue *queue;
    struct image_cache *cache;
    struct metrics *metrics;
    struct mesh_store *store;
    struct import_jail *jail;
    struct resume_gate *resumes;
    struct connection_guard *guard;
    uint64_t body_bytes;          /* charged by requests receiving or holding a body; MHD's thread only */
    struct upload_queue *uploads;
    char token[256];       /* empty: no token required */
    char backend[16];      /* "vulkan" or "gl", known once serving */
    char device[256];      /* the GPU device, known once serving */
    uint64_t max_pixels;   /* width x height the device can render, known once serving */
    atomic_uint_fast64_t next_request;
    long long started_at;  /* Unix time, part of request ids */
    struct rate_limit *rate_limit;   /* NULL: --rate-limit 0 */
};

#endif
