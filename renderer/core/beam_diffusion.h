/* beam_diffusion.h - the total diffuse reflectance of a half-space lit by a collimated beam, by photon beam
 * diffusion (Habel, Christensen and Jarosz 2013): the albedo normalized diffusion is scaled to. */
#ifndef LUCENT_BEAM_DIFFUSION_H
#define LUCENT_BEAM_DIFFUSION_H

/* Multiple scattering (better dipoles integrated along the refracted beam) plus single scattering
 * (Henyey-Greenstein g, sigma_s = sigma_s' / (1 - g)), both integrated over the plane. Coefficients in
 * mm^-1 (the result has no unit), eta >= 1. */
double beam_diffusion_albedo(double sigma_a, double sigma_s_prime, double g, double eta);

#endif
