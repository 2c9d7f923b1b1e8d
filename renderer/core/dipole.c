/* dipole.c - the classic, asymptotic and better dipoles as two-source profiles, and the boundary's Fresnel terms.
 * Written for the extremes: sigma_a = 0 (sigma_tr = 0), eta = 1, coefficients from 1e-6 to 1e5 mm^-1. */
#include "dipole.h"
#include "linalg.h"
#include "profile.h"

#include <math.h>
#include <string.h>

double dipole_fdr(double eta)
{
    return -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
}

double dipole_boundary_a(double eta)
{
    double fdr = dipole_fdr(eta);
    return (1.0 + fdr) / (1.0 - fdr);
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

double fresnel_internal_reflectance(double eta, double cos_i)
{
    double c = fmin(fmax(cos_i, 0.0), 1.0), k = 1.0 / eta;
    if (c == 0.0 || k * k - 1.0 + c * c <= 0.0)
        return 1.0;
    return 1.0 - fresnel_transmittance(k, c);
}

double fresnel_moment(double eta, int k)
{
    /* Below the critical cosine everything reflects; above it F_r falls off like a square root of
     * mu - mu_c, which the substitution mu = mu_c + (1 - mu_c) u^2 makes smooth for the midpoint rule. */
    enum { STEPS = 512 };
    double mu_c = eta > 1.0 ? sqrt(1.0 - 1.0 / (eta * eta)) : 0.0, span = 1.0 - mu_c;
    double sum = pow(mu_c, k + 1) / (k + 1);
    for (int i = 0; i < STEPS; i++) {
        double u = (i + 0.5) / STEPS, mu = mu_c + span * u * u;
        sum += fresnel_internal_reflectance(eta, mu) * pow(mu, k) * 2.0 * span * u / STEPS;
    }
    return sum;
}

double fresnel_diffuse_transmittance(double eta)
{
    /* From outside there is no critical angle: F_t is smooth in mu and the midpoint rule converges fast. */
    enum { STEPS = 512 };
    double sum = 0.0;
    for (int i = 0; i < STEPS; i++) {
        double mu = (i + 0.5) / STEPS;
        sum += fresnel_transmittance(eta, mu) * 2.0 * mu / STEPS;
    }
    return sum;
}

double diffuse_exit_weight(double eta)
{
    return 1.0 / (PI * fresnel_diffuse_transmittance(eta));
}

void dipole_classic(struct profile *p, double sigma_a, double sigma_s_prime, double eta)
{
    memset(p, 0, sizeof *p);
    p->kind = LUCENT_PROFILE_DIPOLE;
    p->sigma_t_prime = sigma_a + sigma_s_prime;
    double alpha_prime = sigma_s_prime / p->sigma_t_prime;
    /* sigma_a / sigma_t' is 1 - alpha' exactly; never derived from alpha' (precision near 1). */
    double sigma_tr = sqrt(3.0 * sigma_a * p->sigma_t_prime);
    p->z[0] = 1.0 / p->sigma_t_prime;
    p->z[1] = p->z[0] * (1.0 + 4.0 * dipole_boundary_a(eta) / 3.0);
    for (int k = 0; k < 2; k++) {
        p->sigma[k] = sigma_tr;
        p->b[k] = alpha_prime * p->z[k] / (4.0 * PI);
    }
}

/* atanh(x) / x - 1 = x^2 / 3 + x^4 / 5 + ..., without cancelling for small x. */
static double atanh_ratio_excess(double x)
{
    if (x > 1e-2)
        return atanh(x) / x - 1.0;
    double x2 = x * x, sum = 0.0;
    for (int k = 9; k >= 1; k--)
        sum = x2 * (1.0 / (2 * k + 1) + sum);
    return sum;
}

double transport_decay_rate(double absorption_over_scattering)
{
    double want = absorption_over_scattering;
    if (!(want > 0.0))
        return 0.0;
    if (!(want < INFINITY))
        return 1.0;
    /* increasing in nu from 0 to infinity: bisection to the last bit, from diffusion's estimate up */
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 200 && hi - lo > 1e-17 * hi; i++) {
        double mid = 0.5 * (lo + hi);
        if (atanh_ratio_excess(mid) > want)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}

void dipole_asymptotic(struct profile *p, double sigma_a, double sigma_s_prime, double eta)
{
    dipole_classic(p, sigma_a, sigma_s_prime, eta);
    p->kind = LUCENT_PROFILE_ASYMPTOTIC_DIPOLE;
    double classic_total = profile_total(p), rate = sigma_s_prime > 0.0
                                                      ? transport_decay_rate(sigma_a / sigma_s_prime) * p->sigma_t_prime
                                                      : p->sigma_t_prime;
    for (int k = 0; k < 2; k++)
        p->sigma[k] = rate;
    double total = profile_total(p);
    if (total > 0.0 && isfinite(total) && classic_total > 0.0)
        for (int k = 0; k < 2; k++)
            p->b[k] *= classic_total / total;
}

void dipole_better(struct profile *p, double sigma_a, double sigma_s_prime, double eta)
{
    dipole_better_at(p, sigma_a, sigma_s_prime, fresnel_moment(eta, 1), fresnel_moment(eta, 2),
                     1.0 / (sigma_a + sigma_s_prime));
}

void dipole_better_at(struct profile *p, double sigma_a, double sigma_s_prime, double c1, double c2, double depth)
{
    memset(p, 0, sizeof *p);
    p->kind = LUCENT_PROFILE_BETTER_DIPOLE;
    double sigma_t = sigma_a + sigma_s_prime, alpha_prime = sigma_s_prime / sigma_t;
    double d = (2.0 * sigma_a + sigma_s_prime) / (3.0 * sigma_t * sigma_t);
    double a = (1.0 + 3.0 * c2) / (1.0 - 2.0 * c1);
    double c_phi = 0.25 * (1.0 - 2.0 * c1), c_e = 0.5 * (1.0 - 3.0 * c2);
    double scale = alpha_prime * alpha_prime / (4.0 * PI);
    p->sigma_t_prime = sigma_t;
    /* The virtual source sits above the boundary (z_v < 0 in d'Eon's convention); the profile only
     * needs its distance, and its flux term's sign flips with z_v's. */
    p->z[0] = depth;
    p->z[1] = depth + 4.0 * a * d;
    for (int k = 0; k < 2; k++) {
        p->sigma[k] = sqrt(sigma_a / d);
        p->b[k] = scale * c_e * p->z[k];
    }
    p->a[0] = scale * c_phi / d;
    p->a[1] = -p->a[0];
}
