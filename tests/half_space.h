/* half_space.h - exact albedos of an index-matched, isotropically scattering half-space of single-scattering
 * albedo w, from Chandrasekhar's H-function (transport theory, no diffusion approximation). */
#ifndef LUCENT_TEST_HALF_SPACE_H
#define LUCENT_TEST_HALF_SPACE_H

/* *normal: light entering straight down (plane albedo at mu0 = 1); *diffuse: light entering diffusely
 * (spherical albedo). */
void half_space_albedo(double w, double *normal, double *diffuse);

#endif
