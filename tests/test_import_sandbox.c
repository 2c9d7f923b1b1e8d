/* test_import_sandbox.c - mesh_import_isolated and mesh_format_sniff: real imports, the hostile inputs
 * of assimp-hazards.md, fuzzed glTF, importers that crash, hang, spin or talk nonsense, and one that
 * tries to escape its sandbox. Usage: test_import_sandbox LUCENT_IMPORT HOSTILE_IMPORTER BUNNY_OBJ */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif

#include "lucent.h"
#include "mesh.h"
#include "import_jail.h"
#include "mesh_import_sandbox.h"
#include "test_support.h"

#include <fcntl.h>
#include <pwd.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

static struct import_jail *real_jail, *hostile_jail;
static char out_path[64];

static struct import_limits LIMITS = {512u << 20, 10, 20, LUCENT_MAX_TRIANGLES};
/* Set by sanitizer builds: AddressSanitizer reserves terabytes of address space, which RLIMIT_AS forbids. */
static int unlimited_address_space;

static const char TRIANGLE_OBJ[] = "v 10 0 0\nv 11 0 0\nv 10 1 0\nf 1 2 3\n";

static double seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU time of the children waited for so far: the importer's own clock, which a busy machine does not
 * stretch as it does the wall clock. */
static double children_cpu_seconds(void)
{
    struct rusage ru;
    getrusage(RUSAGE_CHILDREN, &ru);
    return (double)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
           1e-6 * (double)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

typedef struct outcome {
    lucent_status status;
    lucent_error err;
    struct mesh_info info;
    double seconds, cpu_seconds; /* wall clock, and the importer's CPU time */
} outcome;

/* The output goes to out_path, as the store's temporaries: an empty file open for reading and writing. */
static outcome run(const struct import_jail *jail, const struct import_limits *lim, const void *bytes, size_t len,
                   const char *ext)
{
    outcome o;
    memset(&o, 0, sizeof o);
    int fd = open(out_path, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0) {
        o.status = lucent_fail(&o.err, LUCENT_E_IO, "", "cannot create %s", out_path);
        return o;
    }
    double t0 = seconds(), cpu0 = children_cpu_seconds();
    o.status = mesh_import_isolated(jail, lim, bytes, len, ext, fd, &o.info, &o.err);
    close(fd);
    o.seconds = seconds() - t0;
    o.cpu_seconds = children_cpu_seconds() - cpu0;
    return o;
}

/* The hostile importer reads what to do from the upload's first line. */
static outcome run_as(const struct import_jail *jail, const char *mode, const struct import_limits *lim,
                      const void *rest, size_t len)
{
    size_t n = strlen(mode);
    unsigned char *bytes = malloc(n + 1 + len);
    if (!bytes) {
        outcome o = {.status = LUCENT_E_NOMEM};
        return o;
    }
    memcpy(bytes, mode, n);
    bytes[n] = '\n';
    if (len)
        memcpy(bytes + n + 1, rest, len);
    outcome o = run(jail, lim, bytes, n + 1 + len, "obj");
    free(bytes);
    return o;
}

/* A failure that names itself: the expected status and a message containing part. */
static void expect_failure(const char *what, outcome o, lucent_status status, const char *part)
{
    test_check(o.status == status && strstr(o.err.message, part) != NULL,
               "%s: %s, field \"%s\": %s (%.2f s)", what, lucent_status_name(o.status), o.err.field, o.err.message,
               o.seconds);
}

static unsigned char *read_file(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf = NULL;
    if (f && fseek(f, 0, SEEK_END) == 0 && (*len = (size_t)ftell(f)) > 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (buf = malloc(*len)) && fread(buf, 1, *len, f) != *len) {
        free(buf);
        buf = NULL;
    }
    if (f)
        fclose(f);
    return buf;
}

/* ---- real imports ---- */

static void check_valid(const char *bunny_path)
{
    outcome o = run(real_jail, &LIMITS, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj");
    const struct mesh_info *i = &o.info;
    test_check(o.status == LUCENT_OK && i->triangles == 1 && i->vertices == 3 && i->bytes == strlen(TRIANGLE_OBJ) &&
                   i->bounds_min[0] == 10 && i->bounds_min[1] == 0 && i->bounds_max[0] == 11 &&
                   i->bounds_max[1] == 1 && i->bounds_min[2] == 0 && i->bounds_max[2] == 0,
               "triangle OBJ: %s, %u triangles, %u vertices, bounds [%g %g %g]..[%g %g %g] (source coordinates) "
               "in %.3f s %s",
               lucent_status_name(o.status), i->triangles, i->vertices, i->bounds_min[0], i->bounds_min[1],
               i->bounds_min[2], i->bounds_max[0], i->bounds_max[1], i->bounds_max[2], o.seconds, o.err.message);
    lucent_mesh *m = NULL;
    lucent_error err = {0};
    lucent_status st = lucent_mesh_import_file(out_path, &m, &err);
    test_check(st == LUCENT_OK && lucent_mesh_triangle_count(m) == 1, "its compact output %s loads: %s %s",
               out_path, lucent_status_name(st), err.message);
    lucent_mesh_free(m);

    size_t len = 0;
    unsigned char *bunny = read_file(bunny_path, &len);
    if (!test_check(bunny != NULL, "read the bunny %s (%zu bytes)", bunny_path, len))
        return;
    uint32_t faces = 0;
    for (size_t k = 0; k + 1 < len; k++)
        faces += (k == 0 || bunny[k - 1] == '\n') && bunny[k] == 'f' && bunny[k + 1] == ' ';
    o = run(real_jail, &LIMITS, bunny, len, "obj");
    test_check(o.status == LUCENT_OK && o.info.triangles == faces && o.info.vertices > 0 &&
                   o.info.bounds_max[1] > o.info.bounds_min[1],
               "bunny: %s, %u triangles (the file has %u faces), %u vertices, height %.4f, in %.3f s %s",
               lucent_status_name(o.status), o.info.triangles, faces, o.info.vertices,
               o.info.bounds_max[1] - o.info.bounds_min[1], o.seconds, o.err.message);

    struct import_limits few = LIMITS;
    few.max_triangles = 100;
    expect_failure("bunny with max_triangles 100", run(real_jail, &few, bunny, len, "obj"), LUCENT_E_LIMIT,
                   "at most 100");
    if (unlimited_address_space) {
        printf("     (address-space limits not checked: the importer is built with AddressSanitizer)\n");
        free(bunny);
        return;
    }
    /* the loader itself cannot map assimp into 8 MiB */
    struct import_limits tiny = LIMITS;
    tiny.address_space_bytes = 8u << 20;
    expect_failure("bunny in 8 MiB of address space", run(real_jail, &tiny, bunny, len, "obj"),
                   LUCENT_E_INTERNAL, "could not start");
    /* enough to start, too little to parse: assimp's std::bad_alloc surfaces as a malformed file */
    tiny.address_space_bytes = 24u << 20;
    o = run(real_jail, &tiny, bunny, len, "obj");
    test_check(o.status == LUCENT_E_MESH || o.status == LUCENT_E_LIMIT,
               "bunny in 24 MiB of address space: %s: %s (%.2f s)", lucent_status_name(o.status), o.err.message,
               o.seconds);
    free(bunny);
}

/* ---- the inputs assimp-hazards.md lists, and other garbage ---- */

static void check_hostile(void)
{
    static const char garbage[] = "\x01\x02\x03 this is not a mesh \xff\xfe";
    expect_failure("garbage as OBJ", run(real_jail, &LIMITS, garbage, sizeof garbage - 1, "obj"), LUCENT_E_MESH,
                   "could not read");
    expect_failure("garbage as GLB", run(real_jail, &LIMITS, garbage, sizeof garbage - 1, "glb"), LUCENT_E_MESH,
                   "not a valid binary glTF");
    expect_failure("garbage as STL", run(real_jail, &LIMITS, garbage, sizeof garbage - 1, "stl"), LUCENT_E_MESH,
                   "not a valid STL");
    expect_failure("empty upload", run(real_jail, &LIMITS, "", 0, "obj"), LUCENT_E_MESH, "empty");
    static const char vertices_only[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    outcome o = run(real_jail, &LIMITS, vertices_only, strlen(vertices_only), "obj");
    test_check(o.status == LUCENT_E_MESH && strcmp(o.err.field, "mesh") == 0,
               "OBJ without faces: %s, field \"%s\": %s", lucent_status_name(o.status), o.err.field, o.err.message);

    static const char ply_open[] = "ply\nformat ascii 1.0\n";
    expect_failure("PLY header without end_header (assimp loops forever)",
                   run(real_jail, &LIMITS, ply_open, strlen(ply_open), "ply"), LUCENT_E_MESH, "end_header");
    /* before, at lucentd's default 2 GiB: 1 GB and 8 CPU seconds, then a crash */
    static const char ply_bomb[] = "ply\nformat ascii 1.0\nelement vertex 80000000\nproperty float x\n"
                                   "property float y\nproperty float z\nelement face 1\n"
                                   "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    expect_failure("PLY declaring 80 million vertices in 187 bytes",
                   run(real_jail, &LIMITS, ply_bomb, strlen(ply_bomb), "ply"), LUCENT_E_MESH,
                   "declares more elements");
    static const char ply_cut[] = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                  "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1";
    o = run(real_jail, &LIMITS, ply_cut, strlen(ply_cut), "ply");
    test_check(o.status == LUCENT_OK || o.status == LUCENT_E_MESH,
               "truncated ASCII PLY (assimp asserts): %s: %s", lucent_status_name(o.status), o.err.message);
    static const char mtllib[] = "mtllib /etc/passwd\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    o = run(real_jail, &LIMITS, mtllib, strlen(mtllib), "obj");
    test_check((o.status == LUCENT_OK || o.status == LUCENT_E_MESH) && !strstr(o.err.message, "root:"),
               "OBJ with mtllib /etc/passwd: %s %s, nothing of the file quoted", lucent_status_name(o.status),
               o.err.message);
    static const char uri[] = "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"/etc/passwd\","
                              "\"byteLength\":12}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":12}],"
                              "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":1,\"type\":\"VEC3\"}],"
                              "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
                              "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]}";
    expect_failure("glTF buffer uri /etc/passwd", run(real_jail, &LIMITS, uri, strlen(uri), "gltf"), LUCENT_E_MESH,
                   "other files");
    expect_failure("unknown format", run(real_jail, &LIMITS, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "fbx"),
                   LUCENT_E_INVALID, "unsupported");
}

/* ---- fuzzed glTF ---- */

/* One triangle, positions and indices in an embedded base64 buffer. */
static const char TRIANGLE_GLTF[] =
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":1},\"indices\":0}]}],"
    "\"buffers\":[{\"uri\":\"data:application/octet-stream;base64,AAABAAIAAAAAAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAAAAAACAPwAAAAA=\","
    "\"byteLength\":44}],"
    "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":6,\"target\":34963},"
    "{\"buffer\":0,\"byteOffset\":8,\"byteLength\":36,\"target\":34962}],"
    "\"accessors\":[{\"bufferView\":0,\"byteOffset\":0,\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\","
    "\"max\":[2],\"min\":[0]},{\"bufferView\":1,\"byteOffset\":0,\"componentType\":5126,\"count\":3,"
    "\"type\":\"VEC3\",\"max\":[1.0,1.0,0.0],\"min\":[0.0,0.0,0.0]}]}";

static uint64_t rng_state = 0x2545f4914f6cdd1dull;

static uint64_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

/* A mutation that keeps the JSON valid, so that assimp's glTF reader (not the JSON check in front of
 * it) meets the damage: hostile numbers for counts, offsets, lengths, component types and indices, and
 * random base64 characters in the embedded buffer (changing the indices and coordinates). */
static size_t mutate_gltf(char *out, size_t cap)
{
    static const char *const numbers[] = {"0", "1", "3", "-1", "44", "45", "255", "65535", "2147483647",
                                          "4294967295", "18446744073709551615", "1e308", "-1e308", "0.5",
                                          "5120", "5121", "5125", "5126", "34962", "34963"};
    static const char base64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char *src = TRIANGLE_GLTF, *payload = strstr(TRIANGLE_GLTF, "base64,") + 7;
    size_t n = 0, payload_len = strcspn(payload, "=\"");
    int in_string = 0; /* about one number and two base64 characters changed a file */
    for (const char *p = src; *p && n + 32 < cap;) {
        if (p >= payload && p < payload + payload_len && rng() % 30 == 0) {
            out[n++] = base64[rng() % 64];
            p++;
        } else if (!in_string && (*p == '-' || (*p >= '0' && *p <= '9')) && rng() % 40 == 0) {
            const char *value = numbers[rng() % (sizeof numbers / sizeof numbers[0])];
            memcpy(out + n, value, strlen(value));
            n += strlen(value);
            p += strspn(p, "-+.eE0123456789");
        } else {
            in_string ^= *p == '"';
            out[n++] = *p++;
        }
    }
    return n;
}

static void check_fuzzed_gltf(void)
{
    enum { ROUNDS = 200 };
    size_t len = strlen(TRIANGLE_GLTF);
    outcome o = run(real_jail, &LIMITS, TRIANGLE_GLTF, len, "gltf");
    if (!test_check(o.status == LUCENT_OK && o.info.triangles == 1, "the unfuzzed glTF triangle imports: %s %s",
                    lucent_status_name(o.status), o.err.message))
        return;
    char copy[2 * sizeof TRIANGLE_GLTF];
    int counts[LUCENT_E_INTERNAL + 1] = {0}, crashes = 0, timeouts = 0;
    double total = 0;
    for (int round = 0; round < ROUNDS; round++) {
        size_t n = mutate_gltf(copy, sizeof copy);
        if (round % 4 == 3) /* every fourth one truncated as well */
            n = rng() % n;
        o = run(real_jail, &LIMITS, copy, n, "gltf");
        total += o.seconds;
        counts[o.status]++;
        crashes += strstr(o.err.message, "crashed") != NULL;
        timeouts += strstr(o.err.message, "longer than") != NULL;
        if (o.status != LUCENT_OK && o.status != LUCENT_E_MESH && o.status != LUCENT_E_LIMIT)
            printf("     round %d: %s: %s\n", round, lucent_status_name(o.status), o.err.message);
    }
    test_check(counts[LUCENT_OK] + counts[LUCENT_E_MESH] + counts[LUCENT_E_LIMIT] == ROUNDS,
               "%d glTF files with hostile numbers and buffer bytes: %d imported, %d refused as bad meshes (%d of "
               "them importer crashes, %d timeouts), %d over a limit, %d other; %.3f s per import",
               ROUNDS, counts[LUCENT_OK], counts[LUCENT_E_MESH], crashes, timeouts, counts[LUCENT_E_LIMIT],
               ROUNDS - counts[LUCENT_OK] - counts[LUCENT_E_MESH] - counts[LUCENT_E_LIMIT], total / ROUNDS);
}

/* ---- importers that misbehave ---- */

static void check_misbehaving(const char *bunny_path)
{
    size_t len = 0;
    unsigned char *big = read_file(bunny_path, &len); /* more than a pipe holds: writes must not block */
    struct import_limits lim = LIMITS;
    lim.wall_seconds = 1;
    lim.cpu_seconds = 1;

    expect_failure("importer raising SIGSEGV without reading past its first line",
                   run_as(hostile_jail, "crash", &LIMITS, big, len), LUCENT_E_MESH, "crashed (signal 11)");
    outcome o = run_as(hostile_jail, "hang", &lim, big, len);
    expect_failure("importer sleeping, wall limit 1 s", o, LUCENT_E_MESH, "longer than 1 s");
    /* The message says the wall limit stopped it. It would sleep 60 s, so under 10 s means it was killed,
     * with room for a busy machine; and not before the limit. */
    test_check(o.seconds >= 1 && o.seconds < 10,
               "stopped after %.2f s wall, %.2f s CPU (wall limit 1 s; it sleeps 60 s)", o.seconds, o.cpu_seconds);
    lim.wall_seconds = 20;
    o = run_as(hostile_jail, "spin", &lim, NULL, 0);
    expect_failure("importer spinning, CPU limit 1 s", o, LUCENT_E_MESH, "CPU time");
    /* The message says SIGXCPU (the soft CPU limit) ended it, before the 20 s wall limit however slowly it got
     * the CPU. Its own CPU clock, which load does not stretch, shows the signal came at the 1 s soft limit
     * (measured 0.95-1.00 s) and not at 2 s, the hard limit. */
    test_check(o.cpu_seconds >= 0.5 && o.cpu_seconds < 1.5, "stopped after %.2f s CPU (limit 1 s), %.2f s wall",
               o.cpu_seconds, o.seconds);
    expect_failure("importer answering nonsense", run_as(hostile_jail, "garbage", &LIMITS, NULL, 0),
                   LUCENT_E_INTERNAL, "not understood");
    struct import_jail *missing = NULL;
    outcome none = {.status = import_jail_open("/nonexistent/lucent-import", NULL, &missing, &none.err)};
    expect_failure("importer that does not exist", none, LUCENT_E_INTERNAL, "cannot open");
    struct import_limits zero = LIMITS;
    zero.wall_seconds = 0;
    expect_failure("a zero limit", run(real_jail, &zero, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj"),
                   LUCENT_E_INTERNAL, "positive");
    free(big);
}

/* ---- an importer that tries to escape ---- */

/* What the jail alone gives the importer, seen from inside by the unsealed escape tool. */
static void check_jail(void)
{
    const char *user = import_jail_user(hostile_jail);
    unsigned uid = (unsigned)getuid();
    if (user[0]) {
        struct passwd *pw = getpwnam(user);
        uid = pw ? (unsigned)pw->pw_uid : 0;
    }
    /* with a network namespace there is no loopback to reach; without one, nothing listens on port 9 */
    const char *net = strstr(import_jail_namespaces(hostile_jail), "net") ? "ENETUNREACH" : "ECONNREFUSED";
    char want[256];
    snprintf(want, sizeof want, "env=0 fds=0,1,2,3,4 uid=%u pgrp=own nnp=1 fork=EAGAIN connect=%s cwd=/", uid, net);
    outcome o = run_as(hostile_jail, "jail", &LIMITS, NULL, 0);
    test_check(o.status == LUCENT_E_INVALID && strcmp(o.err.message, want) == 0,
               "inside the jail (%s): %s (want %s)", import_jail_describe(hostile_jail), o.err.message, want);
}

/* Each thing an exploited importer would do next, after sealing itself: each must kill it, and count. */
static void check_escapes(void)
{
    static const char *const attempts[] = {"open", "connect", "fork", "signal", "exec", "mmap-exec"};
    const size_t n = sizeof attempts / sizeof attempts[0];
    uint64_t before = mesh_import_violations();
    for (size_t i = 0; i < n; i++)
        expect_failure(attempts[i], run_as(hostile_jail, attempts[i], &LIMITS, NULL, 0), LUCENT_E_MESH,
                       "stopped by its sandbox");
    uint64_t counted = mesh_import_violations() - before;
    test_check(counted == n, "sandbox violations counted: %llu of %zu", (unsigned long long)counted, n);

    /* an importer that writes one mesh and describes another, or writes garbage */
    outcome o = run(real_jail, &LIMITS, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj");
    size_t len = 0;
    unsigned char *lmesh = o.status == LUCENT_OK ? read_file(out_path, &len) : NULL;
    if (!test_check(lmesh != NULL, "a triangle's compact form to lie about (%zu bytes)", len))
        return;
    expect_failure("importer whose answer does not match its mesh", run_as(hostile_jail, "lie", &LIMITS, lmesh, len),
                   LUCENT_E_MESH, "does not describe the mesh it wrote");
    memset(lmesh + 56, 0x7f, len - 64); /* NaNs where the numbers were */
    expect_failure("importer writing a damaged mesh", run_as(hostile_jail, "lie", &LIMITS, lmesh, len), LUCENT_E_MESH,
                   "failed the daemon's check");
    free(lmesh);
}

/* ---- format sniffing ---- */

static void check_sniff(void)
{
    static const unsigned char binary_stl[84 + 50] = {[80] = 1};
    static const struct {
        const char *type, *bytes;
        size_t len;
        const char *expected;
    } cases[] = {
        {"model/obj", "anything", 8, "obj"},
        {"model/obj; charset=utf-8", "", 0, "obj"},
        {"MODEL/GLTF-BINARY", "", 0, "glb"},
        {"model/gltf+json", "", 0, "gltf"},
        {"application/sla", "", 0, "stl"},
        {"model/stl", "", 0, "stl"},
        {"application/ply", "", 0, "ply"},
        /* a type that is no mesh type lets the bytes decide (legacy application/x-ply, mislabelled files) */
        {"image/png", "glTF", 4, "glb"},
        {"application/json", "{}", 2, "gltf"},
        {"application/x-ply", "ply\nformat ascii 1.0\n", 21, "ply"},
        {"image/png", "hello", 5, NULL},
        /* a mesh type the bytes contradict */
        {"model/obj", "ply\nformat ascii 1.0\n", 21, NULL},
        {"model/gltf+json", "glTF\x02\0\0\0", 8, NULL},
        {"model/stl", "ply\r\n", 5, NULL},
        {"model/stl", "solid x\n", 8, "stl"},
        {"application/octet-stream", "glTF\x02\0\0\0", 8, "glb"},
        {"application/octet-stream", "ply\nformat ascii 1.0\n", 21, "ply"},
        {"application/octet-stream", "solid cube\n", 11, "stl"},
        {"application/octet-stream", (const char *)binary_stl, sizeof binary_stl, "stl"},
        {"application/octet-stream", "\xef\xbb\xbf  {\"asset\":{}}", 18, "gltf"},
        {"text/plain", "# exported\n\nv 1 2 3\n", 20, "obj"},
        {"", "o cube\nv 0 0 0\n", 15, "obj"},
        {NULL, TRIANGLE_OBJ, sizeof TRIANGLE_OBJ - 1, "obj"},
        {NULL, "hello world\n", 12, NULL},
        {NULL, "", 0, NULL},
        {NULL, "vertex 1 2 3\n", 13, NULL},
    };
    int right = 0, n = (int)(sizeof cases / sizeof cases[0]);
    for (int i = 0; i < n; i++) {
        const char *got = mesh_format_sniff(cases[i].type, cases[i].bytes, cases[i].len);
        int ok = (!got && !cases[i].expected) || (got && cases[i].expected && strcmp(got, cases[i].expected) == 0);
        if (!ok)
            printf("     sniff(%s, \"%.12s\"): %s, expected %s\n", cases[i].type ? cases[i].type : "NULL",
                   cases[i].bytes, got ? got : "NULL", cases[i].expected ? cases[i].expected : "NULL");
        right += ok;
    }
    test_check(right == n, "mesh_format_sniff: %d of %d Content-Type/first-bytes cases named right", right, n);
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: %s LUCENT_IMPORT HOSTILE_IMPORTER BUNNY_OBJ\n", argv[0]);
        return 2;
    }
    /* as lucentd: a dedicated user when root */
    const char *user = geteuid() == 0 ? "nobody" : NULL;
    lucent_error err = {0};
    if (import_jail_open(argv[1], user, &real_jail, &err) != LUCENT_OK ||
        import_jail_open(argv[2], user, &hostile_jail, &err) != LUCENT_OK) {
        fprintf(stderr, "cannot set up the import jails: %s\n", err.message);
        return 1;
    }
    printf("     jail: %s\n", import_jail_describe(real_jail));
    unlimited_address_space = getenv("LUCENT_TEST_UNLIMITED_ADDRESS_SPACE") != NULL;
    if (unlimited_address_space)
        LIMITS.address_space_bytes = SIZE_MAX;
    snprintf(out_path, sizeof out_path, "/tmp/lucent_sandbox_%ld.lmesh", (long)getpid());
    check_sniff();
    check_valid(argv[3]);
    check_hostile();
    check_fuzzed_gltf();
    check_misbehaving(argv[3]);
    check_jail();
    check_escapes();
    unlink(out_path);
    import_jail_close(real_jail);
    import_jail_close(hostile_jail);
    return test_finish();
}
