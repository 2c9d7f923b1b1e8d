/* frame_plan.c - turns a validated scene and a mesh into the uniforms and matrices of one frame.
 * Coordinates here are mesh-centred scene units; the request's are shifted by the mesh centre. */
#include "frame_plan.h"

#include "dipole.h"
#include "profile.h"
#include "linalg.h"
#include "view_frame.h"

#include <math.h>
#include <string.h>

#define DEG (PI / 180.0)
#define GOLDEN_ANGLE 2.39996322972865332

static void centred(const double p[3], const struct lucent_mesh *mesh, double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = p[i] - mesh->center[i];
}

lucent_status frame_camera(const lucent_scene *s, const struct lucent_mesh *mesh, struct view_frame *out,
                           lucent_error *err)
{
    double aspect = (double)s->width / s->height;
    double half_v = s->camera.fov_deg * 0.5 * DEG;
    double tan_v = tan(half_v), tan_h = tan_v * aspect;
    double eye[3], forward[3], up[3] = {0, 1, 0};
    double radius = mesh->radius * FRAME_FIT_MARGIN;
    if (s->camera.given) {
        double target[3];
        centred(s->camera.position, mesh, eye);
        centred(s->camera.target, mesh, target);
        for (int i = 0; i < 3; i++) {
            forward[i] = target[i] - eye[i];
            up[i] = s->camera.up[i];
        }
    } else {
        double half_min = atan(fmin(tan_v, tan_h));
        double dist = radius / sin(half_min);
        for (int i = 0; i < 3; i++) {
            forward[i] = s->camera.direction[i];
            eye[i] = -dist * forward[i];
            up[i] = s->camera.up[i];
        }
    }
    struct view_frame cam = {.perspective = 1, .half_w = tan_h, .half_h = tan_v};
    if (view_frame_look(&cam, eye, forward, up) != 0)
        return lucent_fail(err, LUCENT_E_INVALID, "camera.up",
                           "must not be parallel to the viewing direction");
    double depth_forward = v3_dot(cam.forward, eye) * -1.0;  /* centre's depth along forward */
    cam.far = fmax(depth_forward + radius, radius * 1e-3);
    /* Inside the bounding sphere the near plane cannot clear the object: keep it tiny but
     * proportional, so depth precision follows the object's size. */
    cam.near = fmax(depth_forward - radius, radius * 1e-4);
    if (cam.near >= cam.far)
        cam.near = cam.far * 1e-4;
    *out = cam;
    return LUCENT_OK;
}

double frame_scale_mm(const lucent_scene *scene, const struct lucent_mesh *mesh)
{
    return scene->scale_mm > 0.0 ? scene->scale_mm : 50.0 / (2.0 * mesh->radius);
}

static lucent_status plan_camera(const lucent_scene *s, const struct lucent_mesh *mesh, struct view_frame *out,
                                 struct frame_plan *plan, lucent_error *err)
{
    lucent_status st = frame_camera(s, mesh, out, err);
    if (st != LUCENT_OK)
        return st;
    plan->camera = *out;
    double clip[16];
    view_frame_clip(out, clip);
    m4_to_float(clip, plan->camera_clip);
    v3_copy_f4(out->eye, 0.0, plan->camera_eye);
    plan->camera_outside = v3_length(out->eye) > mesh->radius * FRAME_FIT_MARGIN;
    v3_copy_f4(out->eye, 0.0, plan->uniforms.camera_eye);
    return LUCENT_OK;
}

/* Projection image k: orthographic along dir, fitted to the bounding sphere. Texel (0,0) is at
 * view_origin, stepping view_du/dv; its owned image is its side >> owned_shift. */
static void plan_view(int k, const double dir[3], const double up[3], int size, int owned_shift, double radius,
                      struct frame_uniforms *u)
{
    double clip[16];
    double texel = 2.0 * radius / size;
    struct view_frame v = {.perspective = 0, .half_w = radius, .half_h = radius,
                           .near = radius * 0.5, .far = radius * 3.5};
    double veye[3];
    v3_scale_add((double[3]){0, 0, 0}, dir, -2.0 * radius, veye);
    view_frame_look(&v, veye, dir, up);
    view_frame_clip(&v, clip);
    m4_to_float(clip, u->view_clip[k]);
    double origin[3];
    v3_scale_add(veye, v.right, -radius, origin);
    v3_scale_add(origin, v.down, -radius, origin);
    double du[3], dv[3], zero[3] = {0, 0, 0};
    v3_scale_add(zero, v.right, texel, du);
    v3_scale_add(zero, v.down, texel, dv);
    v3_copy_f4(origin, owned_shift, u->view_origin[k]);
    v3_copy_f4(du, size, u->view_du[k]);
    v3_copy_f4(dv, texel, u->view_dv[k]);
    v3_copy_f4(v.forward, 0.0, u->view_dir[k]);
}

/* The camera's projection images: front plus the four sides, in the camera's own frame. */
static void plan_views(const lucent_scene *s, const struct view_frame *cam, double radius, struct frame_plan *plan)
{
    double up_cam[3] = {-cam->down[0], -cam->down[1], -cam->down[2]};
    double right_dir[3] = {-cam->right[0], -cam->right[1], -cam->right[2]};
    /* The left image looks rightwards at the object's left side, and so on. */
    const double *dirs[FRAME_CAMERA_VIEWS] = {cam->forward, cam->right, right_dir, cam->down, up_cam};
    const double *ups[FRAME_CAMERA_VIEWS] = {up_cam, up_cam, up_cam, cam->forward, cam->forward};
    plan->side_projection_size = frame_side_projection_size(s);
    for (int k = 0; k < FRAME_CAMERA_VIEWS; k++)
        plan_view(k, dirs[k], ups[k], k == 0 ? s->projection_size : plan->side_projection_size,
                  frame_owned_shift(s->projection_size), radius, &plan->uniforms);
}

void frame_light_shares(const lucent_scene *s, const struct lucent_mesh *m, const double forward[3], double min_away,
                        double hidden[LUCENT_MAX_LIGHTS], double entering[LUCENT_MAX_LIGHTS])
{
    for (int l = 0; l < s->light_count; l++)
        hidden[l] = entering[l] = 0.0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *i = &m->indices[(size_t)t * 3];
        double v[3][3], e1[3], e2[3], n[3], centroid[3];
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++)
                v[k][a] = m->positions[(size_t)i[k] * 3 + a];
        for (int a = 0; a < 3; a++) {
            e1[a] = v[1][a] - v[0][a];
            e2[a] = v[2][a] - v[0][a];
            centroid[a] = (v[0][a] + v[1][a] + v[2][a]) / 3.0;
        }
        v3_cross(e1, e2, n);   /* length: twice the area */
        double twice_area = v3_length(n);
        if (twice_area == 0.0)
            continue;
        for (int l = 0; l < s->light_count; l++) {
            const lucent_light *li = &s->lights[l];
            double to_light[3], falloff = 1.0;
            for (int a = 0; a < 3; a++)
                to_light[a] = li->type == LUCENT_LIGHT_POINT ? li->position[a] - centroid[a] : -li->direction[a];
            if (li->type == LUCENT_LIGHT_POINT) {
                double d2 = v3_dot(to_light, to_light);
                falloff = d2 > 0.0 ? 1.0 / (d2 * sqrt(d2)) : 0.0;   /* 1/d^2, and to_light unnormalized */
            }
            double flux = v3_dot(n, to_light) * falloff, away = v3_dot(n, forward) / twice_area;
            if (flux < 0.0 && !m->closed) {
                flux = -flux;
                away = -away;
            }
            flux *= li->intensity * (li->color[0] + li->color[1] + li->color[2]);
            if (flux <= 0.0)
                continue;
            entering[l] += flux;
            hidden[l] += away > min_away ? flux : 0.0;
        }
    }
}

static int point_light_inside(const lucent_light *light, const double centred_position[3], double radius)
{
    return light->type == LUCENT_LIGHT_POINT && v3_length(centred_position) <= radius;
}

int frame_light_enters_behind(const lucent_scene *s, const struct lucent_mesh *mesh, const double forward[3])
{
    double hidden[LUCENT_MAX_LIGHTS], entering[LUCENT_MAX_LIGHTS], pos[3];
    frame_light_shares(s, mesh, forward, FRAME_BACK_COS, hidden, entering);
    for (int l = 0; l < s->light_count; l++) {
        centred(s->lights[l].position, mesh, pos);
        if (!point_light_inside(&s->lights[l], pos, mesh->radius * FRAME_FIT_MARGIN) &&
            hidden[l] > FRAME_LIGHT_VIEW_SHARE * entering[l])
            return 1;
    }
    return 0;
}

/* Views along the lights whose light enters where no camera view faces the surface well (transmission):
 * light entering the back is seen by no camera view, so without them it never reaches the front. They
 * join the gathered integration as views like the others: the ownership pass shares every point among
 * all views that see it, so light a camera view also sees is counted once. The lights with the most
 * such light get the FRAME_LIGHT_VIEWS views. */
static void plan_light_views(const lucent_scene *s, const struct lucent_mesh *mesh, const struct view_frame *cam,
                             double radius, struct frame_plan *plan)
{
    double hidden[LUCENT_MAX_LIGHTS] = {0}, entering[LUCENT_MAX_LIGHTS] = {0}, pos[LUCENT_MAX_LIGHTS][3];
    int gathered = plan->view_count == FRAME_CAMERA_VIEWS && s->fallback != LUCENT_FALLBACK_FRONT &&
                   plan->scatter_samples;
    if (gathered)
        frame_light_shares(s, mesh, cam->forward, FRAME_BACK_COS, hidden, entering);
    for (int l = 0; l < s->light_count; l++) {
        centred(s->lights[l].position, mesh, pos[l]);
        const char *reason = "the camera's views see where its light enters";
        if (!gathered)
            reason = "none: only the gathered five-view integration takes light views";
        else if (point_light_inside(&s->lights[l], pos[l], radius))
            reason = "none: a point light within the object's bounds";
        else if (hidden[l] > FRAME_LIGHT_VIEW_SHARE * entering[l])
            continue;   /* a candidate: keeps hidden[l]; chosen or not, its reason is set below */
        plan->transmission_reason[l] = reason;
        hidden[l] = 0.0;
    }
    double up_cam[3] = {-cam->down[0], -cam->down[1], -cam->down[2]};
    for (int v = 0; v < FRAME_LIGHT_VIEWS; v++) {
        int best = -1;
        for (int l = 0; l < s->light_count; l++)
            if (hidden[l] > 0.0 && (best < 0 || hidden[l] > hidden[best]))
                best = l;
        if (best < 0)
            break;
        hidden[best] = 0.0;
        const lucent_light *li = &s->lights[best];
        double dir[3];
        for (int a = 0; a < 3; a++)
            dir[a] = li->type == LUCENT_LIGHT_POINT ? -pos[best][a] : li->direction[a];
        v3_normalize(dir);
        const double *up = fabs(v3_dot(dir, up_cam)) < 0.9 ? up_cam : cam->forward;
        plan_view(plan->view_count, dir, up, plan->side_projection_size,
                  frame_light_owned_shift(plan->side_projection_size), radius, &plan->uniforms);
        plan->view_count++;
        plan->transmission_reason[best] = "light view";
    }
    for (int l = 0; l < s->light_count; l++)
        if (hidden[l] > 0.0)
            plan->transmission_reason[l] = "none: the light views went to lights with more light entering unseen";
}

/* A light needs a shadow map only when the mesh can occlude it from itself. */
static const char *shadow_skip_reason(const lucent_light *l, const struct lucent_mesh *mesh,
                                      const double pos[3])
{
    if (l->intensity == 0.0 || (l->color[0] == 0.0 && l->color[1] == 0.0 && l->color[2] == 0.0))
        return "skipped: light is black";
    if (mesh->convex)
        return "skipped: mesh is convex, n.l already hides every occluded point";
    if (l->type == LUCENT_LIGHT_POINT && v3_length(pos) <= mesh->radius * FRAME_FIT_MARGIN)
        return "skipped: point light inside the bounding sphere (unshadowed)";
    return NULL;
}

/* extra_bias: how far the shadow caster (a proxy) may lie from the shaded surface. */
static void plan_shadow(const lucent_light *l, const double pos[3], double radius, double extra_bias,
                        float clip_out[16], float depth_out[4])
{
    struct view_frame v = {0};
    double up[3], eye[3];
    if (l->type == LUCENT_LIGHT_POINT) {
        double dist = v3_length(pos);
        double fwd[3] = {-pos[0], -pos[1], -pos[2]};
        view_frame_any_up(fwd, up);
        view_frame_look(&v, pos, fwd, up);
        v.perspective = 1;
        v.half_w = v.half_h = tan(asin(fmin(radius / dist, 1.0)));
        v.near = fmax(dist - radius, dist * 1e-3);
        v.far = dist + radius;
        depth_out[2] = 1.0f;
        depth_out[3] = (float)(4.0 * v.half_w * dist / SHADOW_MAP_SIZE + extra_bias);
    } else {
        view_frame_any_up(l->direction, up);
        v3_scale_add((double[3]){0, 0, 0}, l->direction, -2.0 * radius, eye);
        view_frame_look(&v, eye, l->direction, up);
        v.half_w = v.half_h = radius;
        v.near = radius * 0.5;
        v.far = radius * 3.5;
        depth_out[2] = 0.0f;
        depth_out[3] = (float)(4.0 * radius / SHADOW_MAP_SIZE + extra_bias);
    }
    depth_out[0] = (float)v.near;
    depth_out[1] = (float)v.far;
    double clip[16];
    view_frame_clip(&v, clip);
    m4_to_float(clip, clip_out);
}

static void plan_lights(const lucent_scene *s, const struct lucent_mesh *mesh, double proxy_tolerance,
                        struct frame_plan *plan)
{
    struct frame_uniforms *u = &plan->uniforms;
    double radius = mesh->radius * FRAME_FIT_MARGIN;
    plan->shadow_count = 0;
    for (int l = 0; l < s->light_count; l++) {
        const lucent_light *light = &s->lights[l];
        double pos[3];
        centred(light->position, mesh, pos);
        if (light->type == LUCENT_LIGHT_POINT)
            v3_copy_f4(pos, 1.0, u->light_vec[l]);
        else
            v3_copy_f4(light->direction, 0.0, u->light_vec[l]);
        for (int c = 0; c < 3; c++)
            u->light_rgb[l][c] = (float)(light->color[c] * light->intensity);
        const char *skip = shadow_skip_reason(light, mesh, pos);
        plan->shadow_reason[l] = skip ? skip : "shadow map";
        u->light_rgb[l][3] = skip ? -1.0f : (float)plan->shadow_count;
        if (skip)
            continue;
        plan->shadow_mask |= 1u << l;
        plan_shadow(light, pos, radius, proxy_tolerance, u->light_clip[l], u->light_depth[l]);
        memcpy(plan->shadow_clip[plan->shadow_count], u->light_clip[l], sizeof u->light_clip[l]);
        plan->shadow_count++;
    }
}

static void set_sample(float sample[4], double radius, double weight, double phi)
{
    sample[0] = (float)radius;
    sample[1] = (float)weight;
    sample[2] = (float)cos(phi);
    sample[3] = (float)sin(phi);
}

/* Each channel samples its own profile: weight R_trunc / (n R_d(r)). The spiral is turned by a
 * third per channel so the channels' samples do not land on the same texels. */
static void per_channel_samples(const struct profile d[3], double r_min, double r_max, int n,
                                struct frame_uniforms *u)
{
    double radii[LUCENT_MAX_SAMPLES], weights[LUCENT_MAX_SAMPLES];
    for (int c = 0; c < 3; c++) {
        profile_sample_radii(&d[c], r_min, r_max, n, radii, weights);
        for (int j = 0; j < n; j++)
            set_sample(u->samples[c * LUCENT_MAX_SAMPLES + j], radii[j], weights[j] / n,
                       j * GOLDEN_ANGLE + c * 2.0 * PI / 3.0);
    }
}

/* One set of n radii, stratified over the mixture of the three channels' profiles; every texel
 * feeds all channels, each weighted by 1 / (n p_mix(r)). */
static void shared_samples(const struct profile d[3], double r_min, double r_max, int n, struct frame_uniforms *u)
{
    double radii[LUCENT_MAX_SAMPLES], weights[LUCENT_MAX_SAMPLES];
    profile_mixture_radii(d, r_min, r_max, n, radii, weights);
    for (int j = 0; j < n; j++)
        set_sample(u->samples[j], radii[j], weights[j], j * GOLDEN_ANGLE);
}

/* The light views' evenly spread samples over the annulus r_min..r_max (equal areas, golden-angle
 * turns), and the far samples' densities to weigh both sets against each other (balance heuristic). */
static void through_samples(const struct profile d[3], double r_min, double r_max, int n, struct frame_uniforms *u)
{
    double area = PI * (r_max * r_max - r_min * r_min) / n, span_mix = 0.0;
    for (int j = 0; j < n; j++) {
        double r = sqrt(r_min * r_min + (r_max * r_max - r_min * r_min) * (j + 0.5) / n);
        set_sample(u->through[j], r, area, j * GOLDEN_ANGLE + 1.0);
    }
    for (int c = 0; c < 3; c++) {
        double total = profile_disc(&d[c], r_max), span = total - profile_disc(&d[c], r_min);
        u->through_pdf[c] = (float)span;
        span_mix += span / (3.0 * total);
    }
    u->through_pdf[3] = (float)span_mix;
}

/* R_d over the preimage of the projection-plane disc of radius r on a surface tilted to the view by
 * cosine c: an ellipse with semi-axes r and r / c, whose boundary lies r sqrt(cos^2 phi + sin^2 phi / c^2)
 * from its centre; the mean of the disc integral to that distance over phi. */
static double rd_ellipse(const struct profile *d, double r, double c)
{
    enum { STEPS = 32 };
    double sum = 0.0;
    for (int i = 0; i < STEPS; i++) {
        double phi = (i + 0.5) * (0.5 * PI / STEPS), sp = sin(phi), cp = cos(phi);
        sum += profile_disc(d, r * sqrt(cp * cp + sp * sp / (c * c)));
    }
    return sum / STEPS;
}

/* The side of one camera pixel on a surface at the mesh centre's distance, facing the camera, mm. */
static double camera_pixel_mm(const lucent_scene *s, const struct frame_plan *plan)
{
    return 2.0 * v3_length(plan->camera.eye) * plan->camera.half_h / s->height * plan->scale_mm;
}

/* The sphere tables' factors in the block's rows of four (frame_uniforms.h). */
static void copy_sphere_factors(const struct sphere_tables *t, struct frame_uniforms *u)
{
    float *out = &u->sphere_factor[0][0];
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < SPHERE_TABLE_T; i++)
            for (int j = 0; j < SPHERE_TABLE_G; j++)
                out[(c * SPHERE_TABLE_T + i) * SPHERE_TABLE_G + j] = t->channel[c].factor[i][j];
}

static lucent_status plan_material(const lucent_scene *s, const struct lucent_mesh *mesh,
                                   struct sphere_tables *sphere, struct frame_plan *plan, lucent_error *err)
{
    struct frame_uniforms *u = &plan->uniforms;
    /* Light cannot travel further than across the object; truncating the profile there keeps
     * sigma_a = 0 (an infinite diffusion length) finite. */
    double r_max = 2.0 * mesh->radius * plan->scale_mm;
    /* Blocks of one pixel sample the whole profile: a disc a pixel wide is then millimetres wide, and
     * taking it as flat and evenly lit biased the mean by 2-4% (sphere, cube at 64-96 pixels). */
    double r_near = !plan->scatter_samples ? r_max
                    : plan->far_block > 1  ? fmin(plan->far_block * camera_pixel_mm(s, plan), r_max)
                                           : 0.0;
    plan->near_disc_mm = r_near;
    struct profile d[3];
    double g = s->material.g;
    for (int c = 0; c < 3; c++) {
        profile_init(&d[c], s->material.profile, s->material.sigma_a[c], s->material.sigma_s_prime[c], g,
                     s->material.eta);
        for (int k = 0; k < 2; k++) {
            u->profile_z[k][c] = (float)d[c].z[k];
            u->profile_sigma[k][c] = (float)d[c].sigma[k];
            u->profile_a[k][c] = (float)d[c].a[k];
            u->profile_b[k][c] = (float)d[c].b[k];
        }
        u->rd_total[c] = (float)profile_disc(&d[c], r_max);
        for (int i = 0; i < FRAME_NEAR_TABLE; i++) {
            double inv_cos = 1.0 + (double)i / (FRAME_NEAR_TABLE - 1) * (1.0 / FRAME_MIN_AREA_COS - 1.0);
            u->near_rd[i][c] = (float)rd_ellipse(&d[c], r_near, 1.0 / inv_cos);
        }
        double sigma_s = s->material.sigma_s_prime[c] / (1.0 - g);
        u->single_albedo[c] = (float)(sigma_s / (sigma_s + s->material.sigma_a[c]));
        u->single_sigma_t[c] = (float)(sigma_s + s->material.sigma_a[c]);
    }
    lucent_status st = sphere_tables_for(sphere, d, err);
    if (st != LUCENT_OK)
        return st;
    copy_sphere_factors(sphere, u);
    u->rd_total[3] = (float)r_near;
    u->single_albedo[3] = (float)g;
    u->camera_eye[3] = (float)diffuse_exit_weight(s->material.eta);
    u->owned[0] = (float)frame_owned_shift(s->projection_size);
    /* The owned images weigh their depths by e^(rate (depth - centre)) (ownership.comp): R_d falls
     * about as e^(-sigma_tr d) (profile_decay_rate), so the light of a footprint across a depth range
     * lies nearer than its linear mean depth (which left the back-lit sphere 0.76-0.85 of the reference's
     * mean at 256^2). d grows with the depth difference at the rate of its cosine (the light crossing at an angle):
     * half the slowest channel's sigma_tr measured best (sphere 0.88-0.90; the full rate: 0.96-1.07,
     * but rim-lit torus and ketchup sphere 1.16-1.17). Capped so that e^(+-rate radius) fits a float. */
    double view_radius = mesh->radius * FRAME_FIT_MARGIN;
    double slowest = fmin(profile_decay_rate(&d[0]), fmin(profile_decay_rate(&d[1]), profile_decay_rate(&d[2])));
    double sigma_min = 0.5 * slowest * plan->scale_mm;
    u->owned[2] = (float)fmin(fmax(sigma_min, FRAME_DEPTH_RATE_MIN / view_radius), FRAME_DEPTH_RATE_MAX / view_radius);
    u->owned[3] = (float)(2.0 * view_radius);
    if (plan->scatter_samples == 0)
        return LUCENT_OK;
    if (s->sampling == LUCENT_SAMPLING_SHARED)
        shared_samples(d, r_near, r_max, plan->scatter_samples, u);
    else
        per_channel_samples(d, r_near, r_max, plan->scatter_samples, u);
    through_samples(d, r_near, r_max, frame_through_samples(plan->far_block), u);
    return LUCENT_OK;
}

int frame_far_block(int width, int height)
{
    long pixels = (long)width * height;
    return pixels > 320 * 320 ? 4 : pixels > 128 * 128 ? 2 : 1;
}

int frame_through_samples(int far_block)
{
    return far_block > 1 ? FRAME_THROUGH_SAMPLES / 2 : FRAME_THROUGH_SAMPLES;
}

int frame_far_views(const lucent_scene *scene, const struct frame_plan *plan)
{
    return plan->view_count > 1 && scene->fallback != LUCENT_FALLBACK_FRONT ? plan->view_count : 1;
}

int frame_owned_shift(int projection_size)
{
    int shift = 0;
    while (shift < 2 && (projection_size >> shift) > 128)
        shift++;
    return shift;
}

int frame_light_owned_shift(int side_size)
{
    return frame_owned_shift(side_size);
}

struct owned_sides frame_owned_sides(uint32_t projection_size, uint32_t side_size)
{
    int shift = frame_owned_shift((int)projection_size);
    return (struct owned_sides){projection_size >> shift, side_size >> shift,
                                side_size >> frame_light_owned_shift((int)side_size)};
}

uint32_t frame_far_blocks(uint32_t pixels, uint32_t block)
{
    return (pixels + block - 1) / block;
}

int frame_side_projection_size(const lucent_scene *scene)
{
    int side = scene->side_projection_size ? scene->side_projection_size : scene->projection_size / 2;
    return side < LUCENT_MIN_PROJECTION_SIZE ? LUCENT_MIN_PROJECTION_SIZE : side;
}

lucent_status frame_plan_build(const lucent_scene *scene, const struct lucent_mesh *mesh,
                               double proxy_tolerance, int diffuse_limit, struct sphere_tables *sphere,
                               struct frame_plan *plan, lucent_error *err)
{
    memset(plan, 0, sizeof *plan);
    plan->scatter_samples = diffuse_limit ? 0 : scene->samples;
    plan->far_block = frame_far_block(scene->width, scene->height);
    plan->scale_mm = frame_scale_mm(scene, mesh);
    plan->view_count = scene->method == LUCENT_METHOD_SINGLE ? 1 : FRAME_CAMERA_VIEWS;
    struct view_frame cam;
    lucent_status st = plan_camera(scene, mesh, &cam, plan, err);
    if (st != LUCENT_OK)
        return st;
    plan_views(scene, &cam, mesh->radius * FRAME_FIT_MARGIN, plan);
    plan_light_views(scene, mesh, &cam, mesh->radius * FRAME_FIT_MARGIN, plan);
    plan_lights(scene, mesh, proxy_tolerance, plan);
    if ((st = plan_material(scene, mesh, sphere, plan, err)) != LUCENT_OK)
        return st;
    struct frame_uniforms *u = &plan->uniforms;
    u->owned[1] = (float)plan->view_count;
    u->params[0] = (float)scene->material.eta;
    u->params[1] = (float)plan->scale_mm;
    u->params[2] = (float)(proxy_tolerance + mesh->radius * 1e-5);
    u->params[3] = (float)scene->light_count;
    plan->light_count = scene->light_count;
    plan->gather_owned = frame_far_views(scene, plan) > 1 && plan->scatter_samples > 0;
    plan->cull_back_faces = mesh->closed;
    plan->cull_camera = mesh->closed && plan->camera_outside;
    plan->sampling = scene->sampling;
    plan->fallback = scene->fallback;
    plan->single_scattering = scene->single_scattering;
    return LUCENT_OK;
}
