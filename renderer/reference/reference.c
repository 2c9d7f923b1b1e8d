/* reference.c - the CPU ground truth of the dipole model: ray-cast visible points, irradiance points
 * spread evenly over the whole surface with shadow rays, and the sum of their flux times R_d between them. */
#include "reference.h"
#include "clock_ms.h"

#include "bvh.h"
#include "parallel.h"
#include "reference_single.h"
#include "visible_point.h"
#include "dipole.h"
#include "profile.h"
#include "sphere_diffusion.h"
#include "thin_part.h"
#include "linalg.h"

#include <float.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>

/* frac(j / phi): the second coordinate of each point; with the first one stratified along the
 * cumulative area this makes a Fibonacci-like lattice inside every triangle. */
#define GOLDEN_FRACTION 0.61803398874989484820
/* Automatic point count: spacing a quarter of the smallest mean free path (the scale of R_d's peak,
 * z_r = 1 mfp), between these bounds: the floor keeps shadow edges and curvature sampled when a long
 * mean free path alone would ask for few points; above the cap a 64x64 frame no longer renders in
 * about a second (the report's estimated error then says what the cap costs). */
#define AUTO_SPACING_MFP 0.25
#define AUTO_MIN_POINTS 20000.0
#define AUTO_MAX_POINTS 400000.0
/* Hierarchical sum: a node of box diagonal s at distance d from the shaded point is used whole when
 * s < threshold * d (test_reference measures the error of this default against brute force). */
#define DEFAULT_THRESHOLD 0.2
/* Radius, in point spacings, within which points are integrated as one disc (see near_disc). */
#define NEAR_SPACINGS 1.5
#define LEAF_POINTS 8
#define MAX_TREE_DEPTH 60
/* Shadow rays (and the ray measuring the thickness under an exit) start this far (times the mesh radius) off
 * the surface so they miss their own triangle. */
#define SHADOW_OFFSET 1e-6

struct point_node {
    double lo[3], hi[3];
    double extent;           /* box diagonal, scene units */
    double flux[3];          /* sum of E * A per channel (E in light units, A in mm^2) */
    double centroid[3][3];   /* per channel, flux-weighted */
    double normal[3];        /* flux-weighted mean of the points' normals (shorter than 1 where they differ) */
    uint32_t first;          /* leaf: first point; inner: index of the second child (first is next) */
    uint32_t count;          /* leaf: point count; inner: 0 */
};

struct context {
    const lucent_scene *scene;
    const struct lucent_mesh *mesh;
    const struct view_frame *camera;
    struct bvh *bvh;
    struct profile profile[3];
    struct sphere_tables sphere;   /* diffusion in a sphere over R between points */
    struct thin_part_table thin[3];   /* the share of R a thin part keeps, per channel */
    float *vertex_curvature;       /* mesh_vertex_curvature: the exit's, for the sphere's weight */
    double scale_mm, threshold, eta;
    double exit_weight;      /* sr^-1: diffuse_exit_weight(eta) */
    double near_radius;      /* scene units: points closer than this are integrated as a disc */
    double point_area_mm2;
    int brute_force, shadows;
    struct ref_light lights[LUCENT_MAX_LIGHTS];
    int light_count;
    int single;              /* add the single-scattering term */
    struct single_scatter ss;
    /* surface sampling */
    double *cum_area;        /* per triangle, inclusive prefix sum, scene units^2 */
    double total_area;
    size_t point_count;
    double *pos;             /* 3 per point, mesh-centred scene units */
    double *flux;            /* 3 per point, E * A with A in mm^2 */
    double *normal;          /* 3 per point, unit */
    /* hierarchy over the points, which are reordered so every leaf's points are contiguous */
    struct point_node *nodes;
    uint32_t node_count;
    uint32_t *order;
    lucent_image *out;
    const atomic_int *cancel;
};

static int cancelled(const struct context *ctx)
{
    return ctx->cancel && atomic_load(ctx->cancel);
}

/* ---- geometry ---- */

/* ---- irradiance points ---- */

static uint32_t triangle_at(const struct context *ctx, double u)
{
    uint32_t lo = 0, hi = ctx->mesh->triangle_count - 1;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (ctx->cum_area[mid] > u)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* Light entering the surface at p: sum over lights of rgb * falloff * cos * Ft(cos), shadowed. */
static void irradiance(const struct context *ctx, const double p[3], const double n[3], const double g[3],
                       double e[3])
{
    double origin[3];
    v3_scale_add(p, g, SHADOW_OFFSET * ctx->mesh->radius, origin);
    e[0] = e[1] = e[2] = 0.0;
    for (int l = 0; l < ctx->light_count; l++) {
        double cos_l, arrival = ref_light_arrival(&ctx->lights[l], ctx->bvh, ctx->shadows, p, n, origin, &cos_l);
        if (arrival == 0.0)
            continue;
        double k = arrival * fresnel_transmittance(ctx->eta, cos_l);
        for (int c = 0; c < 3; c++)
            e[c] += ctx->lights[l].rgb[c] * k;
    }
}

/* Point j sits at u_j = (j + 1/2) / N along the cumulative area; its position inside the chosen
 * triangle is (s, frac(j / phi)) mapped area-preservingly (s = how far u_j is through the triangle). */
static void make_points(void *arg, size_t begin, size_t end)
{
    struct context *ctx = arg;
    double n_inv = 1.0 / (double)ctx->point_count;
    double area_mm2 = ctx->total_area * n_inv * ctx->scale_mm * ctx->scale_mm;
    for (size_t j = begin; j < end; j++) {
        double u = ((double)j + 0.5) * n_inv * ctx->total_area;
        uint32_t t = triangle_at(ctx, u);
        double before = t > 0 ? ctx->cum_area[t - 1] : 0.0, span = ctx->cum_area[t] - before;
        double s = fmin(fmax((u - before) / span, 0.0), 1.0);
        double v = fmod((double)j * GOLDEN_FRACTION, 1.0), r = sqrt(s);
        double *p = &ctx->pos[j * 3], *n = &ctx->normal[j * 3], g[3], e[3];
        mesh_surface_at(ctx->mesh, t, r * (1.0 - v), r * v, p, n, g);
        irradiance(ctx, p, n, g, e);
        for (int c = 0; c < 3; c++)
            ctx->flux[j * 3 + c] = e[c] * area_mm2;
    }
}

static lucent_status cumulative_area(struct context *ctx, lucent_error *err)
{
    const struct lucent_mesh *m = ctx->mesh;
    ctx->cum_area = malloc((size_t)m->triangle_count * sizeof *ctx->cum_area);
    if (!ctx->cum_area)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory for the areas of %u triangles",
                           m->triangle_count);
    double sum = 0.0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        double v[3][3], e1[3], e2[3], c[3];
        for (int k = 0; k < 3; k++)
            mesh_vertex(m, t, k, v[k]);
        for (int a = 0; a < 3; a++) {
            e1[a] = v[1][a] - v[0][a];
            e2[a] = v[2][a] - v[0][a];
        }
        v3_cross(e1, e2, c);
        sum += 0.5 * v3_length(c);
        ctx->cum_area[t] = sum;
    }
    ctx->total_area = sum;
    if (!(sum > 0.0))
        return lucent_fail(err, LUCENT_E_MESH, "mesh", "the mesh has no surface area to light");
    return LUCENT_OK;
}

static double min_mean_free_path(const struct context *ctx)
{
    double mfp = INFINITY;
    for (int c = 0; c < 3; c++)
        mfp = fmin(mfp, 1.0 / ctx->profile[c].sigma_t_prime);
    return mfp;
}

static lucent_status choose_point_count(struct context *ctx, uint32_t requested, lucent_error *err)
{
    if (requested > LUCENT_MAX_REFERENCE_POINTS)
        return lucent_fail(err, LUCENT_E_LIMIT, "reference.points", "%u irradiance points requested; at most %u",
                           requested, LUCENT_MAX_REFERENCE_POINTS);
    if (requested > 0) {
        ctx->point_count = requested;
        return LUCENT_OK;
    }
    double spacing = AUTO_SPACING_MFP * min_mean_free_path(ctx);
    double area_mm2 = ctx->total_area * ctx->scale_mm * ctx->scale_mm;
    double n = area_mm2 / (spacing * spacing);
    ctx->point_count = (size_t)fmin(fmax(n, AUTO_MIN_POINTS), AUTO_MAX_POINTS);
    return LUCENT_OK;
}

/* ---- the point hierarchy ---- */

static double point_key(const struct context *ctx, uint32_t i, int axis)
{
    return ctx->pos[(size_t)i * 3 + axis];
}

/* Moves the k-th smallest point (along axis) of ids[0..n) to position k, smaller ones before it. */
static void leaf_summary(const struct context *ctx, struct point_node *node)
{
    for (int a = 0; a < 3; a++)
        node->lo[a] = DBL_MAX, node->hi[a] = -DBL_MAX;
    double moment[3][3] = {{0}}, normal[3] = {0.0, 0.0, 0.0}, total = 0.0;
    for (uint32_t i = node->first; i < node->first + node->count; i++) {
        const double *p = &ctx->pos[(size_t)ctx->order[i] * 3], *f = &ctx->flux[(size_t)ctx->order[i] * 3];
        const double *n = &ctx->normal[(size_t)ctx->order[i] * 3];
        double w = f[0] + f[1] + f[2];
        for (int a = 0; a < 3; a++)
            normal[a] += w * n[a];
        total += w;
        for (int a = 0; a < 3; a++) {
            node->lo[a] = fmin(node->lo[a], p[a]);
            node->hi[a] = fmax(node->hi[a], p[a]);
        }
        for (int c = 0; c < 3; c++) {
            node->flux[c] += f[c];
            for (int a = 0; a < 3; a++)
                moment[c][a] += f[c] * p[a];
        }
    }
    for (int c = 0; c < 3; c++)
        for (int a = 0; a < 3; a++)
            node->centroid[c][a] = node->flux[c] > 0.0 ? moment[c][a] / node->flux[c]
                                                       : 0.5 * (node->lo[a] + node->hi[a]);
    for (int a = 0; a < 3; a++)
        node->normal[a] = total > 0.0 ? normal[a] / total : 0.0;
}

static void merge_summary(struct point_node *node, const struct point_node *a, const struct point_node *b)
{
    for (int k = 0; k < 3; k++) {
        node->lo[k] = fmin(a->lo[k], b->lo[k]);
        node->hi[k] = fmax(a->hi[k], b->hi[k]);
    }
    double wa = a->flux[0] + a->flux[1] + a->flux[2], wb = b->flux[0] + b->flux[1] + b->flux[2];
    for (int k = 0; k < 3; k++)
        node->normal[k] = wa + wb > 0.0 ? (wa * a->normal[k] + wb * b->normal[k]) / (wa + wb) : 0.0;
    for (int c = 0; c < 3; c++) {
        node->flux[c] = a->flux[c] + b->flux[c];
        for (int k = 0; k < 3; k++)
            node->centroid[c][k] = node->flux[c] > 0.0
                                       ? (a->flux[c] * a->centroid[c][k] + b->flux[c] * b->centroid[c][k]) / node->flux[c]
                                       : 0.5 * (node->lo[k] + node->hi[k]);
    }
}

static int widest_axis(const struct context *ctx, const uint32_t *ids, uint32_t count)
{
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (uint32_t i = 0; i < count; i++)
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], point_key(ctx, ids[i], a));
            hi[a] = fmax(hi[a], point_key(ctx, ids[i], a));
        }
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (hi[a] - lo[a] > hi[axis] - lo[axis])
            axis = a;
    return axis;
}

/* Median split, depth-first layout; recursion depth is the tree depth (about log2(N / 8)). */
static uint32_t build_points(struct context *ctx, uint32_t first, uint32_t count, int depth)
{
    uint32_t index = ctx->node_count++;
    struct point_node *node = &ctx->nodes[index];
    *node = (struct point_node){.first = first, .count = count};
    if (count <= LEAF_POINTS || depth >= MAX_TREE_DEPTH) {
        leaf_summary(ctx, node);
    } else {
        uint32_t half = count / 2;
        bvh_select_nth(ctx->order + first, count, half, ctx->pos, widest_axis(ctx, ctx->order + first, count));
        uint32_t left = build_points(ctx, first, half, depth + 1);
        uint32_t right = build_points(ctx, first + half, count - half, depth + 1);
        node->first = right;
        node->count = 0;
        merge_summary(node, &ctx->nodes[left], &ctx->nodes[right]);
    }
    double diag[3] = {node->hi[0] - node->lo[0], node->hi[1] - node->lo[1], node->hi[2] - node->lo[2]};
    node->extent = v3_length(diag);
    return index;
}

/* Every split leaves at least LEAF_POINTS / 2 points per leaf, so N / 4 + 1 leaves at most. The points
 * are then stored in leaf order so a leaf is a contiguous range. */
static lucent_status build_point_tree(struct context *ctx, lucent_error *err)
{
    size_t n = ctx->point_count, max_nodes = 2 * (n / (LEAF_POINTS / 2) + 1);
    ctx->order = malloc(n * sizeof *ctx->order);
    ctx->nodes = malloc(max_nodes * sizeof *ctx->nodes);
    double *pos = malloc(n * 3 * sizeof *pos), *flux = malloc(n * 3 * sizeof *flux);
    double *normal = malloc(n * 3 * sizeof *normal);
    if (!ctx->order || !ctx->nodes || !pos || !flux || !normal) {
        free(pos);
        free(flux);
        free(normal);
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory for the hierarchy of %zu irradiance points", n);
    }
    for (size_t i = 0; i < n; i++)
        ctx->order[i] = (uint32_t)i;
    build_points(ctx, 0, (uint32_t)n, 0);
    for (size_t i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            pos[i * 3 + a] = ctx->pos[(size_t)ctx->order[i] * 3 + a];
            flux[i * 3 + a] = ctx->flux[(size_t)ctx->order[i] * 3 + a];
            normal[i * 3 + a] = ctx->normal[(size_t)ctx->order[i] * 3 + a];
        }
    free(ctx->pos);
    free(ctx->flux);
    free(ctx->normal);
    ctx->pos = pos;
    ctx->flux = flux;
    ctx->normal = normal;
    return LUCENT_OK;
}

/* ---- radiance ---- */

/* a - b in mm. */
static void offset_mm(const struct context *ctx, const double a[3], const double b[3], double d[3])
{
    for (int k = 0; k < 3; k++)
        d[k] = (a[k] - b[k]) * ctx->scale_mm;
}

/* Points within near_radius of the shaded point, whose flux is spread over a disc rather than
 * sampled at the points: R_d peaks within z_r of the exit point, which may be far below the point
 * spacing (dense media, huge scales), where a point sum would hit or miss the peak. */
struct near_disc {
    double flux[3];
    uint32_t count;
};

/* The point a pixel sees, as the kernel needs it: where light leaves, its normal, the surface's curvature
 * there, the medium's thickness under it (mm; INFINITY where the ray inward leaves the mesh), how much that
 * is a thin part's (slab_weight, exit_point_at) and the curvature the sphere factor takes: the surface's
 * where the part is at least as thick as its radius of curvature, less in proportion where it is thinner
 * (an ear is a slab, not a ball of its thickness: the sphere factor made a back-lit marble ear too dark). */
struct exit_point {
    const double *p, *n;
    double curvature_mm, thickness_mm, slab_weight, ball_curvature_mm;
};

/* How much of R a pair keeps on exit e's part: all but what the thin part loses through its back face, for
 * pairs on one face, weighted by the cosine between their normals (none from 90 degrees on: through the part
 * profile_rd_between has the slab's pair, and from its sides the loss made a back-lit ear darker still). */
static double thin_part_factor(const struct context *ctx, int c, double r_mm, double on_one_face,
                               const struct exit_point *e)
{
    double w = e->slab_weight * on_one_face;
    return w > 0.0 ? 1.0 - w * (1.0 - thin_part_share(&ctx->thin[c], r_mm, e->thickness_mm)) : 1.0;
}

/* The light from an irradiance point (or a far group's centroid) d away, with normal n_in, to the exit. */
static double kernel(const struct context *ctx, int c, const double d[3], const double n_in[3],
                     const struct exit_point *e)
{
    return profile_rd_between(&ctx->profile[c], d, e->n, n_in) *
           sphere_factor(&ctx->sphere.channel[c], d, e->n, n_in, e->ball_curvature_mm) *
           thin_part_factor(ctx, c, v3_length(d), fmax(v3_dot(n_in, e->n), 0.0), e);
}

static void sum_points(const struct context *ctx, const struct exit_point *e, size_t first, size_t end,
                       double sum[3], struct near_disc *near)
{
    for (size_t i = first; i < end; i++) {
        const double *f = &ctx->flux[i * 3];
        if (f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0)
            continue;
        double d[3];
        offset_mm(ctx, e->p, &ctx->pos[i * 3], d);
        if (v3_length(d) < ctx->near_radius * ctx->scale_mm) {
            for (int c = 0; c < 3; c++)
                near->flux[c] += f[c];
            near->count++;
            continue;
        }
        for (int c = 0; c < 3; c++)
            sum[c] += f[c] * kernel(ctx, c, d, &ctx->normal[i * 3], e);
    }
}

/* The near points' mean irradiance times the integral of R_d over a disc of their total area,
 * the surface being flat at that scale. */
static void add_near_disc(const struct context *ctx, const struct near_disc *near, const struct exit_point *e,
                          double sum[3])
{
    if (near->count == 0)
        return;
    double area = near->count * ctx->point_area_mm2, radius = sqrt(area / PI);
    /* (a thin part's share taken at the disc's mean distance from its centre) */
    for (int c = 0; c < 3; c++)
        sum[c] += near->flux[c] / area * profile_disc(&ctx->profile[c], radius) *
                  thin_part_factor(ctx, c, radius * 2.0 / 3.0, 1.0, e);
}

static double box_distance(const struct point_node *n, const double x[3])
{
    double d2 = 0.0;
    for (int a = 0; a < 3; a++) {
        double d = fmax(fmax(n->lo[a] - x[a], x[a] - n->hi[a]), 0.0);
        d2 += d * d;
    }
    return sqrt(d2);
}

/* Jensen & Buhler 2002: far nodes count as their flux at their centroid. A node holding x is at
 * distance 0 and is always opened. */
static void sum_tree(const struct context *ctx, const struct exit_point *e, double sum[3], struct near_disc *near)
{
    uint32_t stack[MAX_TREE_DEPTH + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        uint32_t index = stack[--top];
        const struct point_node *node = &ctx->nodes[index];
        if (node->flux[0] == 0.0 && node->flux[1] == 0.0 && node->flux[2] == 0.0)
            continue;
        double distance = box_distance(node, e->p);
        if (distance >= ctx->near_radius && node->extent < ctx->threshold * distance) {
            for (int c = 0; c < 3; c++)
                if (node->flux[c] > 0.0) {
                    double d[3];
                    offset_mm(ctx, e->p, node->centroid[c], d);
                    sum[c] += node->flux[c] * kernel(ctx, c, d, node->normal, e);
                }
        } else if (node->count > 0) {
            sum_points(ctx, e, node->first, (size_t)node->first + node->count, sum, near);
        } else {
            stack[top++] = node->first;
            stack[top++] = index + 1;
        }
    }
}

/* The medium under a visible point along its normal, in mm: how far the ray inward runs to the mesh. */
static double thickness_mm(const struct context *ctx, const struct visible_point *v)
{
    double start[3], inward[3] = {-v->n[0], -v->n[1], -v->n[2]};
    struct bvh_hit hit;
    v3_scale_add(v->p, v->g, -SHADOW_OFFSET * ctx->mesh->radius, start);
    return bvh_closest(ctx->bvh, start, inward, INFINITY, &hit) ? hit.t * ctx->scale_mm : INFINITY;
}

/* Visible point v as the kernel takes it. A thin part is one much thinner than its faces' curvature makes a
 * convex body: 1 - thickness x curvature / 2 is 0 on a sphere (its diameter times 1 / radius over 2), whose
 * light lost through its sides the sphere factor has, and 1 on a flat face or a concave one. */
static struct exit_point exit_point_at(const struct context *ctx, const struct visible_point *v)
{
    double curvature = v->curvature / ctx->scale_mm, thickness = thickness_mm(ctx, v);
    double slab = isfinite(thickness) ? fmin(fmax(1.0 - 0.5 * thickness * curvature, 0.0), 1.0) : 0.0;
    return (struct exit_point){v->p, v->n, curvature, thickness, slab, sphere_factor_curvature(curvature, thickness)};
}

static void shade_pixel(struct context *ctx, int x, int y)
{
    lucent_image *img = ctx->out;
    double sum[3] = {0.0, 0.0, 0.0};
    struct visible_point v;
    if (!visible_point_at(ctx->camera, ctx->bvh, ctx->mesh, ctx->vertex_curvature, x + 0.5, y + 0.5, img->width,
                          img->height, &v))
        return;
    struct near_disc near = {{0.0, 0.0, 0.0}, 0};
    struct exit_point e = exit_point_at(ctx, &v);
    if (ctx->brute_force)
        sum_points(ctx, &e, 0, ctx->point_count, sum, &near);
    else
        sum_tree(ctx, &e, sum, &near);
    add_near_disc(ctx, &near, &e, sum);
    double k = fresnel_transmittance(ctx->eta, -v3_dot(v.n, v.dir)) * ctx->exit_weight, single[3] = {0.0, 0.0, 0.0};
    if (ctx->single) {
        double to_eye[3] = {-v.dir[0], -v.dir[1], -v.dir[2]};
        single_scatter_radiance(&ctx->ss, v.p, v.n, v.g, to_eye, single);
    }
    size_t i = (size_t)y * img->width + x;
    for (int c = 0; c < 3; c++)
        img->rgba[i * 4 + c] = (float)(sum[c] * k + single[c]);
    visible_point_write_aovs(img, i, &v);
}

static void shade_rows(void *arg, size_t begin, size_t end)
{
    struct context *ctx = arg;
    for (size_t y = begin; y < end; y++)
        for (int x = 0; x < ctx->out->width; x++)
            shade_pixel(ctx, x, (int)y);
}

/* ---- set-up ---- */

static lucent_status check_inputs(const lucent_scene *scene, const struct lucent_mesh *mesh, double scale_mm,
                                  const struct reference_options *o, lucent_error *err)
{
    if (!mesh || mesh->triangle_count == 0)
        return lucent_fail(err, LUCENT_E_MESH, "mesh", "the mesh has no triangles to render");
    if (!(scale_mm >= LUCENT_MIN_SCALE_MM && scale_mm <= LUCENT_MAX_SCALE_MM))
        return lucent_fail(err, LUCENT_E_LIMIT, "scale_mm", "scale_mm is %g; must be between %g and %g",
                           scale_mm, LUCENT_MIN_SCALE_MM, LUCENT_MAX_SCALE_MM);
    if (!(o->threshold >= 0.0 && o->threshold <= 1.0))
        return lucent_fail(err, LUCENT_E_INVALID, "reference.threshold",
                           "threshold is %g; must be between 0 and 1 (node size / distance)", o->threshold);
    if (scene->light_count < 0 || scene->light_count > LUCENT_MAX_LIGHTS)
        return lucent_fail(err, LUCENT_E_LIMIT, "lights", "%d lights; at most %d", scene->light_count,
                           LUCENT_MAX_LIGHTS);
    if (!(scene->material.eta >= LUCENT_MIN_ETA))
        return lucent_fail(err, LUCENT_E_INVALID, "material.eta", "eta is %g; must be at least %g",
                           scene->material.eta, LUCENT_MIN_ETA);
    return LUCENT_OK;
}

static lucent_status set_up_lights(struct context *ctx, lucent_error *err)
{
    ctx->light_count = ctx->scene->light_count;
    return ref_lights_from_scene(ctx->scene, ctx->mesh, ctx->lights, err);
}

static lucent_status alloc_points(struct context *ctx, lucent_error *err)
{
    ctx->pos = malloc(ctx->point_count * 3 * sizeof *ctx->pos);
    ctx->flux = malloc(ctx->point_count * 3 * sizeof *ctx->flux);
    ctx->normal = malloc(ctx->point_count * 3 * sizeof *ctx->normal);
    if (!ctx->pos || !ctx->flux || !ctx->normal)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory for %zu irradiance points", ctx->point_count);
    return LUCENT_OK;
}

static void free_context(struct context *ctx)
{
    bvh_free(ctx->bvh);
    free(ctx->cum_area);
    free(ctx->pos);
    free(ctx->flux);
    free(ctx->normal);
    free(ctx->vertex_curvature);
    free(ctx->nodes);
    free(ctx->order);
}

/* Estimated relative error of the point sum, fitted conservatively to the worst pixel measured
 * (the centre of a flat square, on the triangles' shared edge) for r = smallest mean free path /
 * point spacing: about 5% near r = 0.5, where R_d's peak spans a few points but the near disc
 * holds too few to be flat; 1% at r = 1.7; 0.05% at r = 2.4; within 1.5% for r < 0.25, where the
 * near disc carries almost all the energy. The hierarchical sum adds about 0.03 threshold^2. */
static double estimated_error(double spacing_mm, double mfp_mm, double threshold)
{
    double r = mfp_mm / spacing_mm;
    return 0.06 * exp(-1.5 * fmax(r - 0.5, 0.0)) + 0.03 * threshold * threshold;
}

lucent_status reference_render(const lucent_scene *scene, const struct lucent_mesh *mesh,
                               const struct view_frame *camera, double scale_mm,
                               const struct reference_options *options, int with_aovs, lucent_image *out,
                               struct reference_report *report, lucent_error *err)
{
    struct context ctx = {.scene = scene, .mesh = mesh, .camera = camera, .scale_mm = scale_mm,
                          .eta = scene->material.eta,
                          .exit_weight = diffuse_exit_weight(scene->material.eta), .out = out,
                          .brute_force = options->brute_force,
                          .cancel = options->cancel,
                          .threshold = options->threshold > 0.0 ? options->threshold : DEFAULT_THRESHOLD};
    *report = (struct reference_report){0};
    *out = (lucent_image){0};
    lucent_status st = check_inputs(scene, mesh, scale_mm, options, err);
    if (st != LUCENT_OK)
        return st;
    if ((st = lucent_image_alloc(out, scene->width, scene->height, with_aovs, err)) != LUCENT_OK)
        return st;
    for (int c = 0; c < 3; c++)
        profile_init(&ctx.profile[c], scene->material.profile, scene->material.sigma_a[c], scene->material.sigma_s_prime[c],
                     scene->material.g, ctx.eta);
    /* Convex meshes cannot shadow themselves; a shadow ray there would only darken the terminator
     * where interpolated normals face the light and flat facets do not (the raster pass skips too). */
    ctx.shadows = !mesh->convex;
    int threads = parallel_threads(options->threads);
    double t0 = now_ms();
    for (int c = 0; c < 3; c++)
        thin_part_table_init(&ctx.thin[c], &ctx.profile[c]);
    if ((st = sphere_tables_for(&ctx.sphere, ctx.profile, err)) || (st = set_up_lights(&ctx, err)) ||
        (st = cumulative_area(&ctx, err)) ||
        (st = choose_point_count(&ctx, options->points, err)) || (st = bvh_build(mesh, &ctx.bvh, err)) ||
        (st = alloc_points(&ctx, err)))
        goto fail;
    if (!(ctx.vertex_curvature = mesh_vertex_curvature(mesh))) {
        st = lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory for the curvature of %u vertices", mesh->vertex_count);
        goto fail;
    }
    ctx.single = scene->single_scattering;
    ctx.ss = (struct single_scatter){.mesh = mesh, .bvh = ctx.bvh, .lights = ctx.lights,
                                     .light_count = ctx.light_count, .shadows = ctx.shadows,
                                     .scale_mm = scale_mm, .eta = ctx.eta};
    single_scatter_material(&ctx.ss, &scene->material);
    ctx.point_area_mm2 = ctx.total_area / (double)ctx.point_count * scale_mm * scale_mm;
    ctx.near_radius = NEAR_SPACINGS * sqrt(ctx.total_area / (double)ctx.point_count);
    parallel_run(&ctx, threads, ctx.point_count, 1024, make_points, ctx.cancel);
    if (cancelled(&ctx))
        goto cancel;
    if (!ctx.brute_force && (st = build_point_tree(&ctx, err)) != LUCENT_OK)
        goto fail;
    double t1 = now_ms();
    parallel_run(&ctx, threads, (size_t)out->height, 1, shade_rows, ctx.cancel);
    if (cancelled(&ctx))
        goto cancel;
    double area_mm2 = ctx.total_area * scale_mm * scale_mm;
    report->points = (uint32_t)ctx.point_count;
    report->point_spacing_mm = sqrt(area_mm2 / (double)ctx.point_count);
    report->min_mean_free_path_mm = min_mean_free_path(&ctx);
    report->threshold = ctx.brute_force ? 0.0 : ctx.threshold;
    report->estimated_rel_error =
        estimated_error(report->point_spacing_mm, report->min_mean_free_path_mm, report->threshold);
    report->ms_points = t1 - t0;
    report->ms_pixels = now_ms() - t1;
    free_context(&ctx);
    return LUCENT_OK;
cancel:
    st = lucent_fail(err, LUCENT_E_CANCELLED, "", "the reference render was cancelled");
fail:
    free_context(&ctx);
    lucent_image_free(out);
    return st;
}
