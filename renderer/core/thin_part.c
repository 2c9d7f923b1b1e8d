/* thin_part.c - the share of R a thin part keeps on the face light entered (profile_slab_share), tabulated
 * over log distance and log thickness, since the series takes up to 256 exponentials an evaluation. */
#include "thin_part.h"

#include <math.h>

#define R_MIN_OCTAVE (-4)
#define T_MIN_OCTAVE (-2)

void thin_part_table_init(struct thin_part_table *t, const struct profile *p)
{
    t->sources = p->z[0] > 0.0;
    t->mfp = 1.0 / p->sigma_t_prime;
    for (int i = 0; i < THIN_PART_T; i++)
        for (int j = 0; j < THIN_PART_R; j++) {
            double thickness = t->mfp * exp2(T_MIN_OCTAVE + (double)i / THIN_PART_PER_OCTAVE);
            double r = t->mfp * exp2(R_MIN_OCTAVE + (double)j / THIN_PART_PER_OCTAVE);
            t->share[i][j] = t->sources ? (float)profile_slab_share(p, r, thickness) : 1.0f;
        }
}

/* Where x (in mean free paths) falls on an axis of n entries from octave `first`: index and fraction. */
static void locate(double x, int first, int n, int *index, double *fraction)
{
    double u = (log2(fmax(x, 1e-300)) - first) * THIN_PART_PER_OCTAVE;
    u = fmin(fmax(u, 0.0), n - 1.0);
    *index = (int)fmin(floor(u), n - 2.0);
    *fraction = u - *index;
}

double thin_part_share(const struct thin_part_table *t, double r_mm, double thickness_mm)
{
    double top = t->mfp * exp2(T_MIN_OCTAVE + (THIN_PART_T - 1.0) / THIN_PART_PER_OCTAVE);
    if (!t->sources || !(thickness_mm < top))
        return 1.0;
    int i, j;
    double fi, fj;
    locate(thickness_mm / t->mfp, T_MIN_OCTAVE, THIN_PART_T, &i, &fi);
    locate(r_mm / t->mfp, R_MIN_OCTAVE, THIN_PART_R, &j, &fj);
    double near = t->share[i][j] * (1.0 - fj) + t->share[i][j + 1] * fj;
    double far = t->share[i + 1][j] * (1.0 - fj) + t->share[i + 1][j + 1] * fj;
    return near * (1.0 - fi) + far * fi;
}
