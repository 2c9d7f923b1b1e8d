/* bench_size_switch.c - what a request of another size costs the warm renderer: median frame times with
 * the image size or the projection size held, and alternating between two, as a Markdown table. */
#include "bench_host.h"
#include "bench_median.h"
#include "lucent.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

struct size_pair {
    const char *name;
    int w[2], projection[2];  /* frame f renders w[f % 2]^2 at projection[f % 2] */
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

/* Median wall time of `frames` frames of `pair` (after 2 unmeasured ones), or a negative value. */
static double measure(lucent_renderer *r, const struct size_pair *pair, int frames, char *device, size_t cap)
{
    double *t = calloc((size_t)frames, sizeof(double));
    double median = -1.0;
    for (int f = -2; t && f < frames; f++) {
        lucent_scene s;
        lucent_scene_defaults(&s);
        s.width = s.height = pair->w[(f + 2) % 2];
        s.projection_size = pair->projection[(f + 2) % 2];
        lucent_image img;
        lucent_stats st;
        lucent_error err = {0};
        double t0 = now_ms();
        if (lucent_render(r, &s, &img, &st, &err) != LUCENT_OK) {
            fprintf(stderr, "bench_size_switch: %s: %s: %s\n", pair->name, err.field, err.message);
            free(t);
            return -1.0;
        }
        if (f >= 0)
            t[f] = now_ms() - t0;
        lucent_image_free(&img);
        snprintf(device, cap, "%s", st.device);
    }
    if (t)
        median = bench_median(t, frames);
    free(t);
    return median;
}

int main(int argc, char **argv)
{
    int frames = argc == 4 ? atoi(argv[1]) : 0, size = argc == 4 ? atoi(argv[3]) : 0;
    if (frames < 1 || size < 16 || size > 4096) {
        fprintf(stderr, "usage: bench_size_switch FRAMES>=1 OUT.md SIZE (16-4096)\n");
        return 2;
    }
    int other = size - 8, p = 512;
    struct size_pair pairs[] = {{"image constant", {size, size}, {p, p}},
                                {"image constant, 8 smaller", {other, other}, {p, p}},
                                {"image alternating", {size, other}, {p, p}},
                                {"projection constant, half", {size, size}, {p / 2, p / 2}},
                                {"projection alternating", {size, size}, {p, p / 2}},
                                {"projection constant, double", {size, size}, {2 * p, 2 * p}},
                                {"projection alternating, double", {size, size}, {2 * p, p}}};
    lucent_error err = {0};
    lucent_renderer *r = lucent_renderer_create(&(lucent_renderer_desc){0}, &err);
    if (!r) {
        fprintf(stderr, "bench_size_switch: %s\n", err.message);
        return 1;
    }
    char cpu[256], device[256] = "";
    cpu_model(cpu, sizeof cpu);
    double ms[sizeof pairs / sizeof pairs[0]];
    int rc = 0;
    for (size_t i = 0; i < sizeof pairs / sizeof pairs[0] && rc == 0; i++)
        rc = (ms[i] = measure(r, &pairs[i], frames, device, sizeof device)) < 0.0;
    lucent_renderer_destroy(r);
    lucent_shutdown();
    FILE *out = rc == 0 ? fopen(argv[2], "w") : NULL;
    if (rc == 0 && !out) {
        fprintf(stderr, "bench_size_switch: cannot write %s\n", argv[2]);
        rc = 1;
    }
    for (size_t i = 0; out && i < sizeof pairs / sizeof pairs[0]; i++) {
        if (i == 0)
            fprintf(out, "CPU: %s; device: %s; default scene (method five); medians of %d frames, ms\n\n"
                         "| frames | image | projection | ms |\n|---|---|---|---|\n", cpu, device, frames);
        fprintf(out, "| %s | %d / %d | %d / %d | %.1f |\n", pairs[i].name, pairs[i].w[0], pairs[i].w[1],
                pairs[i].projection[0], pairs[i].projection[1], ms[i]);
    }
    if (out && fclose(out) != 0)
        rc = 1;
    return rc != 0;
}
