/* connection_guard.c - the whole-request deadline (contract in connection_guard.h). Sockets are shut
 * down, never closed, and only under the lock that the close notification also takes, so a socket
 * number libmicrohttpd has already reused is never touched. */
#include "connection_guard.h"
#include "render_queue.h" /* monotonic_seconds */

#include <pthread.h>
#include <stdlib.h>
#include <sys/socket.h>

struct guarded {
    int fd;
    double since;      /* when the client's clock started */
    int working;       /* the request arrived whole: the clock is stopped */
    int shut;
    struct connection_guard *guard;
    struct guarded *prev, *next;
};

struct connection_guard {
    pthread_mutex_t lock;
    double deadline_s;
    struct guarded *head;
    uint64_t closed;
};

struct connection_guard *connection_guard_create(double deadline_s)
{
    struct connection_guard *g = calloc(1, sizeof *g);
    if (!g)
        return NULL;
    pthread_mutex_init(&g->lock, NULL);
    g->deadline_s = deadline_s;
    return g;
}

void connection_guard_destroy(struct connection_guard *g)
{
    if (!g)
        return;
    while (g->head) {
        struct guarded *e = g->head;
        g->head = e->next;
        free(e);
    }
    pthread_mutex_destroy(&g->lock);
    free(g);
}

void connection_guard_notify(void *cls, struct MHD_Connection *c, void **socket_context,
                             enum MHD_ConnectionNotificationCode code)
{
    struct connection_guard *g = cls;
    if (code == MHD_CONNECTION_NOTIFY_STARTED) {
        const union MHD_ConnectionInfo *info = MHD_get_connection_info(c, MHD_CONNECTION_INFO_CONNECTION_FD);
        struct guarded *e = info ? calloc(1, sizeof *e) : NULL;
        *socket_context = e;
        if (!e)
            return; /* unguarded: only libmicrohttpd's idle timeout applies to it */
        e->fd = info->connect_fd;
        e->since = monotonic_seconds();
        e->guard = g;
        pthread_mutex_lock(&g->lock);
        e->next = g->head;
        if (g->head)
            g->head->prev = e;
        g->head = e;
        pthread_mutex_unlock(&g->lock);
        return;
    }
    struct guarded *e = *socket_context;
    if (code != MHD_CONNECTION_NOTIFY_CLOSED || !e)
        return;
    pthread_mutex_lock(&g->lock);
    if (e->prev)
        e->prev->next = e->next;
    else
        g->head = e->next;
    if (e->next)
        e->next->prev = e->prev;
    pthread_mutex_unlock(&g->lock);
    free(e);
    *socket_context = NULL;
}

static void set_clock(struct MHD_Connection *c, double now, int working)
{
    const union MHD_ConnectionInfo *info = MHD_get_connection_info(c, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
    struct guarded *e = info ? info->socket_context : NULL;
    if (!e)
        return;
    pthread_mutex_lock(&e->guard->lock);
    e->working = working;
    e->since = now;
    pthread_mutex_unlock(&e->guard->lock);
}

void connection_guard_received(struct MHD_Connection *c, double now)
{
    set_clock(c, now, 1);
}

void connection_guard_answered(struct MHD_Connection *c, double now)
{
    set_clock(c, now, 0);
}

int connection_guard_sweep(struct connection_guard *g, double now)
{
    int n = 0;
    pthread_mutex_lock(&g->lock);
    for (struct guarded *e = g->head; e; e = e->next)
        if (!e->working && !e->shut && now - e->since > g->deadline_s) {
            shutdown(e->fd, SHUT_RDWR);
            e->shut = 1;
            n++;
        }
    g->closed += (uint64_t)n;
    pthread_mutex_unlock(&g->lock);
    return n;
}

uint64_t connection_guard_closed(struct connection_guard *g)
{
    pthread_mutex_lock(&g->lock);
    uint64_t n = g->closed;
    pthread_mutex_unlock(&g->lock);
    return n;
}
