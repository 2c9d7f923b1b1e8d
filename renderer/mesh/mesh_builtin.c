/* mesh_builtin.c - the meshes a scene can name instead of a file: a sphere, a torus and the paper's
 * failure case, a sphere with a nose toward +Z, each at a requested density; and the Stanford bunny. */
#include "linalg.h"
#include "mesh.h"
#include "stanford_bunny.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define DEFAULT_TRIANGLES 20000u
/* Candidate tessellations this close to the requested count are ranked by regularity instead. */
#define COUNT_SLACK 0.005

#define TORUS_MAJOR_RADIUS 1.0
#define TORUS_MINOR_RADIUS 0.4

/* The protrusion's radius is 1 + NOSE_HEIGHT * exp(-theta^2 / (2 NOSE_WIDTH^2)), theta measured
 * from +Z: a nose toward the head-on camera whose flanks face sideways, the paper's failure case. */
#define NOSE_HEIGHT 0.55
#define NOSE_WIDTH 0.28

/* ---- choosing a tessellation for a triangle count ---- */

/* Whether (error, irregularity) beats the best so far: errors within COUNT_SLACK count as equal,
 * so among near-exact matches the most even tessellation wins. */
static int better_candidate(double error, double irregularity, double best_error,
                            double best_irregularity)
{
    double e = fmax(error, COUNT_SLACK), best_e = fmax(best_error, COUNT_SLACK);
    if (e != best_e)
        return e < best_e;
    return irregularity < best_irregularity;
}

static double count_error(double count, uint32_t target)
{
    if (count > LUCENT_MAX_BUILTIN_TRIANGLES)
        return INFINITY;
    return fabs(count - target) / target;
}

/* The sphere-like shapes are a box of cells[0] x cells[1] x cells[2] cells projected onto the
 * sphere with equal-angle spacing: 4(ab+bc+ca) triangles, three free counts that can match almost
 * any request. cells[0] and cells[1] are even so that a vertex sits exactly on the +Z axis (the
 * protrusion's tip) and on -Z. */
typedef struct box_lattice {
    uint32_t cells[3];
} box_lattice;

static uint32_t lattice_triangle_count(const box_lattice *l)
{
    uint32_t a = l->cells[0], b = l->cells[1], c = l->cells[2];
    return 4 * (a * b + b * c + c * a);
}

static uint32_t lattice_vertex_count(const box_lattice *l)
{
    return 2 + lattice_triangle_count(l) / 2;
}

static box_lattice plan_box_lattice(uint32_t target)
{
    box_lattice best = {{2, 2, 2}};
    double best_error = INFINITY, best_irregularity = INFINITY;
    double side = sqrt(target / 12.0);
    uint32_t lo = (uint32_t)(side / 2) < 2 ? 2 : (uint32_t)(side / 2);
    uint32_t hi = (uint32_t)(2 * side) + 2;
    for (uint32_t a = lo + (lo & 1); a <= hi; a += 2) {
        for (uint32_t b = a; b <= hi && b <= 2 * a; b += 2) {
            double c_exact = (target / 4.0 - (double)a * b) / (a + b);
            if (c_exact < 0.5)
                continue;
            uint32_t c = (uint32_t)lround(c_exact);
            uint32_t smallest = c < a ? c : a, largest = c > b ? c : b;
            if (largest > 2 * smallest)
                continue;
            double count = 4.0 * ((double)a * b + (double)b * c + (double)c * a);
            double error = count_error(count, target);
            double irregularity = (double)largest / smallest;
            if (better_candidate(error, irregularity, best_error, best_irregularity)) {
                best = (box_lattice){{a, b, c}};
                best_error = error;
                best_irregularity = irregularity;
            }
        }
    }
    return best;
}

/* A torus grid of `major` segments around the Z axis by `minor` around the tube: 2 * major * minor
 * triangles; cells are squarest when major / minor is the ratio of the radii. An even `major`
 * makes the grid symmetric under x -> -x, so its box centre is the torus centre. */
typedef struct torus_grid {
    uint32_t major, minor;
} torus_grid;

static torus_grid plan_torus_grid(uint32_t target)
{
    const double aspect = TORUS_MAJOR_RADIUS / TORUS_MINOR_RADIUS;
    torus_grid best = {4, 3};
    double best_error = INFINITY, best_irregularity = INFINITY;
    double minor_ideal = sqrt(target / (2 * aspect));
    uint32_t lo = (uint32_t)(minor_ideal / 2) < 3 ? 3 : (uint32_t)(minor_ideal / 2);
    uint32_t hi = (uint32_t)(2 * minor_ideal) + 2;
    for (uint32_t minor = lo; minor <= hi; minor++) {
        uint32_t major = 2 * (uint32_t)lround(target / (4.0 * minor));
        if (major < 4)
            continue;
        double error = count_error(2.0 * major * minor, target);
        double irregularity = fabs(log((double)major / minor / aspect));
        if (better_candidate(error, irregularity, best_error, best_irregularity)) {
            best = (torus_grid){major, minor};
            best_error = error;
            best_irregularity = irregularity;
        }
    }
    return best;
}

/* ---- shapes as functions of a direction from the centre ---- */

typedef void (*radial_shape)(const double dir[3], double position[3], double normal[3]);

static void sphere_point(const double dir[3], double position[3], double normal[3])
{
    for (int k = 0; k < 3; k++)
        position[k] = normal[k] = dir[k];
}

/* For r(theta) the surface normal is proportional to r_hat - (r'/r) theta_hat. */
static void protrusion_point(const double dir[3], double position[3], double normal[3])
{
    double sin_theta = sqrt(dir[0] * dir[0] + dir[1] * dir[1]);
    double theta = atan2(sin_theta, dir[2]);
    double bump = NOSE_HEIGHT * exp(-theta * theta / (2 * NOSE_WIDTH * NOSE_WIDTH));
    double r = 1 + bump;
    double slope = -bump * theta / (NOSE_WIDTH * NOSE_WIDTH) / r;
    /* theta_hat is undefined on the Z axis, where the slope is zero anyway */
    double theta_hat[3] = {0, 0, 0};
    if (sin_theta > 0) {
        theta_hat[0] = dir[2] * dir[0] / sin_theta;
        theta_hat[1] = dir[2] * dir[1] / sin_theta;
        theta_hat[2] = -sin_theta;
    }
    double len2 = 0;
    for (int k = 0; k < 3; k++) {
        position[k] = r * dir[k];
        normal[k] = dir[k] - slope * theta_hat[k];
        len2 += normal[k] * normal[k];
    }
    for (int k = 0; k < 3; k++)
        normal[k] /= sqrt(len2);
}

/* ---- triangles ---- */

static double distance_squared(const float *positions, uint32_t i, uint32_t j)
{
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double d = (double)positions[3 * (size_t)i + k] - positions[3 * (size_t)j + k];
        d2 += d * d;
    }
    return d2;
}

/* Splits quad q (counter-clockwise from outside) along its shorter diagonal, which keeps the
 * triangles closest to the curved surface; returns the next free index slot. */
static uint32_t *emit_quad(const float *positions, const uint32_t q[4], uint32_t *out)
{
    static const int split_02[6] = {0, 1, 2, 0, 2, 3};
    static const int split_13[6] = {0, 1, 3, 1, 2, 3};
    const int *split = distance_squared(positions, q[0], q[2]) <= distance_squared(positions, q[1], q[3])
                           ? split_02 : split_13;
    for (int i = 0; i < 6; i++)
        out[i] = q[split[i]];
    return out + 6;
}

/* ---- the box lattice ---- */

/* Position of surface lattice point ijk in the vertex array: the z = 0 cap, then one ring of
 * 2(a+b) points per inner z layer, then the z = c cap. */
static uint32_t lattice_vertex_id(const box_lattice *l, const uint32_t ijk[3])
{
    uint32_t a = l->cells[0], b = l->cells[1], c = l->cells[2];
    uint32_t i = ijk[0], j = ijk[1], k = ijk[2];
    uint32_t cap = (a + 1) * (b + 1), ring = 2 * (a + b);
    if (k == 0)
        return i * (b + 1) + j;
    if (k == c)
        return cap + (c - 1) * ring + i * (b + 1) + j;
    uint32_t base = cap + (k - 1) * ring;
    if (j == 0)
        return base + i;
    if (i == a)
        return base + a + j;
    if (j == b)
        return base + a + b + (a - i);
    return base + 2 * a + b + (b - j);
}

/* Equal-angle cube-to-sphere map: cell edges subtend equal angles, so cells stay even in size. */
static void lattice_direction(const box_lattice *l, const uint32_t ijk[3], double dir[3])
{
    double len2 = 0;
    for (int k = 0; k < 3; k++) {
        double s = -1.0 + 2.0 * ijk[k] / l->cells[k];
        dir[k] = tan(0.25 * PI * s);
        len2 += dir[k] * dir[k];
    }
    for (int k = 0; k < 3; k++)
        dir[k] /= sqrt(len2);
}

static void fill_lattice_vertices(struct lucent_mesh *m, const box_lattice *l, radial_shape shape)
{
    uint32_t a = l->cells[0], b = l->cells[1], c = l->cells[2];
    for (uint32_t k = 0; k <= c; k++) {
        for (uint32_t i = 0; i <= a; i++) {
            /* inside the box only the ring's j = 0 and j = b points are on the surface */
            uint32_t step = (k == 0 || k == c || i == 0 || i == a) ? 1 : b;
            for (uint32_t j = 0; j <= b; j += step) {
                uint32_t ijk[3] = {i, j, k};
                double dir[3], p[3], n[3];
                lattice_direction(l, ijk, dir);
                shape(dir, p, n);
                size_t v = 3 * (size_t)lattice_vertex_id(l, ijk);
                for (int e = 0; e < 3; e++) {
                    m->positions[v + e] = (float)p[e];
                    m->normals[v + e] = (float)n[e];
                }
            }
        }
    }
}

static void fill_lattice_triangles(struct lucent_mesh *m, const box_lattice *l)
{
    /* (u, v, w) with e_u x e_v = e_w: corners in (u, v) order are counter-clockwise seen from +w */
    static const int faces[3][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}};
    static const uint32_t ccw[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    uint32_t *out = m->indices;
    for (int f = 0; f < 3; f++) {
        int u = faces[f][0], v = faces[f][1], w = faces[f][2];
        for (int far_side = 0; far_side <= 1; far_side++) {
            for (uint32_t iu = 0; iu < l->cells[u]; iu++) {
                for (uint32_t iv = 0; iv < l->cells[v]; iv++) {
                    uint32_t q[4];
                    for (int corner = 0; corner < 4; corner++) {
                        /* the near side faces -w, so its corners run the other way round */
                        const uint32_t *d = ccw[far_side ? corner : (4 - corner) % 4];
                        uint32_t ijk[3];
                        ijk[u] = iu + d[0];
                        ijk[v] = iv + d[1];
                        ijk[w] = far_side ? l->cells[w] : 0;
                        q[corner] = lattice_vertex_id(l, ijk);
                    }
                    out = emit_quad(m->positions, q, out);
                }
            }
        }
    }
}

static lucent_status finish_or_free(struct lucent_mesh *m, lucent_mesh **out, lucent_error *err)
{
    lucent_status st = mesh_finish(m, err);
    if (st != LUCENT_OK) {
        lucent_mesh_free(m);
        return st;
    }
    *out = m;
    return LUCENT_OK;
}

static lucent_status build_lattice_shape(uint32_t triangles, radial_shape shape, int convex,
                                         lucent_mesh **out, lucent_error *err)
{
    box_lattice l = plan_box_lattice(triangles);
    struct lucent_mesh *m = mesh_alloc(lattice_vertex_count(&l), lattice_triangle_count(&l), 1);
    if (!m)
        return lucent_fail(err, LUCENT_E_NOMEM, "mesh.triangles",
                           "out of memory for %u triangles", lattice_triangle_count(&l));
    fill_lattice_vertices(m, &l, shape);
    fill_lattice_triangles(m, &l);
    m->convex = convex;
    m->closed = 1;   /* by construction, wound outward; spares mesh_finish the edge sort */
    return finish_or_free(m, out, err);
}

static lucent_status build_sphere(uint32_t triangles, lucent_mesh **out, lucent_error *err)
{
    return build_lattice_shape(triangles, sphere_point, 1, out, err);
}

static lucent_status build_protrusion(uint32_t triangles, lucent_mesh **out, lucent_error *err)
{
    return build_lattice_shape(triangles, protrusion_point, 0, out, err);
}

/* ---- the torus ---- */

static lucent_status build_torus(uint32_t triangles, lucent_mesh **out, lucent_error *err)
{
    torus_grid g = plan_torus_grid(triangles);
    struct lucent_mesh *m = mesh_alloc(g.major * g.minor, 2 * g.major * g.minor, 1);
    if (!m)
        return lucent_fail(err, LUCENT_E_NOMEM, "mesh.triangles",
                           "out of memory for %u triangles", 2 * g.major * g.minor);
    for (uint32_t i = 0; i < g.major; i++) {
        double phi = 2 * PI * i / g.major;
        for (uint32_t j = 0; j < g.minor; j++) {
            double psi = 2 * PI * j / g.minor;
            double ring = TORUS_MAJOR_RADIUS + TORUS_MINOR_RADIUS * cos(psi);
            size_t v = 3 * ((size_t)i * g.minor + j);
            m->positions[v + 0] = (float)(ring * cos(phi));
            m->positions[v + 1] = (float)(ring * sin(phi));
            m->positions[v + 2] = (float)(TORUS_MINOR_RADIUS * sin(psi));
            m->normals[v + 0] = (float)(cos(psi) * cos(phi));
            m->normals[v + 1] = (float)(cos(psi) * sin(phi));
            m->normals[v + 2] = (float)sin(psi);
        }
    }
    /* increasing phi then psi is counter-clockwise seen from outside the tube */
    uint32_t *tri = m->indices;
    for (uint32_t i = 0; i < g.major; i++) {
        uint32_t i1 = (i + 1) % g.major;
        for (uint32_t j = 0; j < g.minor; j++) {
            uint32_t j1 = (j + 1) % g.minor;
            uint32_t q[4] = {i * g.minor + j, i1 * g.minor + j, i1 * g.minor + j1, i * g.minor + j1};
            tri = emit_quad(m->positions, q, tri);
        }
    }
    m->convex = 0;
    m->closed = 1;
    return finish_or_free(m, out, err);
}

/* ---- the Stanford bunny ---- */

/* The scan as the npm package has it (watertight: mesh_finish finds it closed); smooth normals from mesh_finish. */
static lucent_status build_bunny(uint32_t triangles, lucent_mesh **out, lucent_error *err)
{
    (void)triangles;
    struct lucent_mesh *m = mesh_alloc(stanford_bunny_vertex_count, stanford_bunny_triangle_count, 0);
    if (!m)
        return lucent_fail(err, LUCENT_E_NOMEM, "mesh.builtin", "out of memory for the bunny");
    memcpy(m->positions, stanford_bunny_positions, 3 * sizeof(float) * stanford_bunny_vertex_count);
    memcpy(m->indices, stanford_bunny_triangles, 3 * sizeof(uint32_t) * stanford_bunny_triangle_count);
    return finish_or_free(m, out, err);
}

/* ---- lookup ---- */

typedef struct builtin_shape {
    const char *name;
    lucent_status (*build)(uint32_t triangles, lucent_mesh **out, lucent_error *err);
    int fixed; /* a scanned mesh: one density, mesh.triangles refused */
} builtin_shape;

static const builtin_shape SHAPES[] = {
    {"sphere", build_sphere, 0},
    {"torus", build_torus, 0},
    {"protrusion", build_protrusion, 0},
    {"bunny", build_bunny, 1},
};
#define SHAPE_COUNT (sizeof SHAPES / sizeof SHAPES[0])

static const builtin_shape *find_shape(const char *name)
{
    for (size_t i = 0; name && i < SHAPE_COUNT; i++)
        if (strcmp(name, SHAPES[i].name) == 0)
            return &SHAPES[i];
    return NULL;
}

static lucent_status fail_unknown_shape(const char *name, lucent_error *err)
{
    char names[64] = "";
    size_t used = 0;
    for (size_t i = 0; i < SHAPE_COUNT && used < sizeof names; i++)
        used += (size_t)snprintf(names + used, sizeof names - used, "%s%s", i ? ", " : "",
                                 SHAPES[i].name);
    return lucent_fail(err, LUCENT_E_INVALID, "mesh.builtin",
                       "unknown builtin mesh \"%.32s\"; valid names are %s", name ? name : "",
                       names);
}

lucent_status lucent_mesh_builtin(const char *name, uint32_t triangles, lucent_mesh **out,
                                  lucent_error *err)
{
    *out = NULL;
    const builtin_shape *shape = find_shape(name);
    if (!shape)
        return fail_unknown_shape(name, err);
    if (shape->fixed && triangles != 0)
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.triangles",
                           "the %s is a scan of %u triangles and has no other density; omit mesh.triangles",
                           shape->name, stanford_bunny_triangle_count);
    if (triangles == 0)
        triangles = DEFAULT_TRIANGLES;
    if (triangles < LUCENT_MIN_BUILTIN_TRIANGLES || triangles > LUCENT_MAX_BUILTIN_TRIANGLES)
        return lucent_fail(err, LUCENT_E_LIMIT, "mesh.triangles",
                           "must be 0 (the default, %u) or between %u and %u; got %u",
                           DEFAULT_TRIANGLES, LUCENT_MIN_BUILTIN_TRIANGLES, LUCENT_MAX_BUILTIN_TRIANGLES,
                           triangles);
    return shape->build(triangles, out, err);
}
