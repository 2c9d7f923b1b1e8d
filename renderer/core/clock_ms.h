/* clock_ms.h - the monotonic clock in milliseconds, for the timings in lucent_stats and the mesh cache's
 * recency. Static inline: one definition for renderer.c, mesh_cache.c and reference.c. */
#ifndef LUCENT_CLOCK_MS_H
#define LUCENT_CLOCK_MS_H

#include <time.h>

static inline double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

#endif
