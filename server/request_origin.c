/* request_origin.c - the Host and Origin checks of request_origin.h. A page a user visits can send
 * CORS-simple POSTs to 127.0.0.1 without asking, and DNS rebinding lets it read answers under its own
 * host name: the Host says which name the browser used, the Origin which page sent the request. */
#include "request_origin.h"

#include <stddef.h>
#include <string.h>
#include <strings.h>

int list_has(const char *list, const char *name, size_t name_len)
{
    for (const char *p = list; *p;) {
        size_t len = strcspn(p, ",");
        const char *item = p;
        size_t n = len;
        while (n && *item == ' ')
            item++, n--;
        while (n && item[n - 1] == ' ')
            n--;
        if (n == name_len && strncasecmp(item, name, n) == 0)
            return 1;
        p += len;
        if (*p == ',')
            p++;
    }
    return 0;
}

static int is_loopback_listen(const char *listen)
{
    return strncmp(listen, "127.", 4) == 0 || strcmp(listen, "::1") == 0;
}

/* The length of a Host header's name: up to its port, brackets kept for an IPv6 literal. */
static size_t host_name_len(const char *host)
{
    if (host[0] == '[') {
        const char *close = strchr(host, ']');
        return close ? (size_t)(close - host) + 1 : strlen(host);
    }
    return strcspn(host, ":");
}

int host_allowed(const char *host, const char *allowed, const char *listen)
{
    if (!host)
        return 1;
    if (strcmp(allowed, "*") == 0 || (!allowed[0] && !is_loopback_listen(listen)))
        return 1;
    size_t n = host_name_len(host);
    const char *port = host + n;
    if (*port && (*port != ':' || strspn(port + 1, "0123456789") != strlen(port + 1)))
        return 0;
    return list_has(allowed[0] ? allowed : "localhost,127.0.0.1,[::1]", host, n);
}

int origin_allowed(const char *origin, const char *host, const char *cors_origins)
{
    static const char scheme[] = "http://";
    if (!origin)
        return 1;
    if (strcmp(cors_origins, "*") == 0 || list_has(cors_origins, origin, strlen(origin)))
        return 1;
    return host && strncasecmp(origin, scheme, sizeof scheme - 1) == 0 &&
           strcasecmp(origin + sizeof scheme - 1, host) == 0;
}
