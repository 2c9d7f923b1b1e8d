/* fuzz_scene.c - libFuzzer target: the scene document parser (the POST /v1/render body, lucent-render's
 * input) on arbitrary bytes, with and without file meshes. A parsed scene must hold its limits. */
#include "lucent.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lucent_scene s;
    lucent_error err = {0};
    if (lucent_scene_parse((const char *)data, size, size % 2, &s, &err) != LUCENT_OK)
        return 0;
    /* what the renderer relies on: finite, in range */
    if (s.width < 1 || s.width > LUCENT_MAX_IMAGE_SIDE || s.height < 1 || s.height > LUCENT_MAX_IMAGE_SIDE ||
        s.light_count < 1 || s.light_count > LUCENT_MAX_LIGHTS || !(fabs(s.material.g) <= LUCENT_MAX_G) ||
        !(s.material.eta >= LUCENT_MIN_ETA && s.material.eta <= LUCENT_MAX_ETA))
        abort();
    return 0;
}
