/* dipole.h - the dipole diffusion profiles (Jensen et al. 2001's classic one, its asymptotic-decay variant,
 * d'Eon 2012's better one) and the Fresnel terms of the boundary they share. Lengths in mm, coefficients in mm^-1, double precision. */
#ifndef LUCENT_DIPOLE_H
#define LUCENT_DIPOLE_H

struct profile;

double dipole_fdr(double eta);                 /* diffuse Fresnel reflectance (Groenhuis fit) */
double dipole_boundary_a(double eta);          /* A = (1 + F_dr) / (1 - F_dr) */
/* Unpolarized Fresnel transmittance 1 - F_r entering a medium of relative index eta >= 1
 * at incidence cosine cos_i (clamped to [0,1]). */
double fresnel_transmittance(double eta, double cos_i);
/* Fresnel reflectance meeting the boundary from inside (relative index 1 / eta), total internal
 * reflection included. */
double fresnel_internal_reflectance(double eta, double cos_i);
/* The k-th Fresnel moment from inside, int_0^1 F_r(mu) mu^k dmu (d'Eon's C_1 and C_2 are k = 1, 2). */
double fresnel_moment(double eta, int k);
/* The share of diffuse light from outside that enters, 2 int_0^1 F_t(mu) mu dmu = 4 C_phi(1 / eta). Every
 * profile gives the light leaving the surface (its exitance); spread over the exit directions as F_t(cos) / pi
 * it would lose 1 minus this share, so the exit divides by it (d'Eon 2012, pbrt-v3's Sw). */
double fresnel_diffuse_transmittance(double eta);
/* The diffuse exit's weight (sr^-1), 1 / (pi fresnel_diffuse_transmittance): radiance = exitance F_t(cos) weight. */
double diffuse_exit_weight(double eta);

/* Jensen et al. 2001: a real source at z_r = 1 / sigma_t' of power alpha', its mirror image
 * 2 z_b above the boundary, exitance from the flux alone. */
void dipole_classic(struct profile *p, double sigma_a, double sigma_s_prime, double eta);
/* The transport equation's asymptotic decay rate in an infinite medium of isotropic scattering, in units of
 * sigma_t: nu in (0, 1] with atanh(nu) / nu = 1 / albedo, given as sigma_a / sigma_s = (1 - albedo) / albedo
 * (exact near albedo 1; INFINITY: no scattering, nu = 1). Diffusion's own rate is sqrt(3 (1 - albedo)). */
double transport_decay_rate(double absorption_over_scattering);
/* The classic dipole decaying at the transport equation's rate (transport_decay_rate(sigma_a / sigma_s')
 * sigma_t' instead of sigma_tr) and scaled to the classic dipole's total reflectance: asymptotic diffusion
 * for the light far from where it entered (through thick absorbing parts), the dipole's calibrated albedo
 * near it. The same as dipole_classic where albedo is near 1. */
void dipole_asymptotic(struct profile *p, double sigma_a, double sigma_s_prime, double eta);
/* d'Eon 2012, "A Better Dipole": Grosjean's diffusion coefficient D = (2 sigma_a + sigma_s') / (3 sigma_t'^2),
 * the boundary's extrapolation distance from the Fresnel moments, and exitance from fluence and flux,
 * R = alpha'^2 / (4 pi) sum (C_E z (1 + sigma_tr d) / d^2 + C_phi / D) e^(-sigma_tr d) / d over the
 * real source (+) and the virtual one (-, at z_v = -z_r - 4 A D). */
void dipole_better(struct profile *p, double sigma_a, double sigma_s_prime, double eta);
/* The same with its real source at `depth` (mm) instead of 1 / sigma_t' (photon beam diffusion integrates
 * it along the beam), c1 and c2 the Fresnel moments (fresnel_moment). */
void dipole_better_at(struct profile *p, double sigma_a, double sigma_s_prime, double c1, double c2, double depth);

#endif
