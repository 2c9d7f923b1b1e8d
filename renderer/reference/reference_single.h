/* reference_single.h - the low-order terms of the reference integrator: Jensen et al. 2001's single scattering
 * (the refracted view ray marched into the mesh, each point lit along a ray cast to the light's entry point)
 * and the light that crosses it unscattered. */
#ifndef LUCENT_REFERENCE_SINGLE_H
#define LUCENT_REFERENCE_SINGLE_H

#include "bvh.h"
#include "mesh.h"
#include "ref_lights.h"

struct single_scatter {
    const struct lucent_mesh *mesh;
    const struct bvh *bvh;
    const struct ref_light *lights;
    int light_count, shadows;
    double scale_mm, eta, g;
    double sigma_s[3], sigma_t[3];   /* mm^-1: sigma_s = sigma_s' / (1 - g) */
};

/* Fills sigma_s, sigma_t and g from a material. */
void single_scatter_material(struct single_scatter *ss, const lucent_material *m);

/* Radiance leaving surface point p (shading normal n, geometric normal g, both outward) towards the
 * eye (unit to_eye) after one scattering event inside or none (light that entered where the refracted view
 * ray meets the surface and crossed unscattered, leaving there as method path's walks leave), exit Fresnel
 * included. Deterministic. */
void single_scatter_radiance(const struct single_scatter *ss, const double p[3], const double n[3],
                             const double g[3], const double to_eye[3], double out[3]);

#endif
