/* image.c - allocation and release of lucent_image, the linear float frame with its AOVs.
 * Encoding and decoding live in image_io.cpp; this file needs only libc. */
#include "lucent.h"

#include <stdlib.h>

static lucent_status check_side(int side, const char *field, lucent_error *err)
{
    if (side < 1 || side > LUCENT_MAX_IMAGE_SIDE)
        return lucent_fail(err, LUCENT_E_LIMIT, field, "%s is %d; must be between 1 and %d", field,
                           side, LUCENT_MAX_IMAGE_SIDE);
    return LUCENT_OK;
}

lucent_status lucent_image_alloc(lucent_image *img, int width, int height, int with_aovs, lucent_error *err)
{
    if (!img)
        return lucent_fail(err, LUCENT_E_INVALID, "", "lucent_image_alloc: image is NULL");
    *img = (lucent_image){0};
    lucent_status st = check_side(width, "width", err);
    if (st == LUCENT_OK)
        st = check_side(height, "height", err);
    if (st != LUCENT_OK)
        return st;

    /* The side limit keeps pixels * 4 far below SIZE_MAX, so no product here can overflow. */
    size_t pixels = (size_t)width * (size_t)height;
    img->rgba = calloc(pixels * 4, sizeof(float));
    if (with_aovs) {
        img->depth = calloc(pixels, sizeof(float));
        img->normal = calloc(pixels * 3, sizeof(float));
        img->view = calloc(pixels, sizeof(float));
        img->facing = calloc(pixels, sizeof(float));
    }
    if (!img->rgba || (with_aovs && (!img->depth || !img->normal || !img->view || !img->facing))) {
        lucent_image_free(img);
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory for a %dx%d image", width,
                           height);
    }
    /* Zero would name the front projection image; uncovered pixels must say "none". */
    for (size_t i = 0; with_aovs && i < pixels; i++)
        img->view[i] = -1.0f;
    img->width = width;
    img->height = height;
    return LUCENT_OK;
}

void lucent_image_free(lucent_image *img)
{
    if (!img)
        return;
    free(img->rgba);
    free(img->depth);
    free(img->normal);
    free(img->view);
    free(img->facing);
    *img = (lucent_image){0};
}
