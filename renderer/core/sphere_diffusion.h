/* sphere_diffusion.h - the classical dipole's source inside a sphere instead of under a plane: diffusion solved
 * with the sphere's extrapolated boundary, and the factor it puts on R between points of a curved surface. */
#ifndef LUCENT_SPHERE_DIFFUSION_H
#define LUCENT_SPHERE_DIFFUSION_H

#include "lucent.h"
#include "profile.h"

#define SPHERE_TABLE_T 24   /* sigma_tr a, log-spaced over SPHERE_T_MIN..SPHERE_T_MAX (frame.glsl's too) */
#define SPHERE_TABLE_G 24   /* angle between the two points' normals, 0..pi */
#define SPHERE_T_MIN 0.02
#define SPHERE_T_MAX 16.0

/* exact / between on a sphere of radius a = t / sigma_tr, for points whose normals are gamma apart. */
struct sphere_table {
    int sources;    /* 0: a profile without sources (normalized diffusion): the factor is 1 */
    double sigma;   /* sigma_tr, mm^-1 */
    float factor[SPHERE_TABLE_T][SPHERE_TABLE_G];
};

/* One material's three tables and the profiles they were made for (a renderer keeps one across frames). */
struct sphere_tables {
    int filled;
    struct profile made_for[3];
    struct sphere_table channel[3];
};

/* Light leaving a sphere of radius a_mm at angle gamma from where it entered, mm^-2: the dipole's real
 * source z_r inside the entry point, Dirichlet at radius a + z_b, the flux through the surface. Equal to
 * the profile's R(r) as a grows (the plane). Sums 20 a / z_r Legendre terms, at most 16384 (radii over
 * about 800 z_r are summed short): slow, for tables and tests. p must be the classical dipole. */
lucent_status sphere_exitance(const struct profile *p, double a_mm, int count, const double *cos_gamma,
                              double *out, lucent_error *err);
/* Fills t for one channel's profile (milliseconds). */
lucent_status sphere_table_init(struct sphere_table *t, const struct profile *p, lucent_error *err);
/* Fills t for the three channels' profiles p unless it holds them already. */
lucent_status sphere_tables_for(struct sphere_tables *t, const struct profile p[3], lucent_error *err);
/* The factor on profile_rd_between(p, d, n_out, n_in) for two points of a surface curving around them:
 * the sphere through both (radius |d|^2 / 2 depth, depth the mean of each point's depth under the other's
 * tangent plane) weighted by curvature_mm times that radius, at most 1 (the exit's mean curvature, 1/mm,
 * 0 on a flat face: a slab's faces keep Donner and Jensen's kernel). 1 where the points do not lie on a
 * convex surface. */
double sphere_factor(const struct sphere_table *t, const double d[3], const double n_out[3], const double n_in[3],
                     double curvature_mm);
/* The curvature sphere_factor takes where the surface curves by `curvature` over a part `thickness` thick (any
 * length unit and its inverse; INFINITY where the ray inward leaves the mesh): curvature x min(thickness x
 * curvature, 1), 0 where flat or concave. A part thinner than its radius of curvature is a slab, not a ball. */
double sphere_factor_curvature(double curvature, double thickness);

#endif
