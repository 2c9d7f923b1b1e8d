/* server_problem.c - the message for an error answer. The daemon's problem bodies carry "field" (the
 * input at fault) and "detail" (what was expected), which together tell the user what to change. */
#include "server_problem.h"

#include <jansson.h>
#include <string.h>

static const char *str(const json_t *o, const char *key)
{
    const json_t *v = json_object_get(o, key);
    return json_is_string(v) ? json_string_value(v) : NULL;
}

int server_problem(const struct http_response *rs, lc_error *err)
{
    char retry[64] = "";
    if (rs->retry_after)
        snprintf(retry, sizeof retry, " (retry after %s s)", rs->retry_after);
    json_t *doc = rs->body_len ? json_loadb(rs->body, rs->body_len, 0, NULL) : NULL;
    const char *title = str(doc, "title"), *detail = str(doc, "detail"), *field = str(doc, "field");
    if (title && detail) {
        lc_fail(err, LC_E_SERVER, "%ld %s: %s%s%s%s", rs->status, title, field ? field : "", field ? ": " : "",
                detail, retry);
        json_decref(doc);
        return err->code;
    }
    json_decref(doc);
    /* Not a problem document (a proxy's page, say): show its start, on one line. */
    char excerpt[201];
    size_t n = rs->body_len < sizeof excerpt - 1 ? rs->body_len : sizeof excerpt - 1;
    for (size_t i = 0; i < n; i++)
        excerpt[i] = rs->body[i] == '\n' || rs->body[i] == '\r' ? ' ' : rs->body[i];
    excerpt[n] = 0;
    return lc_fail(err, LC_E_SERVER, "%ld from the server%s%s%s", rs->status, n ? ": " : "", excerpt, retry);
}
