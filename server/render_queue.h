/* render_queue.h - the bounded FIFO of render jobs and the one worker thread that owns the renderer; jobs
 * are reference-counted so a request that gave up never leaves the worker writing freed memory. */
#ifndef LUCENTD_RENDER_QUEUE_H
#define LUCENTD_RENDER_QUEUE_H

#include "lucent.h"

#include <microhttpd.h>
#include <time.h>

struct metrics;
struct image_cache;

enum job_outcome { JOB_PENDING = 0, JOB_RENDERED, JOB_FAILED, JOB_DEADLINE, JOB_CANCELLED };

struct render_job {
    /* Set by the submitter, read-only once submitted. */
    lucent_scene scene;
    char etag[65];
    struct MHD_Connection *connection;
    int client_fd;              /* its socket: open while the connection is suspended; -1 unknown */
    double deadline;            /* monotonic seconds */
    double submitted;
    /* Written by whoever finishes the job, before outcome is set; read after the resume. */
    enum job_outcome outcome;
    lucent_error err;
    unsigned char *bytes;       /* the encoded image (JOB_RENDERED) */
    size_t len;
    lucent_stats stats;
    double queue_ms, encode_ms;
    /* Owned by the queue's lock. */
    int refs;
    int running;
    struct render_job *next;    /* in the FIFO */
};

struct render_queue;

struct resume_gate;

/* Starts the worker, which creates the renderer and warms it with one small frame. backend and
 * device_name may be NULL or "" (automatic). Connections are resumed through `resumes`, which must
 * outlive the queue. */
struct render_queue *render_queue_create(int capacity, const char *backend, const char *device_name,
                                         uint64_t mesh_cache_bytes, struct metrics *metrics, struct image_cache *cache,
                                         struct resume_gate *resumes, lucent_error *err);
/* Blocks until the renderer is warm (0: backend, device and the largest image in pixels filled in) or failed
 * to start (-1, err). */
int render_queue_wait_ready(struct render_queue *q, char backend[16], char *device, size_t cap, uint64_t *max_pixels,
                            lucent_error *err);
/* A new job holding one reference (the caller's), or NULL when out of memory. */
struct render_job *render_job_new(void);
void render_job_release(struct render_queue *q, struct render_job *job);
/* Suspends job->connection and queues the job (taking a reference of its own), both under the queue's
 * lock so the worker cannot finish it first; the queue resumes the connection exactly once. Call it
 * from the connection's access handler. -1 (nothing suspended): the queue is full or closed. */
int render_queue_submit(struct render_queue *q, struct render_job *job);
/* Finishes, with JOB_DEADLINE, every job whose deadline has passed. Call it periodically. */
void render_queue_expire(struct render_queue *q, double now);
/* Finishes every unfinished job with JOB_CANCELLED and refuses new ones. */
void render_queue_cancel_all(struct render_queue *q);
/* Stops accepting jobs; queued ones still run. */
void render_queue_close(struct render_queue *q);
/* 1 while the renderer is being re-created after its device was lost (submissions are refused). */
int render_queue_recovering(struct render_queue *q);
/* Jobs waiting or running; in_flight (may be NULL) gets the running count. */
int render_queue_depth(struct render_queue *q, int *in_flight);
/* Seconds the worker has been on its current render past that render's deadline (0 when none): the
 * sweep cancels an overdue frame, so a worker that stays there is stuck in the driver. */
double render_queue_overdue_seconds(struct render_queue *q, double now);
/* Queued renders skipped because their client closed its connection while they waited. */
uint64_t render_queue_abandoned(struct render_queue *q);
/* Jobs not yet finished (resumed). */
int render_queue_open_jobs(struct render_queue *q);
/* Stops the worker after its current render, waiting at most wait_s, then frees the queue (the worker
 * destroys the renderer). -1 when the worker did not return in time (stuck in the driver or in I/O):
 * nothing is freed, and the caller should exit without touching the renderer's device. */
int render_queue_destroy(struct render_queue *q, double wait_s);

double monotonic_seconds(void);
/* CLOCK_REALTIME `seconds` from now, the form pthread_cond_timedwait takes. */
struct timespec realtime_after(double seconds);

#endif
