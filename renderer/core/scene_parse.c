/* scene_parse.c - turns a scene document (scene file or HTTP body, one schema) into a checked lucent_scene.
 * Nothing is clamped or guessed: every wrong, unknown or out-of-range value is an error naming its JSON path. */
#define _POSIX_C_SOURCE 200809L
#include "lucent.h"
#include "linalg.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

/* Status policy. LUCENT_E_LIMIT: a well-formed integer size above what this service is willing
 * to spend on one request (width, height, samples, projection_size, mesh.triangles above their
 * maximum, more than LUCENT_MAX_LIGHTS lights); a bigger server could raise those caps.
 * LUCENT_E_INVALID: everything else - malformed JSON, unknown keys, wrong types, non-integers
 * where integers are required, and any value outside its range, including integers below
 * their minimum - the request itself is wrong, whatever the server's capacity. */

#define PATH_CAP sizeof(((lucent_error *)0)->field)
#define SHOWN_CAP 48 /* bytes of user text (keys, strings) quoted in a path or message */

typedef struct range {
    double lo, hi;
    int open;        /* 1: lo and hi themselves are excluded */
    const char *why; /* appended to the error message when the reason is not obvious */
} range;

/* Every limit the schema enforces, in one place (mirrored in the README). */
static const range R_SCALE_MM = {LUCENT_MIN_SCALE_MM, LUCENT_MAX_SCALE_MM, 0,
                                 "omit scale_mm for automatic scale"};
static const range R_SIGMA_A = {0.0, LUCENT_MAX_SIGMA, 0, NULL};
static const range R_SIGMA_S_PRIME = {LUCENT_MIN_SIGMA_S_PRIME, LUCENT_MAX_SIGMA, 0, NULL};
/* 0.9 looks like a plausible ratio (an object under water), so the message says why not. */
static const range R_ETA = {LUCENT_MIN_ETA, LUCENT_MAX_ETA, 0,
                            "eta is n_inside / n_outside, and below 1 the dipole's diffuse "
                            "Fresnel fit goes negative"};
/* Coordinates are bounded so that differences and squared lengths stay finite in double;
 * 1e15 scene units is far beyond what the float GPU pipeline can resolve anyway. */
static const range R_COORD = {-LUCENT_MAX_COORD, LUCENT_MAX_COORD, 0, NULL};
static const range R_COLOR = {0.0, LUCENT_MAX_COLOR, 0, NULL};
static const range R_ALPHA = {0.0, 1.0, 0, NULL};
static const range R_INTENSITY = {0.0, LUCENT_MAX_INTENSITY, 0, NULL};
/* tan(fov/2) degenerates at 0 and 180 degrees; the ends are excluded. */
static const range R_FOV_DEG = {LUCENT_MIN_FOV_DEG, LUCENT_MAX_FOV_DEG, 1, NULL};
static const range R_EXPOSURE = {-LUCENT_MAX_EXPOSURE, LUCENT_MAX_EXPOSURE, 0, NULL};
static const range R_SIDE = {1, LUCENT_MAX_IMAGE_SIDE, 0, NULL};
static const range R_SAMPLES = {1, LUCENT_MAX_SAMPLES, 0, NULL};
static const range R_PROJECTION = {LUCENT_MIN_PROJECTION_SIZE, LUCENT_MAX_PROJECTION_SIZE, 0, NULL};
static const range R_TRIANGLES = {0, LUCENT_MAX_BUILTIN_TRIANGLES, 0, NULL};
static const range R_G = {-LUCENT_MAX_G, LUCENT_MAX_G, 0, "sigma_s = sigma_s' / (1 - g) diverges as |g| nears 1"};

#define DEFAULT_SIDE 512
#define DEFAULT_SAMPLES 16
#define DEFAULT_PATH_SAMPLES 16   /* walks per pixel and channel of method "path" */
#define DEFAULT_PROJECTION 512
#define DEFAULT_FOV_DEG 40.0
/* The automatic camera's default: from the front left and above, as model viewers frame an object, so
 * that a box shows three faces and the default key light (from the upper right front) models it. */
#define DEFAULT_VIEW_AZIMUTH_DEG 35.0
#define DEFAULT_VIEW_ELEVATION_DEG 25.0
#define DEFAULT_ETA 1.3
/* Sine of the smallest angle allowed between camera.up and the view direction. It is the bound
 * view_frame_look() applies at render time; checking it here fails the request before it queues. */
#define MIN_UP_SINE 1.0e-9

/* Name tables are indexed by the enum they map to and end with NULL. */
static const char *const builtin_names[] = {"sphere", "torus", "protrusion", "bunny", NULL};
#define SCANNED_BUILTIN "bunny" /* one density: mesh.triangles does not apply */
static const char *const light_type_names[] = {
    [LUCENT_LIGHT_DIRECTIONAL] = "directional", [LUCENT_LIGHT_POINT] = "point", NULL};
static const char *const method_names[] = {
    [LUCENT_METHOD_FIVE] = "five", [LUCENT_METHOD_SINGLE] = "single", [LUCENT_METHOD_REFERENCE] = "reference",
    [LUCENT_METHOD_AUTO] = "auto", [LUCENT_METHOD_PATH] = "path", NULL};
static const char *const path_boundary_names[] = {
    [LUCENT_PATH_FRESNEL] = "fresnel", [LUCENT_PATH_CYCLES] = "cycles", NULL};
static const char *const path_filter_names[] = {
    [LUCENT_PATH_FILTER_POINT] = "point", [LUCENT_PATH_FILTER_BOX] = "box", NULL};
static const char *const profile_names[] = {
    [LUCENT_PROFILE_DIPOLE] = "dipole", [LUCENT_PROFILE_BETTER_DIPOLE] = "better_dipole",
    [LUCENT_PROFILE_BURLEY] = "burley", [LUCENT_PROFILE_ASYMPTOTIC_DIPOLE] = "asymptotic_dipole",
    [LUCENT_PROFILE_DEFAULT] = NULL};
static const char *const fallback_names[] = {
    [LUCENT_FALLBACK_NEXT_BEST] = "next_best", [LUCENT_FALLBACK_FRONT] = "front", NULL};
/* Fields method "auto" chooses itself; giving one with it is a conflict, not silently ignored. */
static const char *const auto_chosen_keys[] = {"samples", "sampling", "projection_size", "side_projection_size",
                                               NULL};
static const char *const sampling_names[] = {
    [LUCENT_SAMPLING_SHARED] = "shared", [LUCENT_SAMPLING_PER_CHANNEL] = "per_channel", NULL};
static const char *const format_names[] = {
    [LUCENT_FORMAT_PNG] = "png", [LUCENT_FORMAT_EXR] = "exr", NULL};

static const char *const top_keys[] = {"mesh", "scale_mm", "material", "lights", "camera",
                                       "width", "height", "method", "samples", "sampling",
                                       "projection_size", "side_projection_size", "background",
                                       "exposure", "format", "reference", "path", "fallback",
                                       "single_scattering", NULL};
static const char *const reference_keys[] = {"points", "threshold", NULL};
static const char *const path_keys[] = {"samples", "time_s", "boundary", "filter", "seed", NULL};
static const char *const mesh_keys[] = {"builtin", "triangles", "file", "id", NULL};
static const char *const material_keys[] = {"preset", "sigma_a", "sigma_s_prime", "eta", "g", "profile", NULL};
static const char *const directional_keys[] = {"type", "direction", "color", "intensity", NULL};
static const char *const point_keys[] = {"type", "position", "color", "intensity", NULL};
static const char *const camera_keys[] = {"position", "target", "direction", "up", "fov_deg", NULL};

const char *lucent_profile_name(lucent_profile p)
{
    return p >= LUCENT_PROFILE_DIPOLE && p < LUCENT_PROFILE_DEFAULT ? profile_names[p] : "dipole";
}

/* ---- Text for messages ---- */

/* Copies at most max bytes of s as printable ASCII, anything else as '?': messages end up in
 * JSON responses and logs, and a byte cut out of a UTF-8 sequence would make them invalid. */
static void printable(const char *s, size_t max, char *out, size_t cap)
{
    size_t n = 0;
    for (; n < max && n + 1 < cap && s[n]; n++)
        out[n] = s[n] >= 0x20 && s[n] < 0x7f ? s[n] : '?';
    out[n] = '\0';
}

/* Shortest form that reads back as x, so a message shows the value the user sent. */
static void format_number(double x, char *buf, size_t cap)
{
    snprintf(buf, cap, "%.15g", x);
    if (strtod(buf, NULL) != x)
        snprintf(buf, cap, "%.17g", x);
}

/* What a value is, for the "(got ...)" part of a message. */
static void describe(const json_t *v, char *buf, size_t cap)
{
    char text[SHOWN_CAP + 1];
    switch (json_typeof(v)) {
    case JSON_INTEGER:
        snprintf(buf, cap, "%" JSON_INTEGER_FORMAT, json_integer_value(v));
        break;
    case JSON_REAL:
        format_number(json_real_value(v), buf, cap);
        break;
    case JSON_STRING:
        printable(json_string_value(v), SHOWN_CAP, text, sizeof text);
        snprintf(buf, cap, "the string \"%s%s\"", text,
                 json_string_length(v) > SHOWN_CAP ? "..." : "");
        break;
    case JSON_ARRAY:
        snprintf(buf, cap, "an array of %zu elements", json_array_size(v));
        break;
    case JSON_OBJECT:
        snprintf(buf, cap, "an object");
        break;
    case JSON_TRUE:
        snprintf(buf, cap, "true");
        break;
    case JSON_FALSE:
        snprintf(buf, cap, "false");
        break;
    case JSON_NULL:
        snprintf(buf, cap, "null");
        break;
    }
}

/* "a", "b", "c" */
static void join_names(const char *const names[], char *buf, size_t cap)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; names[i] && used < cap; i++) {
        int n = snprintf(buf + used, cap - used, "%s\"%s\"", i ? ", " : "", names[i]);
        if (n < 0)
            return;
        used += (size_t)n;
    }
}

/* The longest path built here is "lights[3]." plus a SHOWN_CAP key plus "[2]", well inside
 * PATH_CAP; the precisions below never cut anything, they let the compiler see that. */
static void path_key(char out[PATH_CAP], const char *parent, const char *key)
{
    char shown[SHOWN_CAP + 1];
    printable(key, SHOWN_CAP, shown, sizeof shown);
    snprintf(out, PATH_CAP, "%.40s%s%s", parent, parent[0] ? "." : "", shown);
}

static void path_index(char out[PATH_CAP], const char *parent, size_t i)
{
    snprintf(out, PATH_CAP, "%.70s[%zu]", parent, i);
}

/* ---- Typed readers. Each reads member `key` of obj (at `parent`); an absent member
 * leaves *out at its default and succeeds, an explicit null is a wrong type. ---- */

static lucent_status fail_range(const json_t *v, const char *path, lucent_status status,
                                const char *kind, const range *r, lucent_error *err)
{
    char got[96], lo[32], hi[32];
    describe(v, got, sizeof got);
    format_number(r->lo, lo, sizeof lo);
    format_number(r->hi, hi, sizeof hi);
    return lucent_fail(err, status, path, "must be %s %s %s and %s%s (got %s)%s%s", kind,
                       r->open ? "greater than" : "between", lo, r->open ? "less than " : "", hi,
                       got, r->why ? "; " : "", r->why ? r->why : "");
}

static int in_range(double x, const range *r)
{
    return r->open ? x > r->lo && x < r->hi : x >= r->lo && x <= r->hi;
}

static lucent_status check_number(const json_t *v, const char *path, const range *r, double *out,
                                  lucent_error *err)
{
    /* jansson already refuses NaN, Infinity and overflowing literals; isfinite keeps this code
     * correct even if a future decode flag lets one through. */
    double x = json_is_number(v) ? json_number_value(v) : NAN;
    if (!isfinite(x) || !in_range(x, r))
        return fail_range(v, path, LUCENT_E_INVALID, "a number", r, err);
    *out = x + 0.0; /* -0 becomes 0, so later sign tests see a plain zero */
    return LUCENT_OK;
}

/* JSON has one number type, so 512.0 is the integer 512; 1.5 is not an integer. */
static lucent_status check_int(const json_t *v, const char *path, const range *r, int *out,
                               lucent_error *err)
{
    double x = json_is_number(v) ? json_number_value(v) : NAN;
    int integral = isfinite(x) && x == floor(x);
    if (integral && in_range(x, r)) {
        *out = (int)x;
        return LUCENT_OK;
    }
    return fail_range(v, path, integral && x > r->hi ? LUCENT_E_LIMIT : LUCENT_E_INVALID,
                      "an integer", r, err);
}

static lucent_status get_number(const json_t *obj, const char *parent, const char *key,
                                const range *r, double *out, lucent_error *err)
{
    char path[PATH_CAP];
    const json_t *v = json_object_get(obj, key);
    if (!v)
        return LUCENT_OK;
    path_key(path, parent, key);
    return check_number(v, path, r, out, err);
}

static lucent_status get_int(const json_t *obj, const char *parent, const char *key,
                             const range *r, int *out, lucent_error *err)
{
    char path[PATH_CAP];
    const json_t *v = json_object_get(obj, key);
    if (!v)
        return LUCENT_OK;
    path_key(path, parent, key);
    return check_int(v, path, r, out, err);
}

/* An array of exactly n numbers, each within r. */
static lucent_status get_vec(const json_t *obj, const char *parent, const char *key, size_t n,
                             const range *r, double *out, lucent_error *err)
{
    char path[PATH_CAP], elem[PATH_CAP];
    const json_t *v = json_object_get(obj, key);
    if (!v)
        return LUCENT_OK;
    path_key(path, parent, key);
    if (!json_is_array(v) || json_array_size(v) != n) {
        char got[96];
        describe(v, got, sizeof got);
        return lucent_fail(err, LUCENT_E_INVALID, path, "must be an array of %zu numbers (got %s)",
                           n, got);
    }
    for (size_t i = 0; i < n; i++) {
        path_index(elem, path, i);
        lucent_status st = check_number(json_array_get(v, i), elem, r, &out[i], err);
        if (st != LUCENT_OK)
            return st;
    }
    return LUCENT_OK;
}

static lucent_status fail_not_one_of(const json_t *v, const char *path, const char *const names[],
                                     lucent_error *err)
{
    char got[96], list[200];
    describe(v, got, sizeof got);
    join_names(names, list, sizeof list);
    return lucent_fail(err, LUCENT_E_INVALID, path, "must be one of %s (got %s)", list, got);
}

/* A string naming one of names (case-insensitive); *index is its position there. */
static lucent_status get_enum(const json_t *obj, const char *parent, const char *key,
                              const char *const names[], int *index, lucent_error *err)
{
    char path[PATH_CAP];
    const json_t *v = json_object_get(obj, key);
    if (!v)
        return LUCENT_OK;
    const char *s = json_string_value(v);
    for (int i = 0; s && names[i]; i++) {
        if (strcasecmp(s, names[i]) == 0) {
            *index = i;
            return LUCENT_OK;
        }
    }
    path_key(path, parent, key);
    return fail_not_one_of(v, path, names, err);
}

static lucent_status require(const json_t *obj, const char *parent, const char *key,
                             const char *when, lucent_error *err)
{
    char path[PATH_CAP];
    if (json_object_get(obj, key))
        return LUCENT_OK;
    path_key(path, parent, key);
    return lucent_fail(err, LUCENT_E_INVALID, path, "is required %s", when);
}

static lucent_status require_object(const json_t *v, const char *path, lucent_error *err)
{
    char got[96];
    if (json_is_object(v))
        return LUCENT_OK;
    describe(v, got, sizeof got);
    return lucent_fail(err, LUCENT_E_INVALID, path, "must be an object (got %s)", got);
}

static int is_listed(const char *key, const char *const names[])
{
    for (int i = 0; names[i]; i++)
        if (strcmp(key, names[i]) == 0)
            return 1;
    return 0;
}

/* A misspelt key must not silently leave its value at the default. */
static lucent_status check_known_keys(json_t *obj, const char *const allowed[], const char *path,
                                      lucent_error *err)
{
    for (void *it = json_object_iter(obj); it; it = json_object_iter_next(obj, it)) {
        const char *key = json_object_iter_key(it);
        if (is_listed(key, allowed))
            continue;
        char where[PATH_CAP], shown[SHOWN_CAP + 1], list[200];
        path_key(where, path, key);
        printable(key, SHOWN_CAP, shown, sizeof shown);
        join_names(allowed, list, sizeof list);
        return lucent_fail(err, LUCENT_E_INVALID, where, "unknown key \"%s\"; allowed %s%s: %s",
                           shown, path[0] ? "in " : "at the top level", path, list);
    }
    return LUCENT_OK;
}

/* ---- Vectors ---- */

/* Unit vector along v, scaled first so tiny or huge components neither underflow nor overflow.
 * Returns 0 for the zero vector. */
static int normalize3(const double v[3], double out[3])
{
    double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    if (m == 0.0)
        return 0;
    double x = v[0] / m, y = v[1] / m, z = v[2] / m;
    double len = sqrt(x * x + y * y + z * z);
    out[0] = x / len;
    out[1] = y / len;
    out[2] = z / len;
    return 1;
}

/* Length of the cross product of two unit vectors: the sine of the angle between them. */
static double cross_length(const double a[3], const double b[3])
{
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    return sqrt(x * x + y * y + z * z);
}

/* ---- Sections ---- */

static lucent_status parse_mesh_file(json_t *obj, int allow_files, lucent_mesh_ref *m,
                                     lucent_error *err)
{
    const json_t *v = json_object_get(obj, "file");
    if (!allow_files) {
        char list[100];
        join_names(builtin_names, list, sizeof list);
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.file",
                           "files on this machine are not accepted here; use \"builtin\" (one of "
                           "%s)",
                           list);
    }
    if (json_object_get(obj, "triangles"))
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.triangles",
                           "only applies to a builtin mesh, not to \"file\"");
    if (!json_is_string(v) || json_string_length(v) == 0 ||
        json_string_length(v) >= sizeof m->file) {
        char got[96];
        describe(v, got, sizeof got);
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.file",
                           "must be a path of 1 to %zu bytes (got %s)", sizeof m->file - 1, got);
    }
    m->source = LUCENT_MESH_FILE;
    m->builtin[0] = '\0';
    m->triangles = 0;
    snprintf(m->file, sizeof m->file, "%s", json_string_value(v));
    return LUCENT_OK;
}

/* Ids are checked to be exactly lowercase hex of a sha256, so one can never name a path. */
static lucent_status parse_mesh_id(json_t *obj, lucent_mesh_ref *m, lucent_error *err)
{
    const json_t *v = json_object_get(obj, "id");
    const char *id = json_is_string(v) ? json_string_value(v) : "";
    size_t n = json_is_string(v) ? json_string_length(v) : 0;
    int ok = n == LUCENT_MESH_ID_LEN;
    for (size_t i = 0; ok && i < n; i++)
        ok = (id[i] >= '0' && id[i] <= '9') || (id[i] >= 'a' && id[i] <= 'f');
    if (!ok) {
        char got[96];
        describe(v, got, sizeof got);
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.id",
                           "must be the %d lowercase hex digits of an uploaded mesh's sha256 (got %s)",
                           LUCENT_MESH_ID_LEN, got);
    }
    if (json_object_get(obj, "triangles"))
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.triangles",
                           "only applies to a builtin mesh, not to \"id\"");
    memset(m, 0, sizeof *m);
    m->source = LUCENT_MESH_STORED;
    memcpy(m->id, id, LUCENT_MESH_ID_LEN + 1);
    return LUCENT_OK;
}

static lucent_status parse_mesh_builtin(json_t *obj, lucent_mesh_ref *m, lucent_error *err)
{
    int index = 0, triangles = 0;
    lucent_status st = get_enum(obj, "mesh", "builtin", builtin_names, &index, err);
    if (st == LUCENT_OK)
        st = get_int(obj, "mesh", "triangles", &R_TRIANGLES, &triangles, err);
    if (st != LUCENT_OK)
        return st;
    if (triangles > 0 && strcmp(builtin_names[index], SCANNED_BUILTIN) == 0)
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.triangles",
                           "the %s is a scan with one density; omit mesh.triangles", SCANNED_BUILTIN);
    if (triangles > 0 && (uint32_t)triangles < LUCENT_MIN_BUILTIN_TRIANGLES)
        return lucent_fail(err, LUCENT_E_INVALID, "mesh.triangles",
                           "must be 0 (default density) or at least %u (got %d)", LUCENT_MIN_BUILTIN_TRIANGLES,
                           triangles);
    m->source = LUCENT_MESH_BUILTIN;
    snprintf(m->builtin, sizeof m->builtin, "%s", builtin_names[index]);
    m->triangles = (uint32_t)triangles;
    m->file[0] = '\0';
    return LUCENT_OK;
}

static lucent_status parse_mesh(json_t *v, int allow_files, lucent_mesh_ref *m, lucent_error *err)
{
    if (!v)
        return LUCENT_OK;
    lucent_status st = require_object(v, "mesh", err);
    if (st == LUCENT_OK)
        st = check_known_keys(v, mesh_keys, "mesh", err);
    if (st != LUCENT_OK)
        return st;
    int has_builtin = json_object_get(v, "builtin") != NULL;
    int has_file = json_object_get(v, "file") != NULL;
    int has_id = json_object_get(v, "id") != NULL;
    if (has_builtin + has_file + has_id != 1)
        return lucent_fail(err, LUCENT_E_INVALID, "mesh",
                           "must have exactly one of \"builtin\", \"id\" or \"file\" (got %s)",
                           has_builtin + has_file + has_id ? "several" : "none");
    if (has_id)
        return parse_mesh_id(v, m, err);
    return has_file ? parse_mesh_file(v, allow_files, m, err) : parse_mesh_builtin(v, m, err);
}

static lucent_status parse_preset(json_t *obj, lucent_material *mat, lucent_error *err)
{
    const char *names[64];
    int n = 0;
    /* Checked first: with a preset present, any other key is a conflict, not merely unknown. */
    for (void *it = json_object_iter(obj); it; it = json_object_iter_next(obj, it)) {
        char path[PATH_CAP];
        const char *key = json_object_iter_key(it);
        if (strcmp(key, "preset") == 0 || strcmp(key, "g") == 0 || strcmp(key, "profile") == 0)
            continue;
        path_key(path, "material", json_object_iter_key(it));
        return lucent_fail(err, LUCENT_E_INVALID, path,
                           "cannot be combined with \"preset\"; give either a preset (and optionally "
                           "\"g\" and \"profile\") or \"sigma_a\", \"sigma_s_prime\" and optionally \"eta\", "
                           "\"g\" and \"profile\"");
    }
    const json_t *v = json_object_get(obj, "preset");
    if (json_is_string(v) && lucent_material_preset(json_string_value(v), mat) == LUCENT_OK)
        return get_number(obj, "material", "g", &R_G, &mat->g, err);
    while (n + 1 < (int)(sizeof names / sizeof names[0]) &&
           (names[n] = lucent_material_preset_name(n)) != NULL)
        n++;
    names[n] = NULL;
    return fail_not_one_of(v, "material.preset", names, err);
}

static lucent_status parse_coefficients(json_t *obj, lucent_material *mat, lucent_error *err)
{
    static const char when[] = "when no \"preset\" is given";
    lucent_material m = {.eta = DEFAULT_ETA};
    lucent_status st = require(obj, "material", "sigma_a", when, err);
    if (st == LUCENT_OK)
        st = require(obj, "material", "sigma_s_prime", when, err);
    if (st == LUCENT_OK)
        st = get_vec(obj, "material", "sigma_a", 3, &R_SIGMA_A, m.sigma_a, err);
    if (st == LUCENT_OK)
        st = get_vec(obj, "material", "sigma_s_prime", 3, &R_SIGMA_S_PRIME, m.sigma_s_prime, err);
    if (st == LUCENT_OK)
        st = get_number(obj, "material", "eta", &R_ETA, &m.eta, err);
    if (st == LUCENT_OK)
        st = get_number(obj, "material", "g", &R_G, &m.g, err);
    if (st == LUCENT_OK)
        *mat = m;
    return st;
}

static lucent_status parse_material(json_t *v, lucent_material *mat, lucent_error *err)
{
    if (!v)
        return LUCENT_OK;
    lucent_status st = require_object(v, "material", err);
    if (st == LUCENT_OK)
        st = check_known_keys(v, material_keys, "material", err);
    if (st != LUCENT_OK)
        return st;
    st = json_object_get(v, "preset") ? parse_preset(v, mat, err) : parse_coefficients(v, mat, err);
    int profile = (int)LUCENT_PROFILE_DEFAULT;
    if (st == LUCENT_OK)
        st = get_enum(v, "material", "profile", profile_names, &profile, err);
    mat->profile = (lucent_profile)profile;
    return st;
}

static lucent_light default_light(void)
{
    return (lucent_light){.type = LUCENT_LIGHT_DIRECTIONAL, .color = {1, 1, 1}, .intensity = 1};
}

static lucent_status parse_light_geometry(json_t *v, const char *path, lucent_light *l,
                                          lucent_error *err)
{
    char field[PATH_CAP];
    lucent_status st;
    if (l->type == LUCENT_LIGHT_POINT) {
        st = require(v, path, "position", "for a point light", err);
        if (st == LUCENT_OK)
            st = get_vec(v, path, "position", 3, &R_COORD, l->position, err);
        return st;
    }
    st = require(v, path, "direction", "for a directional light", err);
    if (st == LUCENT_OK)
        st = get_vec(v, path, "direction", 3, &R_COORD, l->direction, err);
    if (st != LUCENT_OK)
        return st;
    if (normalize3(l->direction, l->direction))
        return LUCENT_OK;
    path_key(field, path, "direction");
    return lucent_fail(err, LUCENT_E_INVALID, field,
                       "must not be the zero vector (it is the way the light travels)");
}

static lucent_status parse_light(json_t *v, const char *path, lucent_light *out, lucent_error *err)
{
    lucent_light l = default_light();
    int type = LUCENT_LIGHT_DIRECTIONAL;
    lucent_status st = require_object(v, path, err);
    if (st == LUCENT_OK)
        st = get_enum(v, path, "type", light_type_names, &type, err);
    l.type = (lucent_light_type)type;
    /* The allowed keys depend on the type: a point light's "direction" would be ignored. */
    if (st == LUCENT_OK)
        st = check_known_keys(v, l.type == LUCENT_LIGHT_POINT ? point_keys : directional_keys, path,
                              err);
    if (st == LUCENT_OK)
        st = parse_light_geometry(v, path, &l, err);
    if (st == LUCENT_OK)
        st = get_vec(v, path, "color", 3, &R_COLOR, l.color, err);
    if (st == LUCENT_OK)
        st = get_number(v, path, "intensity", &R_INTENSITY, &l.intensity, err);
    if (st == LUCENT_OK)
        *out = l;
    return st;
}

static lucent_status parse_lights(json_t *v, lucent_scene *s, lucent_error *err)
{
    char path[PATH_CAP];
    if (!v)
        return LUCENT_OK;
    size_t n = json_array_size(v);
    if (!json_is_array(v) || n == 0) {
        char got[96];
        describe(v, got, sizeof got);
        return lucent_fail(err, LUCENT_E_INVALID, "lights",
                           "must be an array of 1 to %d light objects; omit it for the default "
                           "key light (got %s)",
                           LUCENT_MAX_LIGHTS, got);
    }
    if (n > LUCENT_MAX_LIGHTS)
        return lucent_fail(err, LUCENT_E_LIMIT, "lights", "at most %d lights are supported (got %zu)",
                           LUCENT_MAX_LIGHTS, n);
    for (size_t i = 0; i < n; i++) {
        path_index(path, "lights", i);
        lucent_status st = parse_light(json_array_get(v, i), path, &s->lights[i], err);
        if (st != LUCENT_OK)
            return st;
    }
    s->light_count = (int)n;
    return LUCENT_OK;
}

/* Rejects cameras that have no well-defined orientation: forward is target - position or direction. */
static lucent_status check_camera_basis(const double view[3], const double up_in[3], int framed, lucent_error *err)
{
    double forward[3], up[3];
    if (!normalize3(view, forward))
        return lucent_fail(err, LUCENT_E_INVALID, framed ? "camera.direction" : "camera.target",
                           framed ? "must not be the zero vector" : "must differ from camera.position");
    if (!normalize3(up_in, up))
        return lucent_fail(err, LUCENT_E_INVALID, "camera.up", "must not be the zero vector");
    if (cross_length(forward, up) < MIN_UP_SINE)
        return lucent_fail(err, LUCENT_E_INVALID, "camera.up", "must not be parallel to the view direction");
    return LUCENT_OK;
}

/* Either position and target (a placed camera) or direction (framed automatically along it). */
static lucent_status parse_camera(json_t *v, lucent_camera *out, lucent_error *err)
{
    static const char when[] = "in a camera object without \"direction\" (omit \"camera\" for automatic framing)";
    if (!v)
        return LUCENT_OK;
    lucent_camera c = *out;
    lucent_status st = require_object(v, "camera", err);
    if (st == LUCENT_OK)
        st = check_known_keys(v, camera_keys, "camera", err);
    int framed = st == LUCENT_OK && json_object_get(v, "direction");
    if (framed && (json_object_get(v, "position") || json_object_get(v, "target")))
        return lucent_fail(err, LUCENT_E_INVALID, "camera.direction",
                           "give either direction (framed automatically) or position and target, not both");
    if (st == LUCENT_OK && framed)
        st = get_vec(v, "camera", "direction", 3, &R_COORD, c.direction, err);
    if (st == LUCENT_OK && !framed)
        st = require(v, "camera", "position", when, err);
    if (st == LUCENT_OK && !framed)
        st = require(v, "camera", "target", when, err);
    if (st == LUCENT_OK && !framed)
        st = get_vec(v, "camera", "position", 3, &R_COORD, c.position, err);
    if (st == LUCENT_OK && !framed)
        st = get_vec(v, "camera", "target", 3, &R_COORD, c.target, err);
    if (st == LUCENT_OK)
        st = get_vec(v, "camera", "up", 3, &R_COORD, c.up, err);
    if (st == LUCENT_OK)
        st = get_number(v, "camera", "fov_deg", &R_FOV_DEG, &c.fov_deg, err);
    double view[3];
    for (int i = 0; i < 3; i++)
        view[i] = framed ? c.direction[i] : c.target[i] - c.position[i];
    if (st == LUCENT_OK)
        st = check_camera_basis(view, c.up, framed, err);
    if (st != LUCENT_OK)
        return st;
    if (framed)
        normalize3(c.direction, c.direction);
    c.given = !framed;
    *out = c;
    return LUCENT_OK;
}

static lucent_status parse_background(json_t *doc, double background[4], lucent_error *err)
{
    lucent_status st = get_vec(doc, "", "background", 4, &R_COLOR, background, err);
    if (st != LUCENT_OK || !json_object_get(doc, "background"))
        return st;
    /* The colour channels are radiance; only alpha is a coverage fraction. */
    return check_number(json_array_get(json_object_get(doc, "background"), 3), "background[3]",
                        &R_ALPHA, &background[3], err);
}

/* Side images may be coarser than the front one, never finer: they share its layered image. */
static lucent_status parse_side_projection(json_t *doc, lucent_scene *s, lucent_error *err)
{
    range r = {LUCENT_MIN_PROJECTION_SIZE, s->projection_size, 0, "it may not exceed projection_size"};
    return get_int(doc, "", "side_projection_size", &r, &s->side_projection_size, err);
}

static lucent_status get_bool(const json_t *obj, const char *key, int *out, lucent_error *err)
{
    const json_t *v = json_object_get(obj, key);
    if (!v)
        return LUCENT_OK;
    if (!json_is_boolean(v)) {
        char got[96];
        describe(v, got, sizeof got);
        return lucent_fail(err, LUCENT_E_INVALID, key, "must be true or false (got %s)", got);
    }
    *out = json_is_true(v);
    return LUCENT_OK;
}

static lucent_status check_auto_conflicts(json_t *doc, const lucent_scene *s, lucent_error *err)
{
    for (int i = 0; s->method == LUCENT_METHOD_AUTO && auto_chosen_keys[i]; i++)
        if (json_object_get(doc, auto_chosen_keys[i]))
            return lucent_fail(err, LUCENT_E_INVALID, auto_chosen_keys[i],
                               "is chosen by method \"auto\"; remove it or pick method \"five\" or \"single\"");
    return LUCENT_OK;
}

static lucent_status parse_output(json_t *doc, lucent_scene *s, lucent_error *err)
{
    int method = s->method, format = s->format, sampling = s->sampling, fallback = s->fallback;
    lucent_status st = get_int(doc, "", "width", &R_SIDE, &s->width, err);
    if (st == LUCENT_OK)
        st = get_int(doc, "", "height", &R_SIDE, &s->height, err);
    if (st == LUCENT_OK)
        st = get_enum(doc, "", "method", method_names, &method, err);
    if (st == LUCENT_OK)
        st = get_int(doc, "", "samples", &R_SAMPLES, &s->samples, err);
    if (st == LUCENT_OK)
        st = get_enum(doc, "", "sampling", sampling_names, &sampling, err);
    if (st == LUCENT_OK)
        st = get_int(doc, "", "projection_size", &R_PROJECTION, &s->projection_size, err);
    if (st == LUCENT_OK)
        st = parse_side_projection(doc, s, err);
    if (st == LUCENT_OK)
        st = parse_background(doc, s->background, err);
    if (st == LUCENT_OK)
        st = get_number(doc, "", "exposure", &R_EXPOSURE, &s->exposure, err);
    if (st == LUCENT_OK)
        st = get_enum(doc, "", "format", format_names, &format, err);
    if (st == LUCENT_OK)
        st = get_enum(doc, "", "fallback", fallback_names, &fallback, err);
    if (st == LUCENT_OK)
        st = get_bool(doc, "single_scattering", &s->single_scattering, err);
    if (method == LUCENT_METHOD_AUTO && !json_object_get(doc, "single_scattering"))
        s->single_scattering = LUCENT_CHOSEN;
    s->fallback = (lucent_fallback)fallback;
    s->method = (lucent_method)method;
    if (st == LUCENT_OK)
        st = check_auto_conflicts(doc, s, err);
    s->sampling = (lucent_sampling)sampling;
    s->format = (lucent_format)format;
    return st;
}

/* Options of method "reference": {"points": 0 or 1000..4e6, "threshold": 0 (brute force) .. 1}. */
static lucent_status parse_reference(json_t *v, lucent_scene *s, lucent_error *err)
{
    static const range points = {0, LUCENT_MAX_REFERENCE_POINTS, 0, "0 picks the count automatically"};
    static const range threshold = {0.0, 1.0, 0, "0 sums every point exactly"};
    int count = (int)s->reference_points;
    if (!v)
        return LUCENT_OK;
    lucent_status st = require_object(v, "reference", err);
    if (st == LUCENT_OK)
        st = check_known_keys(v, reference_keys, "reference", err);
    if (st == LUCENT_OK)
        st = get_int(v, "reference", "points", &points, &count, err);
    if (st == LUCENT_OK)
        st = get_number(v, "reference", "threshold", &threshold, &s->reference_threshold, err);
    if (st == LUCENT_OK && count > 0 && count < 1000)
        st = lucent_fail(err, LUCENT_E_INVALID, "reference.points", "must be 0 (automatic) or at least 1000 (got %d)",
                         count);
    s->reference_points = (uint32_t)count;
    return st;
}

/* Options of method "path": {"samples": 1..65536, "time_s": 0 (none) .. 86400, "boundary": "fresnel" or
 * "cycles", "filter": "point" or "box", "seed": 0..2^31-1}. */
static lucent_status parse_path(json_t *v, lucent_scene *s, lucent_error *err)
{
    static const range samples = {1, LUCENT_MAX_PATH_SAMPLES, 0, NULL};
    static const range time_s = {0.0, LUCENT_MAX_PATH_TIME_S, 0, "0 sets no time limit"};
    static const range seed = {0, 2147483647.0, 0, NULL};
    int count = (int)s->path_samples, boundary = (int)s->path_boundary, filter = (int)s->path_filter;
    int seed_value = (int)s->path_seed;
    if (!v)
        return LUCENT_OK;
    lucent_status st = require_object(v, "path", err);
    if (st == LUCENT_OK)
        st = check_known_keys(v, path_keys, "path", err);
    if (st == LUCENT_OK)
        st = get_int(v, "path", "samples", &samples, &count, err);
    if (st == LUCENT_OK)
        st = get_number(v, "path", "time_s", &time_s, &s->path_time_s, err);
    if (st == LUCENT_OK)
        st = get_enum(v, "path", "boundary", path_boundary_names, &boundary, err);
    if (st == LUCENT_OK)
        st = get_enum(v, "path", "filter", path_filter_names, &filter, err);
    if (st == LUCENT_OK)
        st = get_int(v, "path", "seed", &seed, &seed_value, err);
    s->path_samples = (uint32_t)count;
    s->path_boundary = (lucent_path_boundary)boundary;
    s->path_filter = (lucent_path_filter)filter;
    s->path_seed = (uint32_t)seed_value;
    return st;
}

static lucent_status parse_document(json_t *doc, int allow_files, lucent_scene *s,
                                    lucent_error *err)
{
    if (!json_is_object(doc)) {
        char got[96];
        describe(doc, got, sizeof got);
        return lucent_fail(err, LUCENT_E_INVALID, "", "the scene must be a JSON object (got %s)",
                           got);
    }
    lucent_status st = check_known_keys(doc, top_keys, "", err);
    if (st == LUCENT_OK)
        st = parse_mesh(json_object_get(doc, "mesh"), allow_files, &s->mesh, err);
    if (st == LUCENT_OK)
        st = get_number(doc, "", "scale_mm", &R_SCALE_MM, &s->scale_mm, err);
    if (st == LUCENT_OK)
        st = parse_material(json_object_get(doc, "material"), &s->material, err);
    if (st == LUCENT_OK)
        st = parse_lights(json_object_get(doc, "lights"), s, err);
    if (st == LUCENT_OK)
        st = parse_camera(json_object_get(doc, "camera"), &s->camera, err);
    if (st == LUCENT_OK)
        st = parse_output(doc, s, err);
    if (st == LUCENT_OK)
        st = parse_reference(json_object_get(doc, "reference"), s, err);
    if (st == LUCENT_OK)
        st = parse_path(json_object_get(doc, "path"), s, err);
    return st;
}

void lucent_scene_defaults(lucent_scene *scene)
{
    static const double key_light[3] = {-1, -1, -1}; /* shining from the upper right front */
    memset(scene, 0, sizeof *scene);
    scene->mesh.source = LUCENT_MESH_BUILTIN;
    snprintf(scene->mesh.builtin, sizeof scene->mesh.builtin, "%s", builtin_names[0]);
    (void)lucent_material_preset("marble", &scene->material); /* a fixed, known name */
    scene->lights[0] = default_light();
    normalize3(key_light, scene->lights[0].direction);
    scene->light_count = 1;
    scene->camera.up[1] = 1.0;
    const double deg = PI / 180.0;
    double azimuth = DEFAULT_VIEW_AZIMUTH_DEG * deg, elevation = DEFAULT_VIEW_ELEVATION_DEG * deg;
    scene->camera.direction[0] = sin(azimuth) * cos(elevation);
    scene->camera.direction[1] = -sin(elevation);
    scene->camera.direction[2] = -cos(azimuth) * cos(elevation);
    scene->camera.fov_deg = DEFAULT_FOV_DEG;
    scene->width = DEFAULT_SIDE;
    scene->height = DEFAULT_SIDE;
    scene->method = LUCENT_METHOD_FIVE;
    scene->samples = DEFAULT_SAMPLES;
    scene->projection_size = DEFAULT_PROJECTION;
    scene->format = LUCENT_FORMAT_PNG;
    scene->reference_threshold = -1.0;
    scene->path_samples = DEFAULT_PATH_SAMPLES;
}

lucent_status lucent_scene_parse(const char *json, size_t len, int allow_files, lucent_scene *out,
                                 lucent_error *err)
{
    json_error_t jerr;
    json_t *doc = json_loadb(json, len, JSON_REJECT_DUPLICATES, &jerr);
    if (!doc) {
        char detail[sizeof jerr.text];
        printable(jerr.text, sizeof jerr.text, detail, sizeof detail);
        return lucent_fail(err, LUCENT_E_INVALID, "", "not valid JSON: %s (line %d, column %d)",
                           detail, jerr.line, jerr.column);
    }
    /* Parsed into a copy so that *out is untouched when the document is rejected. */
    lucent_scene s;
    lucent_scene_defaults(&s);
    lucent_status st = parse_document(doc, allow_files, &s, err);
    json_decref(doc);
    if (st == LUCENT_OK)
        *out = s;
    return st;
}
