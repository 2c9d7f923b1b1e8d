/* upload_queue.c - mesh_store_put on a detached thread per upload (a few at a time), resuming the connection
 * when the import ends; shutdown cancels answers, never imports, so the store is never half-written. */
#include "upload_queue.h"
#include "resume_gate.h"

#include "render_queue.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct upload_queue {
    pthread_mutex_t lock;
    pthread_cond_t idle;
    struct mesh_store *store;
    struct resume_gate *resumes;
    int max_running, running, closed;
    struct upload_job *jobs;
};

struct upload_queue *upload_queue_create(struct mesh_store *store, int max_running, struct resume_gate *resumes)
{
    struct upload_queue *q = calloc(1, sizeof *q);
    if (!q)
        return NULL;
    pthread_mutex_init(&q->lock, NULL);
    pthread_cond_init(&q->idle, NULL);
    q->store = store;
    q->resumes = resumes;
    q->max_running = max_running;
    return q;
}

struct upload_job *upload_job_new(unsigned char *bytes, size_t len, const char *format)
{
    struct upload_job *job = calloc(1, sizeof *job);
    if (!job) {
        free(bytes);
        return NULL;
    }
    job->refs = 1;
    job->bytes = bytes;
    job->len = len;
    strncpy(job->format, format, sizeof job->format - 1);
    return job;
}

void upload_job_release(struct upload_queue *q, struct upload_job *job)
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

struct thread_arg {
    struct upload_queue *q;
    struct upload_job *job;
};

static void *import_thread(void *arg)
{
    struct upload_queue *q = ((struct thread_arg *)arg)->q;
    struct upload_job *job = ((struct thread_arg *)arg)->job;
    free(arg);
    lucent_error err = {0};
    char id[65] = "";
    struct mesh_info info;
    int created = 0;
    memset(&info, 0, sizeof info);
    lucent_status st = mesh_store_put(q->store, job->bytes, job->len, job->format, id, &info, &created, &err);
    pthread_mutex_lock(&q->lock);
    int mine = job->done == 0;
    if (mine) {
        job->status = st;
        job->err = err;
        memcpy(job->id, id, sizeof id);
        job->info = info;
        job->created = created;
        job->done = 1;
        resume_gate_enter(q->resumes);
    }
    for (struct upload_job **p = &q->jobs; *p; p = &(*p)->next)
        if (*p == job) {
            *p = job->next;
            break;
        }
    pthread_mutex_unlock(&q->lock);
    if (mine)
        resume_gate_resume(q->resumes, job->connection);
    upload_job_release(q, job);
    /* Last: once running reaches 0, the queue may be destroyed. */
    pthread_mutex_lock(&q->lock);
    q->running--;
    pthread_cond_broadcast(&q->idle);
    pthread_mutex_unlock(&q->lock);
    return NULL;
}

int upload_queue_submit(struct upload_queue *q, struct upload_job *job)
{
    struct thread_arg *arg = malloc(sizeof *arg);
    if (!arg)
        return -1;
    arg->q = q;
    arg->job = job;
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
    pthread_t thread;
    int rc = -1;
    pthread_mutex_lock(&q->lock);
    /* The thread resumes the connection only after taking this lock, so suspending after creating it,
     * still under the lock, cannot come too late. This runs on MHD's own thread, which never waits for
     * this lock while holding an MHD lock. */
    if (!q->closed && q->running < q->max_running && pthread_create(&thread, &attr, import_thread, arg) == 0) {
        job->refs++;
        q->running++;
        job->next = q->jobs;
        q->jobs = job;
        MHD_suspend_connection(job->connection);
        rc = 0;
    }
    pthread_mutex_unlock(&q->lock);
    pthread_attr_destroy(&attr);
    if (rc != 0)
        free(arg);
    return rc;
}

/* Connections are resumed after the lock is released: MHD may call back into this queue (a request
 * completing releases its job) while it holds its own locks. */
void upload_queue_cancel_all(struct upload_queue *q)
{
    pthread_mutex_lock(&q->lock);
    q->closed = 1;
    int n = 0;
    for (struct upload_job *job = q->jobs; job; job = job->next)
        n += job->done == 0;
    struct MHD_Connection **resume = n ? calloc((size_t)n, sizeof *resume) : NULL;
    n = 0;
    for (struct upload_job *job = q->jobs; job && resume; job = job->next)
        if (job->done == 0) {
            job->done = -1;
            resume[n++] = job->connection;
            resume_gate_enter(q->resumes);
        }
    pthread_mutex_unlock(&q->lock);
    for (int i = 0; i < n; i++)
        resume_gate_resume(q->resumes, resume[i]);
    free(resume);
}

int upload_queue_wait_idle(struct upload_queue *q, double deadline)
{
    pthread_mutex_lock(&q->lock);
    while (q->running > 0 && monotonic_seconds() < deadline) {
        struct timespec ts = realtime_after(0.05);
        pthread_cond_timedwait(&q->idle, &q->lock, &ts);
    }
    int running = q->running;
    pthread_mutex_unlock(&q->lock);
    return running;
}

void upload_queue_destroy(struct upload_queue *q)
{
    if (!q)
        return;
    pthread_mutex_lock(&q->lock);
    q->closed = 1;
    while (q->running > 0)
        pthread_cond_wait(&q->idle, &q->lock);
    pthread_mutex_unlock(&q->lock);
    pthread_cond_destroy(&q->idle);
    pthread_mutex_destroy(&q->lock);
    free(q);
}
