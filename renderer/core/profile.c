/* profile.c - evaluation, closed-form integrals and sampling tables of the two-source diffusion profiles
 * (profile.h). Written for the extremes: sigma_a = 0, eta = 1, coefficients from 1e-6 to 1e5 mm^-1. */
#include "profile.h"
#include "dipole.h"
#include "linalg.h"
#include "normalized_diffusion.h"

#include <math.h>

void profile_init(struct profile *p, lucent_profile kind, double sigma_a, double sigma_s_prime, double g,
                  double eta)
{
    if (kind == LUCENT_PROFILE_BETTER_DIPOLE)
        dipole_better(p, sigma_a, sigma_s_prime, eta);
    else if (kind == LUCENT_PROFILE_ASYMPTOTIC_DIPOLE)
        dipole_asymptotic(p, sigma_a, sigma_s_prime, eta);
    else if (kind == LUCENT_PROFILE_BURLEY)
        burley_profile(p, sigma_a, sigma_s_prime, g, eta);
    else
        dipole_classic(p, sigma_a, sigma_s_prime, eta);
}

/* (1 - e^(-x)) / x, 1 at x = 0. */
static double fraction(double x)
{
    return x > 1e-8 ? -expm1(-x) / x : 1.0 - 0.5 * x;
}

/* e^(-s d0) / d0 - e^(-s d1) / d1 for d1 >= d0 > 0, given gap = d1 - d0 (computed without cancelling):
 * e^(-s d0) gap (1 + s d0 fraction(s gap)) / (d0 d1). */
static double falloff_difference(double s, double d0, double d1, double gap)
{
    return exp(-s * d0) * gap * (1.0 + s * d0 * fraction(s * gap)) / (d0 * d1);
}

/* The better dipole's fluence terms: a_1 = -a_0 at one rate, the virtual source below the real one. */
static int paired(const struct profile *p)
{
    return p->a[0] != 0.0 && p->a[1] == -p->a[0] && p->sigma[0] == p->sigma[1];
}

/* Distance from the exit point's axis at radius r to source k; the difference of the two as well. */
static double source_distance(const struct profile *p, int k, double r)
{
    return sqrt(r * r + p->z[k] * p->z[k]);
}

static double source_gap(const struct profile *p, double d0, double d1)
{
    return (p->z[1] - p->z[0]) * (p->z[1] + p->z[0]) / (d0 + d1);
}

/* The paired fluence terms' integral outside radius t, over 2 pi: (e^(-s d0) - e^(-s d1)) / s, finite at
 * s = 0 (sigma_a = 0). */
static double paired_tail(const struct profile *p, double t)
{
    double d0 = source_distance(p, 0, t), d1 = source_distance(p, 1, t), gap = source_gap(p, d0, d1);
    return p->a[0] * exp(-p->sigma[0] * d0) * gap * fraction(p->sigma[0] * gap);
}

double profile_rd(const struct profile *p, double r)
{
    /* Sources at z = 0 (normalized diffusion) diverge as 1 / r at the exit point; a floor far inside
     * the first mean free path keeps R finite without changing any integral measurably. */
    double floor_mm = 1e-6 / p->sigma_t_prime, d[2], sum = 0.0;
    for (int k = 0; k < 2; k++) {
        d[k] = fmax(source_distance(p, k, r), floor_mm);
        sum += p->b[k] * exp(-p->sigma[k] * d[k]) * (1.0 + p->sigma[k] * d[k]) / (d[k] * d[k] * d[k]);
    }
    if (paired(p))
        return sum + p->a[0] * falloff_difference(p->sigma[0], d[0], d[1], source_gap(p, d[0], d[1]));
    for (int k = 0; k < 2; k++)
        sum += p->a[k] * exp(-p->sigma[k] * d[k]) / d[k];
    return sum;
}

/* One source's share of R at the exit point: fluence coefficient a, flux coefficient per unit of depth c,
 * rate s, at signed depth h below the exit's tangent plane (negative: above it) and distance d. */
static double source_term(double a, double c, double s, double h, double d)
{
    return exp(-s * d) * (a / d + c * h * (1.0 + s * d) / (d * d * d));
}

/* The distance to the exit point of a source at depth `to`, across2 (squared) across the exit's plane from
 * it, no nearer than `nearest`. */
static double moved_distance(double across2, double to, double nearest)
{
    return fmax(sqrt(across2 + to * to), nearest);
}

/* Two sources placed for light entering at d (exit - entry, mm) from the exit point: their depth (height) under
 * the exit's tangent plane, their distances from the exit point and their images' (profile_rd_between). */
struct sources {
    double h0, h1, i0, i1, w; /* real depth, virtual height, their images' depths, weight of the images */
    double d0, d1, e0, e1;    /* distances: the real and virtual sources, their images across the exit's boundary */
    double c0, c1;            /* flux coefficients per unit of depth, b / z */
};

static void place_sources(const struct profile *p, const double d[3], const double n_out[3], const double n_in[3],
                          struct sources *q)
{
    /* The real source z_0 inside the entry point along its normal, the virtual one z_1 outside it, and the
     * light they send through the exit's tangent plane. The real source is never taken shallower under
     * that plane than on a flat surface (a thin part, a fold, or an entry point outside the plane: the
     * source keeps its distance and moves to depth z_0; the virtual one stays within 2 z_b above it), and
     * the virtual one is never nearer the exit point than on a plane (only an exit point outside the entry's
     * plane, across air, brings it nearer), so R stays near the planar kernel's peak (within 1%). */
    double floor_mm = 1e-6 / p->sigma_t_prime, tilt = v3_dot(n_in, n_out), z0 = p->z[0], z1 = p->z[1];
    double real[3], virt[3];   /* exit point minus each source */
    for (int a = 0; a < 3; a++) {
        real[a] = d[a] + z0 * n_in[a];
        virt[a] = d[a] - z1 * n_in[a];
    }
    double dd = v3_dot(d, d), depth = v3_dot(real, n_out), zb = 0.5 * (z1 - z0);
    q->h0 = fmax(depth, z0);
    q->h1 = fmin(-v3_dot(virt, n_out), q->h0 + 2.0 * zb);
    /* A real source shallower than z_0 under the exit plane by a convex edge (light entering one face by
     * the edge, leaving the other) is no nearer than on a plane at the straight distance, blended in over
     * its depth 0..z_0 and over the faces' angle (none through opposite faces, where a thin part does
     * carry the light through): at its own distance it made a bright line along a lit cube's edges
     * (skin1: rel L2 0.235 -> 0.212 against method path). */
    double shallow = fmin(fmax((z0 - depth) / z0, 0.0), 1.0) * fmin(fmax(1.0 + tilt, 0.0), 1.0);
    q->d0 = fmax(fmax(fmax(v3_length(real), floor_mm), q->h0), shallow * sqrt(dd + z0 * z0));
    q->d1 = fmax(fmax(v3_length(virt), sqrt(dd + z1 * z1)), fabs(q->h1));
    /* The exit's own boundary: each source's image across the exit's extrapolated boundary (z_b beyond
     * it), opposite in sign. On one plane these are the other source (already counted); through opposite
     * faces they are Donner and Jensen's next pair; between, weighted by the faces' angle. Through slabs of
     * 3-25 mm they bring the light to 0.77-1.19 of method "path"'s in marble (0.49-0.63 without). */
    double across0 = q->d0 * q->d0 - q->h0 * q->h0, across1 = fmax(q->d1 * q->d1 - q->h1 * q->h1, 0.0);
    q->i0 = q->h0 + 2.0 * zb;
    q->i1 = q->h1 - 2.0 * zb;
    q->w = 0.5 * (1.0 - tilt);
    q->e0 = moved_distance(across0, q->i0, floor_mm);
    q->e1 = moved_distance(across1, q->i1, fmax(z0, floor_mm));
    q->c0 = p->b[0] / z0;
    q->c1 = p->b[1] / z1;
}

double profile_rd_between(const struct profile *p, const double d[3], const double n_out[3], const double n_in[3])
{
    if (p->z[0] <= 0.0)
        return profile_rd(p, v3_length(d));
    struct sources q;
    place_sources(p, d, n_out, n_in, &q);
    double sum = source_term(p->a[0], q.c0, p->sigma[0], q.h0, q.d0) +
                 source_term(p->a[1], q.c1, p->sigma[1], q.h1, q.d1);
    sum += q.w * (source_term(-p->a[0], q.c0, p->sigma[0], q.i0, q.e0) +
                  source_term(-p->a[1], q.c1, p->sigma[1], q.i1, q.e1));
    return fmax(sum, 0.0);
}

/* One source's share of R integrated over a disc of radius `radius` centred on the exit's normal, the source
 * at signed depth h and no nearer than `nearest`: 2 pi (a (e^(-s h) - e^(-s D)) / s + c h (e^(-s h) / h -
 * e^(-s D) / D)), D = sqrt(radius^2 + h^2), written not to cancel. */
static double source_disc(double a, double c, double s, double h, double radius, double nearest)
{
    double inner = fmax(fabs(h), nearest), outer = sqrt(radius * radius + inner * inner);
    double delta = radius * radius / (inner + outer);
    return 2.0 * PI *
           (a * exp(-s * inner) * delta * fraction(s * delta) + c * h * falloff_difference(s, inner, outer, delta));
}

/* How near a disc's light lies for source_disc: the disc, its centre `distance` from the exit point and `depth`
 * under its tangent plane, taken as the annulus around the exit's normal of its area that ends at its centre's
 * distance. Taken under the exit point (the distance left out), a face beside it facing as it does lit it as if
 * it lay beneath it: a side-lit bunny's shaded chest took bluish spots from its flank 19 mm away. */
static double disc_nearest(double distance, double depth, double radius)
{
    return sqrt(fmax(distance * distance - radius * radius, depth * depth));
}

double profile_disc_between(const struct profile *p, double radius, const double d[3], const double n_out[3],
                            const double n_in[3])
{
    if (p->z[0] <= 0.0)
        return profile_disc_offset(p, radius, v3_length(d));
    struct sources q;
    place_sources(p, d, n_out, n_in, &q);
    double sum = source_disc(p->a[0], q.c0, p->sigma[0], q.h0, radius, disc_nearest(q.d0, q.h0, radius)) +
                 source_disc(p->a[1], q.c1, p->sigma[1], q.h1, radius, disc_nearest(q.d1, q.h1, radius));
    sum += q.w * (source_disc(-p->a[0], q.c0, p->sigma[0], q.i0, radius, disc_nearest(q.e0, q.i0, radius)) +
                  source_disc(-p->a[1], q.c1, p->sigma[1], q.i1, radius, disc_nearest(q.e1, q.i1, radius)));
    return fmax(sum, 0.0);
}

double profile_slab_share(const struct profile *p, double r, double thickness)
{
    double z0 = p->z[0], z1 = p->z[1], half_space = profile_rd(p, fmax(r, 0.0));
    if (z0 <= 0.0 || !isfinite(thickness) || !(half_space > 0.0))
        return 1.0;
    /* Both sources moved by whole periods down and up: their images across the back's extrapolated boundary
     * and theirs across the exit's. The truncated series swings far from the entry (pairs -1..1 give 2.3x the
     * half space 30 mfp out), so the pairs run to twice the distance in periods, at least 4 (within 1e-3 of R
     * near the entry). */
    double floor_mm = 1e-6 / p->sigma_t_prime, period = 2.0 * (fmax(thickness, 0.0) + z1 - z0), images = 0.0;
    int pairs = (int)fmin(ceil(2.0 * r / period) + 4.0, PROFILE_SLAB_PAIRS);
    for (int i = 1; i <= pairs; i++)
        for (int side = -1; side <= 1; side += 2) {
            double r0 = z0 + side * i * period, r1 = z1 - side * i * period;
            images += source_term(p->a[0], p->b[0] / z0, p->sigma[0], r0, moved_distance(r * r, r0, floor_mm)) +
                      source_term(p->a[1], p->b[1] / z1, p->sigma[1], r1, moved_distance(r * r, r1, floor_mm));
        }
    return fmin(fmax(1.0 + images / half_space, 0.0), 1.0);
}

double profile_tail(const struct profile *p, double t)
{
    double d[2], sum = 0.0;
    for (int k = 0; k < 2; k++) {
        d[k] = source_distance(p, k, t);
        if (p->b[k] != 0.0)
            sum += p->b[k] * exp(-p->sigma[k] * d[k]) / d[k];
    }
    if (paired(p))
        return 2.0 * PI * (sum + paired_tail(p, t));
    for (int k = 0; k < 2; k++)
        if (p->a[k] != 0.0)
            sum += p->a[k] * exp(-p->sigma[k] * d[k]) / p->sigma[k];
    return 2.0 * PI * sum;
}

double profile_total(const struct profile *p)
{
    return profile_tail(p, 0.0);
}

double profile_disc_offset(const struct profile *p, double radius, double offset)
{
    /* T(inner) - T(outer) term by term, each written so that it does not cancel when the disc is
     * narrow: with delta = outer - inner, a fluence term gives a e^(-s inner) delta fraction(s delta)
     * and a flux term b times falloff_difference. */
    double sum = 0.0;
    for (int k = 0; k < 2; k++) {
        double inner = source_distance(p, k, offset), outer = sqrt(inner * inner + radius * radius);
        double delta = outer > 0.0 ? radius * radius / (inner + outer) : 0.0, s = p->sigma[k];
        if (p->b[k] != 0.0)
            sum += p->b[k] * falloff_difference(s, inner, outer, delta);
        if (!paired(p) || radius <= p->z[1])
            sum += p->a[k] * exp(-s * inner) * delta * fraction(s * delta);
    }
    /* A wide disc's paired fluence terms would cancel against each other; their tails do not. */
    if (paired(p) && radius > p->z[1])
        sum += paired_tail(p, fabs(offset)) - paired_tail(p, hypot(radius, offset));
    return 2.0 * PI * sum;
}

double profile_disc(const struct profile *p, double radius)
{
    return profile_disc_offset(p, radius, 0.0);
}

double profile_decay_rate(const struct profile *p)
{
    return fmin(p->sigma[0], p->sigma[1]);
}

/* The profile is integrated on a log-spaced radius grid: its scale runs from z_r (1e-5 mm for dense
 * media) to r_max (metres for sigma_a = 0), so a linear grid cannot resolve both ends. */
#define GRID 2048

struct radial_cdf {
    double r[GRID + 1];
    double cdf[GRID + 1];   /* integral of 2 pi r R from 0 to r[i] */
};

/* Area density to tabulate: one channel's R, or the mixture of three. */
struct density {
    const struct profile *p;
    int channels;
    double scale[3];   /* each channel's factor: 1, or 1 / (3 R_trunc,c) for the mixture */
};

static double density_at(const struct density *m, double r)
{
    double sum = 0.0;
    for (int c = 0; c < m->channels; c++)
        sum += m->scale[c] * profile_rd(&m->p[c], r);
    return sum;
}

static double density_disc(const struct density *m, double r)
{
    double sum = 0.0;
    for (int c = 0; c < m->channels; c++)
        sum += m->scale[c] * profile_disc(&m->p[c], r);
    return sum;
}

static void build_cdf(const struct density *m, double r_max, struct radial_cdf *t)
{
    double mfp = 1.0 / m->p[0].sigma_t_prime;
    for (int c = 1; c < m->channels; c++)
        mfp = fmin(mfp, 1.0 / m->p[c].sigma_t_prime);
    double r_lo = fmin(mfp * 1e-3, r_max * 1e-6);
    double ratio = log(r_max / r_lo) / (GRID - 1);
    t->r[0] = 0.0;
    t->r[1] = r_lo;
    t->cdf[0] = 0.0;
    /* The disc below r_lo in closed form: normalized diffusion's R is not flat there. */
    t->cdf[1] = density_disc(m, r_lo);
    double prev_f = 2.0 * PI * r_lo * density_at(m, r_lo);
    for (int i = 2; i <= GRID; i++) {
        t->r[i] = r_lo * exp(ratio * (i - 1));
        double f = 2.0 * PI * t->r[i] * density_at(m, t->r[i]);
        t->cdf[i] = t->cdf[i - 1] + 0.5 * (f + prev_f) * (t->r[i] - t->r[i - 1]);
        prev_f = f;
    }
}

/* The grid interval [lo, lo + 1] of an increasing table v[0..GRID] that holds x. */
static int bracket(const double *v, double x)
{
    int lo = 0, hi = GRID;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (v[mid] < x)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

static double invert_cdf(const struct radial_cdf *t, double target)
{
    int lo = bracket(t->cdf, target), hi = lo + 1;
    double span = t->cdf[hi] - t->cdf[lo];
    double f = span > 0.0 ? (target - t->cdf[lo]) / span : 0.0;
    return t->r[lo] + f * (t->r[hi] - t->r[lo]);
}

/* The tabulated integral from 0 to r (linear between grid points). */
static double cdf_at(const struct radial_cdf *t, double r)
{
    if (r <= 0.0)
        return 0.0;
    int lo = bracket(t->r, r), hi = lo + 1;
    double f = fmin((r - t->r[lo]) / (t->r[hi] - t->r[lo]), 1.0);
    return t->cdf[lo] + f * (t->cdf[hi] - t->cdf[lo]);
}

/* n radii stratified over the table's integral between r_min and its end. The table only places
 * them; the callers weight them with the closed form, so a sampled annulus and the closed-form disc
 * inside it add up to the plane integral without the table's quadrature error. */
static void stratify(const struct radial_cdf *t, double r_min, int n, double *radii)
{
    double lo = cdf_at(t, r_min), span = t->cdf[GRID] - lo;
    for (int j = 0; j < n; j++)
        radii[j] = invert_cdf(t, lo + span * (j + 0.5) / n);
}

double profile_sample_radii(const struct profile *p, double r_min, double r_max, int n, double *radii,
                            double *weights)
{
    static _Thread_local struct radial_cdf table;
    struct density m = {p, 1, {1.0}};
    build_cdf(&m, r_max, &table);
    stratify(&table, r_min, n, radii);
    double span = profile_disc(p, r_max) - profile_disc(p, r_min);
    for (int j = 0; j < n; j++)
        weights[j] = span / profile_rd(p, radii[j]);
    return span;
}

void profile_mixture_radii(const struct profile p[3], double r_min, double r_max, int n, double *radii,
                           double *weights)
{
    static _Thread_local struct radial_cdf table;
    struct density m = {p, 3, {0}};
    double span = 0.0;
    for (int c = 0; c < 3; c++) {
        double total = profile_disc(&p[c], r_max);
        m.scale[c] = 1.0 / (3.0 * total);
        span += m.scale[c] * (total - profile_disc(&p[c], r_min));
    }
    build_cdf(&m, r_max, &table);
    stratify(&table, r_min, n, radii);
    for (int j = 0; j < n; j++)
        weights[j] = span / (n * density_at(&m, radii[j]));
}
