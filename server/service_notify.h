/* service_notify.h - telling a service manager (systemd's Type=notify) how lucentd is doing: ready,
 * stopping, a status line and watchdog pings, over the datagram socket in $NOTIFY_SOCKET. */
#ifndef LUCENTD_SERVICE_NOTIFY_H
#define LUCENTD_SERVICE_NOTIFY_H

#include <stddef.h>
#include <sys/socket.h>
#include <sys/un.h>

struct service_notify {
    int fd;                   /* -1: not started by a service manager; every call does nothing */
    struct sockaddr_un addr;
    socklen_t addr_len;
    double watchdog_s;        /* ping period (half of $WATCHDOG_USEC); 0: no watchdog */
    double last_ping;
};

/* Reads $NOTIFY_SOCKET and $WATCHDOG_USEC/$WATCHDOG_PID and removes them from the environment. Returns
 * 0, or -1 with a message in err when the socket is named but cannot be used. */
int service_notify_open(struct service_notify *n, char *err, size_t cap);
/* Sends one message of newline-separated KEY=value assignments (sd_notify(3)); best effort. */
void service_notify_send(struct service_notify *n, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Sends WATCHDOG=1 when half the watchdog period has passed since the last ping and `healthy`. */
void service_notify_watchdog(struct service_notify *n, double now, int healthy);
void service_notify_close(struct service_notify *n);

#endif
