/* ref_lights.h - the scene's lights as the CPU integrators (reference, path) see them, in mesh-centred
 * coordinates, and the light one of them brings to a surface point. */
#ifndef LUCENT_REF_LIGHTS_H
#define LUCENT_REF_LIGHTS_H

#include "bvh.h"
#include "lucent.h"
#include "mesh.h"

struct ref_light {
    int point;           /* 1: vec is a position, 0: the direction the light travels (unit) */
    double vec[3];
    double rgb[3];       /* color * intensity */
};

/* The scene's lights, moved into the mesh's centred coordinates; a zero direction is refused. */
lucent_status ref_lights_from_scene(const lucent_scene *scene, const struct lucent_mesh *mesh,
                                    struct ref_light out[LUCENT_MAX_LIGHTS], lucent_error *err);
/* The unit direction from x towards the light; returns the distance to it (INFINITY: directional). */
double ref_light_toward(const struct ref_light *light, const double x[3], double dir[3]);
/* What the light brings to surface point p of normal n, per unit of its rgb: falloff x cos, 0 where the
 * surface faces away or (shadows) a ray from origin towards the light is blocked; *cos_out: the cosine. */
double ref_light_arrival(const struct ref_light *light, const struct bvh *bvh, int shadows, const double p[3],
                         const double n[3], const double origin[3], double *cos_out);

#endif
