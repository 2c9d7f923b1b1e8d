/* frame_passes.h - the passes a frame plan calls for and the shader variants they run, with the variant
 * keys and specialization constants: decided once here, recorded by each backend with its own API calls. */
#ifndef LUCENT_FRAME_PASSES_H
#define LUCENT_FRAME_PASSES_H

#include "frame_plan.h"

/* The projection images are drawn in up to three passes: the front view at projection_size, the four side
 * views at their own (smaller) size, and, where the plan has light views, those at the side views' size.
 * The side and light views land in the top-left side_size^2 corner of layers 1-4 and 5-6 of the
 * projection images' arrays. Each pass writes flux and depth, and the normal. */
enum { PROJECTION_FRONT = 0, PROJECTION_SIDES = 1, PROJECTION_LIGHTS = 2, PROJECTION_PASSES = 3 };
#define SIDE_VIEWS 4

/* The scatter passes, in order: the far annulus per block, its filter over neighbouring blocks, and the
 * compose pass per pixel (scatter.comp). */
enum { SCATTER_COMPOSE = 0, SCATTER_FAR = 1, SCATTER_FAR_FILTER = 2 };
struct scatter_variant {
    int pass;           /* SCATTER_* */
    int block;          /* pixels a side of one far sample: 1, 2 or 4 */
    int samples, views;
    lucent_sampling sampling;
    lucent_fallback fallback;
    int single_scattering;
};
/* View counts a scatter variant is built for: 1, or the five camera views plus 0..FRAME_LIGHT_VIEWS. */
#define VIEW_VARIANTS (FRAME_LIGHT_VIEWS + 2)
#define SCATTER_CONSTANTS 7
#define PROJECTION_CONSTANTS 2

/* Timestamps taken before the first pass and after each of the four. */
enum { TS_START, TS_SHADOW, TS_PROJECTION, TS_GBUFFER, TS_SCATTER, TS_COUNT };

/* std430 struct FarSample in scatter.comp: two vec4. */
#define FRAME_FAR_SAMPLE_BYTES 32
/* Mip levels of an image of side `size`, down to one texel. */
uint32_t frame_mip_levels(uint32_t size);

struct frame_passes {
    int projection[PROJECTION_PASSES];   /* 1: the pass is drawn */
    int first_view[PROJECTION_PASSES];   /* the projection image layer of each pass's first view */
    int views[PROJECTION_PASSES];        /* views each pass draws (light views: only those planned) */
    int scatter[3];                      /* by SCATTER_*: 1 when the pass runs */
    struct scatter_variant variant[3];   /* by SCATTER_* */
};

/* Which passes and variants a plan calls for. Blocks of one pixel have no near disc: their far part holds
 * the point's own light, which the filter would blur, so the compose pass reads the far samples themselves. */
void frame_passes_plan(const struct frame_plan *plan, struct frame_passes *out);

/* A projection variant (specialized by light count and which lights are shadowed: CPU drivers pay for
 * every branch, taken or not): its key among `which` and culling (0 where a backend keys neither), and
 * its constants (constant_id order of projection.frag). */
lucent_status projection_variant_key(int which, int lights, uint32_t shadow_mask, int cull, uint64_t *key,
                                     lucent_error *err);
void projection_variant_constants(int lights, uint32_t shadow_mask, int32_t values[PROJECTION_CONSTANTS]);
/* A scatter variant's key and constants (constant_id order of scatter.comp); refuses variants no shader
 * builds (a far pass without samples, a block other than 1, 2 or 4). */
lucent_status scatter_variant_key(const struct scatter_variant *v, uint64_t *key, lucent_error *err);
void scatter_variant_constants(const struct scatter_variant *v, int32_t values[SCATTER_CONSTANTS]);

#endif
