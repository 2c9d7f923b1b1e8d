/* sphere_diffusion.c - diffusion from the dipole's real source in a sphere (a series in Legendre polynomials
 * and modified spherical Bessel functions) and the table of its ratio to R between points (sphere_diffusion.h). */
#include "sphere_diffusion.h"
#include "linalg.h"

#include <math.h>
#include <stdlib.h>

/* Legendre terms: the source sits z_r under a surface of radius a, so term l falls as (1 - z_r / a)^l. */
#define TERMS_PER_RADIUS 20.0
#define MAX_TERMS 16384
/* The i_l ratios' downward recurrence starts this far above the last term used. */
#define RECURRENCE_GUARD 200
/* Where the sum is this small against its largest terms it is rounding noise: the table holds the last
 * angle computed cleanly (light so faint there that any bounded factor will do). */
#define CANCELLATION 1e-9

/* log k_l(x) and k_l'(x) / k_l(x) for l = 0..n-1, k_l(x) = sqrt(pi / 2x) K_(l+1/2)(x) (upward recurrence,
 * stable for the growing solution). */
static void k_sequence(double x, int n, double *log_k, double *slope)
{
    double ratio = 0.0;   /* k_l / k_(l-1) */
    log_k[0] = log(PI / 2.0) - x - log(x);
    slope[0] = -(1.0 + 1.0 / x);
    for (int l = 1; l < n; l++) {
        ratio = l == 1 ? 1.0 + 1.0 / x : 1.0 / ratio + (2.0 * l - 1.0) / x;
        log_k[l] = log_k[l - 1] + log(ratio);
        slope[l] = -1.0 / ratio - (l + 1.0) / x;
    }
}

/* log i_l(x) and i_l'(x) / i_l(x), i_l(x) = sqrt(pi / 2x) I_(l+1/2)(x) (ratios by downward recurrence,
 * stable for the decaying solution); ratio holds n entries of scratch. */
static void i_sequence(double x, int n, double *log_i, double *slope, double *ratio)
{
    double r = 0.0;   /* i_l / i_(l-1) */
    for (int l = n - 1 + RECURRENCE_GUARD; l >= 1; l--) {
        r = 1.0 / ((2.0 * l + 1.0) / x + r);
        if (l < n)
            ratio[l] = r;
    }
    log_i[0] = x > 20.0 ? x - log(2.0 * x) + log1p(-exp(-2.0 * x)) : log(sinh(x) / x);
    slope[0] = n > 1 ? ratio[1] : 1.0 / tanh(x) - 1.0 / x;
    for (int l = 1; l < n; l++) {
        log_i[l] = log_i[l - 1] + log(ratio[l]);
        slope[l] = 1.0 / ratio[l] - (l + 1.0) / x;
    }
}

/* c_l of J(gamma) = sum_l c_l P_l(cos gamma): the flux -D dphi/dr at r = a of the source z_r inside,
 * phi = alpha' / (4 pi D) (2 sigma / pi) sum (2l + 1) P_l i_l(s r0) [k_l(s r) - k_l(s a_e) i_l(s r) / i_l(s a_e)]. */
static void exitance_terms(const struct profile *p, double a, int n, double *c, double *scratch)
{
    double s = p->sigma[0], z0 = p->z[0], zb = 0.5 * (p->z[1] - p->z[0]), alpha = 4.0 * PI * p->b[0] / z0;
    double *li0 = scratch, *di0 = li0 + n, *li = di0 + n, *di = li + n, *lie = di + n, *die = lie + n;
    double *lk = die + n, *dk = lk + n, *lke = dk + n, *dke = lke + n, *ratio = dke + n;
    i_sequence(s * (a - z0), n, li0, di0, ratio);
    i_sequence(s * a, n, li, di, ratio);
    i_sequence(s * (a + zb), n, lie, die, ratio);
    k_sequence(s * a, n, lk, dk);
    k_sequence(s * (a + zb), n, lke, dke);
    double scale = -alpha / (4.0 * PI) * 2.0 * s * s / PI;
    for (int l = 0; l < n; l++) {
        double free_space = exp(li0[l] + lk[l]) * dk[l];
        double boundary = exp(li0[l] + lke[l] + li[l] - lie[l]) * di[l];
        c[l] = scale * (2.0 * l + 1.0) * (free_space - boundary);
    }
}

static int term_count(const struct profile *p, double a)
{
    double n = ceil(TERMS_PER_RADIUS * a / p->z[0]) + 20.0;
    return n < MAX_TERMS ? (int)n : MAX_TERMS;
}

/* sum_l c_l P_l(x); *magnitude gets sum_l |c_l P_l(x)|. */
static double legendre_sum(const double *c, int n, double x, double *magnitude)
{
    double p0 = 1.0, p1 = x, sum = c[0] + (n > 1 ? c[1] * x : 0.0);
    double size = fabs(c[0]) + (n > 1 ? fabs(c[1] * x) : 0.0);
    for (int l = 2; l < n; l++) {
        double p2 = ((2.0 * l - 1.0) * x * p1 - (l - 1.0) * p0) / l;
        sum += c[l] * p2;
        size += fabs(c[l] * p2);
        p0 = p1;
        p1 = p2;
    }
    *magnitude = size;
    return sum;
}

static lucent_status alloc_terms(int n, double **c, double **scratch, lucent_error *err)
{
    *c = malloc((size_t)n * sizeof **c);
    *scratch = malloc((size_t)n * 11 * sizeof **scratch);
    if (*c && *scratch)
        return LUCENT_OK;
    free(*c);
    free(*scratch);
    return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory for %d terms of diffusion in a sphere", n);
}

lucent_status sphere_exitance(const struct profile *p, double a_mm, int count, const double *cos_gamma,
                              double *out, lucent_error *err)
{
    int n = term_count(p, a_mm);
    double *c, *scratch, magnitude;
    lucent_status st = alloc_terms(n, &c, &scratch, err);
    if (st != LUCENT_OK)
        return st;
    exitance_terms(p, a_mm, n, c, scratch);
    for (int i = 0; i < count; i++)
        out[i] = legendre_sum(c, n, cos_gamma[i], &magnitude);
    free(c);
    free(scratch);
    return LUCENT_OK;
}

static double table_t(int i)
{
    return SPHERE_T_MIN * pow(SPHERE_T_MAX / SPHERE_T_MIN, (double)i / (SPHERE_TABLE_T - 1));
}

/* The profile scaled so that a sphere of radius a is at most MAX_TERMS / TERMS_PER_RADIUS of its z_r: where
 * z_r is smaller still (albedo near 1 in a dense medium) the sphere's light depends on z_r / a no more. */
static struct profile within_terms(const struct profile *p, double a)
{
    struct profile q = *p;
    double k = a / (p->z[0] * (MAX_TERMS - 20) / TERMS_PER_RADIUS);
    if (k > 1.0)
        for (int i = 0; i < 2; i++)
            q.z[i] *= k, q.b[i] *= k;
    return q;
}

lucent_status sphere_table_init(struct sphere_table *t, const struct profile *p, lucent_error *err)
{
    /* Only the classical dipoles have one real source of flux terms to put in a sphere. */
    t->sources = (p->kind == LUCENT_PROFILE_DIPOLE || p->kind == LUCENT_PROFILE_ASYMPTOTIC_DIPOLE) && p->z[0] > 0.0 && p->sigma[0] > 0.0 && isfinite(p->sigma[0]);
    t->sigma = p->sigma[0];
    for (int i = 0; i < SPHERE_TABLE_T; i++)
        for (int j = 0; j < SPHERE_TABLE_G; j++)
            t->factor[i][j] = 1.0f;
    if (!t->sources)
        return LUCENT_OK;
    double *c, *scratch;
    lucent_status st = alloc_terms(MAX_TERMS, &c, &scratch, err);
    if (st != LUCENT_OK)
        return st;
    for (int i = 0; i < SPHERE_TABLE_T; i++) {
        double a = table_t(i) / p->sigma[0], held = 1.0;
        struct profile q = within_terms(p, a);
        /* The real source must lie in the sphere's outer half (a radius of a few mean free paths at least). */
        if (a <= 2.0 * q.z[0])
            continue;
        int n = term_count(&q, a);
        exitance_terms(&q, a, n, c, scratch);
        for (int j = 1; j < SPHERE_TABLE_G; j++) {
            double g = PI * j / (SPHERE_TABLE_G - 1), magnitude;
            double n_in[3] = {sin(g), 0.0, cos(g)}, n_out[3] = {0.0, 0.0, 1.0};
            double d[3] = {-a * n_in[0], 0.0, a - a * n_in[2]};
            double exact = legendre_sum(c, n, cos(g), &magnitude);
            double between = profile_rd_between(&q, d, n_out, n_in), f = exact / between;
            if (exact > CANCELLATION * magnitude && between > 0.0 && isfinite(f))
                held = f;
            t->factor[i][j] = (float)held;
        }
    }
    free(c);
    free(scratch);
    return LUCENT_OK;
}

static int same_profile(const struct profile *a, const struct profile *b)
{
    int same = a->kind == b->kind && a->sigma_t_prime == b->sigma_t_prime;
    for (int k = 0; k < 2; k++)
        same = same && a->z[k] == b->z[k] && a->sigma[k] == b->sigma[k] && a->a[k] == b->a[k] && a->b[k] == b->b[k];
    return same;
}

lucent_status sphere_tables_for(struct sphere_tables *t, const struct profile p[3], lucent_error *err)
{
    if (t->filled && same_profile(&t->made_for[0], &p[0]) && same_profile(&t->made_for[1], &p[1]) &&
        same_profile(&t->made_for[2], &p[2]))
        return LUCENT_OK;
    t->filled = 0;
    for (int c = 0; c < 3; c++) {
        lucent_status st = sphere_table_init(&t->channel[c], &p[c], err);
        if (st != LUCENT_OK)
            return st;
        t->made_for[c] = p[c];
    }
    t->filled = 1;
    return LUCENT_OK;
}

double sphere_factor_curvature(double curvature, double thickness)
{
    return curvature * fmin(fmax(thickness * curvature, 0.0), 1.0);
}

double sphere_factor(const struct sphere_table *t, const double d[3], const double n_out[3], const double n_in[3],
                     double curvature_mm)
{
    if (!t->sources || curvature_mm <= 0.0)
        return 1.0;
    double depth = 0.5 * (v3_dot(d, n_out) - v3_dot(d, n_in)), dd = v3_dot(d, d);
    double len_in = v3_length(n_in);
    if (depth <= 0.0 || len_in <= 0.0)
        return 1.0;
    double a = dd / (2.0 * depth), weight = fmin(curvature_mm * a, 1.0);
    double cos_g = fmin(fmax(v3_dot(n_in, n_out) / len_in, -1.0), 1.0);
    double u = log(fmin(fmax(t->sigma * a, SPHERE_T_MIN), SPHERE_T_MAX) / SPHERE_T_MIN) /
               log(SPHERE_T_MAX / SPHERE_T_MIN) * (SPHERE_TABLE_T - 1);
    double v = acos(cos_g) / PI * (SPHERE_TABLE_G - 1);
    int i = (int)fmin(u, SPHERE_TABLE_T - 2), j = (int)fmin(v, SPHERE_TABLE_G - 2);
    double fu = u - i, fv = v - j;
    double f = (1.0 - fu) * ((1.0 - fv) * t->factor[i][j] + fv * t->factor[i][j + 1]) +
               fu * ((1.0 - fv) * t->factor[i + 1][j] + fv * t->factor[i + 1][j + 1]);
    return 1.0 + weight * (f - 1.0);
}
