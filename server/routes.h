/* routes.h - the flat route table of the HTTP API: path, allowed methods, handler, and whether the
 * bearer token is required. http_server.c matches requests against it; handlers live in routes.c. */
#ifndef LUCENTD_ROUTES_H
#define LUCENTD_ROUTES_H

#include <microhttpd.h>

struct request;

enum { M_GET = 1, M_HEAD = 2, M_POST = 4, M_DELETE = 8, M_OPTIONS = 16 };

struct route {
    const char *name;       /* the metrics label */
    const char *path;
    int prefix;             /* 1: path is a prefix followed by one more segment */
    unsigned methods;       /* besides OPTIONS, which every route answers (CORS preflight) */
    int open;               /* 1: no bearer token required */
    enum MHD_Result (*handler)(struct request *req);
};

/* The route for path, or NULL; *index is its metrics index (ROUTE_UNMATCHED when NULL). */
const struct route *route_match(const char *path, int *index);
/* Metrics labels of every route index, the last one being "unmatched". */
extern const char *const route_labels[];
extern const int route_label_count;
#define ROUTE_UNMATCHED (route_label_count - 1)

/* "GET, HEAD, OPTIONS" for a route's methods. */
void route_allow(unsigned methods, char *buf, size_t cap);

#endif
