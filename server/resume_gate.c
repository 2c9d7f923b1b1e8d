/* resume_gate.c - the count of resumes in flight (contract in resume_gate.h). Without it a worker
 * that had finished a job but not yet resumed its connection could call into a stopped daemon. */
#include "resume_gate.h"
#include "render_queue.h" /* monotonic_seconds, realtime_after */

#include <pthread.h>
#include <stdlib.h>
#include <time.h>

struct resume_gate {
    pthread_mutex_t lock;
    pthread_cond_t idle;
    int in_flight;
};

struct resume_gate *resume_gate_create(void)
{
    struct resume_gate *g = calloc(1, sizeof *g);
    if (!g)
        return NULL;
    pthread_mutex_init(&g->lock, NULL);
    pthread_cond_init(&g->idle, NULL);
    return g;
}

void resume_gate_destroy(struct resume_gate *g)
{
    if (!g)
        return;
    pthread_mutex_destroy(&g->lock);
    pthread_cond_destroy(&g->idle);
    free(g);
}

void resume_gate_enter(struct resume_gate *g)
{
    pthread_mutex_lock(&g->lock);
    g->in_flight++;
    pthread_mutex_unlock(&g->lock);
}

#ifdef LUCENT_FAULT_INJECTION
static void injected_delay(void)
{
    const char *ms = getenv("LUCENTD_FAULT_RESUME_DELAY_MS");
    long n = ms ? strtol(ms, NULL, 10) : 0;
    struct timespec pause = {n / 1000, (n % 1000) * 1000000L};
    if (n > 0)
        nanosleep(&pause, NULL);
}
#endif

void resume_gate_resume(struct resume_gate *g, struct MHD_Connection *c)
{
#ifdef LUCENT_FAULT_INJECTION
    injected_delay();
#endif
    MHD_resume_connection(c);
    pthread_mutex_lock(&g->lock);
    if (--g->in_flight == 0)
        pthread_cond_broadcast(&g->idle);
    pthread_mutex_unlock(&g->lock);
}

int resume_gate_wait(struct resume_gate *g, double deadline)
{
    pthread_mutex_lock(&g->lock);
    while (g->in_flight > 0 && monotonic_seconds() < deadline) {
        struct timespec ts = realtime_after(0.05);
        pthread_cond_timedwait(&g->idle, &g->lock, &ts);
    }
    int left = g->in_flight;
    pthread_mutex_unlock(&g->lock);
    return left;
}
