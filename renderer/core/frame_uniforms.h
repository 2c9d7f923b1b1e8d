/* frame_uniforms.h - C mirror of the std140 block in shaders/frame.glsl (ctest frame_layout holds the two
 * together). Filled once per frame by frame_plan.c, read by the projection and scatter shaders. */
#ifndef LUCENT_FRAME_UNIFORMS_H
#define LUCENT_FRAME_UNIFORMS_H

#include "lucent.h"
#include "sphere_diffusion.h"

/* The camera's five views (front, then four sides), then up to FRAME_LIGHT_VIEWS views along lights
 * whose light enters where no camera view faces the surface (transmission, frame_plan.c). */
#define FRAME_CAMERA_VIEWS 5
#define FRAME_LIGHT_VIEWS 2
#define FRAME_MAX_VIEWS (FRAME_CAMERA_VIEWS + FRAME_LIGHT_VIEWS)
/* THROUGH_SAMPLES in frame.glsl: the evenly spread samples of the light views (transmission), half
 * of them where the far part is integrated per block and filtered (frame_through_samples()). */
#define FRAME_THROUGH_SAMPLES 16
/* MIN_AREA_COS in frame.glsl: the smallest cosine to a view a texel's area is divided by. */
#define FRAME_MIN_AREA_COS 0.1
/* NEAR_TABLE in frame.glsl: entries of the near part's R_d integral over the view's tilt. */
#define FRAME_NEAR_TABLE 17

struct frame_uniforms {
    float view_clip[FRAME_MAX_VIEWS][16];
    float view_origin[FRAME_MAX_VIEWS][4];   /* w: the view's owned image is its side >> w */
    float view_du[FRAME_MAX_VIEWS][4];
    float view_dv[FRAME_MAX_VIEWS][4];
    float view_dir[FRAME_MAX_VIEWS][4];
    float light_vec[LUCENT_MAX_LIGHTS][4];
    float light_rgb[LUCENT_MAX_LIGHTS][4];
    float light_clip[LUCENT_MAX_LIGHTS][16];
    float light_depth[LUCENT_MAX_LIGHTS][4];
    float params[4];
    float camera_eye[4]; /* w: the diffuse exit's weight, diffuse_exit_weight(eta) */
    /* The diffusion profile's two sources k per channel (struct profile): depth (mm), rate (mm^-1),
     * fluence and flux coefficients. */
    float profile_z[2][4];
    float profile_sigma[2][4];
    float profile_a[2][4];
    float profile_b[2][4];
    float rd_total[4];
    float near_rd[FRAME_NEAR_TABLE][4];
    float single_albedo[4];
    float single_sigma_t[4];
    float owned[4];   /* x: the owned images' layers are the front projection image's side >> x (frame_owned_shift);
                       * y: views drawn (frame_plan.view_count); z: the rate (per scene unit) and
                       * w: the centre depth of the owned images' depth weights e^(z (depth - w)) */
    float samples[3 * LUCENT_MAX_SAMPLES][4];
    float through_pdf[4];
    float through[FRAME_THROUGH_SAMPLES][4];
    /* Diffusion in a sphere over R between points (sphere_diffusion.h): channel c's factor at t index i and
     * normals' angle index j is element (c * SPHERE_TABLE_T + i) * SPHERE_TABLE_G + j, four to a row. */
    float sphere_factor[3 * SPHERE_TABLE_T * SPHERE_TABLE_G / 4][4];
};

#endif
