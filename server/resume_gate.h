/* resume_gate.h - counts suspended connections that other threads are resuming, so that shutdown
 * stops libmicrohttpd only after the last MHD_resume_connection has returned. */
#ifndef LUCENT_RESUME_GATE_H
#define LUCENT_RESUME_GATE_H

#include <microhttpd.h>

struct resume_gate;

struct resume_gate *resume_gate_create(void);
void resume_gate_destroy(struct resume_gate *g);

/* Called under the lock that decided a connection's answer is ready (so that a drain which sees the
 * answer ready also sees the resume coming): from here until resume_gate_resume returns, waits wait. */
void resume_gate_enter(struct resume_gate *g);
/* MHD_resume_connection(c), then leaves the gate. Fault-injection builds sleep first for
 * $LUCENTD_FAULT_RESUME_DELAY_MS, to widen the window the gate closes. */
void resume_gate_resume(struct resume_gate *g, struct MHD_Connection *c);
/* Waits until no resume is in flight or the deadline (monotonic seconds) passes; returns how many
 * are still in flight. */
int resume_gate_wait(struct resume_gate *g, double deadline);

#endif
