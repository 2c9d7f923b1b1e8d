/* importer_seccomp.h - the system-call filter lucent-import puts itself under before it reads an
 * upload: what parsing needs (memory, reading stdin, writing its answer and mesh) and nothing else. */
#ifndef LUCENT_IMPORTER_SECCOMP_H
#define LUCENT_IMPORTER_SECCOMP_H

#include "lucent.h"

/* Sets no_new_privs and loads the filter. From then on the process may read fd 0, write fds 1-3,
 * manage memory (never executable), use futexes, signal itself and exit; any other system call
 * (open, socket, connect, fork, exec, kill, ptrace, ...) kills it with SIGSYS. Fails with
 * LUCENT_E_INTERNAL naming the step when the kernel refuses. */
lucent_status importer_seccomp_enter(lucent_error *err);

#endif
