/* test_renderer_memory.c - a warm renderer must not grow: three renderers in turn (sharing the process's
 * device), 200 frames each, the first a warm-up; nor with every pipeline variant a client can ask for; nor its
 * device memory across sizes. Resident memory is sampled from /proc after warm-up and at the end. */
#include "test_support.h"

#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* Resident memory after returning free heap pages, so allocator caching does not pass for a leak. */
static double rss_mib(void)
{
    malloc_trim(0);
    long pages_total = 0, pages_resident = 0;
    FILE *f = fopen("/proc/self/statm", "r");
    if (!f || fscanf(f, "%ld %ld", &pages_total, &pages_resident) != 2)
        pages_resident = 0;
    if (f)
        fclose(f);
    return (double)pages_resident * (double)sysconf(_SC_PAGESIZE) / (1024.0 * 1024.0);
}

static const char *scenes[] = {
    "{\"mesh\":{\"builtin\":\"sphere\"},\"width\":64,\"height\":64,\"projection_size\":64}",
    "{\"mesh\":{\"builtin\":\"torus\"},\"width\":64,\"height\":64,\"projection_size\":64,\"method\":\"single\"}",
};

/* Returns the growth (MiB) to frames 190..199 from frames 100..109 or from where the previous renderer's frames
 * 190..199 left the process (prev_late; 0 for the first), whichever is higher, each level the least RSS seen over
 * those frames: a leak raises it, while a driver's transient buffers come and go (llvmpipe's swing 1.6 MiB
 * between frames, and its caches grow for about 100 frames, then stay flat: measured over 1000). A renderer
 * climbing back to what the process held before is the driver refilling caches (OpenGL's second renderer
 * went 133.9 -> 137.0 MiB once, below the first one's 139.5). */
static double run_renderer(int round, double prev_late, double *late_rss, double *end_rss)
{
    lucent_renderer *r = test_renderer();
    double warm = 1e30, late = 1e30;
    for (int frame = 0; frame < 200; frame++) {
        lucent_image img;
        test_render(r, scenes[frame % 2], &img, NULL);
        lucent_image_free(&img);
        if (frame >= 100 && frame < 110)
            warm = fmin(warm, rss_mib());
        if (frame >= 190)
            late = fmin(late, rss_mib());
    }
    *late_rss = late;
    *end_rss = rss_mib();
    lucent_renderer_destroy(r);
    printf("     renderer %d: RSS at least %.1f MiB over frames 100..109, %.1f over 190..199, %.1f after 200, %.1f after "
           "destroy\n", round, warm, late, *end_rss, rss_mib());
    return late - fmax(warm, prev_late);
}

/* The mesh cache keeps within its byte budget by evicting the least recently used meshes, and refuses
 * a mesh that alone does not fit (a daemon sets the budget; uploads can be large). */
static void check_mesh_budget(void)
{
    static const char *const meshes[] = {"sphere", "torus", "protrusion"};
    const uint64_t budget = 4u << 20;
    lucent_renderer_desc desc = {.mesh_cache_bytes = budget};
    lucent_renderer *r = lucent_renderer_create(&desc, NULL);
    uint64_t peak = 0, first_device = 0, last_device = 0;
    int rendered = 0;
    for (int i = 0; i < 12; i++) {
        char json[200];
        snprintf(json, sizeof json, "{\"mesh\":{\"builtin\":\"%s\",\"triangles\":%d},\"width\":32,\"height\":32,"
                 "\"projection_size\":64}", meshes[i % 3], 20000 + 10000 * (i / 3));
        lucent_image img;
        lucent_stats stats;
        test_render(r, json, &img, &stats);
        lucent_image_free(&img);
        peak = stats.mesh_cache_bytes > peak ? stats.mesh_cache_bytes : peak;
        first_device = i == 0 ? stats.device_bytes : first_device;
        last_device = stats.device_bytes;
        rendered++;
    }
    test_check(peak <= budget, "%d meshes of 20k-50k triangles through a %.1f MiB mesh cache: at most %.2f MiB held",
               rendered, budget / 1048576.0, peak / 1048576.0);
    /* Evicted meshes give their device memory back: the last frame holds at most the first's plus the budget. */
    test_check(last_device <= first_device + budget, "device memory %.2f MiB after the first mesh, %.2f MiB after the "
               "12th (at most %.2f)", first_device / 1048576.0, last_device / 1048576.0,
               (first_device + budget) / 1048576.0);
    const char *big = "{\"mesh\":{\"builtin\":\"sphere\",\"triangles\":400000},\"width\":32,\"height\":32}";
    lucent_scene scene;
    lucent_scene_parse(big, strlen(big), 0, &scene, NULL);
    lucent_image img = {0};
    lucent_error err = {0};
    lucent_status st = lucent_render(r, &scene, &img, NULL, &err);
    lucent_image_free(&img);
    test_check(st == LUCENT_E_LIMIT && strcmp(err.field, "mesh") == 0, "a 400k-triangle mesh is refused: [%s] %s",
               err.field, err.message);
    lucent_stats stats;
    test_render(r, "{\"mesh\":{\"builtin\":\"torus\"},\"width\":32,\"height\":32}", &img, &stats);
    lucent_image_free(&img);
    test_check(stats.mesh_cache_bytes <= budget, "the renderer goes on afterwards (%.2f MiB held)",
               stats.mesh_cache_bytes / 1048576.0);
    lucent_renderer_destroy(r);
}

/* Each sample count is its own set of scatter pipelines (far, filter, compose), some MiB of generated
 * code on a CPU driver: only the most recently used are kept (pipeline_lru.h). */
static void check_pipeline_variants(void)
{
    lucent_renderer *r = test_renderer();
    double warm = 0.0;
    uint64_t first_bytes = 0;
    const int counts = 32;
    for (int samples = 1; samples <= counts; samples++) {
        char json[160];
        snprintf(json, sizeof json, "{\"mesh\":{\"builtin\":\"sphere\"},\"width\":32,\"height\":32,"
                 "\"projection_size\":64,\"samples\":%d}", samples);
        lucent_image img;
        lucent_stats stats;
        test_render(r, json, &img, &stats);
        lucent_image_free(&img);
        if (samples == 1)
            first_bytes = stats.device_bytes;
        if (samples == counts / 2)
            warm = rss_mib();
    }
    double growth = rss_mib() - warm;
    test_check(growth < 8.0, "sample counts %d..%d (%d new scatter pipelines): RSS grew %.2f MiB (limit 8)",
               counts / 2 + 1, counts, 3 * counts / 2, growth);
    /* A larger frame and back: its render targets are freed, the count comes back to the byte. */
    lucent_image img;
    lucent_stats big, back;
    test_render(r, "{\"mesh\":{\"builtin\":\"sphere\"},\"width\":256,\"height\":128,\"projection_size\":256}",
                &img, &big);
    lucent_image_free(&img);
    test_render(r, "{\"mesh\":{\"builtin\":\"sphere\"},\"width\":32,\"height\":32,\"projection_size\":64}",
                &img, &back);
    lucent_image_free(&img);
    test_check(big.device_bytes > first_bytes && back.device_bytes == first_bytes,
               "device memory %.2f MiB at 32^2, %.2f MiB at 256x128 (projection 256), %.2f MiB back at 32^2",
               first_bytes / 1048576.0, big.device_bytes / 1048576.0, back.device_bytes / 1048576.0);
    lucent_renderer_destroy(r);
}

int main(void)
{
    check_mesh_budget();
    check_pipeline_variants();
    double end[3], late[3];
    /* The first of the three warms the driver up: OpenGL's grew 3.7 MiB from frames 100..109 to 190..199 on a
     * slow CI machine and the next one came back 1.7 MiB lower, so only the second and third are held to it. */
    for (int i = 0; i < 3; i++) {
        double growth = run_renderer(i + 1, i ? late[i - 1] : 0.0, &late[i], &end[i]);
        if (i == 0)
            printf("     renderer 1 (the driver's warm-up) grew %.2f MiB to frames 190..199 from frames 100..109\n",
                   growth);
        else
            test_check(growth < 2.0, "renderer %d grew %.2f MiB to frames 190..199 from frames 100..109 or the "
                       "previous renderer's 190..199 (limit 2)", i + 1, growth);
    }
    /* lavapipe's code generator keeps a second slab the first time a renderer is re-created (about
     * 23 MiB, measured; it never frees JIT memory pools; here the checks above have re-created one
     * already); from then on create/destroy must be flat. */
    printf("     renderer 2 ends %.2f MiB above renderer 1\n", end[1] - end[0]);
    /* Levels over frames 190..199 (one sample at the end swings 1.6 MiB), against the higher of the two before:
     * OpenGL's driver ended renderer 2 5.5 MiB below renderer 1 and renderer 3 3.9 MiB above renderer 2 on a CI
     * machine, still below renderer 1: refilled caches, not a leak. */
    double before = fmax(late[0], late[1]);
    test_check(late[2] - before < 2.0, "renderer 3 over frames 190..199 is %.2f MiB above the higher of renderers 1 "
               "and 2 (limit 2)", late[2] - before);
    return test_finish();
}
