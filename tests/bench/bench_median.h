/* bench_median.h - the median the benchmarks report (robust to the odd slow frame on a shared machine).
 * Header-only: two tiny functions shared by every benchmark program. */
#ifndef LUCENT_BENCH_MEDIAN_H
#define LUCENT_BENCH_MEDIAN_H

#include <stdlib.h>

static int bench_compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sorts v in place and returns its median; n >= 1. */
static double bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, bench_compare_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

#endif
