/* image_compare.c - how far an image is from a reference: the error measures of the speed/accuracy
 * trade, over the whole object and over the silhouette band where a single projection image fails,
 * and the error split into speckle (high-pass), mottle (blotches a few pixels wide), low frequencies and energy
 * (mean ratio). */
#include "json_text.h"
#include "lucent.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* cos(70 degrees): normals beyond it are in the silhouette band. */
#define BAND_COS 0.3420201433

struct accumulator {
    double diff2, ref2, abs_sum, abs_max;
    int values, pixels, over_10pct;
    double *rel;     /* per-pixel relative errors, for the percentile */
};

static int covered(const lucent_image *img, size_t i)
{
    return img->rgba[i * 4 + 3] > 0.0f;
}

static void add_pixel(struct accumulator *a, const float *t, const float *r, double floor)
{
    double d2 = 0.0, r2 = 0.0;
    for (int c = 0; c < 3; c++) {
        double d = (double)t[c] - r[c];
        d2 += d * d;
        r2 += (double)r[c] * r[c];
        a->abs_sum += fabs(d);
        a->abs_max = fmax(a->abs_max, fabs(d));
    }
    a->diff2 += d2;
    a->ref2 += r2;
    a->values += 3;
    double rel = sqrt(d2) / fmax(sqrt(r2), floor);
    a->over_10pct += rel > 0.1;
    a->rel[a->pixels++] = rel;
}

static int compare_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* A norm of differences over a reference norm; the absolute norm where the reference is black. */
static double relative(double diff2, double ref2)
{
    return ref2 > 0.0 ? sqrt(diff2 / ref2) : sqrt(diff2);
}

static void finish(struct accumulator *a, lucent_error_measures *m)
{
    *m = (lucent_error_measures){.pixels = a->pixels};
    if (a->pixels == 0)
        return;
    qsort(a->rel, (size_t)a->pixels, sizeof *a->rel, compare_double);
    m->rel_l2 = relative(a->diff2, a->ref2);
    m->mean_abs = a->abs_sum / a->values;
    m->max_abs = a->abs_max;
    m->p99_rel = a->rel[(size_t)floor(0.99 * (a->pixels - 1))];
    m->share_over_10pct = (double)a->over_10pct / a->pixels;
}

/* Mean reference radiance magnitude over covered pixels, for the relative-error floor. */
static double mean_reference(const lucent_image *ref, size_t pixels)
{
    double sum = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < pixels; i++)
        if (covered(ref, i)) {
            const float *r = &ref->rgba[i * 4];
            sum += sqrt((double)r[0] * r[0] + (double)r[1] * r[1] + (double)r[2] * r[2]);
            n++;
        }
    return n ? sum / n : 0.0;
}

/* Mean of channel c over the (2 * r + 1)^2 box centred on (x, y); the box lies inside the image. */
static double box_mean(const lucent_image *img, int x, int y, int c, int r)
{
    double sum = 0.0;
    for (int v = y - r; v <= y + r; v++)
        for (int u = x - r; u <= x + r; u++)
            sum += img->rgba[((size_t)v * img->width + u) * 4 + c];
    return sum / ((2 * r + 1) * (2 * r + 1));
}

/* Whether the 5x5 neighbourhood of (x, y) lies in the image and is covered in both images, so both
 * box filters below see only object pixels (a silhouette is not an error of either method). */
static int interior(const lucent_image *test, const lucent_image *ref, int x, int y)
{
    if (x < 2 || y < 2 || x >= ref->width - 2 || y >= ref->height - 2)
        return 0;
    for (int v = y - 2; v <= y + 2; v++)
        for (int u = x - 2; u <= x + 2; u++) {
            size_t i = (size_t)v * ref->width + u;
            if (!covered(test, i) || !covered(ref, i))
                return 0;
        }
    return 1;
}

struct frequency_sums {
    double high_diff2, ref2, low_diff2, low_ref2;
    int pixels;
};

/* hp(x) = x - box3x3(x) is what a viewer sees as speckle; box5x5 keeps what survives a small blur. */
static void add_frequencies(struct frequency_sums *f, const lucent_image *test, const lucent_image *ref, int x, int y)
{
    size_t i = ((size_t)y * ref->width + x) * 4;
    for (int c = 0; c < 3; c++) {
        double t = test->rgba[i + c], r = ref->rgba[i + c];
        double high = (t - box_mean(test, x, y, c, 1)) - (r - box_mean(ref, x, y, c, 1));
        double low_t = box_mean(test, x, y, c, 2), low_r = box_mean(ref, x, y, c, 2);
        f->high_diff2 += high * high;
        f->ref2 += r * r;
        f->low_diff2 += (low_t - low_r) * (low_t - low_r);
        f->low_ref2 += low_r * low_r;
    }
    f->pixels++;
}

static void compare_frequencies(const lucent_image *test, const lucent_image *ref, lucent_image_error *out)
{
    struct frequency_sums f = {0};
    for (int y = 0; y < ref->height; y++)
        for (int x = 0; x < ref->width; x++)
            if (interior(test, ref, x, y))
                add_frequencies(&f, test, ref, x, y);
    out->interior_pixels = f.pixels;
    out->noise = relative(f.high_diff2, f.ref2);
    out->low_frequency_rel_l2 = relative(f.low_diff2, f.low_ref2);
}

/* Mottle: the band between a 3x3 and a 25x25 box, blotches up to three far blocks of 4 pixels across, which
 * the 3x3 high-pass of noise hardly sees. The band is linear, so it is taken of test - ref at once; its box
 * means come from one summed-area table per channel. */
#define MOTTLE_RADIUS 12
enum { SAT_COVERED = 3, SAT_VALUES = 4 };

/* (w + 1) x (h + 1) entries of SAT_VALUES sums over [0, x) x [0, y): test - ref in R, G, B, and pixels covered
 * in both; NULL when out of memory. */
static double *summed_areas(const lucent_image *test, const lucent_image *ref)
{
    size_t row = (size_t)ref->width + 1;
    double *t = calloc(row * ((size_t)ref->height + 1) * SAT_VALUES, sizeof *t);
    if (!t)
        return NULL;
    for (int y = 0; y < ref->height; y++)
        for (int x = 0; x < ref->width; x++) {
            size_t i = (size_t)y * ref->width + x;
            double *at = &t[((y + 1) * row + x + 1) * SAT_VALUES], *up = at - row * SAT_VALUES;
            double value[SAT_VALUES] = {(double)test->rgba[i * 4] - ref->rgba[i * 4],
                                        (double)test->rgba[i * 4 + 1] - ref->rgba[i * 4 + 1],
                                        (double)test->rgba[i * 4 + 2] - ref->rgba[i * 4 + 2],
                                        covered(test, i) && covered(ref, i)};
            for (int k = 0; k < SAT_VALUES; k++)
                at[k] = value[k] + up[k] + at[k - SAT_VALUES] - up[k - SAT_VALUES];
        }
    return t;
}

/* Mean of value k over the (2 r + 1)^2 box centred on (x, y), which lies inside the image. */
static double sat_mean(const double *t, int width, int k, int x, int y, int r)
{
    size_t row = (size_t)width + 1, x0 = (size_t)(x - r), x1 = (size_t)(x + r + 1);
    size_t y0 = (size_t)(y - r), y1 = (size_t)(y + r + 1);
    double sum = t[(y1 * row + x1) * SAT_VALUES + k] - t[(y0 * row + x1) * SAT_VALUES + k] -
                 t[(y1 * row + x0) * SAT_VALUES + k] + t[(y0 * row + x0) * SAT_VALUES + k];
    return sum / ((2 * r + 1) * (2 * r + 1));
}

/* ||bp(test - ref)|| / ||ref||, bp(x) = box3x3(x) - box25x25(x), over the pixels whose 25x25 neighbourhood is
 * covered in both images; NaN where none is. */
static lucent_status compare_mottle(const lucent_image *test, const lucent_image *ref, lucent_image_error *out,
                                    lucent_error *err)
{
    const int r = MOTTLE_RADIUS, w = ref->width;
    double *t = summed_areas(test, ref), diff2 = 0.0, ref2 = 0.0;
    if (!t)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory comparing images");
    out->mottle_pixels = 0;
    for (int y = r; y < ref->height - r; y++)
        for (int x = r; x < w - r; x++) {
            if (sat_mean(t, w, SAT_COVERED, x, y, r) < 1.0 - 1e-9)
                continue;
            size_t i = ((size_t)y * w + x) * 4;
            for (int c = 0; c < 3; c++) {
                double band = sat_mean(t, w, c, x, y, 1) - sat_mean(t, w, c, x, y, r);
                diff2 += band * band;
                ref2 += (double)ref->rgba[i + c] * ref->rgba[i + c];
            }
            out->mottle_pixels++;
        }
    free(t);
    out->mottle = out->mottle_pixels ? relative(diff2, ref2) : NAN;
    return LUCENT_OK;
}

/* Summed RGB of test over that of the reference, over the pixels covered in both: 1 when the energy
 * matches; 0 when the reference is black there. */
static double mean_ratio(const lucent_image *test, const lucent_image *ref, size_t pixels)
{
    double t = 0.0, r = 0.0;
    for (size_t i = 0; i < pixels; i++)
        if (covered(test, i) && covered(ref, i))
            for (int c = 0; c < 3; c++) {
                t += test->rgba[i * 4 + c];
                r += ref->rgba[i * 4 + c];
            }
    return r > 0.0 ? t / r : 0.0;
}

static int same_size(const lucent_image *x, const lucent_image *y)
{
    return x->rgba && y->rgba && x->width == y->width && x->height == y->height;
}

lucent_status lucent_image_compare(const lucent_image *test, const lucent_image *ref, lucent_image_error *out,
                                   lucent_error *err)
{
    memset(out, 0, sizeof *out);
    if (!same_size(test, ref))
        return lucent_fail(err, LUCENT_E_INVALID, "compare", "images differ in size (%dx%d vs reference %dx%d)",
                           test->width, test->height, ref->width, ref->height);
    size_t pixels = (size_t)test->width * test->height;
    struct accumulator all = {0}, band = {0};
    all.rel = malloc(pixels * sizeof *all.rel);
    band.rel = malloc(pixels * sizeof *band.rel);
    if (!all.rel || !band.rel) {
        free(all.rel);
        free(band.rel);
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory comparing images");
    }
    double floor = 1e-3 * mean_reference(ref, pixels);
    for (size_t i = 0; i < pixels; i++) {
        int in_test = covered(test, i), in_ref = covered(ref, i);
        out->coverage_mismatch += in_test != in_ref;
        if (!in_test || !in_ref)
            continue;
        add_pixel(&all, &test->rgba[i * 4], &ref->rgba[i * 4], floor);
        if (ref->facing && fabsf(ref->facing[i]) < BAND_COS)
            add_pixel(&band, &test->rgba[i * 4], &ref->rgba[i * 4], floor);
    }
    finish(&all, &out->object);
    finish(&band, &out->band);
    free(all.rel);
    free(band.rel);
    compare_frequencies(test, ref, out);
    out->mean_ratio = mean_ratio(test, ref, pixels);
    return compare_mottle(test, ref, out, err);
}

/* Pixel (x, y) joins subset (x % 8, y % 8): each is a lattice over the whole image and neighbours see
 * nearly the same truth, so the subsets' sums differ mostly by noise and their spread estimates the whole
 * sum's standard error (whole columns would differ by what the image shows). */
enum { NOISY_LATTICE = 8, NOISY_SUBSETS = NOISY_LATTICE * NOISY_LATTICE };

static double noisy_sqrt_ratio(double sum, double truth2)
{
    return sqrt(fmax(sum, 0.0) / truth2);
}

lucent_status lucent_image_compare_noisy_pair(const lucent_image *t1, const lucent_image *t2, const lucent_image *a,
                                              const lucent_image *b, lucent_noisy_error *out, lucent_error *err)
{
    out->rel_l2 = out->rel_l2_low = out->rel_l2_high = out->noise = out->test_noise = NAN;
    if (!same_size(a, b) || !t1 != !t2 || (t1 && (!same_size(t1, a) || !same_size(t2, a))))
        return lucent_fail(err, LUCENT_E_INVALID, "compare", "images differ in size or are missing");
    double cross[NOISY_SUBSETS] = {0}, truth2 = 0.0, half_diff2 = 0.0, test_half_diff2 = 0.0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
        if (!covered(a, i) || !covered(b, i) || (t1 && (!covered(t1, i) || !covered(t2, i))))
            continue;
        size_t px = i % (size_t)a->width, py = i / (size_t)a->width;
        double *subset = &cross[px % NOISY_LATTICE + NOISY_LATTICE * (py % NOISY_LATTICE)];
        for (int c = 0; c < 3; c++) {
            double x = a->rgba[i * 4 + c], y = b->rgba[i * 4 + c];
            double s = t1 ? t1->rgba[i * 4 + c] : 0.0, t = t2 ? t2->rgba[i * 4 + c] : 0.0;
            /* Both pairings: each has the squared difference as its expectation; their mean varies less. */
            *subset += 0.5 * ((s - x) * (t - y) + (t - x) * (s - y));
            truth2 += x * y;
            half_diff2 += 0.25 * (x - y) * (x - y);
            test_half_diff2 += 0.25 * (s - t) * (s - t);
        }
    }
    if (truth2 <= 0.0)
        return LUCENT_OK;
    out->noise = sqrt(half_diff2 / truth2);
    if (!t1)
        return LUCENT_OK;
    out->test_noise = sqrt(test_half_diff2 / truth2);
    double sum = 0.0, spread = 0.0;
    for (int k = 0; k < NOISY_SUBSETS; k++)
        sum += cross[k];
    for (int k = 0; k < NOISY_SUBSETS; k++)
        spread += (cross[k] - sum / NOISY_SUBSETS) * (cross[k] - sum / NOISY_SUBSETS);
    double standard_error = sqrt(spread * NOISY_SUBSETS / (NOISY_SUBSETS - 1));
    out->rel_l2 = noisy_sqrt_ratio(sum, truth2);
    out->rel_l2_low = noisy_sqrt_ratio(sum - 2.0 * standard_error, truth2);
    out->rel_l2_high = noisy_sqrt_ratio(sum + 2.0 * standard_error, truth2);
    return LUCENT_OK;
}

lucent_status lucent_image_compare_noisy(const lucent_image *test, const lucent_image *a, const lucent_image *b,
                                         lucent_noisy_error *out, lucent_error *err)
{
    return lucent_image_compare_noisy_pair(test, test, a, b, out, err);
}

lucent_status lucent_image_average(lucent_image *into, const lucent_image *other, lucent_error *err)
{
    if (!same_size(into, other))
        return lucent_fail(err, LUCENT_E_INVALID, "average", "images differ in size or are missing");
    for (size_t i = 0; i < (size_t)into->width * into->height * 4; i++)
        if (i % 4 != 3)
            into->rgba[i] = 0.5f * (into->rgba[i] + other->rgba[i]);
    return LUCENT_OK;
}

/* The measures' JSON members, without braces (null where a measure is not finite). */
static int measures_json(const lucent_error_measures *m, char *buf, size_t cap)
{
    char v[5][32];
    const double x[5] = {m->rel_l2, m->mean_abs, m->max_abs, m->p99_rel, m->share_over_10pct};
    for (int i = 0; i < 5; i++)
        json_number(x[i], v[i], sizeof v[i]);
    return snprintf(buf, cap, "\"pixels\":%d,\"rel_l2\":%s,\"mean_abs\":%s,\"max_abs\":%s,\"p99_rel\":%s,"
                              "\"share_over_10pct\":%s",
                    m->pixels, v[0], v[1], v[2], v[3], v[4]);
}

int lucent_image_error_json(const lucent_image_error *e, char *buf, size_t cap)
{
    char object[256], band[256], mean_ratio[32], noise[32], low[32], mottle[32];
    measures_json(&e->object, object, sizeof object);
    measures_json(&e->band, band, sizeof band);
    json_number(e->mean_ratio, mean_ratio, sizeof mean_ratio);
    json_number(e->noise, noise, sizeof noise);
    json_number(e->low_frequency_rel_l2, low, sizeof low);
    json_number(e->mottle, mottle, sizeof mottle);
    int n = snprintf(buf, cap,
                     "{%s,\"coverage_mismatch\":%d,\"mean_ratio\":%s,\"interior_pixels\":%d,\"noise\":%s,"
                     "\"low_frequency_rel_l2\":%s,\"mottle_pixels\":%d,\"mottle\":%s,\"silhouette_band\":{%s}}",
                     object, e->coverage_mismatch, mean_ratio, e->interior_pixels, noise, low, e->mottle_pixels, mottle,
                     band);
    return n < 0 || (size_t)n >= cap ? -1 : n;
}
