/* mesh_import_sandbox.c - runs lucent-import in a child process under rlimits and a wall-clock
 * deadline, feeds it the upload and reads its one-line JSON answer (contract in the header). */
#define _GNU_SOURCE /* pipe2 */

#include "mesh_import_sandbox.h"
#include "import_jail.h"
#include "mesh_compact.h"

#include <errno.h>
#include <fcntl.h>
#include <jansson.h>
#include <limits.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#define ANSWER_CAP 4096       /* the importer answers one short JSON line */
#define LOG_CAP 4096          /* of its stderr, relayed to ours */
#define CHUNK 65536
#define CHILD_FILES 16        /* stdin, stdout, stderr, fd 3, its own file, what the loader opens */
#define EXIT_NOT_STARTED 127  /* as import_jail.c exits when a layer cannot be set up */

static atomic_uint_fast64_t violations; /* importers the seccomp filter killed */

typedef struct transcript {
    char answer[ANSWER_CAP + 1];
    size_t answer_len;
    int answer_overflow;
    char log[LOG_CAP + 1];
    size_t log_len;
} transcript;

static void close_fd(int *fd)
{
    if (*fd >= 0)
        close(*fd);
    *fd = -1;
}

lucent_status mesh_import_self_test(const struct import_jail *jail, const struct import_limits *lim,
                                    lucent_error *err)
{
    static const char triangle[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    struct mesh_info info;
    lucent_error why = {0};
    int fd = memfd_create("lucent-import-self-test", MFD_CLOEXEC);
    if (fd < 0)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "memfd_create failed: %s", strerror(errno));
    lucent_status st = mesh_import_isolated(jail, lim, triangle, sizeof triangle - 1, "obj", fd, &info, &why);
    close(fd);
    if (st != LUCENT_OK)
        return lucent_fail(err, st, "", "the mesh importer's self-test failed: %s", why.message);
    return LUCENT_OK;
}

uint64_t mesh_import_violations(void)
{
    return atomic_load(&violations);
}

/* The largest compact file the importer may write: no output holds more than LUCENT_MAX_TRIANGLES,
 * nor more than 3 vertices a triangle. */
static uint64_t output_cap(const struct import_limits *lim)
{
    uint32_t triangles = lim->max_triangles < LUCENT_MAX_TRIANGLES ? lim->max_triangles : LUCENT_MAX_TRIANGLES;
    return mesh_compact_size(3 * triangles, triangles);
}

/* ---- starting the child ---- */

/* A limit above the daemon's own hard limit cannot be set by an unprivileged child. */
static void add_limit(struct import_child_spec *cs, int resource, rlim_t soft, rlim_t hard)
{
    struct rlimit current;
    if (getrlimit(resource, &current) == 0 && current.rlim_max != RLIM_INFINITY) {
        soft = soft < current.rlim_max ? soft : current.rlim_max;
        hard = hard < current.rlim_max ? hard : current.rlim_max;
    }
    int i = cs->limit_count++;
    cs->resources[i] = resource;
    cs->limits[i].rlim_cur = soft;
    cs->limits[i].rlim_max = hard;
}

static void prepare(struct import_child_spec *cs, char *argv[6], char max_triangles[16],
                    const struct import_limits *lim, const char *ext)
{
    snprintf(max_triangles, 16, "%u", lim->max_triangles);
    char *args[] = {"lucent-import", "--format", (char *)ext, "--max-triangles", max_triangles, NULL};
    memcpy(argv, args, sizeof args);
    *cs = (struct import_child_spec){.argv = argv};
    add_limit(cs, RLIMIT_AS, lim->address_space_bytes, lim->address_space_bytes);
    /* the soft limit sends SIGXCPU, which ends it; the hard one SIGKILLs one second later */
    add_limit(cs, RLIMIT_CPU, (rlim_t)lim->cpu_seconds, (rlim_t)lim->cpu_seconds + 1);
    add_limit(cs, RLIMIT_FSIZE, output_cap(lim), output_cap(lim));
    add_limit(cs, RLIMIT_NOFILE, CHILD_FILES, CHILD_FILES);
    add_limit(cs, RLIMIT_CORE, 0, 0); /* crashes on hostile files must not fill the disk */
    add_limit(cs, RLIMIT_NPROC, 0, 0); /* no fork, should the seccomp filter fail to stop one */
}

typedef struct child {
    pid_t pid;
    int in_fd, out_fd, log_fd; /* the parent's ends; -1 once closed */
} child;

static lucent_status spawn(const struct import_jail *jail, const struct import_child_spec *cs, int mesh_fd,
                           child *c, lucent_error *err)
{
    int in[2] = {-1, -1}, out[2] = {-1, -1}, log[2] = {-1, -1};
    /* a socket for stdin, so that send(MSG_NOSIGNAL) turns a child that stopped reading into EPIPE
     * instead of a SIGPIPE that would end the daemon */
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, in) != 0 || pipe2(out, O_CLOEXEC) != 0 ||
        pipe2(log, O_CLOEXEC) != 0) {
        int e = errno;
        close_fd(&in[0]), close_fd(&in[1]), close_fd(&out[0]), close_fd(&out[1]), close_fd(&log[0]);
        close_fd(&log[1]);
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "could not create pipes for the mesh importer: %s",
                           strerror(e));
    }
    int fds[4] = {in[1], out[1], log[1], mesh_fd};
    pid_t pid = -1;
    lucent_status st = import_jail_spawn(jail, cs, fds, &pid, err);
    close_fd(&in[1]), close_fd(&out[1]), close_fd(&log[1]);
    if (st != LUCENT_OK) {
        close_fd(&in[0]), close_fd(&out[0]), close_fd(&log[0]);
        return st;
    }
    fcntl(in[0], F_SETFL, fcntl(in[0], F_GETFL) | O_NONBLOCK);
    *c = (child){pid, in[0], out[0], log[0]};
    return LUCENT_OK;
}

/* ---- talking to it ---- */

/* Reads what is available; keeps up to cap bytes and drops the rest. Closes fd at end of file. */
static void drain(int *fd, char *buf, size_t cap, size_t *len, int *overflow)
{
    char chunk[CHUNK];
    ssize_t n = read(*fd, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR)
        return;
    if (n <= 0) {
        close_fd(fd);
        return;
    }
    size_t keep = (size_t)n < cap - *len ? (size_t)n : cap - *len;
    memcpy(buf + *len, chunk, keep);
    *len += keep;
    buf[*len] = '\0';
    if (overflow && keep < (size_t)n)
        *overflow = 1;
}

/* Writes the input and collects the output until the child closes its output or the deadline
 * passes. Returns 0, 1 when the deadline passed, -1 when poll failed. */
static int exchange(child *c, const unsigned char *in, size_t len, int64_t deadline, transcript *t)
{
    size_t sent = 0;
    if (len == 0)
        close_fd(&c->in_fd);
    while (c->out_fd >= 0 || c->log_fd >= 0) {
        int64_t left = deadline - import_jail_now_ms();
        if (left <= 0)
            return 1;
        struct pollfd p[3] = {{c->in_fd, POLLOUT, 0}, {c->out_fd, POLLIN, 0}, {c->log_fd, POLLIN, 0}};
        int n = poll(p, 3, left < INT_MAX ? (int)left : INT_MAX);
        if (n < 0 && errno != EINTR)
            return -1;
        if (n <= 0)
            continue;
        if (p[0].revents) {
            size_t want = len - sent < CHUNK ? len - sent : CHUNK;
            ssize_t w = send(c->in_fd, in + sent, want, MSG_NOSIGNAL);
            if (w > 0 && (sent += (size_t)w) == len)
                close_fd(&c->in_fd); /* end of file for the child */
            else if (w < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)
                close_fd(&c->in_fd); /* it stopped reading; its exit status says why */
        }
        if (p[1].revents)
            drain(&c->out_fd, t->answer, ANSWER_CAP, &t->answer_len, &t->answer_overflow);
        if (p[2].revents)
            drain(&c->log_fd, t->log, LOG_CAP, &t->log_len, NULL);
    }
    return 0;
}

/* ---- its answer ---- */

static lucent_status not_understood(const transcript *t, lucent_error *err)
{
    int shown = (int)strcspn(t->answer, "\r\n");
    return lucent_fail(err, LUCENT_E_INTERNAL, "", "the mesh importer's answer was not understood: %.*s",
                       shown < 200 ? shown : 200, t->answer);
}

static lucent_status parse_info(const transcript *t, const struct import_limits *lim, struct mesh_info *info,
                                lucent_error *err)
{
    json_error_t jerr;
    json_int_t triangles, vertices;
    double *lo = info->bounds_min, *hi = info->bounds_max;
    json_t *doc = json_loadb(t->answer, t->answer_len, JSON_REJECT_DUPLICATES, &jerr);
    int ok = doc && json_unpack_ex(doc, &jerr, JSON_STRICT, "{s:I, s:I, s:{s:[FFF], s:[FFF]}}", "triangles",
                                   &triangles, "vertices", &vertices, "bounds", "min", &lo[0], &lo[1], &lo[2],
                                   "max", &hi[0], &hi[1], &hi[2]) == 0;
    json_decref(doc);
    ok = ok && triangles >= 1 && triangles <= lim->max_triangles && vertices >= 1 && vertices <= 3 * triangles;
    for (int k = 0; ok && k < 3; k++)
        ok = isfinite(lo[k]) && isfinite(hi[k]) && lo[k] <= hi[k];
    if (!ok)
        return not_understood(t, err);
    info->triangles = (uint32_t)triangles;
    info->vertices = (uint32_t)vertices;
    return LUCENT_OK;
}

static lucent_status parse_refusal(const transcript *t, const struct import_limits *lim, lucent_error *err)
{
    json_error_t jerr;
    const char *name, *field, *message;
    json_t *doc = json_loadb(t->answer, t->answer_len, JSON_REJECT_DUPLICATES, &jerr);
    lucent_status status = LUCENT_OK;
    if (doc && json_unpack_ex(doc, &jerr, JSON_STRICT, "{s:s, s:s, s:s}", "status", &name, "field", &field,
                              "message", &message) == 0)
        for (lucent_status s = LUCENT_E_INVALID; s <= LUCENT_E_NOSPACE; s++)
            if (s != LUCENT_E_CANCELLED && s != LUCENT_E_DEVICE_LOST && strcmp(name, lucent_status_name(s)) == 0)
                status = s;
    lucent_status st;
    if (status == LUCENT_OK)
        st = not_understood(t, err);
    else if (status == LUCENT_E_NOMEM) /* the importer's memory is capped: not a transient failure */
        st = lucent_fail(err, LUCENT_E_LIMIT, "mesh",
                         "importing this mesh needs more than the %zu MiB of memory the importer may use",
                         lim->address_space_bytes >> 20);
    else /* whatever the importer called the field, for the daemon the upload as a whole is "mesh" */
        st = lucent_fail(err, status, "mesh", "%s", message);
    json_decref(doc); /* message points into doc */
    return st;
}

static lucent_status unsound_output(const char *why, lucent_error *err)
{
    fprintf(stderr, "lucent: mesh importer: its output failed the daemon's check: %s\n", why);
    return lucent_fail(err, LUCENT_E_MESH, "mesh", "the mesh importer's output failed the daemon's check (%.300s)",
                       why);
}

/* The daemon's own reading of what the importer wrote: an importer a hostile file took over may write
 * anything and describe it falsely, so the mesh must be sound, within the limits, and be the one the
 * answer describes. */
static lucent_status check_output(int fd, const struct import_limits *lim, const struct mesh_info *info,
                                  lucent_error *err)
{
    struct stat st;
    if (fstat(fd, &st) != 0)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "cannot inspect the imported mesh: %s", strerror(errno));
    if (st.st_size <= 0 || (uint64_t)st.st_size > output_cap(lim))
        return unsound_output("its size is not that of a mesh within the limits", err);
    size_t size = (size_t)st.st_size;
    void *data = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
    if (data == MAP_FAILED)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "cannot map the imported mesh: %s", strerror(errno));
    lucent_mesh *m = NULL;
    lucent_error why = {0};
    lucent_status read = mesh_compact_read(data, size, &m, &why);
    munmap(data, size);
    if (read != LUCENT_OK)
        return unsound_output(why.message, err);
    double lo[3], hi[3];
    mesh_bounds(m, lo, hi);
    int same = m->triangle_count == info->triangles && m->vertex_count == info->vertices;
    for (int k = 0; k < 3; k++)
        same = same && lo[k] == info->bounds_min[k] && hi[k] == info->bounds_max[k];
    lucent_mesh_free(m);
    return same ? LUCENT_OK : unsound_output("its answer does not describe the mesh it wrote", err);
}

static lucent_status interpret(int status, const transcript *t, const char *ext, size_t len,
                               const struct import_limits *lim, int mesh_fd, struct mesh_info *info, lucent_error *err)
{
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGSYS) {
        atomic_fetch_add(&violations, 1);
        fprintf(stderr, "lucent: mesh importer: SANDBOX VIOLATION: killed by its seccomp filter for a system "
                        "call parsing never makes (a %s upload of %zu bytes); see the importer's lines above\n",
                ext, len);
        return lucent_fail(err, LUCENT_E_MESH, "mesh",
                           "the mesh importer was stopped by its sandbox: this file made it attempt a system call "
                           "that parsing never needs (opening a file, a socket, a new process or a signal)");
    }
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU)
        return lucent_fail(err, LUCENT_E_MESH, "mesh",
                           "the mesh importer used more than %d s of CPU time on this file and was stopped",
                           lim->cpu_seconds);
    if (WIFSIGNALED(status))
        return lucent_fail(err, LUCENT_E_MESH, "mesh", "the mesh importer crashed (signal %d) on this file",
                           WTERMSIG(status));
    int code = WEXITSTATUS(status);
    if (code == EXIT_NOT_STARTED)
        return lucent_fail(err, LUCENT_E_INTERNAL, "",
                           "could not start the mesh importer: its sandbox could not be set up, or it cannot load "
                           "within %zu MiB of address space (its lines above say which)",
                           lim->address_space_bytes >> 20);
    if (t->answer_overflow || (code != 0 && code != 2))
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "the mesh importer failed (exit status %d)", code);
    if (code != 0)
        return parse_refusal(t, lim, err);
    lucent_status st = parse_info(t, lim, info, err);
    return st == LUCENT_OK ? check_output(mesh_fd, lim, info, err) : st;
}

static int known_ext(const char *ext)
{
    static const char *const exts[] = {"obj", "ply", "stl", "gltf", "glb", "bundle"};
    for (size_t i = 0; ext && i < sizeof exts / sizeof exts[0]; i++)
        if (strcmp(ext, exts[i]) == 0)
            return 1;
    return 0;
}

/* The importer's stderr, a log line per line of it, each byte that could forge or hide a line (line
 * ends, escape sequences, anything not printable ASCII) written as \xNN: it is the hostile side's text. */
static void relay_log(const char *log, size_t len)
{
    char line[4 * LOG_CAP + 1];
    size_t n = 0;
    for (size_t i = 0; i <= len; i++) {
        unsigned char c = i < len ? (unsigned char)log[i] : '\n';
        if (c == '\n') {
            if (n > 0) {
                line[n] = '\0';
                fprintf(stderr, "lucent: mesh importer: %s\n", line);
            }
            n = 0;
        } else if (c >= 0x20 && c < 0x7f && c != '\\') {
            line[n++] = (char)c;
        } else {
            n += (size_t)snprintf(line + n, sizeof line - n, "\\x%02x", c);
        }
    }
}

lucent_status mesh_import_isolated(const struct import_jail *jail, const struct import_limits *lim,
                                   const void *bytes, size_t len, const char *ext, int mesh_fd,
                                   struct mesh_info *info, lucent_error *err)
{
    if (lim->address_space_bytes == 0 || lim->cpu_seconds <= 0 || lim->wall_seconds <= 0 ||
        lim->max_triangles == 0)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "every mesh import limit must be positive");
    if (!known_ext(ext))
        return lucent_fail(err, LUCENT_E_INVALID, "Content-Type",
                           "unsupported mesh format \"%.16s\"; send OBJ, PLY, STL, glTF or GLB", ext ? ext : "");
    struct import_child_spec cs;
    char *argv[6], max_triangles[16];
    child c = {-1, -1, -1, -1};
    transcript t = {.answer_len = 0};
    int status = 0;
    prepare(&cs, argv, max_triangles, lim, ext);
    lucent_status st = spawn(jail, &cs, mesh_fd, &c, err);
    if (st != LUCENT_OK)
        return st;
    int64_t deadline = import_jail_now_ms() + 1000 * (int64_t)lim->wall_seconds;
    int exchanged = exchange(&c, bytes, len, deadline, &t);
    close_fd(&c.in_fd), close_fd(&c.out_fd), close_fd(&c.log_fd);
    int reaped = import_jail_reap(c.pid, exchanged != 0 ? 0 : deadline, &status);
    relay_log(t.log, t.log_len);

    if (exchanged < 0)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "poll failed while talking to the mesh importer");
    if (reaped < 0)
        return lucent_fail(err, LUCENT_E_INTERNAL, "",
                           "the mesh importer's exit status was lost (is SIGCHLD ignored?)");
    if (exchanged == 1 || reaped == 1)
        return lucent_fail(err, LUCENT_E_MESH, "mesh",
                           "the mesh importer took longer than %d s on this file and was stopped",
                           lim->wall_seconds);
    info->bytes = len;
    info->created = 0;
    return interpret(status, &t, ext, len, lim, mesh_fd, info, err);
}
