/* fuzz_image.c - libFuzzer target: bytes as the reference image of lucent-render --compare, written to a
 * temporary .png or .exr, read with lucent_image_load and compared; what loads must be a sane image. */
#include "lucent.h"

#include <fcntl.h>
#include <jansson.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* lucent_image_load takes a path (OpenImageIO picks its reader from the extension, then from the
 * content): each input is written to $TMPDIR/fuzz_image.<pid>.png or .exr, created afresh (O_EXCL:
 * never through a link left there) and removed once read, so only a crash leaves one behind, the
 * crashing input. libFuzzer may end with _Exit, so nothing is left for atexit to remove. */
static char png_path[128], exr_path[128];

/* lucent_image_compare is linear in the pixels with no size-dependent branch beyond the image
 * edges, and a legitimate 4096 x 4096 reference takes seconds under the sanitizers, which would
 * read as a timeout: larger images are loaded and checked, not compared. */
#define COMPARE_MAX_PIXELS (256 * 256)

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    const char *tmp = getenv("TMPDIR");
    if (!tmp || !*tmp || strlen(tmp) > 64)
        tmp = "/tmp";
    snprintf(png_path, sizeof png_path, "%s/fuzz_image.%ld.png", tmp, (long)getpid());
    snprintf(exr_path, sizeof exr_path, "%s/fuzz_image.%ld.exr", tmp, (long)getpid());
    return 0;
}

static void write_input(const char *path, const uint8_t *data, size_t len)
{
    unlink(path);
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0) {
        perror(path);
        abort();
    }
    while (len > 0) {
        ssize_t n = write(fd, data, len);
        if (n <= 0) {
            perror(path);
            abort();
        }
        data += n;
        len -= (size_t)n;
    }
    if (close(fd) != 0)
        abort();
}

static int starts_with(const uint8_t *data, size_t size, const char *magic, size_t len)
{
    return size >= len && memcmp(data, magic, len) == 0;
}

/* A PNG holds 8- or 16-bit values: loaded, they are linear, premultiplied and within [0, 1]. An EXR
 * may hold any float, NaN and infinities included; the comparison must cope with those. */
static void check_image(const lucent_image *img, int is_png)
{
    if (img->width < 1 || img->width > LUCENT_MAX_IMAGE_SIDE || img->height < 1 ||
        img->height > LUCENT_MAX_IMAGE_SIDE || !img->rgba)
        abort();
    if (!is_png)
        return;
    if (img->depth || img->normal || img->view || img->facing)
        abort();
    for (size_t i = 0; i < (size_t)img->width * img->height; i++) {
        const float *px = img->rgba + 4 * i;
        if (!(px[3] >= 0 && px[3] <= 1))
            abort();
        for (int c = 0; c < 3; c++)
            if (!(px[c] >= 0 && px[c] <= px[3] * (1 + 1e-6f)))
                abort();
    }
}

/* What print_comparison in lucent_render.c prints: it must fit its buffer and be JSON. */
static void check_compare(const lucent_image *test, const lucent_image *ref)
{
    lucent_image_error e;
    lucent_error err = {0};
    char buf[1024];
    if (lucent_image_compare(test, ref, &e, &err) != LUCENT_OK)
        abort();
    int pixels = ref->width * ref->height;
    if (e.object.pixels > pixels || e.band.pixels > e.object.pixels || e.interior_pixels > e.object.pixels ||
        e.mottle_pixels > e.interior_pixels || e.coverage_mismatch > pixels)
        abort();
    if (lucent_image_error_json(&e, buf, sizeof buf) <= 0)
        abort();
    json_t *doc = json_loads(buf, JSON_REJECT_DUPLICATES, NULL);
    if (!doc)
        abort();
    json_decref(doc);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    const char *path = data[0] & 1 ? exr_path : png_path;
    write_input(path, data + 1, size - 1);
    lucent_image ref;
    lucent_error err = {0};
    lucent_status st = lucent_image_load(path, &ref, &err);
    unlink(path);
    if (st != LUCENT_OK) {
        if (ref.rgba || !err.message[0])
            abort();
        return 0;
    }
    /* OpenImageIO's PNG reader takes nothing without the signature, nor its EXR reader the PNG one */
    check_image(&ref, starts_with(data + 1, size - 1, "\x89PNG\r\n\x1a\n", 8));
    if ((size_t)ref.width * ref.height <= COMPARE_MAX_PIXELS) {
        /* the reference against itself, and against a test image covering every pixel */
        lucent_image test;
        if (lucent_image_alloc(&test, ref.width, ref.height, 0, &err) != LUCENT_OK)
            abort();
        for (size_t i = 0; i < 4 * (size_t)ref.width * ref.height; i++)
            test.rgba[i] = 0.5f;
        check_compare(&ref, &ref);
        check_compare(&test, &ref);
        lucent_image_free(&test);
    }
    lucent_image_free(&ref);
    return 0;
}
