/* mesh_store.c - the content-addressed mesh store (contract in mesh_store.h). Every file appears by
 * rename of an fsynced temporary; the metadata file, renamed last, marks a complete entry and holds
 * the mesh's MAC, checked whenever the mesh file is not the one last checked. Several processes may
 * share the directory: the files are the truth, each process's index only a cache of them, and every
 * change to the set of entries happens under store_lock(). */
#define _GNU_SOURCE /* mkostemp */

#include "mesh_store.h"
#include "store_integrity.h"
#include "store_lock.h"

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
#define DEFAULT_KEY_NAME "store.key"
#define ID_LEN 64
#define NAME_SLACK 80 /* "/", an id, an extension, a temporary's suffix */

/* What identifies one version of a file: any write, rename or chmod changes ctime, which no one can set. */
struct file_stamp {
    dev_t dev;
    ino_t ino;
    off_t size;
    struct timespec mtime, ctime;
};

struct store_entry {
    char id[ID_LEN + 1];
    char mac[STORE_MAC_HEX + 1];
    struct mesh_info info;
    struct file_stamp checked;  /* the mesh file as its MAC was last found right; ino 0: not yet */
};

/* One entry as found on disk; the metadata file's mtime is its last use (every get touches it), so
 * every process sharing the store evicts by the same order. */
struct census_entry {
    char id[ID_LEN + 1];
    uint64_t disk_bytes;        /* both files */
    struct timespec last_used;
};

/* Ids being imported now: a second put of the same bytes waits for the first instead of importing
 * them again (uploads at once run at most --max-imports, 64; past this many puts import unguarded). */
#define MAX_IMPORTING 64

struct mesh_store {
    pthread_mutex_t lock;
    pthread_cond_t imported;            /* an import of `importing` ended */
    char importing[MAX_IMPORTING][ID_LEN + 1];
    char *dir;
    unsigned char key[STORE_KEY_BYTES];
    const struct import_jail *jail;
    struct import_limits lim;
    uint64_t budget, used;      /* used: the files' bytes at this process's last census */
    struct store_entry *entries;
    size_t count, cap;
    uint32_t *slots;            /* hash index: entry index + 1, 0 empty; linear probing */
    size_t slot_count;          /* a power of two, at least twice cap */
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
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    int ok = fd >= 0 && fsync(fd) == 0;
    if (fd >= 0)
        close(fd);
    return ok;
}

/* Ids are sha256 digests: their first 16 hex digits are already a uniform hash. */
static size_t id_slot(const struct mesh_store *s, const char *id)
{
    uint64_t h = 0;
    for (int i = 0; i < 16; i++)
        h = h << 4 | (uint64_t)(id[i] <= '9' ? id[i] - '0' : id[i] - 'a' + 10);
    return (size_t)h & (s->slot_count - 1);
}

static struct store_entry *index_find(struct mesh_store *s, const char *id)
{
    if (!s->slot_count || !mesh_id_valid(id))
        return NULL;
    for (size_t i = id_slot(s, id); s->slots[i]; i = (i + 1) & (s->slot_count - 1))
        if (strcmp(s->entries[s->slots[i] - 1].id, id) == 0)
            return &s->entries[s->slots[i] - 1];
    return NULL;
}

static void slot_insert(struct mesh_store *s, size_t entry)
{
    size_t i = id_slot(s, s->entries[entry].id);
    while (s->slots[i])
        i = (i + 1) & (s->slot_count - 1);
    s->slots[i] = (uint32_t)entry + 1;
}

static void index_rebuild(struct mesh_store *s)
{
    memset(s->slots, 0, s->slot_count * sizeof *s->slots);
    for (size_t k = 0; k < s->count; k++)
        slot_insert(s, k);
}

/* Makes room for one more entry, so that adding it after the files are in place cannot fail. */
static lucent_status index_reserve(struct mesh_store *s, lucent_error *err)
{
    if (s->count < s->cap)
        return LUCENT_OK;
    size_t cap = s->cap ? 2 * s->cap : 64;
    struct store_entry *grown = realloc(s->entries, cap * sizeof *grown);
    uint32_t *slots = cap <= UINT32_MAX / 2 ? calloc(2 * cap, sizeof *slots) : NULL;
    if (grown)
        s->entries = grown;
    if (!grown || !slots) {
        free(slots);
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory indexing the mesh store");
    }
    free(s->slots);
    s->slots = slots;
    s->slot_count = 2 * cap;
    s->cap = cap;
    index_rebuild(s);
    return LUCENT_OK;
}

/* Drops id from this process's index (its files are another matter). */
static void index_forget_locked(struct mesh_store *s, const char *id)
{
    struct store_entry *e = index_find(s, id);
    if (!e)
        return;
    *e = s->entries[--s->count];
    index_rebuild(s);
}

/* Removes an entry's files under the store lock: the metadata first (without it the entry is gone, and
 * a mesh file left behind is removed at the next open). 1 removed, 0 there was none, -1 on failure.
 * The caller syncs the directory once the locks are released. */
static int unlink_entry(const struct mesh_store *s, const char *id)
{
    char mesh_path[PATH_MAX], meta_path[PATH_MAX];
    entry_path(s, id, "lmesh", mesh_path);
    entry_path(s, id, "json", meta_path);
    if (unlink(meta_path) != 0)
        return errno == ENOENT ? 0 : -1;
    unlink(mesh_path);
    return 1;
}

static void index_add(struct mesh_store *s, const char *id, const char *mac, const struct mesh_info *info)
{
    struct store_entry *e = &s->entries[s->count++];
    memset(e, 0, sizeof *e);
    snprintf(e->id, sizeof e->id, "%s", id);
    snprintf(e->mac, sizeof e->mac, "%s", mac);
    e->info = *info;
    slot_insert(s, s->count - 1);
}

/* ---- metadata ---- */

static char *metadata_text(const char *id, const char *mac, const struct mesh_info *m)
{
    json_t *doc = json_pack("{s:s, s:s, s:I, s:I, s:{s:[fff], s:[fff]}, s:I, s:I}", "id", id, "mac", mac, "triangles",
                            (json_int_t)m->triangles, "vertices", (json_int_t)m->vertices, "bounds", "min",
                            m->bounds_min[0], m->bounds_min[1], m->bounds_min[2], "max", m->bounds_max[0],
                            m->bounds_max[1], m->bounds_max[2], "bytes", (json_int_t)m->bytes, "created",
                            (json_int_t)m->created);
    char *text = doc ? json_dumps(doc, JSON_COMPACT | JSON_REAL_PRECISION(17)) : NULL;
    json_decref(doc);
    return text;
}

/* Reads <id>.json back; 0 when it is not exactly what metadata_text writes for this id. */
static int metadata_read(const char *path, const char *id, char mac[STORE_MAC_HEX + 1], struct mesh_info *m)
{
    json_error_t jerr;
    const char *stored_id, *stored_mac;
    json_int_t triangles, vertices, bytes, created;
    double *lo = m->bounds_min, *hi = m->bounds_max;
    json_t *doc = json_load_file(path, JSON_REJECT_DUPLICATES, &jerr);
    int ok = doc && json_unpack_ex(doc, &jerr, JSON_STRICT, "{s:s, s:s, s:I, s:I, s:{s:[FFF], s:[FFF]}, s:I, s:I}",
                                   "id", &stored_id, "mac", &stored_mac, "triangles", &triangles, "vertices", &vertices, "bounds",
                                   "min", &lo[0], &lo[1], &lo[2], "max", &hi[0], &hi[1], &hi[2], "bytes", &bytes,
                                   "created", &created) == 0;
    ok = ok && strcmp(stored_id, id) == 0 && strlen(stored_mac) == STORE_MAC_HEX && triangles >= 1 && triangles <= LUCENT_MAX_TRIANGLES &&
         vertices >= 1 && vertices <= 3 * triangles && bytes >= 0 && created >= 0;
    for (int k = 0; ok && k < 3; k++)
        ok = isfinite(lo[k]) && isfinite(hi[k]) && lo[k] <= hi[k];
    if (ok)
        memcpy(mac, stored_mac, STORE_MAC_HEX + 1);
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

static lucent_status store_io_error(const char *what, lucent_error *err)
{
    return lucent_fail(err, lucent_io_status(errno), "", "%s: %s", what, strerror(errno));
}

/* A temporary is claimed while it is written, so a process opening the store meanwhile leaves it be;
 * made and claimed under the store lock, so that process cannot see it unclaimed. */
static lucent_status make_temp(const struct mesh_store *s, char path[PATH_MAX], int *fd, lucent_error *err)
{
    snprintf(path, PATH_MAX, "%s/" TEMP_PREFIX "XXXXXX", s->dir);
    int lock = store_lock(s->dir);
    if (lock < 0) {
        path[0] = '\0';
        return store_io_error("cannot lock the mesh store", err);
    }
    *fd = mkostemp(path, O_CLOEXEC);
    lucent_status st = LUCENT_OK;
    if (*fd < 0 || store_claim_file(*fd) != 0) {
        st = store_io_error("cannot create a file in the mesh store", err);
        if (*fd >= 0) {
            close(*fd);
            unlink(path);
        }
        *fd = -1;
        path[0] = '\0';
    }
    store_unlock(lock);
    return st;
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

static lucent_status write_metadata(const struct mesh_store *s, const char *id, const char *mac,
                                    const struct mesh_info *info, char path[PATH_MAX], uint64_t *size,
                                    lucent_error *err)
{
    int fd;
    char *text = metadata_text(id, mac, info);
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

/* Reads the entry <id>.json names from disk; 0 when it is absent, incomplete or damaged. */
static int entry_read(const struct mesh_store *s, const char *id, char mac[STORE_MAC_HEX + 1], struct mesh_info *info)
{
    char mesh_path[PATH_MAX], meta_path[PATH_MAX];
    struct stat mesh_st;
    entry_path(s, id, "lmesh", mesh_path);
    entry_path(s, id, "json", meta_path);
    return stat(mesh_path, &mesh_st) == 0 && S_ISREG(mesh_st.st_mode) && metadata_read(meta_path, id, mac, info);
}

/* Indexes an entry read from disk (unless the index has it already); 0 when out of memory. */
static int index_learn_locked(struct mesh_store *s, const char *id, const char *mac, const struct mesh_info *info)
{
    if (index_find(s, id))
        return 1;
    if (index_reserve(s, NULL) != LUCENT_OK)
        return 0;
    index_add(s, id, mac, info);
    return 1;
}

/* Indexes the entry <id>.json names; 0 when it is incomplete or damaged. */
static int index_existing(struct mesh_store *s, const char *id)
{
    struct mesh_info info;
    char mac[STORE_MAC_HEX + 1];
    return entry_read(s, id, mac, &info) && index_learn_locked(s, id, mac, &info);
}

typedef char entry_id[ID_LEN + 1];

/* The ids every <id>.json of the store directory names (after `after`, when given), in directory order;
 * *ids is malloc'd, the caller's. */
static lucent_status entry_ids(const struct mesh_store *s, const char *after, entry_id **ids, size_t *count,
                               lucent_error *err)
{
    entry_id id, *list = NULL;
    size_t n = 0, cap = 0;
    DIR *d = opendir(s->dir);
    if (!d)
        return store_io_error("cannot list the mesh store", err);
    lucent_status st = LUCENT_OK;
    for (struct dirent *e; st == LUCENT_OK && (e = readdir(d));) {
        if (!entry_name(e->d_name, "json", id) || (after && strcmp(id, after) <= 0))
            continue;
        if (n == cap) {
            entry_id *grown = realloc(list, (cap = cap ? 2 * cap : 256) * sizeof *list);
            if (!grown) {
                st = lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory listing the mesh store");
                break;
            }
            list = grown;
        }
        memcpy(list[n++], id, sizeof id);
    }
    closedir(d);
    if (st != LUCENT_OK) {
        free(list);
        return st;
    }
    *ids = list;
    *count = n;
    return LUCENT_OK;
}

/* Every complete entry on disk with its bytes and last use, and their total. Under the store lock. */
static lucent_status census(const struct mesh_store *s, struct census_entry **out, size_t *count, uint64_t *total,
                            lucent_error *err)
{
    char mesh_path[PATH_MAX], meta_path[PATH_MAX];
    entry_id *ids = NULL;
    size_t n_ids = 0, n = 0;
    *total = 0;
    lucent_status st = entry_ids(s, NULL, &ids, &n_ids, err);
    struct census_entry *list = st == LUCENT_OK ? malloc((n_ids ? n_ids : 1) * sizeof *list) : NULL;
    if (st == LUCENT_OK && !list)
        st = lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory listing the mesh store");
    for (size_t i = 0; st == LUCENT_OK && i < n_ids; i++) {
        struct stat mesh_st, meta_st;
        entry_path(s, ids[i], "lmesh", mesh_path);
        entry_path(s, ids[i], "json", meta_path);
        if (stat(meta_path, &meta_st) != 0 || stat(mesh_path, &mesh_st) != 0)
            continue; /* half an entry: left for the next open to clean */
        memcpy(list[n].id, ids[i], sizeof ids[i]);
        list[n].disk_bytes = (uint64_t)mesh_st.st_size + (uint64_t)meta_st.st_size;
        list[n].last_used = meta_st.st_mtim;
        *total += list[n++].disk_bytes;
    }
    free(ids);
    if (st != LUCENT_OK || !out)
        free(list);
    else
        *out = list;
    if (count)
        *count = n;
    return st;
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

/* Two passes under the store lock: metadata (and temporaries no process still writes) first, then
 * meshes that no metadata claimed. */
static lucent_status scan(struct mesh_store *s, lucent_error *err)
{
    char id[ID_LEN + 1], path[PATH_MAX];
    int removed = 0;
    int lock = store_lock(s->dir);
    if (lock < 0)
        return lucent_fail(err, LUCENT_E_IO, "", "cannot lock the mesh store \"%s\": %s", s->dir, strerror(errno));
    DIR *d = opendir(s->dir);
    if (!d) {
        store_unlock(lock);
        return lucent_fail(err, LUCENT_E_IO, "", "cannot list the mesh store \"%s\": %s", s->dir, strerror(errno));
    }
    for (struct dirent *e; (e = readdir(d));) {
        if (strncmp(e->d_name, TEMP_PREFIX, strlen(TEMP_PREFIX)) == 0) {
            snprintf(path, sizeof path, "%s/%s", s->dir, e->d_name);
            if (!store_file_claimed(path)) /* else another replica's upload in progress */
                remove_leftover(s, e->d_name, &removed);
        } else if (entry_name(e->d_name, "json", id) && !index_existing(s, id))
            remove_leftover(s, e->d_name, &removed);
    }
    rewinddir(d);
    for (struct dirent *e; (e = readdir(d));)
        if (entry_name(e->d_name, "lmesh", id) && !index_find(s, id))
            remove_leftover(s, e->d_name, &removed);
    closedir(d);
    lucent_status st = census(s, NULL, NULL, &s->used, err);
    store_unlock(lock);
    if (st == LUCENT_OK && removed > 0 && !sync_dir(s->dir))
        return lucent_fail(err, LUCENT_E_IO, "", "cannot sync the mesh store \"%s\": %s", s->dir, strerror(errno));
    return st;
}

lucent_status mesh_store_open(const char *dir, uint64_t byte_budget, const char *key_file,
                              const struct import_jail *jail, const struct import_limits *lim,
                              struct mesh_store **out, lucent_error *err)
{
    struct stat st;
    char default_key[PATH_MAX];
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
    if (!key_file || !key_file[0]) {
        snprintf(default_key, sizeof default_key, "%s/" DEFAULT_KEY_NAME, dir);
        key_file = default_key;
    }
    struct mesh_store *s = calloc(1, sizeof *s);
    if (!s)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory opening the mesh store");
    pthread_mutex_init(&s->lock, NULL);
    pthread_cond_init(&s->imported, NULL);
    s->budget = byte_budget;
    s->lim = *lim;
    s->dir = strdup(dir);
    s->jail = jail;
    lucent_status status = s->dir ? store_key_load(key_file, s->key, err)
                                  : lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory opening the mesh store");
    if (status == LUCENT_OK)
        status = scan(s, err);
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
    free(s->slots);
    free(s->dir);
    free(s);
}

/* ---- file versions ---- */

static void stamp_of(const struct stat *st, struct file_stamp *out)
{
    *out = (struct file_stamp){st->st_dev, st->st_ino, st->st_size, st->st_mtim, st->st_ctim};
}

/* Leaves the stamp zero (not checked) when the file cannot be seen. */
static void stamp_file(const char *path, struct file_stamp *out)
{
    struct stat st;
    memset(out, 0, sizeof *out);
    if (stat(path, &st) == 0)
        stamp_of(&st, out);
}

static int same_stamp(const struct file_stamp *a, const struct file_stamp *b)
{
    return a->ino != 0 && a->dev == b->dev && a->ino == b->ino && a->size == b->size &&
           a->mtime.tv_sec == b->mtime.tv_sec && a->mtime.tv_nsec == b->mtime.tv_nsec &&
           a->ctime.tv_sec == b->ctime.tv_sec && a->ctime.tv_nsec == b->ctime.tv_nsec;
}

/* ---- putting ---- */

static lucent_status over_budget(const struct mesh_store *s, uint64_t needed, lucent_error *err)
{
    return lucent_fail(err, LUCENT_E_LIMIT, "mesh", "this mesh needs %llu bytes in the store, more than its whole "
                       "budget of %llu (--store-bytes)", (unsigned long long)needed, (unsigned long long)s->budget);
}

static int older_use(const void *a, const void *b)
{
    const struct census_entry *x = a, *y = b;
    if (x->last_used.tv_sec != y->last_used.tv_sec)
        return x->last_used.tv_sec < y->last_used.tv_sec ? -1 : 1;
    if (x->last_used.tv_nsec != y->last_used.tv_nsec)
        return x->last_used.tv_nsec < y->last_used.tv_nsec ? -1 : 1;
    return strcmp(x->id, y->id);
}

/* Makes room for `needed` more bytes by removing the least recently used meshes of the census (by any
 * process), under the store lock; *used is what remains. */
static void evict(struct mesh_store *s, struct census_entry *list, size_t count, uint64_t *used, uint64_t needed)
{
    if (count > 1) /* qsort may not be given a null list, which an empty census is */
        qsort(list, count, sizeof *list, older_use);
    for (size_t k = 0; k < count && *used + needed > s->budget; k++) {
        if (unlink_entry(s, list[k].id) < 0)
            return; /* cannot delete: the put is refused as over budget */
        *used -= list[k].disk_bytes;
        pthread_mutex_lock(&s->lock);
        index_forget_locked(s, list[k].id);
        pthread_mutex_unlock(&s->lock);
        fprintf(stderr, "lucent: mesh store: evicted mesh %s, the least recently used, to make room\n", list[k].id);
    }
}

/* Moves both temporaries into place under the store lock, unless some process stored the same id
 * first; clears their names once they are renamed. */
static lucent_status commit(struct mesh_store *s, const char *id, const char *mac, char *tmp_mesh, char *tmp_meta,
                            uint64_t disk_bytes, struct mesh_info *info, int *created, lucent_error *err)
{
    char mesh_path[PATH_MAX], meta_path[PATH_MAX], stored_mac[STORE_MAC_HEX + 1];
    struct mesh_info stored;
    struct census_entry *list = NULL;
    size_t count = 0;
    uint64_t used = 0;
    lucent_status st = LUCENT_OK;
    entry_path(s, id, "lmesh", mesh_path);
    entry_path(s, id, "json", meta_path);
    int lock = store_lock(s->dir);
    if (lock < 0)
        return store_io_error("cannot lock the mesh store", err);
    if (entry_read(s, id, stored_mac, &stored)) { /* a concurrent put of the same bytes got here first */
        *info = stored;
        pthread_mutex_lock(&s->lock);
        index_learn_locked(s, id, stored_mac, &stored);
        pthread_mutex_unlock(&s->lock);
        goto unlock;
    }
    if (disk_bytes > s->budget) {
        st = over_budget(s, disk_bytes, err);
        goto unlock;
    }
    if ((st = census(s, &list, &count, &used, err)) != LUCENT_OK)
        goto unlock;
    evict(s, list, count, &used, disk_bytes);
    if (used + disk_bytes > s->budget) {
        st = store_io_error("cannot evict meshes to make room", err);
        goto unlock;
    }
    if (rename(tmp_mesh, mesh_path) != 0) {
        st = store_io_error("cannot store the mesh", err);
        goto unlock;
    }
    tmp_mesh[0] = '\0';
    if (rename(tmp_meta, meta_path) != 0) {
        st = store_io_error("cannot store the mesh metadata", err);
        unlink(mesh_path);
        goto unlock;
    }
    tmp_meta[0] = '\0';
    pthread_mutex_lock(&s->lock);
    if (!index_find(s, id) && index_reserve(s, NULL) == LUCENT_OK) { /* else a get reads it from disk */
        index_add(s, id, mac, info);
        stamp_file(mesh_path, &s->entries[s->count - 1].checked); /* as renamed: the MAC was just computed */
    }
    s->used = used + disk_bytes;
    pthread_mutex_unlock(&s->lock);
    *created = 1;
unlock:
    store_unlock(lock);
    free(list);
    /* after the locks: a sync takes milliseconds to seconds */
    if (*created && !sync_dir(s->dir)) /* the entry exists; only its durability is in doubt */
        st = lucent_fail(err, LUCENT_E_IO, "", "cannot sync the mesh store directory: %s", strerror(errno));
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

lucent_status mesh_store_put(struct mesh_store *s, const void *bytes, size_t len, const char *format,
                             char id_out[65], struct mesh_info *info, int *created, lucent_error *err)
{
    char tmp_mesh[PATH_MAX] = "", tmp_meta[PATH_MAX] = "";
    uint64_t mesh_bytes = 0, meta_bytes = 0;
    int fd = -1;
    char mac[STORE_MAC_HEX + 1];
    lucent_status st;
    *created = 0;
    if ((st = sha256_hex(bytes, len, id_out, err)) != LUCENT_OK)
        return st;
    char stored_mac[STORE_MAC_HEX + 1];
    struct mesh_info stored;
    if (entry_read(s, id_out, stored_mac, &stored)) { /* stored already, perhaps by another process */
        pthread_mutex_lock(&s->lock);
        index_learn_locked(s, id_out, stored_mac, &stored);
        pthread_mutex_unlock(&s->lock);
        *info = stored;
        return LUCENT_OK;
    }

    pthread_mutex_lock(&s->lock);
    const struct store_entry *existing;
    int slot;
    while (!(existing = index_find(s, id_out)) && importing_slot(s, id_out) >= 0)
        pthread_cond_wait(&s->imported, &s->lock);
    if (existing)
        *info = existing->info;
    slot = existing || st != LUCENT_OK ? -1 : importing_slot(s, "");
    if (slot >= 0)
        memcpy(s->importing[slot], id_out, ID_LEN + 1);
    pthread_mutex_unlock(&s->lock);
    if (existing || st != LUCENT_OK)
        return st;

    /* importing takes seconds: the lock is not held, so gets and other puts go on meanwhile */
    if ((st = make_temp(s, tmp_mesh, &fd, err)) != LUCENT_OK ||
        (st = mesh_import_isolated(s->jail, &s->lim, bytes, len, format, fd, info, err)) != LUCENT_OK ||
        (st = sync_file(fd, &mesh_bytes, err)) != LUCENT_OK ||
        (st = store_mac_of_file(s->key, id_out, fd, mac, err)) != LUCENT_OK)
        goto done;
    info->created = (int64_t)time(NULL);
    if ((st = write_metadata(s, id_out, mac, info, tmp_meta, &meta_bytes, err)) != LUCENT_OK)
        goto done;
    st = commit(s, id_out, mac, tmp_mesh, tmp_meta, mesh_bytes + meta_bytes, info, created, err);
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

/* Removes an entry's files under the store lock and forgets it: 1 removed, 0 none on disk, -1 failed
 * (errno set). */
static int remove_entry(struct mesh_store *s, const char *id)
{
    int lock = store_lock(s->dir);
    if (lock < 0)
        return -1;
    int removed = unlink_entry(s, id);
    int saved = errno;
    uint64_t used = 0;
    int counted = census(s, NULL, NULL, &used, NULL) == LUCENT_OK;
    pthread_mutex_lock(&s->lock);
    index_forget_locked(s, id);
    if (counted)
        s->used = used;
    pthread_mutex_unlock(&s->lock);
    store_unlock(lock);
    if (removed > 0)
        sync_dir(s->dir);
    errno = saved;
    return removed;
}

/* Forgets an entry another process removed (its metadata is gone); 1 when that is so. */
static int removed_elsewhere(struct mesh_store *s, const char *id)
{
    char meta_path[PATH_MAX];
    entry_path(s, id, "json", meta_path);
    if (access(meta_path, F_OK) == 0 || errno != ENOENT)
        return 0;
    pthread_mutex_lock(&s->lock);
    index_forget_locked(s, id);
    pthread_mutex_unlock(&s->lock);
    return 1;
}

/* Drops an entry whose mesh failed its check; its files go with it (they are not what was stored). */
static lucent_status damaged(struct mesh_store *s, const char *id, const char *why, lucent_error *err)
{
    fprintf(stderr, "lucent: mesh store: mesh %s failed its integrity check (%s); removed\n", id, why);
    remove_entry(s, id);
    return lucent_fail(err, LUCENT_E_IO, "mesh.id",
                       "the stored mesh %s failed its integrity check (%s) and was removed; upload it again", id, why);
}

/* The mesh file must be the one its MAC was computed over: checked again whenever the file is not the
 * version last checked, outside the lock (hashing a large mesh takes a while). */
static lucent_status verify(struct mesh_store *s, const char *id, const char *path, const char *mac,
                            const struct file_stamp *checked, lucent_error *err)
{
    struct stat st;
    struct file_stamp now;
    /* every render gets its mesh: an unchanged file costs one lstat, and is opened only to be hashed */
    if (lstat(path, &st) == 0 && S_ISREG(st.st_mode)) {
        stamp_of(&st, &now);
        if (same_stamp(checked, &now))
            return LUCENT_OK;
    }
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd < 0 && errno == ENOENT && removed_elsewhere(s, id)) /* deleted or evicted by another replica */
        return absent(id, err);
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        if (fd >= 0)
            close(fd);
        return damaged(s, id, "its file is missing or not a regular file", err);
    }
    stamp_of(&st, &now);
    char found[STORE_MAC_HEX + 1];
    lucent_status status = store_mac_of_file(s->key, id, fd, found, err);
    close(fd);
    if (status != LUCENT_OK)
        return status;
    if (strcmp(found, mac) != 0)
        return damaged(s, id, "its file changed after it was stored", err);
    pthread_mutex_lock(&s->lock);
    struct store_entry *e = index_find(s, id);
    if (e && strcmp(e->mac, mac) == 0)
        e->checked = now;
    pthread_mutex_unlock(&s->lock);
    return LUCENT_OK;
}

lucent_status mesh_store_get(struct mesh_store *s, const char *id, struct mesh_info *info, char *path, size_t cap,
                             lucent_error *err)
{
    lucent_status st = check_id(id, err);
    if (st != LUCENT_OK)
        return st;
    char mac[STORE_MAC_HEX + 1];
    struct file_stamp checked = {0};
    struct mesh_info found = {0};
    pthread_mutex_lock(&s->lock);
    struct store_entry *e = index_find(s, id);
    int present = e != NULL;
    if (present) {
        memcpy(mac, e->mac, sizeof mac);
        checked = e->checked;
        found = e->info;
    }
    pthread_mutex_unlock(&s->lock);
    if (!present) { /* perhaps stored by another process since this one last looked */
        if (!entry_read(s, id, mac, &found))
            return absent(id, err);
        pthread_mutex_lock(&s->lock);
        index_learn_locked(s, id, mac, &found);
        pthread_mutex_unlock(&s->lock);
    }
    if ((size_t)snprintf(path, cap, "%s/%s.lmesh", s->dir, id) >= cap)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "the buffer for the mesh path is too small");
    if ((st = verify(s, id, path, mac, &checked, err)) != LUCENT_OK)
        return st;
    /* the metadata's mtime is the entry's last use, which every process sharing the store evicts by */
    char meta_path[PATH_MAX];
    entry_path(s, id, "json", meta_path);
    utimensat(AT_FDCWD, meta_path, NULL, 0);
    if (info)
        *info = found;
    return LUCENT_OK;
}

lucent_status mesh_store_delete(struct mesh_store *s, const char *id, lucent_error *err)
{
    lucent_status st = check_id(id, err);
    if (st != LUCENT_OK)
        return st;
    int removed = remove_entry(s, id);
    if (removed == 0)
        return absent(id, err);
    if (removed < 0)
        return lucent_fail(err, LUCENT_E_IO, "", "cannot delete mesh %s: %s", id, strerror(errno));
    return LUCENT_OK;
}

/* ---- listing ---- */

static int id_order(const void *a, const void *b)
{
    return strcmp(a, b);
}

lucent_status mesh_store_list(struct mesh_store *s, const char *after, size_t limit, struct mesh_listing **out,
                              size_t *count, int *more, lucent_error *err)
{
    char mac[STORE_MAC_HEX + 1];
    entry_id *ids = NULL;
    size_t n = 0;
    *out = NULL;
    *count = 0;
    *more = 0;
    lucent_status st = entry_ids(s, after, &ids, &n, err);
    if (st != LUCENT_OK)
        return st;
    struct mesh_listing *page = calloc(limit ? limit : 1, sizeof *page);
    if (!page)
        st = lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory listing the mesh store");
    if (st == LUCENT_OK) {
        if (n > 1)
            qsort(ids, n, sizeof *ids, id_order);
        size_t k = 0;
        for (; k < n && *count < limit; k++)
            if (entry_read(s, ids[k], mac, &page[*count].info))
                memcpy(page[(*count)++].id, ids[k], ID_LEN + 1);
        *more = k < n;
        *out = page;
    }
    free(ids);
    return st;
}

uint64_t mesh_store_bytes(struct mesh_store *s)
{
    pthread_mutex_lock(&s->lock);
    uint64_t used = s->used;
    pthread_mutex_unlock(&s->lock);
    return used;
}
