/* http_server.c - libmicrohttpd set-up and the request life cycle: state per connection, checks before the
 * body (route, Host, method, Origin, token, length), the capped body, dispatch, logging and metrics. */
#include "http_server.h"

#include "access_log.h"
#include "connection_guard.h"
#include "metrics.h"
#include "problem.h"
#include "rate_limit.h"
#include "render_queue.h"
#include "request_origin.h"
#include "routes.h"
#include "url_unescape.h"
#include "server.h"
#include "upload_queue.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define CONNECTION_MEMORY (128 * 1024) /* headers in and out: Lucent-Modelled can be 2 KiB */
#define INITIAL_BODY (256 * 1024)

const char *http_header(struct request *req, const char *name)
{
    return MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND, name);
}

/* The origin to echo in Access-Control-Allow-Origin, or NULL when CORS does not apply. */
static const char *cors_origin(struct request *req)
{
    const char *list = req->srv->cfg.cors_origins;
    const char *origin = http_header(req, MHD_HTTP_HEADER_ORIGIN);
    if (!list[0] || !origin)
        return NULL;
    if (strcmp(list, "*") == 0)
        return "*";
    return list_has(list, origin, strlen(origin)) ? origin : NULL;
}

enum MHD_Result http_send(struct request *req, unsigned status, struct MHD_Response *resp)
{
    if (!resp)
        return MHD_NO; /* out of memory: MHD closes the connection */
    MHD_add_response_header(resp, "X-Request-Id", req->id);
    const char *origin = cors_origin(req);
    if (origin) {
        MHD_add_response_header(resp, MHD_HTTP_HEADER_ACCESS_CONTROL_ALLOW_ORIGIN, origin);
        MHD_add_response_header(resp, "Access-Control-Expose-Headers",
                                "ETag, Server-Timing, Lucent-Modelled, X-Request-Id, Retry-After");
        MHD_add_response_header(resp, "Timing-Allow-Origin", origin);
        if (strcmp(origin, "*") != 0)
            MHD_add_response_header(resp, MHD_HTTP_HEADER_VARY, "Origin");
    }
    req->status = status;
    enum MHD_Result r = MHD_queue_response(req->connection, status, resp);
    MHD_destroy_response(resp);
    return r;
}

enum MHD_Result http_send_bytes(struct request *req, unsigned status, const char *content_type, const void *bytes,
                                size_t len)
{
    struct MHD_Response *resp = MHD_create_response_from_buffer(len, (void *)bytes, MHD_RESPMEM_MUST_COPY);
    if (!resp)
        return MHD_NO;
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, content_type);
    req->bytes_out = len;
    return http_send(req, status, resp);
}

enum MHD_Result http_send_error(struct request *req, const lucent_error *err)
{
    const struct problem_kind *kind = problem_lookup(err->status, err->field);
    size_t len = 0;
    char *body = problem_json(kind, err, req->id, &len);
    if (!body)
        return MHD_NO;
    struct MHD_Response *resp = MHD_create_response_from_buffer(len, body, MHD_RESPMEM_MUST_FREE);
    if (!resp) {
        free(body);
        return MHD_NO;
    }
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, "application/problem+json");
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    /* A 503 names the configured wait; a 429, the time until this client's bucket holds a token. */
    int retry = kind->http_status == MHD_HTTP_SERVICE_UNAVAILABLE ? req->srv->cfg.retry_after_s
                : kind->http_status == MHD_HTTP_TOO_MANY_REQUESTS ? req->retry_after_s
                                                                   : -1;
    if (retry >= 0) {
        char secs[16];
        snprintf(secs, sizeof secs, "%d", retry);
        MHD_add_response_header(resp, MHD_HTTP_HEADER_RETRY_AFTER, secs);
    }
    if (kind->http_status == MHD_HTTP_METHOD_NOT_ALLOWED && req->route) {
        char allow[64];
        route_allow(req->route->methods, allow, sizeof allow);
        MHD_add_response_header(resp, MHD_HTTP_HEADER_ALLOW, allow);
    }
    if (kind->http_status == MHD_HTTP_UNAUTHORIZED)   /* RFC 6750 3.1: error only when a token was sent */
        MHD_add_response_header(resp, MHD_HTTP_HEADER_WWW_AUTHENTICATE,
                                err->status == (lucent_status)PROBLEM_TOKEN_WRONG
                                    ? "Bearer realm=\"lucentd\", error=\"invalid_token\""
                                    : "Bearer realm=\"lucentd\"");
    req->bytes_out = len;
    return http_send(req, kind->http_status, resp);
}

enum MHD_Result http_send_problem(struct request *req, int code, const char *field, const char *fmt, ...)
{
    lucent_error err;
    memset(&err, 0, sizeof err);
    err.status = (lucent_status)code;
    snprintf(err.field, sizeof err.field, "%s", field ? field : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err.message, sizeof err.message, fmt, ap);
    va_end(ap);
    return http_send_error(req, &err);
}

static unsigned method_bit(const char *m)
{
    static const struct { const char *name; unsigned bit; } methods[] = {
        {"GET", M_GET}, {"HEAD", M_HEAD}, {"POST", M_POST}, {"DELETE", M_DELETE}, {"OPTIONS", M_OPTIONS}};
    for (size_t i = 0; i < sizeof methods / sizeof methods[0]; i++)
        if (strcmp(m, methods[i].name) == 0)
            return methods[i].bit;
    return 0;
}

/* 0 when the request carries the daemon's token, else PROBLEM_UNAUTHORIZED (none given) or
 * PROBLEM_TOKEN_WRONG. Compares in time independent of where the strings differ, so the token cannot
 * be guessed byte by byte. */
static int token_problem(struct request *req)
{
    const char *token = req->srv->token;
    const char *auth = http_header(req, MHD_HTTP_HEADER_AUTHORIZATION);
    if (!auth || strncasecmp(auth, "Bearer ", 7) != 0)
        return PROBLEM_UNAUTHORIZED;
    const char *given = auth + 7;
    size_t n = strlen(token), m = strlen(given);
    unsigned char diff = (unsigned char)(n != m);
    for (size_t i = 0; i < n; i++)
        diff |= (unsigned char)(token[i] ^ (i < m ? given[i] : 0));
    return diff == 0 ? 0 : PROBLEM_TOKEN_WRONG;
}

/* Seconds (rounded up, at least 1) until this client may send again under --rate-limit; 0: now. Routes
 * open without a token (probes, the web page's files) are not limited. */
static int rate_limited(struct request *req)
{
    if (!req->srv->rate_limit || req->route->open)
        return 0;
    const union MHD_ConnectionInfo *info = MHD_get_connection_info(req->connection, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
    double wait = rate_limit_take(req->srv->rate_limit, info ? info->client_addr : NULL, monotonic_seconds());
    return wait > 0.0 ? (int)ceil(wait) : 0;
}

static enum MHD_Result preflight(struct request *req)
{
    char allow[64];
    route_allow(req->route->methods, allow, sizeof allow);
    struct MHD_Response *resp = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
    if (!resp)
        return MHD_NO;
    MHD_add_response_header(resp, MHD_HTTP_HEADER_ALLOW, allow);
    if (cors_origin(req)) {
        MHD_add_response_header(resp, "Access-Control-Allow-Methods", allow);
        MHD_add_response_header(resp, "Access-Control-Allow-Headers",
                                "Content-Type, Authorization, Accept, If-None-Match, X-Request-Id");
        MHD_add_response_header(resp, "Access-Control-Max-Age", "600");
    }
    return http_send(req, MHD_HTTP_NO_CONTENT, resp);
}

/* The client's X-Request-Id when it is short and plain, else a new one. */
static void assign_id(struct request *req)
{
    const char *given = http_header(req, "X-Request-Id");
    if (given && strlen(given) <= 64 && strlen(given) > 0 &&
        strspn(given, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_.") == strlen(given)) {
        snprintf(req->id, sizeof req->id, "%s", given);
        return;
    }
    /* The start time makes ids unique across restarts; the counter within one run. */
    uint64_t n = atomic_fetch_add(&req->srv->next_request, 1);
    snprintf(req->id, sizeof req->id, "%08llx-%06llx", (unsigned long long)req->srv->started_at & 0xffffffffu,
             (unsigned long long)n);
}

/* Raises this request's charge against --max-body-total to `bytes`; -1 (nothing charged) past it. */
static int charge_body(struct request *req, uint64_t bytes)
{
    struct server *srv = req->srv;
    if (bytes <= req->body_charged)
        return 0;
    uint64_t more = bytes - req->body_charged;
    if (srv->body_bytes + more > srv->cfg.max_body_total)
        return -1;
    srv->body_bytes += more;
    req->body_charged = bytes;
    return 0;
}

static enum MHD_Result bodies_full(struct request *req)
{
    return http_send_problem(req, PROBLEM_BODIES_FULL, NULL,
                             "request bodies in flight hold %llu of the %llu bytes this server allows; retry shortly",
                             (unsigned long long)req->srv->body_bytes, (unsigned long long)req->srv->cfg.max_body_total);
}

/* Checks made before any body byte is read; a response queued here means MHD discards the body. */
static enum MHD_Result first_call(struct request *req, int *answered)
{
    *answered = 1;
    if (!req->route)
        return http_send_problem(req, PROBLEM_NO_ROUTE, NULL, "no resource at %s (see /openapi.json)", req->path);
    /* Probes and the page's static files are open to any Host (kubelets probe by IP); the API is not. */
    const char *host = http_header(req, MHD_HTTP_HEADER_HOST);
    if (!req->route->open && !host_allowed(host, req->srv->cfg.allowed_hosts, req->srv->cfg.listen))
        return http_send_problem(req, PROBLEM_HOST, "Host", "this daemon does not answer for the host \"%.64s\" "
                                 "(--allowed-hosts)", host);
    if (req->method_bit == M_OPTIONS)
        return preflight(req);
    if (!(req->route->methods & req->method_bit))
        return http_send_problem(req, PROBLEM_METHOD, NULL, "%s does not accept %s", req->route->path, req->method);
    if ((req->retry_after_s = rate_limited(req)) > 0)
        return http_send_problem(req, PROBLEM_RATE_LIMITED, NULL, "this client is over %g requests a second "
                                 "(bursts of %g); retry in %d s", req->srv->cfg.rate_limit, req->srv->cfg.rate_burst,
                                 req->retry_after_s);
    const char *origin = http_header(req, MHD_HTTP_HEADER_ORIGIN);
    if ((req->method_bit == M_POST || req->method_bit == M_DELETE) &&
        !origin_allowed(origin, host, req->srv->cfg.cors_origins))
        return http_send_problem(req, PROBLEM_ORIGIN, "Origin", "requests from the page at \"%.64s\" may not "
                                 "upload, delete or render here (--cors-origins)", origin);
    int token = !req->route->open && req->srv->token[0] ? token_problem(req) : 0;
    if (token)
        return http_send_problem(req, token, "Authorization", token == PROBLEM_UNAUTHORIZED
                                 ? "send the daemon's token as \"Authorization: Bearer TOKEN\""
                                 : "the bearer token given is not this daemon's");
    const char *cl = http_header(req, MHD_HTTP_HEADER_CONTENT_LENGTH);
    uint64_t max = req->srv->cfg.max_body_bytes;
    if (cl) {
        char *end = NULL;
        errno = 0;
        unsigned long long n = strtoull(cl, &end, 10);
        if (errno || *end || n > max)
            return http_send_problem(req, PROBLEM_BODY_TOO_LARGE, "Content-Length",
                                     "the body may have at most %llu bytes (Content-Length: %.24s)",
                                     (unsigned long long)max, cl);
        /* The declared length is charged in full (it will be needed), but memory follows the bytes that
         * actually arrive. */
        if (req->method_bit == M_POST && charge_body(req, n) != 0)
            return bodies_full(req);
        size_t first = n < INITIAL_BODY ? (size_t)n : INITIAL_BODY;
        if (first > 0 && req->method_bit == M_POST && (req->body = malloc(first)) == NULL)
            return http_send_problem(req, LUCENT_E_NOMEM, NULL, "no memory for a %llu-byte body", n);
        req->body_cap = req->body ? first : 0;
    }
    *answered = 0;
    return MHD_YES;
}

/* Appends a chunk. Only POST routes read a body; any other method's body is dropped. Returns 0, or the
 * problem that ends the request at once: over --max-body-bytes (a body without Content-Length grows up
 * to it), over --max-body-total, or out of memory. */
static int take_body(struct request *req, const char *data, size_t size)
{
    uint64_t max = req->srv->cfg.max_body_bytes;
    if (req->method_bit != M_POST)
        return 0;
    if (req->body_len + size > max)
        return PROBLEM_BODY_TOO_LARGE;
    if (req->body_len + size > req->body_cap) {
        size_t cap = req->body_cap ? req->body_cap * 2 : 64 * 1024;
        while (cap < req->body_len + size)
            cap *= 2;
        if (cap > max)
            cap = (size_t)max;
        if (charge_body(req, cap) != 0)
            return PROBLEM_BODIES_FULL;
        unsigned char *grown = realloc(req->body, cap);
        if (!grown)
            return LUCENT_E_NOMEM;
        req->body = grown;
        req->body_cap = cap;
    }
    memcpy(req->body + req->body_len, data, size);
    req->body_len += size;
    return 0;
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *connection, const char *url, const char *method,
                                  const char *version, const char *upload_data, size_t *upload_data_size,
                                  void **con_cls)
{
    (void)version;
    struct server *srv = cls;
    struct request *req = *con_cls;
    if (!req) {
        req = calloc(1, sizeof *req);
        if (!req)
            return MHD_NO;
        *con_cls = req;
        req->srv = srv;
        req->connection = connection;
        req->start = monotonic_seconds();
        req->cache = "-";
        snprintf(req->method, sizeof req->method, "%s", method);
        snprintf(req->path, sizeof req->path, "%s", url);
        req->method_bit = method_bit(method);
        req->route = route_match(url, &req->route_index);
        assign_id(req);
        int answered = 0;
        enum MHD_Result r = first_call(req, &answered);
        if (answered) /* the rest of it is not read */
            connection_guard_received(connection, req->start);
        return answered ? r : MHD_YES;
    }
    if (req->status) {
        *upload_data_size = 0; /* answered on the first call; the body is discarded */
        return MHD_YES;
    }
    if (*upload_data_size) {
        size_t size_given = *upload_data_size;
        int refused = take_body(req, upload_data, *upload_data_size);
        *upload_data_size = 0;
        if (!refused)
            return MHD_YES;
        /* libmicrohttpd 0.9 cannot answer in the middle of a body, and reading the rest only to answer
         * would let the client send for as long as it likes: the connection is closed at once. (A body
         * with a Content-Length is refused before it is read, with a 413 or a 503.) */
        log_line(LOG_WARN, "request %s: connection closed after %zu bytes of its body: %s", req->id,
                 req->body_len + size_given,
                 refused == PROBLEM_BODY_TOO_LARGE ? "over --max-body-bytes"
                 : refused == PROBLEM_BODIES_FULL  ? "the bodies in flight would exceed --max-body-total"
                                                   : "out of memory");
        return MHD_NO;
    }
    connection_guard_received(connection, monotonic_seconds());
    return req->route->handler(req);
}

static void on_completed(void *cls, struct MHD_Connection *connection, void **con_cls,
                         enum MHD_RequestTerminationCode toe)
{
    struct server *srv = cls;
    struct request *req = *con_cls;
    if (!req)
        return;
    *con_cls = NULL;
    static const char *const notes[] = {
        [MHD_REQUEST_TERMINATED_COMPLETED_OK] = NULL,
        [MHD_REQUEST_TERMINATED_WITH_ERROR] = "error",
        [MHD_REQUEST_TERMINATED_TIMEOUT_REACHED] = "timeout",
        [MHD_REQUEST_TERMINATED_DAEMON_SHUTDOWN] = "shutdown",
        [MHD_REQUEST_TERMINATED_READ_ERROR] = "read-error",
        [MHD_REQUEST_TERMINATED_CLIENT_ABORT] = "client-abort",
    };
    struct access_entry e = {
        .request_id = req->id, .method = req->method, .path = req->path, .status = req->status,
        .bytes = req->bytes_out, .queue_ms = req->queue_ms, .render_ms = req->render_ms,
        .encode_ms = req->encode_ms, .total_ms = (monotonic_seconds() - req->start) * 1e3, .cache = req->cache,
        .note = (unsigned)toe < sizeof notes / sizeof notes[0] ? notes[toe] : "unknown"};
    log_request(&e);
    if (req->status)
        metrics_request(srv->metrics, req->route_index, req->status);
    render_job_release(srv->queue, req->job);
    upload_job_release(srv->uploads, req->upload);
    srv->body_bytes -= req->body_charged;
    connection_guard_answered(connection, monotonic_seconds());
    free(req->body);
    free(req);
}

static void mhd_log(void *cls, const char *fmt, va_list ap)
{
    (void)cls;
    char msg[512];
    vsnprintf(msg, sizeof msg, fmt, ap);
    msg[strcspn(msg, "\n")] = 0;
    log_line(LOG_WARN, "libmicrohttpd: %s", msg);
}

/* libmicrohttpd's unescape callback: url_unescape (%00 kept as sent). */
static size_t unescape_keeping_nul(void *cls, struct MHD_Connection *c, char *s)
{
    (void)cls;
    (void)c;
    return url_unescape(s);
}

struct MHD_Daemon *http_start(struct server *srv, uint16_t *port, lucent_error *err)
{
    const struct config *cfg = &srv->cfg;
    struct sockaddr_in v4;
    struct sockaddr_in6 v6;
    struct sockaddr *addr;
    unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_EPOLL | MHD_ALLOW_SUSPEND_RESUME | MHD_USE_ERROR_LOG;
    memset(&v4, 0, sizeof v4);
    memset(&v6, 0, sizeof v6);
    if (inet_pton(AF_INET, cfg->listen, &v4.sin_addr) == 1) {
        v4.sin_family = AF_INET;
        v4.sin_port = htons((uint16_t)cfg->port);
        addr = (struct sockaddr *)&v4;
    } else if (inet_pton(AF_INET6, cfg->listen, &v6.sin6_addr) == 1) {
        v6.sin6_family = AF_INET6;
        v6.sin6_port = htons((uint16_t)cfg->port);
        addr = (struct sockaddr *)&v6;
        flags |= MHD_USE_IPv6;
    } else {
        lucent_fail(err, LUCENT_E_INVALID, "listen", "\"%s\" is not an IPv4 or IPv6 address", cfg->listen);
        return NULL;
    }
    struct MHD_Daemon *d = MHD_start_daemon(
        flags, (uint16_t)cfg->port, NULL, NULL, on_request, srv, MHD_OPTION_EXTERNAL_LOGGER, mhd_log, NULL,
        MHD_OPTION_SOCK_ADDR, addr,
        MHD_OPTION_CONNECTION_LIMIT, (unsigned)cfg->max_connections, MHD_OPTION_CONNECTION_TIMEOUT,
        (unsigned)cfg->connection_timeout_s, MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)CONNECTION_MEMORY,
        MHD_OPTION_NOTIFY_COMPLETED, on_completed, srv, MHD_OPTION_UNESCAPE_CALLBACK, unescape_keeping_nul, NULL,
        MHD_OPTION_NOTIFY_CONNECTION, connection_guard_notify, srv->guard,
        MHD_OPTION_PER_IP_CONNECTION_LIMIT, (unsigned)cfg->max_connections_per_client, MHD_OPTION_END);
    if (!d) {
        lucent_fail(err, LUCENT_E_IO, "listen", "cannot listen on %s port %d (in use, or not an address of this host)",
                    cfg->listen, cfg->port);
        return NULL;
    }
    const union MHD_DaemonInfo *info = MHD_get_daemon_info(d, MHD_DAEMON_INFO_BIND_PORT);
    *port = info ? info->port : (uint16_t)cfg->port;
    return d;
}

unsigned http_connections(struct MHD_Daemon *d)
{
    const union MHD_DaemonInfo *info = MHD_get_daemon_info(d, MHD_DAEMON_INFO_CURRENT_CONNECTIONS);
    return info ? info->num_connections : 0;
}
