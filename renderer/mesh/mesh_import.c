/* mesh_import.c - reads OBJ, PLY, STL and glTF 2.0 meshes through assimp into a lucent_mesh.
 * Built for untrusted bytes: assimp only ever sees the caller's buffer, never the disk. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* fstat, fileno, strcasecmp; the CMake build defines it too */
#endif

#include "mesh.h"
#include "mesh_compact.h"

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fcntl.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAX_MESH_BYTES ((size_t)512 << 20)
#define MAX_MESH_BYTES_TEXT "512 MiB"

/* Nesting deeper than this is refused rather than recursed into. */
#define MAX_NODE_DEPTH 1024

/* Post-processing is limited to steps that cannot fail on a validated scene: when a step fails,
 * aiApplyPostProcessing in assimp 5.2.5 uses the freed scene. Node transforms, dropping points,
 * lines and degenerate triangles are therefore done here and in mesh_finish instead of by
 * PreTransformVertices, SortByPType and FindDegenerates (which fail when nothing is left; the
 * last also drops triangles below an absolute 1e-6 area, erasing meshes modelled in metres). */
#define POST_PROCESS_FLAGS \
    (aiProcess_RemoveComponent | aiProcess_Triangulate | aiProcess_JoinIdenticalVertices)

/* Removed so that JoinIdenticalVertices welds vertices that were split only along UV seams or by
 * colours; welded vertices get smooth computed normals across those seams. */
#define UNUSED_COMPONENTS                                                              \
    (aiComponent_TANGENTS_AND_BITANGENTS | aiComponent_COLORS | aiComponent_TEXCOORDS | \
     aiComponent_BONEWEIGHTS)

/* ---- format recognition ----
 * Each check returns NULL when the bytes may be the format, else what is wrong with them. They stop
 * the inputs known to hang or crash assimp before it sees them, and keep a declared format from
 * being handed to another of assimp's readers (it sniffs content when the glTF readers refuse). */

static uint32_t read_le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* assimp's PLY reader takes any case for the magic, so this check must too. */
static int starts_like_ply(const unsigned char *data, size_t len)
{
    return len >= 3 && (data[0] | 0x20) == 'p' && (data[1] | 0x20) == 'l' &&
           (data[2] | 0x20) == 'y';
}

/* Where the data begins after a line of exactly "end_header" (the only spelling assimp's PLY parser
 * stops at), give or take that line's end; 0 when there is no such line: that parser loops forever. */
static size_t ply_header_end(const unsigned char *data, size_t len)
{
    static const char token[] = "\nend_header";
    const size_t n = sizeof token - 1;
    const unsigned char *end = data + len;
    for (const unsigned char *p = data; (size_t)(end - p) >= n; p++) {
        if (!(p = memchr(p, '\n', (size_t)(end - p))) || (size_t)(end - p) < n)
            return 0;
        if (memcmp(p, token, n) == 0)
            return p + n == end || strchr(" \t\r\n", p[n]) != NULL ? (size_t)(p + n - data) : 0;
    }
    return 0;
}

/* assimp's line ends (ParsingUtils.h IsLineEnd) */
static int ply_line_end(unsigned char c)
{
    return c == '\n' || c == '\r' || c == '\0' || c == '\f';
}

static const unsigned char *skip_spaces(const unsigned char *p, const unsigned char *end)
{
    while (p < end && (*p == ' ' || *p == '\t'))
        p++;
    return p;
}

/* Whether the line [*p, end) starts with token followed by a space, a tab or its end; if so *p moves
 * past the token and that one character, as assimp's TokenMatch does. */
static int ply_token(const unsigned char **p, const unsigned char *end, const char *token)
{
    size_t n = strlen(token);
    if ((size_t)(end - *p) < n || memcmp(*p, token, n) != 0 ||
        (*p + n < end && (*p)[n] != ' ' && (*p)[n] != '\t'))
        return 0;
    *p += *p + n < end ? n + 1 : n;
    return 1;
}

/* An element declared in a PLY header as assimp 5.2.5 reads it (PlyParser.cpp, ParseElement): after
 * "element", a known name and one blank precede the count, but an unknown name is itself read as the
 * count; digits, wrapping modulo 2^32 (strtoul10). Vertices and faces (tristrips fill the same faces)
 * are what its loader builds the mesh from. */
enum ply_kind { PLY_NONE, PLY_OTHER, PLY_VERTEX, PLY_FACE };

typedef struct ply_element {
    enum ply_kind kind;
    uint32_t count;
} ply_element;

static ply_element ply_element_of(const unsigned char *p, const unsigned char *end)
{
    static const struct {
        const char *name;
        enum ply_kind kind;
    } known[] = {{"vertex", PLY_VERTEX}, {"face", PLY_FACE}, {"tristrips", PLY_FACE}, {"edge", PLY_OTHER},
                 {"material", PLY_OTHER}};
    ply_element e = {PLY_NONE, 0};
    p = skip_spaces(p, end);
    if (!ply_token(&p, end, "element"))
        return e;
    e.kind = PLY_OTHER;
    p = skip_spaces(p, end);
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
        if (ply_token(&p, end, known[i].name)) {
            e.kind = known[i].kind;
            break;
        }
    p = skip_spaces(p, end);
    for (; p < end && *p >= '0' && *p <= '9'; p++)
        e.count = e.count * 10 + (uint32_t)(*p - '0');
    return e;
}

/* What is wrong with a PLY header for assimp 5.2.5, or NULL:
 * - no line of exactly "end_header": its parser loops forever;
 * - a count beyond the data: it sizes an element's instances by the declared count before reading
 *   any (a 187-byte PLY declaring 80 million vertices cost lucent-import 1 GB and 8 CPU seconds, then
 *   crashed once the sandbox's memory limit failed an allocation; a count wrapping to 2^32 - 1 asks
 *   for 100 GB). An instance takes at least a byte (unless its element has no properties: no use to a
 *   mesh);
 * - a second vertex or face element: its loader sizes the mesh's vertices and faces by the first and
 *   writes the second's past them (a heap overflow in lucent-import). */
static const char *ply_header_problem(const unsigned char *data, size_t len)
{
    size_t body = ply_header_end(data, len);
    if (!body)
        return "is not closed by an end_header line";
    unsigned vertex_elements = 0, face_elements = 0;
    for (const unsigned char *line = data, *end = data + body; line < end;) {
        const unsigned char *eol = line;
        while (eol < end && !ply_line_end(*eol))
            eol++;
        ply_element e = ply_element_of(line, eol);
        if (e.count > len - body)
            return "declares more elements than the data after it can hold";
        vertex_elements += e.kind == PLY_VERTEX;
        face_elements += e.kind == PLY_FACE;
        if (vertex_elements > 1 || face_elements > 1)
            return "declares a second vertex or face element";
        line = eol + 1;
    }
    return NULL;
}

static const char *ply_problem(const unsigned char *data, size_t len)
{
    if (!starts_like_ply(data, len) || len < 4 || (data[3] != '\n' && data[3] != '\r'))
        return "it does not start with a \"ply\" line";
    return NULL; /* the header is checked for every format, in check_bytes */
}

static int is_blank(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

/* Binary STL is an 84-byte header and 50 bytes per triangle, nothing else; ASCII starts "solid". */
static const char *stl_problem(const unsigned char *data, size_t len)
{
    if (len >= 84 && (len - 84) % 50 == 0 && read_le32(data + 80) == (len - 84) / 50)
        return NULL;
    size_t i = 0;
    while (i < len && is_blank(data[i]))
        i++;
    if (len - i >= 5 && memcmp(data + i, "solid", 5) == 0)
        return NULL;
    return "it neither starts with \"solid\" nor has the size its triangle count implies";
}

/* The glTF JSON must parse (jansson: strict, at most JSON_PARSER_MAX_DEPTH deep, where assimp's
 * recursive parser would overflow the stack) and declare version 2, or assimp's glTF readers
 * refuse it and assimp tries every other reader on it. */
static const char *gltf_json_problem(const unsigned char *json, size_t len)
{
    json_error_t jerr;
    json_t *doc = json_loadb((const char *)json, len, 0, &jerr);
    if (!doc)
        return "its JSON is malformed or nested too deeply";
    const char *version = json_string_value(json_object_get(json_object_get(doc, "asset"), "version"));
    int is_v2 = version && version[0] == '2';
    json_decref(doc);
    return is_v2 ? NULL : "it is not glTF 2.0 (asset.version must start with 2)";
}

/* GLB: "glTF", version 2, the total length, a JSON chunk, then nothing or a BIN chunk, laid out
 * as assimp reads them. */
static const char *glb_problem(const unsigned char *data, size_t len)
{
    if (len < 20 || memcmp(data, "glTF", 4) != 0 || read_le32(data + 4) != 2 ||
        read_le32(data + 8) != len)
        return "its header is not a glTF 2.0 binary header giving the data's length";
    size_t json_len = read_le32(data + 12);
    if (json_len > len - 20 || memcmp(data + 16, "JSON", 4) != 0)
        return "its first chunk is not JSON or does not fit";
    size_t body = 20 + ((json_len + 3) & ~(size_t)3);
    if (body <= len && len - body >= 8 &&
        (memcmp(data + body + 4, "BIN\0", 4) != 0 || read_le32(data + body) > len - body - 8))
        return "its second chunk is not BIN or does not fit";
    return gltf_json_problem(data + 20, json_len);
}

typedef struct mesh_format {
    const char *ext;
    const char *label;
    const char *(*problem)(const unsigned char *data, size_t len); /* NULL: any bytes may be it */
} mesh_format;

static const mesh_format FORMATS[] = {
    {"obj", "OBJ", NULL},
    {"ply", "PLY", ply_problem},
    {"stl", "STL", stl_problem},
    {"gltf", "glTF", gltf_json_problem},
    {"glb", "binary glTF", glb_problem},
};
#define FORMAT_COUNT (sizeof FORMATS / sizeof FORMATS[0])
#define SUPPORTED_EXTENSIONS ".obj, .ply, .stl, .gltf, .glb"

static const mesh_format *find_format(const char *ext)
{
    for (size_t i = 0; ext && i < FORMAT_COUNT; i++)
        if (strcasecmp(ext, FORMATS[i].ext) == 0)
            return &FORMATS[i];
    return NULL;
}

static lucent_status check_bytes(const mesh_format *format, const unsigned char *data, size_t len,
                                 lucent_error *err)
{
    if (len == 0)
        return lucent_fail(err, LUCENT_E_MESH, "mesh.file", "the %s data is empty", format->label);
    if (len > MAX_MESH_BYTES)
        return lucent_fail(err, LUCENT_E_LIMIT, "mesh.file",
                           "the %s data is %zu bytes; at most " MAX_MESH_BYTES_TEXT " are accepted",
                           format->label, len);
    /* whatever the declared format: content sniffing could still route PLY bytes to that reader */
    const char *ply = starts_like_ply(data, len) ? ply_header_problem(data, len) : NULL;
    if (ply)
        return lucent_fail(err, LUCENT_E_MESH, "mesh.file", "the PLY header %s", ply);
    const char *problem = format->problem ? format->problem(data, len) : NULL;
    if (problem)
        return lucent_fail(err, LUCENT_E_MESH, "mesh.file", "the data is not a valid %s file: %s",
                           format->label, problem);
    return LUCENT_OK;
}

/* ---- a file system holding nothing but the caller's files ---- */

#define MISSING_NAME_MAX 96

typedef struct memory_volume {
    const lucent_mesh_file *files;
    size_t count;
    unsigned refused_opens;           /* attempts to reach files the caller did not give, or to write */
    char missing[MISSING_NAME_MAX];   /* the first such name (printable ASCII, cut short) */
} memory_volume;

typedef struct memory_file {
    struct aiFile file; /* first member, so the aiFile pointer assimp passes back is this struct */
    const lucent_mesh_file *source;
    size_t pos;
} memory_file;

static size_t file_read(struct aiFile *file, char *buffer, size_t size, size_t count)
{
    memory_file *f = (memory_file *)file;
    if (size == 0)
        return 0;
    size_t whole = (f->source->len - f->pos) / size;
    if (count > whole)
        count = whole;
    memcpy(buffer, (const unsigned char *)f->source->data + f->pos, count * size);
    f->pos += count * size;
    return count;
}

static size_t file_write(struct aiFile *file, const char *buffer, size_t size, size_t count)
{
    (void)file, (void)buffer, (void)size, (void)count;
    return 0;
}

static size_t file_tell(struct aiFile *file)
{
    return ((memory_file *)file)->pos;
}

static size_t file_size(struct aiFile *file)
{
    return ((memory_file *)file)->source->len;
}

static void file_flush(struct aiFile *file)
{
    (void)file;
}

/* Offsets are size_t, so assimp expresses backward seeks as wrapped values: unsigned wrap-around
 * arithmetic gives the intended position. */
static enum aiReturn file_seek(struct aiFile *file, size_t offset, enum aiOrigin origin)
{
    memory_file *f = (memory_file *)file;
    size_t target;
    switch (origin) {
    case aiOrigin_SET: target = offset; break;
    case aiOrigin_CUR: target = f->pos + offset; break;
    case aiOrigin_END: target = f->source->len + offset; break;
    default: return aiReturn_FAILURE;
    }
    if (target > f->source->len)
        return aiReturn_FAILURE;
    f->pos = target;
    return aiReturn_SUCCESS;
}

/* The path `name` (assimp joins the main file's folder and the reference) with "." and ".." segments
 * resolved and backslashes read as slashes; 0 if it climbs above the root or does not fit. */
static int normalize_path(const char *name, char *out, size_t cap)
{
    size_t n = 0;
    for (const char *p = name; *p;) {
        while (*p == '/' || *p == '\\')
            p++;
        const char *seg = p;
        while (*p && *p != '/' && *p != '\\')
            p++;
        size_t len = (size_t)(p - seg);
        if (len == 0 || (len == 1 && seg[0] == '.'))
            continue;
        if (len == 2 && seg[0] == '.' && seg[1] == '.') {
            if (n == 0)
                return 0;
            while (n > 0 && out[n - 1] != '/')
                n--;
            n -= n > 0; /* the slash before the dropped segment */
            continue;
        }
        if (n + (n > 0) + len + 1 > cap)
            return 0;
        if (n > 0)
            out[n++] = '/';
        memcpy(out + n, seg, len);
        n += len;
    }
    out[n] = '\0';
    return n > 0;
}

static const lucent_mesh_file *volume_find(const memory_volume *volume, const char *name)
{
    char path[1024];
    if (!normalize_path(name, path, sizeof path))
        return NULL;
    for (size_t i = 0; i < volume->count; i++)
        if (strcmp(volume->files[i].name, path) == 0)
            return &volume->files[i];
    return NULL;
}

static void note_refused(memory_volume *volume, const char *name)
{
    if (volume->refused_opens++ > 0)
        return;
    size_t n = 0;
    for (const char *c = name; *c && n + 1 < sizeof volume->missing; c++)
        volume->missing[n++] = *c >= 0x20 && *c < 0x7f && *c != '"' && *c != '\\' ? *c : '?';
    volume->missing[n] = '\0';
}

static struct aiFile *volume_open(struct aiFileIO *io, const char *name, const char *mode)
{
    memory_volume *volume = (memory_volume *)(void *)io->UserData;
    const lucent_mesh_file *source = strpbrk(mode, "wa+") ? NULL : volume_find(volume, name);
    if (!source) {
        note_refused(volume, name);
        return NULL;
    }
    memory_file *f = calloc(1, sizeof *f);
    if (!f)
        return NULL;
    f->file.ReadProc = file_read;
    f->file.WriteProc = file_write;
    f->file.TellProc = file_tell;
    f->file.FileSizeProc = file_size;
    f->file.SeekProc = file_seek;
    f->file.FlushProc = file_flush;
    f->source = source;
    return &f->file;
}

static void volume_close(struct aiFileIO *io, struct aiFile *file)
{
    (void)io;
    free(file);
}

/* ---- importing with assimp ---- */

/* assimp's error text can quote the input, so it goes to the log (printable ASCII only), never
 * into the error a client sees. */
static void log_import_failure(const char *label, const char *reason)
{
    char text[256];
    snprintf(text, sizeof text, "%s", reason);
    for (char *c = text; *c; c++)
        if ((unsigned char)*c < 0x20 || (unsigned char)*c > 0x7e)
            *c = '?';
    fprintf(stderr, "lucent: assimp could not import %s data: %s\n", label, text);
}

static unsigned primitive_type_of(unsigned index_count)
{
    switch (index_count) {
    case 1: return aiPrimitiveType_POINT;
    case 2: return aiPrimitiveType_LINE;
    case 3: return aiPrimitiveType_TRIANGLE;
    default: return aiPrimitiveType_POLYGON;
    }
}

/* Truncated files can leave faces without indices or a mesh whose declared primitive types its
 * faces contradict; assimp's triangulation then fails an assertion and aborts the process. */
static int faces_match_primitive_types(const struct aiScene *scene)
{
    const unsigned kinds = aiPrimitiveType_POINT | aiPrimitiveType_LINE |
                           aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON;
    for (unsigned i = 0; i < scene->mNumMeshes; i++) {
        const struct aiMesh *mesh = scene->mMeshes[i];
        unsigned seen = 0;
        if (mesh->mNumFaces && !mesh->mFaces)
            return 0;
        for (unsigned f = 0; f < mesh->mNumFaces; f++) {
            const struct aiFace *face = &mesh->mFaces[f];
            if (face->mNumIndices == 0 || !face->mIndices)
                return 0;
            seen |= primitive_type_of(face->mNumIndices);
        }
        if (seen != (mesh->mPrimitiveTypes & kinds))
            return 0;
    }
    return 1;
}

/* Imports through io (which serves only `name`), checks the raw scene, then post-processes it.
 * Returns NULL on failure, after logging why. */
static const struct aiScene *import_scene(struct aiFileIO *io, const char *name, const char *label)
{
    struct aiPropertyStore *props = aiCreatePropertyStore();
    if (!props)
        return NULL;
    aiSetImportPropertyInteger(props, AI_CONFIG_PP_RVC_FLAGS, UNUSED_COMPONENTS);
    const struct aiScene *scene =
        aiImportFileExWithProperties(name, aiProcess_ValidateDataStructure, io, props);
    aiReleasePropertyStore(props);
    if (!scene) {
        log_import_failure(label, aiGetErrorString());
        return NULL;
    }
    if (!faces_match_primitive_types(scene)) {
        log_import_failure(label, "faces contradict their mesh's primitive types");
        aiReleaseImport(scene);
        return NULL;
    }
    /* returns NULL only if a step failed, which these steps do not on a checked scene */
    const struct aiScene *processed = aiApplyPostProcessing(scene, POST_PROCESS_FLAGS);
    if (!processed)
        log_import_failure(label, aiGetErrorString());
    return processed;
}

/* ---- assimp scene to lucent_mesh ---- */

/* An affine transform as the top three rows of a row-major 4x4 matrix (assimp's layout). */
typedef struct affine {
    double m[3][4];
} affine;

static const affine IDENTITY = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

static affine affine_from_ai(const struct aiMatrix4x4 *t)
{
    affine a = {{{t->a1, t->a2, t->a3, t->a4}, {t->b1, t->b2, t->b3, t->b4},
                 {t->c1, t->c2, t->c3, t->c4}}};
    return a;
}

static affine affine_mul(const affine *a, const affine *b)
{
    affine r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            r.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] +
                        a->m[i][2] * b->m[2][j] + (j == 3 ? a->m[i][3] : 0);
    return r;
}

/* Cofactor matrix of the linear part: det * inverse-transpose, which maps normals without
 * dividing by a determinant that may be zero. Returns the determinant. */
static double normal_matrix(const affine *t, double n[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            n[i][j] = t->m[i1][j1] * t->m[i2][j2] - t->m[i1][j2] * t->m[i2][j1];
        }
    return t->m[0][0] * n[0][0] + t->m[0][1] * n[0][1] + t->m[0][2] * n[0][2];
}

/* Walks the node tree, placing every mesh each node references with the node's absolute
 * transform, as PreTransformVertices would. A first walk only counts (out == NULL), so limits are
 * enforced before memory is allocated for instanced copies. */
typedef struct scene_walk {
    const struct aiScene *scene;
    uint64_t *mesh_triangles;       /* faces with 3 indices, per scene mesh */
    struct lucent_mesh *out;
    uint64_t vertices, triangles;   /* counted or written so far */
    int any_normals;
} scene_walk;

static lucent_status place_instance(scene_walk *w, const struct aiMesh *mesh, const affine *t,
                                    lucent_error *err)
{
    struct lucent_mesh *m = w->out;
    double nt[3][3];
    double det = normal_matrix(t, nt);
    double side = det < 0 ? -1 : 1;
    uint32_t base = (uint32_t)w->vertices;
    for (unsigned v = 0; v < mesh->mNumVertices; v++) {
        const struct aiVector3D *p = &mesh->mVertices[v];
        float *dst = m->positions + 3 * ((size_t)base + v);
        for (int k = 0; k < 3; k++)
            dst[k] = (float)(t->m[k][0] * p->x + t->m[k][1] * p->y + t->m[k][2] * p->z + t->m[k][3]);
        if (!m->normals)
            continue;
        /* zero where the mesh has none: mesh_finish computes those */
        float *n = m->normals + 3 * ((size_t)base + v);
        const struct aiVector3D *src = mesh->mNormals ? &mesh->mNormals[v] : NULL;
        for (int k = 0; k < 3; k++)
            n[k] = src ? (float)(side * (nt[k][0] * src->x + nt[k][1] * src->y + nt[k][2] * src->z))
                       : 0.0f;
    }
    uint32_t *tri = m->indices + 3 * w->triangles;
    for (unsigned f = 0; f < mesh->mNumFaces; f++) {
        const struct aiFace *face = &mesh->mFaces[f];
        if (face->mNumIndices != 3)
            continue; /* points and lines */
        for (int k = 0; k < 3; k++) {
            /* checked per mesh: an index past this mesh would silently land in the next one */
            if (face->mIndices[k] >= mesh->mNumVertices)
                return lucent_fail(err, LUCENT_E_MESH, "mesh.file",
                                   "a face refers to a vertex that does not exist");
            /* a mirroring transform turns counter-clockwise faces clockwise: swap two corners */
            tri[det < 0 && k ? 3 - k : k] = base + face->mIndices[k];
        }
        tri += 3;
    }
    return LUCENT_OK;
}

static lucent_status walk_node(scene_walk *w, const struct aiNode *node, const affine *parent,
                               unsigned depth, lucent_error *err)
{
    if (depth > MAX_NODE_DEPTH)
        return lucent_fail(err, LUCENT_E_MESH, "mesh.file",
                           "the node hierarchy is more than %d levels deep", MAX_NODE_DEPTH);
    affine local = affine_from_ai(&node->mTransformation);
    affine world = affine_mul(parent, &local);
    for (unsigned i = 0; i < node->mNumMeshes; i++) {
        unsigned index = node->mMeshes[i];
        if (index >= w->scene->mNumMeshes || w->mesh_triangles[index] == 0)
            continue;
        const struct aiMesh *mesh = w->scene->mMeshes[index];
        if (w->out) {
            lucent_status st = place_instance(w, mesh, &world, err);
            if (st != LUCENT_OK)
                return st;
        }
        w->vertices += mesh->mNumVertices;
        w->triangles += w->mesh_triangles[index];
        w->any_normals |= mesh->mNormals != NULL;
        /* after JoinIdenticalVertices a vertex serves at least one face, so 3 per triangle */
        if (w->triangles > LUCENT_MAX_TRIANGLES || w->vertices > 3 * (uint64_t)LUCENT_MAX_TRIANGLES)
            return lucent_fail(err, LUCENT_E_LIMIT, "mesh.file",
                               "the file places more than %u triangles (or %u vertices); that is "
                               "the limit", LUCENT_MAX_TRIANGLES, 3 * LUCENT_MAX_TRIANGLES);
    }
    for (unsigned c = 0; c < node->mNumChildren; c++) {
        lucent_status st = walk_node(w, node->mChildren[c], &world, depth + 1, err);
        if (st != LUCENT_OK)
            return st;
    }
    return LUCENT_OK;
}

static uint64_t *count_mesh_triangles(const struct aiScene *scene)
{
    uint64_t *counts = calloc(scene->mNumMeshes ? scene->mNumMeshes : 1, sizeof *counts);
    if (!counts)
        return NULL;
    for (unsigned i = 0; i < scene->mNumMeshes; i++) {
        const struct aiMesh *mesh = scene->mMeshes[i];
        if (!mesh->mVertices)
            continue;
        for (unsigned f = 0; f < mesh->mNumFaces; f++)
            counts[i] += mesh->mFaces[f].mNumIndices == 3;
    }
    return counts;
}

static lucent_status scene_to_mesh(const struct aiScene *scene, struct lucent_mesh **out,
                                   lucent_error *err)
{
    lucent_status st;
    struct lucent_mesh *m = NULL;
    scene_walk w = {scene, count_mesh_triangles(scene), NULL, 0, 0, 0};
    if (!w.mesh_triangles)
        return lucent_fail(err, LUCENT_E_NOMEM, "mesh.file", "out of memory reading the scene");
    if ((st = walk_node(&w, scene->mRootNode, &IDENTITY, 0, err)) != LUCENT_OK)
        goto done;
    if (w.triangles == 0) {
        st = lucent_fail(err, LUCENT_E_MESH, "mesh.file", "the file contains no triangles");
        goto done;
    }
    if (!(m = mesh_alloc((uint32_t)w.vertices, (uint32_t)w.triangles, w.any_normals))) {
        st = lucent_fail(err, LUCENT_E_NOMEM, "mesh.file",
                         "out of memory for %llu vertices and %llu triangles",
                         (unsigned long long)w.vertices, (unsigned long long)w.triangles);
        goto done;
    }
    w.out = m;
    w.vertices = w.triangles = 0;
    if ((st = walk_node(&w, scene->mRootNode, &IDENTITY, 0, err)) != LUCENT_OK)
        goto done;
    m->convex = 0;
    if ((st = mesh_finish(m, err)) != LUCENT_OK) {
        /* mesh_finish cannot know where the mesh came from; here the file is to blame */
        if (err)
            snprintf(err->field, sizeof err->field, "mesh.file");
        goto done;
    }
    *out = m;
    m = NULL;

done:
    lucent_mesh_free(m);
    free(w.mesh_triangles);
    return st;
}

/* ---- public entry points ---- */

/* Checked before assimp runs: the main file's bytes, the names (relative and confined, see lucent.h),
 * and the total size. */
static lucent_status check_files(const lucent_mesh_file *files, size_t count, size_t main,
                                 const mesh_format *format, lucent_error *err)
{
    size_t total = 0;
    for (size_t i = 0; i < count; i++) {
        char path[1024];
        if (!files[i].name || !normalize_path(files[i].name, path, sizeof path) ||
            strcmp(path, files[i].name) != 0)
            return lucent_fail(err, LUCENT_E_INVALID, "mesh.file",
                               "file %zu's name is not a relative path without \".\" or \"..\"", i);
        if (files[i].len > MAX_MESH_BYTES - total)
            return lucent_fail(err, LUCENT_E_LIMIT, "mesh.file",
                               "the files are more than " MAX_MESH_BYTES_TEXT " together");
        total += files[i].len;
    }
    return check_bytes(format, files[main].data, files[main].len, err);
}

lucent_status lucent_mesh_import_files(const lucent_mesh_file *files, size_t count, size_t main,
                                       const char *ext_hint, lucent_mesh **out, lucent_error *err)
{
    *out = NULL;
    const mesh_format *format = find_format(ext_hint);
    if (!format)
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.file",
                           "unsupported mesh format \"%.16s\"; supported: " SUPPORTED_EXTENSIONS,
                           ext_hint ? ext_hint : "");
    if (main >= count)
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.file", "the main file is not among the files");
    lucent_status st = check_files(files, count, main, format, err);
    if (st != LUCENT_OK)
        return st;

    memory_volume volume = {files, count, 0, ""};
    /* assimp keeps a pointer to io until the scene is released, so both live in this frame */
    struct aiFileIO io = {volume_open, volume_close, (aiUserData)(void *)&volume};
    const struct aiScene *scene = import_scene(&io, files[main].name, format->label);
    if (!scene) {
        if (volume.refused_opens > 0 && count == 1)
            return lucent_fail(err, LUCENT_E_MESH, "mesh.file",
                               "could not read the %s data: it refers to other files (\"%s\": buffers, "
                               "images or material libraries), which are never opened; embed them (for "
                               "glTF, use .glb or data: URIs) or send them in the same upload",
                               format->label, volume.missing);
        if (volume.refused_opens > 0)
            return lucent_fail(err, LUCENT_E_MESH, "mesh.file",
                               "could not read the %s data: it refers to \"%s\", which is not among the "
                               "files sent", format->label, volume.missing);
        return lucent_fail(err, LUCENT_E_MESH, "mesh.file",
                           "could not read the %s data: it is malformed or uses a feature Lucent "
                           "does not support", format->label);
    }
    st = scene_to_mesh(scene, out, err);
    aiReleaseImport(scene);
    return st;
}

lucent_status lucent_mesh_import_memory(const void *data, size_t len, const char *ext_hint,
                                        lucent_mesh **out, lucent_error *err)
{
    char name[16];
    snprintf(name, sizeof name, "$$mem$$.%.6s", ext_hint ? ext_hint : "");
    lucent_mesh_file file = {name, data, len};
    return lucent_mesh_import_files(&file, 1, 0, ext_hint, out, err);
}

static const char *path_extension(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash + 1 : path, '.');
    return dot ? dot + 1 : "";
}

/* Reads a regular file of at most MAX_MESH_BYTES into a malloc'd buffer owned by the caller. */
static lucent_status read_whole_file(const char *path, unsigned char **data, size_t *len,
                                     lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    unsigned char *buf = NULL;
    struct stat info;
    /* Non-blocking, so that a FIFO planted at the path cannot hang the caller in open until a writer
     * comes; it is refused below with every other file that is not regular. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
    if (!f) {
        if (fd >= 0)
            close(fd);
        return lucent_fail(err, LUCENT_E_IO, "mesh.file", "cannot open \"%s\"", path);
    }
    if (fstat(fileno(f), &info) != 0 || !S_ISREG(info.st_mode)) {
        st = lucent_fail(err, LUCENT_E_IO, "mesh.file", "\"%s\" is not a regular file", path);
        goto done;
    }
    if ((uint64_t)info.st_size > MAX_MESH_BYTES) {
        st = lucent_fail(err, LUCENT_E_LIMIT, "mesh.file",
                         "\"%s\" is %lld bytes; at most " MAX_MESH_BYTES_TEXT " are accepted", path,
                         (long long)info.st_size);
        goto done;
    }
    size_t size = (size_t)info.st_size;
    if (!(buf = malloc(size ? size : 1))) {
        st = lucent_fail(err, LUCENT_E_NOMEM, "mesh.file", "out of memory reading \"%s\"", path);
        goto done;
    }
    if (fread(buf, 1, size, f) != size) {
        st = lucent_fail(err, LUCENT_E_IO, "mesh.file", "could not read \"%s\"", path);
        goto done;
    }
    *data = buf;
    *len = size;
    buf = NULL;

done:
    free(buf);
    fclose(f);
    return st;
}

/* Files starting with the compact form's magic (the mesh store's .lmesh) skip assimp. */
lucent_status lucent_mesh_import_file(const char *path, lucent_mesh **out, lucent_error *err)
{
    *out = NULL;
    const char *ext = path_extension(path);
    const mesh_format *format = find_format(ext);
    if (!format && strcasecmp(ext, MESH_COMPACT_EXTENSION) != 0)
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.file",
                           "\"%s\" is not a supported mesh file; supported: " SUPPORTED_EXTENSIONS
                           ", ." MESH_COMPACT_EXTENSION, path);
    unsigned char *data = NULL;
    size_t len = 0;
    lucent_status st = read_whole_file(path, &data, &len, err);
    if (st == LUCENT_OK && mesh_compact_detect(data, len))
        st = mesh_compact_read(data, len, out, err);
    else if (st == LUCENT_OK && format)
        st = lucent_mesh_import_memory(data, len, format->ext, out, err);
    else if (st == LUCENT_OK)
        st = lucent_fail(err, LUCENT_E_MESH, "mesh.file",
                         "\"%s\" does not start with the compact mesh magic", path);
    free(data);
    return st;
}
