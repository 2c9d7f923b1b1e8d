/* thin_part.h - the light a thin part (an ear, a slab's face) loses through its back face: Donner and Jensen's
 * multipole share of R on a slab (profile_slab_share) tabulated over distance and thickness, for the reference. */
#ifndef LUCENT_THIN_PART_H
#define LUCENT_THIN_PART_H

#include "profile.h"

#define THIN_PART_PER_OCTAVE 4
#define THIN_PART_R 65   /* r: 1/16 .. 4096 mean free paths, log-spaced */
#define THIN_PART_T 57   /* thickness: 1/4 .. 4096 mean free paths */

struct thin_part_table {
    int sources;   /* 0: a profile without sources (normalized diffusion): the share is 1 */
    double mfp;    /* 1 / sigma_t', mm */
    float share[THIN_PART_T][THIN_PART_R];
};

/* Fills t for one channel's profile (about 2 ms). */
void thin_part_table_init(struct thin_part_table *t, const struct profile *p);
/* profile_slab_share(p, r_mm, thickness_mm), bilinear in log r and log thickness: r below the table as its
 * first column, beyond it as its last; thinner than the table as its thinnest; 1 beyond it (or INFINITY). */
double thin_part_share(const struct thin_part_table *t, double r_mm, double thickness_mm);

#endif
