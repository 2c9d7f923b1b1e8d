/* path.h - method "path": light's own transport inside the object by brute-force Monte Carlo random walks
 * (free flights, Henyey-Greenstein scattering, a dielectric boundary), in double precision on the CPU. */
#ifndef LUCENT_PATH_H
#define LUCENT_PATH_H

#include "lucent.h"
#include "mesh.h"
#include "view_frame.h"

#include <stdatomic.h>

struct path_options {
    uint32_t samples;          /* walks per pixel and channel */
    double time_s;             /* 0: none; else no further pass of one sample per pixel starts after this */
    lucent_path_boundary boundary;
    lucent_path_filter filter;
    uint64_t seed;
    int threads;               /* 0 = one per online CPU */
    const atomic_int *cancel;  /* when it turns non-zero the render stops (LUCENT_E_CANCELLED) */
};

struct path_report {
    uint32_t samples;          /* passes completed (each one walk per pixel and channel) */
    double rel_std_error;      /* the image's own noise: sqrt(sum of per-pixel variances of the mean) over
                                * the root of the sum of squared means, RGB over covered pixels */
    double mean_steps;         /* scattering events and boundary hits per walk */
    double escaped_share;      /* walks that left the mesh's neighbourhood (open meshes), counted as dark */
    double ms;
};

/* Renders `scene` (already validated) of `mesh` through `camera` at scale_mm millimetres per unit, as
 * reference_render fills its image (radiance, coverage, AOVs when with_aovs; with the box filter, coverage is
 * the share of passes that hit and AOVs are those of the first hit). Deterministic for a
 * given scene, options and sample count, whatever the thread count. */
lucent_status path_render(const lucent_scene *scene, const struct lucent_mesh *mesh, const struct view_frame *camera,
                          double scale_mm, const struct path_options *options, int with_aovs, lucent_image *out,
                          struct path_report *report, lucent_error *err);

#endif
