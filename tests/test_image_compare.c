/* test_image_compare.c - the error measures on images whose error is known by construction: equal
 * images, a uniform 20% gain, an error confined to the silhouette band, coverage differences; and the
 * frequency split (noise, low frequencies, mean ratio) on a smooth quadratic image, whose box means
 * are known in closed form, perturbed by a gain, a checkerboard and a linear ramp; mottle (the 3x3 to 25x25
 * band) against box means summed pixel by pixel, on fine and coarse checkerboards; and the error against
 * a truth seen only through two noisy estimates of it, with the spread of that estimate checked over
 * many draws of the noise. */
#include "json_text.h"
#include "test_support.h"

#include <jansson.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 40
#define H 30

/* A width x height image with AOVs, zeroed; the run ends here if it cannot be made, since no check could run. */
static void alloc_sized(lucent_image *img, int width, int height)
{
    lucent_error err = {0};
    if (lucent_image_alloc(img, width, height, 1, &err) != LUCENT_OK) {
        printf("FAIL alloc: %s\n", err.message);
        exit(1);
    }
}

static void alloc_image(lucent_image *img)
{
    alloc_sized(img, W, H);
}

/* A covered disc of radiance (1, 0.5, 0.25); facing falls to 0 at the rim, so the outer ring is
 * the silhouette band. */
static void make_reference(lucent_image *img)
{
    alloc_image(img);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double dx = (x + 0.5 - W / 2.0) / 14.0, dy = (y + 0.5 - H / 2.0) / 14.0, d2 = dx * dx + dy * dy;
            size_t i = (size_t)y * W + x;
            if (d2 >= 1.0)
                continue;
            float *p = &img->rgba[i * 4];
            p[0] = 1.0f, p[1] = 0.5f, p[2] = 0.25f, p[3] = 1.0f;
            img->facing[i] = (float)sqrt(1.0 - d2);
            img->view[i] = 0.0f;
        }
}

static void copy_image(const lucent_image *src, lucent_image *dst)
{
    alloc_image(dst);
    for (int i = 0; i < src->width * src->height; i++) {
        for (int c = 0; c < 4; c++)
            dst->rgba[i * 4 + c] = src->rgba[i * 4 + c];
        dst->facing[i] = src->facing[i];
    }
}

/* The smooth image: covered on the rectangle [X0, X1) x [Y0, Y1), channel c = A[c] + B q(x, y) with
 * q = (x - W/2)^2 + (y - H/2)^2. Over a box of half-width r, the mean of (x - W/2)^2 is itself plus
 * 2/3 (r = 1) or 2 (r = 2), so box3x3(image) = image + 4B/3 and box5x5(image) = image + 4B. */
#define X0 3
#define X1 37
#define Y0 4
#define Y1 26
#define B 0.002
static const double A[3] = {0.6, 0.3, 0.15};
/* Pixels whose 5x5 neighbourhood lies in the rectangle. */
#define INTERIOR ((X1 - X0 - 4) * (Y1 - Y0 - 4))
/* RGB values on the rectangle. */
#define RECTANGLE_VALUES ((X1 - X0) * (Y1 - Y0) * 3)

static double smooth_value(int c, int x, int y)
{
    double dx = x - W / 2, dy = y - H / 2;
    return A[c] + B * (dx * dx + dy * dy);
}

static int in_rectangle(int x, int y)
{
    return x >= X0 && x < X1 && y >= Y0 && y < Y1;
}

static int in_interior(int x, int y)
{
    return x >= X0 + 2 && x < X1 - 2 && y >= Y0 + 2 && y < Y1 - 2;
}

static void make_smooth(lucent_image *img)
{
    alloc_image(img);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if (in_rectangle(x, y)) {
                float *p = &img->rgba[((size_t)y * W + x) * 4];
                for (int c = 0; c < 3; c++)
                    p[c] = (float)smooth_value(c, x, y);
                p[3] = 1.0f;
            }
}

/* test = ref + amount(x, y) on every covered pixel and channel. */
static void perturb(const lucent_image *ref, lucent_image *test, double (*amount)(int x, int y))
{
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3 && in_rectangle(x, y); c++) {
                size_t i = ((size_t)y * W + x) * 4 + c;
                test->rgba[i] = (float)(ref->rgba[i] + amount(x, y));
            }
}

#define CHECKER 0.01
#define RAMP 0.005
static double checker(int x, int y)
{
    return (x + y) % 2 ? -CHECKER : CHECKER;
}

static double ramp(int x, int y)
{
    (void)y;
    return RAMP * (x - X0);
}

/* Closed-form sums over the interior: ||ref||^2, ||box5x5(ref)||^2 and ||ramp||^2, over RGB. */
struct interior_sums {
    double ref2, low_ref2, ramp2;
};

static struct interior_sums interior_sums(void)
{
    struct interior_sums s = {0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3 && in_interior(x, y); c++) {
                double f = smooth_value(c, x, y);
                s.ref2 += f * f;
                s.low_ref2 += (f + 4 * B) * (f + 4 * B);
                s.ramp2 += ramp(x, y) * ramp(x, y);
            }
    return s;
}

static int near(double measured, double expected, double rel_tol)
{
    return fabs(measured - expected) <= rel_tol * fabs(expected);
}

static void check_frequencies(void)
{
    lucent_image ref, test;
    lucent_image_error e;
    lucent_error err = {0};
    make_smooth(&ref);
    copy_image(&ref, &test);
    const struct interior_sums s = interior_sums();
    const double n3 = 3.0 * INTERIOR;

    lucent_image_compare(&test, &ref, &e, &err);
    test_check(e.interior_pixels == INTERIOR && e.noise == 0.0 && e.low_frequency_rel_l2 == 0.0 && e.mean_ratio == 1.0,
               "smooth, identical: %d interior pixels (expected %d), noise %g, low-frequency %g (both expected 0), "
               "mean ratio %g (expected 1)",
               e.interior_pixels, INTERIOR, e.noise, e.low_frequency_rel_l2, e.mean_ratio);

    /* hp(1.2 ref) - hp(ref) = 0.2 hp(ref) = -0.2 * 4B/3 in every channel of every interior pixel. */
    for (int i = 0; i < W * H * 4; i++)
        if (i % 4 != 3)
            test.rgba[i] = ref.rgba[i] * 1.2f;
    lucent_image_compare(&test, &ref, &e, &err);
    double noise = 0.2 * (4 * B / 3) * sqrt(n3 / s.ref2);
    test_check(near(e.mean_ratio, 1.2, 1e-6) && near(e.low_frequency_rel_l2, 0.2, 1e-6) && near(e.noise, noise, 1e-3),
               "smooth, 20%% gain: mean ratio %.7f (1.2 +-1e-6 rel), low-frequency %.7f (0.2 +-1e-6 rel), noise %.6g "
               "(%.6g = 0.2 ||hp(ref)|| / ||ref||, +-1e-3 rel)",
               e.mean_ratio, e.low_frequency_rel_l2, e.noise, noise);

    /* A checkerboard's 3x3 box mean is 1/9 of it and its 5x5 one 1/25 (one cell more of the centre's sign). */
    perturb(&ref, &test, checker);
    lucent_image_compare(&test, &ref, &e, &err);
    noise = 8.0 / 9.0 * CHECKER * sqrt(n3 / s.ref2);
    double low = CHECKER / 25.0 * sqrt(n3 / s.low_ref2);
    test_check(near(e.noise, noise, 1e-3) && near(e.low_frequency_rel_l2, low, 1e-3) && near(e.mean_ratio, 1.0, 1e-6),
               "checkerboard +-%g: noise %.6g (%.6g +-1e-3 rel), low-frequency %.6g (%.6g, 1/22 of the noise, "
               "+-1e-3 rel), mean ratio %.7f (1 +-1e-6: it cancels over the even rectangle)",
               CHECKER, e.noise, noise, e.low_frequency_rel_l2, low, e.mean_ratio);

    /* A linear ramp passes both box filters unchanged: no high-pass part at all. */
    perturb(&ref, &test, ramp);
    lucent_image_compare(&test, &ref, &e, &err);
    low = sqrt(s.ramp2 / s.low_ref2);
    test_check(e.noise < 1e-5 && near(e.low_frequency_rel_l2, low, 1e-3) && e.mean_ratio > 1.05,
               "ramp %g a pixel: noise %.3g (< 1e-5), low-frequency %.6g (%.6g +-1e-3 rel), mean ratio %.4f (> 1.05)",
               RAMP, e.noise, e.low_frequency_rel_l2, low, e.mean_ratio);

    /* Radiance behind uncovered pixels must not leak into any box: a pixel uncovered in the test only
     * takes its 5x5 neighbourhood out of the interior; one covered in the test only counts nowhere. */
    lucent_image_free(&test);
    copy_image(&ref, &test);
    size_t centre = (size_t)(H / 2) * W + W / 2;
    test.rgba[centre * 4 + 3] = 0.0f;
    for (size_t i = 0; i < (size_t)W * H; i++)
        if (test.rgba[i * 4 + 3] == 0.0f)
            test.rgba[i * 4] = 100.0f;
    test.rgba[(W + 1) * 4 + 3] = 1.0f;
    lucent_image_compare(&test, &ref, &e, &err);
    test_check(e.interior_pixels == INTERIOR - 25 && e.noise == 0.0 && e.low_frequency_rel_l2 == 0.0 &&
                   e.mean_ratio == 1.0,
               "radiance 100 behind uncovered pixels, centre uncovered and (1,1) covered in the test only: %d "
               "interior pixels (expected %d), noise %g, low-frequency %g (expected 0), mean ratio %g (expected 1)",
               e.interior_pixels, INTERIOR - 25, e.noise, e.low_frequency_rel_l2, e.mean_ratio);
    lucent_image_free(&test);
    lucent_image_free(&ref);
}

/* Mottle's image: M x M, covered, channel c = A[c]; MOTTLE_R is the 25x25 box's half-width. */
#define M 64
#define MOTTLE_R 12
#define MOTTLE_INTERIOR ((M - 2 * MOTTLE_R) * (M - 2 * MOTTLE_R))

static void make_flat(lucent_image *img, double (*amount)(int x, int y))
{
    alloc_sized(img, M, M);
    for (int i = 0; i < M * M; i++) {
        for (int c = 0; c < 3; c++)
            img->rgba[i * 4 + c] = (float)(A[c] + (amount ? amount(i % M, i / M) : 0.0));
        img->rgba[i * 4 + 3] = 1.0f;
    }
}

/* Blotches: cells of 6 x 6 pixels, +-CHECKER. */
static double blotches(int x, int y)
{
    return (x / 6 + y / 6) % 2 ? -CHECKER : CHECKER;
}

/* What mottle should be for test = ref + amount: box means summed pixel by pixel (the ref's band is 0). */
static double mottle_by_sums(double (*amount)(int x, int y))
{
    double diff2 = 0.0, ref2 = 0.0;
    for (int y = MOTTLE_R; y < M - MOTTLE_R; y++)
        for (int x = MOTTLE_R; x < M - MOTTLE_R; x++) {
            double small = 0.0, large = 0.0;
            for (int v = -MOTTLE_R; v <= MOTTLE_R; v++)
                for (int u = -MOTTLE_R; u <= MOTTLE_R; u++) {
                    large += amount(x + u, y + v);
                    small += abs(u) <= 1 && abs(v) <= 1 ? amount(x + u, y + v) : 0.0;
                }
            double band = small / 9.0 - large / ((2 * MOTTLE_R + 1) * (2 * MOTTLE_R + 1));
            for (int c = 0; c < 3; c++) {
                diff2 += band * band;
                ref2 += A[c] * A[c];
            }
        }
    return sqrt(diff2 / ref2);
}

static void check_mottle(void)
{
    lucent_image ref, test;
    lucent_image_error e;
    lucent_error err = {0};
    make_flat(&ref, NULL);
    make_flat(&test, NULL);
    lucent_image_compare(&test, &ref, &e, &err);
    test_check(e.mottle_pixels == MOTTLE_INTERIOR && e.mottle == 0.0,
               "mottle, identical: %d pixels (expected %d), mottle %g (expected 0)", e.mottle_pixels, MOTTLE_INTERIOR,
               e.mottle);

    /* A pixel checkerboard is speckle: its 3x3 mean is 1/9 of it, its 25x25 one 1/625. */
    lucent_image_free(&test);
    make_flat(&test, checker);
    lucent_image_compare(&test, &ref, &e, &err);
    double want = mottle_by_sums(checker), speckle_mottle = e.mottle, speckle_noise = e.noise;
    test_check(near(e.mottle, want, 1e-6) && e.mottle < 0.15 * e.noise,
               "mottle of a pixel checkerboard +-%g: %.6g (summed %.6g, +-1e-6 rel), below 0.15 of its noise %.4g",
               CHECKER, e.mottle, want, e.noise);

    /* Blotches 6 pixels wide, as strong: mottle sees them, noise's 3x3 high-pass only along their edges. */
    lucent_image_free(&test);
    make_flat(&test, blotches);
    lucent_image_compare(&test, &ref, &e, &err);
    want = mottle_by_sums(blotches);
    test_check(near(e.mottle, want, 1e-6) && e.mottle > 5.0 * speckle_mottle && e.noise < speckle_noise,
               "mottle of 6-pixel blotches +-%g: %.6g (summed %.6g, +-1e-6 rel), over 5x the checkerboard's; their "
               "noise %.4g below its %.4g",
               CHECKER, e.mottle, want, e.noise, speckle_noise);

    /* Both boxes keep a linear ramp; an uncovered pixel takes its 25x25 neighbourhood out, and the radiance
     * behind it leaks into no box. */
    lucent_image_free(&test);
    make_flat(&test, ramp);
    size_t centre = (size_t)(M / 2) * M + M / 2;
    test.rgba[centre * 4 + 3] = 0.0f;
    test.rgba[centre * 4] = 100.0f;
    lucent_image_compare(&test, &ref, &e, &err);
    int left = MOTTLE_INTERIOR - (2 * MOTTLE_R + 1) * (2 * MOTTLE_R + 1);
    test_check(e.mottle_pixels == left && e.mottle < 1e-6,
               "mottle of a ramp with its centre uncovered (radiance 100 behind it): %d pixels (expected %d), "
               "mottle %.3g (< 1e-6)",
               e.mottle_pixels, left, e.mottle);
    lucent_image_free(&test);
    lucent_image_free(&ref);
}

/* Uniform in [-1, 1), from a fixed LCG: the same noise every run. */
static double noise_unit(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (*state >> 8) / 8388608.0 - 1.0;
}

/* a and b: two independent estimates of truth, each pixel and channel times (1 + amplitude u), u uniform
 * in [-1, 1) (relative noise amplitude/sqrt(3) each). */
static void noisy_estimates(const lucent_image *truth, lucent_image *a, lucent_image *b, double amplitude,
                            unsigned *state)
{
    for (int k = 0; k < W * H * 4; k++)
        if (k % 4 != 3) {
            a->rgba[k] = (float)(truth->rgba[k] * (1.0 + amplitude * noise_unit(state)));
            b->rgba[k] = (float)(truth->rgba[k] * (1.0 + amplitude * noise_unit(state)));
        }
}

/* Amplitude 0.3: the mean of a and b has relative noise 0.3/sqrt(6) = 0.122, and the test is the truth
 * times 1.1 (error 0.1). rel_l2 against the mean reads about sqrt(0.1^2 + 0.122^2); compare_noisy
 * should give 0.1 within its own spread over these 2244 values (about 0.004), inside its interval. */
static void check_noisy_error(const lucent_image *truth, lucent_image *a, lucent_image *b, lucent_image *test)
{
    lucent_image mean;
    lucent_error err = {0};
    copy_image(truth, &mean);
    unsigned state = 7;
    noisy_estimates(truth, a, b, 0.3, &state);
    double t2 = 0.0, d2 = 0.0;
    for (int k = 0; k < W * H * 4; k++)
        if (k % 4 != 3) {
            mean.rgba[k] = 0.5f * (a->rgba[k] + b->rgba[k]);
            test->rgba[k] = 1.1f * truth->rgba[k];
            t2 += (double)truth->rgba[k] * truth->rgba[k];
            d2 += ((double)mean.rgba[k] - truth->rgba[k]) * ((double)mean.rgba[k] - truth->rgba[k]);
        }
    double true_noise = sqrt(d2 / t2);
    lucent_image_error e;
    lucent_noisy_error n;
    lucent_image_compare(test, &mean, &e, &err);
    lucent_status st = lucent_image_compare_noisy(test, a, b, &n, &err);
    test_check(st == LUCENT_OK && fabs(n.rel_l2 - 0.1) < 0.015 && n.rel_l2_low < 0.1 && n.rel_l2_high > 0.1 &&
                   n.rel_l2_low > 0.0 && fabs(n.noise - true_noise) < 0.1 * true_noise && e.object.rel_l2 > 0.15,
               "true error 0.1 behind two noisy truths (%d values, tolerance 0.015): compare_noisy %.4f (2 standard "
               "errors %.4f-%.4f; rel L2 against their mean %.4f), noise of the mean %.4f (actual %.4f, expected 0.122)",
               RECTANGLE_VALUES, n.rel_l2, n.rel_l2_low, n.rel_l2_high, e.object.rel_l2, n.noise, true_noise);
    lucent_image_free(&mean);
}

/* The interval's width against the spread it claims: over 200 draws of the noise, the cross sum's own
 * standard deviation against the mean standard error compare_noisy estimated (within 25%), and the
 * share of intervals holding the true 0.1 (about 95% for 2 standard errors; at least 88%). */
static void check_noisy_interval(const lucent_image *truth, lucent_image *a, lucent_image *b,
                                 const lucent_image *test)
{
    enum { DRAWS = 200 };
    lucent_error err = {0};
    unsigned state = 11;
    double t2 = 0.0, sum = 0.0, sum2 = 0.0, se = 0.0;
    int held = 0;
    for (int k = 0; k < W * H * 4; k++)
        if (k % 4 != 3)
            t2 += (double)truth->rgba[k] * truth->rgba[k];
    for (int d = 0; d < DRAWS; d++) {
        lucent_noisy_error n;
        noisy_estimates(truth, a, b, 0.3, &state);
        lucent_image_compare_noisy(test, a, b, &n, &err);
        double cross = n.rel_l2 * n.rel_l2 * t2;  /* the estimates' own sum a.b differs from t2 by noise */
        sum += cross;
        sum2 += cross * cross;
        se += (n.rel_l2_high * n.rel_l2_high - n.rel_l2 * n.rel_l2) * t2 / 2.0 / DRAWS;
        held += n.rel_l2_low <= 0.1 && 0.1 <= n.rel_l2_high;
    }
    double spread = sqrt(fmax(sum2 / DRAWS - (sum / DRAWS) * (sum / DRAWS), 0.0));
    test_check(fabs(se / spread - 1.0) < 0.25 && held >= DRAWS * 88 / 100,
               "over %d draws: the cross sum's spread %.4g, mean standard error estimated %.4g (ratio %.3f, "
               "tolerance 25%%); intervals holding the true 0.1: %d (at least %d)",
               DRAWS, spread, se, se / spread, held, DRAWS * 88 / 100);
}

/* Noise far above the error: the truth itself behind estimates with amplitude 3 (noise of the mean
 * 1.22) cannot be told from a small error, so the interval starts at 0 and still bounds it from above,
 * far below the noise. */
static void check_noise_hides_error(const lucent_image *truth, lucent_image *a, lucent_image *b)
{
    lucent_error err = {0};
    lucent_noisy_error n;
    unsigned state = 6;
    noisy_estimates(truth, a, b, 3.0, &state);
    lucent_status st = lucent_image_compare_noisy(truth, a, b, &n, &err);
    test_check(st == LUCENT_OK && n.rel_l2_low == 0.0 && n.rel_l2_high >= n.rel_l2 && n.rel_l2_high < 0.5 &&
                   n.noise > 1.0,
               "the truth behind noise %.3f: compare_noisy %.4f, interval %.4f-%.4f (expected from 0)", n.noise,
               n.rel_l2, n.rel_l2_low, n.rel_l2_high);
}

/* Both sides noisy: the test (the truth times 1.1) seen through two estimates t1, t2 with the same noise
 * as a and b. Over 100 draws compare_noisy_pair's squared error should average 0.01 (within 10%; one
 * draw's spreads about 0.0018, so the mean's about 2%) and its interval hold 0.1 in at least 88 of them,
 * where compare_noisy against the test's mean adds that noise (about 0.026); the test's noise is reported
 * (1.1 times the truth's), and the pair given one test twice is compare_noisy exactly. */
static void check_noisy_pair(const lucent_image *truth, lucent_image *a, lucent_image *b)
{
    enum { DRAWS = 100 };
    lucent_image test, t1, t2;
    lucent_error err = {0};
    copy_image(truth, &test);
    copy_image(truth, &t1);
    copy_image(truth, &t2);
    for (int k = 0; k < W * H * 4; k++)
        if (k % 4 != 3)
            test.rgba[k] = 1.1f * truth->rgba[k];
    unsigned state = 13;
    double pair2 = 0.0, one2 = 0.0, noise_ratio = 0.0;
    int held = 0, ok = 1;
    for (int d = 0; d < DRAWS; d++) {
        lucent_noisy_error pair, one;
        noisy_estimates(truth, a, b, 0.3, &state);
        noisy_estimates(&test, &t1, &t2, 0.3, &state);
        ok &= lucent_image_compare_noisy_pair(&t1, &t2, a, b, &pair, &err) == LUCENT_OK;
        ok &= lucent_image_average(&t1, &t2, &err) == LUCENT_OK;
        ok &= lucent_image_compare_noisy(&t1, a, b, &one, &err) == LUCENT_OK;
        pair2 += pair.rel_l2 * pair.rel_l2 / DRAWS;
        one2 += one.rel_l2 * one.rel_l2 / DRAWS;
        noise_ratio += pair.test_noise / pair.noise / DRAWS;
        held += pair.rel_l2_low <= 0.1 && 0.1 <= pair.rel_l2_high;
    }
    lucent_noisy_error same, alone;
    lucent_image_compare_noisy_pair(&test, &test, a, b, &same, &err);
    lucent_image_compare_noisy(&test, a, b, &alone, &err);
    test_check(ok && fabs(pair2 / 0.01 - 1.0) < 0.1 && held >= DRAWS * 88 / 100 && one2 > 0.02 &&
                   fabs(noise_ratio - 1.1) < 0.05 && same.rel_l2 == alone.rel_l2 &&
                   same.rel_l2_high == alone.rel_l2_high && same.test_noise == 0.0,
               "true error 0.1 (squared 0.01), both sides noisy, over %d draws: compare_noisy_pair's squared error "
               "%.5f on average, intervals holding 0.1: %d (at least %d); compare_noisy against the test's mean "
               "%.5f (adds its noise); the test's noise %.3f times the truth's (expected 1.1); one test given twice "
               "%.6f = compare_noisy %.6f, test noise %g",
               DRAWS, pair2, held, DRAWS * 88 / 100, one2, noise_ratio, same.rel_l2, alone.rel_l2, same.test_noise);
    lucent_image_free(&test);
    lucent_image_free(&t1);
    lucent_image_free(&t2);
}

/* lucent_image_average on the smooth image and 1.1 times it: RGB 1.05 times the truth, alpha kept;
 * another size refused. */
static void check_average(const lucent_image *truth, const lucent_image *brighter, const lucent_image *small)
{
    lucent_image mean;
    lucent_error err = {0};
    copy_image(truth, &mean);
    lucent_status st = lucent_image_average(&mean, brighter, &err);
    double worst = 0.0;
    int alpha_kept = 1;
    for (int k = 0; k < W * H * 4; k++) {
        if (k % 4 == 3)
            alpha_kept &= mean.rgba[k] == truth->rgba[k];
        else
            worst = fmax(worst, fabs(mean.rgba[k] - 1.05 * truth->rgba[k]));
    }
    test_check(st == LUCENT_OK && worst < 1e-6 && alpha_kept &&
                   lucent_image_average(&mean, small, &err) == LUCENT_E_INVALID,
               "average of the truth and 1.1 times it: worst difference from 1.05 times %.2g (below 1e-6), alpha "
               "kept %d, another size refused: %s",
               worst, alpha_kept, err.message);
    lucent_image_free(&mean);
}

static void check_noisy_truth(void)
{
    lucent_image truth, a, b, test;
    lucent_error err = {0};
    lucent_noisy_error n;
    make_smooth(&truth);
    copy_image(&truth, &a);
    copy_image(&truth, &b);
    copy_image(&truth, &test);
    check_noisy_error(&truth, &a, &b, &test);
    check_noisy_interval(&truth, &a, &b, &test);
    lucent_status st = lucent_image_compare_noisy(&truth, &a, &b, &n, &err);
    test_check(st == LUCENT_OK && n.rel_l2 < 0.03 && n.rel_l2_low == 0.0 && n.rel_l2_high < 0.05,
               "the truth itself behind them: %.4f, interval %.4f-%.4f (expected from 0, below 0.05)", n.rel_l2, n.rel_l2_low,
               n.rel_l2_high);
    st = lucent_image_compare_noisy(NULL, &a, &b, &n, &err);
    test_check(st == LUCENT_OK && isnan(n.rel_l2) && isnan(n.rel_l2_high) && n.noise > 0.0,
               "no test: rel %g (NAN), noise %.4f", n.rel_l2, n.noise);
    check_noise_hides_error(&truth, &a, &b);
    check_noisy_pair(&truth, &a, &b);
    for (int k = 0; k < W * H * 4; k++)
        if (k % 4 != 3)
            a.rgba[k] = b.rgba[k] = 0.0f;
    st = lucent_image_compare_noisy(&test, &a, &b, &n, &err);
    test_check(st == LUCENT_OK && isnan(n.rel_l2) && isnan(n.noise), "black truths: rel %g, noise %g (NAN)",
               n.rel_l2, n.noise);
    lucent_image small = {0};
    lucent_image_alloc(&small, 8, 8, 0, &err);
    test_check(lucent_image_compare_noisy(&test, &a, &small, &n, &err) == LUCENT_E_INVALID,
               "size mismatch refused: %s", err.message);
    check_average(&truth, &test, &small);
    lucent_image *all[] = {&truth, &a, &b, &test, &small};
    for (int i = 0; i < 5; i++)
        lucent_image_free(all[i]);
}

int main(void)
{
    lucent_image ref, test;
    lucent_image_error e;
    lucent_error err = {0};
    make_reference(&ref);
    copy_image(&ref, &test);

    lucent_image_compare(&test, &ref, &e, &err);
    test_check(e.object.pixels > 500 && e.object.rel_l2 == 0.0 && e.object.max_abs == 0.0 && e.band.pixels > 0 && e.band.rel_l2 == 0.0,
               "identical: %d pixels (%d in the band), rel L2 %g, max abs %g", e.object.pixels, e.band.pixels, e.object.rel_l2,
               e.object.max_abs);

    for (int i = 0; i < W * H * 4; i++)
        if (i % 4 != 3)
            test.rgba[i] = ref.rgba[i] * 1.2f;
    lucent_image_compare(&test, &ref, &e, &err);
    test_check(fabs(e.object.rel_l2 - 0.2) < 1e-6 && fabs(e.object.p99_rel - 0.2) < 1e-6 && e.object.share_over_10pct == 1.0 &&
                   fabs(e.object.max_abs - 0.2) < 1e-6 && fabs(e.band.rel_l2 - 0.2) < 1e-6,
               "20%% gain: rel L2 %.6f, p99 %.6f, share >10%% %.3f, max abs %.6f, band rel L2 %.6f", e.object.rel_l2,
               e.object.p99_rel, e.object.share_over_10pct, e.object.max_abs, e.band.rel_l2);

    int band = 0;
    for (int i = 0; i < W * H; i++) {
        for (int c = 0; c < 3; c++)
            test.rgba[i * 4 + c] = ref.rgba[i * 4 + c];
        if (ref.rgba[i * 4 + 3] > 0.0f && ref.facing[i] < 0.342f) {
            test.rgba[i * 4] = 0.0f;   /* the single-image failure: red lost at the silhouette */
            band++;
        }
    }
    lucent_image_compare(&test, &ref, &e, &err);
    test_check(e.band.pixels == band && e.band.share_over_10pct == 1.0 && e.band.rel_l2 > e.object.rel_l2 &&
                   e.object.share_over_10pct < 1.0 && e.object.share_over_10pct > 0.0,
               "error only in the band (%d px): band rel L2 %.4f > whole %.4f; share >10%% band %.2f, whole %.3f",
               band, e.band.rel_l2, e.object.rel_l2, e.band.share_over_10pct, e.object.share_over_10pct);

    test.rgba[3] = 1.0f;              /* corner covered in the test only */
    test.rgba[(W * H / 2 + W / 2) * 4 + 3] = 0.0f;   /* centre uncovered in the test only */
    lucent_image_compare(&test, &ref, &e, &err);
    test_check(e.coverage_mismatch == 2, "coverage differs in %d pixels (2 made)", e.coverage_mismatch);

    char json[1024];
    test_check(lucent_image_error_json(&e, json, sizeof json) > 0 && json[0] == '{' && strstr(json, "\"noise\":") &&
                   strstr(json, "\"low_frequency_rel_l2\":") && strstr(json, "\"mean_ratio\":") &&
                   strstr(json, "\"interior_pixels\":") && strstr(json, "\"rel_l2\":") &&
                   strstr(json, "\"mottle\":null") && strstr(json, "\"mottle_pixels\":0"),
               "JSON has the old and the new keys (mottle null: no pixel has 25x25 covered neighbours): %s", json);
    check_frequencies();
    check_mottle();
    check_noisy_truth();

    /* A black reference makes the per-pixel relative measures 0/0: JSON has no NaN, so they print as null. */
    for (int i = 0; i < W * H; i++)
        ref.rgba[i * 4] = ref.rgba[i * 4 + 1] = ref.rgba[i * 4 + 2] = 0.0f;
    lucent_image_compare(&test, &ref, &e, &err);
    int written = lucent_image_error_json(&e, json, sizeof json);
    json_t *parsed = written > 0 ? json_loads(json, 0, NULL) : NULL;
    test_check(parsed && !isfinite(e.object.p99_rel) && json_is_null(json_object_get(parsed, "p99_rel")),
               "black reference: p99 rel %g written as null, the JSON parses: %s", e.object.p99_rel, json);
    json_decref(parsed);
    char escaped[32];
    json_escape("GPU \"x\"\\\n", escaped, sizeof escaped);   /* what a device name could hold (--stats) */
    test_check(strcmp(escaped, "GPU \\\"x\\\"\\\\\\u000a") == 0, "JSON string escaped: %s", escaped);

    lucent_image small = {0};
    lucent_image_alloc(&small, 8, 8, 0, &err);
    test_check(lucent_image_compare(&small, &ref, &e, &err) == LUCENT_E_INVALID, "size mismatch refused: %s",
               err.message);
    lucent_image_free(&small);
    lucent_image_free(&test);
    lucent_image_free(&ref);
    return test_finish();
}
