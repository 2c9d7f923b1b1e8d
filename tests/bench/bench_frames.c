/* bench_frames.c - warm frame times of scene documents: median of N frames per pass and in total, with
 * the CPU model and the device, as a Markdown table (frame_ratio.sh runs two builds side by side). */
#include "bench_host.h"
#include "bench_median.h"
#include "lucent.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { T_TOTAL, T_PROJECTION, T_SCATTER, T_COUNT };

static int read_scene(const char *path, lucent_scene *s, lucent_error *err)
{
    static char buf[1 << 16];
    FILE *f = fopen(path, "rb");
    size_t n = f ? fread(buf, 1, sizeof buf, f) : 0;
    if (f)
        fclose(f);
    if (n == 0 || n == sizeof buf) {
        fprintf(stderr, "bench_frames: cannot read %s (or it is over 64 KiB)\n", path);
        return -1;
    }
    if (lucent_scene_parse(buf, n, 1, s, err) != LUCENT_OK) {
        fprintf(stderr, "bench_frames: %s: %s: %s\n", path, err->field, err->message);
        return -1;
    }
    return 0;
}

/* Medians of `frames` warm frames (after 2 unmeasured ones) into ms[T_COUNT]. */
static int measure(lucent_renderer *r, const lucent_scene *s, int frames, double ms[T_COUNT], char *device,
                   size_t cap)
{
    double *t[T_COUNT];
    int rc = 0;
    for (int k = 0; k < T_COUNT; k++)
        t[k] = calloc((size_t)frames, sizeof(double));
    for (int f = -2; f < frames && rc == 0; f++) {
        lucent_image img;
        lucent_stats st;
        lucent_error err = {0};
        if (lucent_render(r, s, &img, &st, &err) != LUCENT_OK) {
            fprintf(stderr, "bench_frames: %s: %s\n", err.field, err.message);
            rc = -1;
            break;
        }
        lucent_image_free(&img);
        snprintf(device, cap, "%s", st.device);
        if (f >= 0) {
            t[T_TOTAL][f] = st.ms_total - st.ms_mesh_load;
            t[T_PROJECTION][f] = st.ms_projection;
            t[T_SCATTER][f] = st.ms_scatter;
        }
    }
    for (int k = 0; k < T_COUNT; k++) {
        if (rc == 0)
            ms[k] = bench_median(t[k], frames);
        free(t[k]);
    }
    return rc;
}

int main(int argc, char **argv)
{
    int frames = argc > 3 ? atoi(argv[1]) : 0;
    if (frames < 1) {
        fprintf(stderr, "usage: bench_frames FRAMES>=1 OUT.md SCENE.json...\n");
        return 2;
    }
    FILE *out = fopen(argv[2], "w");
    if (!out) {
        fprintf(stderr, "bench_frames: cannot write %s\n", argv[2]);
        return 1;
    }
    lucent_error err = {0};
    lucent_renderer *r = lucent_renderer_create(&(lucent_renderer_desc){0}, &err);
    if (!r) {
        fprintf(stderr, "bench_frames: %s\n", err.message);
        fclose(out);
        return 1;
    }
    char cpu[256], device[256] = "";
    cpu_model(cpu, sizeof cpu);
    int rc = 0;
    for (int a = 3; a < argc && rc == 0; a++) {
        lucent_scene s;
        double ms[T_COUNT];
        rc = read_scene(argv[a], &s, &err) || measure(r, &s, frames, ms, device, sizeof device);
        if (rc == 0) {
            if (a == 3)
                fprintf(out, "CPU: %s; device: %s; medians of %d warm frames, ms\n\n"
                             "| scene | total | projection | scatter |\n|---|---|---|---|\n", cpu, device, frames);
            fprintf(out, "| %s | %.2f | %.2f | %.2f |\n", argv[a], ms[T_TOTAL], ms[T_PROJECTION], ms[T_SCATTER]);
        }
    }
    lucent_renderer_destroy(r);
    lucent_shutdown();
    if (fclose(out) != 0)
        rc = 1;
    return rc != 0;
}
