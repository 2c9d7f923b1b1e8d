/* test_mesh_import.c - imports assimp's test models, the npm bunny and hostile bytes: good files load
 * clean, bad ones fail cleanly and read nothing else. Usage: test_mesh_import MODELS_ROOT BUNNY_OBJ */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* opendir, stat */
#endif

#include "lucent.h"
#include "mesh.h"
#include "test_support.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>


/* Describes what is wrong with a mesh the importer returned, or NULL when it is sound. */
static const char *mesh_problem(const struct lucent_mesh *m)
{
    if (!m || m->triangle_count == 0)
        return "no triangles";
    if (!(m->radius > 0) || !isfinite(m->radius))
        return "radius not positive";
    for (size_t i = 0; i < 3 * (size_t)m->triangle_count; i++)
        if (m->indices[i] >= m->vertex_count)
            return "index out of range";
    for (size_t v = 0; v < m->vertex_count; v++) {
        const float *p = m->positions + 3 * v, *n = m->normals + 3 * v;
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return "non-finite position";
        if (!(fabs(len - 1) < 1e-5))
            return "normal not finite and unit";
        if (sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]) > m->radius * (1 + 1e-6))
            return "vertex outside the radius";
    }
    return NULL;
}

static void expect_file_loads(const char *root, const char *rel, uint32_t triangles)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", root, rel);
    lucent_mesh *m = NULL;
    lucent_error err = {0};
    lucent_status st = lucent_mesh_import_file(path, &m, &err);
    if (!test_check(st == LUCENT_OK, "%s: loads (%s %s)", rel, lucent_status_name(st), err.message))
        return;
    const char *problem = mesh_problem(m);
    test_check(!problem && m->triangle_count == triangles && m->convex == 0,
          "%s: %u triangles (expected %u), %u vertices, radius %.4g, %s", rel, m->triangle_count,
          triangles, m->vertex_count, m->radius, problem ? problem : "finite unit normals");
    lucent_mesh_free(m);
}

static void expect_file_fails(const char *root, const char *rel, lucent_status status,
                              const char *message_part)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", root, rel);
    lucent_mesh *m = NULL;
    lucent_error err = {0};
    lucent_status st = lucent_mesh_import_file(path, &m, &err);
    test_check(st == status && !m && err.message[0] && strstr(err.message, message_part),
          "%s: fails with %s (%s: %s)", rel, lucent_status_name(status), lucent_status_name(st),
          err.message);
    lucent_mesh_free(m);
}

/* Imports bytes; returns the status and sets *wrong to what broke the importer's contract (a success
 * that is not a sound mesh, a failure without a message or that left a mesh), else NULL. */
static lucent_status import_bytes(const void *data, size_t len, const char *ext, lucent_error *err,
                                  uint32_t *triangles, const char **wrong)
{
    lucent_mesh *m = NULL;
    memset(err, 0, sizeof *err);
    lucent_status st = lucent_mesh_import_memory(data, len, ext, &m, err);
    *triangles = lucent_mesh_triangle_count(m);
    *wrong = NULL;
    if (st == LUCENT_OK && mesh_problem(m))
        *wrong = mesh_problem(m);
    if (st != LUCENT_OK && (!err->message[0] || m))
        *wrong = "failed without a message or left a mesh";
    lucent_mesh_free(m);
    return st;
}

static void expect_memory_fails(const char *what, const char *text, size_t len, const char *ext,
                                lucent_status status)
{
    lucent_error err;
    uint32_t triangles;
    const char *wrong;
    lucent_status st = import_bytes(text, len, ext, &err, &triangles, &wrong);
    test_check(st == status && err.message[0] && !wrong, "%s (as %s): %s, field \"%s\": %s%s%s", what, ext,
          lucent_status_name(st), err.field, err.message, wrong ? "; " : "", wrong ? wrong : "");
}

static void expect_memory_loads(const char *what, const char *text, const char *ext,
                                uint32_t triangles)
{
    lucent_error err;
    uint32_t got;
    const char *wrong;
    lucent_status st = import_bytes(text, strlen(text), ext, &err, &got, &wrong);
    test_check(st == LUCENT_OK && got == triangles && !wrong, "%s (as %s): %s, %u triangles (expected %u) %s%s",
          what, ext, lucent_status_name(st), got, triangles, err.message, wrong ? wrong : "");
}

/* ---- good files ---- */

static void check_models(const char *root)
{
    static const struct {
        const char *path;
        uint32_t triangles;
    } models[] = {
        {"OBJ/box.obj", 12},
        {"OBJ/spider.obj", 1312},
        {"OBJ/WusonOBJ.obj", 3732},
        {"OBJ/concave_polygon.obj", 64},      /* concave faces, triangulated */
        {"OBJ/cube_usemtl.obj", 12},          /* its mtllib is refused, the geometry still loads */
        {"OBJ/testmixed.obj", 12},            /* lines among the faces are dropped */
        {"OBJ/box_without_lineending.obj", 12},
        {"PLY/cube.ply", 12},                 /* ASCII */
        {"PLY/cube_binary.ply", 12},          /* binary */
        {"PLY/Wuson.ply", 3732},
        {"PLY/float-color.ply", 1},
        {"STL/Spider_ascii.stl", 1312},
        {"STL/Spider_binary.stl", 1312},
        {"STL/Wuson.stl", 3732},
        {"STL/sphereWithHole.stl", 285},
        {"STL/triangle_with_two_solids.stl", 2},
        {"glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf", 12},
        {"glTF2/simple_skin/simple_skin.gltf", 8},
        {"glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", 12},
        {"glTF2/BoxBadNormals-glTF-Binary/BoxBadNormals.glb", 12},
        {"glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", 110336},
    };
    for (size_t i = 0; i < sizeof models / sizeof models[0]; i++)
        expect_file_loads(root, models[i].path, models[i].triangles);

    /* files that exist and are well-formed, but must not load */
    expect_file_fails(root, "glTF2/BoxTextured-glTF/BoxTextured.gltf", LUCENT_E_MESH, "other files");
    expect_file_fails(root, "glTF2/IndexOutOfRange/IndexOutOfRange.gltf", LUCENT_E_MESH, "other files");
    expect_file_fails(root, "glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", LUCENT_E_MESH,
                      "finite");
    expect_file_fails(root, "glTF2/RecursiveNodes/RecursiveNodes.gltf", LUCENT_E_MESH, "");
    expect_file_fails(root, "OBJ/number_formats.obj", LUCENT_E_MESH, "no usable triangle");
    expect_file_fails(root, "OBJ/testpoints.obj", LUCENT_E_MESH, "no triangles");
    expect_file_fails(root, "OBJ/testline.obj", LUCENT_E_MESH, "no triangles");
    expect_file_fails(root, "PLY/points.ply", LUCENT_E_MESH, "");
    expect_file_fails(root, "3DS/fels.3ds", LUCENT_E_INVALID, ".glb");
    expect_file_fails(root, "OBJ/does-not-exist.obj", LUCENT_E_IO, "cannot open");
}

/* ---- the models' invalid folders ---- */

static int path_mentions_invalid(const char *path)
{
    for (const char *p = path; *p; p++)
        if (strncasecmp(p, "invalid", 7) == 0)
            return 1;
    return 0;
}

static unsigned char *read_all(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char *buf = NULL;
    struct stat info;
    if (fstat(fileno(f), &info) == 0 && (buf = malloc((size_t)info.st_size + 1)))
        *len = fread(buf, 1, (size_t)info.st_size, f);
    fclose(f);
    return buf;
}

/* Through the file entry point (format from the name), and its bytes declared as every format. */
static void check_invalid_file(const char *path)
{
    lucent_mesh *m = NULL;
    lucent_error err = {0};
    lucent_status st = lucent_mesh_import_file(path, &m, &err);
    if (st == LUCENT_OK) {
        const char *problem = mesh_problem(m);
        test_check(!problem, "%s: imports anyway (%u triangles); result is %s", path, m->triangle_count,
              problem ? problem : "sound");
    } else {
        test_check(err.message[0] && !m, "%s: fails with %s: %s", path, lucent_status_name(st),
              err.message);
    }
    lucent_mesh_free(m);

    static const char *exts[] = {"obj", "ply", "stl", "gltf", "glb"};
    size_t len = 0;
    unsigned char *bytes = read_all(path, &len);
    if (!test_check(bytes != NULL, "%s: readable", path))
        return;
    char outcomes[512] = "";
    int kept = 1;
    for (size_t i = 0; i < 5; i++) {
        uint32_t triangles;
        const char *wrong;
        st = import_bytes(bytes, len, exts[i], &err, &triangles, &wrong);
        kept = kept && !wrong;
        size_t used = strlen(outcomes);
        snprintf(outcomes + used, sizeof outcomes - used, " %s:%s%s%s", exts[i],
                 st == LUCENT_OK ? "loads" : lucent_status_name(st), wrong ? " BROKEN " : "", wrong ? wrong : "");
    }
    test_check(kept, "%s: as bytes of each format, a sound mesh or an error with a message:%s", path, outcomes);
    free(bytes);
}

static void walk_invalid(const char *dir, int inside_invalid, int *count)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    for (struct dirent *e; (e = readdir(d));) {
        if (e->d_name[0] == '.')
            continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        struct stat info;
        if (stat(path, &info) != 0)
            continue;
        int invalid = inside_invalid || path_mentions_invalid(e->d_name);
        if (S_ISDIR(info.st_mode)) {
            walk_invalid(path, invalid, count);
        } else if (invalid && S_ISREG(info.st_mode)) {
            check_invalid_file(path);
            (*count)++;
        }
    }
    closedir(d);
}

/* ---- hostile bytes ---- */

#define TRIANGLE_OBJ "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"

/* Positions (0,0,0) (1,0,0) (0,1,0), then three +Z normals, float32 little-endian. */
#define TRIANGLE_BIN_BASE64                                                                   \
    "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/"

/* A one-triangle glTF whose only buffer lives at uri; node_extra is added to the node. */
static void write_gltf(char *out, size_t cap, const char *uri, const char *node_extra)
{
    snprintf(out, cap,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
             "\"nodes\":[{\"mesh\":0%s}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1}}]}],"
             "\"buffers\":[{\"uri\":\"%s\",\"byteLength\":72}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":72}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
             "\"min\":[0,0,0],\"max\":[1,1,0]},"
             "{\"bufferView\":0,\"byteOffset\":36,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}]}",
             node_extra, uri);
}

/* A real, valid buffer on disk: if the importer could open paths, this one would load. */
static const char *write_canary_buffer(void)
{
    static char path[64];
    static const unsigned char floats[72] = {
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x80, 0x3f, 0, 0, 0, 0, 0, 0, 0, 0,
        0, 0, 0, 0, 0, 0, 0x80, 0x3f, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x80, 0x3f,
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x80, 0x3f, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x80, 0x3f};
    snprintf(path, sizeof path, "/tmp/lucent_canary_%ld.bin", (long)getpid());
    FILE *f = fopen(path, "wb");
    if (!f)
        return NULL;
    fwrite(floats, 1, sizeof floats, f);
    fclose(f);
    return path;
}

static void check_external_references(void)
{
    char gltf[2048];
    write_gltf(gltf, sizeof gltf, "data:application/octet-stream;base64," TRIANGLE_BIN_BASE64, "");
    expect_memory_loads("glTF with its buffer embedded (control)", gltf, "gltf", 1);

    static const char *uris[] = {"/etc/passwd", "../../../../../../etc/passwd", "/proc/self/environ"};
    for (size_t i = 0; i < sizeof uris / sizeof uris[0]; i++) {
        char what[96];
        snprintf(what, sizeof what, "glTF buffer uri \"%s\"", uris[i]);
        write_gltf(gltf, sizeof gltf, uris[i], "");
        expect_memory_fails(what, gltf, strlen(gltf), "gltf", LUCENT_E_MESH);
    }
    const char *canary = write_canary_buffer();
    if (test_check(canary != NULL, "canary buffer written")) {
        write_gltf(gltf, sizeof gltf, canary, "");
        expect_memory_fails("glTF buffer uri naming a valid buffer on disk", gltf, strlen(gltf),
                            "gltf", LUCENT_E_MESH);
        remove(canary);
    }

    static const char *mtllibs[] = {"/etc/passwd", "/proc/self/environ", "../../../etc/shadow"};
    for (size_t i = 0; i < sizeof mtllibs / sizeof mtllibs[0]; i++) {
        char obj[256], what[96];
        snprintf(obj, sizeof obj, "mtllib %s\nusemtl root\n" TRIANGLE_OBJ, mtllibs[i]);
        snprintf(what, sizeof what, "OBJ with mtllib %s", mtllibs[i]);
        expect_memory_loads(what, obj, "obj", 1);
    }
}

/* Node transforms are baked in: translation and scale move the triangle, a mirroring scale keeps
 * its winding consistent with its (transformed) normals. */
static void check_node_transforms(void)
{
    char gltf[2048];
    write_gltf(gltf, sizeof gltf, "data:application/octet-stream;base64," TRIANGLE_BIN_BASE64,
               ",\"translation\":[10,0,0],\"scale\":[-2,2,2]");
    lucent_mesh *m = NULL;
    lucent_error err = {0};
    lucent_status st = lucent_mesh_import_memory(gltf, strlen(gltf), "gltf", &m, &err);
    if (!test_check(st == LUCENT_OK, "mirrored, scaled, translated glTF node loads (%s)", err.message))
        return;
    /* the triangle spans x in [8, 10], y in [0, 2]: box centre (9, 1, 0) */
    double face[3], e1[3], e2[3];
    const float *p = m->positions;
    const uint32_t *t = m->indices;
    for (int k = 0; k < 3; k++) {
        e1[k] = p[3 * t[1] + k] - p[3 * t[0] + k];
        e2[k] = p[3 * t[2] + k] - p[3 * t[0] + k];
    }
    face[2] = e1[0] * e2[1] - e1[1] * e2[0];
    test_check(fabs(m->center[0] - 9) < 1e-6 && fabs(m->center[1] - 1) < 1e-6 && fabs(m->radius - sqrt(2)) < 1e-6,
          "transform baked: centre (%.3f, %.3f, %.3f), radius %.4f", m->center[0], m->center[1],
          m->center[2], m->radius);
    test_check(face[2] > 0 && m->normals[2] > 0.999,
          "mirrored triangle still winds counter-clockwise around its normal (face z %.2f, normal z %.3f)",
          face[2], m->normals[2]);
    lucent_mesh_free(m);
}

static void check_hostile_bytes(void)
{
    static const char *exts[] = {"obj", "ply", "stl", "gltf", "glb"};
    for (size_t i = 0; i < 5; i++) {
        expect_memory_fails("empty buffer", "", 0, exts[i], LUCENT_E_MESH);
        expect_memory_fails("NULL empty buffer", NULL, 0, exts[i], LUCENT_E_MESH);
    }

    /* PLY without end_header: assimp would loop forever */
    static const char ply_open[] = "ply\nformat ascii 1.0\n";
    static const char ply_comment[] = "ply\nformat ascii 1.0\ncomment end_header\nelement vertex 3\n";
    static const char ply_upper[] = "PLY\nformat ascii 1.0\nEND_HEADER\n";
    expect_memory_fails("PLY header without end_header", ply_open, strlen(ply_open), "ply", LUCENT_E_MESH);
    expect_memory_fails("PLY with end_header only in a comment", ply_comment, strlen(ply_comment),
                        "ply", LUCENT_E_MESH);
    expect_memory_fails("PLY with END_HEADER in capitals", ply_upper, strlen(ply_upper), "ply",
                        LUCENT_E_MESH);
    for (size_t i = 0; i < 5; i++)
        expect_memory_fails("PLY bytes without end_header", ply_open, strlen(ply_open), exts[i],
                            LUCENT_E_MESH);

    /* counts the data cannot hold, which assimp allocates for before reading any (found by fuzz_import):
     * 1000 vertices declared and 3 present imported before; 80 million cost lucent-import 1 GB and 8 s,
     * then a crash; an unknown element name is read as the count, here 2^32 - 1 (100 GB asked for) */
    static const char ply_overcount[] =
        "ply\nformat ascii 1.0\nelement vertex 1000\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    static const char ply_wrapped[] = "ply\nformat ascii 1.0\nelement 4294967295 1\nproperty float x\n"
                                      "end_header\n0 0 0\n1 0 0\n0 1 0\n";
    for (size_t i = 0; i < 6; i++) {
        const char *text = i < 5 ? ply_overcount : ply_wrapped, *ext = i < 5 ? exts[i] : "ply";
        lucent_error err;
        uint32_t triangles;
        const char *wrong;
        lucent_status st = import_bytes(text, strlen(text), ext, &err, &triangles, &wrong);
        test_check(st == LUCENT_E_MESH && strstr(err.message, "declares more elements") && !wrong,
                   "PLY declaring %s, more than its data holds (as %s): %s: %s",
                   i < 5 ? "1000 vertices" : "2^32 - 1 instances", ext, lucent_status_name(st), err.message);
    }

    /* a second vertex or face element: assimp sizes the mesh by the first and writes the second past
     * it, a heap overflow (found by fuzz_import against an ASan-built assimp); the faces one imported */
    static const char ply_two_vertex[] =
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
        "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n0 0 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    static const char ply_two_face[] =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nelement tristrips 2\n"
        "property list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n3 0 2 1\n";
    for (size_t i = 0; i < 2; i++) {
        const char *text = i ? ply_two_face : ply_two_vertex;
        lucent_error err;
        uint32_t triangles;
        const char *wrong;
        lucent_status st = import_bytes(text, strlen(text), "ply", &err, &triangles, &wrong);
        test_check(st == LUCENT_E_MESH && strstr(err.message, "second vertex or face") && !wrong,
                   "PLY with a second %s element: %s: %s", i ? "face (tristrips)" : "vertex", lucent_status_name(st),
                   err.message);
    }

    /* truncated in the vertex list: faces without indices abort assimp's triangulation */
    static const char ply_cut[] =
        "ply\nformat ascii 1.0\nelement vertex 8\nproperty float32 x\nproperty float32 y\n"
        "property float32 z\nelement face 6\nproperty list uint8 int32 vertex_index\nend_header\n"
        "0 0 0\n0 0 1\n0 1";
    expect_memory_fails("PLY truncated in its vertex list", ply_cut, strlen(ply_cut), "ply",
                        LUCENT_E_MESH);

    /* random bytes, fixed seed */
    static unsigned char noise[4096];
    uint32_t state = 12345;
    for (size_t i = 0; i < sizeof noise; i++) {
        state = state * 1664525u + 1013904223u;
        noise[i] = (unsigned char)(state >> 24);
    }
    for (size_t i = 0; i < 5; i++)
        expect_memory_fails("4 KiB of random bytes", (const char *)noise, sizeof noise, exts[i],
                            LUCENT_E_MESH);

    static const char nan_obj[] = "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    static const char inf_obj[] = "v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    static const char range_obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
    static const char negative_obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9\n";
    static const char degenerate_obj[] = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 4\nf 4 4 4\n";
    expect_memory_fails("OBJ with a NaN coordinate", nan_obj, strlen(nan_obj), "obj", LUCENT_E_MESH);
    expect_memory_fails("OBJ with a coordinate beyond float range", inf_obj, strlen(inf_obj), "obj",
                        LUCENT_E_MESH);
    expect_memory_fails("OBJ face index past the end", range_obj, strlen(range_obj), "obj",
                        LUCENT_E_MESH);
    expect_memory_fails("OBJ negative face index past the start", negative_obj,
                        strlen(negative_obj), "obj", LUCENT_E_MESH);
    expect_memory_fails("OBJ of only degenerate triangles", degenerate_obj, strlen(degenerate_obj),
                        "obj", LUCENT_E_MESH);
    expect_memory_loads("OBJ triangle (control)", TRIANGLE_OBJ, "obj", 1);

    /* declared glTF, but assimp would hand it to another reader by content */
    expect_memory_fails("OBJ text declared as glTF", TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "gltf",
                        LUCENT_E_MESH);
    static const char gltf_v1[] = "{\"asset\":{\"version\":\"1.0\"}}";
    expect_memory_fails("glTF 1.0", gltf_v1, strlen(gltf_v1), "gltf", LUCENT_E_MESH);
    size_t depth = 100000;
    char *deep = malloc(depth + 64);
    if (deep) {
        int n = sprintf(deep, "{\"asset\":{\"version\":\"2.0\"},\"x\":");
        memset(deep + n, '[', depth);
        expect_memory_fails("glTF nested 100000 deep", deep, (size_t)n + depth, "gltf", LUCENT_E_MESH);
        free(deep);
    }
    static const char glb_short[] = "glTF\x02\0\0\0\x0c\0\0\0";
    expect_memory_fails("GLB header only", glb_short, sizeof glb_short - 1, "glb", LUCENT_E_MESH);
    static const char stl_short[] = "not an stl";
    expect_memory_fails("STL of the wrong size", stl_short, strlen(stl_short), "stl", LUCENT_E_MESH);

    expect_memory_fails("unknown format", TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), "fbx", LUCENT_E_INVALID);
    lucent_error err = {0};
    lucent_mesh *m = NULL;
    lucent_status st = lucent_mesh_import_memory(TRIANGLE_OBJ, strlen(TRIANGLE_OBJ), NULL, &m, &err);
    test_check(st == LUCENT_E_INVALID && strcmp(err.field, "mesh.file") == 0,
          "no format given: %s, field \"%s\"", lucent_status_name(st), err.field);
    char dir[64];
    snprintf(dir, sizeof dir, "/tmp/lucent_dir_%ld.obj", (long)getpid());
    if (test_check(mkdir(dir, 0700) == 0, "made directory %s", dir)) {
        st = lucent_mesh_import_file(dir, &m, &err);
        test_check(st == LUCENT_E_IO && !m, "a directory named like a mesh: %s: %s", lucent_status_name(st),
              err.message);
        rmdir(dir);
    }
    st = lucent_mesh_import_file("/tmp", &m, &err);
    test_check(st == LUCENT_E_INVALID && strcmp(err.field, "mesh.file") == 0,
          "a path without a mesh extension: %s: %s", lucent_status_name(st), err.message);
}

/* ---- the bunny ---- */

static uint32_t count_obj_faces(const char *path)
{
    FILE *f = fopen(path, "r");
    uint32_t faces = 0;
    char line[256];
    while (f && fgets(line, sizeof line, f))
        faces += line[0] == 'f' && line[1] == ' ';
    if (f)
        fclose(f);
    return faces;
}

static void check_bunny(const char *path)
{
    lucent_mesh *m = NULL;
    lucent_error err = {0};
    lucent_status st = lucent_mesh_import_file(path, &m, &err);
    if (!test_check(st == LUCENT_OK, "bunny %s loads (%s %s)", path, lucent_status_name(st), err.message))
        return;
    uint32_t faces = count_obj_faces(path);
    const char *problem = mesh_problem(m);
    test_check(!problem && m->triangle_count == faces && faces > 1000,
          "bunny: %u triangles (the file has %u faces), %u vertices, radius %.4f, %s",
          m->triangle_count, faces, m->vertex_count, m->radius, problem ? problem : "sound");
    lucent_mesh_free(m);
}

/* A FIFO planted where a mesh file should be: refused at once, not waited on for a writer (the daemon's
 * one render worker would hang there). The alarm turns a hang into a failure. */
static void check_fifo(void)
{
    char path[128];
    snprintf(path, sizeof path, "/tmp/lucent-fifo-%ld.obj", (long)getpid());
    unlink(path);
    if (!test_check(mkfifo(path, 0600) == 0, "made a FIFO at %s", path))
        return;
    alarm(10);
    lucent_mesh *m = NULL;
    lucent_error err = {0};
    lucent_status st = lucent_mesh_import_file(path, &m, &err);
    alarm(0);
    test_check(st == LUCENT_E_IO && !m, "a FIFO as a mesh file is refused at once: %s", err.message);
    lucent_mesh_free(m);
    unlink(path);
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: %s MODELS_ROOT BUNNY_OBJ\n", argv[0]);
        return 2;
    }
    check_models(argv[1]);
    int invalid_files = 0;
    walk_invalid(argv[1], 0, &invalid_files);
    test_check(invalid_files > 0, "found %d files under invalid folders", invalid_files);
    check_external_references();
    check_node_transforms();
    check_hostile_bytes();
    check_fifo();
    check_bunny(argv[2]);
    return test_finish();
}
