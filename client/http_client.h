/* http_client.h - every request the client makes, through one libcurl handle (an upload and the render
 * after it share a connection): token, bodies, answers to memory or a file, kept headers, -v lines. */
#ifndef LUCENT_HTTP_CLIENT_H
#define LUCENT_HTTP_CLIENT_H

#include <curl/curl.h>
#include <stddef.h>
#include <stdio.h>

#include "cli_error.h"

struct http_client {
    CURL *curl;
    char *base;  /* the server URL without a trailing slash */
    char *auth;  /* "Authorization: Bearer TOKEN", or NULL */
    int verbose;
};

struct http_request {
    const char *method; /* GET, POST or DELETE */
    const char *path;   /* from the server's root: "/v1/render" */
    const void *body;   /* POST only; not copied */
    size_t body_len;
    curl_mime *form;    /* POST only: a multipart/form-data body instead of body (curl sets its type) */
    const char *content_type;
    const char *accept;
    FILE *sink; /* when set, a 2xx answer's body is written here instead of to memory */
};

struct http_response {
    long status;
    char *body; /* NUL-terminated; everything not sent to the sink */
    size_t body_len;
    char *content_type, *request_id, *server_timing, *modelled, *retry_after;
    /* internal to the transfer */
    CURL *curl;
    FILE *sink;
    int sink_errno;
    int too_large;
};

/* token may be NULL. Returns LC_OK, or LC_E_USAGE for a URL that is not http(s). */
int http_client_init(struct http_client *c, const char *base_url, const char *token, int verbose, lc_error *err);
void http_client_cleanup(struct http_client *c);

/* LC_OK whenever the server answered, whatever the status (the caller judges it); LC_E_CONNECT when it
 * could not be reached or the transfer broke, LC_E_FILE when the sink could not be written.
 * *rs is always initialised and must be released with http_response_free. */
int http_perform(struct http_client *c, const struct http_request *rq, struct http_response *rs, lc_error *err);
void http_response_free(struct http_response *rs);

#endif
