/* bvh.c - median-split BVH over triangles with iterative traversal and Moller-Trumbore intersection,
 * all in double precision so the reference integrator's visibility is exact to rounding. */
#include "bvh.h"

#include "linalg.h"

#include <float.h>
#include <stdlib.h>

#define LEAF_SIZE 4
/* A median split halves every range, so 4M triangles need 21 levels; the cap only bounds the stack. */
#define MAX_DEPTH 60
/* Barycentric slack so a ray through a shared edge or vertex hits at least one of its triangles. */
#define EDGE_EPS 1e-9

struct bvh_node {
    double lo[3], hi[3];
    uint32_t first;   /* leaf: first slot in tris; inner: index of the second child (first is next) */
    uint32_t count;   /* leaf: triangle count; inner: 0 */
};

struct bvh_tri {
    double v0[3], e1[3], e2[3];
    uint32_t index;
};

struct bvh {
    struct bvh_node *nodes;
    struct bvh_tri *tris;
    uint32_t node_count;
};

/* Scratch of the build: triangle order, centroids and per-triangle bounds. */
struct builder {
    struct bvh *bvh;
    uint32_t *ids;
    double *centroid;   /* 3 per triangle */
    double *bounds;     /* 6 per triangle: lo, hi */
};

static void vertex(const struct lucent_mesh *m, uint32_t t, int k, double out[3])
{
    const float *p = &m->positions[(size_t)m->indices[(size_t)t * 3 + k] * 3];
    out[0] = p[0], out[1] = p[1], out[2] = p[2];
}

static void prepare_triangles(const struct lucent_mesh *m, struct builder *b)
{
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        double p[3][3];
        for (int k = 0; k < 3; k++)
            vertex(m, t, k, p[k]);
        double *lo = &b->bounds[(size_t)t * 6], *hi = lo + 3;
        for (int i = 0; i < 3; i++) {
            lo[i] = fmin(p[0][i], fmin(p[1][i], p[2][i]));
            hi[i] = fmax(p[0][i], fmax(p[1][i], p[2][i]));
            b->centroid[(size_t)t * 3 + i] = (p[0][i] + p[1][i] + p[2][i]) / 3.0;
        }
        b->ids[t] = t;
    }
}

void bvh_select_nth(uint32_t *ids, int64_t n, int64_t k, const double *centroid, int axis)
{
    int64_t lo = 0, hi = n - 1;
    while (lo < hi) {
        double pivot = centroid[(size_t)ids[lo + (hi - lo) / 2] * 3 + axis];
        int64_t i = lo, j = hi;
        while (i <= j) {
            while (centroid[(size_t)ids[i] * 3 + axis] < pivot)
                i++;
            while (centroid[(size_t)ids[j] * 3 + axis] > pivot)
                j--;
            if (i <= j) {
                uint32_t tmp = ids[i];
                ids[i++] = ids[j];
                ids[j--] = tmp;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return;
    }
}

static int widest_centroid_axis(const struct builder *b, uint32_t first, uint32_t count)
{
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (uint32_t i = first; i < first + count; i++)
        for (int a = 0; a < 3; a++) {
            double c = b->centroid[(size_t)b->ids[i] * 3 + a];
            lo[a] = fmin(lo[a], c);
            hi[a] = fmax(hi[a], c);
        }
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (hi[a] - lo[a] > hi[axis] - lo[axis])
            axis = a;
    return axis;
}

static void node_bounds(const struct builder *b, struct bvh_node *node, uint32_t first, uint32_t count)
{
    for (int a = 0; a < 3; a++)
        node->lo[a] = DBL_MAX, node->hi[a] = -DBL_MAX;
    for (uint32_t i = first; i < first + count; i++) {
        const double *tb = &b->bounds[(size_t)b->ids[i] * 6];
        for (int a = 0; a < 3; a++) {
            node->lo[a] = fmin(node->lo[a], tb[a]);
            node->hi[a] = fmax(node->hi[a], tb[3 + a]);
        }
    }
}

/* Depth-first layout: a node's first child follows it. Recursion depth is the tree depth. */
static void build_node(struct builder *b, uint32_t first, uint32_t count, int depth)
{
    uint32_t index = b->bvh->node_count++;
    struct bvh_node *node = &b->bvh->nodes[index];
    node_bounds(b, node, first, count);
    if (count <= LEAF_SIZE || depth >= MAX_DEPTH) {
        node->first = first;
        node->count = count;
        return;
    }
    int axis = widest_centroid_axis(b, first, count);
    uint32_t half = count / 2;
    bvh_select_nth(b->ids + first, count, half, b->centroid, axis);
    build_node(b, first, half, depth + 1);
    /* nodes may not move: the array was sized for the worst case up front. */
    b->bvh->nodes[index].first = b->bvh->node_count;
    b->bvh->nodes[index].count = 0;
    build_node(b, first + half, count - half, depth + 1);
}

static void store_triangles(const struct lucent_mesh *m, struct builder *b)
{
    for (uint32_t i = 0; i < m->triangle_count; i++) {
        struct bvh_tri *t = &b->bvh->tris[i];
        double p1[3], p2[3];
        t->index = b->ids[i];
        vertex(m, t->index, 0, t->v0);
        vertex(m, t->index, 1, p1);
        vertex(m, t->index, 2, p2);
        for (int a = 0; a < 3; a++) {
            t->e1[a] = p1[a] - t->v0[a];
            t->e2[a] = p2[a] - t->v0[a];
        }
    }
}

lucent_status bvh_build(const struct lucent_mesh *mesh, struct bvh **out, lucent_error *err)
{
    *out = NULL;
    if (mesh->triangle_count == 0)
        return lucent_fail(err, LUCENT_E_MESH, "mesh", "the mesh has no triangles to trace rays against");
    size_t n = mesh->triangle_count;
    struct builder b = {0};
    b.bvh = calloc(1, sizeof *b.bvh);
    b.ids = malloc(n * sizeof *b.ids);
    b.centroid = malloc(n * 3 * sizeof *b.centroid);
    b.bounds = malloc(n * 6 * sizeof *b.bounds);
    if (b.bvh) {
        b.bvh->nodes = malloc(2 * n * sizeof *b.bvh->nodes);
        b.bvh->tris = malloc(n * sizeof *b.bvh->tris);
    }
    if (!b.bvh || !b.bvh->nodes || !b.bvh->tris || !b.ids || !b.centroid || !b.bounds) {
        lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory for the ray-tracing tree of %zu triangles", n);
        goto fail;
    }
    prepare_triangles(mesh, &b);
    build_node(&b, 0, mesh->triangle_count, 0);
    store_triangles(mesh, &b);
    free(b.ids);
    free(b.centroid);
    free(b.bounds);
    *out = b.bvh;
    return LUCENT_OK;
fail:
    bvh_free(b.bvh);
    free(b.ids);
    free(b.centroid);
    free(b.bounds);
    return LUCENT_E_NOMEM;
}

void bvh_free(struct bvh *bvh)
{
    if (!bvh)
        return;
    free(bvh->nodes);
    free(bvh->tris);
    free(bvh);
}

struct ray {
    double o[3], d[3], inv[3];
};

static void ray_init(struct ray *r, const double origin[3], const double dir[3])
{
    for (int a = 0; a < 3; a++) {
        r->o[a] = origin[a];
        r->d[a] = dir[a];
        r->inv[a] = 1.0 / dir[a];   /* +-inf for axis-parallel rays; fmin/fmax below absorb the NaNs */
    }
}

/* Entry distance into the node's box, or -1 when the ray misses it within (0, t_max). */
static double box_entry(const struct bvh_node *n, const struct ray *r, double t_max)
{
    double t0 = 0.0, t1 = t_max;
    for (int a = 0; a < 3; a++) {
        /* Parallel to a slab: 0 * inf would be NaN where the origin lies on the box's face. */
        if (r->d[a] == 0.0) {
            if (r->o[a] < n->lo[a] || r->o[a] > n->hi[a])
                return -1.0;
            continue;
        }
        double ta = (n->lo[a] - r->o[a]) * r->inv[a], tb = (n->hi[a] - r->o[a]) * r->inv[a];
        t0 = fmax(t0, fmin(ta, tb));
        t1 = fmin(t1, fmax(ta, tb));
    }
    return t0 <= t1 ? t0 : -1.0;
}

/* Moller-Trumbore; returns 1 with t, u, v when 0 < t < t_max. */
static int intersect(const struct bvh_tri *t, const struct ray *r, double t_max, double *t_out, double *u_out,
                     double *v_out)
{
    double p[3], s[3], q[3];
    v3_cross(r->d, t->e2, p);
    double det = v3_dot(t->e1, p);
    if (det == 0.0)
        return 0;
    double inv = 1.0 / det;
    for (int a = 0; a < 3; a++)
        s[a] = r->o[a] - t->v0[a];
    double u = v3_dot(s, p) * inv;
    if (u < -EDGE_EPS || u > 1.0 + EDGE_EPS)
        return 0;
    v3_cross(s, t->e1, q);
    double v = v3_dot(r->d, q) * inv;
    if (v < -EDGE_EPS || u + v > 1.0 + EDGE_EPS)
        return 0;
    double dist = v3_dot(t->e2, q) * inv;
    if (!(dist > 0.0 && dist < t_max))
        return 0;
    *t_out = dist, *u_out = u, *v_out = v;
    return 1;
}

/* Walks the tree; any_hit stops at the first triangle hit. Returns 1 when something was hit. */
static int traverse(const struct bvh *bvh, const struct ray *r, double t_max, int any_hit, struct bvh_hit *hit)
{
    uint32_t stack[MAX_DEPTH + 2];
    int top = 0, found = 0;
    if (box_entry(&bvh->nodes[0], r, t_max) < 0.0)
        return 0;
    stack[top++] = 0;
    while (top > 0) {
        const struct bvh_node *n = &bvh->nodes[stack[--top]];
        if (n->count > 0) {
            for (uint32_t i = n->first; i < n->first + n->count; i++) {
                double t, u, v;
                if (!intersect(&bvh->tris[i], r, t_max, &t, &u, &v))
                    continue;
                if (any_hit)
                    return 1;
                t_max = t, found = 1;
                *hit = (struct bvh_hit){bvh->tris[i].index, t, u, v};
            }
            continue;
        }
        uint32_t a = (uint32_t)(n - bvh->nodes) + 1, b = n->first;
        double ta = box_entry(&bvh->nodes[a], r, t_max), tb = box_entry(&bvh->nodes[b], r, t_max);
        /* Push the farther child first so the nearer one is opened first and shrinks t_max. */
        if (ta >= 0.0 && tb >= 0.0 && ta < tb) {
            stack[top++] = b;
            stack[top++] = a;
        } else {
            if (ta >= 0.0)
                stack[top++] = a;
            if (tb >= 0.0)
                stack[top++] = b;
        }
    }
    return found;
}

int bvh_closest(const struct bvh *bvh, const double origin[3], const double dir[3], double t_max,
                struct bvh_hit *hit)
{
    struct ray r;
    ray_init(&r, origin, dir);
    return traverse(bvh, &r, t_max, 0, hit);
}

int bvh_occluded(const struct bvh *bvh, const double origin[3], const double dir[3], double t_max)
{
    struct ray r;
    ray_init(&r, origin, dir);
    return traverse(bvh, &r, t_max, 1, NULL);
}
