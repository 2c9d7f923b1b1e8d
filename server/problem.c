/* problem.c - RFC 9457 application/problem+json bodies and the single table that maps lucent_status
 * and the daemon's own error codes to HTTP statuses. */
#include "problem.h"

#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Field-specific rows come before the catch-all row of the same code. The mesh store reports an
 * unknown format as INVALID on "Content-Type" and an unknown id as INVALID on "mesh.id". */
static const struct problem_kind table[] = {
    {LUCENT_E_INVALID, "Content-Type", 415, "unsupported-media-type", "Unsupported media type"},
    {LUCENT_E_INVALID, "mesh.id", 404, "unknown-mesh", "Unknown mesh"},
    {LUCENT_E_INVALID, NULL, 400, "invalid-request", "Invalid request"},
    {LUCENT_E_MESH, NULL, 422, "unusable-mesh", "Mesh has nothing to render"},
    {LUCENT_E_LIMIT, NULL, 413, "over-limit", "Over a limit of this server"},
    {LUCENT_E_IO, NULL, 500, "io-error", "Storage error"},
    {LUCENT_E_NOMEM, NULL, 503, "out-of-memory", "Out of memory"},
    {LUCENT_E_GPU, NULL, 500, "render-failed", "Render failed"},
    {LUCENT_E_INTERNAL, NULL, 500, "internal-error", "Internal error"},
    {LUCENT_E_CANCELLED, NULL, 503, "deadline", "Render deadline exceeded"},
    {LUCENT_E_DEVICE_LOST, NULL, 503, "device-lost", "GPU device lost"},
    {LUCENT_E_NOSPACE, NULL, 507, "storage-full", "Insufficient storage"},
    {PROBLEM_NO_ROUTE, NULL, 404, "not-found", "Not found"},
    {PROBLEM_METHOD, NULL, 405, "method-not-allowed", "Method not allowed"},
    {PROBLEM_NOT_ACCEPTABLE, NULL, 406, "not-acceptable", "No acceptable image type"},
    {PROBLEM_UNAUTHORIZED, NULL, 401, "unauthorized", "Bearer token required"},
    {PROBLEM_TOKEN_WRONG, NULL, 401, "token-rejected", "Bearer token not accepted"},
    {PROBLEM_RATE_LIMITED, NULL, 429, "rate-limited", "Too many requests"},
    {PROBLEM_QUEUE_FULL, NULL, 503, "queue-full", "Render queue full"},
    {PROBLEM_NOT_READY, NULL, 503, "not-ready", "Not ready"},
    {PROBLEM_DEADLINE, NULL, 503, "deadline", "Render deadline exceeded"},
    {PROBLEM_BODY_TOO_LARGE, NULL, 413, "body-too-large", "Request body too large"},
    {PROBLEM_HOST, NULL, 421, "host-not-served", "Host not served"},
    {PROBLEM_ORIGIN, NULL, 403, "origin-refused", "Cross-origin request refused"},
    {PROBLEM_BODIES_FULL, NULL, 503, "bodies-full", "Too many request bodies in flight"},
};

const struct problem_kind *problem_lookup(int code, const char *field)
{
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++)
        if (table[i].code == code && (!table[i].field || (field && strcmp(field, table[i].field) == 0)))
            return &table[i];
    return code == LUCENT_E_INTERNAL ? NULL : problem_lookup(LUCENT_E_INTERNAL, NULL); /* an unknown code is our bug */
}

/* Messages may quote request text; JSON strings must be UTF-8, so anything else becomes '?'. */
static void ascii(const char *in, char *out, size_t cap)
{
    size_t i = 0;
    for (; in[i] && i + 1 < cap; i++)
        out[i] = (unsigned char)in[i] < 0x20 || (unsigned char)in[i] > 0x7e ? '?' : in[i];
    out[i] = 0;
}

char *problem_json(const struct problem_kind *kind, const lucent_error *err, const char *request_id,
                   size_t *len)
{
    char type[96], instance[96], detail[sizeof err->message], field[sizeof err->field];
    ascii(err->message, detail, sizeof detail);
    ascii(err->field, field, sizeof field);
    snprintf(type, sizeof type, "tag:lucent,2026:problem:%s", kind->slug);
    snprintf(instance, sizeof instance, "urn:lucent:request:%s", request_id);
    json_t *o = json_pack("{s:s, s:s, s:i, s:s, s:s}", "type", type, "title", kind->title, "status",
                          (int)kind->http_status, "detail", detail, "instance", instance);
    if (o && field[0])
        json_object_set_new(o, "field", json_string(field));
    char *body = o ? json_dumps(o, JSON_COMPACT) : NULL;
    json_decref(o);
    if (body)
        *len = strlen(body);
    return body;
}
