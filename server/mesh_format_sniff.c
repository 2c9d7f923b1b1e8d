/* mesh_format_sniff.c - names the format of an upload (obj, ply, stl, gltf, glb) from its Content-Type
 * and its first bytes, which decide unless the type is a mesh type. Declared in mesh_import_sandbox.h. */
#include "mesh_import_sandbox.h"

#include <string.h>
#include <strings.h>

#define SNIFF_WINDOW 4096 /* OBJ is recognized by the first keyword within this many bytes */

static const struct {
    const char *type;
    const char *ext;
} TYPES[] = {
    {"model/obj", "obj"},        {"model/stl", "stl"},          {"model/x.stl-ascii", "stl"},
    {"model/x.stl-binary", "stl"}, {"application/sla", "stl"},  {"application/vnd.ms-pki.stl", "stl"},
    {"model/ply", "ply"},        {"application/ply", "ply"},    {"model/x-ply", "ply"},
    {"model/gltf+json", "gltf"}, {"model/gltf-binary", "glb"},
};

static int type_is(const char *type, size_t len, const char *name)
{
    return strlen(name) == len && strncasecmp(type, name, len) == 0;
}

static int starts_with(const unsigned char *p, size_t len, const char *prefix)
{
    size_t n = strlen(prefix);
    return len >= n && memcmp(p, prefix, n) == 0;
}

static int is_space(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

/* The first line that is neither blank nor a comment starts with an OBJ statement. */
static int looks_like_obj(const unsigned char *p, size_t len)
{
    static const char *const keywords[] = {"v", "vn", "vt", "vp", "f", "o", "g", "s", "l", "p", "usemtl", "mtllib"};
    const unsigned char *end = p + (len < SNIFF_WINDOW ? len : SNIFF_WINDOW);
    while (p < end) {
        while (p < end && is_space(*p))
            p++;
        if (p < end && *p == '#') {
            while (p < end && *p != '\n')
                p++;
            continue;
        }
        const unsigned char *word = p;
        while (p < end && !is_space(*p))
            p++;
        for (size_t i = 0; word < p && i < sizeof keywords / sizeof keywords[0]; i++)
            if (strlen(keywords[i]) == (size_t)(p - word) && memcmp(word, keywords[i], (size_t)(p - word)) == 0)
                return p < end && (*p == ' ' || *p == '\t');
        return 0;
    }
    return 0;
}

static const char *sniff_bytes(const unsigned char *p, size_t len)
{
    if (starts_with(p, len, "glTF"))
        return "glb";
    if (len >= 4 && strncasecmp((const char *)p, "ply", 3) == 0 && (p[3] == '\n' || p[3] == '\r'))
        return "ply";
    /* binary STL: an 80-byte header, a triangle count, and 50 bytes per triangle exactly */
    if (len >= 84 && (len - 84) % 50 == 0 &&
        (p[80] | (size_t)p[81] << 8 | (size_t)p[82] << 16 | (size_t)p[83] << 24) == (len - 84) / 50)
        return "stl";
    size_t i = starts_with(p, len, "\xef\xbb\xbf") ? 3 : 0; /* a UTF-8 byte order mark */
    while (i < len && is_space(p[i]))
        i++;
    if (i < len && p[i] == '{')
        return "gltf";
    if (starts_with(p + i, len - i, "solid"))
        return "stl";
    return looks_like_obj(p + i, len - i) ? "obj" : NULL;
}

const char *mesh_format_of_type(const char *content_type)
{
    const char *type = content_type ? content_type : "";
    while (*type == ' ' || *type == '\t')
        type++;
    size_t type_len = strcspn(type, "; \t");
    for (size_t i = 0; i < sizeof TYPES / sizeof TYPES[0]; i++)
        if (type_is(type, type_len, TYPES[i].type))
            return TYPES[i].ext;
    return NULL;
}

const char *mesh_format_of_bytes(const void *bytes, size_t len)
{
    return sniff_bytes(bytes, len);
}

/* A declared mesh type names the format unless the bytes are recognizably another one; any other
 * type (none, generic, or one this list lacks, such as the legacy application/x-ply) lets the bytes
 * decide. */
static const char *combine(const char *declared, const char *sniffed)
{
    if (!declared)
        return sniffed;
    return !sniffed || strcmp(sniffed, declared) == 0 ? declared : NULL;
}

const char *mesh_format_sniff(const char *content_type, const void *bytes, size_t len)
{
    return combine(mesh_format_of_type(content_type), sniff_bytes(bytes, len));
}

const char *mesh_upload_format(const char *content_type, const void *bytes, size_t len, lucent_error *err)
{
    const char *declared = mesh_format_of_type(content_type), *sniffed = sniff_bytes(bytes, len);
    const char *ext = combine(declared, sniffed);
    if (!ext && declared && sniffed)
        lucent_fail(err, LUCENT_E_INVALID, "Content-Type",
                    "the Content-Type says %s but the bytes are %s: send the type of the file, or "
                    "application/octet-stream to have it recognized", declared, sniffed);
    else if (!ext)
        lucent_fail(err, LUCENT_E_INVALID, "Content-Type",
                    "not a mesh format Lucent reads: send OBJ, PLY, STL, glTF or GLB (Content-Type model/obj, "
                    "model/ply, model/stl, model/gltf+json, model/gltf-binary, or application/octet-stream to "
                    "have it recognized), or a glTF with the files it names as multipart/form-data");
    return ext;
}
