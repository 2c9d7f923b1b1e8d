/* valid_reflection.c - Blender Cycles' correction of a shading normal at grazing views, re-derived in
 * double precision so that method "path" with boundary "cycles" enters the medium as Cycles does. */
#include "valid_reflection.h"
#include "linalg.h"

#include <math.h>
#include <string.h>

void valid_reflection_normal(const double g[3], const double i[3], const double n[3], double out[3])
{
    double threshold = fmin(0.9 * v3_dot(g, i), 0.01), ni = v3_dot(n, i);
    double gr = 2.0 * ni * v3_dot(g, n) - v3_dot(g, i);
    memcpy(out, n, 3 * sizeof *out);
    if (gr >= threshold)
        return;
    double x[3];
    v3_scale_add(n, g, -v3_dot(n, g), x);
    if (v3_normalize(x) == 0.0) {
        memcpy(out, g, 3 * sizeof *out);
        return;
    }
    /* n' = nx x + nz g with 2 (nx ix + nz iz) nz - iz = threshold: nz^2 = (c +- b) / (2 a). */
    double ix = v3_dot(i, x), iz = v3_dot(i, g), a = ix * ix + iz * iz;
    double b = sqrt(fmax(ix * ix * (a - threshold * threshold), 0.0)), c = iz * threshold + a;
    double z2[2] = {(c + b) / (2.0 * a), (c - b) / (2.0 * a)}, nx[2], nz[2], r[2];
    int valid[2];
    for (int k = 0; k < 2; k++) {
        valid[k] = z2[k] > 1e-5 && z2[k] <= 1.0 + 1e-5;
        nx[k] = sqrt(fmax(1.0 - z2[k], 0.0));
        nz[k] = sqrt(fmax(z2[k], 0.0));
        r[k] = 2.0 * (nx[k] * ix + nz[k] * iz) * nz[k] - iz;
    }
    int pick;
    if (valid[0] && valid[1]) {
        int ok0 = r[0] >= 1e-5, ok1 = r[1] >= 1e-5;
        pick = ok0 && ok1 ? (r[0] < r[1] ? 0 : 1) : (r[0] > r[1] ? 0 : 1);
    } else if (valid[0] || valid[1]) {
        pick = valid[0] ? 0 : 1;
    } else {
        memcpy(out, g, 3 * sizeof *out);
        return;
    }
    for (int k = 0; k < 3; k++)
        out[k] = nx[pick] * x[k] + nz[pick] * g[k];
}
