/* profile.h - radial diffusion profiles R(r) as two point sources, their closed-form integrals and the
 * radial sampling tables the scatter pass and the reference draw with. Lengths in mm, double precision. */
#ifndef LUCENT_PROFILE_H
#define LUCENT_PROFILE_H

#include "lucent.h"

/* Two sources on the normal through the exit point, at depths z[k] (mm):
 *   R(r) = sum_k e^(-sigma_k D_k) (a_k / D_k + b_k (1 + sigma_k D_k) / D_k^3),  D_k = sqrt(r^2 + z_k^2),
 * in mm^-2. The classic dipole has flux terms only (b), the better dipole fluence terms (a) as well,
 * normalized diffusion two fluence-like terms at z = 0. The integral over the plane outside t is
 *   T(t) = 2 pi sum_k e^(-sigma_k D_k) (a_k / sigma_k + b_k / D_k),
 * a pair of fluence terms a_1 = -a_0 sharing sigma taken as their difference (finite at sigma = 0). */
struct profile {
    lucent_profile kind;
    double z[2], sigma[2], a[2], b[2];
    double sigma_t_prime;   /* sigma_a + sigma_s': the reference's sampling floor is 1 / this */
};

/* The profile of one colour channel; kind as material.profile, g its Henyey-Greenstein mean cosine. */
void profile_init(struct profile *p, lucent_profile kind, double sigma_a, double sigma_s_prime, double g,
                  double eta);
double profile_rd(const struct profile *p, double r);        /* R(r), mm^-2; finite for r > 0 */
/* R from light entering at one point of a curved surface to an exit point: d = exit - entry (mm), n_out and
 * n_in the outward normals there (n_in may be a mean, shorter than 1). Both sources sit on the entry's
 * normal, with their images across the exit's boundary where the exit faces away from the entry, and R is
 * the light they send through the exit's tangent plane: through opposite faces, Donner and Jensen 2005's
 * slab transmittance with its first two pairs. Equal to profile_rd(|d|) where both lie on one plane;
 * normalized diffusion, which has no sources, is always profile_rd(|d|). Never negative. */
double profile_rd_between(const struct profile *p, const double d[3], const double n_out[3], const double n_in[3]);
/* profile_rd_between integrated over a disc of radius `radius` (mm) on the entry's surface, its centre at d
 * (exit - centre; the scatter pass's near disc across an edge or through a thin part). Per source and image,
 * the disc is taken as the annulus around the exit's normal of the disc's area that ends at the disc centre's
 * distance: exact for a disc centred under the exit point; for one two radii or more beside it on the exit's
 * plane or a slab's far face, within 11% of the integral (or 1.2% of the light of the disc under it); about 2x
 * for one just touching the exit's normal (tests/test_profiles.c). A face meeting the exit's at an edge is
 * rougher: 0.6-0.9x two radii or more beyond the edge, anything from 0 to 6x where the disc reaches it. */
double profile_disc_between(const struct profile *p, double radius, const double d[3], const double n_out[3],
                            const double n_in[3]);
/* A thin part (an ear, a slab's face) loses through its back face light that a half space would send back
 * out: the share of R(r) that is left on the lit face of a slab `thickness` mm thick, by Donner and Jensen
 * 2005's multipole reflectance (0..1; the pairs run to 4 or twice r in periods 2 (thickness + 2 z_b), at most
 * PROFILE_SLAB_PAIRS). 1 for a profile without sources (normalized diffusion) or an infinite thickness. */
#define PROFILE_SLAB_PAIRS 64
double profile_slab_share(const struct profile *p, double r, double thickness);
double profile_tail(const struct profile *p, double t);      /* T(t): integral of R outside radius t */
double profile_total(const struct profile *p);               /* T(0): the total diffuse reflectance */
double profile_disc(const struct profile *p, double radius); /* integral of R over the disc, T(0) - T(radius) */
/* Integral of R(sqrt(s^2 + offset^2)) over the disc s < radius: a disc on a plane `offset` mm from the
 * exit point, T(|offset|) - T(sqrt(radius^2 + offset^2)), without cancelling for narrow discs. */
double profile_disc_offset(const struct profile *p, double radius, double offset);
/* The slowest exponential rate of the profile's tail (mm^-1): how fast its light fades with depth. */
double profile_decay_rate(const struct profile *p);

/* Stratified radii r_j = CDF^-1(CDF(r_min) + (j + 1/2) / n (CDF(r_max) - CDF(r_min))) of 2 pi r R(r)
 * over the annulus r_min..r_max (tabulated), and its integral R_ann there (closed form).
 * weight_j = R_ann / R(r_j) turns a sample at r_j into an estimate of the integral. n <= 256.
 * Returns R_ann. */
double profile_sample_radii(const struct profile *p, double r_min, double r_max, int n, double *radii,
                            double *weights);

/* The same for one set of n radii shared by three channels: stratified over the mixture
 * p_mix(r) = (1/3) sum_c R_c(r) / R_trunc,c restricted to the annulus, so weight_j = P / (n p_mix(r_j))
 * (P: the mixture's integral over the annulus) makes sum_j f(r_j) weight_j an estimate of the
 * annulus integral of f for every channel's f = R_c. */
void profile_mixture_radii(const struct profile p[3], double r_min, double r_max, int n, double *radii,
                           double *weights);

#endif
