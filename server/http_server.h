/* http_server.h - the libmicrohttpd daemon and the per-request state handlers work with. Every handler call
 * and response happens on MHD's one polling thread; other threads only resume connections. */
#ifndef LUCENTD_HTTP_SERVER_H
#define LUCENTD_HTTP_SERVER_H

#include "lucent.h"

#include <microhttpd.h>
#include <stddef.h>
#include <stdint.h>

struct server;
struct route;
struct render_job;
struct upload_job;

struct request {
    struct server *srv;
    struct MHD_Connection *connection;
    char id[65];
    char method[16];
    char path[512];
    unsigned method_bit;
    const struct route *route;
    int route_index;
    double start;
    unsigned char *body;          /* the request body, up to cfg.max_body_bytes */
    size_t body_len, body_cap;
    uint64_t body_charged;        /* of the server's --max-body-total: the declared length, or the capacity */
    struct render_job *job;       /* a reference while a render is queued, running or answered */
    struct upload_job *upload;    /* the same for a mesh import */
    unsigned status;              /* sent so far; 0 until a response is queued */
    size_t bytes_out;
    double queue_ms, render_ms, encode_ms;
    const char *cache;            /* "hit" or "miss" for renders, else "-" */
    int retry_after_s;            /* for a 429: seconds until this client's next request may pass */
};

/* Starts listening on cfg.listen:cfg.port; *port receives the bound port. NULL on failure (err). */
struct MHD_Daemon *http_start(struct server *srv, uint16_t *port, lucent_error *err);
/* Connections open now (suspended ones included). */
unsigned http_connections(struct MHD_Daemon *d);

/* Value of a request header, or NULL. */
const char *http_header(struct request *req, const char *name);
/* Adds the headers every response carries (request id, CORS), records the status, queues resp and
 * releases the caller's reference to it. */
enum MHD_Result http_send(struct request *req, unsigned status, struct MHD_Response *resp);
/* A body response; the bytes are copied. */
enum MHD_Result http_send_bytes(struct request *req, unsigned status, const char *content_type, const void *bytes,
                                size_t len);
/* A problem+json response for a code of problem.h's table (with Allow, Retry-After or
 * WWW-Authenticate when the status calls for one). */
enum MHD_Result http_send_problem(struct request *req, int code, const char *field, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
enum MHD_Result http_send_error(struct request *req, const lucent_error *err);

#endif
