/* reference.h - the ground truth of the dipole model: the same scene computed on the CPU in double
 * precision, without image-space shortcuts (ray-cast visible points, irradiance points spread over
 * the whole surface, shadow rays), by brute force or a Jensen & Buhler 2002 hierarchical sum. */
#ifndef LUCENT_REFERENCE_H
#define LUCENT_REFERENCE_H

#include "lucent.h"
#include "mesh.h"
#include "view_frame.h"

#include <stdatomic.h>

struct reference_options {
    uint32_t points;      /* irradiance points over the whole surface; 0 = automatic (see .c) */
    int brute_force;      /* 1: sum every point for every pixel; 0: hierarchical */
    double threshold;     /* hierarchical: a node of extent s at distance d is used whole when
                           * s / d < threshold; 0 = default */
    int threads;          /* 0 = one per online CPU */
    const atomic_int *cancel;  /* when it turns non-zero the render stops (LUCENT_E_CANCELLED) */
};

/* What the integrator can say about its own accuracy. */
struct reference_report {
    uint32_t points;            /* irradiance points used */
    double point_spacing_mm;    /* mean distance between neighbouring points, sqrt(area / points) */
    double min_mean_free_path_mm; /* smallest 1 / sigma_t' of the three channels */
    double threshold;           /* hierarchical threshold used (0 for brute force) */
    double estimated_rel_error; /* from point spacing vs mean free path and the threshold */
    double ms_points, ms_pixels;
};

/* Renders `scene` (already validated) of `mesh` seen through `camera` (mesh-centred coordinates,
 * from frame_camera) at scale_mm millimetres per unit. Fills out like lucent_render: rgba radiance
 * and coverage, and when with_aovs depth (camera distance), normal (world) and view (0 where
 * covered, -1 elsewhere). Deterministic for a given scene and options. */
lucent_status reference_render(const lucent_scene *scene, const struct lucent_mesh *mesh,
                               const struct view_frame *camera, double scale_mm,
                               const struct reference_options *options, int with_aovs, lucent_image *out,
                               struct reference_report *report, lucent_error *err);

#endif
