/* connection_guard.h - a deadline on sending a whole request: a client that trickles its headers or
 * body a byte at a time keeps libmicrohttpd's idle timeout from ever firing, and a few hundred such
 * clients would hold every connection (slowloris). */
#ifndef LUCENT_CONNECTION_GUARD_H
#define LUCENT_CONNECTION_GUARD_H

#include <microhttpd.h>
#include <stdint.h>

struct connection_guard;

/* deadline_s: seconds a client has from opening the connection (or from its previous answer on a
 * kept-alive one) to the last byte of its request. */
struct connection_guard *connection_guard_create(double deadline_s);
void connection_guard_destroy(struct connection_guard *g);

/* libmicrohttpd's MHD_OPTION_NOTIFY_CONNECTION callback (cls: the guard). */
void connection_guard_notify(void *cls, struct MHD_Connection *c, void **socket_context,
                             enum MHD_ConnectionNotificationCode code);
/* The request on c has arrived whole (the clock stops: the server is working on it) or has been
 * answered (the clock starts again for the next request on a kept-alive connection). */
void connection_guard_received(struct MHD_Connection *c, double now);
void connection_guard_answered(struct MHD_Connection *c, double now);

/* Shuts down the sockets of clients past the deadline; libmicrohttpd then closes them. Returns how
 * many; safe from any thread. */
int connection_guard_sweep(struct connection_guard *g, double now);
/* Connections closed so far for being too slow. */
uint64_t connection_guard_closed(struct connection_guard *g);

#endif
