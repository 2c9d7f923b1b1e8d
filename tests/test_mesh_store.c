/* test_mesh_store.c - the content-addressed mesh store: ids, idempotent puts, reopening, deleting, the
 * byte budget, clean-up of interrupted writes, hostile ids, concurrent puts and several processes
 * sharing one store.
 * Usage: test_mesh_store LUCENT_IMPORT */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#endif

#include "lucent.h"
#include "import_jail.h"
#include "mesh_store.h"
#include "store_lock.h"
#include "test_support.h"

#include <dirent.h>
#include <limits.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const char *import_tool;
static struct import_jail *jail; /* the one open_store gives its stores */
static struct import_limits LIMITS = {512u << 20, 10, 20, LUCENT_MAX_TRIANGLES};

static const char TRIANGLE_OBJ[] = "v 10 0 0\nv 11 0 0\nv 10 1 0\nf 1 2 3\n";
/* sha256sum of TRIANGLE_OBJ, computed outside this program */
static const char TRIANGLE_ID[] = "85569efac4ffb2e92d00a8e1cb0b0899ceb2bf156ab7c12ce7e7fb2f8dd52f46";
static const char QUAD_OBJ[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

static double seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void make_dir(char *path)
{
    strcpy(path, "/tmp/lucent_store_XXXXXX");
    if (!mkdtemp(path)) {
        perror("mkdtemp");
        exit(1);
    }
}

/* Number of directory entries (besides . and ..); how many start with prefix when it is not NULL. */
/* Files in the store but its MAC key and lock file (store.key, store.lock), which every store has. */
static int count_files(const char *dir, const char *prefix)
{
    int n = 0;
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d));)
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && strcmp(e->d_name, "store.key") &&
             strcmp(e->d_name, "store.lock") &&
             (!prefix || strncmp(e->d_name, prefix, strlen(prefix)) == 0);
    if (d)
        closedir(d);
    return n;
}

static void remove_dir(const char *dir)
{
    char path[PATH_MAX];
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d));)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            unlink(path);
        }
    if (d)
        closedir(d);
    rmdir(dir);
}

static int file_exists(const char *dir, const char *name)
{
    char path[PATH_MAX];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &st) == 0;
}

static void write_file(const char *dir, const char *name, const char *text)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static struct mesh_store *open_store(const char *dir, uint64_t budget)
{
    struct mesh_store *s = NULL;
    lucent_error err = {0};
    lucent_status st = mesh_store_open(dir, budget, NULL, jail, &LIMITS, &s, &err);
    if (!test_check(st == LUCENT_OK, "open %s with a %llu-byte budget: %s %s", dir, (unsigned long long)budget,
                    lucent_status_name(st), err.message))
        exit(test_finish());
    return s;
}

/* ---- put, get, reopen, delete ---- */

static void check_lifecycle(void)
{
    char dir[64], id[65], id2[65], quad_id[65], path[PATH_MAX], name[128];
    struct mesh_info info, again, got;
    lucent_error err = {0};
    int created = -1;
    make_dir(dir);
    struct mesh_store *s = open_store(dir, 1 << 20);

    double t0 = seconds();
    lucent_status st = mesh_store_put(s, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj", id, &info, &created, &err);
    double t1 = seconds();
    test_check(st == LUCENT_OK && created == 1 && strcmp(id, TRIANGLE_ID) == 0 && info.triangles == 1 &&
                   info.bytes == strlen(TRIANGLE_OBJ) && info.created > 0 && info.bounds_min[0] == 10,
               "put triangle OBJ: %s, created %d, id %s (sha256 of the bytes: %s), %u triangles, %.3f s %s",
               lucent_status_name(st), created, id, strcmp(id, TRIANGLE_ID) == 0 ? "yes" : "no", info.triangles,
               t1 - t0, err.message);
    int64_t triangle_created = info.created;
    uint64_t one = mesh_store_bytes(s);
    snprintf(name, sizeof name, "%s.lmesh", id);
    int has_mesh = file_exists(dir, name);
    snprintf(name, sizeof name, "%s.json", id);
    test_check(has_mesh && file_exists(dir, name) && count_files(dir, NULL) == 2 && one > 0,
               "on disk: <id>.lmesh and <id>.json, nothing else; the store counts %llu bytes",
               (unsigned long long)one);

    t0 = seconds();
    st = mesh_store_put(s, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj", id2, &again, &created, &err);
    t1 = seconds();
    test_check(st == LUCENT_OK && created == 0 && strcmp(id, id2) == 0 && again.created == info.created &&
                   mesh_store_bytes(s) == one && count_files(dir, NULL) == 2,
               "the same bytes again: %s, created %d, same id, nothing written, %.4f s", lucent_status_name(st),
               created, t1 - t0);

    st = mesh_store_get(s, id, &got, path, sizeof path, &err);
    lucent_mesh *m = NULL;
    lucent_status loaded = st == LUCENT_OK ? lucent_mesh_import_file(path, &m, &err) : st;
    test_check(st == LUCENT_OK && got.triangles == 1 && loaded == LUCENT_OK && lucent_mesh_triangle_count(m) == 1,
               "get: %s -> %s, which the renderer loads (%u triangle) %s", lucent_status_name(st), path,
               lucent_mesh_triangle_count(m), err.message);
    lucent_mesh_free(m);

    const char *sniffed = mesh_upload_format(NULL, QUAD_OBJ, strlen(QUAD_OBJ), &err);
    st = mesh_store_put(s, QUAD_OBJ, strlen(QUAD_OBJ), sniffed ? sniffed : "none", quad_id, &info, &created, &err);
    test_check(st == LUCENT_OK && created == 1 && info.triangles == 2,
               "put a quad without a Content-Type (sniffed: %s): %s, %u triangles", sniffed ? sniffed : "nothing",
               lucent_status_name(st), info.triangles);
    uint64_t two = mesh_store_bytes(s);

    static const char no_faces[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    st = mesh_store_put(s, no_faces, strlen(no_faces), "obj", id2, &info, &created, &err);
    test_check(st == LUCENT_E_MESH && count_files(dir, NULL) == 4, "OBJ without faces: %s (%s), no file left",
               lucent_status_name(st), err.message);
    err = (lucent_error){0};
    sniffed = mesh_upload_format("model/ply", TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), &err);
    test_check(!sniffed && err.status == LUCENT_E_INVALID && strcmp(err.field, "Content-Type") == 0 &&
                   strstr(err.message, "says ply") && strstr(err.message, "are obj"),
               "OBJ bytes declared model/ply: %s, field \"%s\": %s", lucent_status_name(err.status), err.field,
               err.message);
    err = (lucent_error){0};
    sniffed = mesh_upload_format("application/octet-stream", "hello", 5, &err);
    test_check(!sniffed && err.status == LUCENT_E_INVALID && strcmp(err.field, "Content-Type") == 0,
               "unrecognizable bytes as application/octet-stream: %s, field \"%s\"", lucent_status_name(err.status),
               err.field);
    st = mesh_store_put(s, "hello", 5, "docx", id2, &info, &created, &err);
    test_check(st == LUCENT_E_INVALID && strcmp(err.field, "Content-Type") == 0,
               "a format the importer does not know: %s, field \"%s\"", lucent_status_name(st), err.field);

    /* an interrupted put, an interrupted delete, damaged metadata, and someone else's file */
    mesh_store_close(s);
    const char *orphan = "00000000000000000000000000000000000000000000000000000000000000aa";
    const char *lone = "00000000000000000000000000000000000000000000000000000000000000bb";
    const char *damaged = "00000000000000000000000000000000000000000000000000000000000000cc";
    write_file(dir, ".tmp-Ab12Cd", "half a mesh");
    snprintf(name, sizeof name, "%s.lmesh", orphan);
    write_file(dir, name, "a mesh whose metadata never arrived");
    snprintf(name, sizeof name, "%s.json", lone);
    write_file(dir, name, "{\"id\":\"...\"");
    snprintf(name, sizeof name, "%s.lmesh", damaged);
    write_file(dir, name, "a mesh");
    snprintf(name, sizeof name, "%s.json", damaged);
    write_file(dir, name, "{\"triangles\": \"many\"}");
    write_file(dir, "notes.txt", "not the store's");
    s = open_store(dir, 1 << 20);
    st = mesh_store_get(s, id, &got, path, sizeof path, &err);
    lucent_status st2 = mesh_store_get(s, quad_id, &again, path, sizeof path, &err);
    test_check(st == LUCENT_OK && st2 == LUCENT_OK && got.triangles == 1 && got.created == triangle_created &&
                   again.triangles == 2 && mesh_store_bytes(s) == two,
               "reopened: both meshes are there with their metadata (%s, %s), %llu bytes as before",
               lucent_status_name(st), lucent_status_name(st2), (unsigned long long)mesh_store_bytes(s));
    test_check(count_files(dir, ".tmp-") == 0 && count_files(dir, "00000") == 0 && count_files(dir, NULL) == 5 &&
                   file_exists(dir, "notes.txt"),
               "reopened: the temporary file, the orphan mesh, the lone and the damaged metadata are gone, "
               "notes.txt is kept (%d files)", count_files(dir, NULL));

    st = mesh_store_delete(s, id, &err);
    st2 = mesh_store_get(s, id, &got, path, sizeof path, &err);
    test_check(st == LUCENT_OK && st2 == LUCENT_E_INVALID && strcmp(err.field, "mesh.id") == 0 &&
                   strstr(err.message, "no mesh with id") && mesh_store_bytes(s) == two - one &&
                   count_files(dir, NULL) == 3,
               "delete: %s; then get: %s \"%s\"; %llu bytes left", lucent_status_name(st), lucent_status_name(st2),
               err.message, (unsigned long long)mesh_store_bytes(s));
    st = mesh_store_delete(s, id, &err);
    test_check(st == LUCENT_E_INVALID && strstr(err.message, "no mesh with id"), "delete again: %s",
               lucent_status_name(st));
    mesh_store_close(s);
    s = open_store(dir, 1 << 20);
    test_check(mesh_store_get(s, id, &got, path, sizeof path, &err) == LUCENT_E_INVALID &&
                   mesh_store_bytes(s) == two - one,
               "reopened after the delete: still gone");
    mesh_store_close(s);
    remove_dir(dir);
}

/* ---- ids ---- */

static void check_ids(void)
{
    char dir[64], path[PATH_MAX], upper[65];
    make_dir(dir);
    struct mesh_store *s = open_store(dir, 1 << 20);
    for (int i = 0; i < 64; i++)
        upper[i] = (char)(TRIANGLE_ID[i] >= 'a' ? TRIANGLE_ID[i] - 32 : TRIANGLE_ID[i]);
    upper[64] = '\0';
    const char *hostile[] = {"../x", upper, "85569efac4ffb2e92d00a8e1cb0b0899", "",
                             "85569efac4ffb2e92d00a8e1cb0b0899ceb2bf156ab7c12ce7e7fb2f8dd52f460",
                             "85569efac4ffb2e92d00a8e1cb0b0899ceb2bf156ab7c12ce7e7fb2f8dd52f4/",
                             "../../../../../../../../../../../../../../../../../../../etc/passwd",
                             "85569efac4ffb2e92d00a8e1cb0b0899ceb2bf156ab7c12ce7e7fb2f8dd52f4g"};
    int refused = 0, n = (int)(sizeof hostile / sizeof hostile[0]);
    for (int i = 0; i < n; i++) {
        lucent_error e1 = {0}, e2 = {0};
        lucent_status g = mesh_store_get(s, hostile[i], NULL, path, sizeof path, &e1);
        lucent_status d = mesh_store_delete(s, hostile[i], &e2);
        int ok = !mesh_id_valid(hostile[i]) && g == LUCENT_E_INVALID && d == LUCENT_E_INVALID &&
                 strcmp(e1.field, "mesh.id") == 0 && strstr(e1.message, "64 lowercase");
        if (!ok)
            printf("     id \"%s\" was not refused: %s %s\n", hostile[i], lucent_status_name(g), e1.message);
        refused += ok;
    }
    test_check(refused == n && mesh_id_valid(TRIANGLE_ID) && !mesh_id_valid(upper),
               "%d of %d hostile ids (\"../x\", upper case, short, long, empty, slash, traversal, non-hex) refused "
               "by get and delete with field mesh.id", refused, n);
    mesh_store_close(s);
    remove_dir(dir);
}

/* ---- the budget ---- */

static void check_budget(void)
{
    char dir[64], id[65];
    struct mesh_info info;
    lucent_error err = {0};
    int created;
    make_dir(dir);
    struct mesh_store *probe = open_store(dir, 1 << 20);
    lucent_status st = mesh_store_put(probe, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj", id, &info, &created, &err);
    uint64_t one = mesh_store_bytes(probe);
    test_check(st == LUCENT_OK, "one triangle takes %llu bytes of the store", (unsigned long long)one);
    mesh_store_close(probe);
    remove_dir(dir);

    /* room for two meshes: a third evicts the least recently used */
    static const char wider[] = "v 10 0 0\nv 12 0 0\nv 10 1 0\nf 1 2 3\n";
    char a[65], b[65], c[65], path[PATH_MAX];
    make_dir(dir);
    uint64_t budget = 2 * one + one / 2;
    struct mesh_store *s = open_store(dir, budget);
    lucent_status sa = mesh_store_put(s, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj", a, &info, &created, &err);
    lucent_status sb = mesh_store_put(s, wider, strlen(wider), "obj", b, &info, &created, &err);
    lucent_status ga = mesh_store_get(s, a, &info, path, sizeof path, &err); /* A is now the more recent */
    lucent_status sc = mesh_store_put(s, QUAD_OBJ, strlen(QUAD_OBJ), "obj", c, &info, &created, &err);
    lucent_status gb = mesh_store_get(s, b, &info, path, sizeof path, &err);
    lucent_status ga2 = mesh_store_get(s, a, &info, path, sizeof path, &err);
    lucent_status gc = mesh_store_get(s, c, &info, path, sizeof path, &err);
    test_check(sa == LUCENT_OK && sb == LUCENT_OK && ga == LUCENT_OK && sc == LUCENT_OK && gb == LUCENT_E_INVALID &&
                   ga2 == LUCENT_OK && gc == LUCENT_OK && mesh_store_bytes(s) <= budget && count_files(dir, NULL) == 4,
               "A, B, a get of A, then C in a %llu-byte budget: B, the least recently used, evicted (%s); A (%s) and "
               "C (%s) kept, %llu bytes in %d files", (unsigned long long)budget, lucent_status_name(gb),
               lucent_status_name(ga2), lucent_status_name(gc), (unsigned long long)mesh_store_bytes(s),
               count_files(dir, NULL));
    mesh_store_close(s);
    remove_dir(dir);

    /* a mesh larger than the whole budget is refused, and evicts nothing */
    make_dir(dir);
    s = open_store(dir, one);
    sa = mesh_store_put(s, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj", a, &info, &created, &err);
    sc = mesh_store_put(s, QUAD_OBJ, strlen(QUAD_OBJ), "obj", c, &info, &created, &err);
    test_check(sa == LUCENT_OK && sc == LUCENT_E_LIMIT && strstr(err.message, "whole budget") &&
                   mesh_store_bytes(s) == one,
               "a mesh larger than the whole budget: %s \"%s\"; the stored one stays (%llu bytes)",
               lucent_status_name(sc), err.message, (unsigned long long)mesh_store_bytes(s));
    mesh_store_close(s);
    remove_dir(dir);
}

/* ---- concurrency ---- */

typedef struct putter {
    struct mesh_store *store;
    const char *bytes;
    char id[65];
    int created;
    lucent_status status;
} putter;

static void *put_thread(void *arg)
{
    putter *p = arg;
    struct mesh_info info;
    lucent_error err = {0};
    p->status = mesh_store_put(p->store, p->bytes, strlen(p->bytes), "obj", p->id, &info, &p->created, &err);
    if (p->status != LUCENT_OK)
        printf("     a put failed: %s\n", err.message);
    return NULL;
}

/* Runs four puts at once; returns how many created an entry, -1 if any failed. */
static int put_four(struct mesh_store *s, const char *const bytes[4], putter p[4])
{
    pthread_t threads[4];
    int created = 0;
    for (int i = 0; i < 4; i++) {
        p[i] = (putter){s, bytes[i], "", -1, LUCENT_E_INTERNAL};
        pthread_create(&threads[i], NULL, put_thread, &p[i]);
    }
    for (int i = 0; i < 4; i++)
        pthread_join(threads[i], NULL);
    for (int i = 0; i < 4; i++) {
        if (p[i].status != LUCENT_OK)
            return -1;
        created += p[i].created;
    }
    return created;
}

/* Lines in a file (0 when it is missing). */
static int count_lines(const char *path)
{
    FILE *f = fopen(path, "r");
    int n = 0, c;
    while (f && (c = fgetc(f)) != EOF)
        n += c == '\n';
    if (f)
        fclose(f);
    return n;
}

static void check_concurrency(void)
{
    char dir[64], tools[64];
    putter p[4];
    make_dir(dir);
    make_dir(tools);
    /* the importer behind a wrapper that counts its runs */
    char wrapper[PATH_MAX], runs[PATH_MAX];
    snprintf(wrapper, sizeof wrapper, "%s/count-import.sh", tools);
    snprintf(runs, sizeof runs, "%s/import-runs", tools);
    FILE *w = fopen(wrapper, "w");
    fprintf(w, "#!/bin/sh\necho run >> '%s'\nexec '%s' \"$@\"\n", runs, import_tool);
    fclose(w);
    chmod(wrapper, 0755);
    struct import_jail *real_jail = jail;
    lucent_error err = {0};
    if (!test_check(import_jail_open(wrapper, NULL, &jail, &err) == LUCENT_OK, "a jail for the counting wrapper %s",
                    err.message))
        return;
    struct import_jail *wrapper_jail = jail;
    struct mesh_store *s = open_store(dir, 1 << 20);
    jail = real_jail;
    const char *same[4] = {QUAD_OBJ, QUAD_OBJ, QUAD_OBJ, QUAD_OBJ};
    double t0 = seconds();
    int created = put_four(s, same, p);
    int same_id = strcmp(p[0].id, p[1].id) == 0 && strcmp(p[0].id, p[2].id) == 0 && strcmp(p[0].id, p[3].id) == 0;
    test_check(created == 1 && same_id && count_files(dir, NULL) == 2 && count_lines(runs) == 1,
               "4 threads put the same bytes: %d created, one id, %d files, the importer run %d time(s) (%.3f s)",
               created, count_files(dir, NULL), count_lines(runs), seconds() - t0);
    static const char a[] = "v 0 0 0\nv 2 0 0\nv 0 2 0\nf 1 2 3\n", b[] = "v 0 0 0\nv 3 0 0\nv 0 3 0\nf 1 2 3\n",
                      c[] = "v 0 0 0\nv 4 0 0\nv 0 4 0\nf 1 2 3\n";
    const char *distinct[4] = {a, b, c, QUAD_OBJ};
    uint64_t before = mesh_store_bytes(s);
    t0 = seconds();
    created = put_four(s, distinct, p);
    test_check(created == 3 && count_files(dir, NULL) == 8 && mesh_store_bytes(s) > before,
               "4 threads put 3 new meshes and the stored one: %d created, %d files, %llu bytes (%.3f s)", created,
               count_files(dir, NULL), (unsigned long long)mesh_store_bytes(s), seconds() - t0);
    uint64_t bytes = mesh_store_bytes(s);
    mesh_store_close(s);
    import_jail_close(wrapper_jail);
    s = open_store(dir, 1 << 20);
    test_check(mesh_store_bytes(s) == bytes, "reopened: %llu bytes, the same as counted in memory",
               (unsigned long long)mesh_store_bytes(s));
    mesh_store_close(s);
    remove_dir(dir);
    remove_dir(tools);
}

/* ---- integrity: a stored mesh changed on disk is never served ---- */

/* Copies the file src over dst in place (same inode, as an attacker writing into the store would). */
static void overwrite(const char *src, const char *dst)
{
    size_t len = 0;
    FILE *in = fopen(src, "rb"), *out = fopen(dst, "r+b");
    char buf[4096];
    if (in && out)
        while ((len = fread(buf, 1, sizeof buf, in)) > 0)
            fwrite(buf, 1, len, out);
    if (in)
        fclose(in);
    if (out)
        fclose(out);
}

static void check_integrity(void)
{
    char dir[64], a[65], b[65], path_a[PATH_MAX], path_b[PATH_MAX], key[PATH_MAX], other_key[PATH_MAX];
    struct mesh_info info;
    lucent_error err = {0};
    int created;
    struct stat st;
    make_dir(dir);
    struct mesh_store *s = open_store(dir, 1 << 20);
    snprintf(key, sizeof key, "%s/store.key", dir);
    int key_seen = stat(key, &st) == 0;
    test_check(key_seen && st.st_size == 32 && (st.st_mode & 0777) == 0600,
               "the store made its MAC key: %lld bytes, mode %o", (long long)st.st_size, st.st_mode & 0777);
    static const char same_size[] = "v 10 0 0\nv 12 0 0\nv 10 1 0\nf 1 2 3\n"; /* as TRIANGLE_OBJ, wider */
    lucent_status sa = mesh_store_put(s, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj", a, &info, &created, &err);
    lucent_status sb = mesh_store_put(s, same_size, strlen(same_size), "obj", b, &info, &created, &err);
    mesh_store_close(s);
    s = open_store(dir, 1 << 20);
    lucent_status ga = mesh_store_get(s, a, &info, path_a, sizeof path_a, &err);
    lucent_status gb = mesh_store_get(s, b, &info, path_b, sizeof path_b, &err);
    test_check(sa == LUCENT_OK && sb == LUCENT_OK && ga == LUCENT_OK && gb == LUCENT_OK,
               "two meshes stored, reopened and checked against their MACs with the same key: %s %s", a, b);

    /* B's compact file is a sound mesh with a valid checksum: only the MAC, which covers the id, tells */
    overwrite(path_b, path_a);
    lucent_status swapped = mesh_store_get(s, a, &info, path_a, sizeof path_a, &err);
    test_check(swapped == LUCENT_E_IO && strcmp(err.field, "mesh.id") == 0 && strstr(err.message, "integrity"),
               "another stored mesh copied over A's file: %s, field %s: %s", lucent_status_name(swapped), err.field,
               err.message);
    lucent_status again = mesh_store_get(s, a, &info, path_a, sizeof path_a, &err);
    test_check(again == LUCENT_E_INVALID && count_files(dir, NULL) == 2,
               "then A is gone (%s: %s), B's files stay (%d files)", lucent_status_name(again), err.message,
               count_files(dir, NULL));
    mesh_store_close(s);

    /* the same store under another key: nothing in it verifies */
    snprintf(other_key, sizeof other_key, "%s.other-key", dir);
    struct mesh_store *t = NULL;
    lucent_status opened = mesh_store_open(dir, 1 << 20, other_key, jail, &LIMITS, &t, &err);
    lucent_status under_other = opened == LUCENT_OK ? mesh_store_get(t, b, &info, path_b, sizeof path_b, &err) : opened;
    test_check(under_other == LUCENT_E_IO, "B read with another --store-key: %s: %s", lucent_status_name(under_other),
               err.message);
    mesh_store_close(t);
    unlink(other_key);

    chmod(key, 0644);
    t = NULL;
    opened = mesh_store_open(dir, 1 << 20, NULL, jail, &LIMITS, &t, &err);
    test_check(opened == LUCENT_E_IO && strcmp(err.field, "store-key") == 0,
               "a key other users may read is refused: %s, field %s: %s", lucent_status_name(opened), err.field,
               err.message);
    mesh_store_close(t);
    remove_dir(dir);
}

/* ---- several processes on one store (lucentd replicas on a shared volume) ---- */

/* A small mesh of its own for each n. */
static void numbered_obj(char *out, size_t cap, int n)
{
    snprintf(out, cap, "v %d 0 0\nv %d 0 0\nv %d 1 0\nf 1 2 3\n", 20 + n, 21 + n, 20 + n);
}

/* Opens the store in a child process and does one thing there: "put" (mesh text), "get" or "delete"
 * (an id), or "puts" (six numbered meshes from base). The child's exit status: 0 when it went as asked. */
static pid_t spawn(const char *dir, uint64_t budget, const char *what, const char *arg, int base)
{
    pid_t pid = fork();
    if (pid != 0)
        return pid;
    struct mesh_store *s = NULL;
    lucent_error err = {0};
    struct mesh_info info;
    char id[65], path[PATH_MAX], obj[128];
    int created, ok = mesh_store_open(dir, budget, NULL, jail, &LIMITS, &s, &err) == LUCENT_OK;
    if (ok && strcmp(what, "put") == 0)
        ok = mesh_store_put(s, arg, strlen(arg), "obj", id, &info, &created, &err) == LUCENT_OK;
    else if (ok && strcmp(what, "get") == 0)
        ok = mesh_store_get(s, arg, &info, path, sizeof path, &err) == LUCENT_OK;
    else if (ok && strcmp(what, "delete") == 0)
        ok = mesh_store_delete(s, arg, &err) == LUCENT_OK;
    for (int k = 0; ok && strcmp(what, "puts") == 0 && k < 6; k++) {
        numbered_obj(obj, sizeof obj, base + k);
        ok = mesh_store_put(s, obj, strlen(obj), "obj", id, &info, &created, &err) == LUCENT_OK;
    }
    if (!ok)
        fprintf(stderr, "child %s: %s\n", what, err.message);
    mesh_store_close(s);
    _exit(ok ? 0 : 1);
}

static int reap(pid_t pid)
{
    int status;
    return pid > 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static void check_sharing(void)
{
    char dir[64], path[PATH_MAX], id[65], a[65], b[65], c[65];
    struct mesh_info info;
    lucent_error err = {0};
    int created;
    make_dir(dir);
    struct mesh_store *s = open_store(dir, 1 << 20);
    int put = reap(spawn(dir, 1 << 20, "put", TRIANGLE_OBJ, 0));
    lucent_status got = mesh_store_get(s, TRIANGLE_ID, &info, path, sizeof path, &err);
    test_check(put == 0 && got == LUCENT_OK, "stored by another process after this one opened: child %d, get %s",
               put, lucent_status_name(got));
    int deleted = reap(spawn(dir, 1 << 20, "delete", TRIANGLE_ID, 0));
    got = mesh_store_get(s, TRIANGLE_ID, &info, path, sizeof path, &err);
    test_check(deleted == 0 && got == LUCENT_E_INVALID && strstr(err.message, "no mesh") && count_files(dir, NULL) == 0,
               "deleted by another process: child %d, then get %s \"%s\" (a 404, not a damaged mesh), %d files",
               deleted, lucent_status_name(got), err.message, count_files(dir, NULL));
    mesh_store_put(s, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj", id, &info, &created, &err);
    uint64_t one = mesh_store_bytes(s);
    mesh_store_close(s);
    remove_dir(dir);

    /* eviction follows uses in every process: another process's get of A keeps A over B */
    static const char wider[] = "v 10 0 0\nv 12 0 0\nv 10 1 0\nf 1 2 3\n";
    uint64_t budget = 2 * one + one / 2;
    make_dir(dir);
    s = open_store(dir, budget);
    mesh_store_put(s, TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "obj", a, &info, &created, &err);
    mesh_store_put(s, wider, strlen(wider), "obj", b, &info, &created, &err);
    int used = reap(spawn(dir, budget, "get", a, 0));
    lucent_status sc = mesh_store_put(s, QUAD_OBJ, strlen(QUAD_OBJ), "obj", c, &info, &created, &err);
    lucent_status ga = mesh_store_get(s, a, &info, path, sizeof path, &err);
    lucent_status gb = mesh_store_get(s, b, &info, path, sizeof path, &err);
    test_check(used == 0 && sc == LUCENT_OK && ga == LUCENT_OK && gb == LUCENT_E_INVALID,
               "A and B put here, A used by another process, then C: B evicted (%s), A kept (%s)",
               lucent_status_name(gb), lucent_status_name(ga));
    mesh_store_close(s);
    remove_dir(dir);

    /* four processes putting six meshes each at once into room for six: the budget holds and every entry
     * left is whole */
    budget = 6 * one + one / 2;
    make_dir(dir);
    pid_t writers[4];
    for (int w = 0; w < 4; w++)
        writers[w] = spawn(dir, budget, "puts", NULL, 10 * w);
    int failed = 0;
    for (int w = 0; w < 4; w++)
        failed += reap(writers[w]) != 0;
    s = open_store(dir, budget);
    uint64_t bytes = mesh_store_bytes(s);
    int entries = count_files(dir, NULL) / 2, whole = 0;
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d));)
        if (strlen(e->d_name) == 69 && strcmp(e->d_name + 64, ".json") == 0) {
            memcpy(id, e->d_name, 64);
            id[64] = '\0';
            whole += mesh_store_get(s, id, &info, path, sizeof path, &err) == LUCENT_OK;
        }
    if (d)
        closedir(d);
    test_check(failed == 0 && bytes <= budget && entries >= 1 && whole == entries && count_files(dir, ".tmp-") == 0 &&
                   count_files(dir, NULL) == 2 * entries,
               "4 processes x 6 puts at once into a %llu-byte budget: %d failed; %d entries of %llu bytes, %d whole, "
               "%d temporaries", (unsigned long long)budget, failed, entries, (unsigned long long)bytes, whole,
               count_files(dir, ".tmp-"));
    mesh_store_close(s);
    remove_dir(dir);

    /* a process opening the store leaves another's upload in progress alone, and cleans it up once that
     * process is gone */
    make_dir(dir);
    snprintf(path, sizeof path, "%s/.tmp-inflight", dir);
    int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0600);
    int claimed = fd >= 0 && store_claim_file(fd) == 0;
    int opened = reap(spawn(dir, 1 << 20, "open", NULL, 0));
    int kept = file_exists(dir, ".tmp-inflight");
    if (fd >= 0)
        close(fd);
    int reopened = reap(spawn(dir, 1 << 20, "open", NULL, 0));
    test_check(claimed && opened == 0 && kept && reopened == 0 && !file_exists(dir, ".tmp-inflight"),
               "a temporary another process still writes: kept by an opening store (%d); removed once released (%d)",
               kept, !file_exists(dir, ".tmp-inflight"));
    remove_dir(dir);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s LUCENT_IMPORT\n", argv[0]);
        return 2;
    }
    import_tool = argv[1];
    lucent_error err = {0};
    if (import_jail_open(import_tool, NULL, &jail, &err) != LUCENT_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    /* set by sanitizer builds: AddressSanitizer reserves terabytes of address space up front */
    if (getenv("LUCENT_TEST_UNLIMITED_ADDRESS_SPACE"))
        LIMITS.address_space_bytes = SIZE_MAX;
    check_lifecycle();
    check_ids();
    check_budget();
    check_concurrency();
    check_integrity();
    check_sharing();
    import_jail_close(jail);
    return test_finish();
}
