/* service_notify.c - systemd's notification protocol spoken directly (it is one datagram per message),
 * so lucentd needs no libsystemd: the socket from $NOTIFY_SOCKET, the watchdog from $WATCHDOG_USEC. */
#define _GNU_SOURCE /* unsetenv under -std=c11 */

#include "service_notify.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* $WATCHDOG_USEC applies to this process only when $WATCHDOG_PID is unset or names it. */
static double watchdog_seconds(void)
{
    const char *usec = getenv("WATCHDOG_USEC"), *pid = getenv("WATCHDOG_PID");
    char *end = NULL;
    if (!usec || (pid && strtol(pid, &end, 10) != (long)getpid()))
        return 0.0;
    unsigned long long us = strtoull(usec, &end, 10);
    return end != usec && *end == '\0' && us > 0 ? (double)us / 2e6 : 0.0;
}

int service_notify_open(struct service_notify *n, char *err, size_t cap)
{
    memset(n, 0, sizeof *n);
    n->fd = -1;
    const char *path = getenv("NOTIFY_SOCKET");
    int rc = 0;
    size_t len = path ? strlen(path) : 0;
    if (len == 0)
        goto done;
    if ((path[0] != '/' && path[0] != '@') || len >= sizeof n->addr.sun_path) {
        snprintf(err, cap, "NOTIFY_SOCKET \"%.100s\" is not a socket path or an abstract name", path);
        rc = -1;
        goto done;
    }
    n->addr.sun_family = AF_UNIX;
    memcpy(n->addr.sun_path, path, len);
    if (path[0] == '@')
        n->addr.sun_path[0] = '\0'; /* abstract namespace: no terminator, the length says where it ends */
    n->addr_len = (socklen_t)(offsetof(struct sockaddr_un, sun_path) + len + (path[0] == '/'));
    n->fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (n->fd < 0) {
        snprintf(err, cap, "cannot make a socket for NOTIFY_SOCKET: %s", strerror(errno));
        rc = -1;
        goto done;
    }
    n->watchdog_s = watchdog_seconds();
done:
    unsetenv("NOTIFY_SOCKET"); /* nothing lucentd starts may speak for it */
    unsetenv("WATCHDOG_USEC");
    unsetenv("WATCHDOG_PID");
    return rc;
}

void service_notify_send(struct service_notify *n, const char *fmt, ...)
{
    if (n->fd < 0)
        return;
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    int len = vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (len <= 0)
        return;
    if ((size_t)len >= sizeof msg)
        len = sizeof msg - 1; /* a status line cut short is still a status line */
    (void)sendto(n->fd, msg, (size_t)len, MSG_NOSIGNAL, (const struct sockaddr *)&n->addr, n->addr_len);
}

void service_notify_watchdog(struct service_notify *n, double now, int healthy)
{
    if (n->fd < 0 || n->watchdog_s <= 0.0 || !healthy || now - n->last_ping < n->watchdog_s)
        return;
    service_notify_send(n, "WATCHDOG=1");
    n->last_ping = now;
}

void service_notify_close(struct service_notify *n)
{
    if (n->fd >= 0)
        close(n->fd);
    n->fd = -1;
}
