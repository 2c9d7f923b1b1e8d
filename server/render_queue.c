/* render_queue.c - one render worker that alone owns the lucent_renderer, fed by a mutex, a condition variable
 * and a FIFO (Redis bio.c style); each job is finished once, and its finisher resumes the connection. */
#define _GNU_SOURCE /* POLLRDHUP */

#include "render_queue.h"
#include "resume_gate.h"

#include "access_log.h"
#include "image_cache.h"
#include "metrics.h"

#include <poll.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

struct render_queue {
    pthread_mutex_t lock;
    pthread_cond_t wake;        /* worker: a job arrived or stop; starter: ready changed */
    pthread_t thread;
    int capacity;
    struct render_job *head, *tail;
    int queued;
    struct render_job *current;
    lucent_renderer *renderer;  /* the worker's, for lucent_render_cancel (thread-safe) */
    int closed, stop;
    int exited;                 /* the worker has returned; destroy waits for this, bounded */
    int started;                /* 1 warm, -1 failed */
    int recovering;             /* the device was lost; a new renderer is being made */
    lucent_error start_err;
    char backend[16];
    char device[256];
    char backend_request[16];
    char device_request[128];
    uint64_t mesh_cache_bytes;
    uint64_t max_pixels;        /* the renderer's largest image */
    struct metrics *metrics;
    struct image_cache *cache;
    struct resume_gate *resumes;
    uint64_t abandoned;         /* jobs skipped because their client had gone */
};

double monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

struct timespec realtime_after(double seconds)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    ts.tv_sec += (time_t)seconds;
    ts.tv_nsec += (long)((seconds - (double)(time_t)seconds) * 1e9);
    if (ts.tv_nsec >= 1000000000L) {
        ts.tv_sec++;
        ts.tv_nsec -= 1000000000L;
    }
    return ts;
}

struct render_job *render_job_new(void)
{
    struct render_job *job = calloc(1, sizeof *job);
    if (job) {
        job->refs = 1;
        job->client_fd = -1;
    }
    return job;
}

void render_job_release(struct render_queue *q, struct render_job *job)
{
    if (!job)
        return;
    pthread_mutex_lock(&q->lock);
    int last = --job->refs == 0;
    pthread_mutex_unlock(&q->lock);
    if (last) {
        free(job->bytes);
        free(job);
    }
}

/* Under the lock: records the outcome; the caller resumes the connection after unlocking. */
static int finish_locked(struct render_job *job, enum job_outcome outcome)
{
    if (job->outcome != JOB_PENDING)
        return 0;
    job->outcome = outcome;
    return 1;
}

static void remove_queued_locked(struct render_queue *q, struct render_job *job)
{
    struct render_job **p = &q->head;
    while (*p && *p != job)
        p = &(*p)->next;
    if (!*p)
        return;
    *p = job->next;
    if (q->tail == job) {
        q->tail = q->head;
        while (q->tail && q->tail->next)
            q->tail = q->tail->next;
    }
    job->next = NULL;
    q->queued--;
    job->refs--; /* the queue's reference; the request still holds its own */
}

/* Whether the client closed its end while its request waited (nothing would read the image). Its
 * connection is suspended, so libmicrohttpd does not watch the socket, and the descriptor stays open.
 * A client that half-closes after its request counts as gone, as nginx treats it. */
static int client_gone(const struct render_job *job)
{
    struct pollfd p = {job->client_fd, POLLRDHUP, 0};
    return job->client_fd >= 0 && poll(&p, 1, 0) == 1 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR));
}

/* Renders and encodes one job outside the lock. The result goes to the cache even when the request
 * already gave up: a retry of the same scene then finds it. */
static lucent_status run_job(struct render_queue *q, lucent_renderer *r, struct render_job *job, double started,
                             lucent_error *failure)
{
    lucent_error err = {0};
    lucent_image img = {0};
    lucent_stats stats;
    memset(&stats, 0, sizeof stats);
    unsigned char *bytes = NULL;
    size_t len = 0;
    double t0 = monotonic_seconds();
    lucent_status st = lucent_render(r, &job->scene, &img, &stats, &err);
    double t1 = monotonic_seconds();
    if (st == LUCENT_OK)
        st = lucent_image_encode(&img, job->scene.format, job->scene.exposure, job->scene.background, &bytes, &len,
                                 &err);
    double t2 = monotonic_seconds();
    lucent_image_free(&img);
    metrics_observe(q->metrics, HIST_QUEUE_WAIT, job->scene.method, started - job->submitted);
    if (st == LUCENT_OK) {
        metrics_observe(q->metrics, HIST_RENDER, job->scene.method, t1 - t0);
        metrics_observe(q->metrics, HIST_ENCODE, job->scene.method, t2 - t1);
        image_cache_put(q->cache, job->etag, bytes, len, stats.modelled);
    }
    log_line(LOG_DEBUG, "render %.12s: %s in %.1f ms, encoded %zu bytes in %.1f ms%s", job->etag,
             st == LUCENT_OK ? "rendered" : err.message, (t1 - t0) * 1e3, len, (t2 - t1) * 1e3,
             job->outcome == JOB_PENDING ? "" : " (the request had already given up)");
    pthread_mutex_lock(&q->lock);
    q->current = NULL;
    if (st == LUCENT_E_DEVICE_LOST)
        q->recovering = 1;  /* before the answer goes out: a client that reads it sees /readyz 503 */
    int mine = job->outcome == JOB_PENDING;
    if (mine) {
        resume_gate_enter(q->resumes);
        job->stats = stats;
        job->err = err;
        job->bytes = bytes;
        job->len = len;
        job->queue_ms = (started - job->submitted) * 1e3;
        job->encode_ms = (t2 - t1) * 1e3;
        bytes = NULL;
        finish_locked(job, st == LUCENT_OK ? JOB_RENDERED : JOB_FAILED);
    }
    pthread_mutex_unlock(&q->lock);
    free(bytes);
    if (mine)
        resume_gate_resume(q->resumes, job->connection);
    *failure = err;
    return st;
}

/* A tiny frame of the default scene compiles the common pipelines before the daemon reports ready. */
static int warm_up(struct render_queue *q, lucent_renderer *r, lucent_error *err)
{
    lucent_scene scene;
    lucent_scene_defaults(&scene);
    scene.width = scene.height = 64;
    lucent_image img = {0};
    lucent_stats stats;
    lucent_status st = lucent_render(r, &scene, &img, &stats, err);
    lucent_image_free(&img);
    if (st == LUCENT_OK) {
        snprintf(q->backend, sizeof q->backend, "%s", stats.backend);
        snprintf(q->device, sizeof q->device, "%s", stats.device);
    }
    q->max_pixels = lucent_renderer_max_pixels(r);
    return st == LUCENT_OK ? 0 : -1;
}

static lucent_renderer *make_renderer(struct render_queue *q, lucent_error *err)
{
    lucent_renderer_desc desc = {.backend = q->backend_request[0] ? q->backend_request : NULL,
                                 .device_name = q->device_request[0] ? q->device_request : NULL, .verbose = 0,
                                 .mesh_cache_bytes = q->mesh_cache_bytes};
    lucent_renderer *r = lucent_renderer_create(&desc, err);
    if (r && warm_up(q, r, err) != 0) {
        lucent_renderer_destroy(r);
        r = NULL;
    }
    return r;
}

/* The device was lost (a driver reset, a hang): the renderer goes, and a new one on a new device is
 * made and warmed up, retried each second until it works or the daemon stops (NULL). Meanwhile renders
 * are refused (503) and /readyz answers 503; queued renders wait for the new renderer. */
static lucent_renderer *recover(struct render_queue *q, lucent_renderer *lost, const lucent_error *why)
{
    log_line(LOG_ERROR, "%s; re-creating the renderer", why->message);
    metrics_device_lost(q->metrics);
    pthread_mutex_lock(&q->lock);
    q->renderer = NULL;  /* run_job has set recovering already */
    pthread_mutex_unlock(&q->lock);
    lucent_renderer_destroy(lost);
    for (;;) {
        lucent_error err = {0};
        lucent_renderer *r = make_renderer(q, &err);
        pthread_mutex_lock(&q->lock);
        int stop = q->stop;
        if (r) {
            q->renderer = r;
            q->recovering = 0;
        }
        pthread_mutex_unlock(&q->lock);
        if (r) {
            log_line(LOG_INFO, "renderer re-created on %s device \"%s\"", q->backend, q->device);
            return r;
        }
        log_line(LOG_ERROR, "re-creating the renderer failed: %s%s", err.message, stop ? "" : "; retrying in 1 s");
        if (stop)
            return NULL;
        sleep(1);
    }
}

static void *worker(void *arg)
{
    struct render_queue *q = arg;
    lucent_error err = {0};
    lucent_renderer *r = make_renderer(q, &err);
    int ok = r != NULL;
    pthread_mutex_lock(&q->lock);
    q->renderer = ok ? r : NULL;
    q->started = ok ? 1 : -1;
    q->start_err = err;
    pthread_cond_broadcast(&q->wake);
    while (ok) {
        while (!q->head && !q->stop)
            pthread_cond_wait(&q->wake, &q->lock);
        if (!q->head)
            break;
        struct render_job *job = q->head;
        q->head = job->next;
        if (!q->head)
            q->tail = NULL;
        job->next = NULL;
        q->queued--;
        q->current = job; /* the queue's reference moves to the worker */
        int gone = client_gone(job) && finish_locked(job, JOB_CANCELLED);
        if (gone) {
            q->abandoned++;
            q->current = NULL;
            resume_gate_enter(q->resumes);
        }
        pthread_mutex_unlock(&q->lock);
        if (gone) {
            log_line(LOG_INFO, "render %.12s skipped: its client closed the connection while it waited", job->etag);
            resume_gate_resume(q->resumes, job->connection);
            render_job_release(q, job);
            pthread_mutex_lock(&q->lock);
            continue;
        }
        lucent_error failure = {0};
        lucent_status st = run_job(q, r, job, monotonic_seconds(), &failure);
        render_job_release(q, job);
        if (st == LUCENT_E_DEVICE_LOST && !(r = recover(q, r, &failure)))
            ok = 0;
        pthread_mutex_lock(&q->lock);
    }
    q->renderer = NULL;
    pthread_mutex_unlock(&q->lock);
    lucent_renderer_destroy(r);
    pthread_mutex_lock(&q->lock);
    q->exited = 1;
    pthread_cond_broadcast(&q->wake);
    pthread_mutex_unlock(&q->lock);
    return NULL;
}

struct render_queue *render_queue_create(int capacity, const char *backend, const char *device_name,
                                         uint64_t mesh_cache_bytes, struct metrics *metrics, struct image_cache *cache,
                                         struct resume_gate *resumes, lucent_error *err)
{
    struct render_queue *q = calloc(1, sizeof *q);
    if (!q) {
        lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory creating the render queue");
        return NULL;
    }
    pthread_mutex_init(&q->lock, NULL);
    pthread_cond_init(&q->wake, NULL);
    q->capacity = capacity;
    q->mesh_cache_bytes = mesh_cache_bytes;
    q->metrics = metrics;
    q->cache = cache;
    q->resumes = resumes;
    snprintf(q->backend_request, sizeof q->backend_request, "%s", backend ? backend : "");
    snprintf(q->device_request, sizeof q->device_request, "%s", device_name ? device_name : "");
    if (pthread_create(&q->thread, NULL, worker, q) != 0) {
        pthread_cond_destroy(&q->wake);
        pthread_mutex_destroy(&q->lock);
        free(q);
        lucent_fail(err, LUCENT_E_INTERNAL, "", "cannot start the render thread");
        return NULL;
    }
    return q;
}

int render_queue_wait_ready(struct render_queue *q, char backend[16], char *device, size_t cap, uint64_t *max_pixels,
                            lucent_error *err)
{
    pthread_mutex_lock(&q->lock);
    while (!q->started)
        pthread_cond_wait(&q->wake, &q->lock);
    int ok = q->started > 0;
    if (ok) {
        snprintf(backend, 16, "%s", q->backend);
        snprintf(device, cap, "%s", q->device);
        *max_pixels = q->max_pixels;
    }
    else if (err)
        *err = q->start_err;
    pthread_mutex_unlock(&q->lock);
    return ok ? 0 : -1;
}

int render_queue_submit(struct render_queue *q, struct render_job *job)
{
    pthread_mutex_lock(&q->lock);
    int full = q->closed || q->started <= 0 || q->recovering || q->queued + (q->current != NULL) >= q->capacity;
    if (!full) {
        job->refs++;
        job->submitted = monotonic_seconds();
        MHD_suspend_connection(job->connection);
        if (q->tail)
            q->tail->next = job;
        else
            q->head = job;
        q->tail = job;
        q->queued++;
        pthread_cond_signal(&q->wake);
    }
    pthread_mutex_unlock(&q->lock);
    return full ? -1 : 0;
}

/* Collects the connections of the jobs finished here; resumed after the lock is released. */
#define SWEEP_MAX 256

static void sweep(struct render_queue *q, double now, enum job_outcome outcome)
{
    struct MHD_Connection *resume[SWEEP_MAX];
    int n;
    do {
        n = 0;
        pthread_mutex_lock(&q->lock);
        struct render_job *job = q->head;
        while (job && n < SWEEP_MAX) {
            struct render_job *next = job->next;
            if ((outcome == JOB_CANCELLED || job->deadline <= now) && finish_locked(job, outcome)) {
                resume_gate_enter(q->resumes);
                resume[n++] = job->connection;
                remove_queued_locked(q, job);
            }
            job = next;
        }
        struct render_job *cur = q->current;
        int overdue = cur && (outcome == JOB_CANCELLED || cur->deadline <= now);
        /* Stops a long (reference) render whose answer nobody waits for; asked again on every sweep
         * in case the first request came just before the render began. */
        if (overdue && q->renderer)
            lucent_render_cancel(q->renderer);
        if (overdue && n < SWEEP_MAX && finish_locked(cur, outcome)) {
            resume_gate_enter(q->resumes);
            resume[n++] = cur->connection;
        }
        pthread_mutex_unlock(&q->lock);
        for (int i = 0; i < n; i++)
            resume_gate_resume(q->resumes, resume[i]);
    } while (n == SWEEP_MAX);
}

void render_queue_expire(struct render_queue *q, double now)
{
    sweep(q, now, JOB_DEADLINE);
}

void render_queue_cancel_all(struct render_queue *q)
{
    render_queue_close(q);
    sweep(q, 0, JOB_CANCELLED);
}

void render_queue_close(struct render_queue *q)
{
    pthread_mutex_lock(&q->lock);
    q->closed = 1;
    pthread_mutex_unlock(&q->lock);
}

int render_queue_recovering(struct render_queue *q)
{
    pthread_mutex_lock(&q->lock);
    int recovering = q->recovering;
    pthread_mutex_unlock(&q->lock);
    return recovering;
}

uint64_t render_queue_abandoned(struct render_queue *q)
{
    pthread_mutex_lock(&q->lock);
    uint64_t n = q->abandoned;
    pthread_mutex_unlock(&q->lock);
    return n;
}

double render_queue_overdue_seconds(struct render_queue *q, double now)
{
    pthread_mutex_lock(&q->lock);
    double overdue = q->current && now > q->current->deadline ? now - q->current->deadline : 0.0;
    pthread_mutex_unlock(&q->lock);
    return overdue;
}

int render_queue_depth(struct render_queue *q, int *in_flight)
{
    pthread_mutex_lock(&q->lock);
    int depth = q->queued + (q->current != NULL);
    if (in_flight)
        *in_flight = q->current != NULL;
    pthread_mutex_unlock(&q->lock);
    return depth;
}

int render_queue_open_jobs(struct render_queue *q)
{
    pthread_mutex_lock(&q->lock);
    int open = q->queued + (q->current && q->current->outcome == JOB_PENDING);
    pthread_mutex_unlock(&q->lock);
    return open;
}

int render_queue_destroy(struct render_queue *q, double wait_s)
{
    if (!q)
        return 0;
    struct timespec until = realtime_after(wait_s);
    pthread_mutex_lock(&q->lock);
    q->stop = 1;
    q->closed = 1;
    pthread_cond_broadcast(&q->wake);
    while (!q->exited && pthread_cond_timedwait(&q->wake, &q->lock, &until) == 0)
        ;
    int exited = q->exited;
    pthread_mutex_unlock(&q->lock);
    if (!exited)
        return -1; /* stuck in a call that does not return: the queue stays, for the worker's sake */
    pthread_join(q->thread, NULL);
    pthread_cond_destroy(&q->wake);
    pthread_mutex_destroy(&q->lock);
    free(q);
    return 0;
}
