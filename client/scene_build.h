/* scene_build.h - the scene document a render sends: a --scene file (or nothing) with each scene flag
 * of `lucent render` applied on top, in command-line order. */
#ifndef LUCENT_SCENE_BUILD_H
#define LUCENT_SCENE_BUILD_H

#include <jansson.h>

#include "cli_args.h"
#include "cli_error.h"

/* The flags that set scene fields; their ids belong to scene_apply. */
extern const struct cli_option scene_options[];

/* What earlier flags did that later ones depend on. */
struct scene_state {
    int lights_started; /* lights begun by --light-dir / --light-pos; the first replaces the file's lights */
};

/* Reads a scene document (a JSON object; duplicate keys refused). */
int scene_load(const char *path, json_t **scene, lc_error *err);
int scene_apply(json_t *scene, struct scene_state *st, const struct cli_option *opt, const char *value,
                lc_error *err);

#endif
