/* linalg.h - the little vector and matrix algebra the frame set-up needs, in double precision.
 * Matrices are column-major 4x4 (as GLSL reads them); vectors are double[3]. */
#ifndef LUCENT_LINALG_H
#define LUCENT_LINALG_H

#include <math.h>

#define PI 3.14159265358979323846

static inline double v3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void v3_cross(const double a[3], const double b[3], double out[3])
{
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    out[0] = x, out[1] = y, out[2] = z;
}

static inline double v3_length(const double a[3])
{
    return sqrt(v3_dot(a, a));
}

/* Normalizes in place; returns the original length (0 leaves the vector unchanged). */
static inline double v3_normalize(double a[3])
{
    double len = v3_length(a);
    if (len > 0.0)
        a[0] /= len, a[1] /= len, a[2] /= len;
    return len;
}

static inline void v3_scale_add(const double a[3], const double b[3], double s, double out[3])
{
    out[0] = a[0] + b[0] * s, out[1] = a[1] + b[1] * s, out[2] = a[2] + b[2] * s;
}

static inline void v3_copy_f4(const double a[3], double w, float out[4])
{
    out[0] = (float)a[0], out[1] = (float)a[1], out[2] = (float)a[2], out[3] = (float)w;
}

/* m = a * b */
static inline void m4_mul(const double a[16], const double b[16], double m[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++)
                s += a[k * 4 + r] * b[c * 4 + k];
            m[c * 4 + r] = s;
        }
}

static inline void m4_to_float(const double m[16], float out[16])
{
    for (int i = 0; i < 16; i++)
        out[i] = (float)m[i];
}

#endif
