/* problem.h - RFC 9457 problem details: the one table from error codes to HTTP statuses and titles.
 * Handlers never choose an error status themselves; they name a code and this table decides. */
#ifndef LUCENTD_PROBLEM_H
#define LUCENTD_PROBLEM_H

#include "lucent.h"

/* The daemon's own failures, numbered after lucent_status so one code space holds both. */
enum {
    PROBLEM_NO_ROUTE = 100,     /* no such path */
    PROBLEM_METHOD,             /* path exists, method does not */
    PROBLEM_NOT_ACCEPTABLE,     /* Accept and format leave no image type */
    PROBLEM_UNAUTHORIZED,       /* bearer token missing */
    PROBLEM_TOKEN_WRONG,        /* bearer token given, not the daemon's */
    PROBLEM_RATE_LIMITED,       /* over --rate-limit; Retry-After from the request's bucket */
    PROBLEM_QUEUE_FULL,
    PROBLEM_NOT_READY,          /* starting or draining */
    PROBLEM_DEADLINE,           /* the render did not finish within render-timeout */
    PROBLEM_BODY_TOO_LARGE,
    PROBLEM_HOST,               /* the Host is not one this daemon serves (DNS rebinding) */
    PROBLEM_ORIGIN,             /* a POST or DELETE sent by a web page of a foreign origin */
    PROBLEM_BODIES_FULL,        /* the bodies in flight hold --max-body-total */
};

struct problem_kind {
    int code;
    const char *field;   /* NULL: any field */
    unsigned http_status;
    const char *slug;    /* the problem type: "tag:lucent,2026:problem:<slug>" */
    const char *title;
};

/* The row for code and field (the first match in the table). */
const struct problem_kind *problem_lookup(int code, const char *field);
/* A problem+json body (malloc'd, NUL-terminated) for err (err->status is the code). */
char *problem_json(const struct problem_kind *kind, const lucent_error *err, const char *request_id,
                   size_t *len);

#endif
