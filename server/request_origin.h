/* request_origin.h - who a request claims to be for and from: the Host it names (against DNS
 * rebinding) and the Origin that sent it (against web pages driving a local daemon). */
#ifndef LUCENTD_REQUEST_ORIGIN_H
#define LUCENTD_REQUEST_ORIGIN_H

#include <stddef.h>

/* Whether name (case-insensitive) is an item of the comma-separated list (spaces around items ignored). */
int list_has(const char *list, const char *name, size_t name_len);
/* Whether a Host header (port and all; NULL: none sent) names this daemon. allowed is --allowed-hosts:
 * names without port, comma-separated; "*" any; "" the loopback names (localhost, 127.0.0.1, [::1])
 * when listen is a loopback address, any host otherwise. A request without Host is not a browser's. */
int host_allowed(const char *host, const char *allowed, const char *listen);
/* Whether a request from origin (NULL: no Origin header, not a browser's cross-site request) may
 * change state or spend renders: the daemon's own origin (http:// and its Host), or one of the
 * --cors-origins (or any, with "*"). */
int origin_allowed(const char *origin, const char *host, const char *cors_origins);

#endif
