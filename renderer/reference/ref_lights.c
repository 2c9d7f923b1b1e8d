/* ref_lights.c - lights for the CPU integrators: set-up from the scene, direction, falloff and shadow rays. */
#include "ref_lights.h"
#include "linalg.h"

#include <float.h>
#include <math.h>

lucent_status ref_lights_from_scene(const lucent_scene *scene, const struct lucent_mesh *mesh,
                                    struct ref_light out[LUCENT_MAX_LIGHTS], lucent_error *err)
{
    for (int l = 0; l < scene->light_count; l++) {
        const lucent_light *in = &scene->lights[l];
        out[l].point = in->type == LUCENT_LIGHT_POINT;
        for (int a = 0; a < 3; a++) {
            out[l].vec[a] = out[l].point ? in->position[a] - mesh->center[a] : in->direction[a];
            out[l].rgb[a] = in->color[a] * in->intensity;
        }
        if (!out[l].point && v3_normalize(out[l].vec) == 0.0)
            return lucent_fail(err, LUCENT_E_INVALID, "lights.direction", "light %d has a zero direction", l);
    }
    return LUCENT_OK;
}

double ref_light_toward(const struct ref_light *light, const double x[3], double dir[3])
{
    if (!light->point) {
        for (int a = 0; a < 3; a++)
            dir[a] = -light->vec[a];
        return INFINITY;
    }
    for (int a = 0; a < 3; a++)
        dir[a] = light->vec[a] - x[a];
    return v3_normalize(dir);
}

double ref_light_arrival(const struct ref_light *light, const struct bvh *bvh, int shadows, const double p[3],
                         const double n[3], const double origin[3], double *cos_out)
{
    double dir[3], t_max = ref_light_toward(light, p, dir);
    double falloff = light->point ? 1.0 / fmax(t_max * t_max, DBL_MIN) : 1.0;
    *cos_out = v3_dot(n, dir);
    if (*cos_out <= 0.0 || (shadows && bvh_occluded(bvh, origin, dir, t_max)))
        return 0.0;
    return falloff * *cos_out;
}
