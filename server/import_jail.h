/* import_jail.h - the process boundary around lucent-import: a child with no environment, only its
 * four descriptors and its executable, its own process group, rlimits, a dedicated user, namespaces. */
#ifndef LUCENT_IMPORT_JAIL_H
#define LUCENT_IMPORT_JAIL_H

#include "lucent.h"

#include <sys/resource.h>
#include <sys/types.h>

struct import_jail;

#define IMPORT_JAIL_LIMITS 6

/* What one child gets: argv for the importer and the rlimits to set (soft and hard). */
struct import_child_spec {
    char *const *argv;
    int resources[IMPORT_JAIL_LIMITS];
    struct rlimit limits[IMPORT_JAIL_LIMITS];
    int limit_count;
};

/* Opens the importer (it is run by descriptor, so a dedicated user needs no path to it) and finds at
 * start which layers this machine allows: when lucentd runs as root and `user` names an account, the
 * child switches to it; unprivileged namespaces (user, network, IPC, UTS) are tried in a probe child.
 * user NULL or "" keeps the daemon's user. A missing importer or user switch that fails is an error;
 * refused namespaces are not (the jail says so). */
lucent_status import_jail_open(const char *tool, const char *user, struct import_jail **out, lucent_error *err);
void import_jail_close(struct import_jail *jail);

/* One line saying what the jail applies and what this machine refused, for the log and /readyz. */
const char *import_jail_describe(const struct import_jail *jail);
/* The user the importer runs as ("" when the daemon's own) and the namespaces it gets ("" for none,
 * else e.g. "user,net,ipc,uts"). */
const char *import_jail_user(const struct import_jail *jail);
const char *import_jail_namespaces(const struct import_jail *jail);

/* Starts the importer with fds[0..3] as its stdin, stdout, stderr and fd 3; nothing else is open in
 * it. It leads its own process group, dies with the daemon (PR_SET_PDEATHSIG), has no_new_privs and
 * RLIMIT_NPROC 0. A layer that fails in the child makes it exit 127 with the step on its stderr. The
 * caller must end it with import_jail_reap. The daemon must not set SIGCHLD to SIG_IGN. */
lucent_status import_jail_spawn(const struct import_jail *jail, const struct import_child_spec *spec,
                                const int fds[4], pid_t *pid, lucent_error *err);

/* Waits for the child until deadline_ms (CLOCK_MONOTONIC milliseconds), then kills it; either way
 * kills whatever else is left in its process group before reaping it. Returns 1 when it had to be
 * killed, 0 when it ended by itself, -1 when its status is lost. */
int import_jail_reap(pid_t pid, int64_t deadline_ms, int *status);

/* Milliseconds on CLOCK_MONOTONIC. */
int64_t import_jail_now_ms(void);

#endif
