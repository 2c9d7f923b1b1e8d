/* test_mesh_closed.c - mesh_orient_closed: closed builtins are recognized, an inside-out copy is turned
 * back outward (indices and normals as before), and open or inconsistent meshes are not "closed". */
#include "mesh.h"
#include "test_support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static struct lucent_mesh *builtin(const char *name)
{
    lucent_mesh *m = NULL;
    lucent_error err = {0};
    if (lucent_mesh_builtin(name, 0, &m, &err) != LUCENT_OK) {
        printf("FAIL %s: %s\n", name, err.message);
        exit(1);
    }
    return m;
}

static void recognizes_builtin(const char *name)
{
    struct lucent_mesh *m = builtin(name);
    size_t n = (size_t)m->triangle_count * 3;
    uint32_t *before = malloc(n * sizeof *before);
    memcpy(before, m->indices, n * sizeof *before);
    m->closed = 0;
    lucent_error err = {0};
    int ok = mesh_orient_closed(m, &err) == LUCENT_OK;
    test_check(ok && m->closed && memcmp(before, m->indices, n * sizeof *before) == 0,
               "%s (%u triangles): recognized closed and outward, left unchanged", name, m->triangle_count);
    free(before);
    lucent_mesh_free(m);
}

static void turns_inside_out_mesh_outward(void)
{
    struct lucent_mesh *m = builtin("protrusion");
    size_t n = (size_t)m->triangle_count * 3, v = (size_t)m->vertex_count * 3;
    uint32_t *indices = malloc(n * sizeof *indices);
    float *normals = malloc(v * sizeof *normals);
    memcpy(indices, m->indices, n * sizeof *indices);
    memcpy(normals, m->normals, v * sizeof *normals);
    for (size_t t = 0; t < m->triangle_count; t++) {
        uint32_t tmp = m->indices[t * 3 + 1];
        m->indices[t * 3 + 1] = m->indices[t * 3 + 2];
        m->indices[t * 3 + 2] = tmp;
    }
    for (size_t i = 0; i < v; i++)
        m->normals[i] = -m->normals[i];
    m->closed = 0;
    lucent_error err = {0};
    int ok = mesh_orient_closed(m, &err) == LUCENT_OK && m->closed;
    test_check(ok && memcmp(indices, m->indices, n * sizeof *indices) == 0 &&
                   memcmp(normals, m->normals, v * sizeof *normals) == 0,
               "inside-out protrusion turned back outward (winding and normals restored)");
    free(indices);
    free(normals);
    lucent_mesh_free(m);
}

static void open_and_inconsistent_meshes(void)
{
    struct lucent_mesh *m = builtin("sphere");
    lucent_error err = {0};
    m->closed = 0;
    m->triangle_count--;   /* a hole */
    mesh_orient_closed(m, &err);
    test_check(!m->closed, "sphere with one triangle removed is open");
    m->triangle_count++;
    uint32_t tmp = m->indices[1];   /* one triangle wound against its neighbours */
    m->indices[1] = m->indices[2];
    m->indices[2] = tmp;
    m->closed = 0;
    mesh_orient_closed(m, &err);
    test_check(!m->closed, "sphere with one flipped triangle is not consistently wound");
    lucent_mesh_free(m);
}

int main(void)
{
    recognizes_builtin("sphere");
    recognizes_builtin("torus");
    recognizes_builtin("protrusion");
    turns_inside_out_mesh_outward();
    open_and_inconsistent_meshes();
    return test_finish();
}
