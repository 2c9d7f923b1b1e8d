/* dipole.h - Jensen et al. 2001 dipole diffusion profile, Fresnel terms and the radial sampling table.
 * All lengths in millimetres, coefficients in mm^-1, double precision. */
#ifndef LUCENT_DIPOLE_H
#define LUCENT_DIPOLE_H

/* Derived quantities for one colour channel. */
struct dipole {
    double sigma_a, sigma_s_prime, eta;
    double sigma_t_prime;   /* sigma_a + sigma_s' */
    double alpha_prime;     /* reduced albedo sigma_s' / sigma_t' */
    double sigma_tr;        /* effective transport coefficient; 0 when sigma_a = 0 */
    double z_r, z_v;        /* real source depth, virtual source height */
};

double dipole_fdr(double eta);                 /* diffuse Fresnel reflectance (Groenhuis fit) */
double dipole_boundary_a(double eta);          /* A = (1 + F_dr) / (1 - F_dr) */
void dipole_init(struct dipole *d, double sigma_a, double sigma_s_prime, double eta);
double dipole_rd(const struct dipole *d, double r);   /* R_d(r), mm^-2 */
double dipole_rd_total(const struct dipole *d);       /* closed-form plane integral of R_d */
/* Integral of R_d over a disc of the given radius (mm) around the exit point: the closed form
 * (alpha'/2) sum over z in {z_r, z_v} of (e^(-sigma_tr z) - z e^(-sigma_tr D) / D), D = sqrt(radius^2 + z^2),
 * which tends to dipole_rd_total as the radius grows. */
double dipole_rd_disc(const struct dipole *d, double radius);
/* Unpolarized Fresnel transmittance 1 - F_r entering a medium of relative index eta >= 1
 * at incidence cosine cos_i (clamped to [0,1]). */
double fresnel_transmittance(double eta, double cos_i);

/* Stratified radii r_j = CDF^-1(CDF(r_min) + (j + 1/2) / n (CDF(r_max) - CDF(r_min))) of the profile
 * 2 pi r R_d(r) over the annulus r_min..r_max (tabulated), and its integral R_ann there (closed form).
 * weight_j = R_ann / R_d(r_j) turns a sample at r_j into an estimate of the integral. n <= 256.
 * Returns R_ann. */
double dipole_sample_radii(const struct dipole *d, double r_min, double r_max, int n, double *radii,
                           double *weights);

/* The same for one set of n radii shared by three channels: stratified over the mixture
 * p_mix(r) = (1/3) sum_c R_d,c(r) / R_trunc,c restricted to the annulus, so weight_j = P / (n p_mix(r_j))
 * (P: the mixture's integral over the annulus) makes sum_j f(r_j) weight_j an estimate of the
 * annulus integral of f for every channel's f = R_d,c. */
void dipole_mixture_radii(const struct dipole d[3], double r_min, double r_max, int n, double *radii,
                          double *weights);

#endif
