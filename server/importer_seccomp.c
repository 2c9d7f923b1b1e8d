/* importer_seccomp.c - lucent-import's seccomp filter (contract in importer_seccomp.h). The list was
 * taken from strace of the importer over the fuzz corpus in every format, after start-up. */
#define _GNU_SOURCE /* AT_EMPTY_PATH */

#include "importer_seccomp.h"

#include <errno.h>
#include <fcntl.h>
#include <seccomp.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/ioctl.h>
#include <unistd.h>

#define IMPORT_OUT_FD 3 /* the compact mesh; see mesh_import_sandbox.h */

/* Allowed without looking at the arguments: they touch only the process's own memory and state. */
static const int PLAIN[] = {
    SCMP_SYS(brk),          SCMP_SYS(munmap),   SCMP_SYS(mremap),     SCMP_SYS(madvise),
    SCMP_SYS(futex),        SCMP_SYS(close),    SCMP_SYS(fstat),      SCMP_SYS(lseek),
    SCMP_SYS(getpid),       SCMP_SYS(gettid),   SCMP_SYS(rt_sigprocmask), SCMP_SYS(rt_sigaction),
    SCMP_SYS(rt_sigreturn), SCMP_SYS(exit),     SCMP_SYS(exit_group), SCMP_SYS(clock_gettime),
    SCMP_SYS(getrandom),    SCMP_SYS(sysinfo), /* glibc qsort sizes its buffer by physical memory */
    SCMP_SYS(sigaltstack),  /* AddressSanitizer asks for it on every C++ throw */
};

static int add(scmp_filter_ctx f, int syscall, unsigned n, const struct scmp_arg_cmp *cmp)
{
    return seccomp_rule_add_array(f, SCMP_ACT_ALLOW, syscall, n, cmp);
}

static int add_rules(scmp_filter_ctx f)
{
    int rc = 0;
    for (size_t i = 0; rc == 0 && i < sizeof PLAIN / sizeof PLAIN[0]; i++)
        rc = add(f, PLAIN[i], 0, NULL);
    struct scmp_arg_cmp from_stdin = SCMP_A0(SCMP_CMP_EQ, 0);
    struct scmp_arg_cmp no_exec = SCMP_A2(SCMP_CMP_MASKED_EQ, PROT_EXEC, 0);
    struct scmp_arg_cmp own_pid = SCMP_A0(SCMP_CMP_EQ, (scmp_datum_t)getpid());
    struct scmp_arg_cmp empty_path = SCMP_A3(SCMP_CMP_MASKED_EQ, AT_EMPTY_PATH, AT_EMPTY_PATH);
    struct scmp_arg_cmp tty_query = SCMP_A1(SCMP_CMP_EQ, TCGETS);
    if (rc == 0)
        rc = add(f, SCMP_SYS(read), 1, &from_stdin);
    for (int fd = 1; rc == 0 && fd <= IMPORT_OUT_FD; fd++) {
        struct scmp_arg_cmp to_fd = SCMP_A0(SCMP_CMP_EQ, (scmp_datum_t)fd);
        rc = add(f, SCMP_SYS(write), 1, &to_fd);
    }
    if (rc == 0) /* memory may be mapped and protected, never made executable */
        rc = add(f, SCMP_SYS(mmap), 1, &no_exec);
    if (rc == 0)
        rc = add(f, SCMP_SYS(mprotect), 1, &no_exec);
    if (rc == 0) /* abort() raises SIGABRT at itself */
        rc = add(f, SCMP_SYS(tgkill), 1, &own_pid);
    if (rc == 0) /* fstat of an open descriptor, as glibc's stdio does it */
        rc = add(f, SCMP_SYS(newfstatat), 1, &empty_path);
    if (rc == 0) /* stdio asks whether stdout is a terminal */
        rc = add(f, SCMP_SYS(ioctl), 1, &tty_query);
    return rc;
}

#if defined(__SANITIZE_ADDRESS__)
/* LeakSanitizer's check at exit needs a thread and ptrace, which the filter forbids; the import
 * code's leaks are checked in-process by tests/fuzz/fuzz_import instead. */
const char *__asan_default_options(void);
const char *__asan_default_options(void)
{
    return "detect_leaks=0";
}
#endif

lucent_status importer_seccomp_enter(lucent_error *err)
{
    scmp_filter_ctx f = seccomp_init(SCMP_ACT_KILL_PROCESS);
    if (!f)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "seccomp_init failed: cannot build the import sandbox");
    const char *step = "seccomp_rule_add";
    int rc = add_rules(f);
    if (rc == 0) {
        step = "seccomp_load"; /* sets no_new_privs first (SCMP_FLTATR_CTL_NNP is on by default) */
        rc = seccomp_load(f);
    }
    seccomp_release(f);
    if (rc != 0)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "%s failed: cannot enter the import sandbox: %s", step,
                           strerror(-rc));
    return LUCENT_OK;
}
