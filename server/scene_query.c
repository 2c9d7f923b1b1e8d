/* scene_query.c - GET /v1/render's query fields mapped onto the scene document, one table row per field;
 * values are typed here, ranges are the parser's job. */
#include "scene_query.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The mapping, also documented per parameter in server/openapi.json:
 *   mesh            -> mesh.builtin, or mesh.id when it is 64 hex digits
 *   mesh_triangles  -> mesh.triangles           scale_mm -> scale_mm
 *   preset          -> material.preset          sigma_a, sigma_s_prime (r,g,b), eta, g, profile -> material.*
 *   light_type, light_dir, light_pos, light_color, light_intensity -> lights[0].type/direction/position/
 *                      color/intensity (one light; light_pos alone implies light_type=point)
 *   camera_pos, camera_target, camera_dir, camera_up, fov -> camera.position/target/direction/up/fov_deg
 *   w, h            -> width, height            background (r,g,b,a), exposure, method, samples, sampling,
 *   projection_size, side_projection_size, fallback, single_scattering (true/false), format -> the same
 *   reference_points, reference_threshold -> reference.points, reference.threshold
 *   path_samples, path_time_s, path_boundary, path_filter, path_seed -> path.samples, path.time_s, path.boundary,
 *   path.filter, path.seed
 * Vectors are comma-separated numbers. */
enum kind { K_STRING, K_NUMBER, K_VECTOR, K_BOOL, K_MESH };

struct mapping {
    const char *query;
    const char *parent;   /* "" top level, "light" = lights[0], else an object key */
    const char *key;
    enum kind kind;
};

static const struct mapping table[] = {
    {"mesh", "mesh", "builtin", K_MESH},
    {"mesh_triangles", "mesh", "triangles", K_NUMBER},
    {"scale_mm", "", "scale_mm", K_NUMBER},
    {"preset", "material", "preset", K_STRING},
    {"sigma_a", "material", "sigma_a", K_VECTOR},
    {"sigma_s_prime", "material", "sigma_s_prime", K_VECTOR},
    {"eta", "material", "eta", K_NUMBER},
    {"g", "material", "g", K_NUMBER},
    {"profile", "material", "profile", K_STRING},
    {"light_type", "light", "type", K_STRING},
    {"light_dir", "light", "direction", K_VECTOR},
    {"light_pos", "light", "position", K_VECTOR},
    {"light_color", "light", "color", K_VECTOR},
    {"light_intensity", "light", "intensity", K_NUMBER},
    {"camera_pos", "camera", "position", K_VECTOR},
    {"camera_target", "camera", "target", K_VECTOR},
    {"camera_dir", "camera", "direction", K_VECTOR},
    {"camera_up", "camera", "up", K_VECTOR},
    {"fov", "camera", "fov_deg", K_NUMBER},
    {"w", "", "width", K_NUMBER},
    {"h", "", "height", K_NUMBER},
    {"method", "", "method", K_STRING},
    {"samples", "", "samples", K_NUMBER},
    {"sampling", "", "sampling", K_STRING},
    {"fallback", "", "fallback", K_STRING},
    {"single_scattering", "", "single_scattering", K_BOOL},
    {"projection_size", "", "projection_size", K_NUMBER},
    {"side_projection_size", "", "side_projection_size", K_NUMBER},
    {"background", "", "background", K_VECTOR},
    {"exposure", "", "exposure", K_NUMBER},
    {"format", "", "format", K_STRING},
    {"reference_points", "reference", "points", K_NUMBER},
    {"reference_threshold", "reference", "threshold", K_NUMBER},
    {"path_samples", "path", "samples", K_NUMBER},
    {"path_time_s", "path", "time_s", K_NUMBER},
    {"path_boundary", "path", "boundary", K_STRING},
    {"path_filter", "path", "filter", K_STRING},
    {"path_seed", "path", "seed", K_NUMBER},
};
#define MAPPING_COUNT (sizeof table / sizeof table[0])

#define MAX_VECTOR 8

static const struct mapping *find(const char *query)
{
    for (size_t i = 0; i < MAPPING_COUNT; i++)
        if (strcmp(table[i].query, query) == 0)
            return &table[i];
    return NULL;
}

/* A JSON number (RFC 8259: no hex, no leading '+', spaces or dot), finite as a double; -1 otherwise. The
 * same spelling in a POST body would parse to the same value, so GET and POST stay equivalent. */
static int number(const char *s, size_t len, double *out)
{
    size_t i = 0;
    i += i < len && s[i] == '-';
    size_t digits = strspn(s + i, "0123456789");
    if (digits == 0 || digits > len - i || (s[i] == '0' && digits > 1))
        return -1;
    i += digits;
    if (i < len && s[i] == '.') {
        size_t frac = strspn(s + i + 1, "0123456789");
        if (frac == 0)
            return -1;
        i += 1 + frac;
    }
    if (i < len && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        i += i < len && (s[i] == '+' || s[i] == '-');
        size_t exp = strspn(s + i, "0123456789");
        if (exp == 0)
            return -1;
        i += exp;
    }
    if (i != len || len >= 64)
        return -1;
    char buf[64];
    memcpy(buf, s, len);
    buf[len] = 0;
    *out = strtod(buf, NULL);
    return isfinite(*out) ? 0 : -1;
}

static int is_hex64(const char *s)
{
    size_t n = strspn(s, "0123456789abcdefABCDEF");
    return n == LUCENT_MESH_ID_LEN && s[n] == 0;
}

static json_t *value_of(const struct mapping *m, const char *v, lucent_error *err)
{
    double d;
    switch (m->kind) {
    case K_STRING:
    case K_MESH: {
        json_t *s = json_string(v);
        if (!s)
            lucent_fail(err, LUCENT_E_INVALID, m->query, "must be UTF-8 text");
        return s;
    }
    case K_BOOL:
        if (strcmp(v, "true") == 0 || strcmp(v, "false") == 0)
            return json_boolean(v[0] == 't');
        lucent_fail(err, LUCENT_E_INVALID, m->query, "must be true or false (got \"%.40s\")", v);
        return NULL;
    case K_NUMBER:
        if (number(v, strlen(v), &d) != 0) {
            lucent_fail(err, LUCENT_E_INVALID, m->query, "expected a finite JSON number (got \"%.40s\")", v);
            return NULL;
        }
        return json_real(d);
    case K_VECTOR: {
        json_t *a = json_array();
        int n = 0;
        for (const char *p = v;; n++) {
            size_t len = strcspn(p, ",");
            if (n >= MAX_VECTOR || number(p, len, &d) != 0) {
                json_decref(a);
                lucent_fail(err, LUCENT_E_INVALID, m->query,
                            n >= MAX_VECTOR ? "too many numbers (got \"%.40s\")"
                                            : "expected comma-separated finite JSON numbers (got \"%.40s\")",
                            v);
                return NULL;
            }
            json_array_append_new(a, json_real(d));
            if (!p[len])
                break;
            p += len + 1;
        }
        return a;
    }
    }
    return NULL;
}

/* The object a mapping writes into, created on first use. */
static json_t *parent_of(json_t *doc, const struct mapping *m)
{
    if (!m->parent[0])
        return doc;
    if (strcmp(m->parent, "light") == 0) {
        json_t *lights = json_object_get(doc, "lights");
        if (!lights) {
            lights = json_array();
            json_array_append_new(lights, json_object());
            json_object_set_new(doc, "lights", lights);
        }
        return json_array_get(lights, 0);
    }
    json_t *o = json_object_get(doc, m->parent);
    if (!o) {
        o = json_object();
        json_object_set_new(doc, m->parent, o);
    }
    return o;
}

static json_t *build(const struct query_field *fields, int count, lucent_error *err)
{
    json_t *doc = json_object();
    for (int i = 0; doc && i < count; i++) {
        const struct mapping *m = find(fields[i].key);
        const char *v = fields[i].value;
        for (int j = 0; m && j < i; j++)
            if (strcmp(fields[j].key, fields[i].key) == 0) {
                lucent_fail(err, LUCENT_E_INVALID, m->query, "given more than once");
                goto fail;
            }
        if (!m) {
            const char *k = fields[i].key;
            if (strcmp(query_key_field(k), k) == 0) {
                lucent_fail(err, LUCENT_E_INVALID, k, "unknown query field (see /openapi.json)");
                goto fail;
            }
            char shown[41];
            size_t n = 0;
            for (; k[n] && n < sizeof shown - 1; n++)
                shown[n] = k[n] >= 0x20 && k[n] < 0x7f && k[n] != '"' && k[n] != '\\' ? k[n] : '?';
            shown[n] = '\0';
            lucent_fail(err, LUCENT_E_INVALID, "query", "unknown query field \"%s\" (see /openapi.json)", shown);
            goto fail;
        }
        if (!v || !*v) {
            lucent_fail(err, LUCENT_E_INVALID, m->query, "needs a value");
            goto fail;
        }
        json_t *value = value_of(m, v, err);
        if (!value)
            goto fail;
        const char *key = m->kind == K_MESH && is_hex64(v) ? "id" : m->key;
        json_object_set_new(parent_of(doc, m), key, value);
    }
    json_t *light = json_array_get(json_object_get(doc, "lights"), 0);
    if (light && json_object_get(light, "position") && !json_object_get(light, "type"))
        json_object_set_new(light, "type", json_string("point"));
    return doc;
fail:
    json_decref(doc);
    return NULL;
}

const char *query_key_field(const char *key)
{
    size_t n = strlen(key);
    return n && n <= 40 && strspn(key, "abcdefghijklmnopqrstuvwxyz0123456789_") == n ? key : "query";
}

char *scene_query_document(const struct query_field *fields, int count, lucent_error *err)
{
    json_t *doc = build(fields, count, err);
    char *text = doc ? json_dumps(doc, JSON_COMPACT) : NULL;
    if (doc && !text)
        lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory building the scene");
    json_decref(doc);
    return text;
}

/* The parser names JSON paths; users of GET wrote query fields, so errors are renamed back. */
static void rename_field(lucent_error *err)
{
    char path[96];
    for (size_t i = 0; i < MAPPING_COUNT; i++) {
        const struct mapping *m = &table[i];
        if (m->kind == K_MESH)
            continue;
        if (strcmp(m->parent, "light") == 0)
            snprintf(path, sizeof path, "lights[0].%s", m->key);
        else
            snprintf(path, sizeof path, "%s%s%s", m->parent, m->parent[0] ? "." : "", m->key);
        size_t n = strlen(path);
        if (strncmp(err->field, path, n) == 0 && (err->field[n] == 0 || err->field[n] == '[')) {
            char renamed[sizeof err->field];
            snprintf(renamed, sizeof renamed, "%s%s", m->query, err->field + n);
            memcpy(err->field, renamed, sizeof renamed);
            return;
        }
    }
    if (strncmp(err->field, "mesh.", 5) == 0 || strcmp(err->field, "lights[0]") == 0)
        snprintf(err->field, sizeof err->field, "%s", err->field[0] == 'm' ? "mesh" : "light_type");
}

lucent_status scene_query_parse(const struct query_field *fields, int count, lucent_scene *out, int *format_given,
                                lucent_error *err)
{
    char *text = scene_query_document(fields, count, err);
    if (!text)
        return err->status;
    lucent_status st = lucent_scene_parse(text, strlen(text), 0, out, err);
    free(text);
    if (st != LUCENT_OK)
        rename_field(err);
    *format_given = 0;
    for (int i = 0; i < count; i++)
        *format_given |= strcmp(fields[i].key, "format") == 0;
    return st;
}
