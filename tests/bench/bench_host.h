/* bench_host.h - what machine a benchmark ran on, for the header of every table it prints: timings
 * are only comparable within one run on one machine. Header-only, shared by the benchmark programs. */
#ifndef LUCENT_BENCH_HOST_H
#define LUCENT_BENCH_HOST_H

#include <stdio.h>
#include <string.h>

/* The CPU's model name from /proc/cpuinfo, or "unknown CPU". */
static void cpu_model(char *out, size_t cap)
{
    snprintf(out, cap, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        char *colon = strchr(line, ':');
        if (strncmp(line, "model name", 10) == 0 && colon) {
            snprintf(out, cap, "%s", colon + 2);
            out[strcspn(out, "\n")] = '\0';
            break;
        }
    }
    if (f)
        fclose(f);
}

#endif
