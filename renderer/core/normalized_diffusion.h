/* normalized_diffusion.h - Christensen and Burley's 2015 normalized diffusion profile, fitted to Monte Carlo
 * simulations of the searchlight configuration. Lengths in mm, double precision. */
#ifndef LUCENT_NORMALIZED_DIFFUSION_H
#define LUCENT_NORMALIZED_DIFFUSION_H

struct profile;

/* The fitted shape factor s(A) = 1.85 - A + 7 |A - 0.8|^3 (searchlight, lengths in mean free paths). */
double burley_scale(double albedo);
/* R(r) = A s (e^(-s r / l) + e^(-s r / (3 l))) / (8 pi l r), integrating to A over the plane: A is the
 * half-space's total reflectance by photon beam diffusion (multiple and single scattering, g and eta's
 * boundary included; beam_diffusion.h), at most 1, and l = 1 / sigma_t' the mean free path. */
void burley_profile(struct profile *p, double sigma_a, double sigma_s_prime, double g, double eta);

#endif
