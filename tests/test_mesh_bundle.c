/* test_mesh_bundle.c - multi-file meshes: lucent_mesh_import_files resolving a glTF's buffer against the
 * files given and nothing else (assimp also retries a missing name under other folders of the upload),
 * and mesh_bundle's name rules, canonical encoding and distrustful decoding. */
#include "lucent.h"
#include "mesh_bundle.h"
#include "test_support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One triangle whose positions live in the buffer `uri`. */
static void triangle_gltf(char *out, size_t cap, const char *uri)
{
    snprintf(out, cap,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
             "\"buffers\":[{\"uri\":\"%s\",\"byteLength\":36}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
             "\"min\":[0,0,0],\"max\":[1,1,0]}]}",
             uri);
}

static const float POSITIONS[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};

/* Imports `gltf_name` (naming `uri`) with the buffer stored as `bin_name`; returns the status. */
static lucent_status import_pair(const char *gltf_name, const char *uri, const char *bin_name, lucent_error *err,
                                 uint32_t *triangles)
{
    char gltf[1024];
    triangle_gltf(gltf, sizeof gltf, uri);
    lucent_mesh_file files[2] = {{gltf_name, gltf, strlen(gltf)}, {bin_name, POSITIONS, sizeof POSITIONS}};
    lucent_mesh *m = NULL;
    *err = (lucent_error){0};
    lucent_status st = lucent_mesh_import_files(files, 2, 0, "gltf", &m, err);
    *triangles = m ? lucent_mesh_triangle_count(m) : 0;
    lucent_mesh_free(m);
    return st;
}

static void resolving(void)
{
    static const struct {
        const char *gltf, *uri, *bin;
        int found;
    } cases[] = {
        {"tri.gltf", "tri.bin", "tri.bin", 1},
        {"scene/tri.gltf", "tri.bin", "scene/tri.bin", 1},
        {"scene/tri.gltf", "../data/tri.bin", "data/tri.bin", 1},
        {"scene/tri.gltf", "./tri.bin", "scene/tri.bin", 1},
        {"scene/tri.gltf", "tri.bin", "tri.bin", 0},          /* beside the upload's root, not the glTF */
        {"scene/tri.gltf", "../../../etc/tri.bin", "etc/tri.bin", 0}, /* climbs out of the upload */
        {"tri.gltf", "/proc/self/exe", "tri.bin", 0},         /* on disk, and long enough: never read */
        {"tri.gltf", "other.bin", "tri.bin", 0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        lucent_error err;
        uint32_t triangles;
        lucent_status st = import_pair(cases[i].gltf, cases[i].uri, cases[i].bin, &err, &triangles);
        int ok = cases[i].found ? st == LUCENT_OK && triangles == 1
                                : st == LUCENT_E_MESH && strstr(err.message, "not among the files sent");
        test_check(ok, "%s naming \"%s\", buffer sent as %s: %s, %u triangle(s) %s", cases[i].gltf, cases[i].uri,
                   cases[i].bin, lucent_status_name(st), triangles, err.message);
    }
    lucent_error err;
    uint32_t triangles;
    lucent_status st = import_pair("tri.gltf", "tri.bin", "../tri.bin", &err, &triangles);
    test_check(st == LUCENT_E_INVALID, "a file named \"../tri.bin\" is refused before assimp runs: %s (%s)",
               lucent_status_name(st), err.message);
    char gltf[1024];
    triangle_gltf(gltf, sizeof gltf, "tri.bin");
    lucent_mesh *m = NULL;
    st = lucent_mesh_import_memory(gltf, strlen(gltf), "gltf", &m, &err);
    test_check(st == LUCENT_E_MESH && strstr(err.message, "\"tri.bin\"") && strstr(err.message, "same upload"),
               "alone, the glTF is refused naming the file it needs: %s", err.message);
    lucent_mesh_free(m);
}

static lucent_status check_names(const char *const *names, size_t count, lucent_error *err)
{
    lucent_mesh_file files[MESH_BUNDLE_MAX_FILES + 1];
    for (size_t i = 0; i < count; i++)
        files[i] = (lucent_mesh_file){names[i], "x", 1};
    size_t main;
    const char *ext;
    *err = (lucent_error){0};
    return mesh_bundle_check(files, count, &main, &ext, err);
}

static void name_rules(void)
{
    static const struct {
        const char *names[3];
        size_t count;
        const char *why;
    } refused[] = {
        {{"a.gltf", "a.bin", "a.bin"}, 3, "a name twice"},
        {{"a.gltf", "b.obj"}, 2, "two mesh files"},
        {{"a.bin", "b.png"}, 2, "no mesh file"},
        {{"a.gltf", "../a.bin"}, 2, "a \"..\" segment"},
        {{"a.gltf", "x/./a.bin"}, 2, "a \".\" segment"},
        {{"a.gltf", "/a.bin"}, 2, "an absolute name"},
        {{"a.gltf", "x//a.bin"}, 2, "an empty segment"},
        {{"a.gltf", "x\\a.bin"}, 2, "a backslash"},
        {{"a.gltf", "a\tb.bin"}, 2, "a control character"},
        {{"a.gltf", "\xff.bin"}, 2, "a name that is not UTF-8"},
        {{"a.gltf", ""}, 2, "an empty name"},
    };
    lucent_error err;
    for (size_t i = 0; i < sizeof refused / sizeof refused[0]; i++) {
        lucent_status st = check_names(refused[i].names, refused[i].count, &err);
        test_check(st == LUCENT_E_INVALID && strcmp(err.field, "body") == 0, "refused, %s: %s (%s)", refused[i].why,
                   lucent_status_name(st), err.message);
    }
    const char *many[MESH_BUNDLE_MAX_FILES + 1];
    char names[MESH_BUNDLE_MAX_FILES + 1][16];
    for (int i = 0; i <= MESH_BUNDLE_MAX_FILES; i++) {
        snprintf(names[i], sizeof names[i], i ? "b%d.bin" : "a.gltf", i);
        many[i] = names[i];
    }
    test_check(check_names(many, MESH_BUNDLE_MAX_FILES, &err) == LUCENT_OK &&
                   check_names(many, MESH_BUNDLE_MAX_FILES + 1, &err) == LUCENT_E_INVALID,
               "%d files are taken, %d refused (%s)", MESH_BUNDLE_MAX_FILES, MESH_BUNDLE_MAX_FILES + 1, err.message);
    const char *good[] = {"textures/b.png", "Model.GLTF", "données/ä.bin"};
    lucent_mesh_file files[3];
    for (int i = 0; i < 3; i++)
        files[i] = (lucent_mesh_file){good[i], "x", 1};
    size_t main = 99;
    const char *ext = NULL;
    lucent_status st = mesh_bundle_check(files, 3, &main, &ext, &err);
    test_check(st == LUCENT_OK && ext && strcmp(ext, "gltf") == 0 && strcmp(files[main].name, "Model.GLTF") == 0 &&
                   strcmp(files[0].name, "Model.GLTF") == 0 && strcmp(files[2].name, "textures/b.png") == 0,
               "sorted by name, the mesh file found by its extension in any case (%s, %s), UTF-8 names taken: %s",
               files[main < 3 ? main : 0].name, ext ? ext : "none", lucent_status_name(st));
}

static void encoding(void)
{
    lucent_mesh_file one[3] = {{"m.obj", "v 0 0 0\n", 8}, {"m.mtl", "", 0}, {"tex/a.png", "\0\1\2", 3}};
    lucent_mesh_file two[3] = {one[2], one[0], one[1]};
    size_t main;
    const char *ext;
    lucent_error err = {0};
    unsigned char *a = NULL, *b = NULL;
    size_t alen = 0, blen = 0;
    mesh_bundle_check(one, 3, &main, &ext, &err);
    mesh_bundle_check(two, 3, &main, &ext, &err);
    lucent_status st = mesh_bundle_encode(one, 3, &a, &alen, &err);
    if (st == LUCENT_OK)
        st = mesh_bundle_encode(two, 3, &b, &blen, &err);
    test_check(st == LUCENT_OK && alen == blen && memcmp(a, b, alen) == 0,
               "the same files in another order encode to the same %zu bytes", alen);

    lucent_mesh_file back[MESH_BUNDLE_MAX_FILES];
    size_t count = 0;
    st = mesh_bundle_decode(a, alen, back, &count, &err);
    int same = st == LUCENT_OK && count == 3;
    for (size_t i = 0; same && i < 3; i++)
        same = strcmp(back[i].name, one[i].name) == 0 && back[i].len == one[i].len &&
               memcmp(back[i].data, one[i].data, one[i].len) == 0;
    test_check(same, "decoded: the three files, names and bytes as sent (%s)", lucent_status_name(st));

    size_t cut_accepted = 0;
    for (size_t n = 0; n < alen; n++)
        cut_accepted += mesh_bundle_decode(a, n, back, &count, &err) == LUCENT_OK;
    unsigned char *longer = malloc(alen + 1);
    memcpy(longer, a, alen);
    longer[alen] = 0;
    int trailing = mesh_bundle_decode(longer, alen + 1, back, &count, &err) == LUCENT_OK;
    test_check(cut_accepted == 0 && !trailing, "every one of the %zu shorter prefixes and one trailing byte refused",
               alen);
    /* the first name's NUL made part of the name, and two names swapped, by editing the bytes */
    memcpy(longer, a, alen);
    size_t first_name = 21 + 4 + 4; /* magic line, count, name length */
    longer[first_name + 1] = '\0';
    int inner_nul = mesh_bundle_decode(longer, alen, back, &count, &err) == LUCENT_OK;
    unsigned char *swapped = NULL;
    size_t slen = 0;
    lucent_mesh_file unsorted[2] = {{"b.bin", "1", 1}, {"a.gltf", "2", 1}};
    mesh_bundle_encode(unsorted, 2, &swapped, &slen, &err);
    int out_of_order = mesh_bundle_decode(swapped, slen, back, &count, &err) == LUCENT_OK;
    test_check(!inner_nul && !out_of_order, "a NUL inside a name and names out of order refused (%s)", err.message);
    free(swapped);
    free(longer);
    free(a);
    free(b);
}

int main(void)
{
    resolving();
    name_rules();
    encoding();
    return test_finish();
}
