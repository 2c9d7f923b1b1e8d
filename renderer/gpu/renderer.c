/* renderer.c - the warm renderer: a GPU backend (gpu.h) and cached meshes, and lucent_render(), which plans a
 * frame, has the backend draw it (or the CPU reference integrate it) and says what it modelled. */
#include "auto_plan.h"
#include "clock_ms.h"
#include "gpu.h"
#include "json_text.h"
#include "mesh_cache.h"
#include "path.h"
#include "reference.h"

#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct lucent_renderer {
    struct gpu *gpu;
    struct mesh_cache meshes;
    struct frame_plan plan;   /* rebuilt every frame; lives here to keep 4 KB of samples off the stack */
    struct auto_plan chosen;  /* method "auto": the scene actually rendered */
    struct sphere_tables sphere;   /* the last material's tables of diffusion in a sphere */
    atomic_int cancel;        /* set by lucent_render_cancel from any thread */
    int verbose;
};

lucent_renderer *lucent_renderer_create(const lucent_renderer_desc *desc, lucent_error *err)
{
    lucent_status st;
    lucent_renderer *r = calloc(1, sizeof *r);
    if (!r) {
        lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory creating the renderer");
        return NULL;
    }
    r->verbose = desc ? desc->verbose : 0;
    mesh_cache_init(&r->meshes, desc && desc->mesh_cache_bytes ? desc->mesh_cache_bytes : MESH_CACHE_DEFAULT_BYTES);
    if ((st = gpu_open(desc ? desc->backend : NULL, desc ? desc->device_name : NULL, r->verbose, &r->gpu, err))) {
        free(r);
        return NULL;
    }
    return r;
}

void lucent_renderer_destroy(lucent_renderer *r)
{
    if (!r)
        return;
    if (r->gpu) {
        gpu_settle(r->gpu, NULL);   /* a frame whose wait timed out finishes before its meshes go */
        mesh_cache_destroy(r->gpu, &r->meshes);
    }
    gpu_close(r->gpu);
    free(r);
}

/* Every component finite and within +-bound (NaN fails). */
static int within(const double v[3], double bound)
{
    for (int i = 0; i < 3; i++)
        if (!(v[i] >= -bound && v[i] <= bound))
            return 0;
    return 1;
}

/* A hand-built light, as the parser would take it: a direction or position in range (a direction not
 * zero), colour and intensity in range. */
static lucent_status check_light(const lucent_light *l, int i, lucent_error *err)
{
    char field[32];
    const double zero[3] = {0, 0, 0};
    int point = l->type == LUCENT_LIGHT_POINT;
    snprintf(field, sizeof field, "lights[%d]", i);
    if (l->type != LUCENT_LIGHT_DIRECTIONAL && !point)
        return lucent_fail(err, LUCENT_E_LIMIT, field, "unknown light type %d", (int)l->type);
    if (!within(point ? l->position : l->direction, LUCENT_MAX_COORD) ||
        (!point && memcmp(l->direction, zero, sizeof zero) == 0))
        return lucent_fail(err, LUCENT_E_LIMIT, field, "%s must be finite, within +-%g%s", point ? "position" : "direction",
                           LUCENT_MAX_COORD, point ? "" : " and not zero");
    if (!within(l->color, LUCENT_MAX_COLOR) || l->color[0] < 0 || l->color[1] < 0 || l->color[2] < 0 ||
        !(l->intensity >= 0 && l->intensity <= LUCENT_MAX_INTENSITY))
        return lucent_fail(err, LUCENT_E_LIMIT, field, "color must be 0..%g and intensity 0..%g", LUCENT_MAX_COLOR,
                           LUCENT_MAX_INTENSITY);
    return LUCENT_OK;
}

/* A hand-built camera: the parser's field-of-view range, positions in range, distinct eye and target. */
static lucent_status check_camera(const lucent_camera *c, lucent_error *err)
{
    if (!c->given)
        return LUCENT_OK;
    if (!(c->fov_deg > LUCENT_MIN_FOV_DEG && c->fov_deg < LUCENT_MAX_FOV_DEG))
        return lucent_fail(err, LUCENT_E_LIMIT, "camera.fov_deg", "must be between %g and %g degrees",
                           LUCENT_MIN_FOV_DEG, LUCENT_MAX_FOV_DEG);
    if (!within(c->position, LUCENT_MAX_COORD) || !within(c->target, LUCENT_MAX_COORD) ||
        !within(c->up, LUCENT_MAX_COORD) || memcmp(c->position, c->target, sizeof c->position) == 0)
        return lucent_fail(err, LUCENT_E_LIMIT, "camera", "position, target and up must be finite, within +-%g, "
                           "and the position apart from the target", LUCENT_MAX_COORD);
    return LUCENT_OK;
}

/* Library callers may build scenes by hand: what the parser guarantees and the GPU side and the dipole
 * rely on is checked again (the comparisons are written so that NaN fails them); a value the parser
 * refuses would otherwise reach the plan as inf or NaN (g = 1: sigma_s infinite; fov 0: 1 / tan 0). */
static lucent_status check_scene(const lucent_scene *s, lucent_error *err)
{
    if (s->width < 1 || s->height < 1 || s->width > LUCENT_MAX_IMAGE_SIDE || s->height > LUCENT_MAX_IMAGE_SIDE)
        return lucent_fail(err, LUCENT_E_LIMIT, "width", "image size %dx%d outside 1..%d", s->width, s->height,
                           LUCENT_MAX_IMAGE_SIDE);
    if (s->projection_size < LUCENT_MIN_PROJECTION_SIZE || s->projection_size > LUCENT_MAX_PROJECTION_SIZE)
        return lucent_fail(err, LUCENT_E_LIMIT, "projection_size", "must be %d..%d", LUCENT_MIN_PROJECTION_SIZE,
                           LUCENT_MAX_PROJECTION_SIZE);
    if (s->side_projection_size < 0 || s->side_projection_size > s->projection_size ||
        (s->side_projection_size && s->side_projection_size < LUCENT_MIN_PROJECTION_SIZE))
        return lucent_fail(err, LUCENT_E_LIMIT, "side_projection_size", "must be 0 or %d..projection_size",
                           LUCENT_MIN_PROJECTION_SIZE);
    if (s->samples < 1 || s->samples > LUCENT_MAX_SAMPLES)
        return lucent_fail(err, LUCENT_E_LIMIT, "samples", "must be 1..%d", LUCENT_MAX_SAMPLES);
    const lucent_material *m = &s->material;
    for (int c = 0; c < 3; c++)
        if (!(m->sigma_a[c] >= 0.0 && m->sigma_a[c] <= LUCENT_MAX_SIGMA) ||
            !(m->sigma_s_prime[c] >= LUCENT_MIN_SIGMA_S_PRIME && m->sigma_s_prime[c] <= LUCENT_MAX_SIGMA))
            return lucent_fail(err, LUCENT_E_LIMIT, "material", "coefficients outside the documented ranges");
    if (!(m->eta >= LUCENT_MIN_ETA && m->eta <= LUCENT_MAX_ETA))
        return lucent_fail(err, LUCENT_E_LIMIT, "material.eta", "must be %g..%g", LUCENT_MIN_ETA, LUCENT_MAX_ETA);
    if (s->scale_mm != 0.0 && !(s->scale_mm >= LUCENT_MIN_SCALE_MM && s->scale_mm <= LUCENT_MAX_SCALE_MM))
        return lucent_fail(err, LUCENT_E_LIMIT, "scale_mm", "must be 0 (automatic) or %g..%g", LUCENT_MIN_SCALE_MM,
                           LUCENT_MAX_SCALE_MM);
    if (!(m->g >= -LUCENT_MAX_G && m->g <= LUCENT_MAX_G))
        return lucent_fail(err, LUCENT_E_LIMIT, "material.g", "must be %g..%g", -LUCENT_MAX_G, LUCENT_MAX_G);
    if (!(m->profile >= LUCENT_PROFILE_DIPOLE && m->profile <= LUCENT_PROFILE_DEFAULT))
        return lucent_fail(err, LUCENT_E_LIMIT, "material.profile", "must be one of lucent_profile's values (got %d)",
                           (int)m->profile);
    if (s->single_scattering != 0 && s->single_scattering != 1 &&
        !(s->single_scattering == LUCENT_CHOSEN && s->method == LUCENT_METHOD_AUTO))
        return lucent_fail(err, LUCENT_E_LIMIT, "single_scattering", "must be 0, 1 or (method auto) LUCENT_CHOSEN");
    if (s->light_count < 1 || s->light_count > LUCENT_MAX_LIGHTS)
        return lucent_fail(err, LUCENT_E_LIMIT, "lights", "must hold 1..%d lights", LUCENT_MAX_LIGHTS);
    for (int i = 0; i < s->light_count; i++) {
        lucent_status st = check_light(&s->lights[i], i, err);
        if (st != LUCENT_OK)
            return st;
    }
    return check_camera(&s->camera, err);
}

const char *lucent_renderer_backend(const lucent_renderer *r)
{
    return r->gpu->backend;
}

const char *lucent_renderer_device(const lucent_renderer *r)
{
    return r->gpu->device;
}

uint64_t lucent_renderer_max_pixels(const lucent_renderer *r)
{
    return r->gpu->max_pixels;
}

static lucent_status check_device_limits(const lucent_renderer *r, const lucent_scene *s, lucent_error *err)
{
    uint64_t pixels = (uint64_t)s->width * (uint64_t)s->height, max = lucent_renderer_max_pixels(r);
    if (s->method == LUCENT_METHOD_REFERENCE || s->method == LUCENT_METHOD_PATH || pixels <= max)
        return LUCENT_OK;
    return lucent_fail(err, LUCENT_E_LIMIT, "width",
                       "a %dx%d image is %llu pixels; this device (%s) renders at most %llu (%s)",
                       s->width, s->height, (unsigned long long)pixels, r->gpu->device, (unsigned long long)max,
                       r->gpu->max_pixels_why);
}

/* The facing AOV: cosine between each covered pixel's normal and the direction to the eye, which
 * image comparisons use to find the silhouette band. */
static void fill_facing(lucent_image *img, const struct view_frame *camera)
{
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            size_t i = (size_t)y * img->width + x;
            if (img->view[i] < 0.0f)
                continue;
            double dir[3];
            view_frame_pixel_ray(camera, x, y, img->width, img->height, dir);
            const float *n = &img->normal[i * 3];
            img->facing[i] = (float)-(n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2]);
        }
}

/* AOVs only travel in EXR; a PNG request skips copying them. */
static lucent_status read_image(lucent_renderer *r, const lucent_scene *s, const struct gpu_result *res,
                                lucent_image *out, lucent_error *err)
{
    int with_aovs = s->format == LUCENT_FORMAT_EXR;
    lucent_status st = lucent_image_alloc(out, s->width, s->height, with_aovs, err);
    if (st != LUCENT_OK)
        return st;
    size_t pixels = (size_t)s->width * s->height;
    const float *normal_view = res->normal_view;
    memcpy(out->rgba, res->rgba, pixels * 16);
    if (!with_aovs)
        return LUCENT_OK;
    memcpy(out->depth, res->depth, pixels * 4);
    for (size_t i = 0; i < pixels; i++) {
        memcpy(&out->normal[i * 3], &normal_view[i * 4], 12);
        out->view[i] = normal_view[i * 4 + 3];
    }
    fill_facing(out, &r->plan.camera);
    return LUCENT_OK;
}

/* The profile a method that integrates one does: the material's, the dipole when it names none. */
static lucent_profile integrated_profile(const lucent_material *m)
{
    return m->profile == LUCENT_PROFILE_DEFAULT ? LUCENT_PROFILE_DIPOLE : m->profile;
}

static const char *method_name(lucent_method m)
{
    switch (m) {
    case LUCENT_METHOD_SINGLE: return "single";
    case LUCENT_METHOD_REFERENCE: return "reference";
    case LUCENT_METHOD_AUTO: return "auto";
    case LUCENT_METHOD_PATH: return "path";
    default: return "five";
    }
}

/* requested: the scene as asked; s: as rendered (differs for method "auto", whose choices follow). */
static void describe(const lucent_scene *requested, const lucent_scene *s, const struct auto_plan *chosen,
                     const struct frame_plan *plan, const struct gpu_mesh *gm, lucent_stats *stats)
{
    char lights[512] = "", choices[sizeof chosen->decisions + 16] = "", device[2 * sizeof stats->device];
    json_escape(stats->device, device, sizeof device);
    size_t n = 0;
    int shared = s->sampling == LUCENT_SAMPLING_SHARED, samples = plan->scatter_samples;
    int gathered = frame_far_views(s, plan);
    for (int l = 0; l < s->light_count && n < sizeof lights; l++)
        n += (size_t)snprintf(lights + n, sizeof lights - n, "%s\"%s\"", l ? "," : "", plan->shadow_reason[l]);
    char through[512] = "";
    size_t m = 0;
    for (int l = 0; l < s->light_count && m < sizeof through; l++)
        m += (size_t)snprintf(through + m, sizeof through - m, "%s\"%s\"", l ? "," : "",
                              plan->transmission_reason[l]);
    if (chosen)
        snprintf(choices, sizeof choices, "\"auto\":{%s},", chosen->decisions);
    stats->profile = integrated_profile(&s->material);
    stats->single_scattering = s->single_scattering;
    snprintf(stats->modelled, sizeof stats->modelled,
             "{\"method\":\"%s\",\"backend\":\"%s\",\"device\":\"%s\",%s\"views\":%d,\"profile\":\"%s\","
             "\"subsurface\":\"%s\",\"samples_per_channel\":%d,"
             "\"sampling\":\"%s\",\"texel_fetches_per_far_sample\":%d,\"far_block_pixels\":%d,"
             "\"near_disc_mm\":%.6g,\"projection_size\":%d,"
             "\"side_projection_size\":%d,\"scale_mm\":%.9g,\"shadows\":[%s],\"transmission\":[%s],"
             "\"projection_triangles\":{\"front\":%u,\"sides_and_shadows\":%u},"
             "\"hidden_point_fallback\":\"%s\",\"single_scattering\":%s}",
             method_name(requested->method), stats->backend, device, choices, plan->view_count,
             lucent_profile_name(stats->profile),
             samples ? "sampled profile" : "diffuse limit (irradiance x total R_d)", samples,
             shared ? "shared" : "per_channel", samples ? gathered * (shared ? samples : 3 * samples) : 0,
             samples ? plan->far_block : 0, plan->near_disc_mm, s->projection_size,
             plan->view_count > 1 ? plan->side_projection_size : 0, plan->scale_mm, lights, through,
             gpu_mesh_geometry(gm, PROXY_FRONT).index_count / 3, gpu_mesh_geometry(gm, PROXY_SIDES).index_count / 3,
             plan->view_count == 1 || s->fallback == LUCENT_FALLBACK_FRONT
                 ? "front"
                 : "far part gathered from every view's share of the surface; near part from the next best-facing "
                   "visible view, then front, the two best views blended",
             s->single_scattering ? "true" : "false");
    stats->triangles = gm->mesh->triangle_count;
    stats->proxy_triangles = gm->proxies[PROXY_FRONT].triangles;
    stats->shadow_maps = plan->shadow_count;
    stats->views = plan->view_count;
}

/* What the CPU methods share with the raster passes: the camera and the scale. */
static lucent_status cpu_view(const lucent_scene *scene, const struct gpu_mesh *gm, struct view_frame *camera,
                              double *scale_mm, lucent_error *err)
{
    *scale_mm = frame_scale_mm(scene, gm->mesh);
    return frame_camera(scene, gm->mesh, camera, err);
}

/* method "reference": the CPU integrator on the cached mesh, with the same camera and AOVs. */
static lucent_status render_reference(lucent_renderer *r, const lucent_scene *scene, const struct gpu_mesh *gm,
                                      lucent_image *out, lucent_stats *stats, lucent_error *err)
{
    struct view_frame camera;
    double scale_mm;
    lucent_status st = cpu_view(scene, gm, &camera, &scale_mm, err);
    if (st != LUCENT_OK)
        return st;
    struct reference_options options = {.points = scene->reference_points,
                                        .brute_force = scene->reference_threshold == 0.0,
                                        .threshold = fmax(scene->reference_threshold, 0.0),
                                        .cancel = &r->cancel};
    struct reference_report report;
    int with_aovs = scene->format == LUCENT_FORMAT_EXR;
    st = reference_render(scene, gm->mesh, &camera, scale_mm, &options, with_aovs, out, &report, err);
    if (st != LUCENT_OK)
        return st;
    stats->triangles = gm->mesh->triangle_count;
    stats->profile = integrated_profile(&scene->material);
    stats->single_scattering = scene->single_scattering;
    snprintf(stats->modelled, sizeof stats->modelled,
             "{\"method\":\"reference\",\"backend\":\"cpu\",\"profile\":\"%s\",\"scale_mm\":%.9g,\"points\":%u,"
             "\"point_spacing_mm\":%.6g,"
             "\"min_mean_free_path_mm\":%.6g,\"sum\":\"%s\",\"threshold\":%.6g,\"estimated_rel_error\":%.3g,"
             "\"ms_points\":%.3f,\"ms_pixels\":%.3f,\"single_scattering\":%s}",
             lucent_profile_name(stats->profile), scale_mm, report.points, report.point_spacing_mm,
             report.min_mean_free_path_mm,
             options.brute_force ? "brute force" : "hierarchical", report.threshold, report.estimated_rel_error,
             report.ms_points, report.ms_pixels, scene->single_scattering ? "true" : "false");
    return LUCENT_OK;
}

/* method "path": random walks in the medium on the CPU, with the same camera and AOVs. */
static lucent_status render_path(lucent_renderer *r, const lucent_scene *scene, const struct gpu_mesh *gm,
                                 lucent_image *out, lucent_stats *stats, lucent_error *err)
{
    struct view_frame camera;
    double scale_mm;
    lucent_status st = cpu_view(scene, gm, &camera, &scale_mm, err);
    if (st != LUCENT_OK)
        return st;
    struct path_options options = {.samples = scene->path_samples, .time_s = scene->path_time_s,
                                   .boundary = scene->path_boundary, .filter = scene->path_filter,
                                   .seed = scene->path_seed,
                                   .cancel = &r->cancel};
    struct path_report report;
    st = path_render(scene, gm->mesh, &camera, scale_mm, &options, scene->format == LUCENT_FORMAT_EXR, out, &report,
                     err);
    if (st != LUCENT_OK)
        return st;
    stats->triangles = gm->mesh->triangle_count;
    stats->profile = LUCENT_PROFILE_DEFAULT;
    snprintf(stats->modelled, sizeof stats->modelled,
             "{\"method\":\"path\",\"backend\":\"cpu\",\"scale_mm\":%.9g,\"boundary\":\"%s\",\"filter\":\"%s\","
             "\"samples\":%u,\"samples_asked\":%u,\"seed\":%u,\"rel_std_error\":%.4g,\"mean_steps\":%.4g,"
             "\"escaped_share\":%.4g,\"ms_walks\":%.3f}",
             scale_mm, scene->path_boundary == LUCENT_PATH_CYCLES ? "cycles" : "fresnel",
             scene->path_filter == LUCENT_PATH_FILTER_BOX ? "box" : "point", report.samples,
             scene->path_samples, scene->path_seed, report.rel_std_error, report.mean_steps, report.escaped_share,
             report.ms);
    return LUCENT_OK;
}

lucent_status lucent_render(lucent_renderer *r, const lucent_scene *scene, lucent_image *out,
                            lucent_stats *stats, lucent_error *err)
{
    lucent_stats local;
    if (!stats)
        stats = &local;
    memset(stats, 0, sizeof *stats);
    memset(out, 0, sizeof *out);
    snprintf(stats->device, sizeof stats->device, "%s", r->gpu->device);
    snprintf(stats->backend, sizeof stats->backend, "%s", r->gpu->backend);
    atomic_store(&r->cancel, 0);
    double t0 = now_ms();
    struct gpu_mesh *gm;
    struct frame_plan *plan = &r->plan;
    lucent_status st;
    /* A frame that timed out must finish before its meshes, targets or pipelines are touched. */
    if ((st = check_scene(scene, err)) || (st = check_device_limits(r, scene, err)) ||
        (st = gpu_settle(r->gpu, err)) ||
        (st = mesh_cache_get(r->gpu, &r->meshes, &scene->mesh, &gm, &stats->ms_mesh_load, err)))
        return st;
    if (scene->method == LUCENT_METHOD_REFERENCE || scene->method == LUCENT_METHOD_PATH) {
        st = scene->method == LUCENT_METHOD_PATH ? render_path(r, scene, gm, out, stats, err)
                                                 : render_reference(r, scene, gm, out, stats, err);
        stats->ms_total = now_ms() - t0;
        return st;
    }
    const lucent_scene *s = scene;
    struct auto_plan *chosen = NULL;
    if (scene->method == LUCENT_METHOD_AUTO) {
        if ((st = auto_plan_choose(scene, gm->mesh, &r->chosen, err)))
            return st;
        chosen = &r->chosen;
        s = &chosen->scene;
    }
    double t_proxies = now_ms();
    if ((st = mesh_cache_upload(r->gpu, &r->meshes, gm, s->projection_size, frame_side_projection_size(s), err)))
        return st;
    stats->ms_mesh_load += now_ms() - t_proxies;
    int proxied = gm->proxies[PROXY_FRONT].triangles || gm->proxies[PROXY_SIDES].triangles;
    double tolerance = proxied ? PROXY_TOLERANCE * gm->mesh->radius : 0.0;
    if ((st = frame_plan_build(s, gm->mesh, tolerance, chosen && chosen->diffuse_limit, &r->sphere, plan, err)))
        return st;
    struct gpu_frame frame = {plan, (uint32_t)s->width, (uint32_t)s->height, (uint32_t)s->projection_size,
                              (uint32_t)plan->side_projection_size, (struct gpu_draw){gm->full.gpu, gm->full.index_count},
                              gpu_mesh_geometry(gm, PROXY_FRONT), gpu_mesh_geometry(gm, PROXY_SIDES)};
    struct gpu_result res;
    if ((st = gpu_render(r->gpu, &frame, &res, err)))
        return st;
    stats->ms_shadow = res.ms_shadow;
    stats->ms_projection = res.ms_projection;
    stats->ms_gbuffer = res.ms_gbuffer;
    stats->ms_scatter = res.ms_scatter;
    double t1 = now_ms();
    if ((st = read_image(r, scene, &res, out, err)))
        return st;
    stats->ms_readback = now_ms() - t1;
    stats->ms_total = now_ms() - t0;
    stats->mesh_cache_bytes = mesh_cache_bytes(&r->meshes);
    stats->device_bytes = r->gpu->memory_bytes;
    describe(scene, s, chosen, plan, gm, stats);
    return LUCENT_OK;
}

void lucent_render_cancel(lucent_renderer *r)
{
    atomic_store(&r->cancel, 1);
}

int lucent_stats_json(const lucent_stats *s, char *buf, size_t cap)
{
    char device[2 * sizeof s->device];
    json_escape(s->device, device, sizeof device);
    int n = snprintf(buf, cap,
                     "{\"backend\":\"%s\",\"device\":\"%s\",\"triangles\":%u,\"proxy_triangles\":%u,"
                     "\"shadow_maps\":%d,\"views\":%d,"
                     "\"mesh_cache_bytes\":%llu,\"device_bytes\":%llu,"
                     "\"ms\":{\"mesh_load\":%.3f,\"shadow\":%.3f,\"projection\":%.3f,\"gbuffer\":%.3f,"
                     "\"scatter\":%.3f,\"readback\":%.3f,\"total\":%.3f},\"modelled\":%s}",
                     s->backend, device, s->triangles, s->proxy_triangles, s->shadow_maps, s->views,
                     (unsigned long long)s->mesh_cache_bytes, (unsigned long long)s->device_bytes, s->ms_mesh_load,
                     s->ms_shadow, s->ms_projection, s->ms_gbuffer, s->ms_scatter, s->ms_readback, s->ms_total,
                     s->modelled[0] ? s->modelled : "{}");
    return n < 0 || (size_t)n >= cap ? -1 : n;
}
