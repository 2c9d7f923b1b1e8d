/* frame_passes.c - the passes and shader variants of frame_passes.h. Keys number every variant densely so
 * that a pipeline cache (pipeline_lru.h) can tell them apart. */
#include "frame_passes.h"

#include <string.h>

uint32_t frame_mip_levels(uint32_t size)
{
    uint32_t levels = 1;
    while (size >> levels)
        levels++;
    return levels;
}

void frame_passes_plan(const struct frame_plan *plan, struct frame_passes *out)
{
    memset(out, 0, sizeof *out);
    int five = plan->view_count > 1;
    out->projection[PROJECTION_FRONT] = 1;
    out->views[PROJECTION_FRONT] = 1;
    out->projection[PROJECTION_SIDES] = five;
    out->first_view[PROJECTION_SIDES] = 1;
    out->views[PROJECTION_SIDES] = five ? SIDE_VIEWS : 0;
    out->projection[PROJECTION_LIGHTS] = plan->view_count > FRAME_CAMERA_VIEWS;
    out->first_view[PROJECTION_LIGHTS] = 1 + SIDE_VIEWS;
    out->views[PROJECTION_LIGHTS] = plan->view_count > FRAME_CAMERA_VIEWS ? plan->view_count - FRAME_CAMERA_VIEWS : 0;
    struct scatter_variant v = {SCATTER_FAR, plan->far_block, plan->scatter_samples, plan->view_count,
                                plan->sampling, plan->fallback, plan->single_scattering};
    for (int pass = SCATTER_COMPOSE; pass <= SCATTER_FAR_FILTER; pass++) {
        out->variant[pass] = v;
        out->variant[pass].pass = pass;
    }
    out->scatter[SCATTER_FAR] = plan->scatter_samples > 0;
    out->scatter[SCATTER_FAR_FILTER] = plan->scatter_samples > 0 && plan->far_block > 1;
    out->scatter[SCATTER_COMPOSE] = 1;
}

lucent_status projection_variant_key(int which, int lights, uint32_t shadow_mask, int cull, uint64_t *key,
                                     lucent_error *err)
{
    if (lights < 1 || lights > LUCENT_MAX_LIGHTS || shadow_mask >> lights || which < 0 || which >= PROJECTION_PASSES)
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "no projection pipeline for %d lights, mask 0x%x", lights,
                           (unsigned)shadow_mask);
    uint64_t variant = ((uint64_t)(cull != 0) * PROJECTION_PASSES + (uint64_t)which) * LUCENT_MAX_LIGHTS +
                       (uint64_t)(lights - 1);
    *key = variant << LUCENT_MAX_LIGHTS | shadow_mask;
    return LUCENT_OK;
}

void projection_variant_constants(int lights, uint32_t shadow_mask, int32_t values[PROJECTION_CONSTANTS])
{
    values[0] = lights;
    values[1] = (int32_t)shadow_mask;
}

lucent_status scatter_variant_key(const struct scatter_variant *v, uint64_t *key, lucent_error *err)
{
    int views = v->views == 1 ? 0 : v->views - FRAME_CAMERA_VIEWS + 1;   /* 0: one view; 1..: five + lights */
    if (v->samples < 0 || v->samples > LUCENT_MAX_SAMPLES || views < 0 || views >= VIEW_VARIANTS ||
        v->pass < SCATTER_COMPOSE || v->pass > SCATTER_FAR_FILTER || (v->pass != SCATTER_COMPOSE && v->samples == 0) ||
        (v->block != 1 && v->block != 2 && v->block != 4))
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "no scatter pipeline for %d samples, %d views%s", v->samples,
                           v->views, v->pass == SCATTER_COMPOSE ? "" : ", far pass");
    int shared = v->sampling == LUCENT_SAMPLING_SHARED, front = v->fallback == LUCENT_FALLBACK_FRONT;
    int single = v->single_scattering != 0;
    uint64_t pass = (uint64_t)v->pass * 3 + (uint64_t)(v->block == 4 ? 2 : v->block - 1);
    *key = ((((pass * (LUCENT_MAX_SAMPLES + 1) + (uint64_t)v->samples) * VIEW_VARIANTS + (uint64_t)views) * 2 +
             (uint64_t)shared) * 2 + (uint64_t)front) * 2 + (uint64_t)single;
    return LUCENT_OK;
}

void scatter_variant_constants(const struct scatter_variant *v, int32_t values[SCATTER_CONSTANTS])
{
    int32_t c[SCATTER_CONSTANTS] = {v->samples, v->views, v->sampling == LUCENT_SAMPLING_SHARED,
                                    v->fallback == LUCENT_FALLBACK_FRONT, v->single_scattering != 0, v->pass,
                                    v->block};
    memcpy(values, c, sizeof c);
}
