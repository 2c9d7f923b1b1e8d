/* half_space.c - exact albedos of an index-matched, isotropically scattering half-space (Chandrasekhar's
 * H-function): the transport-theory values the random walks and the profiles' totals are checked against. */
#include "half_space.h"

#include <math.h>

#define H_POINTS 2000

/* Chandrasekhar's H(mu) for isotropic scattering of albedo w on a midpoint grid, by iterating
 * 1 / H(mu) = sqrt(1 - w) + w / 2 int_0^1 mu' H(mu') / (mu + mu') dmu'. */
static void h_function(double w, double h[H_POINTS])
{
    for (int i = 0; i < H_POINTS; i++)
        h[i] = 1.0;
    for (int it = 0; it < 500; it++) {
        double change = 0.0;
        for (int i = 0; i < H_POINTS; i++) {
            double mu = (i + 0.5) / H_POINTS, sum = 0.0;
            for (int j = 0; j < H_POINTS; j++) {
                double mj = (j + 0.5) / H_POINTS;
                sum += mj * h[j] / (mu + mj);
            }
            double next = 1.0 / (sqrt(1.0 - w) + 0.5 * w * sum / H_POINTS);
            change = fmax(change, fabs(next - h[i]));
            h[i] = next;
        }
        if (change < 1e-12)
            break;
    }
}

/* The half-space's albedo for light entering straight down (plane albedo at mu0 = 1: 1 - H(1) sqrt(1 - w))
 * and for light entering diffusely (spherical albedo: 1 - 2 sqrt(1 - w) int H mu dmu). */
void half_space_albedo(double w, double *normal, double *diffuse)
{
    static double h[H_POINTS];
    h_function(w, h);
    double moment = 0.0, h1 = 1.5 * h[H_POINTS - 1] - 0.5 * h[H_POINTS - 2];   /* H at mu = 1 */
    for (int i = 0; i < H_POINTS; i++)
        moment += h[i] * (i + 0.5) / H_POINTS;
    *normal = 1.0 - h1 * sqrt(1.0 - w);
    *diffuse = 1.0 - 2.0 * sqrt(1.0 - w) * moment / H_POINTS;
}
