/* import_jail.c - starts lucent-import sealed off from the daemon (contract in import_jail.h). The
 * seccomp filter is the importer's own (importer_seccomp.c); everything around it is set up here. */
#define _GNU_SOURCE /* close_range, fexecve, setgroups, unshare */

#include "import_jail.h"

#include <errno.h>
#include <fcntl.h>
#include <grp.h>
#include <pwd.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define EXIT_NOT_STARTED 127 /* as a shell reports a program it could not run */
#define TOOL_FD 4            /* the importer's own file, kept open for fexecve */
#define FIRST_CLOSED 5
#define FALLBACK_FD_CAP 65536 /* closing one by one, past this many the daemon could not have opened */
#define REAP_POLL_NS 5000000L

struct import_jail {
    int tool_fd;
    int switch_user;
    uid_t uid;
    gid_t gid;
    char user[64];
    int ns_flags;
    char namespaces[32];
    char description[512];
};

int64_t import_jail_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* ---- in the child, between fork and exec: plain system calls only (the daemon has threads) ---- */

_Noreturn static void child_fail(const char *step)
{
    static const char prefix[] = "import jail: ";
    static const char suffix[] = " failed\n";
    if (write(2, prefix, sizeof prefix - 1) < 0 || write(2, step, strlen(step)) < 0 ||
        write(2, suffix, sizeof suffix - 1) < 0)
        _exit(EXIT_NOT_STARTED);
    _exit(EXIT_NOT_STARTED);
}

/* fds[i] becomes descriptor i (the tool TOOL_FD): each is first copied above them all, so that
 * moving one into place never closes another's source. */
static void place_fds(const int fds[4], int tool_fd)
{
    int src[TOOL_FD + 1] = {fds[0], fds[1], fds[2], fds[3], tool_fd}, high[TOOL_FD + 1];
    for (int i = 0; i <= TOOL_FD; i++)
        if ((high[i] = fcntl(src[i], F_DUPFD, FIRST_CLOSED)) < 0)
            child_fail("moving descriptors");
    for (int i = 0; i <= TOOL_FD; i++)
        if (dup2(high[i], i) != i)
            child_fail("moving descriptors");
}

/* Everything else the daemon had open (listening and client sockets, other imports' pipes, the
 * store): close_range where the kernel has it (5.9), else one by one up to the descriptor limit. */
static void close_the_rest(void)
{
    if (close_range(FIRST_CLOSED, ~0u, 0) == 0)
        return;
    struct rlimit rl;
    if (getrlimit(RLIMIT_NOFILE, &rl) != 0)
        child_fail("getrlimit(RLIMIT_NOFILE)");
    rlim_t cap = rl.rlim_cur < FALLBACK_FD_CAP ? rl.rlim_cur : FALLBACK_FD_CAP;
    for (rlim_t fd = FIRST_CLOSED; fd < cap; fd++)
        close((int)fd);
}

static void switch_user(const struct import_jail *jail)
{
    if (setgroups(0, NULL) != 0 || setgid(jail->gid) != 0 || setuid(jail->uid) != 0 || getuid() != jail->uid)
        child_fail("switching to the import user");
}

_Noreturn static void child_exec(const struct import_jail *jail, const struct import_child_spec *spec,
                                 const int fds[4], pid_t parent)
{
    static char *const no_environment[] = {NULL};
    sigset_t none;
    if (setpgid(0, 0) != 0)
        child_fail("setpgid");
    place_fds(fds, jail->tool_fd);
    close_the_rest();
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, NULL);
    for (int sig = 1; sig < NSIG; sig++) /* what the daemon ignores (SIGPIPE) must not stay ignored */
        if (sig != SIGKILL && sig != SIGSTOP)
            signal(sig, SIG_DFL);
    if (chdir("/") != 0)
        child_fail("chdir(\"/\")");
    if (jail->switch_user)
        switch_user(jail);
    /* after the user switch, which clears it; a daemon already gone leaves no one to kill it */
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != parent)
        child_fail("PR_SET_PDEATHSIG");
    if (jail->ns_flags && unshare(jail->ns_flags) != 0)
        child_fail("unshare");
    for (int i = 0; i < spec->limit_count; i++)
        if (setrlimit(spec->resources[i], &spec->limits[i]) != 0)
            child_fail("setrlimit");
    if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0)
        child_fail("PR_SET_NO_NEW_PRIVS");
    fexecve(TOOL_FD, spec->argv, no_environment);
    child_fail("fexecve");
}

lucent_status import_jail_spawn(const struct import_jail *jail, const struct import_child_spec *spec,
                                const int fds[4], pid_t *pid, lucent_error *err)
{
    pid_t parent = getpid();
    pid_t p = fork();
    if (p == 0)
        child_exec(jail, spec, fds, parent);
    if (p < 0)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "could not start the mesh importer: %s", strerror(errno));
    /* also here, so that a kill of the group cannot come before the child made it (EACCES: it exec'd) */
    setpgid(p, p);
    *pid = p;
    return LUCENT_OK;
}

int import_jail_reap(pid_t pid, int64_t deadline_ms, int *status)
{
    int killed = 0;
    for (;;) {
        siginfo_t si;
        memset(&si, 0, sizeof si);
        /* WNOWAIT: the exited child stays a zombie, so its group id cannot be reused before the kill below */
        int r = waitid(P_PID, (id_t)pid, &si, WEXITED | WNOWAIT | (killed ? 0 : WNOHANG));
        if (r == 0 && si.si_pid == pid)
            break;
        if (r < 0 && errno != EINTR)
            return -1;
        if (r == 0 && import_jail_now_ms() >= deadline_ms) {
            kill(-pid, SIGKILL);
            kill(pid, SIGKILL);
            killed = 1;
        } else if (r == 0) {
            struct timespec pause = {0, REAP_POLL_NS};
            nanosleep(&pause, NULL);
        }
    }
    kill(-pid, SIGKILL); /* anything it started that the sandbox let through */
    while (waitpid(pid, status, 0) != pid)
        if (errno != EINTR)
            return -1;
    return killed;
}

/* ---- finding what this machine allows ---- */

/* In a probe child: whether the user switch and then unshare(flags) succeed; the errno otherwise. */
static int probe_namespaces(const struct import_jail *jail, int flags)
{
    pid_t p = fork();
    if (p == 0) {
        if (jail->switch_user && (setgroups(0, NULL) != 0 || setgid(jail->gid) != 0 || setuid(jail->uid) != 0))
            _exit(errno & 0xff);
        _exit(unshare(flags) == 0 ? 0 : errno & 0xff);
    }
    int status;
    if (p < 0 || waitpid(p, &status, 0) != p)
        return errno ? errno : ECHILD;
    return WIFEXITED(status) ? WEXITSTATUS(status) : ECHILD;
}

static lucent_status find_user(struct import_jail *jail, const char *user, lucent_error *err)
{
    if (!user || !user[0] || geteuid() != 0)
        return LUCENT_OK;
    struct passwd pw, *found = NULL;
    char buf[4096];
    int e = getpwnam_r(user, &pw, buf, sizeof buf, &found);
    if (!found)
        return lucent_fail(err, LUCENT_E_INVALID, "import-user",
                           "no user \"%.60s\" to run the mesh importer as%s%s (name another, or \"\" to keep root)",
                           user, e ? ": " : "", e ? strerror(e) : "");
    if (pw.pw_uid == 0)
        return lucent_fail(err, LUCENT_E_INVALID, "import-user", "the mesh importer must not run as root");
    jail->switch_user = 1;
    jail->uid = pw.pw_uid;
    jail->gid = pw.pw_gid;
    snprintf(jail->user, sizeof jail->user, "%s", user);
    return LUCENT_OK;
}

static void find_namespaces(struct import_jail *jail, char *refused, size_t cap)
{
    static const struct {
        int flags;
        const char *names;
    } tries[] = {
        {CLONE_NEWUSER | CLONE_NEWNET | CLONE_NEWIPC | CLONE_NEWUTS, "user,net,ipc,uts"},
        {CLONE_NEWNET | CLONE_NEWIPC | CLONE_NEWUTS, "net,ipc,uts"}, /* privileged, without a user namespace */
    };
    int first_error = 0;
    for (size_t i = 0; i < sizeof tries / sizeof tries[0]; i++) {
        int e = probe_namespaces(jail, tries[i].flags);
        if (e == 0) {
            jail->ns_flags = tries[i].flags;
            snprintf(jail->namespaces, sizeof jail->namespaces, "%s", tries[i].names);
            return;
        }
        if (!first_error)
            first_error = e;
    }
    snprintf(refused, cap, "; namespaces refused here (%s)", strerror(first_error));
}

lucent_status import_jail_open(const char *tool, const char *user, struct import_jail **out, lucent_error *err)
{
    struct stat st;
    *out = NULL;
    struct import_jail *jail = calloc(1, sizeof *jail);
    if (!jail)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory setting up the mesh importer");
    lucent_status status = LUCENT_OK;
    jail->tool_fd = open(tool, O_RDONLY | O_CLOEXEC);
    if (jail->tool_fd < 0)
        status = lucent_fail(err, LUCENT_E_INTERNAL, "", "cannot open the mesh importer \"%s\": %s", tool,
                             strerror(errno));
    else if (fstat(jail->tool_fd, &st) != 0 || !S_ISREG(st.st_mode) || !(st.st_mode & S_IXUSR))
        status = lucent_fail(err, LUCENT_E_INTERNAL, "", "the mesh importer \"%s\" is not an executable file", tool);
    else
        status = find_user(jail, user, err);
    if (status != LUCENT_OK) {
        import_jail_close(jail);
        return status;
    }
    char refused[96] = "";
    find_namespaces(jail, refused, sizeof refused);
    char who[96];
    if (jail->switch_user)
        snprintf(who, sizeof who, "user %s (uid %u)", jail->user, (unsigned)jail->uid);
    else
        snprintf(who, sizeof who, "the daemon's own user%s", geteuid() == 0 ? " (root: --import-user is empty)"
                                                                              : " (lucentd is not root)");
    snprintf(jail->description, sizeof jail->description,
             "lucent-import's seccomp filter; no_new_privs; no environment; fds 0-3 and its executable only; "
             "its own process group; RLIMIT_NPROC 0; %s; %s%s%s", who,
             jail->ns_flags ? "namespaces " : "no namespaces", jail->namespaces, refused);
    *out = jail;
    return LUCENT_OK;
}

void import_jail_close(struct import_jail *jail)
{
    if (!jail)
        return;
    if (jail->tool_fd >= 0)
        close(jail->tool_fd);
    free(jail);
}

const char *import_jail_describe(const struct import_jail *jail)
{
    return jail->description;
}

const char *import_jail_user(const struct import_jail *jail)
{
    return jail->user;
}

const char *import_jail_namespaces(const struct import_jail *jail)
{
    return jail->namespaces;
}
