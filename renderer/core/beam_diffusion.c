/* beam_diffusion.c - photon beam diffusion's total reflectance as Pharr, Jakob and Humphreys write it (pbrt,
 * 15.5): exitance of better dipoles at exponentially distributed depths, and the beam's single scattering. */
#include "beam_diffusion.h"
#include "dipole.h"
#include "linalg.h"

#include <math.h>

/* Quadrature: depths and exit distances stratified over e^(-sigma_t z) (pbrt's 100 of each), radii on a
 * log grid from 1e-4 to 1e3 mean free paths. 160 radii and 64 depths agree with 600 and 400 to 1e-4. */
#define DEPTHS 64
#define RADII 160

struct beam {
    double sigma_a, sigma_s_prime, sigma_s, g, eta;
    double c1, c2;   /* Fresnel moments from inside */
};

/* Exitance at distance r from the beam's entry, from scattering deeper than the first event. */
static double multiple(const struct beam *b, double r)
{
    double st = b->sigma_a + b->sigma_s_prime, rho = b->sigma_s_prime / st;
    double d = (2.0 * b->sigma_a + b->sigma_s_prime) / (3.0 * st * st), s = sqrt(b->sigma_a / d);
    double ze = -2.0 * d * (1.0 + 3.0 * b->c2) / (1.0 - 2.0 * b->c1);
    double c_phi = 0.25 * (1.0 - 2.0 * b->c1), c_e = 0.5 * (1.0 - 3.0 * b->c2), sum = 0.0;
    for (int i = 0; i < DEPTHS; i++) {
        double zr = -log1p(-(i + 0.5) / DEPTHS) / st, zv = -zr + 2.0 * ze;
        double dr = sqrt(r * r + zr * zr), dv = sqrt(r * r + zv * zv);
        double fluence = (exp(-s * dr) / dr - exp(-s * dv) / dv) / (4.0 * PI * d);
        double flux = (zr * (1.0 + s * dr) * exp(-s * dr) / (dr * dr * dr) -
                       zv * (1.0 + s * dv) * exp(-s * dv) / (dv * dv * dv)) / (4.0 * PI);
        /* kappa: the dipole's source cannot emit above the surface it sits under. */
        double kappa = -expm1(-2.0 * st * (dr + zr));
        sum += kappa * rho * rho * (c_phi * fluence + c_e * flux);
    }
    return sum / DEPTHS;
}

static double henyey_greenstein(double g, double mu)
{
    return (1.0 - g * g) / (4.0 * PI * pow(1.0 + g * g + 2.0 * g * mu, 1.5));
}

/* Exitance at distance r from light scattered once on the beam, leaving through the boundary: depths
 * below t_crit cannot reach r within the critical angle. */
static double single(const struct beam *b, double r)
{
    double st = b->sigma_a + b->sigma_s, rho = b->sigma_s / st, t_crit = r * sqrt(b->eta * b->eta - 1.0);
    double sum = 0.0;
    for (int i = 0; i < DEPTHS; i++) {
        double t = t_crit - log1p(-(i + 0.5) / DEPTHS) / st, dist = sqrt(r * r + t * t), cos_o = t / dist;
        double out = 1.0 - fresnel_internal_reflectance(b->eta, cos_o);
        sum += rho * exp(-st * (dist + t_crit)) / (dist * dist) * henyey_greenstein(b->g, cos_o) * out * cos_o;
    }
    return sum / DEPTHS;
}

double beam_diffusion_albedo(double sigma_a, double sigma_s_prime, double g, double eta)
{
    struct beam b = {sigma_a, sigma_s_prime, sigma_s_prime / (1.0 - g), g, eta,
                     fresnel_moment(eta, 1), fresnel_moment(eta, 2)};
    double mfp = 1.0 / (sigma_a + sigma_s_prime), lo = 1e-4 * mfp, ratio = pow(1e7, 1.0 / RADII), sum = 0.0;
    /* Inside lo the exitance is flat enough to count as the disc's area times its value at lo. */
    sum += PI * lo * lo * (multiple(&b, lo) + single(&b, lo));
    for (int i = 0; i < RADII; i++) {
        double r0 = lo * pow(ratio, i), r1 = r0 * ratio, r = sqrt(r0 * r1);
        sum += 2.0 * PI * r * (multiple(&b, r) + single(&b, r)) * (r1 - r0);
    }
    return sum;
}
