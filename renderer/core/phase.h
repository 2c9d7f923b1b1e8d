/* phase.h - the Henyey-Greenstein phase function the single-scattering terms share.
 * mu: the cosine between the directions light travels before and after scattering. */
#ifndef LUCENT_PHASE_H
#define LUCENT_PHASE_H

#include "linalg.h"

#include <math.h>

/* The floor keeps g near +-1 with mu near +-1 finite (the parser bounds |g| by 0.95, where it never acts). */
static inline double henyey_greenstein(double g, double mu)
{
    return (1.0 - g * g) / (4.0 * PI * pow(fmax(1.0 + g * g - 2.0 * g * mu, 1e-12), 1.5));
}

#endif
