/* frame_plan.h - everything one render needs decided on the CPU before recording commands:
 * views, shadow maps worth drawing, the dipole sample tables, and what was skipped and why. */
#ifndef LUCENT_FRAME_PLAN_H
#define LUCENT_FRAME_PLAN_H

#include "frame_uniforms.h"
#include "lucent.h"
#include "mesh.h"
#include "view_frame.h"

/* Margin around the bounding sphere so silhouettes never touch an image border. */
#define FRAME_FIT_MARGIN 1.02
/* Bounds of the owned images' depth weights' exponent over a view's depth range (+-1 radius): below
 * the low one the logarithm that undoes them loses precision, above the high one float overflows. */
#define FRAME_DEPTH_RATE_MIN 0.01
#define FRAME_DEPTH_RATE_MAX 30.0
/* The scatter pass takes the irradiance as the point's own over a disc around each pixel (the near
 * part, per pixel) and samples the annulus outside it once per block of pixels (the far part, smooth
 * at that scale by construction), the disc's radius one block side. The block's side for an image:
 * 4 above 320^2 pixels, 2 above 128^2, else 1 (and no disc: the whole profile is sampled per pixel).
 * Measured: at 256^2 blocks of 4 draw blotches (side-lit bunny noise 0.027 against 0.020) and at
 * 512^2 they are as close to the reference as 2 at a quarter of the cost. */
int frame_far_block(int width, int height);
/* The owned images (ownership.comp: each view's share of the flux, what the far annulus gathers) have
 * the projection images' side >> this: 128 texels or more for the front view, at most 4x coarser.
 * Measured at projection 512: the side-lit bunny as close to the reference at 128 as at 256, and the
 * ownership pass 4x cheaper; at projection 64 a 16-texel front image doubled the error of small
 * renders (render_extremes). */
int frame_owned_shift(int projection_size);
/* A light view's owned image is as fine as the front's (its side's frame_owned_shift(), not the front's
 * shift, which leaves the camera's side views 4x coarser): the light it carries through thin parts is
 * placed at the samples' footprints, and at the side views' resolution a back-lit bunny's ear spread its
 * light over its outline (0.94 of the reference's light at 256^2 with a 64^2 owned image, 0.96 at 128^2). */
int frame_light_owned_shift(int side_size);
/* The owned images' sides: the front view's, the camera side views' (both >> frame_owned_shift of the
 * front's size) and the light views' (>> frame_light_owned_shift). */
struct owned_sides {
    uint32_t front, sides, lights;
};
struct owned_sides frame_owned_sides(uint32_t projection_size, uint32_t side_size);
/* Blocks along an image side of `pixels` pixels, the last one partial where the side is not a multiple. */
uint32_t frame_far_blocks(uint32_t pixels, uint32_t block);

struct frame_plan {
    struct frame_uniforms uniforms;
    struct view_frame camera;               /* mesh-centred, as frame_camera() gives it */
    float camera_clip[16];
    float camera_eye[4];
    int view_count;                         /* 1 (single), or 5 plus the light views */
    int scatter_samples;                    /* per channel; 0 = diffuse limit (no sampling) */
    int far_block;                          /* pixels a side of one far-annulus sample: 1, 2 or 4 */
    double near_disc_mm;                    /* radius of the near part's disc */
    int side_projection_size;               /* resolved side image size, texels */
    int shadow_count;                       /* shadow maps to draw */
    uint32_t shadow_mask;                   /* bit l: light l reads shadow map */
    int camera_outside;                     /* eye outside the bounding sphere */
    float shadow_clip[LUCENT_MAX_LIGHTS][16];
    double scale_mm;                        /* resolved millimetres per scene unit */
    const char *shadow_reason[LUCENT_MAX_LIGHTS];  /* why light l has or has no shadow map */
    const char *transmission_reason[LUCENT_MAX_LIGHTS];  /* why light l has or has no light view */
    /* What the passes draw, decided here so that a backend records a frame from the plan alone. */
    int light_count;
    int gather_owned;       /* the far annulus is gathered over every view's share (frame_far_views > 1) */
    int cull_back_faces;    /* a closed mesh: the projection and shadow views, outside the bounding
                             * sphere, never see its back faces */
    int cull_camera;        /* ... nor does the camera, when it is outside the sphere too */
    lucent_sampling sampling;
    lucent_fallback fallback;
    int single_scattering;
};

/* A light gets a light view (transmission) when more than FRAME_LIGHT_VIEW_SHARE of its entering light
 * enters on surface within acos(FRAME_BACK_COS) of facing straight away from the camera, where no
 * camera view faces it by more than cos 60 degrees. */
#define FRAME_BACK_COS 0.866
#define FRAME_LIGHT_VIEW_SHARE 0.10
/* 1 when a light brings more than FRAME_LIGHT_VIEW_SHARE of its light in on surface facing away from the
 * camera (within acos(FRAME_BACK_COS) of straight away) and is no point light within the object's bounds:
 * the lights that the five-view integration gives light views. */
int frame_light_enters_behind(const lucent_scene *scene, const struct lucent_mesh *mesh, const double forward[3]);
/* The light each light brings into the surface (area x cosine x irradiance, unshadowed), in one pass
 * over the triangles: entering[l] in all, hidden[l] on surface whose normal's cosine to `forward` (the
 * camera's) exceeds `min_away` (0: any surface facing away from the camera). An open mesh is lit on the
 * side facing the light. */
void frame_light_shares(const lucent_scene *scene, const struct lucent_mesh *mesh, const double forward[3],
                        double min_away, double hidden[LUCENT_MAX_LIGHTS], double entering[LUCENT_MAX_LIGHTS]);

/* The evenly spread samples light views add (FRAME_THROUGH_SAMPLES, half where the far part is
 * integrated per block and then filtered). Measured at 256^2, back light: 8 instead of 16 took the frame
 * from 1.45x to 1.16-1.30x that without light views, the error within 0.01 but the skin1 sphere's
 * (0.30 -> 0.35); per pixel (no filter) 8 raised the back-lit sphere's noise from 0.14 to 0.21. */
int frame_through_samples(int far_block);

/* The views the far annulus is gathered from: all five, over each view's share of the surface (the
 * owned images), with five views and the default fallback; else 1, the view each point chooses. */
int frame_far_views(const lucent_scene *scene, const struct frame_plan *plan);

/* The camera of a scene in mesh-centred coordinates (perspective, near/far around the bounding
 * sphere), shared by the raster passes and the reference integrator. */
lucent_status frame_camera(const lucent_scene *scene, const struct lucent_mesh *mesh, struct view_frame *out,
                           lucent_error *err);
/* Millimetres per scene unit: scene->scale_mm, or what makes the bounding sphere 50 mm across. */
double frame_scale_mm(const lucent_scene *scene, const struct lucent_mesh *mesh);

/* The side images' size for a scene: side_projection_size, or half projection_size (at least
 * LUCENT_MIN_PROJECTION_SIZE) when it is 0. */
int frame_side_projection_size(const lucent_scene *scene);

/* Side of every shadow map, texels. */
#define SHADOW_MAP_SIZE 1024

/* proxy_tolerance: how far (scene units) the projection passes' geometry may stray from the
 * camera's (a simplified proxy mesh), widening the visibility test. diffuse_limit: replace the
 * sampled sum by the point's irradiance times the integral of R_d (method auto decides). sphere: the
 * caller's tables of diffusion in a sphere, refilled when the material changes. */
lucent_status frame_plan_build(const lucent_scene *scene, const struct lucent_mesh *mesh,
                               double proxy_tolerance, int diffuse_limit, struct sphere_tables *sphere,
                               struct frame_plan *plan, lucent_error *err);

#endif
