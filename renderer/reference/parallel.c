/* parallel.c - the thread pool of parallel.h: a shared counter hands out chunks; no queue, no state
 * kept between runs. */
#include "parallel.h"

#include <pthread.h>
#include <unistd.h>

struct job {
    void *ctx;
    parallel_fn fn;
    size_t count, chunk;
    const atomic_int *cancel;
    atomic_size_t next;
};

static void *job_worker(void *arg)
{
    struct job *job = arg;
    for (;;) {
        size_t begin = atomic_fetch_add(&job->next, job->chunk);
        if (begin >= job->count || (job->cancel && atomic_load(job->cancel)))
            return NULL;
        size_t end = begin + job->chunk < job->count ? begin + job->chunk : job->count;
        job->fn(job->ctx, begin, end);
    }
}

void parallel_run(void *ctx, int threads, size_t count, size_t chunk, parallel_fn fn, const atomic_int *cancel)
{
    struct job job = {.ctx = ctx, .fn = fn, .count = count, .chunk = chunk, .cancel = cancel};
    atomic_init(&job.next, 0);
    pthread_t tid[PARALLEL_MAX_THREADS];
    int started = 0;
    for (int i = 1; i < threads && i < PARALLEL_MAX_THREADS; i++)
        if (pthread_create(&tid[started], NULL, job_worker, &job) == 0)
            started++;
    job_worker(&job);
    for (int i = 0; i < started; i++)
        pthread_join(tid[i], NULL);
}

int parallel_threads(int requested)
{
    long n = requested > 0 ? requested : sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > PARALLEL_MAX_THREADS ? PARALLEL_MAX_THREADS : (int)n;
}
