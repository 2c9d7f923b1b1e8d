/* bench_table2.c - the paper's Table 2 on this machine: the six triangle counts at 512x512 with
 * "single" and "five" (shared sampling, the default) and "five" with the paper's per-channel sampling
 * (48 fetches a pixel), warm, median of N frames, beside the paper's FPS-1 / FPS-2; with --backend
 * vulkan,gl each row once per backend, measured back to back. Not a test. */
#include "bench_host.h"
#include "bench_median.h"
#include "lucent.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct paper_row {
    const char *model;
    uint32_t triangles;
    double fps1, fps2;
};

static const struct paper_row paper[] = {
    {"Decimated Stanford bunny", 17082, 50.41, 15.81}, {"Walker head", 20720, 57.77, 17.12},
    {"Stanford bunny", 68328, 34.15, 10.91},           {"Gargoyle", 100000, 27.52, 8.83},
    {"Gist-MP3", 460612, 14.55, 5.45},                 {"Gist-Monkey", 969920, 14.17, 4.04}};

enum { T_TOTAL, T_SHADOW, T_PROJECTION, T_GBUFFER, T_SCATTER, T_READBACK, T_COUNT };

struct measure {
    double median[T_COUNT];
    uint32_t triangles, proxy_triangles;
};

static int measure(lucent_renderer *r, uint32_t triangles, lucent_method method, lucent_sampling sampling,
                   int frames, int size, struct measure *m)
{
    lucent_scene s;
    lucent_scene_defaults(&s);
    snprintf(s.mesh.builtin, sizeof s.mesh.builtin, "protrusion");
    s.mesh.triangles = triangles;
    s.width = s.height = size;
    s.projection_size = size;
    s.method = method;
    s.sampling = sampling;
    s.lights[0].direction[0] = -1.0, s.lights[0].direction[1] = 0.0, s.lights[0].direction[2] = 0.0;
    /* the paper's set-up: the protrusion seen head-on, lit from the camera's right */
    s.camera.direction[0] = 0.0, s.camera.direction[1] = 0.0, s.camera.direction[2] = -1.0;
    double *t[T_COUNT];
    for (int k = 0; k < T_COUNT; k++)
        t[k] = calloc((size_t)frames, sizeof(double));
    lucent_error err = {0};
    int warmup = 3, rc = 0;
    for (int f = -warmup; f < frames && rc == 0; f++) {
        lucent_image img;
        lucent_stats st;
        if (lucent_render(r, &s, &img, &st, &err) != LUCENT_OK) {
            fprintf(stderr, "bench: %s: %s\n", err.field, err.message);
            rc = -1;
            break;
        }
        lucent_image_free(&img);
        m->triangles = st.triangles;
        m->proxy_triangles = st.proxy_triangles;
        if (f < 0)
            continue;
        double v[T_COUNT] = {st.ms_total - st.ms_mesh_load, st.ms_shadow, st.ms_projection, st.ms_gbuffer,
                             st.ms_scatter, st.ms_readback};
        for (int k = 0; k < T_COUNT; k++)
            t[k][f] = v[k];
    }
    for (int k = 0; k < T_COUNT; k++) {
        if (rc == 0)
            m->median[k] = bench_median(t[k], frames);
        free(t[k]);
    }
    return rc;
}

#define MAX_BACKENDS 2

/* --backend LIST (comma-separated, default auto) anywhere; the rest positional. */
static int parse_backends(int *argc, char **argv, char names[MAX_BACKENDS][16])
{
    const char *list = "auto";
    int n = 0, kept = 1;
    for (int i = 1; i < *argc; i++) {
        if (strcmp(argv[i], "--backend") == 0 && i + 1 < *argc)
            list = argv[++i];
        else
            argv[kept++] = argv[i];
    }
    *argc = kept;
    for (const char *p = list; *p && n < MAX_BACKENDS; n++) {
        size_t len = strcspn(p, ",");
        snprintf(names[n], 16, "%.*s", (int)len, p);
        if (!lucent_backend_valid(names[n]))
            return -1;
        p += len + (p[len] == ',');
    }
    return n;
}

int main(int argc, char **argv)
{
    char backends[MAX_BACKENDS][16];
    int nb = parse_backends(&argc, argv, backends);
    const char *out_path = argc > 1 ? argv[1] : "bench_table2.md";
    int frames = argc > 2 ? atoi(argv[2]) : 20;
    int size = argc > 3 ? atoi(argv[3]) : 512;
    if (nb < 1 || frames < 1 || size < 16) {
        fprintf(stderr, "usage: bench_table2 [OUT.md] [FRAMES>=1] [SIZE>=16] [--backend vulkan|gl|auto[,...]]\n");
        return 2;
    }
    lucent_renderer *rs[MAX_BACKENDS] = {0};
    for (int b = 0; b < nb; b++) {
        lucent_error err = {0};
        lucent_renderer_desc desc = {.backend = backends[b], .verbose = 1};
        if (!(rs[b] = lucent_renderer_create(&desc, &err))) {
            fprintf(stderr, "bench: %s: %s\n", backends[b], err.message);
            for (int k = 0; k < b; k++)
                lucent_renderer_destroy(rs[k]);
            return 1;
        }
    }
    FILE *out = fopen(out_path, "w");
    if (!out) {
        perror(out_path);
        for (int b = 0; b < nb; b++)
            lucent_renderer_destroy(rs[b]);
        return 1;
    }
    char cpu[256], head[1024];
    cpu_model(cpu, sizeof cpu);
    snprintf(head, sizeof head,
             "Table 2 at %dx%d (front projection image %d^2, side images %d^2), median of %d warm frames; "
             "mesh = builtin protrusion at the paper's triangle count, lit from the side.\n"
             "CPU: %s; device: %s\n\n"
             "| paper model | backend | triangles | proxy | paper FPS-1 | paper FPS-2 | single FPS | five FPS | five/single "
             "| five >= FPS-2 | five per-channel FPS | five ms: shadow / projection / gbuffer / scatter / readback |\n"
             "|---|---|---|---|---|---|---|---|---|---|---|---|\n",
             size, size, size, size / 2, frames, cpu, lucent_renderer_device(rs[0]));
    fputs(head, stdout);
    fputs(head, out);
    int rc = 0;
    for (size_t i = 0; i < sizeof paper / sizeof paper[0] && rc == 0; i++)
        for (int b = 0; b < nb && rc == 0; b++) {
            lucent_renderer *r = rs[b];
            struct measure one = {0}, five = {0}, paper_five = {0};
            if (measure(r, paper[i].triangles, LUCENT_METHOD_SINGLE, LUCENT_SAMPLING_SHARED, frames, size, &one) ||
                measure(r, paper[i].triangles, LUCENT_METHOD_FIVE, LUCENT_SAMPLING_SHARED, frames, size, &five) ||
                measure(r, paper[i].triangles, LUCENT_METHOD_FIVE, LUCENT_SAMPLING_PER_CHANNEL, frames, size,
                        &paper_five)) {
                rc = 1;
                break;
            }
            double fps1 = 1000.0 / one.median[T_TOTAL], fps5 = 1000.0 / five.median[T_TOTAL];
            char row[512];
            snprintf(row, sizeof row,
                     "| %s | %s | %u | %u | %.2f | %.2f | %.2f | %.2f | %.2fx | %s | %.2f | %.1f / %.1f / %.1f / %.1f / %.1f |\n",
                     paper[i].model, lucent_renderer_backend(r), five.triangles, five.proxy_triangles, paper[i].fps1,
                     paper[i].fps2, fps1, fps5, five.median[T_TOTAL] / one.median[T_TOTAL],
                     fps5 >= paper[i].fps2 ? "yes" : "no", 1000.0 / paper_five.median[T_TOTAL], five.median[T_SHADOW],
                     five.median[T_PROJECTION], five.median[T_GBUFFER], five.median[T_SCATTER], five.median[T_READBACK]);
            fputs(row, stdout);
            fputs(row, out);
            fflush(stdout);
        }
    fclose(out);
    for (int b = 0; b < nb; b++)
        lucent_renderer_destroy(rs[b]);
    return rc;
}
