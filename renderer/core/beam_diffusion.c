/* beam_diffusion.c - photon beam diffusion's total reflectance as Pharr, Jakob and Humphreys write it (pbrt,
 * 15.5): exitance of better dipoles at exponentially distributed depths, and the beam's single scattering. */
#include "beam_diffusion.h"
#include "dipole.h"
#include "linalg.h"
#include "phase.h"
#include "profile.h"

#include <math.h>

/* Quadrature: depths and exit distances stratified over e^(-sigma_t z) (pbrt's 100 of each), radii on a
 * log grid from 1e-4 to 1e3 mean free paths. 160 radii and 64 depths agree with 600 and 400 to 1e-4. */
#define DEPTHS 64
#define RADII 160

struct beam {
    double sigma_s, sigma_t, eta, g;          /* single scattering's (sigma_s = sigma_s' / (1 - g)) */
    double sigma_t_prime;
    struct profile dipole[DEPTHS];            /* the better dipole with its source at each depth */
};

/* Exitance at distance r from the beam's entry, from scattering deeper than the first event: the better
 * dipole of each depth (alpha'^2 exitance), times kappa: its source cannot emit above the surface. */
static double multiple(const struct beam *b, double r)
{
    double sum = 0.0;
    for (int i = 0; i < DEPTHS; i++) {
        double zr = b->dipole[i].z[0], kappa = -expm1(-2.0 * b->sigma_t_prime * (sqrt(r * r + zr * zr) + zr));
        sum += kappa * profile_rd(&b->dipole[i], r);
    }
    return sum / DEPTHS;
}

/* Exitance at distance r from light scattered once on the beam, leaving through the boundary: depths
 * below t_crit cannot reach r within the critical angle. The beam travels down and the light leaves
 * upwards, so the scattering angle's cosine is -cos_o. */
static double single(const struct beam *b, double r)
{
    double st = b->sigma_t, rho = b->sigma_s / st, t_crit = r * sqrt(b->eta * b->eta - 1.0);
    double sum = 0.0;
    for (int i = 0; i < DEPTHS; i++) {
        double t = t_crit - log1p(-(i + 0.5) / DEPTHS) / st, dist = sqrt(r * r + t * t), cos_o = t / dist;
        double out = 1.0 - fresnel_internal_reflectance(b->eta, cos_o);
        sum += rho * exp(-st * (dist + t_crit)) / (dist * dist) * henyey_greenstein(b->g, -cos_o) * out * cos_o;
    }
    return sum / DEPTHS;
}

double beam_diffusion_albedo(double sigma_a, double sigma_s_prime, double g, double eta)
{
    double sigma_s = sigma_s_prime / (1.0 - g), c1 = fresnel_moment(eta, 1), c2 = fresnel_moment(eta, 2);
    struct beam b = {.sigma_s = sigma_s, .sigma_t = sigma_s + sigma_a, .eta = eta, .g = g,
                     .sigma_t_prime = sigma_a + sigma_s_prime};
    for (int i = 0; i < DEPTHS; i++)
        dipole_better_at(&b.dipole[i], sigma_a, sigma_s_prime, c1, c2, -log1p(-(i + 0.5) / DEPTHS) / b.sigma_t_prime);
    double mfp = 1.0 / b.sigma_t_prime, lo = 1e-4 * mfp, ratio = pow(1e7, 1.0 / RADII), sum = 0.0;
    /* Inside lo the exitance is flat enough to count as the disc's area times its value at lo. */
    sum += PI * lo * lo * (multiple(&b, lo) + single(&b, lo));
    for (int i = 0; i < RADII; i++) {
        double r0 = lo * pow(ratio, i), r1 = r0 * ratio, r = sqrt(r0 * r1);
        sum += 2.0 * PI * r * (multiple(&b, r) + single(&b, r)) * (r1 - r0);
    }
    return sum;
}
