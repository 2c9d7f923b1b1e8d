/* mesh_bundle.c - checks, encodes and decodes the files of a multi-file mesh upload. The daemon encodes
 * what a form carried; the sandboxed importer decodes it, so decoding trusts nothing. */
#include "mesh_bundle.h"

#include <jansson.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char MAGIC[] = "lucent mesh bundle 1\n";
#define MAGIC_LEN (sizeof MAGIC - 1)

static const char *const MESH_EXTS[] = {"gltf", "glb", "obj", "ply", "stl"};

/* What is wrong with a name, or NULL. */
static const char *name_problem(const char *name)
{
    size_t len = strlen(name);
    if (len == 0 || len > MESH_BUNDLE_NAME_MAX)
        return "is empty or longer than 255 bytes";
    json_t *utf8 = json_stringn(name, len);
    if (!utf8)
        return "is not UTF-8";
    json_decref(utf8);
    for (const char *seg = name;; seg++) {
        size_t n = strcspn(seg, "/");
        if (n == 0 || (n == 1 && seg[0] == '.') || (n == 2 && seg[0] == '.' && seg[1] == '.'))
            return "has an empty, \".\" or \"..\" path segment";
        seg += n;
        if (!*seg)
            break;
    }
    for (const unsigned char *c = (const unsigned char *)name; *c; c++)
        if (*c < 0x20 || *c == 0x7f || *c == '\\')
            return "holds a control character or a backslash";
    return NULL;
}

static const char *mesh_ext_of(const char *name)
{
    const char *dot = strrchr(name, '.');
    for (size_t i = 0; dot && !strchr(dot, '/') && i < sizeof MESH_EXTS / sizeof MESH_EXTS[0]; i++)
        if (strcasecmp(dot + 1, MESH_EXTS[i]) == 0)
            return MESH_EXTS[i];
    return NULL;
}

static int by_name(const void *a, const void *b)
{
    return strcmp(((const lucent_mesh_file *)a)->name, ((const lucent_mesh_file *)b)->name);
}

lucent_status mesh_bundle_check(lucent_mesh_file *files, size_t count, size_t *main, const char **ext,
                                lucent_error *err)
{
    if (count == 0 || count > MESH_BUNDLE_MAX_FILES)
        return lucent_fail(err, LUCENT_E_INVALID, "body", "send between 1 and %d files; this upload has %zu",
                           MESH_BUNDLE_MAX_FILES, count);
    for (size_t i = 0; i < count; i++) {
        const char *problem = name_problem(files[i].name);
        if (problem)
            return lucent_fail(err, LUCENT_E_INVALID, "body",
                               "file %zu's name %s; names are relative paths such as \"model.bin\" or "
                               "\"textures/a.png\"", i + 1, problem);
    }
    qsort(files, count, sizeof *files, by_name);
    size_t meshes = 0;
    for (size_t i = 0; i < count; i++) {
        if (i > 0 && strcmp(files[i - 1].name, files[i].name) == 0)
            return lucent_fail(err, LUCENT_E_INVALID, "body", "\"%s\" is sent twice", files[i].name);
        if (mesh_ext_of(files[i].name) && meshes++ == 0) {
            *main = i;
            *ext = mesh_ext_of(files[i].name);
        }
    }
    if (meshes != 1)
        return lucent_fail(err, LUCENT_E_INVALID, "body",
                           "the upload holds %zu mesh files (.gltf, .glb, .obj, .ply, .stl); send exactly one, "
                           "with the files it names", meshes);
    return LUCENT_OK;
}

static unsigned char *put_le(unsigned char *p, uint64_t v, int bytes)
{
    for (int i = 0; i < bytes; i++)
        *p++ = (unsigned char)(v >> (8 * i));
    return p;
}

static uint64_t get_le(const unsigned char *p, int bytes)
{
    uint64_t v = 0;
    for (int i = 0; i < bytes; i++)
        v |= (uint64_t)p[i] << (8 * i);
    return v;
}

lucent_status mesh_bundle_encode(const lucent_mesh_file *files, size_t count, unsigned char **out, size_t *len,
                                 lucent_error *err)
{
    size_t total = MAGIC_LEN + 4;
    for (size_t i = 0; i < count; i++) {
        size_t entry = 4 + strlen(files[i].name) + 1 + 8;
        if (files[i].len > SIZE_MAX - total - entry)
            return lucent_fail(err, LUCENT_E_LIMIT, "body", "the files are too large together");
        total += entry + files[i].len;
    }
    unsigned char *buf = malloc(total), *p = buf;
    if (!buf)
        return lucent_fail(err, LUCENT_E_NOMEM, "body", "out of memory taking the upload");
    memcpy(p, MAGIC, MAGIC_LEN);
    p = put_le(p + MAGIC_LEN, count, 4);
    for (size_t i = 0; i < count; i++) {
        size_t name_len = strlen(files[i].name);
        p = put_le(p, name_len, 4);
        memcpy(p, files[i].name, name_len + 1);
        p = put_le(p + name_len + 1, files[i].len, 8);
        if (files[i].len)
            memcpy(p, files[i].data, files[i].len);
        p += files[i].len;
    }
    *out = buf;
    *len = total;
    return LUCENT_OK;
}

static lucent_status malformed(const char *why, lucent_error *err)
{
    return lucent_fail(err, LUCENT_E_INVALID, "body", "not a mesh bundle: %s", why);
}

lucent_status mesh_bundle_decode(const unsigned char *bytes, size_t len, lucent_mesh_file files[MESH_BUNDLE_MAX_FILES],
                                 size_t *count, lucent_error *err)
{
    if (len < MAGIC_LEN + 4 || memcmp(bytes, MAGIC, MAGIC_LEN) != 0)
        return malformed("it does not start with the magic line", err);
    const unsigned char *p = bytes + MAGIC_LEN, *end = bytes + len;
    uint64_t n = get_le(p, 4);
    p += 4;
    if (n == 0 || n > MESH_BUNDLE_MAX_FILES)
        return malformed("the file count is out of range", err);
    for (size_t i = 0; i < n; i++) {
        if (end - p < 4)
            return malformed("a name is cut short", err);
        uint64_t name_len = get_le(p, 4);
        p += 4;
        if (name_len == 0 || name_len > MESH_BUNDLE_NAME_MAX || (uint64_t)(end - p) < name_len + 1 + 8 ||
            p[name_len] != '\0' || memchr(p, '\0', name_len))
            return malformed("a name is cut short or holds NUL", err);
        files[i].name = (const char *)p;
        p += name_len + 1;
        uint64_t size = get_le(p, 8);
        p += 8;
        if (size > (uint64_t)(end - p))
            return malformed("a file is cut short", err);
        files[i].data = p;
        files[i].len = (size_t)size;
        p += size;
        if (i > 0 && strcmp(files[i - 1].name, files[i].name) >= 0)
            return malformed("the names are not in order", err);
    }
    if (p != end)
        return malformed("bytes follow the last file", err);
    *count = (size_t)n;
    return LUCENT_OK;
}

lucent_status mesh_bundle_import(const unsigned char *bytes, size_t len, lucent_mesh **out, lucent_error *err)
{
    lucent_mesh_file files[MESH_BUNDLE_MAX_FILES];
    size_t count = 0, main = 0;
    const char *ext = NULL;
    *out = NULL;
    lucent_status st = mesh_bundle_decode(bytes, len, files, &count, err);
    if (st == LUCENT_OK)
        st = mesh_bundle_check(files, count, &main, &ext, err);
    return st == LUCENT_OK ? lucent_mesh_import_files(files, count, main, ext, out, err) : st;
}
