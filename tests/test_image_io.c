/* test_image_io.c - checks image.c and image_io.cpp: allocation, PNG/EXR encoding, compositing,
 * exposure, round trips through lucent_image_load, and the error paths. Prints measured errors. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include "lucent.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define W 64
#define H 48

static int passed, failed;
static char tmpdir[] = "/tmp/lucent_image_io_XXXXXX";

/* fmt may be NULL when there is nothing measured to print. */
static void check(int ok, const char *name, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static void check(int ok, const char *name, const char *fmt, ...)
{
    printf("%s %s", ok ? "ok  " : "FAIL", name);
    if (fmt) {
        va_list ap;
        va_start(ap, fmt);
        printf(": ");
        vprintf(fmt, ap);
        va_end(ap);
    }
    printf("\n");
    if (ok)
        passed++;
    else
        failed++;
}

static void check_status(lucent_status st, const lucent_error *err, const char *name)
{
    check(st == LUCENT_OK, name, st == LUCENT_OK ? NULL : "%s: %s", lucent_status_name(st),
          err->message);
}

/* A few results stay valid at once, so one call can pass two paths. */
static const char *tmp_path(const char *name)
{
    static char path[4][256];
    static int next;
    char *p = path[next++ % 4];
    snprintf(p, sizeof path[0], "%s/%s", tmpdir, name);
    return p;
}

static unsigned char *read_file(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    *len = (size_t)ftell(f);
    rewind(f);
    unsigned char *bytes = malloc(*len ? *len : 1);
    if (bytes && fread(bytes, 1, *len, f) != *len) {
        free(bytes);
        bytes = NULL;
    }
    fclose(f);
    return bytes;
}

static int write_file(const char *path, const unsigned char *bytes, size_t len)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return 0;
    int ok = fwrite(bytes, 1, len, f) == len;
    return fclose(f) == 0 && ok;
}

/* Gradients under a disc of coverage with fractional edges, plus one HDR and one tiny pixel. */
static void fill_synthetic(lucent_image *img)
{
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            double d = hypot(x - W / 2.0, y - H / 2.0);
            double a = fmin(fmax(18.5 - d, 0.0), 1.0);
            double straight[3] = {1.5 * x / (W - 1), (double)y / (H - 1), 0.5 + 0.5 * sin(x * 0.3)};
            for (int c = 0; c < 3; c++)
                img->rgba[i * 4 + c] = (float)(straight[c] * a);
            img->rgba[i * 4 + 3] = (float)a;
            if (a > 0.0) {
                img->depth[i] = (float)(3.0 + 0.01 * x - 0.02 * y);
                img->normal[i * 3 + 0] = (float)((x - W / 2.0) / 18.5);
                img->normal[i * 3 + 1] = (float)((y - H / 2.0) / 18.5);
                img->normal[i * 3 + 2] = 0.25f;
                img->view[i] = (float)((x + y) % 5);
            }
        }
    }
    float *hdr = img->rgba + ((size_t)(H / 2) * W + W / 2) * 4;
    hdr[0] = hdr[1] = hdr[2] = 1.0e4f;
    float *tiny = hdr + 4;
    tiny[0] = tiny[1] = tiny[2] = 1.0e-30f;
}

static double srgb_encode(double v)
{
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

static double clamp01(double v)
{
    return fmin(fmax(v, 0.0), 1.0);
}

/* The documented compositing, computed independently of image_io.cpp. */
static void expected_pixel(const float *rgba, double exposure, const double bg[4], double out[4])
{
    double a = rgba[3];
    for (int c = 0; c < 3; c++)
        out[c] = rgba[c] * exp2(exposure) + bg[c] * (1.0 - a);
    out[3] = a + bg[3] * (1.0 - a);
}

static int same_floats(const float *a, const float *b, size_t n)
{
    return a && b && memcmp(a, b, n * sizeof(float)) == 0;
}

static double max_abs_diff(const float *a, const float *b, size_t n)
{
    double worst = 0.0;
    for (size_t i = 0; i < n; i++)
        worst = fmax(worst, fabs((double)a[i] - b[i]));
    return worst;
}

/* Encodes to memory, stores the bytes as a file and loads that file back. */
static lucent_status encode_and_load(const lucent_image *img, lucent_format format,
                                     double exposure, const double bg[4], const char *name,
                                     lucent_image *out)
{
    lucent_error err = {0};
    unsigned char *bytes = NULL;
    size_t len = 0;
    *out = (lucent_image){0};
    lucent_status st = lucent_image_encode(img, format, exposure, bg, &bytes, &len, &err);
    if (st == LUCENT_OK)
        st = write_file(tmp_path(name), bytes, len) ? LUCENT_OK : LUCENT_E_IO;
    free(bytes);
    if (st == LUCENT_OK)
        st = lucent_image_load(tmp_path(name), out, &err);
    if (st != LUCENT_OK)
        printf("     (%s: %s)\n", name, err.message);
    return st;
}

static void test_alloc(void)
{
    lucent_image img;
    lucent_error err = {0};
    check_status(lucent_image_alloc(&img, 3, 2, 1, &err), &err, "alloc 3x2");
    int zero = 1, minus_one = 1;
    for (int i = 0; i < 6; i++) {
        zero &= img.rgba[i * 4] == 0 && img.rgba[i * 4 + 3] == 0 && img.depth[i] == 0 &&
                img.normal[i * 3 + 2] == 0;
        minus_one &= img.view[i] == -1.0f;
    }
    check(img.width == 3 && img.height == 2 && zero && minus_one, "alloc zeroes, view = -1", NULL);
    lucent_image_free(&img);
    lucent_image_free(&img);
    check(!img.rgba && !img.view && img.width == 0, "free twice leaves a zeroed struct", NULL);

    lucent_status st = lucent_image_alloc(&img, 0, 5, 1, &err);
    check(st == LUCENT_E_LIMIT && !img.rgba, "alloc width 0 -> limit", "%s", err.message);
    st = lucent_image_alloc(&img, 5, LUCENT_MAX_IMAGE_SIDE + 1, 1, &err);
    check(st == LUCENT_E_LIMIT && strcmp(err.field, "height") == 0, "alloc height 4097 -> limit",
          "%s", err.message);
}

static void test_exr_round_trip(const lucent_image *src)
{
    const double clear[4] = {0, 0, 0, 0};
    lucent_image back;
    lucent_status st = encode_and_load(src, LUCENT_FORMAT_EXR, 0.0, clear, "mem.exr", &back);
    check(st == LUCENT_OK, "EXR encode to memory and load", NULL);
    if (st != LUCENT_OK)
        return;
    size_t n = (size_t)W * H;
    check(back.width == W && back.height == H, "EXR size", "%dx%d", back.width, back.height);
    check(back.depth && back.normal && back.view, "EXR has Z, N.X/N.Y/N.Z and view channels",
          NULL);
    check(same_floats(src->rgba, back.rgba, n * 4), "EXR RGBA bitwise",
          "max |error| %g (incl. 1e4 and 1e-30 pixels)", max_abs_diff(src->rgba, back.rgba, n * 4));
    if (back.depth && back.normal && back.view) {
        check(same_floats(src->depth, back.depth, n) && same_floats(src->normal, back.normal, n * 3)
                  && same_floats(src->view, back.view, n),
              "EXR AOVs bitwise", "max |error| depth %g normal %g view %g",
              max_abs_diff(src->depth, back.depth, n),
              max_abs_diff(src->normal, back.normal, n * 3), max_abs_diff(src->view, back.view, n));
    }

    lucent_error err = {0};
    st = lucent_image_write(tmp_path("file.exr"), src, LUCENT_FORMAT_EXR, 0.0, clear, &err);
    check_status(st, &err, "EXR write to file");
    lucent_image from_file;
    st = lucent_image_load(tmp_path("file.exr"), &from_file, &err);
    check(st == LUCENT_OK && same_floats(back.rgba, from_file.rgba, n * 4) &&
              same_floats(back.depth, from_file.depth, n) &&
              same_floats(back.normal, from_file.normal, n * 3) &&
              same_floats(back.view, from_file.view, n),
          "EXR file decodes identically to memory encode", NULL);
    size_t file_len = 0, mem_len = 0;
    unsigned char *file_bytes = read_file(tmp_path("file.exr"), &file_len);
    unsigned char *mem_bytes = read_file(tmp_path("mem.exr"), &mem_len);
    /* Not a check: OpenImageIO stamps EXR headers with the current second (capDate). */
    printf("     EXR file %zu bytes, memory %zu bytes, bytes identical: %s\n", file_len, mem_len,
           file_bytes && mem_bytes && file_len == mem_len &&
                   memcmp(file_bytes, mem_bytes, file_len) == 0
               ? "yes"
               : "no");
    free(file_bytes);
    free(mem_bytes);
    lucent_image_free(&from_file);
    lucent_image_free(&back);
}

static void test_exr_without_aovs(const lucent_image *src)
{
    const double clear[4] = {0, 0, 0, 0};
    lucent_image bare = {.width = W, .height = H, .rgba = src->rgba};
    lucent_image back;
    lucent_status st = encode_and_load(&bare, LUCENT_FORMAT_EXR, 0.0, clear, "bare.exr", &back);
    check(st == LUCENT_OK && !back.depth && !back.normal && !back.view &&
              same_floats(src->rgba, back.rgba, (size_t)W * H * 4),
          "EXR without AOVs loads them as NULL", NULL);
    lucent_image_free(&back);
}

/* Compares in 8-bit sRGB code values, where the only expected error is rounding (<= 0.5). */
static void compare_png(const lucent_image *src, const lucent_image *back, double exposure,
                        const double bg[4], const char *name)
{
    double worst_code = 0.0, worst_alpha = 0.0, worst_linear = 0.0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        double want[4];
        expected_pixel(src->rgba + i * 4, exposure, bg, want);
        const float *got = back->rgba + i * 4;
        worst_alpha = fmax(worst_alpha, fabs(got[3] - clamp01(want[3])) * 255.0);
        for (int c = 0; c < 3; c++) {
            double want_code = want[3] > 0 ? clamp01(srgb_encode(want[c] / want[3])) : 0.0;
            double got_code = got[3] > 0 ? clamp01(srgb_encode(got[c] / got[3])) : 0.0;
            worst_code = fmax(worst_code, fabs(got_code - want_code) * 255.0);
            if (want[3] > 0 && want[c] / want[3] <= 1.0)
                worst_linear = fmax(worst_linear, fabs(got[c] - want[c]));
        }
    }
    check(worst_code <= 1.0 && worst_alpha <= 1.0 && back->depth == NULL, name,
          "max error %.3f/255 sRGB colour, %.3f/255 alpha; max linear premultiplied %.2e",
          worst_code, worst_alpha, worst_linear);
}

static int has_srgb_chunk(const unsigned char *png, size_t len)
{
    for (size_t at = 8; at + 8 <= len;) {
        size_t n = (size_t)png[at] << 24 | (size_t)png[at + 1] << 16 | (size_t)png[at + 2] << 8 |
                   png[at + 3];
        if (memcmp(png + at + 4, "sRGB", 4) == 0)
            return 1;
        at += 12 + n;
    }
    return 0;
}

static void test_png(const lucent_image *src)
{
    const double clear[4] = {0, 0, 0, 0};
    lucent_error err = {0};
    unsigned char *bytes = NULL;
    size_t len = 0;
    lucent_status st = lucent_image_encode(src, LUCENT_FORMAT_PNG, 0.0, clear, &bytes, &len, &err);
    check_status(st, &err, "PNG encode to memory");
    if (st != LUCENT_OK)
        return;
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    check(len > 8 && memcmp(bytes, signature, 8) == 0, "PNG signature", "%zu bytes", len);
    check(has_srgb_chunk(bytes, len), "PNG tagged sRGB (sRGB chunk)", NULL);

    st = lucent_image_write(tmp_path("file.png"), src, LUCENT_FORMAT_PNG, 0.0, clear, &err);
    check_status(st, &err, "PNG write to file");
    size_t file_len = 0;
    unsigned char *file_bytes = read_file(tmp_path("file.png"), &file_len);
    check(file_bytes && file_len == len && memcmp(file_bytes, bytes, len) == 0,
          "PNG file bytes identical to memory encode", NULL);
    free(file_bytes);
    free(bytes);

    lucent_image back;
    st = lucent_image_load(tmp_path("file.png"), &back, &err);
    check_status(st, &err, "PNG load");
    if (st == LUCENT_OK)
        compare_png(src, &back, 0.0, clear, "PNG round trip, transparent background");
    lucent_image_free(&back);
}

static void test_background(const lucent_image *src)
{
    const double bg[4] = {0.2, 0.4, 0.6, 1.0};
    lucent_image back;
    if (encode_and_load(src, LUCENT_FORMAT_EXR, 0.0, bg, "bg.exr", &back) != LUCENT_OK) {
        check(0, "EXR over opaque background", "encode or load failed");
        return;
    }
    double worst = 0.0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        double want[4];
        expected_pixel(src->rgba + i * 4, 0.0, bg, want);
        for (int c = 0; c < 4; c++)
            worst = fmax(worst, fabs(back.rgba[i * 4 + c] - want[c]) / fmax(1.0, fabs(want[c])));
    }
    const float *corner = back.rgba;
    check(worst <= 1e-7 && corner[0] == 0.2f && corner[3] == 1.0f, "EXR over opaque background",
          "max relative error %.2e; uncovered corner = (%g %g %g %g)", worst, corner[0], corner[1],
          corner[2], corner[3]);
    lucent_image_free(&back);

    if (encode_and_load(src, LUCENT_FORMAT_PNG, 0.0, bg, "bg.png", &back) == LUCENT_OK)
        compare_png(src, &back, 0.0, bg, "PNG over opaque background");
    else
        check(0, "PNG over opaque background", "encode or load failed");
    lucent_image_free(&back);

    const double half[4] = {0.5, 0.25, 0.0, 0.5};
    if (encode_and_load(src, LUCENT_FORMAT_PNG, 0.0, half, "half.png", &back) == LUCENT_OK)
        compare_png(src, &back, 0.0, half, "PNG over half-transparent background");
    else
        check(0, "PNG over half-transparent background", "encode or load failed");
    lucent_image_free(&back);
}

static void test_exposure(const lucent_image *src)
{
    const double clear[4] = {0, 0, 0, 0};
    lucent_image back;
    if (encode_and_load(src, LUCENT_FORMAT_EXR, 1.0, clear, "exposed.exr", &back) != LUCENT_OK) {
        check(0, "exposure +1 doubles radiance", "encode or load failed");
        return;
    }
    int exact = 1;
    for (size_t i = 0; i < (size_t)W * H * 4; i++)
        exact &= back.rgba[i] == (i % 4 == 3 ? src->rgba[i] : 2.0f * src->rgba[i]);
    check(exact, "exposure +1 doubles radiance exactly, alpha unchanged", NULL);
    lucent_image_free(&back);
}

static void test_non_finite(void)
{
    lucent_image img;
    lucent_error err = {0};
    if (lucent_image_alloc(&img, 2, 1, 1, &err) != LUCENT_OK) {
        check(0, "non-finite input", "%s", err.message);
        return;
    }
    const float bad[8] = {NAN, INFINITY, -INFINITY, 1.0f, 0.5f, 0.5f, 0.5f, NAN};
    memcpy(img.rgba, bad, sizeof bad);
    const double clear[4] = {0, 0, 0, 0};
    lucent_image back;
    lucent_status st = encode_and_load(&img, LUCENT_FORMAT_EXR, 0.0, clear, "nan.exr", &back);
    check(st == LUCENT_OK && isnan(back.rgba[0]) && back.rgba[1] == INFINITY &&
              back.rgba[2] == -INFINITY && isnan(back.rgba[7]),
          "EXR keeps NaN and +-Inf as they are", NULL);
    lucent_image_free(&back);
    st = encode_and_load(&img, LUCENT_FORMAT_PNG, 0.0, clear, "nan.png", &back);
    check(st == LUCENT_OK && back.rgba[0] == 0 && back.rgba[1] == 0 && back.rgba[3] == 1.0f &&
              back.rgba[7] == 0,
          "PNG writes non-finite values as 0", st == LUCENT_OK ? "pixel 0 = (%g %g %g %g)" : NULL,
          back.rgba ? back.rgba[0] : 0, back.rgba ? back.rgba[1] : 0,
          back.rgba ? back.rgba[2] : 0, back.rgba ? back.rgba[3] : 0);
    lucent_image_free(&back);
    lucent_image_free(&img);
}

static void test_errors(const lucent_image *src)
{
    const double clear[4] = {0, 0, 0, 0};
    lucent_error err = {0};
    const char *unwritable = "/nonexistent-lucent-dir/out.png";
    lucent_status st = lucent_image_write(unwritable, src, LUCENT_FORMAT_PNG, 0.0, clear, &err);
    check(st == LUCENT_E_IO && strstr(err.message, unwritable), "unwritable path -> io", "%s",
          err.message);

    lucent_image back;
    st = lucent_image_load(tmp_path("missing.exr"), &back, &err);
    check(st == LUCENT_E_IO && strstr(err.message, "missing.exr") && !back.rgba,
          "missing file -> io", "%s", err.message);

    write_file(tmp_path("garbage.png"), (const unsigned char *)"not an image", 12);
    st = lucent_image_load(tmp_path("garbage.png"), &back, &err);
    check(st == LUCENT_E_IO && !back.rgba, "garbage file -> io", "%s", err.message);

    unsigned char *bytes = NULL;
    size_t len = 0;
    st = lucent_image_encode(src, LUCENT_FORMAT_EXR, 100.0, clear, &bytes, &len, &err);
    check(st == LUCENT_E_LIMIT && !bytes && strcmp(err.field, "exposure") == 0,
          "exposure 100 -> limit", "%s", err.message);
    st = lucent_image_encode(src, LUCENT_FORMAT_PNG, 0.0, NULL, &bytes, &len, &err);
    check(st == LUCENT_E_INVALID && !bytes, "NULL background -> invalid", "%s", err.message);
}

static void remove_tmpdir(void)
{
    static const char *names[] = {"mem.exr", "file.exr", "bare.exr", "file.png", "bg.exr",
                                  "bg.png",  "half.png", "exposed.exr", "nan.exr", "nan.png",
                                  "garbage.png"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        remove(tmp_path(names[i]));
    rmdir(tmpdir);
}

int main(void)
{
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    test_alloc();

    lucent_image src;
    lucent_error err = {0};
    if (lucent_image_alloc(&src, W, H, 1, &err) != LUCENT_OK) {
        printf("FAIL alloc %dx%d: %s\n", W, H, err.message);
        return 1;
    }
    fill_synthetic(&src);
    test_exr_round_trip(&src);
    test_exr_without_aovs(&src);
    test_png(&src);
    test_background(&src);
    test_exposure(&src);
    test_non_finite();
    test_errors(&src);
    lucent_image_free(&src);
    remove_tmpdir();

    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
