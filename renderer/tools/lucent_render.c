/* lucent_render.c - the one-shot command-line renderer: reads a scene document, renders it once with
 * liblucent and writes PNG or EXR; exit 0 on success, 1 on a rendering error, 2 on bad usage. */
#include "lucent.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_SCENE_BYTES (16u << 20)

static const char usage[] =
    "usage: lucent-render SCENE.json -o OUT.png|OUT.exr [--stats] [--compare REF.exr [--compare REF2.exr]\n"
    "                     [--twin T.exr]] [--backend B] [--device NAME] [--verbose]\n"
    "  SCENE.json   scene document (see README); '-' reads standard input\n"
    "  -o FILE      output image; the extension (.png or .exr) picks the format\n"
    "  --stats      print pass times and what was modelled, as JSON on standard output\n"
    "  --compare R  print the error of this render against the EXR R (written with exposure 0 and no\n"
    "               background, e.g. by method \"reference\"), as JSON on standard output; given twice\n"
    "               (two independent noisy truths, e.g. method \"path\" under two seeds), against their mean,\n"
    "               and as \"without_noise\" the error with their noise cancelled, its interval of 2\n"
    "               standard errors, and the noise of their mean\n"
    "  --twin T     with --compare twice: this render is itself noisy and T.exr an independent estimate of\n"
    "               the same image (e.g. the scene under another seed); \"compare\" is their mean's, and\n"
    "               \"without_noise\" cancels both sides' noise (\"test_noise\": that of their mean)\n"
    "  --backend B  vulkan, gl (OpenGL 4.5 through EGL) or auto (Vulkan, else OpenGL; the default, or\n"
    "               $LUCENT_BACKEND)\n"
    "  --device S   use the first device whose name contains S (else $LUCENT_DEVICE)\n"
    "  --verbose    log the chosen device and resource creation to standard error\n";

struct options {
    const char *scene_path, *out_path, *backend, *device, *compare_path[2], *twin_path;
    int stats, verbose;
};

static int parse_args(int argc, char **argv, struct options *o)
{
    memset(o, 0, sizeof *o);
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "-o") == 0 && i + 1 < argc)
            o->out_path = argv[++i];
        else if (strcmp(argv[i], "--compare") == 0 && i + 1 < argc && !o->compare_path[1])
            o->compare_path[o->compare_path[0] != NULL] = argv[++i];
        else if (strcmp(argv[i], "--twin") == 0 && i + 1 < argc && !o->twin_path)
            o->twin_path = argv[++i];
        else if (strcmp(argv[i], "--backend") == 0 && i + 1 < argc)
            o->backend = argv[++i];
        else if (strcmp(argv[i], "--device") == 0 && i + 1 < argc)
            o->device = argv[++i];
        else if (strcmp(argv[i], "--stats") == 0)
            o->stats = 1;
        else if (strcmp(argv[i], "--verbose") == 0)
            o->verbose = 1;
        else if ((argv[i][0] != '-' || strcmp(argv[i], "-") == 0) && !o->scene_path)
            o->scene_path = argv[i];
        else {
            fprintf(stderr, "lucent-render: unexpected argument \"%s\"\n", argv[i]);
            return -1;
        }
    }
    if (o->backend && !lucent_backend_valid(o->backend)) {
        fprintf(stderr, "lucent-render: --backend must be vulkan, gl or auto (got \"%s\")\n", o->backend);
        return -1;
    }
    if (o->twin_path && !o->compare_path[1]) {
        fputs("lucent-render: --twin needs --compare twice (two estimates of the truth)\n", stderr);
        return -1;
    }
    if (!o->scene_path || !o->out_path) {
        fprintf(stderr, "lucent-render: %s\n", !o->scene_path ? "no scene given" : "no output given (-o)");
        return -1;
    }
    return 0;
}

/* Reads a whole file (or stdin for "-") up to MAX_SCENE_BYTES; returns NULL on failure. */
static char *read_all(const char *path, size_t *len)
{
    FILE *f = strcmp(path, "-") == 0 ? stdin : fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = malloc(MAX_SCENE_BYTES + 1);
    size_t n = buf ? fread(buf, 1, MAX_SCENE_BYTES + 1, f) : 0;
    int bad = !buf || ferror(f) || n > MAX_SCENE_BYTES;
    if (f != stdin)
        fclose(f);
    if (bad) {
        free(buf);
        return NULL;
    }
    *len = n;
    return buf;
}

static int format_from_path(const char *path, lucent_format *out)
{
    const char *dot = strrchr(path, '.');
    if (dot && strcasecmp(dot, ".png") == 0)
        *out = LUCENT_FORMAT_PNG;
    else if (dot && strcasecmp(dot, ".exr") == 0)
        *out = LUCENT_FORMAT_EXR;
    else
        return -1;
    return 0;
}

/* Prints {"compare": {...}} for the rendered image against a reference EXR or, given two, against their
 * mean, with "without_noise": the error against the truth both estimate (lucent_image_compare_noisy); given
 * a twin of the render as well, for the mean of the two and with both sides' noise cancelled. */
static int print_comparison(const lucent_image *img, const char *const ref_path[2], const char *twin_path)
{
    lucent_image ref[2] = {{0}}, twin = {0};
    lucent_image_error e;
    lucent_noisy_error n = {0};
    lucent_error err = {0};
    char buf[1024];
    int ok = lucent_image_load(ref_path[0], &ref[0], &err) == LUCENT_OK &&
             (!ref_path[1] || lucent_image_load(ref_path[1], &ref[1], &err) == LUCENT_OK) &&
             (!twin_path || lucent_image_load(twin_path, &twin, &err) == LUCENT_OK) &&
             (!ref_path[1] ||
              (lucent_image_compare_noisy_pair(img, twin_path ? &twin : img, &ref[0], &ref[1], &n, &err) == LUCENT_OK &&
               lucent_image_average(&ref[0], &ref[1], &err) == LUCENT_OK)) &&
             (!twin_path || lucent_image_average(&twin, img, &err) == LUCENT_OK) &&
             lucent_image_compare(twin_path ? &twin : img, &ref[0], &e, &err) == LUCENT_OK &&
             lucent_image_error_json(&e, buf, sizeof buf) > 0;
    char test_noise[48] = "";
    if (twin_path)
        snprintf(test_noise, sizeof test_noise, ",\"test_noise\":%.6g", n.test_noise);
    if (ok && ref_path[1] && isfinite(n.noise))
        printf("{\"compare\":%s,\"without_noise\":{\"rel_l2\":%.6g,\"low\":%.6g,\"high\":%.6g,\"noise\":%.6g%s}}\n",
               buf, n.rel_l2, n.rel_l2_low, n.rel_l2_high, n.noise, test_noise);
    else if (ok && ref_path[1])  /* black truths: no relative error, and %g would print nan, not JSON */
        printf("{\"compare\":%s,\"without_noise\":null}\n", buf);
    else if (ok)
        printf("{\"compare\":%s}\n", buf);
    else
        fprintf(stderr, "lucent-render: cannot compare: %s\n", err.message);
    lucent_image_free(&ref[0]);
    lucent_image_free(&ref[1]);
    lucent_image_free(&twin);
    return ok ? 0 : -1;
}

static void report(const char *what, const lucent_error *err)
{
    fprintf(stderr, "lucent-render: %s: %s%s%s\n", what, err->field[0] ? err->field : "",
            err->field[0] ? ": " : "", err->message);
}

int main(int argc, char **argv)
{
    struct options o;
    if (parse_args(argc, argv, &o) != 0) {
        fputs(usage, stderr);
        return 2;
    }
    lucent_scene scene;
    lucent_format format;
    if (format_from_path(o.out_path, &format) != 0) {
        fprintf(stderr, "lucent-render: output \"%s\" must end in .png or .exr\n", o.out_path);
        return 2;
    }
    size_t len = 0;
    char *json = read_all(o.scene_path, &len);
    if (!json) {
        fprintf(stderr, "lucent-render: cannot read scene \"%s\" (missing, unreadable or over %u bytes)\n",
                o.scene_path, MAX_SCENE_BYTES);
        return 2;
    }
    lucent_error err = {0};
    lucent_status st = lucent_scene_parse(json, len, 1, &scene, &err);
    free(json);
    if (st != LUCENT_OK) {
        report("invalid scene", &err);
        return 2;
    }
    scene.format = format;

    int rc = 1;
    lucent_image img = {0};
    lucent_stats stats;
    lucent_renderer_desc desc = {.backend = o.backend, .device_name = o.device, .verbose = o.verbose};
    lucent_renderer *r = lucent_renderer_create(&desc, &err);
    if (!r) {
        report("cannot start the renderer", &err);
        return 1;
    }
    if (lucent_render(r, &scene, &img, &stats, &err) != LUCENT_OK) {
        report("render failed", &err);
        goto done;
    }
    if (lucent_image_write(o.out_path, &img, format, scene.exposure, scene.background, &err) != LUCENT_OK) {
        report("cannot write the image", &err);
        goto done;
    }
    if (o.stats) {
        char buf[4096];
        if (lucent_stats_json(&stats, buf, sizeof buf) > 0)
            puts(buf);
    }
    rc = o.compare_path[0] && print_comparison(&img, o.compare_path, o.twin_path) != 0 ? 1 : 0;
done:
    lucent_image_free(&img);
    lucent_renderer_destroy(r);
    lucent_shutdown();
    return rc;
}
