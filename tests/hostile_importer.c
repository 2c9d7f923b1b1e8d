/* hostile_importer.c - stands in for lucent-import in tests and misbehaves as its upload's first line
 * says: crashes, hangs, spins, lies, or seals itself as lucent-import does and then tries to escape.
 * Other uploads it imports as lucent-import would (lucentd's start-up self-test sends one). */
#define _GNU_SOURCE /* environ */

#include "importer_seccomp.h"
#include "mesh_compact.h"

#include <arpa/inet.h>
#include <errno.h>
#include <jansson.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#define INPUT_CAP (1 << 20)

extern char **environ;
static unsigned char input[INPUT_CAP];

/* Its answer when an attempt was not stopped: the daemon will not understand it, and the test sees why. */
static int escaped(const char *what)
{
    printf("{\"status\":\"internal\",\"field\":\"mesh\",\"message\":\"ESCAPED: %s succeeded\"}\n", what);
    return 2;
}

/* What a buggy or hostile importer does to the daemon without trying to leave its sandbox; 0 when
 * `what` is not one of these. */
static int misbehave(const char *what)
{
    if (strcmp(what, "crash") == 0) {
        signal(SIGSEGV, SIG_DFL); /* not AddressSanitizer's handler, which would exit 1 instead */
        raise(SIGSEGV);
    }
    if (strcmp(what, "hang") == 0)
        sleep(600);
    if (strcmp(what, "spin") == 0)
        for (volatile unsigned long i = 0;; i++)
            continue;
    if (strcmp(what, "garbage") == 0) {
        printf("this is not JSON\n");
        return 1;
    }
    if (strcmp(what, "nomem") == 0) {
        printf("{\"status\":\"nomem\",\"field\":\"mesh\",\"message\":\"out of memory\"}\n");
        return 1;
    }
    if (strcmp(what, "forge") == 0) { /* log lines of the daemon's own form, and a terminal escape */
        fprintf(stderr, "warning\n2026-01-01T00:00:00.000Z info lucentd: access id=forged GET /v1/render "
                        "status=200\n\033[2Khidden\n");
        printf("{\"status\":\"mesh\",\"field\":\"mesh\",\"message\":\"nothing to render\"}\n");
        return 1;
    }
    return 0;
}

static int connect_loopback(void)
{
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons(9)};
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    int rc = fd >= 0 ? connect(fd, (struct sockaddr *)&a, sizeof a) : -1;
    int e = errno;
    if (fd >= 0)
        close(fd);
    errno = e;
    return rc;
}

/* Not an attempt: the whole input imported as OBJ, the mesh to fd 3 and the answer lucent-import gives. */
static int import_plainly(FILE *out, size_t len)
{
    lucent_mesh *m = NULL;
    lucent_error err = {0};
    if (!out || lucent_mesh_import_memory(input, len, "obj", &m, &err) != LUCENT_OK ||
        mesh_compact_write(m, out, &err) != LUCENT_OK || fflush(out) != 0) {
        printf("{\"status\":\"invalid\",\"field\":\"mesh\",\"message\":\"not an attempt, nor a mesh\"}\n");
        lucent_mesh_free(m);
        return 2;
    }
    double lo[3], hi[3];
    mesh_bounds(m, lo, hi);
    printf("{\"triangles\":%u,\"vertices\":%u,\"bounds\":{\"min\":[%.17g,%.17g,%.17g],\"max\":[%.17g,%.17g,%.17g]}}\n",
           m->triangle_count, m->vertex_count, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    lucent_mesh_free(m);
    return 0;
}

/* Unsealed: what the jail alone gives the importer, as a refusal message the test reads. */
static int report_jail(void)
{
    char fds[256] = "";
    size_t n = 0, env = 0;
    for (int fd = 0; fd < 1024; fd++)
        if (fcntl(fd, F_GETFD) >= 0)
            n += (size_t)snprintf(fds + n, sizeof fds - n, "%s%d", n ? "," : "", fd);
    while (environ && environ[env])
        env++;
    pid_t child = fork();
    if (child == 0)
        _exit(0);
    const char *fork_result = child < 0 ? strerrorname_np(errno) : "allowed";
    if (child > 0)
        waitpid(child, NULL, 0);
    const char *net = connect_loopback() == 0 ? "connected" : strerrorname_np(errno);
    char cwd[256];
    printf("{\"status\":\"invalid\",\"field\":\"mesh\",\"message\":\"env=%zu fds=%s uid=%u pgrp=%s nnp=%d "
           "fork=%s connect=%s cwd=%s\"}\n",
           env, fds, (unsigned)getuid(), getpgrp() == getpid() ? "own" : "shared", prctl(PR_GET_NO_NEW_PRIVS, 0, 0, 0, 0),
           fork_result, net, getcwd(cwd, sizeof cwd) ? cwd : "?");
    return 2;
}

int main(void)
{
    ssize_t len = read(0, input, sizeof input - 1);
    if (len <= 0)
        return 3;
    input[len] = 0;
    size_t line = strcspn((char *)input, "\n");
    char what[32];
    snprintf(what, sizeof what, "%.*s", (int)line, (const char *)input);
    if (strcmp(what, "jail") == 0)
        return report_jail();
    if (misbehave(what))
        return strcmp(what, "garbage") == 0 ? 0 : 2;
    lucent_error err = {0};
    FILE *out = fdopen(3, "wb"); /* before the filter, as lucent-import does it */
    json_object_seed(0);
    if (importer_seccomp_enter(&err) != LUCENT_OK) {
        printf("{\"status\":\"internal\",\"field\":\"\",\"message\":\"%s\"}\n", err.message);
        return 2;
    }
    if (strcmp(what, "open") == 0 && open("/etc/passwd", O_RDONLY) >= 0)
        return escaped("open(\\\"/etc/passwd\\\")");
    if (strcmp(what, "connect") == 0 && connect_loopback() == 0)
        return escaped("connect to 127.0.0.1:9");
    if (strcmp(what, "fork") == 0 && fork() >= 0)
        return escaped("fork");
    if (strcmp(what, "signal") == 0 && kill(getppid(), SIGCONT) == 0)
        return escaped("kill(parent)");
    if (strcmp(what, "exec") == 0) {
        char *argv[] = {"/bin/true", NULL};
        execv(argv[0], argv);
    }
    if (strcmp(what, "mmap-exec") == 0 &&
        mmap(NULL, 4096, PROT_READ | PROT_EXEC, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0) != MAP_FAILED)
        return escaped("mmap(PROT_EXEC)");
    if (strcmp(what, "lie") == 0) { /* the rest of the input to fd 3, and an answer that does not match it */
        size_t rest = (size_t)len - line - 1;
        if (write(3, input + line + 1, rest) != (ssize_t)rest)
            return 3;
        printf("{\"triangles\":1,\"vertices\":3,\"bounds\":{\"min\":[0,0,0],\"max\":[5,5,5]}}\n");
        return 0;
    }
    return import_plainly(out, (size_t)len);
}
