/* lucentd.c - the daemon's life cycle: settings, start-up (HTTP first, so /readyz can say "starting"), the
 * deadline loop, and the SIGTERM order: not ready, stop accepting, drain, resume all, stop, exit 0. */
#include "access_log.h"
#include "config.h"
#include "http_server.h"
#include "image_cache.h"
#include "import_jail.h"
#include "connection_guard.h"
#include "resume_gate.h"
#include "mesh_store.h"
#include "metrics.h"
#include "rate_limit.h"
#include "render_queue.h"
#include "routes.h"
#include "server.h"
#include "service_notify.h"
#include "upload_queue.h"

#include "lucentd_build.h"

#include <errno.h>
#include <malloc.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define TICK_NS (20 * 1000 * 1000) /* deadline sweep and signal check period */
#define FLUSH_SECONDS 2.0          /* after draining, time given to resumed connections to send their answers */
#define STUCK_SECONDS 5.0          /* a frame this long past its cancelled deadline: the worker is stuck */
#define STATUS_SECONDS 1.0         /* the service manager's status line is refreshed at most this often */

static volatile sig_atomic_t stop_signal;

static void on_signal(int sig)
{
    stop_signal = sig;
}

static int install_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    struct sigaction ignore = sa;
    ignore.sa_handler = SIG_IGN;
    return sigaction(SIGTERM, &sa, NULL) || sigaction(SIGINT, &sa, NULL) || sigaction(SIGPIPE, &ignore, NULL) ? -1 : 0;
}

static void tick(void)
{
    struct timespec ts = {0, TICK_NS};
    nanosleep(&ts, NULL);
}

/* The service manager's status line and watchdog, once a tick. The watchdog goes unfed while the render
 * worker is stuck in the driver, so a manager with WatchdogSec restarts a daemon that cannot render. */
static void notify_tick(struct server *srv, struct service_notify *n, double now, double *last_status)
{
    if (n->fd < 0) /* no service manager: nothing to tell, nothing to ask the queue */
        return;
    int in_flight = 0, depth = render_queue_depth(srv->queue, &in_flight);
    double overdue = render_queue_overdue_seconds(srv->queue, now);
    int stuck = overdue > STUCK_SECONDS;
    service_notify_watchdog(n, now, !stuck);
    if (now - *last_status < STATUS_SECONDS)
        return;
    *last_status = now;
    if (stuck)
        service_notify_send(n, "STATUS=render worker stuck %.0f s past a render's deadline; watchdog not fed",
                            overdue);
    else
        service_notify_send(n, "STATUS=serving on %s: %d renders queued or running (%d running)", srv->device,
                            depth, in_flight);
}

/* The token is the file's first line; surrounding whitespace is dropped (editors add a newline). */
static int read_token(const char *path, char *out, size_t cap)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        log_line(LOG_ERROR, "cannot read token file %s: %s", path, strerror(errno));
        return -1;
    }
    char line[512] = "";
    int ok = fgets(line, sizeof line, f) != NULL;
    fclose(f);
    char *s = line;
    while (*s == ' ' || *s == '\t')
        s++;
    size_t n = strcspn(s, "\r\n \t");
    if (!ok || n == 0 || n >= cap) {
        log_line(LOG_ERROR, "token file %s must hold one token of 1..%zu characters on its first line", path, cap - 1);
        return -1;
    }
    memcpy(out, s, n);
    out[n] = 0;
    return 0;
}

/* Queued and running renders and imports get until the drain deadline; the rest are answered 503. */
static void drain(struct server *srv, struct MHD_Daemon *d)
{
    double deadline = monotonic_seconds() + srv->cfg.drain_timeout_s;
    render_queue_close(srv->queue);
    upload_queue_wait_idle(srv->uploads, deadline);
    int open;
    while ((open = render_queue_open_jobs(srv->queue)) > 0 && monotonic_seconds() < deadline) {
        render_queue_expire(srv->queue, monotonic_seconds());
        tick();
    }
    if (open > 0)
        log_line(LOG_WARN, "drain deadline reached; answering %d unfinished renders with 503", open);
    render_queue_cancel_all(srv->queue);
    upload_queue_cancel_all(srv->uploads);
    double flush = monotonic_seconds() + FLUSH_SECONDS;
    resume_gate_wait(srv->resumes, flush); /* answers ready, not yet handed back to libmicrohttpd */
    while (http_connections(d) > 0 && monotonic_seconds() < flush)
        tick();
}

/* After the drain, how long the render worker may take to return from its last frame. */
#define WORKER_STOP_SECONDS 5

/* Stops libmicrohttpd once no other thread is still resuming one of its connections (a worker that
 * finished a job just before the drain ended would otherwise call into a stopped daemon). -1: one
 * is stuck, and stopping could only crash; the caller exits without it. */
static int stop_http(struct server *srv, struct MHD_Daemon *d)
{
    int left = resume_gate_wait(srv->resumes, monotonic_seconds() + WORKER_STOP_SECONDS);
    if (left > 0) {
        log_line(LOG_ERROR, "%d connection(s) still being resumed after %d s; exiting without stopping HTTP", left,
                 WORKER_STOP_SECONDS);
        return -1;
    }
    MHD_stop_daemon(d);
    return 0;
}

/* Blocks from 256 KiB up (images, render targets, meshes, bodies) are mapped and unmapped, so their
 * pages go back to the system when freed. glibc otherwise raises this threshold to the largest block
 * freed, and later such blocks land on heaps that keep their pages: 80 MB more after the memory soak. */
#define MMAP_THRESHOLD_BYTES (256 * 1024)

int main(int argc, char **argv)
{
    static struct server srv; /* large; lives for the whole process */
    int rc = config_load(&srv.cfg, argc, argv);
    if (rc != 0)
        return rc > 0 ? 0 : 2;
    log_set_level(srv.cfg.log_level);
    struct service_notify notify;
    char notify_err[160];
    if (service_notify_open(&notify, notify_err, sizeof notify_err) != 0)
        log_line(LOG_WARN, "%s: the service manager is not told when lucentd is ready", notify_err);
    if (mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES) != 1)
        log_line(LOG_WARN, "cannot fix the allocator's mmap threshold: memory freed may stay resident");
    srv.started_at = (long long)time(NULL);
    config_log(&srv.cfg);
    if (srv.cfg.token_file[0] && read_token(srv.cfg.token_file, srv.token, sizeof srv.token) != 0)
        return 2;
    if (install_signals() != 0) {
        log_line(LOG_ERROR, "cannot install signal handlers: %s", strerror(errno));
        return 1;
    }
    rc = 1;
    lucent_error err = {0};
    struct MHD_Daemon *d = NULL;
    srv.metrics = metrics_create(route_labels, route_label_count);
    srv.cache = image_cache_create(srv.cfg.cache_bytes);
    srv.rate_limit = srv.cfg.rate_limit > 0 ? rate_limit_new(srv.cfg.rate_limit, srv.cfg.rate_burst) : NULL;
    srv.resumes = resume_gate_create();
    srv.guard = connection_guard_create(srv.cfg.request_timeout_s);
    if (!srv.metrics || !srv.cache || (srv.cfg.rate_limit > 0 && !srv.rate_limit) || !srv.resumes || !srv.guard) {
        log_line(LOG_ERROR, "out of memory at start-up");
        goto done;
    }
    struct import_limits lim = {.address_space_bytes = (size_t)srv.cfg.import_memory_bytes,
                                .cpu_seconds = srv.cfg.import_cpu_s,
                                .wall_seconds = srv.cfg.import_wall_s,
                                .max_triangles = srv.cfg.max_triangles};
    if (import_jail_open(srv.cfg.import_tool, srv.cfg.import_user, &srv.jail, &err) != LUCENT_OK ||
        mesh_import_self_test(srv.jail, &lim, &err) != LUCENT_OK)
        goto fail;
    log_line(LOG_INFO, "mesh importer sandbox: %s", import_jail_describe(srv.jail));
    if (mesh_store_open(srv.cfg.store_dir, srv.cfg.store_bytes, srv.cfg.store_key, srv.jail, &lim, &srv.store, &err) != LUCENT_OK)
        goto fail;
    log_line(LOG_INFO, "mesh store %s: %llu bytes of %llu", srv.cfg.store_dir,
             (unsigned long long)mesh_store_bytes(srv.store), (unsigned long long)srv.cfg.store_bytes);
    srv.uploads = upload_queue_create(srv.store, srv.cfg.max_imports, srv.resumes);
    if (!srv.uploads) {
        log_line(LOG_ERROR, "out of memory at start-up");
        goto done;
    }
    double t0 = monotonic_seconds();
    srv.queue = render_queue_create(srv.cfg.queue_length, srv.cfg.backend, srv.cfg.device, srv.cfg.mesh_cache_bytes,
                                    srv.metrics, srv.cache, srv.resumes, &err);
    if (!srv.queue)
        goto fail;
    uint16_t port = 0;
    d = http_start(&srv, &port, &err);
    if (!d)
        goto fail;
    log_line(LOG_INFO, "listening on http://%s%s%s:%u (version %s, renderer %.12s)", strchr(srv.cfg.listen, ':') ? "[" : "",
             srv.cfg.listen, strchr(srv.cfg.listen, ':') ? "]" : "", port, LUCENTD_VERSION, LUCENTD_RENDERER_HASH);
    service_notify_send(&notify, "STATUS=warming the renderer (listening on port %u)", port);
    if (render_queue_wait_ready(srv.queue, srv.backend, srv.device, sizeof srv.device, &srv.max_pixels, &err) != 0)
        goto fail;
    atomic_store(&srv.phase, PHASE_SERVING);
    log_line(LOG_INFO, "ready: %s device \"%s\", renderer warm in %.0f ms; limits: body %llu B, image %dx%d (device: %llu "
                       "pixels), %u triangles, %d samples, %d lights, projection %d, render %g s, queue %d, %d connections",
             srv.backend, srv.device, (monotonic_seconds() - t0) * 1e3, (unsigned long long)srv.cfg.max_body_bytes, srv.cfg.max_width,
             srv.cfg.max_height, (unsigned long long)srv.max_pixels, srv.cfg.max_triangles, srv.cfg.max_samples, srv.cfg.max_lights,
             srv.cfg.max_projection_size, srv.cfg.render_timeout_s, srv.cfg.queue_length, srv.cfg.max_connections);
    service_notify_send(&notify, "READY=1\nSTATUS=serving on %s: 0 renders queued or running\nMAINPID=%ld", srv.device,
                        (long)getpid());
    double last_status = monotonic_seconds();
    while (!stop_signal) {
        render_queue_expire(srv.queue, monotonic_seconds());
        notify_tick(&srv, &notify, monotonic_seconds(), &last_status);
        int slow = connection_guard_sweep(srv.guard, monotonic_seconds());
        if (slow > 0)
            log_line(LOG_INFO, "closed %d connection(s) that took over %g s to send a request (--request-timeout)",
                     slow, srv.cfg.request_timeout_s);
        tick();
    }
    log_line(LOG_INFO, "%s: draining (up to %g s)", stop_signal == SIGINT ? "SIGINT" : "SIGTERM",
             srv.cfg.drain_timeout_s);
    atomic_store(&srv.phase, PHASE_DRAINING);
    service_notify_send(&notify, "STOPPING=1\nSTATUS=draining: %d renders queued or running (up to %g s)",
                        render_queue_depth(srv.queue, NULL), srv.cfg.drain_timeout_s);
    MHD_socket listen_fd = MHD_quiesce_daemon(d);
    drain(&srv, d);
    if (stop_http(&srv, d) != 0)
        return 1;
    d = NULL;
    if (listen_fd != MHD_INVALID_SOCKET)
        close(listen_fd); /* quiesce hands the socket to us; closed only after the daemon stopped */
    log_line(LOG_INFO, "stopped");
    rc = 0;
    goto done;
fail:
    log_line(LOG_ERROR, "%s%s%s", err.field[0] ? err.field : "", err.field[0] ? ": " : "", err.message);
    service_notify_send(&notify, "STATUS=failed to start: %s%s%s", err.field[0] ? err.field : "",
                        err.field[0] ? ": " : "", err.message);
done:
    service_notify_close(&notify);
    if (d) {
        render_queue_cancel_all(srv.queue);
        upload_queue_cancel_all(srv.uploads);
        if (stop_http(&srv, d) != 0)
            return 1;
    }
    upload_queue_destroy(srv.uploads); /* imports always complete: the store is never left half-written */
    if (render_queue_destroy(srv.queue, WORKER_STOP_SECONDS) != 0) {
        /* Exiting ends the stuck thread; releasing its device first could only hang or crash. */
        log_line(LOG_ERROR, "the render worker did not stop within %d s (a hung device or driver); exiting "
                            "without it", WORKER_STOP_SECONDS);
        return 1;
    }
    mesh_store_close(srv.store);
    import_jail_close(srv.jail);
    lucent_shutdown();
    image_cache_destroy(srv.cache);
    rate_limit_free(srv.rate_limit);
    metrics_destroy(srv.metrics);
    resume_gate_destroy(srv.resumes);
    connection_guard_destroy(srv.guard);
    return rc;
}
