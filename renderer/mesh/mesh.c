/* mesh.c - lifetime of lucent_mesh and mesh_finish, the gate every importer and generator passes:
 * validation, removal of degenerate triangles and unused vertices, recentring and unit normals. */
#include "mesh.h"
#include "linalg.h"
#include "mesh_normals.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* A triangle smaller than this fraction of the bounding box's squared diagonal has sides near
 * float resolution (~1e-7 of the box), so its orientation is rounding noise: it is dropped. */
#define DEGENERATE_AREA_FRACTION 1e-14

/* malloc for count items that returns NULL only when memory (or size_t) runs out, never for 0. */
static void *alloc_items(size_t count, size_t item_size)
{
    if (count > SIZE_MAX / item_size)
        return NULL;
    return malloc(count ? count * item_size : 1);
}

struct lucent_mesh *mesh_alloc(uint32_t vertex_count, uint32_t triangle_count, int with_normals)
{
    struct lucent_mesh *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    m->vertex_count = vertex_count;
    m->triangle_count = triangle_count;
    m->positions = alloc_items(3 * (size_t)vertex_count, sizeof *m->positions);
    m->indices = alloc_items(3 * (size_t)triangle_count, sizeof *m->indices);
    if (with_normals)
        m->normals = alloc_items(3 * (size_t)vertex_count, sizeof *m->normals);
    if (!m->positions || !m->indices || (with_normals && !m->normals)) {
        lucent_mesh_free(m);
        return NULL;
    }
    return m;
}

void lucent_mesh_free(lucent_mesh *mesh)
{
    if (!mesh)
        return;
    free(mesh->positions);
    free(mesh->normals);
    free(mesh->indices);
    free(mesh);
}

uint32_t lucent_mesh_triangle_count(const lucent_mesh *mesh)
{
    return mesh ? mesh->triangle_count : 0;
}

static lucent_status check_counts(const struct lucent_mesh *m, lucent_error *err)
{
    if (m->triangle_count == 0)
        return lucent_fail(err, LUCENT_E_MESH, "mesh", "the mesh has no triangles");
    if (m->triangle_count > LUCENT_MAX_TRIANGLES)
        return lucent_fail(err, LUCENT_E_LIMIT, "mesh",
                           "the mesh has %u triangles; at most %u are allowed",
                           m->triangle_count, LUCENT_MAX_TRIANGLES);
    return LUCENT_OK;
}

static lucent_status check_indices(const struct lucent_mesh *m, lucent_error *err)
{
    size_t n = 3 * (size_t)m->triangle_count;
    for (size_t i = 0; i < n; i++)
        if (m->indices[i] >= m->vertex_count)
            return lucent_fail(err, LUCENT_E_MESH, "mesh",
                               "triangle %zu refers to vertex %u, but the mesh has only %u vertices",
                               i / 3, m->indices[i], m->vertex_count);
    return LUCENT_OK;
}

static lucent_status check_positions(const struct lucent_mesh *m, lucent_error *err)
{
    size_t n = 3 * (size_t)m->vertex_count;
    for (size_t i = 0; i < n; i++)
        if (!isfinite(m->positions[i]))
            return lucent_fail(err, LUCENT_E_MESH, "mesh",
                               "vertex %zu has a coordinate that is not a finite number", i / 3);
    return LUCENT_OK;
}

/* Squared diagonal of the box around the vertices that triangles use (unused ones may lie anywhere). */
static double used_diagonal_squared(const struct lucent_mesh *m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    size_t n = 3 * (size_t)m->triangle_count;
    for (size_t i = 0; i < n; i++) {
        const float *p = m->positions + 3 * (size_t)m->indices[i];
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], p[k]);
            hi[k] = fmax(hi[k], p[k]);
        }
    }
    double d2 = 0;
    for (int k = 0; k < 3; k++)
        d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return d2;
}

static void triangle_cross(const float *positions, const uint32_t *tri, double out[3])
{
    const float *a = positions + 3 * (size_t)tri[0];
    const float *b = positions + 3 * (size_t)tri[1];
    const float *c = positions + 3 * (size_t)tri[2];
    double e1[3] = {(double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2]};
    double e2[3] = {(double)c[0] - a[0], (double)c[1] - a[1], (double)c[2] - a[2]};
    out[0] = e1[1] * e2[2] - e1[2] * e2[1];
    out[1] = e1[2] * e2[0] - e1[0] * e2[2];
    out[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

static int triangle_is_degenerate(const float *positions, const uint32_t *tri, double min_area)
{
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
        return 1;
    double c[3];
    triangle_cross(positions, tri, c);
    /* <= so that a mesh collapsed to one point (min_area 0) loses every triangle */
    return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) <= min_area;
}

static void drop_degenerate_triangles(struct lucent_mesh *m)
{
    double min_area = DEGENERATE_AREA_FRACTION * used_diagonal_squared(m);
    uint32_t kept = 0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->indices + 3 * (size_t)t;
        if (triangle_is_degenerate(m->positions, tri, min_area))
            continue;
        uint32_t *dst = m->indices + 3 * (size_t)kept++;
        dst[0] = tri[0];
        dst[1] = tri[1];
        dst[2] = tri[2];
    }
    m->triangle_count = kept;
}

/* A triangle as its indices rotated to start at the smallest (winding kept), and where it stood. */
struct tri_key {
    uint32_t v[3];
    uint32_t t;
};

static int compare_tri_keys(const void *pa, const void *pb)
{
    const struct tri_key *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->v[k] != b->v[k])
            return a->v[k] < b->v[k] ? -1 : 1;
    return (a->t > b->t) - (a->t < b->t);
}

/* A face listed twice is one surface, not two: a second copy would double its irradiance points in
 * the reference and its weight in smooth normals. The same face wound the other way is kept. */
static lucent_status drop_duplicate_triangles(struct lucent_mesh *m, lucent_error *err)
{
    uint32_t n = m->triangle_count;
    struct tri_key *keys = alloc_items(n, sizeof *keys);
    unsigned char *drop = calloc(n ? n : 1, 1);
    if (!keys || !drop) {
        free(keys);
        free(drop);
        return lucent_fail(err, LUCENT_E_NOMEM, "mesh", "out of memory checking %u triangles", n);
    }
    for (uint32_t t = 0; t < n; t++) {
        const uint32_t *tri = m->indices + 3 * (size_t)t;
        int first = tri[1] < tri[0] ? (tri[2] < tri[1] ? 2 : 1) : (tri[2] < tri[0] ? 2 : 0);
        for (int k = 0; k < 3; k++)
            keys[t].v[k] = tri[(first + k) % 3];
        keys[t].t = t;
    }
    qsort(keys, n, sizeof *keys, compare_tri_keys);
    for (uint32_t i = 1; i < n; i++)
        drop[keys[i].t] = memcmp(keys[i].v, keys[i - 1].v, sizeof keys[i].v) == 0;
    uint32_t kept = 0;
    for (uint32_t t = 0; t < n; t++)
        if (!drop[t])
            memmove(m->indices + 3 * (size_t)kept++, m->indices + 3 * (size_t)t, 3 * sizeof *m->indices);
    m->triangle_count = kept;
    free(keys);
    free(drop);
    return LUCENT_OK;
}

/* Renumbers the used vertices densely in their original order, moving their data down in place. */
static lucent_status drop_unused_vertices(struct lucent_mesh *m, lucent_error *err)
{
    uint32_t *remap = alloc_items(m->vertex_count, sizeof *remap);
    if (!remap)
        return lucent_fail(err, LUCENT_E_NOMEM, "mesh", "out of memory compacting %u vertices",
                           m->vertex_count);
    size_t n = 3 * (size_t)m->triangle_count;
    for (uint32_t v = 0; v < m->vertex_count; v++)
        remap[v] = UINT32_MAX;
    for (size_t i = 0; i < n; i++)
        remap[m->indices[i]] = 0;

    uint32_t kept = 0;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        if (remap[v] == UINT32_MAX)
            continue;
        remap[v] = kept;
        for (int k = 0; k < 3; k++) {
            m->positions[3 * (size_t)kept + k] = m->positions[3 * (size_t)v + k];
            if (m->normals)
                m->normals[3 * (size_t)kept + k] = m->normals[3 * (size_t)v + k];
        }
        kept++;
    }
    for (size_t i = 0; i < n; i++)
        m->indices[i] = remap[m->indices[i]];
    m->vertex_count = kept;
    free(remap);
    return LUCENT_OK;
}

/* Sets center (box centre, in double) and radius, and makes positions relative to the centre. */
static lucent_status recentre(struct lucent_mesh *m, lucent_error *err)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < m->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->positions[3 * (size_t)v + k]);
            hi[k] = fmax(hi[k], m->positions[3 * (size_t)v + k]);
        }
    for (int k = 0; k < 3; k++)
        m->center[k] = 0.5 * (lo[k] + hi[k]);

    double r2 = 0;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        float *p = m->positions + 3 * (size_t)v;
        double d2 = 0;
        for (int k = 0; k < 3; k++) {
            double d = p[k] - m->center[k];
            d2 += d * d;
            p[k] = (float)d;
        }
        r2 = fmax(r2, d2);
    }
    m->radius = sqrt(r2);
    if (!(m->radius > 0) || !isfinite(m->radius))
        return lucent_fail(err, LUCENT_E_MESH, "mesh", "the mesh has no extent (bounding radius %g)",
                           m->radius);
    return LUCENT_OK;
}

lucent_status mesh_finish(struct lucent_mesh *m, lucent_error *err)
{
    lucent_status st;
    if ((st = check_counts(m, err)) != LUCENT_OK || (st = check_indices(m, err)) != LUCENT_OK ||
        (st = check_positions(m, err)) != LUCENT_OK)
        return st;

    uint32_t submitted = m->triangle_count;
    drop_degenerate_triangles(m);
    if (m->triangle_count == 0)
        return lucent_fail(err, LUCENT_E_MESH, "mesh",
                           "no usable triangle: all %u have a repeated vertex or zero area",
                           submitted);

    if ((st = drop_duplicate_triangles(m, err)) != LUCENT_OK || (st = drop_unused_vertices(m, err)) != LUCENT_OK ||
        (st = recentre(m, err)) != LUCENT_OK ||
        (st = mesh_fill_normals(m, err)) != LUCENT_OK)
        return st;
    return m->closed ? LUCENT_OK : mesh_orient_closed(m, err);
}

/* ---- normals (declared in mesh_normals.h, shared with the proxy simplifier) ---- */

static int normal_is_usable(const float *n)
{
    double len2 = (double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2];
    return isfinite(len2) && len2 > 0;
}

/* Writes v normalized to out; where v has no direction, the direction from the centre to the
 * vertex (outward on closed meshes) stands in, and +Z at the centre itself. */
static void write_unit(float *out, const double v[3], const float *position)
{
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 0 && isfinite(len)) {
        for (int k = 0; k < 3; k++)
            out[k] = (float)(v[k] / len);
        return;
    }
    double radial[3] = {position[0], position[1], position[2]};
    double radial_len = sqrt(radial[0] * radial[0] + radial[1] * radial[1] + radial[2] * radial[2]);
    for (int k = 0; k < 3; k++)
        out[k] = radial_len > 0 ? (float)(radial[k] / radial_len) : (k == 2 ? 1.0f : 0.0f);
}

/* Adds each face's cross product (twice its area, so larger faces weigh more) to its vertices. */
static void accumulate_face_normals(const struct lucent_mesh *m, double *sums)
{
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->indices + 3 * (size_t)t;
        double c[3];
        triangle_cross(m->positions, tri, c);
        for (int corner = 0; corner < 3; corner++)
            for (int k = 0; k < 3; k++)
                sums[3 * (size_t)tri[corner] + k] += c[k];
    }
}

lucent_status mesh_fill_normals(struct lucent_mesh *m, lucent_error *err)
{
    size_t n = 3 * (size_t)m->vertex_count;
    int replace_all = m->normals == NULL;
    if (replace_all && !(m->normals = alloc_items(n, sizeof *m->normals)))
        return lucent_fail(err, LUCENT_E_NOMEM, "mesh", "out of memory for %u normals",
                           m->vertex_count);
    double *sums = calloc(n ? n : 1, sizeof *sums);
    if (!sums)
        return lucent_fail(err, LUCENT_E_NOMEM, "mesh", "out of memory for %u normals", m->vertex_count);
    accumulate_face_normals(m, sums);
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        float *normal = m->normals + 3 * (size_t)v;
        const float *position = m->positions + 3 * (size_t)v;
        const double *faces = sums + 3 * (size_t)v;
        if (replace_all || !normal_is_usable(normal)) {
            write_unit(normal, faces, position);
            continue;
        }
        /* Files may carry flipped normals: the winding decides which side is outside, for the
         * raster passes as for the reference (mesh_surface_at). */
        double given[3] = {normal[0], normal[1], normal[2]};
        double sign = given[0] * faces[0] + given[1] * faces[1] + given[2] * faces[2] < 0.0 ? -1.0 : 1.0;
        for (int k = 0; k < 3; k++)
            given[k] *= sign;
        write_unit(normal, given, position);
    }
    free(sums);
    return LUCENT_OK;
}

void mesh_bounds(const struct lucent_mesh *m, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++)
        lo[k] = INFINITY, hi[k] = -INFINITY;
    for (size_t v = 0; v < m->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            double x = m->center[k] + m->positions[3 * v + k];
            lo[k] = fmin(lo[k], x);
            hi[k] = fmax(hi[k], x);
        }
}

void mesh_vertex(const struct lucent_mesh *m, uint32_t t, int k, double out[3])
{
    const float *p = &m->positions[(size_t)m->indices[(size_t)t * 3 + k] * 3];
    out[0] = p[0], out[1] = p[1], out[2] = p[2];
}

/* Triangle t's vertices and its winding's normal (not normalized). */
static void triangle_corners(const struct lucent_mesh *m, uint32_t t, double v[3][3], double g[3])
{
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++)
        mesh_vertex(m, t, k, v[k]);
    for (int a = 0; a < 3; a++) {
        e1[a] = v[1][a] - v[0][a];
        e2[a] = v[2][a] - v[0][a];
    }
    v3_cross(e1, e2, g);
}

void mesh_surface_at(const struct lucent_mesh *m, uint32_t t, double b1, double b2, double p[3], double n[3],
                     double g[3])
{
    double v[3][3], w[3] = {1.0 - b1 - b2, b1, b2};
    triangle_corners(m, t, v, g);
    v3_normalize(g);
    for (int a = 0; a < 3; a++)
        p[a] = n[a] = 0.0;
    for (int k = 0; k < 3; k++) {
        const float *vn = &m->normals[(size_t)m->indices[(size_t)t * 3 + k] * 3];
        for (int a = 0; a < 3; a++) {
            p[a] += w[k] * v[k][a];
            n[a] += w[k] * vn[a];
        }
    }
    /* Files may carry flipped normals: the winding decides which side is outside. */
    double sign = v3_normalize(n) == 0.0 ? 0.0 : v3_dot(n, g) < 0.0 ? -1.0 : 1.0;
    for (int a = 0; a < 3; a++)
        n[a] = sign == 0.0 ? g[a] : sign * n[a];
}

double mesh_curvature(const struct lucent_mesh *m, uint32_t t)
{
    double v[3][3], n[3][3], g[3], facing = 0.0, sum = 0.0;
    triangle_corners(m, t, v, g);
    for (int k = 0; k < 3; k++) {
        const float *vn = &m->normals[(size_t)m->indices[(size_t)t * 3 + k] * 3];
        n[k][0] = vn[0], n[k][1] = vn[1], n[k][2] = vn[2];
        facing += v3_dot(n[k], g);
    }
    for (int k = 0; k < 3; k++) {
        const double *a = v[k], *b = v[(k + 1) % 3], *na = n[k], *nb = n[(k + 1) % 3];
        double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, dn[3] = {nb[0] - na[0], nb[1] - na[1], nb[2] - na[2]};
        double ee = v3_dot(e, e);
        if (ee > 0.0)
            sum += v3_dot(dn, e) / ee;
    }
    /* as mesh_surface_at, the winding decides which side is outside */
    return (facing < 0.0 ? -sum : sum) / 3.0;
}

/* Over what share of the bounding radius the vertex curvature is averaged: the sphere's weight (the scatter pass
 * and reference) wants the body's curvature between points millimetres apart, not a scanned mesh's per-triangle
 * ripple, whose sign flips patch the image. At most this many passes of averaging (each about one edge). */
#define CURVATURE_SCALE 0.1
#define CURVATURE_MAX_PASSES 64

float *mesh_vertex_curvature(const struct lucent_mesh *m)
{
    size_t nv = m->vertex_count, nt = m->triangle_count;
    float *k = malloc(nv * sizeof *k);
    double *sum = calloc(nv, sizeof *sum), *weight = calloc(nv, sizeof *weight), *area = malloc(nt * sizeof *area);
    if (!k || !sum || !weight || !area) {
        free(k);
        k = NULL;
        goto done;
    }
    double area_total = 0.0;
    for (uint32_t t = 0; t < nt; t++) {
        double v[3][3], g[3], c = mesh_curvature(m, t);
        triangle_corners(m, t, v, g);
        area[t] = 0.5 * v3_length(g);
        area_total += area[t];
        for (int j = 0; j < 3; j++) {
            uint32_t i = m->indices[(size_t)t * 3 + j];
            sum[i] += area[t] * c;
            weight[i] += area[t];
        }
    }
    double edge = sqrt(2.0 * area_total / fmax((double)nt, 1.0)), reach = CURVATURE_SCALE * m->radius;
    int passes = edge > 0.0 ? (int)fmin(ceil(reach * reach / (edge * edge)), CURVATURE_MAX_PASSES) : 0;
    for (int pass = 0;; pass++) {
        for (size_t i = 0; i < nv; i++)
            k[i] = weight[i] > 0.0 ? (float)(sum[i] / weight[i]) : 0.0f;
        if (pass == passes)
            break;
        memset(sum, 0, nv * sizeof *sum);
        for (uint32_t t = 0; t < nt; t++) {
            const uint32_t *ix = &m->indices[(size_t)t * 3];
            double mean = area[t] * (k[ix[0]] + k[ix[1]] + k[ix[2]]) / 3.0;
            for (int j = 0; j < 3; j++)
                sum[ix[j]] += mean;
        }
    }
done:
    free(sum);
    free(weight);
    free(area);
    return k;
}

double mesh_curvature_at(const struct lucent_mesh *m, const float *vertex_curvature, uint32_t t, double b1, double b2)
{
    const uint32_t *ix = &m->indices[(size_t)t * 3];
    return (1.0 - b1 - b2) * vertex_curvature[ix[0]] + b1 * vertex_curvature[ix[1]] + b2 * vertex_curvature[ix[2]];
}
