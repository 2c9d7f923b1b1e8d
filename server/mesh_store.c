/* mesh_store.c - the content-addressed mesh store (contract in mesh_store.h). Every file appears by
 * rename of an fsynced temporary; the metadata file is renamed last, so it marks a complete entry. */
#include "mesh_store.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <jansson.h>
#include <limits.h>
#include <math.h>
#include <openssl/evp.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define TEMP_PREFIX ".tmp-"
#define ID_LEN 64
#define NAME_SLACK 80 /* "/", an id, an extension, a temporary's suffix */

struct store_entry {
    char id[ID_LEN + 1];
    struct mesh_info info;
    uint64_t disk_bytes; /* both files */
};

/* Ids being imported now: a second put of the same bytes waits for the first instead of importing
 * them again (uploads at once run at most --max-imports, 64; past this many puts import unguarded). */
#define MAX_IMPORTING 64

struct mesh_store {
    pthread_mutex_t lock;
    pthread_cond_t imported;            /* an import of `importing` ended */
    char importing[MAX_IMPORTING][ID_LEN + 1];
    char *dir, *import_tool;
    struct import_limits lim;
    uint64_t budget, used;
    struct store_entry *entries;
    size_t count, cap;
};

int mesh_id_valid(const char *id)
{
    size_t n = 0;
    while (n < ID_LEN && ((id[n] >= '0' && id[n] <= '9') || (id[n] >= 'a' && id[n] <= 'f')))
        n++;
    return n == ID_LEN && id[n] == '\0';
}

static lucent_status check_id(const char *id, lucent_error *err)
{
    if (!id || !mesh_id_valid(id))
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.id",
                           "not a mesh id: ids are 64 lowercase hexadecimal digits (the upload's sha256)");
    return LUCENT_OK;
}

static lucent_status sha256_hex(const void *bytes, size_t len, char out[ID_LEN + 1], lucent_error *err)
{
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned int md_len = 0;
    if (EVP_Digest(bytes, len, md, &md_len, EVP_sha256(), NULL) != 1 || md_len != ID_LEN / 2)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "could not compute the sha256 of the upload");
    for (unsigned i = 0; i < md_len; i++)
        snprintf(out + 2 * i, 3, "%02x", md[i]);
    return LUCENT_OK;
}

static void entry_path(const struct mesh_store *s, const char *id, const char *ext, char path[PATH_MAX])
{
    snprintf(path, PATH_MAX, "%s/%s.%s", s->dir, id, ext);
}

/* The directory entry of a rename or unlink is durable only once the directory is synced. */
static int sync_dir(const char *dir)
{
    int fd = open(dir, O_RDONLY | O_DIRECTORY);
    int ok = fd >= 0 && fsync(fd) == 0;
    if (fd >= 0)
        close(fd);
    return ok;
}

static struct store_entry *index_find(struct mesh_store *s, const char *id)
{
    for (size_t i = 0; i < s->count; i++)
        if (strcmp(s->entries[i].id, id) == 0)
            return &s->entries[i];
    return NULL;
}

/* Makes room for one more entry, so that adding it after the files are in place cannot fail. */
static lucent_status index_reserve(struct mesh_store *s, lucent_error *err)
{
    if (s->count < s->cap)
        return LUCENT_OK;
    size_t cap = s->cap ? 2 * s->cap : 64;
    struct store_entry *grown = realloc(s->entries, cap * sizeof *grown);
    if (!grown)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory indexing the mesh store");
    s->entries = grown;
    s->cap = cap;
    return LUCENT_OK;
}

static void index_add(struct mesh_store *s, const char *id, const struct mesh_info *info, uint64_t disk_bytes)
{
    struct store_entry *e = &s->entries[s->count++];
    snprintf(e->id, sizeof e->id, "%s", id);
    e->info = *info;
    e->disk_bytes = disk_bytes;
    s->used += disk_bytes;
}

/* ---- metadata ---- */

static char *metadata_text(const char *id, const struct mesh_info *m)
{
    json_t *doc = json_pack("{s:s, s:I, s:I, s:{s:[fff], s:[fff]}, s:I, s:I}", "id", id, "triangles",
                            (json_int_t)m->triangles, "vertices", (json_int_t)m->vertices, "bounds", "min",
                            m->bounds_min[0], m->bounds_min[1], m->bounds_min[2], "max", m->bounds_max[0],
                            m->bounds_max[1], m->bounds_max[2], "bytes", (json_int_t)m->bytes, "created",
                            (json_int_t)m->created);
    char *text = doc ? json_dumps(doc, JSON_COMPACT | JSON_REAL_PRECISION(17)) : NULL;
    json_decref(doc);
    return text;
}

/* Reads <id>.json back; 0 when it is not exactly what metadata_text writes for this id. */
static int metadata_read(const char *path, const char *id, struct mesh_info *m)
{
    json_error_t jerr;
    const char *stored_id;
    json_int_t triangles, vertices, bytes, created;
    double *lo = m->bounds_min, *hi = m->bounds_max;
    json_t *doc = json_load_file(path, JSON_REJECT_DUPLICATES, &jerr);
    int ok = doc && json_unpack_ex(doc, &jerr, JSON_STRICT, "{s:s, s:I, s:I, s:{s:[FFF], s:[FFF]}, s:I, s:I}",
                                   "id", &stored_id, "triangles", &triangles, "vertices", &vertices, "bounds",
                                   "min", &lo[0], &lo[1], &lo[2], "max", &hi[0], &hi[1], &hi[2], "bytes", &bytes,
                                   "created", &created) == 0;
    ok = ok && strcmp(stored_id, id) == 0 && triangles >= 1 && triangles <= LUCENT_MAX_TRIANGLES &&
         vertices >= 1 && vertices <= 3 * triangles && bytes >= 0 && created >= 0;
    for (int k = 0; ok && k < 3; k++)
        ok = isfinite(lo[k]) && isfinite(hi[k]) && lo[k] <= hi[k];
    json_decref(doc);
    if (ok) {
        m->triangles = (uint32_t)triangles;
        m->vertices = (uint32_t)vertices;
        m->bytes = (uint64_t)bytes;
        m->created = (int64_t)created;
    }
    return ok;
}

/* ---- temporary files ---- */

static lucent_status make_temp(const struct mesh_store *s, char path[PATH_MAX], int *fd, lucent_error *err)
{
    snprintf(path, PATH_MAX, "%s/" TEMP_PREFIX "XXXXXX", s->dir);
    *fd = mkstemp(path);
    if (*fd < 0) {
        path[0] = '\0';
        return lucent_fail(err, lucent_io_status(errno), "", "cannot create a file in the mesh store: %s",
                           strerror(errno));
    }
    return LUCENT_OK;
}

static lucent_status write_all(int fd, const char *text, size_t len, lucent_error *err)
{
    while (len > 0) {
        ssize_t n = write(fd, text, len);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return lucent_fail(err, lucent_io_status(errno), "", "could not write to the mesh store: %s",
                               strerror(errno));
        text += n;
        len -= (size_t)n;
    }
    return LUCENT_OK;
}

/* Flushes a file to disk and returns its size. */
static lucent_status sync_file(int fd, uint64_t *size, lucent_error *err)
{
    struct stat st;
    if (fsync(fd) != 0 || fstat(fd, &st) != 0)
        return lucent_fail(err, lucent_io_status(errno), "", "could not flush the mesh store to disk: %s",
                           strerror(errno));
    *size = (uint64_t)st.st_size;
    return LUCENT_OK;
}

static lucent_status write_metadata(const struct mesh_store *s, const char *id, const struct mesh_info *info,
                                    char path[PATH_MAX], uint64_t *size, lucent_error *err)
{
    int fd;
    char *text = metadata_text(id, info);
    if (!text)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory writing mesh metadata");
    lucent_status st = make_temp(s, path, &fd, err);
    if (st == LUCENT_OK) {
        if ((st = write_all(fd, text, strlen(text), err)) == LUCENT_OK)
            st = sync_file(fd, size, err);
        close(fd);
    }
    free(text);
    return st;
}

/* ---- opening ---- */

/* Whether name is "<id>.<ext>"; copies the id. */
static int entry_name(const char *name, const char *ext, char id[ID_LEN + 1])
{
    if (strlen(name) != ID_LEN + 1 + strlen(ext) || name[ID_LEN] != '.' || strcmp(name + ID_LEN + 1, ext) != 0)
        return 0;
    memcpy(id, name, ID_LEN);
    id[ID_LEN] = '\0';
    return mesh_id_valid(id);
}

/* Indexes the entry <id>.json names; 0 when it is incomplete or damaged. */
static int index_existing(struct mesh_store *s, const char *id)
{
    char mesh_path[PATH_MAX], meta_path[PATH_MAX];
    struct stat mesh_st, meta_st;
    struct mesh_info info;
    entry_path(s, id, "lmesh", mesh_path);
    entry_path(s, id, "json", meta_path);
    if (stat(mesh_path, &mesh_st) != 0 || !S_ISREG(mesh_st.st_mode) || stat(meta_path, &meta_st) != 0 ||
        !metadata_read(meta_path, id, &info) || index_reserve(s, NULL) != LUCENT_OK)
        return 0;
    index_add(s, id, &info, (uint64_t)mesh_st.st_size + (uint64_t)meta_st.st_size);
    return 1;
}

static void remove_leftover(const struct mesh_store *s, const char *name, int *removed)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", s->dir, name);
    if (unlink(path) == 0) {
        fprintf(stderr, "lucent: mesh store: removed the unfinished or damaged file %s\n", path);
        (*removed)++;
    }
}

/* Two passes: metadata (and temporaries) first, then meshes that no metadata claimed. */
static lucent_status scan(struct mesh_store *s, lucent_error *err)
{
    char id[ID_LEN + 1];
    int removed = 0;
    DIR *d = opendir(s->dir);
    if (!d)
        return lucent_fail(err, LUCENT_E_IO, "", "cannot list the mesh store \"%s\": %s", s->dir, strerror(errno));
    for (struct dirent *e; (e = readdir(d));) {
        if (strncmp(e->d_name, TEMP_PREFIX, strlen(TEMP_PREFIX)) == 0)
            remove_leftover(s, e->d_name, &removed);
        else if (entry_name(e->d_name, "json", id) && !index_existing(s, id))
            remove_leftover(s, e->d_name, &removed);
    }
    rewinddir(d);
    for (struct dirent *e; (e = readdir(d));)
        if (entry_name(e->d_name, "lmesh", id) && !index_find(s, id))
            remove_leftover(s, e->d_name, &removed);
    closedir(d);
    if (removed > 0 && !sync_dir(s->dir))
        return lucent_fail(err, LUCENT_E_IO, "", "cannot sync the mesh store \"%s\": %s", s->dir, strerror(errno));
    return LUCENT_OK;
}

lucent_status mesh_store_open(const char *dir, uint64_t byte_budget, const char *import_tool,
                              const struct import_limits *lim, struct mesh_store **out, lucent_error *err)
{
    struct stat st;
    *out = NULL;
    if (strlen(dir) + NAME_SLACK >= PATH_MAX)
        return lucent_fail(err, LUCENT_E_INVALID, "", "the mesh store path is too long");
    if ((mkdir(dir, 0700) != 0 && errno != EEXIST) || stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return lucent_fail(err, LUCENT_E_IO, "", "cannot use \"%s\" as the mesh store directory: %s", dir,
                           strerror(errno));
    /* Uploads write here: a read-only store (a read-only mount, permissions) fails now, not at the first one. */
    if (access(dir, W_OK | X_OK) != 0)
        return lucent_fail(err, LUCENT_E_IO, "", "the mesh store directory \"%s\" is not writable: %s", dir,
                           strerror(errno));
    struct mesh_store *s = calloc(1, sizeof *s);
    if (!s)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory opening the mesh store");
    pthread_mutex_init(&s->lock, NULL);
    pthread_cond_init(&s->imported, NULL);
    s->budget = byte_budget;
    s->lim = *lim;
    s->dir = strdup(dir);
    s->import_tool = strdup(import_tool);
    lucent_status status = s->dir && s->import_tool
                               ? scan(s, err)
                               : lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory opening the mesh store");
    if (status != LUCENT_OK) {
        mesh_store_close(s);
        return status;
    }
    *out = s;
    return LUCENT_OK;
}

void mesh_store_close(struct mesh_store *s)
{
    if (!s)
        return;
    pthread_mutex_destroy(&s->lock);
    pthread_cond_destroy(&s->imported);
    free(s->entries);
    free(s->dir);
    free(s->import_tool);
    free(s);
}

/* ---- putting ---- */

/* needed = 0 when the store is full before the upload is even imported */
static lucent_status over_budget(const struct mesh_store *s, uint64_t needed, lucent_error *err)
{
    char need[64] = "";
    if (needed > 0)
        snprintf(need, sizeof need, " and this mesh needs %llu", (unsigned long long)needed);
    return lucent_fail(err, LUCENT_E_LIMIT, "mesh",
                       "the mesh store is full: it holds %llu of its %llu bytes%s; delete meshes to make room",
                       (unsigned long long)s->used, (unsigned long long)s->budget, need);
}

/* Moves both temporaries into place under the lock; clears their names once they are renamed. */
static lucent_status commit(struct mesh_store *s, const char *id, char *tmp_mesh, char *tmp_meta,
                            uint64_t disk_bytes, struct mesh_info *info, int *created, lucent_error *err)
{
    char mesh_path[PATH_MAX], meta_path[PATH_MAX];
    lucent_status st = LUCENT_OK;
    entry_path(s, id, "lmesh", mesh_path);
    entry_path(s, id, "json", meta_path);
    pthread_mutex_lock(&s->lock);
    const struct store_entry *existing = index_find(s, id);
    if (existing) { /* a concurrent put of the same bytes got here first */
        *info = existing->info;
        goto unlock;
    }
    if (s->used + disk_bytes > s->budget) {
        st = over_budget(s, disk_bytes, err);
        goto unlock;
    }
    if ((st = index_reserve(s, err)) != LUCENT_OK)
        goto unlock;
    if (rename(tmp_mesh, mesh_path) != 0) {
        st = lucent_fail(err, lucent_io_status(errno), "", "cannot store the mesh: %s", strerror(errno));
        goto unlock;
    }
    tmp_mesh[0] = '\0';
    if (rename(tmp_meta, meta_path) != 0) {
        st = lucent_fail(err, lucent_io_status(errno), "", "cannot store the mesh metadata: %s", strerror(errno));
        unlink(mesh_path);
        goto unlock;
    }
    tmp_meta[0] = '\0';
    index_add(s, id, info, disk_bytes);
    *created = 1;
    if (!sync_dir(s->dir)) /* the entry exists; only its durability is in doubt */
        st = lucent_fail(err, LUCENT_E_IO, "", "cannot sync the mesh store directory: %s", strerror(errno));
unlock:
    pthread_mutex_unlock(&s->lock);
    return st;
}

/* The slot of `importing` holding id ("" finds a free one), or -1. Called with the lock held. */
static int importing_slot(const struct mesh_store *s, const char *id)
{
    for (int i = 0; i < MAX_IMPORTING; i++)
        if (strcmp(s->importing[i], id) == 0)
            return i;
    return -1;
}

lucent_status mesh_store_put(struct mesh_store *s, const void *bytes, size_t len, const char *content_type,
                             char id_out[65], struct mesh_info *info, int *created, lucent_error *err)
{
    char tmp_mesh[PATH_MAX] = "", tmp_meta[PATH_MAX] = "";
    uint64_t mesh_bytes = 0, meta_bytes = 0;
    int fd = -1;
    lucent_status st;
    *created = 0;
    const char *ext = mesh_format_sniff(content_type, bytes, len);
    const char *declared = mesh_format_of_type(content_type), *sniffed = mesh_format_of_bytes(bytes, len);
    if (!ext && declared && sniffed)
        return lucent_fail(err, LUCENT_E_INVALID, "Content-Type",
                           "the Content-Type says %s but the bytes are %s: send the type of the file, or "
                           "application/octet-stream to have it recognized", declared, sniffed);
    if (!ext)
        return lucent_fail(err, LUCENT_E_INVALID, "Content-Type",
                           "not a mesh format Lucent reads: send OBJ, PLY, STL, glTF with embedded buffers or "
                           "GLB (Content-Type model/obj, model/ply, model/stl, model/gltf+json, "
                           "model/gltf-binary, or application/octet-stream to have it recognized)");
    if ((st = sha256_hex(bytes, len, id_out, err)) != LUCENT_OK)
        return st;

    pthread_mutex_lock(&s->lock);
    const struct store_entry *existing;
    int slot;
    while (!(existing = index_find(s, id_out)) && importing_slot(s, id_out) >= 0)
        pthread_cond_wait(&s->imported, &s->lock);
    if (existing)
        *info = existing->info;
    else if (s->used >= s->budget)
        st = over_budget(s, 0, err);
    slot = existing || st != LUCENT_OK ? -1 : importing_slot(s, "");
    if (slot >= 0)
        memcpy(s->importing[slot], id_out, ID_LEN + 1);
    pthread_mutex_unlock(&s->lock);
    if (existing || st != LUCENT_OK)
        return st;

    /* importing takes seconds: the lock is not held, so gets and other puts go on meanwhile */
    if ((st = make_temp(s, tmp_mesh, &fd, err)) != LUCENT_OK ||
        (st = mesh_import_isolated(s->import_tool, &s->lim, bytes, len, ext, tmp_mesh, info, err)) != LUCENT_OK ||
        (st = sync_file(fd, &mesh_bytes, err)) != LUCENT_OK)
        goto done;
    info->created = (int64_t)time(NULL);
    if ((st = write_metadata(s, id_out, info, tmp_meta, &meta_bytes, err)) != LUCENT_OK)
        goto done;
    st = commit(s, id_out, tmp_mesh, tmp_meta, mesh_bytes + meta_bytes, info, created, err);
done:
    if (fd >= 0)
        close(fd);
    if (tmp_mesh[0])
        unlink(tmp_mesh);
    if (tmp_meta[0])
        unlink(tmp_meta);
    if (slot >= 0) {
        pthread_mutex_lock(&s->lock);
        s->importing[slot][0] = '\0';
        pthread_cond_broadcast(&s->imported);
        pthread_mutex_unlock(&s->lock);
    }
    return st;
}

/* ---- reading and deleting ---- */

static lucent_status absent(const char *id, lucent_error *err)
{
    return lucent_fail(err, LUCENT_E_INVALID, "mesh.id", "no mesh with id %s", id);
}

lucent_status mesh_store_get(struct mesh_store *s, const char *id, struct mesh_info *info, char *path, size_t cap,
                             lucent_error *err)
{
    lucent_status st = check_id(id, err);
    if (st != LUCENT_OK)
        return st;
    pthread_mutex_lock(&s->lock);
    const struct store_entry *e = index_find(s, id);
    if (!e)
        st = absent(id, err);
    else if ((size_t)snprintf(path, cap, "%s/%s.lmesh", s->dir, id) >= cap)
        st = lucent_fail(err, LUCENT_E_INTERNAL, "", "the buffer for the mesh path is too small");
    else if (info)
        *info = e->info;
    pthread_mutex_unlock(&s->lock);
    return st;
}

lucent_status mesh_store_delete(struct mesh_store *s, const char *id, lucent_error *err)
{
    char mesh_path[PATH_MAX], meta_path[PATH_MAX];
    lucent_status st = check_id(id, err);
    if (st != LUCENT_OK)
        return st;
    entry_path(s, id, "lmesh", mesh_path);
    entry_path(s, id, "json", meta_path);
    pthread_mutex_lock(&s->lock);
    struct store_entry *e = index_find(s, id);
    if (!e) {
        st = absent(id, err);
    } else if (unlink(meta_path) != 0 && errno != ENOENT) {
        st = lucent_fail(err, LUCENT_E_IO, "", "cannot delete mesh %s: %s", id, strerror(errno));
    } else {
        /* without its metadata the entry is gone; a mesh file left behind is removed at the next open */
        unlink(mesh_path);
        s->used -= e->disk_bytes;
        *e = s->entries[--s->count];
        if (!sync_dir(s->dir))
            st = lucent_fail(err, LUCENT_E_IO, "", "cannot sync the mesh store directory: %s", strerror(errno));
    }
    pthread_mutex_unlock(&s->lock);
    return st;
}

uint64_t mesh_store_bytes(struct mesh_store *s)
{
    pthread_mutex_lock(&s->lock);
    uint64_t used = s->used;
    pthread_mutex_unlock(&s->lock);
    return used;
}
