/* bench_trade.c - the measured speed/accuracy trade: every fast mode timed warm and scored against method
 * "reference" over 6 meshes x 4 lights x 4 materials x 2 sizes, and with --path against method "path" too
 * (every profile's reference as well); writes CSV, Markdown and plot tables. */
#include "bench_host.h"
#include "bench_median.h"
#include "bench_scene.h"
#include "flat_cube.h"
#include "lucent.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N(a) (sizeof(a) / sizeof((a)[0]))

/* A mode is a scene fragment added to the case (and a profile, DEFAULT: the scene's); one line here adds
 * it everywhere. Frames with single scattering are scored against a reference that has it too. */
struct mode {
    const char *name;
    const char *json;
    lucent_profile profile;
};

/* The cube is seen from above its front-right corner, so the camera sees its +X, +Y and +Z faces and
 * the edges between them. Every light below strikes exactly one face head-on (front: +Z, side: +X,
 * back: the hidden -Z) and leaves the others unlit, so what those show is light diffused around an
 * edge from a neighbouring face, which an image-space method finds only by crossing views. */
/* The slab, 50 x 50 x 3 mm and seen face-on, shows light through a thin part under the back light, and
 * the rim light comes from 130 degrees off the view direction (issue 11's transmission cases). */
enum { MESH_SPHERE, MESH_TORUS, MESH_PROTRUSION, MESH_BUNNY, MESH_CUBE, MESH_SLAB, MESH_COUNT };
enum { LIGHT_FRONT, LIGHT_SIDE, LIGHT_BACK, LIGHT_RIM };
static const struct mesh_case meshes[] = {
    [MESH_SPHERE] = {"sphere", "{\"builtin\":\"sphere\"}", ""},
    [MESH_TORUS] = {"torus", "{\"builtin\":\"torus\"}", ""},
    [MESH_PROTRUSION] = {"protrusion", "{\"builtin\":\"protrusion\"}", ""},
    [MESH_BUNNY] = {"bunny", NULL, ""},
    [MESH_CUBE] = {"cube", NULL, "\"camera\":{\"position\":[1.6,1.2,2.0],\"target\":[0,0,0]},"},
    [MESH_SLAB] = {"slab", NULL, "\"scale_mm\":50,"},
};

static const struct light_case lights[] = {[LIGHT_FRONT] = {"front", "[0,0,-1]"},
                                           [LIGHT_SIDE] = {"side", "[-1,0,0]"},
                                           [LIGHT_BACK] = {"back", "[0,0,1]"},
                                           [LIGHT_RIM] = {"rim", "[-0.766,0,0.643]"}};
static const char *const materials[] = {"marble", "skin1", "skimmilk", "ketchup"};
static const int sizes[] = {256, 512};
static const struct mode modes[] = {
    {"single", "\"method\":\"single\"", LUCENT_PROFILE_DEFAULT},
    {"five", "\"method\":\"five\"", LUCENT_PROFILE_DEFAULT},
    {"five per_channel", "\"method\":\"five\",\"sampling\":\"per_channel\"", LUCENT_PROFILE_DEFAULT},
    {"five samples 4", "\"method\":\"five\",\"samples\":4", LUCENT_PROFILE_DEFAULT},
    {"five samples 8", "\"method\":\"five\",\"samples\":8", LUCENT_PROFILE_DEFAULT},
    {"five samples 32", "\"method\":\"five\",\"samples\":32", LUCENT_PROFILE_DEFAULT},
    {"five samples 64", "\"method\":\"five\",\"samples\":64", LUCENT_PROFILE_DEFAULT},
    {"five projection 128", "\"method\":\"five\",\"projection_size\":128", LUCENT_PROFILE_DEFAULT},
    {"five projection 256", "\"method\":\"five\",\"projection_size\":256", LUCENT_PROFILE_DEFAULT},
    {"five projection 1024", "\"method\":\"five\",\"projection_size\":1024", LUCENT_PROFILE_DEFAULT},
    {"single samples 64", "\"method\":\"single\",\"samples\":64", LUCENT_PROFILE_DEFAULT},
    {"five fallback front", "\"method\":\"five\",\"fallback\":\"front\"", LUCENT_PROFILE_DEFAULT},
    {"auto", "\"method\":\"auto\"", LUCENT_PROFILE_DEFAULT},
    {"five single scattering", "\"method\":\"five\",\"single_scattering\":true", LUCENT_PROFILE_DEFAULT},
    {"five better_dipole", "\"method\":\"five\"", LUCENT_PROFILE_BETTER_DIPOLE},
    {"five burley", "\"method\":\"five\"", LUCENT_PROFILE_BURLEY},
    {"five asymptotic_dipole", "\"method\":\"five\"", LUCENT_PROFILE_ASYMPTOTIC_DIPOLE},
};

enum { MODES = (int)N(modes), CASES_PER_SIZE = (int)(N(meshes) * N(lights) * N(materials)) };
enum { T_TOTAL, T_SHADOW, T_PROJECTION, T_GBUFFER, T_SCATTER, T_READBACK, T_COUNT };

struct options {
    const char *prefix;
    int path_walks;                     /* --path: walks a pixel and channel of method "path"; 0: not rendered */
    const char *backend;                /* --backend; NULL: $LUCENT_BACKEND, else auto */
    const char *mesh_file[MESH_COUNT];  /* the meshes given as files: the bunny, and the cube and slab written here */
    char cube_path[4096], slab_path[4096];
    int frames, size_count;
    unsigned meshes, lights, modes;   /* selected (--meshes, --lights, --modes): bit i for meshes[i], ... */
};

struct case_id {
    int size, mesh, light, material;
};

/* An image against method "path": the measures against the walks' image, and rel L2 with the walks' noise
 * cancelled (lucent_image_compare_noisy against the two halves the image is the mean of). */
struct against_path {
    lucent_image_error e;
    lucent_noisy_error clean;
};

struct result {
    double ms[T_COUNT];  /* medians over the timed frames */
    lucent_image_error e;
    struct against_path path;  /* with --path */
};

/* With --path, per case: the walks' own noise and time, and every profile's reference against them, and
 * the dipole's with single scattering (Jensen et al.'s whole BSSRDF; the walks have every order). */
struct path_case {
    double noise, ms;
    struct against_path reference[LUCENT_PROFILE_DEFAULT];
    struct against_path reference_single;
};

/* Method "path" as two independent halves of the walks (seeds 1 and 2) and their mean, with AOVs. */
struct walks {
    lucent_image mean, half[2];
};

/* One mode at one size, summarized over every case (medians). */
struct summary {
    double ms, rel_l2, band_rel_l2, noise, low_frequency_rel_l2, mean_ratio;
    int worst, worst_band;  /* case indices */
    int pareto;
};
enum { SUMMARY_MEDIANS = 6 };

struct outputs {
    FILE *csv, *md, *tsv;
    FILE *path_csv, *path_tsv;   /* with --path */
    char device[sizeof(((lucent_stats *)0)->device)];   /* as the renders report it */
    const char *backend;
};

static struct case_id case_of(int index)
{
    struct case_id c;
    c.material = index % (int)N(materials);
    index /= (int)N(materials);
    c.light = index % (int)N(lights);
    index /= (int)N(lights);
    c.mesh = index % (int)N(meshes);
    c.size = index / (int)N(meshes);
    return c;
}

static int case_index(int size, int mesh, int light, int material)
{
    return ((size * (int)N(meshes) + mesh) * (int)N(lights) + light) * (int)N(materials) + material;
}

static void case_label(int index, char *buf, size_t cap)
{
    struct case_id c = case_of(index);
    snprintf(buf, cap, "%s %s %s", meshes[c.mesh].name, lights[c.light].name, materials[c.material]);
}

static int usage(void)
{
    fprintf(stderr, "usage: bench_trade [--quick] [--frames F] [--meshes M,...] [--lights L,...] [--modes M,...]\n"
                    "                   [--backend B] [--path WALKS] BUNNY.obj OUT_PREFIX\n"
                    "  writes OUT_PREFIX.csv, OUT_PREFIX.md, OUT_PREFIX_summary.tsv (for plot_trade.sh) and\n"
                    "  OUT_PREFIX_cube.obj and OUT_PREFIX_slab.obj (the meshes it writes and renders);\n"
                    "  --quick: 256x256 only (default 256 and 512); F: timed warm frames per mode (default 5);\n"
                    "  --meshes, --lights, --modes: only these (comma-separated names as in the report, default all;\n"
                    "  the paper's claim and the cube table need the side light and their modes);\n"
                    "  B: vulkan, gl or auto (bench_table2 compares backends within one run);\n"
                    "  --path: also render method path (boundary fresnel, WALKS walks a pixel and channel, even: two\n"
                    "  halves under seeds 1 and 2, so their noise cancels in the error) per case and score every\n"
                    "  mode and every profile's reference against it: OUT_PREFIX_path.csv,\n"
                    "  a section of OUT_PREFIX.md and OUT_PREFIX_path_summary.tsv (plot_trade.sh ... path)\n");
    return 2;
}

/* The bits of the comma-separated names in `list` among names[0..count); 0 if one is unknown. */
static unsigned parse_names(const char *list, const char *(*name_of)(int), int count)
{
    unsigned bits = 0;
    for (const char *at = list;; at++) {
        size_t len = strcspn(at, ",");
        int found = -1;
        for (int i = 0; i < count && found < 0; i++)
            if (strlen(name_of(i)) == len && strncmp(name_of(i), at, len) == 0)
                found = i;
        if (found < 0)
            return 0;
        bits |= 1u << found;
        at += len;
        if (*at == '\0')
            return bits;
    }
}

static const char *mesh_name(int i)
{
    return meshes[i].name;
}

static const char *light_name(int i)
{
    return lights[i].name;
}

static const char *mode_name(int i)
{
    return modes[i].name;
}

static int parse_options(int argc, char **argv, struct options *o)
{
    *o = (struct options){.frames = 5, .size_count = (int)N(sizes), .meshes = (1u << N(meshes)) - 1,
                          .lights = (1u << N(lights)) - 1,
                          .modes = (1u << MODES) - 1};
    int positional = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--quick") == 0) {
            o->size_count = 1;
        } else if (strcmp(argv[i], "--frames") == 0 && i + 1 < argc) {
            char *end;
            long f = strtol(argv[++i], &end, 10);
            if (*end || f < 1 || f > 1000)
                return -1;
            o->frames = (int)f;
        } else if (strcmp(argv[i], "--meshes") == 0 && i + 1 < argc) {
            if (!(o->meshes = parse_names(argv[++i], mesh_name, (int)N(meshes))))
                return -1;
        } else if (strcmp(argv[i], "--lights") == 0 && i + 1 < argc) {
            if (!(o->lights = parse_names(argv[++i], light_name, (int)N(lights))))
                return -1;
        } else if (strcmp(argv[i], "--backend") == 0 && i + 1 < argc) {
            if (!lucent_backend_valid(o->backend = argv[++i]))
                return -1;
        } else if (strcmp(argv[i], "--path") == 0 && i + 1 < argc) {
            char *end;
            long w = strtol(argv[++i], &end, 10);
            if (*end || w < 2 || w % 2 || w > (long)LUCENT_MAX_PATH_SAMPLES)
                return -1;
            o->path_walks = (int)w;
        } else if (strcmp(argv[i], "--modes") == 0 && i + 1 < argc) {
            if (!(o->modes = parse_names(argv[++i], mode_name, MODES)))
                return -1;
        } else if (positional == 0) {
            o->mesh_file[MESH_BUNNY] = argv[i], positional++;
        } else if (positional == 1) {
            o->prefix = argv[i], positional++;
        } else {
            return -1;
        }
    }
    return positional == 2 ? 0 : -1;
}

/* The scene of one case with the given fragment ("method" and knobs). */
static lucent_status make_scene(const struct options *o, struct case_id c, const char *fragment, lucent_scene *s,
                                lucent_error *err)
{
    return bench_scene(&meshes[c.mesh], o->mesh_file[c.mesh], materials[c.material], &lights[c.light], sizes[c.size],
                       fragment, s, err);
}

static void record_frame(const lucent_stats *st, double *t, int frames, int f)
{
    double v[T_COUNT] = {st->ms_total - st->ms_mesh_load, st->ms_shadow, st->ms_projection, st->ms_gbuffer,
                         st->ms_scatter, st->ms_readback};
    for (int k = 0; k < T_COUNT; k++)
        t[k * frames + f] = v[k];
}

/* One warm-up frame, then `frames` timed ones; the last is kept in *last (with its stats) to be scored. */
static lucent_status measure(lucent_renderer *r, const lucent_scene *s, int frames, lucent_image *last,
                             lucent_stats *last_stats, struct result *out, char *device, lucent_error *err)
{
    double *t = calloc((size_t)frames * T_COUNT, sizeof *t);
    if (!t)
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory for %d frame times", frames);
    lucent_status st = LUCENT_OK;
    for (int f = -1; f < frames && st == LUCENT_OK; f++) {
        lucent_image img;
        lucent_stats stats;
        st = lucent_render(r, s, &img, &stats, err);
        if (st != LUCENT_OK)
            break;
        if (f >= 0)
            record_frame(&stats, t, frames, f);
        memcpy(device, stats.device, sizeof stats.device);
        if (f == frames - 1) {
            *last = img;
            *last_stats = stats;
        } else {
            lucent_image_free(&img);
        }
    }
    for (int k = 0; k < T_COUNT && st == LUCENT_OK; k++)
        out->ms[k] = bench_median(t + k * frames, frames);
    free(t);
    return st;
}

static void write_csv_row(FILE *csv, int index, int mode, const struct result *x)
{
    struct case_id c = case_of(index);
    const lucent_image_error *e = &x->e;
    fprintf(csv,
            "%s,%s,%s,%d,%s,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%d,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%.6g,%.6g,%.6g,%.6g,"
            "%.6g,%.6g,%d,%.6g,%.6g\n",
            meshes[c.mesh].name, lights[c.light].name, materials[c.material], sizes[c.size], modes[mode].name,
            x->ms[T_TOTAL], x->ms[T_SHADOW], x->ms[T_PROJECTION], x->ms[T_GBUFFER], x->ms[T_SCATTER],
            x->ms[T_READBACK], e->object.pixels, e->coverage_mismatch, e->object.rel_l2, e->object.mean_abs,
            e->object.max_abs, e->object.p99_rel, e->object.share_over_10pct, e->band.pixels, e->band.rel_l2,
            e->band.mean_abs, e->band.max_abs, e->band.p99_rel, e->band.share_over_10pct, e->mean_ratio,
            e->interior_pixels, e->noise, e->low_frequency_rel_l2);
}

/* The reference of one case, with or without single scattering, for one diffusion profile. */
static lucent_status render_reference(lucent_renderer *r, const struct options *o, int index, int single,
                                      lucent_profile profile, lucent_image *ref, lucent_error *err)
{
    lucent_scene s;
    lucent_stats stats;
    lucent_status st = make_scene(o, case_of(index),
                                  single ? "\"method\":\"reference\",\"format\":\"exr\",\"single_scattering\":true"
                                         : "\"method\":\"reference\",\"format\":\"exr\"",
                                  &s, err);
    s.material.profile = profile;
    if (st == LUCENT_OK)
        st = lucent_render(r, &s, ref, &stats, err);
    if (st != LUCENT_OK)
        return st;
    char label[128];
    case_label(index, label, sizeof label);
    fprintf(stderr, "bench_trade: %d %s: reference%s, profile %s, %.0f ms\n", sizes[case_of(index).size], label,
            single ? " with single scattering" : "", lucent_profile_name(profile), stats.ms_total);
    return LUCENT_OK;
}

/* Method "path" for one case (boundary fresnel), half the walks with seed 1 and half with seed 2, their
 * mean, its noise (from the halves' difference) and the time of both. */
static lucent_status render_path(lucent_renderer *r, const struct options *o, int index, struct walks *w,
                                 struct path_case *pc, lucent_error *err)
{
    lucent_image *out[2] = {&w->mean, &w->half[1]};
    lucent_status st = LUCENT_OK;
    pc->ms = 0.0;
    for (int k = 0; k < 2 && st == LUCENT_OK; k++) {
        char fragment[128];
        snprintf(fragment, sizeof fragment,
                 "\"method\":\"path\",\"path\":{\"samples\":%d,\"seed\":%d},\"format\":\"exr\"", o->path_walks / 2,
                 k + 1);
        lucent_scene s;
        lucent_stats stats;
        st = make_scene(o, case_of(index), fragment, &s, err);
        if (st == LUCENT_OK)
            st = lucent_render(r, &s, out[k], &stats, err);
        pc->ms += st == LUCENT_OK ? stats.ms_total : 0.0;
    }
    if (st == LUCENT_OK)
        st = lucent_image_alloc(&w->half[0], w->mean.width, w->mean.height, 0, err);
    if (st != LUCENT_OK)
        return st;
    size_t values = (size_t)w->mean.width * w->mean.height * 4;
    memcpy(w->half[0].rgba, w->mean.rgba, values * sizeof *w->mean.rgba);
    lucent_noisy_error walks_noise = {.noise = NAN};
    st = lucent_image_average(&w->mean, &w->half[1], err);
    if (st == LUCENT_OK)
        st = lucent_image_compare_noisy(NULL, &w->half[0], &w->half[1], &walks_noise, err);
    pc->noise = walks_noise.noise;
    char label[128];
    case_label(index, label, sizeof label);
    fprintf(stderr, "bench_trade: %d %s: path, %d walks, %.0f ms, noise %.3g\n", sizes[case_of(index).size], label,
            o->path_walks, pc->ms, pc->noise);
    return st;
}

static lucent_status compare_to_walks(const lucent_image *test, const struct walks *w, struct against_path *out,
                                      lucent_error *err)
{
    lucent_status st = lucent_image_compare(test, &w->mean, &out->e, err);
    return st == LUCENT_OK ? lucent_image_compare_noisy(test, &w->half[0], &w->half[1], &out->clean, err) : st;
}

/* Renders every mode of one case, each scored against the reference of the profile it reports it
 * integrated (method auto chooses one), rendered when first needed, and with --path against the walks
 * too, as is every profile's reference; rows go to the CSV as they are measured. */
static lucent_status run_case(lucent_renderer *r, const struct options *o, int index, struct result *row,
                              struct path_case *pc, struct outputs *out, lucent_error *err)
{
    lucent_image ref[2][LUCENT_PROFILE_DEFAULT] = {{{0}}};
    struct walks path = {0};
    lucent_scene s;
    lucent_status st = o->path_walks ? render_path(r, o, index, &path, pc, err) : LUCENT_OK;
    for (int m = 0; m < MODES && st == LUCENT_OK; m++) {
        if (!(o->modes & 1u << m))
            continue;
        lucent_image last = {0};
        lucent_stats stats = {.profile = LUCENT_PROFILE_DIPOLE};
        st = make_scene(o, case_of(index), modes[m].json, &s, err);
        if (modes[m].profile != LUCENT_PROFILE_DEFAULT)
            s.material.profile = modes[m].profile;
        if (st == LUCENT_OK)
            st = measure(r, &s, o->frames, &last, &stats, &row[m], out->device, err);
        lucent_image *reference = st == LUCENT_OK ? &ref[stats.single_scattering][stats.profile] : NULL;
        if (st == LUCENT_OK && !reference->rgba)
            st = render_reference(r, o, index, stats.single_scattering, stats.profile, reference, err);
        if (st == LUCENT_OK)
            st = lucent_image_compare(&last, reference, &row[m].e, err);
        if (st == LUCENT_OK && o->path_walks)
            st = compare_to_walks(&last, &path, &row[m].path, err);
        lucent_image_free(&last);
        if (st == LUCENT_OK)
            write_csv_row(out->csv, index, m, &row[m]);
    }
    for (int p = 0; p < LUCENT_PROFILE_DEFAULT && o->path_walks && st == LUCENT_OK; p++) {
        if (!ref[0][p].rgba)
            st = render_reference(r, o, index, 0, (lucent_profile)p, &ref[0][p], err);
        if (st == LUCENT_OK)
            st = compare_to_walks(&ref[0][p], &path, &pc->reference[p], err);
    }
    lucent_image *with_single = &ref[1][LUCENT_PROFILE_DIPOLE];
    if (o->path_walks && st == LUCENT_OK && !with_single->rgba)
        st = render_reference(r, o, index, 1, LUCENT_PROFILE_DIPOLE, with_single, err);
    if (o->path_walks && st == LUCENT_OK)
        st = compare_to_walks(with_single, &path, &pc->reference_single, err);
    fflush(out->csv);
    for (int k = 0; k < 2 * LUCENT_PROFILE_DEFAULT; k++)
        lucent_image_free(&ref[k / LUCENT_PROFILE_DEFAULT][k % LUCENT_PROFILE_DEFAULT]);
    lucent_image_free(&path.mean);
    lucent_image_free(&path.half[0]);
    lucent_image_free(&path.half[1]);
    return st;
}

static int worse(const struct result *res, int a, int b, int mode, int band)
{
    const lucent_image_error *x = &res[a * MODES + mode].e, *y = &res[b * MODES + mode].e;
    return band ? x->band.rel_l2 > y->band.rel_l2 : x->object.rel_l2 > y->object.rel_l2;
}

static int case_selected(const struct options *o, int index)
{
    return (o->lights >> case_of(index).light) & (o->meshes >> case_of(index).mesh) & 1u;
}

static int cases_selected(const struct options *o)
{
    int n = 0;
    for (int i = 0; i < CASES_PER_SIZE; i++)
        n += case_selected(o, i);
    return n;
}

static struct summary summarize(const struct options *o, const struct result *res, int size, int mode, double *scratch)
{
    struct summary s = {0};
    int first = case_index(size, 0, 0, 0), n = 0;
    s.worst = s.worst_band = -1;
    double *v[SUMMARY_MEDIANS];
    for (int k = 0; k < SUMMARY_MEDIANS; k++)
        v[k] = scratch + k * CASES_PER_SIZE;
    for (int i = first; i < first + CASES_PER_SIZE; i++) {
        if (!case_selected(o, i))
            continue;
        const struct result *x = &res[i * MODES + mode];
        v[0][n] = x->ms[T_TOTAL], v[1][n] = x->e.object.rel_l2, v[2][n] = x->e.band.rel_l2;
        v[3][n] = x->e.noise, v[4][n] = x->e.low_frequency_rel_l2, v[5][n] = x->e.mean_ratio;
        n++;
        s.worst = s.worst < 0 || worse(res, i, s.worst, mode, 0) ? i : s.worst;
        s.worst_band = s.worst_band < 0 || worse(res, i, s.worst_band, mode, 1) ? i : s.worst_band;
    }
    double *median[SUMMARY_MEDIANS] = {&s.ms, &s.rel_l2, &s.band_rel_l2, &s.noise, &s.low_frequency_rel_l2,
                                       &s.mean_ratio};
    for (int k = 0; k < SUMMARY_MEDIANS; k++)
        *median[k] = bench_median(v[k], n);
    return s;
}

/* Pareto front on (median ms, median rel L2): no other mode is at least as fast and as accurate and
 * strictly better in one. */
static void mark_pareto(const struct options *o, struct summary *s)
{
    for (int i = 0; i < MODES; i++) {
        s[i].pareto = 1;
        for (int j = 0; j < MODES; j++)
            if ((o->modes & 1u << j) && s[j].ms <= s[i].ms && s[j].rel_l2 <= s[i].rel_l2 && (s[j].ms < s[i].ms || s[j].rel_l2 < s[i].rel_l2))
                s[i].pareto = 0;
    }
}

static void write_summary(const struct options *o, const struct result *res, const struct summary *s, int size,
                          const struct outputs *out)
{
    char worst[128], worst_band[128];
    emit(out->md, "\n### %dx%d\n\n| mode | median ms | median rel L2 | median band rel L2 | median noise "
                  "| median low-frequency rel L2 | median mean ratio | worst rel L2 (case) "
                  "| worst band rel L2 (case) | Pareto |\n|---|---|---|---|---|---|---|---|---|---|\n",
         sizes[size], sizes[size]);
    for (int m = 0; m < MODES; m++) {
        if (!(o->modes & 1u << m))
            continue;
        case_label(s[m].worst, worst, sizeof worst);
        case_label(s[m].worst_band, worst_band, sizeof worst_band);
        emit(out->md, "| %s | %.1f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f (%s) | %.4f (%s) | %s |\n", modes[m].name,
             s[m].ms, s[m].rel_l2, s[m].band_rel_l2, s[m].noise, s[m].low_frequency_rel_l2, s[m].mean_ratio,
             res[s[m].worst * MODES + m].e.object.rel_l2, worst, res[s[m].worst_band * MODES + m].e.band.rel_l2,
             worst_band, s[m].pareto ? "yes" : "");
        fprintf(out->tsv, "%d\t%s\t%.3f\t%.6g\t%.6g\t%d\n", sizes[size], modes[m].name, s[m].ms, s[m].rel_l2,
                s[m].band_rel_l2, s[m].pareto);
    }
}

static int mode_named(const char *name)
{
    for (int m = 0; m < MODES; m++)
        if (strcmp(modes[m].name, name) == 0)
            return m;
    return -1;
}

/* The paper's claim: five projection images fix the silhouette band that one image gets wrong on
 * side-lit protrusions. Band rel L2 of five vs single on the side-lit protrusion and bunny. */
static void write_claim(const struct options *o, const struct result *res, const struct outputs *out)
{
    static const int claim_meshes[] = {MESH_PROTRUSION, MESH_BUNNY};
    const int one = mode_named("single"), five = mode_named("five");
    char misses[1024] = "";
    size_t used = 0;
    emit(out->md, "\n### The paper's claim: five views beat one at the silhouette under a side light\n\n"
                  "| size | case | single band rel L2 | five band rel L2 | five/single | single rel L2 | five rel L2 "
                  "| five beats single (band) |\n|---|---|---|---|---|---|---|---|\n");
    for (int z = 0; z < o->size_count; z++)
        for (size_t k = 0; k < N(claim_meshes); k++)
            for (int mat = 0; mat < (int)N(materials); mat++) {
                int i = case_index(z, claim_meshes[k], LIGHT_SIDE, mat);
                const lucent_image_error *a = &res[i * MODES + one].e, *b = &res[i * MODES + five].e;
                int beats = b->band.rel_l2 < a->band.rel_l2;
                char label[128];
                case_label(i, label, sizeof label);
                emit(out->md, "| %d | %s | %.4f | %.4f | %.2f | %.4f | %.4f | %s |\n", sizes[z], label,
                     a->band.rel_l2, b->band.rel_l2, b->band.rel_l2 / a->band.rel_l2, a->object.rel_l2, b->object.rel_l2,
                     beats ? "yes" : "**no**");
                if (!beats && used < sizeof misses)
                    used += (size_t)snprintf(misses + used, sizeof misses - used, "%s%s at %d", used ? "; " : "",
                                             label, sizes[z]);
            }
    if (used)
        emit(out->md, "\nFive views do NOT beat one in the silhouette band for: %s.\n", misses);
    else
        emit(out->md, "\nFive views beat one in the silhouette band in every one of these cases.\n");
}

/* The cube lit on one face, side light: the edge-crossing case, per material, for the default method
 * and auto. */
static void write_cube(const struct options *o, const struct result *res, const struct outputs *out)
{
    const int shown[] = {mode_named("five"), mode_named("auto")};
    emit(out->md, "\n### The cube lit on one face (side light on +X; +Y and +Z lit only around the edges)\n\n"
                  "| size | case | mode | rel L2 | band rel L2 | noise | low-frequency rel L2 | mean ratio |\n"
                  "|---|---|---|---|---|---|---|---|\n");
    for (int z = 0; z < o->size_count; z++)
        for (int mat = 0; mat < (int)N(materials); mat++)
            for (size_t k = 0; k < N(shown); k++) {
                int i = case_index(z, MESH_CUBE, LIGHT_SIDE, mat);
                const lucent_image_error *e = &res[i * MODES + shown[k]].e;
                char label[128];
                case_label(i, label, sizeof label);
                emit(out->md, "| %d | %s | %s | %.4f | %.4f | %.4f | %.4f | %.4f |\n", sizes[z], label,
                     modes[shown[k]].name, e->object.rel_l2, e->band.rel_l2, e->noise, e->low_frequency_rel_l2,
                     e->mean_ratio);
            }
}

/* Both modes a table compares were measured. */
static int modes_selected(const struct options *o, const char *a, const char *b)
{
    return ((o->modes >> mode_named(a)) & 1u) && ((o->modes >> mode_named(b)) & 1u);
}

static void write_path_row(FILE *csv, int index, const char *what, const char *profile, const struct against_path *a,
                           const struct path_case *pc, double ms)
{
    struct case_id c = case_of(index);
    fprintf(csv, "%s,%s,%s,%d,%s,%s,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.3f\n", meshes[c.mesh].name,
            lights[c.light].name, materials[c.material], sizes[c.size], what, profile, a->e.object.rel_l2,
            a->clean.rel_l2, a->clean.rel_l2_low, a->clean.rel_l2_high, a->e.mean_ratio, pc->noise, ms);
}

/* One line of the table against path: medians over the selected cases of size z. what: a mode, or -1 - p
 * for profile p's reference, or WHAT_WALKS for the walks themselves, or WHAT_SINGLE for the dipole's
 * reference with single scattering. */
enum { WHAT_WALKS = -1 - LUCENT_PROFILE_DEFAULT, WHAT_SINGLE = -2 - LUCENT_PROFILE_DEFAULT };
static void write_path_line(const struct options *o, const struct result *res, const struct path_case *pcs, int z,
                            int what, double *scratch, const struct outputs *out)
{
    double *ms = scratch, *l2 = ms + CASES_PER_SIZE, *clean = l2 + CASES_PER_SIZE, *high = clean + CASES_PER_SIZE;
    double *ratio = high + CASES_PER_SIZE;
    int n = 0, resolved = 0, first = case_index(z, 0, 0, 0);
    for (int i = first; i < first + CASES_PER_SIZE; i++) {
        if (!case_selected(o, i))
            continue;
        const struct path_case *pc = &pcs[i];
        const struct against_path *a = what >= 0             ? &res[i * MODES + what].path
                                       : what == WHAT_SINGLE ? &pc->reference_single
                                                             : &pc->reference[-1 - what];
        int walks = what == WHAT_WALKS;
        ms[n] = what >= 0 ? res[i * MODES + what].ms[T_TOTAL] : walks ? pc->ms : 0.0;
        l2[n] = walks ? pc->noise : a->e.object.rel_l2;
        clean[n] = walks ? 0.0 : a->clean.rel_l2;
        high[n] = walks ? 0.0 : a->clean.rel_l2_high;
        resolved += !walks && a->clean.rel_l2_low > 0.0;
        ratio[n] = walks ? 1.0 : a->e.mean_ratio;
        n++;
    }
    char name[64];
    if (what >= 0)
        snprintf(name, sizeof name, "%s", modes[what].name);
    else if (what == WHAT_WALKS)
        snprintf(name, sizeof name, "path (its noise)");
    else if (what == WHAT_SINGLE)
        snprintf(name, sizeof name, "reference dipole + single scattering");
    else
        snprintf(name, sizeof name, "reference %s", lucent_profile_name((lucent_profile)(-1 - what)));
    int timed = what >= 0 || what == WHAT_WALKS;   /* the references are not timed here */
    double median_ms = timed ? bench_median(ms, n) : 0.0, median_clean = bench_median(clean, n);
    char ms_text[32] = "-";
    if (timed)
        snprintf(ms_text, sizeof ms_text, "%.1f", median_ms);
    emit(out->md, "| %s | %s | %.4f | %.4f | %.4f | %d of %d | %.4f |\n", name, ms_text, bench_median(l2, n),
         median_clean, bench_median(high, n), resolved, n, bench_median(ratio, n));
    if (what >= 0)
        fprintf(out->path_tsv, "%d\t%s\t%.3f\t%.6g\t%.6g\t0\n", sizes[z], name, median_ms, median_clean,
                bench_median(l2, n));
}

/* With --path: every mode and every profile's reference against the walks, per case (CSV) and as medians. */
static void write_path_report(const struct options *o, const struct result *res, const struct path_case *pcs,
                              const struct outputs *out, double *scratch)
{
    fprintf(out->path_csv, "scene,light,material,size,what,profile,rel_l2,rel_l2_without_noise,"
                          "without_noise_low,without_noise_high,mean_ratio,path_noise,ms\n");
    fprintf(out->path_tsv, "size\tmode\tms\trel_l2\tband_rel_l2\tpareto\n");
    for (int i = 0; i < o->size_count * CASES_PER_SIZE; i++) {
        if (!case_selected(o, i))
            continue;
        for (int m = 0; m < MODES; m++)
            if (o->modes & 1u << m)
                write_path_row(out->path_csv, i, modes[m].name, "", &res[i * MODES + m].path, &pcs[i],
                               res[i * MODES + m].ms[T_TOTAL]);
        for (int p = 0; p < LUCENT_PROFILE_DEFAULT; p++)
            write_path_row(out->path_csv, i, "reference", lucent_profile_name((lucent_profile)p), &pcs[i].reference[p],
                           &pcs[i], NAN);
        write_path_row(out->path_csv, i, "reference single scattering", "dipole", &pcs[i].reference_single, &pcs[i],
                       NAN);
    }
    emit(out->md, "\n## Against method \"path\" (%d walks a pixel and channel, boundary fresnel)\n\n"
                  "Medians over the same cases. The walks are two independent halves (seeds 1 and 2) and "
                  "\"rel L2\" is against their mean, which adds the walks' noise (the path row: ||(a - b) / 2|| / "
                  "||truth||); \"w/o noise\" is sqrt(sum (test - a).(test - b) / sum a.b), in which the halves' "
                  "noise cancels in expectation; \"high\" is the same with the sum 2 standard errors higher (its "
                  "spread over 64 lattices of every 8th pixel), a bound on the error; \"resolved\" counts the cases "
                  "whose error stands 2 standard errors above the noise (the rest read 0 or near it because the "
                  "walks cannot tell). The modes' mean ratio is their mean radiance over the walks'.\n",
         o->path_walks);
    for (int z = 0; z < o->size_count; z++) {
        emit(out->md, "\n### %dx%d against path\n\n| mode | median ms | median rel L2 | median w/o noise "
                      "| median high | resolved | median mean ratio |\n|---|---|---|---|---|---|---|\n", sizes[z], sizes[z]);
        write_path_line(o, res, pcs, z, WHAT_WALKS, scratch, out);
        for (int p = 0; p < LUCENT_PROFILE_DEFAULT; p++)
            write_path_line(o, res, pcs, z, -1 - p, scratch, out);
        write_path_line(o, res, pcs, z, WHAT_SINGLE, scratch, out);
        for (int m = 0; m < MODES; m++)
            if (o->modes & 1u << m)
                write_path_line(o, res, pcs, z, m, scratch, out);
    }
}

static void write_report(const struct options *o, const struct result *res, const struct path_case *pcs,
                         const struct outputs *out, double *scratch)
{
    char names[256] = "";
    int mesh_count = 0, light_count = 0;
    for (size_t m = 0, used = 0; m < N(meshes) && used < sizeof names; m++)
        if ((o->meshes >> m) & 1u)
            used += (size_t)snprintf(names + used, sizeof names - used, "%s%s", mesh_count++ ? ", " : "",
                                     meshes[m].name);
    for (size_t l = 0; l < N(lights); l++)
        light_count += (int)((o->lights >> l) & 1u);
    char cpu[256];
    cpu_model(cpu, sizeof cpu);
    emit(out->md, "## Speed/accuracy trade against method \"reference\"\n\nCPU: %s; backend %s, device: %s.\n\n", cpu,
         out->backend, out->device);
    emit(out->md, "Per mode: median over %d cases (%d meshes: %s; x %d lights x %d materials) of the warm frame "
                  "time (median of %d frames after 1 warm-up), of the relative L2 error, whole object and "
                  "silhouette band (normal 70-90 degrees from the view), of the noise (high-pass error "
                  "||hp(test) - hp(ref)|| / ||ref||, hp = x - box3x3(x)), the low-frequency error (relative L2 "
                  "of both images blurred by a 5x5 box) and the mean ratio (test's mean radiance over the "
                  "reference's); worst case; on the Pareto front of (median ms, median rel L2). The cube is "
                  "seen from above its front-right corner (+X, +Y, +Z faces), each light striking one face; "
                  "the slab (50 x 50 x 3 mm) face-on; the rim light 130 degrees from the view direction.\n",
         cases_selected(o), mesh_count, names, light_count, (int)N(materials), o->frames);
    fprintf(out->tsv, "size\tmode\tms\trel_l2\tband_rel_l2\tpareto\n");
    for (int z = 0; z < o->size_count; z++) {
        struct summary s[MODES];
        for (int m = 0; m < MODES; m++)
            s[m] = summarize(o, res, z, m, scratch);
        mark_pareto(o, s);
        write_summary(o, res, s, z, out);
    }
    int side = (o->lights >> LIGHT_SIDE) & 1u;
    if (side && modes_selected(o, "single", "five") && (o->meshes >> MESH_PROTRUSION) & (o->meshes >> MESH_BUNNY) & 1u)
        write_claim(o, res, out);
    if (side && modes_selected(o, "five", "auto") && (o->meshes >> MESH_CUBE) & 1u)
        write_cube(o, res, out);
    if (o->path_walks)
        write_path_report(o, res, pcs, out, scratch);
}

static int open_outputs(const char *prefix, int with_path, struct outputs *out)
{
    static const char *const suffix[5] = {".csv", ".md", "_summary.tsv", "_path.csv", "_path_summary.tsv"};
    FILE *f[5] = {NULL, NULL, NULL, NULL, NULL};
    int rc = bench_open_files(prefix, suffix, f, with_path ? 5 : 3);
    out->csv = f[0], out->md = f[1], out->tsv = f[2], out->path_csv = f[3], out->path_tsv = f[4];
    if (rc != 0)
        return -1;
    fprintf(out->csv, "scene,light,material,size,mode,ms,ms_shadow,ms_projection,ms_gbuffer,ms_scatter,ms_readback,"
                      "pixels,coverage_mismatch,rel_l2,mean_abs,max_abs,p99_rel,share_over_10pct,band_pixels,"
                      "band_rel_l2,band_mean_abs,band_max_abs,band_p99_rel,band_share_over_10pct,mean_ratio,"
                      "interior_pixels,noise,low_frequency_rel_l2\n");
    return 0;
}

/* Closes every output; -1 if any failed to open or write. */
static int close_outputs(struct outputs *out)
{
    FILE *f[5] = {out->csv, out->md, out->tsv, out->path_csv, out->path_tsv};
    return bench_close_files(f, 5);
}

static int run(lucent_renderer *r, const struct options *o, struct result *res, struct path_case *pcs,
               struct outputs *out)
{
    lucent_error err = {0};
    for (int i = 0; i < o->size_count * CASES_PER_SIZE; i++)
        if (case_selected(o, i) && run_case(r, o, i, &res[i * MODES], &pcs[i], out, &err) != LUCENT_OK) {
            char label[128];
            case_label(i, label, sizeof label);
            fprintf(stderr, "bench_trade: %d %s: %s%s%s\n", sizes[case_of(i).size], label, err.field,
                    err.field[0] ? ": " : "", err.message);
            return -1;
        }
    double scratch[SUMMARY_MEDIANS * CASES_PER_SIZE];
    write_report(o, res, pcs, out, scratch);
    return 0;
}

int main(int argc, char **argv)
{
    struct options o;
    if (parse_options(argc, argv, &o) != 0)
        return usage();
    if (bench_write_obj(o.prefix, "cube", flat_cube_obj, o.cube_path, sizeof o.cube_path) != 0 ||
        bench_write_obj(o.prefix, "slab", flat_slab_obj, o.slab_path, sizeof o.slab_path) != 0)
        return 2;
    o.mesh_file[MESH_CUBE] = o.cube_path;
    o.mesh_file[MESH_SLAB] = o.slab_path;
    if (bench_paths_fit(o.mesh_file, MESH_COUNT, "bench_trade") != 0)
        return 2;
    struct outputs out = {0};
    struct result *res = calloc((size_t)o.size_count * CASES_PER_SIZE * MODES, sizeof *res);
    struct path_case *pcs = calloc((size_t)o.size_count * CASES_PER_SIZE, sizeof *pcs);
    lucent_error err = {0};
    lucent_renderer_desc desc = {.backend = o.backend, .verbose = 0};
    lucent_renderer *r = NULL;
    int rc = 1;
    if (!res || !pcs)
        fprintf(stderr, "bench_trade: out of memory\n");
    else if (!(r = lucent_renderer_create(&desc, &err)))
        fprintf(stderr, "bench_trade: %s\n", err.message);
    else if ((out.backend = lucent_renderer_backend(r)) && open_outputs(o.prefix, o.path_walks > 0, &out) == 0 &&
             run(r, &o, res, pcs, &out) == 0)
        rc = 0;
    if (close_outputs(&out) != 0 && rc == 0) {
        fprintf(stderr, "bench_trade: writing %s.* failed\n", o.prefix);
        rc = 1;
    }
    lucent_renderer_destroy(r);
    free(res);
    free(pcs);
    lucent_shutdown();
    return rc;
}
