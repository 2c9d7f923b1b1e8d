/* http_client.c - the client's libcurl use: one easy handle reset before each request (connections
 * stay cached), answers captured to memory or a sink, transport failures mapped to exit codes. */
#include "http_client.h"

#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_MEMORY_BODY (16u << 20) /* JSON answers and problems are small; more means a wrong server */
#define CONNECT_TIMEOUT_S 10L

int http_client_init(struct http_client *c, const char *base_url, const char *token, int verbose, lc_error *err)
{
    memset(c, 0, sizeof *c);
    c->verbose = verbose;
    if (strncmp(base_url, "http://", 7) != 0 && strncmp(base_url, "https://", 8) != 0)
        return lc_fail(err, LC_E_USAGE, "--server: expected an http:// or https:// URL, got '%s'", base_url);
    size_t n = strlen(base_url);
    while (n > 0 && base_url[n - 1] == '/')
        n--;
    c->base = strndup(base_url, n);
    if (!c->base)
        goto nomem;
    if (token) {
        size_t len = strlen("Authorization: Bearer ") + strlen(token) + 1;
        c->auth = malloc(len);
        if (!c->auth)
            goto nomem;
        snprintf(c->auth, len, "Authorization: Bearer %s", token);
    }
    c->curl = curl_easy_init();
    if (!c->curl)
        goto nomem;
    return LC_OK;
nomem:
    http_client_cleanup(c);
    return lc_fail(err, LC_E_INTERNAL, "cannot set up libcurl (out of memory)");
}

void http_client_cleanup(struct http_client *c)
{
    if (c->curl)
        curl_easy_cleanup(c->curl);
    free(c->base);
    free(c->auth);
    memset(c, 0, sizeof *c);
}

void http_response_free(struct http_response *rs)
{
    free(rs->body);
    free(rs->content_type);
    free(rs->request_id);
    free(rs->server_timing);
    free(rs->modelled);
    free(rs->retry_after);
    memset(rs, 0, sizeof *rs);
}

static int append(struct http_response *rs, const char *data, size_t n)
{
    if (rs->body_len + n > MAX_MEMORY_BODY) {
        rs->too_large = 1;
        return -1;
    }
    char *grown = realloc(rs->body, rs->body_len + n + 1);
    if (!grown)
        return -1;
    memcpy(grown + rs->body_len, data, n);
    rs->body = grown;
    rs->body_len += n;
    rs->body[rs->body_len] = 0;
    return 0;
}

static size_t on_body(char *data, size_t size, size_t nmemb, void *user)
{
    struct http_response *rs = user;
    size_t n = size * nmemb;
    long status = 0;
    curl_easy_getinfo(rs->curl, CURLINFO_RESPONSE_CODE, &status);
    if (rs->sink && status / 100 == 2) {
        if (fwrite(data, 1, n, rs->sink) != n) {
            rs->sink_errno = errno ? errno : EIO;
            return 0;
        }
        return n;
    }
    return append(rs, data, n) == 0 ? n : 0;
}

/* Keeps the value of a header we report; a new status line (after 100 Continue) starts afresh. */
static size_t on_header(char *line, size_t size, size_t nmemb, void *user)
{
    struct http_response *rs = user;
    size_t n = size * nmemb;
    static const struct { const char *name; size_t offset; } kept[] = {
        {"content-type", offsetof(struct http_response, content_type)},
        {"x-request-id", offsetof(struct http_response, request_id)},
        {"server-timing", offsetof(struct http_response, server_timing)},
        {"lucent-modelled", offsetof(struct http_response, modelled)},
        {"retry-after", offsetof(struct http_response, retry_after)},
    };
    if (n >= 5 && strncmp(line, "HTTP/", 5) == 0) {
        for (size_t i = 0; i < sizeof kept / sizeof kept[0]; i++) {
            char **slot = (char **)((char *)rs + kept[i].offset);
            free(*slot);
            *slot = NULL;
        }
        return n;
    }
    const char *colon = memchr(line, ':', n);
    if (!colon)
        return n;
    size_t name_len = (size_t)(colon - line);
    for (size_t i = 0; i < sizeof kept / sizeof kept[0]; i++) {
        if (strlen(kept[i].name) != name_len || strncasecmp(line, kept[i].name, name_len) != 0)
            continue;
        const char *v = colon + 1, *end = line + n;
        while (v < end && (*v == ' ' || *v == '\t'))
            v++;
        while (end > v && isspace((unsigned char)end[-1]))
            end--;
        char **slot = (char **)((char *)rs + kept[i].offset);
        free(*slot);
        *slot = strndup(v, (size_t)(end - v));
        if (!*slot)
            return 0;
    }
    return n;
}

static void log_answer(const struct http_client *c, const struct http_request *rq, const struct http_response *rs)
{
    double total = 0;
    curl_easy_getinfo(c->curl, CURLINFO_TOTAL_TIME, &total);
    fprintf(stderr, "lucent: %s %s -> %ld in %.0f ms, request id %s\n", rq->method, rq->path, rs->status, total * 1e3,
            rs->request_id ? rs->request_id : "(none)");
    if (rs->server_timing)
        fprintf(stderr, "lucent: Server-Timing: %s\n", rs->server_timing);
    if (rs->modelled)
        fprintf(stderr, "lucent: Lucent-Modelled: %s\n", rs->modelled);
}

static int transport_error(const struct http_client *c, const struct http_response *rs, CURLcode code,
                           const char *detail, lc_error *err)
{
    if (rs->sink_errno)
        return lc_fail(err, LC_E_FILE, "cannot write the image: %s", strerror(rs->sink_errno));
    if (rs->too_large)
        return lc_fail(err, LC_E_SERVER, "the answer from %s is over %u MiB: is that a lucentd?", c->base,
                       MAX_MEMORY_BODY >> 20);
    switch (code) {
    case CURLE_OUT_OF_MEMORY:
        return lc_fail(err, LC_E_INTERNAL, "out of memory");
    case CURLE_URL_MALFORMAT:
    case CURLE_UNSUPPORTED_PROTOCOL:
        return lc_fail(err, LC_E_USAGE, "--server %s: %s", c->base, detail);
    case CURLE_COULDNT_RESOLVE_HOST:
    case CURLE_COULDNT_CONNECT:
    case CURLE_OPERATION_TIMEDOUT:
        if (rs->status == 0)
            return lc_fail(err, LC_E_CONNECT,
                           "cannot reach the server at %s: %s (is lucentd running? --server or LUCENT_SERVER "
                           "sets the address)", c->base, detail);
        break;
    default:
        break;
    }
    return lc_fail(err, LC_E_CONNECT, "the connection to %s failed: %s", c->base, detail);
}

int http_perform(struct http_client *c, const struct http_request *rq, struct http_response *rs, lc_error *err)
{
    memset(rs, 0, sizeof *rs);
    rs->curl = c->curl;
    rs->sink = rq->sink;
    char errbuf[CURL_ERROR_SIZE] = "";
    char line[256];
    struct curl_slist *headers = NULL, *grown;
    int rc = LC_OK;
    size_t url_len = strlen(c->base) + strlen(rq->path) + 1;
    char *url = malloc(url_len);
    if (!url)
        return lc_fail(err, LC_E_INTERNAL, "out of memory");
    snprintf(url, url_len, "%s%s", c->base, rq->path);

    const char *header_lines[3] = {c->auth, NULL, NULL};
    if (rq->content_type) {
        snprintf(line, sizeof line, "Content-Type: %s", rq->content_type);
        header_lines[1] = line;
    }
    char accept[128];
    if (rq->accept) {
        snprintf(accept, sizeof accept, "Accept: %s", rq->accept);
        header_lines[2] = accept;
    }
    for (int i = 0; i < 3; i++) {
        if (!header_lines[i])
            continue;
        grown = curl_slist_append(headers, header_lines[i]);
        if (!grown) {
            rc = lc_fail(err, LC_E_INTERNAL, "out of memory");
            goto done;
        }
        headers = grown;
    }

    CURL *h = c->curl;
    curl_easy_reset(h);
    curl_easy_setopt(h, CURLOPT_URL, url);
    curl_easy_setopt(h, CURLOPT_PROTOCOLS_STR, "http,https");
    curl_easy_setopt(h, CURLOPT_NOSIGNAL, 1L);
    curl_easy_setopt(h, CURLOPT_CONNECTTIMEOUT, CONNECT_TIMEOUT_S);
    curl_easy_setopt(h, CURLOPT_USERAGENT, "lucent/" LUCENT_VERSION);
    curl_easy_setopt(h, CURLOPT_ERRORBUFFER, errbuf);
    curl_easy_setopt(h, CURLOPT_HTTPHEADER, headers);
    curl_easy_setopt(h, CURLOPT_WRITEFUNCTION, on_body);
    curl_easy_setopt(h, CURLOPT_WRITEDATA, rs);
    curl_easy_setopt(h, CURLOPT_HEADERFUNCTION, on_header);
    curl_easy_setopt(h, CURLOPT_HEADERDATA, rs);
    if (strcmp(rq->method, "POST") == 0 && rq->form) {
        curl_easy_setopt(h, CURLOPT_MIMEPOST, rq->form);
    } else if (strcmp(rq->method, "POST") == 0) {
        curl_easy_setopt(h, CURLOPT_POSTFIELDS, rq->body ? rq->body : "");
        curl_easy_setopt(h, CURLOPT_POSTFIELDSIZE_LARGE, (curl_off_t)rq->body_len);
    } else if (strcmp(rq->method, "GET") != 0) {
        curl_easy_setopt(h, CURLOPT_CUSTOMREQUEST, rq->method);
    }

    CURLcode code = curl_easy_perform(h);
    curl_easy_getinfo(h, CURLINFO_RESPONSE_CODE, &rs->status);
    if (code != CURLE_OK) {
        rc = transport_error(c, rs, code, errbuf[0] ? errbuf : curl_easy_strerror(code), err);
        goto done;
    }
    if (c->verbose)
        log_answer(c, rq, rs);
done:
    curl_easy_setopt(c->curl, CURLOPT_ERRORBUFFER, NULL); /* errbuf is about to go out of scope */
    curl_slist_free_all(headers);
    free(url);
    return rc;
}
