/* dipole.c - the classic dipole of Jensen et al. 2001 and the tables the scatter pass samples with.
 * Written for the extremes: sigma_a = 0 (sigma_tr = 0), eta = 1, coefficients from 1e-6 to 1e5 mm^-1. */
#include "dipole.h"
#include "linalg.h"

#include <math.h>


double dipole_fdr(double eta)
{
    return -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
}

double dipole_boundary_a(double eta)
{
    double fdr = dipole_fdr(eta);
    return (1.0 + fdr) / (1.0 - fdr);
}

void dipole_init(struct dipole *d, double sigma_a, double sigma_s_prime, double eta)
{
    d->sigma_a = sigma_a;
    d->sigma_s_prime = sigma_s_prime;
    d->eta = eta;
    d->sigma_t_prime = sigma_a + sigma_s_prime;
    /* 1 - alpha' is sigma_a / sigma_t' exactly; never derive it from alpha' (precision near 1). */
    d->alpha_prime = sigma_s_prime / d->sigma_t_prime;
    d->sigma_tr = sqrt(3.0 * sigma_a * d->sigma_t_prime);
    d->z_r = 1.0 / d->sigma_t_prime;
    d->z_v = d->z_r * (1.0 + 4.0 * dipole_boundary_a(eta) / 3.0);
}

static double source_term(double z, double sigma_tr, double r)
{
    double dist = sqrt(r * r + z * z);
    return z * (sigma_tr * dist + 1.0) * exp(-sigma_tr * dist) / (dist * dist * dist);
}

double dipole_rd(const struct dipole *d, double r)
{
    return d->alpha_prime / (4.0 * PI) *
           (source_term(d->z_r, d->sigma_tr, r) + source_term(d->z_v, d->sigma_tr, r));
}

double dipole_rd_total(const struct dipole *d)
{
    double s = sqrt(3.0 * d->sigma_a / d->sigma_t_prime);
    double a = dipole_boundary_a(d->eta);
    return 0.5 * d->alpha_prime * (1.0 + exp(-4.0 / 3.0 * a * s)) * exp(-s);
}

static double disc_term(double z, double sigma_tr, double radius)
{
    double dist = sqrt(radius * radius + z * z);
    return exp(-sigma_tr * z) - z * exp(-sigma_tr * dist) / dist;
}

double dipole_rd_disc(const struct dipole *d, double radius)
{
    return 0.5 * d->alpha_prime * (disc_term(d->z_r, d->sigma_tr, radius) + disc_term(d->z_v, d->sigma_tr, radius));
}

double fresnel_transmittance(double eta, double cos_i)
{
    double c = fmin(fmax(cos_i, 0.0), 1.0);
    if (c == 0.0)
        return 0.0;
    /* eta >= 1: light enters the denser medium, so g is real (no total internal reflection). */
    double g = sqrt(eta * eta - 1.0 + c * c);
    double a = (g - c) / (g + c);
    double b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    double fr = 0.5 * a * a * (1.0 + b * b);
    return 1.0 - fmin(fr, 1.0);
}

/* The profile is integrated on a log-spaced radius grid: its scale runs from z_r (1e-5 mm for dense
 * media) to r_max (metres for sigma_a = 0), so a linear grid cannot resolve both ends. */
#define GRID 2048

struct radial_cdf {
    double r[GRID + 1];
    double cdf[GRID + 1];   /* integral of 2 pi r R_d from 0 to r[i] */
};

/* Area density of the profile to tabulate: one channel's R_d, or the mixture of three. */
struct profile {
    const struct dipole *d;
    int channels;
    double scale[3];   /* each channel's factor: 1, or 1 / (3 R_trunc,c) for the mixture */
};

static double profile_at(const struct profile *p, double r)
{
    double sum = 0.0;
    for (int c = 0; c < p->channels; c++)
        sum += p->scale[c] * dipole_rd(&p->d[c], r);
    return sum;
}

static void build_cdf(const struct profile *p, double r_max, struct radial_cdf *t)
{
    double z_min = p->d[0].z_r;
    for (int c = 1; c < p->channels; c++)
        z_min = fmin(z_min, p->d[c].z_r);
    double r_lo = fmin(z_min * 1e-3, r_max * 1e-6);
    double ratio = log(r_max / r_lo) / (GRID - 1);
    t->r[0] = 0.0;
    /* The disc below r_lo carries R_d(0) * area; R_d is flat there. */
    t->r[1] = r_lo;
    t->cdf[0] = 0.0;
    t->cdf[1] = PI * r_lo * r_lo * profile_at(p, 0.0);
    double prev_f = 2.0 * PI * r_lo * profile_at(p, r_lo);
    for (int i = 2; i <= GRID; i++) {
        t->r[i] = r_lo * exp(ratio * (i - 1));
        double f = 2.0 * PI * t->r[i] * profile_at(p, t->r[i]);
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

double dipole_sample_radii(const struct dipole *d, double r_min, double r_max, int n, double *radii,
                           double *weights)
{
    static _Thread_local struct radial_cdf table;
    struct profile p = {d, 1, {1.0}};
    build_cdf(&p, r_max, &table);
    stratify(&table, r_min, n, radii);
    double span = dipole_rd_disc(d, r_max) - dipole_rd_disc(d, r_min);
    for (int j = 0; j < n; j++)
        weights[j] = span / dipole_rd(d, radii[j]);
    return span;
}

void dipole_mixture_radii(const struct dipole d[3], double r_min, double r_max, int n, double *radii,
                          double *weights)
{
    static _Thread_local struct radial_cdf table;
    struct profile p = {d, 3, {0}};
    double span = 0.0;
    for (int c = 0; c < 3; c++) {
        double total = dipole_rd_disc(&d[c], r_max);
        p.scale[c] = 1.0 / (3.0 * total);
        span += p.scale[c] * (total - dipole_rd_disc(&d[c], r_min));
    }
    build_cdf(&p, r_max, &table);
    stratify(&table, r_min, n, radii);
    for (int j = 0; j < n; j++)
        weights[j] = span / (n * profile_at(&p, radii[j]));
}
