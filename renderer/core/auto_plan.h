/* auto_plan.h - method "auto": the image-space render a scene needs (views, samples, sampling scheme,
 * projection size, diffuse limit), chosen from the kernel's size against the texel footprint. */
#ifndef LUCENT_AUTO_PLAN_H
#define LUCENT_AUTO_PLAN_H

#include "lucent.h"
#include "mesh.h"

/* Kernels whose 95% radius is under this many texels are summed as the diffuse limit. */
#define AUTO_DIFFUSE_LIMIT_TEXELS 0.5
#define AUTO_MIN_SAMPLES 4
#define AUTO_MAX_SAMPLES 64
/* Five views are drawn when more than this share of the entering light is hidden from the front. */
#define AUTO_HIDDEN_LIGHT_SHARE 0.01
/* Channels whose kernels differ more than this in radius sample their own profiles. */
#define AUTO_PER_CHANNEL_SPREAD 3.0

struct auto_plan {
    lucent_scene scene;      /* method five or single with the chosen knobs */
    int diffuse_limit;       /* 1: no sampling, irradiance x integral of R_d */
    double kernel_texels;    /* largest channel's 95% radius in front-image texels */
    double object_pixels;    /* the bounding sphere's diameter on screen, pixels */
    double hidden_light_share; /* of the entering light, the share on surface facing away from the camera */
    lucent_profile profile;  /* the given one, else the one chosen */
    char decisions[768];     /* JSON members (no braces) saying what was chosen and why */
};

/* Resolves a method "auto" scene for mesh. Fails only when the camera is degenerate. */
lucent_status auto_plan_choose(const lucent_scene *scene, const struct lucent_mesh *mesh, struct auto_plan *out,
                               lucent_error *err);

#endif
