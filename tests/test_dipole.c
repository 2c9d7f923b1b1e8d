/* test_dipole.c - checks the dipole profile, Fresnel terms and sampling tables against the values
 * in shared/research/translucency.md and against their own closed forms. */
#include "dipole.h"
#include "profile.h"
#include "lucent.h"

#include <math.h>
#include <stdio.h>

static int passed, failed;

static void check_close(const char *what, double got, double want, double rel_tol)
{
    double rel = fabs(got - want) / fmax(fabs(want), 1e-300);
    int ok = isfinite(got) && rel <= rel_tol;
    printf("%-4s %-44s got %.6g want %.6g rel.err %.2e (tol %.0e)\n", ok ? "ok" : "FAIL", what, got, want,
           rel, rel_tol);
    ok ? passed++ : failed++;
}

static void check(const char *what, int ok)
{
    printf("%-4s %s\n", ok ? "ok" : "FAIL", what);
    ok ? passed++ : failed++;
}

static void boundary_terms(void)
{
    check_close("F_dr(1.3)", dipole_fdr(1.3), 0.44476, 1e-4);
    check_close("A(1.3)", dipole_boundary_a(1.3), 2.60206, 1e-4);
    check_close("F_dr(1.0) is not zero", dipole_fdr(1.0), 0.00160, 1e-2);
    check_close("A(1.5)", dipole_boundary_a(1.5), 3.95950, 1e-4);
    check_close("Ft(eta 1, 30 deg) = 1", fresnel_transmittance(1.0, cos(0.5236)), 1.0, 1e-12);
    check_close("Ft(1.5, normal) = 0.96", fresnel_transmittance(1.5, 1.0), 0.96, 1e-9);
    check("Ft(1.3, grazing) = 0", fresnel_transmittance(1.3, 0.0) == 0.0);
}

static void skin1_profile(void)
{
    struct profile d;
    dipole_classic(&d, 0.032, 0.74, 1.3);
    const double r[] = {0.0, 0.5, 1.0, 2.0, 5.0};
    const double want[] = {0.044431, 0.036048, 0.022019, 0.0072614, 0.00080183};
    char what[64];
    for (int i = 0; i < 5; i++) {
        snprintf(what, sizeof what, "Skin1 red R_d(%.1f mm)", r[i]);
        check_close(what, profile_rd(&d, r[i]), want[i], 1e-3);
    }
    check_close("Skin1 red R_d total (closed form)", profile_total(&d), 0.43596, 1e-4);
    dipole_classic(&d, 0.0071, 3.00, 1.3);
    check_close("Marble blue R_d(0), eta 1.3", profile_rd(&d, 0.0), 0.74944, 1e-3);
    dipole_classic(&d, 0.97, 0.07, 1.3);
    check_close("Ketchup green R_d(5 mm)", profile_rd(&d, 5.0), 6.5e-8, 2e-2);
}

/* The paper's Rd column; Chicken1 blue is 0.126 by the formula against 0.10 printed (unexplained in
 * the research notes), so that one entry gets a wider tolerance. */
static void preset_reflectance(void)
{
    static const struct { const char *name; double rd[3]; } paper[] = {
        {"apple", {0.85, 0.84, 0.53}},    {"chicken1", {0.31, 0.15, 0.10}}, {"chicken2", {0.32, 0.16, 0.10}},
        {"cream", {0.98, 0.90, 0.73}},    {"ketchup", {0.16, 0.01, 0.00}},  {"marble", {0.83, 0.79, 0.75}},
        {"potato", {0.77, 0.62, 0.21}},   {"skimmilk", {0.81, 0.81, 0.69}}, {"skin1", {0.44, 0.22, 0.13}},
        {"skin2", {0.63, 0.44, 0.34}},    {"spectralon", {1.0, 1.0, 1.0}},  {"wholemilk", {0.91, 0.88, 0.76}}};
    int count = 0;
    for (size_t i = 0; i < sizeof paper / sizeof paper[0]; i++) {
        lucent_material m;
        if (lucent_material_preset(paper[i].name, &m) != LUCENT_OK) {
            check(paper[i].name, 0);
            continue;
        }
        for (int c = 0; c < 3; c++) {
            struct profile d;
            dipole_classic(&d, m.sigma_a[c], m.sigma_s_prime[c], m.eta);
            double got = profile_total(&d);
            double tol = (i == 1 && c == 2) ? 0.03 : 0.0101;
            int ok = fabs(got - paper[i].rd[c]) <= tol;
            printf("%-4s Rd total %-10s ch%d got %.3f paper %.2f |diff| %.3f (tol %.3f)\n", ok ? "ok" : "FAIL",
                   paper[i].name, c, got, paper[i].rd[c], fabs(got - paper[i].rd[c]), tol);
            ok ? passed++ : failed++;
        }
        count++;
    }
    check("all 12 presets known", count == 12 && lucent_material_preset_name(12) == NULL);
}

/* Where the sampling table puts radius j of n over r_min..r_max: its share of the annulus integral
 * (closed form) must be (j + 1/2) / n. Returns the worst difference, in units of 1/n. */
static double placement_error(const struct profile *d, double r_min, double r_max, int n, const double *radii)
{
    double lo = profile_disc(d, r_min), span = profile_disc(d, r_max) - lo, worst = 0.0;
    for (int j = 0; j < n; j++)
        worst = fmax(worst, fabs((profile_disc(d, radii[j]) - lo) / span - (j + 0.5) / n) * n);
    return worst;
}

/* Plane integral against the closed form, and the table's numerical CDF placing the radii where the
 * closed form says, every preset. */
static void energy_conservation(void)
{
    double radii[64], weights[64];
    for (int i = 0; lucent_material_preset_name(i); i++) {
        lucent_material m;
        lucent_material_preset(lucent_material_preset_name(i), &m);
        for (int c = 0; c < 3; c++) {
            if (m.sigma_a[c] == 0.0)
                continue;   /* 1/r^3 tail: the closed form is the limit at infinite radius */
            struct profile d;
            dipole_classic(&d, m.sigma_a[c], m.sigma_s_prime[c], m.eta);
            double r_max = 200.0 / profile_decay_rate(&d);
            char what[80];
            snprintf(what, sizeof what, "plane integral = closed form, %s ch%d", lucent_material_preset_name(i), c);
            check_close(what, profile_sample_radii(&d, 0.0, r_max, 16, radii, weights), profile_total(&d), 1e-3);
            snprintf(what, sizeof what, "radii placed by the CDF, %s ch%d (1/n)", lucent_material_preset_name(i), c);
            check_close(what, 1.0 + placement_error(&d, 0.0, r_max, 16, radii), 1.0, 1e-2);
        }
    }
}

/* The disc integral's closed form against a numerical integral of 2 pi r R_d, and its limit. */
static void disc_integral(void)
{
    struct profile d;
    dipole_classic(&d, 0.032, 0.74, 1.3);
    const double r[] = {0.1, 1.0, 5.0};
    for (int i = 0; i < 3; i++) {
        enum { STEPS = 200000 };
        double sum = 0.0, h = r[i] / STEPS;
        for (int k = 0; k < STEPS; k++)
            sum += 2.0 * 3.14159265358979323846 * (k + 0.5) * h * profile_rd(&d, (k + 0.5) * h) * h;
        char what[64];
        snprintf(what, sizeof what, "Skin1 red disc integral to %.1f mm", r[i]);
        check_close(what, profile_disc(&d, r[i]), sum, 1e-4);
    }
    check_close("disc integral to 1e6 mm = R_d total", profile_disc(&d, 1e6), profile_total(&d), 1e-9);
    dipole_classic(&d, 0.0, 1e4, 1.0);
    check("disc integral finite for sigma_a = 0, sigma_s' = 1e4", isfinite(profile_disc(&d, 1e-3)));
}

static void extremes(void)
{
    struct profile d;
    double radii[64], weights[64];
    dipole_classic(&d, 0.0, 11.6, 1.3);
    check_close("Spectralon R_d total = 1 (sigma_tr = 0)", profile_total(&d), 1.0, 1e-12);
    check("Spectralon R_d(0), R_d(1e4 mm) finite and > 0",
          isfinite(profile_rd(&d, 0.0)) && profile_rd(&d, 1e4) > 0.0 && isfinite(profile_rd(&d, 1e4)));
    double total = profile_sample_radii(&d, 0.0, 50.0, 64, radii, weights);
    int ok = isfinite(total) && total > 0.9 && total < 1.0;
    for (int j = 0; j < 64; j++)
        ok &= isfinite(radii[j]) && isfinite(weights[j]) && radii[j] <= 50.0 && (j == 0 || radii[j] > radii[j - 1]);
    printf("     Spectralon truncated at 50 mm: integral %.6f\n", total);
    check("Spectralon sampling table finite, increasing, within r_max", ok);

    const double sigmas[] = {1e-4, 1e-2, 1.0, 1e2, 1e4};
    for (int i = 0; i < 5; i++) {
        dipole_classic(&d, 0.01, sigmas[i], 1.0);
        double t = profile_sample_radii(&d, 0.0, 1e3, 16, radii, weights);
        int fine = isfinite(t) && t >= 0.0;
        for (int j = 0; j < 16; j++)
            fine &= isfinite(radii[j]) && isfinite(weights[j]) && weights[j] > 0.0;
        char what[80];
        snprintf(what, sizeof what, "sigma_s' = %g, eta = 1: table finite (integral %.4g)", sigmas[i], t);
        check(what, fine);
    }
    dipole_classic(&d, 0.5, 0.74, 1.3);
    double t = profile_sample_radii(&d, 0.0, 1e3, 16, radii, weights);
    double spread = 0.0;
    for (int j = 0; j < 16; j++)
        spread = fmax(spread, fabs(weights[j] * profile_rd(&d, radii[j]) / t - 1.0));
    check_close("weight x R_d(r_j) = integral for every sample", 1.0 + spread, 1.0, 1e-9);
}

/* The shared (mixture) table integrates every channel of every preset: sum_j R_d,c(r_j) w_j. */
static void mixture_quadrature(void)
{
    double radii[64], weights[64], one[64], w1[64];
    const int counts[] = {4, 16, 64};
    for (int i = 0; lucent_material_preset_name(i); i++) {
        lucent_material m;
        lucent_material_preset(lucent_material_preset_name(i), &m);
        struct profile d[3];
        for (int c = 0; c < 3; c++)
            dipole_classic(&d[c], m.sigma_a[c], m.sigma_s_prime[c], m.eta);
        for (int k = 0; k < 3; k++) {
            int n = counts[k];
            profile_mixture_radii(d, 0.0, 50.0, n, radii, weights);
            double worst = 0.0;
            for (int c = 0; c < 3; c++) {
                double want = profile_sample_radii(&d[c], 0.0, 50.0, 1, one, w1), got = 0.0;
                for (int j = 0; j < n; j++)
                    got += profile_rd(&d[c], radii[j]) * weights[j];
                worst = fmax(worst, fabs(got / want - 1.0));
            }
            double tol = n == 4 ? 0.1 : n == 16 ? 0.02 : 0.005;
            char what[96];
            snprintf(what, sizeof what, "mixture table, %s, %d samples: worst channel", lucent_material_preset_name(i), n);
            check_close(what, 1.0 + worst, 1.0, tol);
        }
    }
}

/* Sampling an annulus (the far part of the scatter pass; the disc inside is its near part):
 * the estimates integrate R_d between the radii, per channel and for the shared table. */
static void annulus_quadrature(void)
{
    double radii[64], weights[64];
    lucent_material m;
    lucent_material_preset("skin1", &m);
    struct profile d[3];
    for (int c = 0; c < 3; c++)
        dipole_classic(&d[c], m.sigma_a[c], m.sigma_s_prime[c], m.eta);
    const double inner[] = {0.05, 0.5, 5.0};
    for (int i = 0; i < 3; i++) {
        double want = profile_disc(&d[0], 50.0) - profile_disc(&d[0], inner[i]);
        double got = profile_sample_radii(&d[0], inner[i], 50.0, 16, radii, weights);
        int inside = 1;
        for (int j = 0; j < 16; j++)
            inside &= radii[j] >= inner[i] && radii[j] <= 50.0;
        char what[96];
        snprintf(what, sizeof what, "Skin1 red annulus %.2f-50 mm: integral (radii inside: %d)", inner[i], inside);
        check_close(what, inside ? got : -1.0, want, 2e-3);
        snprintf(what, sizeof what, "Skin1 red annulus %.2f-50 mm: radii placed by the CDF (1/n)", inner[i]);
        check_close(what, 1.0 + placement_error(&d[0], inner[i], 50.0, 16, radii), 1.0, 1e-2);
        profile_mixture_radii(d, inner[i], 50.0, 16, radii, weights);
        double worst = 0.0;
        for (int c = 0; c < 3; c++) {
            double sum = 0.0, ring = profile_disc(&d[c], 50.0) - profile_disc(&d[c], inner[i]);
            for (int j = 0; j < 16; j++)
                sum += profile_rd(&d[c], radii[j]) * weights[j];
            worst = fmax(worst, fabs(sum / ring - 1.0));
        }
        snprintf(what, sizeof what, "Skin1 annulus %.2f-50 mm, shared table, 16 samples: worst channel", inner[i]);
        check_close(what, 1.0 + worst, 1.0, 0.02);
    }
}

int main(void)
{
    mixture_quadrature();
    annulus_quadrature();
    disc_integral();
    boundary_terms();
    skin1_profile();
    preset_reflectance();
    energy_conservation();
    extremes();
    printf("%d passed, %d failed\n", passed, failed);
    return failed != 0;
}
