/* test_gpu_faults.c - liblucent through injected GPU faults (test builds; renderer/gpu/gpu_faults.h): a
 * failed submit and a timed-out fence fail one frame and the next is exact; a lost device refuses every
 * later frame on its renderer, and a new renderer gets a new device and renders the same image. */
#include "test_support.h"

#include <stdlib.h>
#include <string.h>

static const char *SCENE = "{\"mesh\":{\"builtin\":\"sphere\"},\"width\":48,\"height\":48,\"projection_size\":64}";

/* One frame of SCENE; the status, and the image in img on success. */
static lucent_status frame(lucent_renderer *r, lucent_image *img, lucent_error *err)
{
    lucent_scene scene;
    if (lucent_scene_parse(SCENE, strlen(SCENE), 0, &scene, err) != LUCENT_OK)
        return err->status;
    memset(img, 0, sizeof *img);
    return lucent_render(r, &scene, img, NULL, err);
}

static int same_pixels(const lucent_image *a, const lucent_image *b)
{
    return a->width == b->width && a->height == b->height &&
           memcmp(a->rgba, b->rgba, sizeof(float) * 4 * (size_t)a->width * (size_t)a->height) == 0;
}

int main(void)
{
    /* Frames count over the process from 1; read once, before the first frame. */
    setenv("LUCENT_FAULTS", "submit@2,timeout@4,lost@6", 1);
    lucent_renderer *r = test_renderer();
    lucent_image first, img;
    lucent_error err = {0};
    lucent_status st = frame(r, &first, &err);
    test_check(st == LUCENT_OK, "frame 1 renders (%s)", lucent_status_name(st));
    st = frame(r, &img, &err);
    test_check(st == LUCENT_E_GPU, "frame 2, the submit fails: %s: %s", lucent_status_name(st), err.message);
    st = frame(r, &img, &err);
    test_check(st == LUCENT_OK && same_pixels(&first, &img), "frame 3 renders the same pixels (%s)",
               lucent_status_name(st));
    lucent_image_free(&img);
    st = frame(r, &img, &err);
    test_check(st == LUCENT_E_GPU, "frame 4, the fence wait times out: %s: %s", lucent_status_name(st),
               err.message);
    st = frame(r, &img, &err);
    test_check(st == LUCENT_OK && same_pixels(&first, &img), "frame 5 waits for frame 4, then renders the same "
               "pixels (%s)", lucent_status_name(st));
    lucent_image_free(&img);
    st = frame(r, &img, &err);
    test_check(st == LUCENT_E_DEVICE_LOST, "frame 6, the device is lost: %s: %s", lucent_status_name(st),
               err.message);
    st = frame(r, &img, &err);
    test_check(st == LUCENT_E_DEVICE_LOST, "the renderer refuses the next frame: %s: %s", lucent_status_name(st),
               err.message);
    lucent_renderer *fresh = test_renderer();
    st = frame(fresh, &img, &err);
    test_check(st == LUCENT_OK && same_pixels(&first, &img), "a new renderer (a new device) renders the same pixels "
               "(%s)", lucent_status_name(st));
    lucent_image_free(&img);
    lucent_renderer_destroy(r);
    lucent_renderer_destroy(fresh);
    lucent_image_free(&first);
    return test_finish();
}
