/* scene_build.c - maps render flags onto scene fields. Values are checked for syntax only; ranges are
 * the daemon's to judge, so one parser decides and its messages name the field. */
#include "scene_build.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

#include "file_io.h"

enum kind {
    K_NUM,     /* a number at path */
    K_INT,     /* an integer at path */
    K_STR,     /* a string at path */
    K_VEC3,    /* 3 numbers at path */
    K_VEC4,    /* 4 numbers at path */
    K_TRUE,    /* true at path */
    K_FALSE,   /* false at path */
    K_MESH,    /* mesh.builtin, mesh.id or mesh.file, by the value's shape */
    K_PRESET,  /* material.preset, dropping coefficients */
    K_COEFF,   /* 3 numbers at path, dropping material.preset */
    K_SIZE,    /* width and height from WxH */
    K_LIGHT,   /* starts a light: path is "direction" or "position" */
    K_LIGHT_VEC3, /* 3 numbers in the current light */
    K_LIGHT_NUM   /* a number in the current light */
};

enum {
    F_MESH, F_MESH_TRIANGLES, F_SCALE_MM, F_PRESET, F_SIGMA_A, F_SIGMA_S_PRIME, F_ETA, F_G, F_PROFILE,
    F_LIGHT_DIR, F_LIGHT_POS, F_LIGHT_COLOR, F_LIGHT_INTENSITY,
    F_CAMERA_POS, F_CAMERA_TARGET, F_CAMERA_DIR, F_CAMERA_UP, F_FOV,
    F_WIDTH, F_HEIGHT, F_SIZE, F_METHOD, F_SAMPLES, F_SAMPLING, F_FALLBACK, F_SINGLE_SCATTERING,
    F_NO_SINGLE_SCATTERING, F_PROJECTION_SIZE, F_SIDE_PROJECTION_SIZE, F_REFERENCE_POINTS,
    F_REFERENCE_THRESHOLD, F_PATH_SAMPLES, F_PATH_TIME, F_PATH_BOUNDARY, F_PATH_FILTER, F_PATH_SEED, F_BACKGROUND, F_EXPOSURE, F_FORMAT, F_COUNT
};

static const struct { const char *path; enum kind kind; } rules[F_COUNT] = {
    [F_MESH] = {"mesh", K_MESH},
    [F_MESH_TRIANGLES] = {"mesh.triangles", K_INT},
    [F_SCALE_MM] = {"scale_mm", K_NUM},
    [F_PRESET] = {"material.preset", K_PRESET},
    [F_SIGMA_A] = {"material.sigma_a", K_COEFF},
    [F_SIGMA_S_PRIME] = {"material.sigma_s_prime", K_COEFF},
    [F_ETA] = {"material.eta", K_NUM},
    [F_G] = {"material.g", K_NUM},
    [F_PROFILE] = {"material.profile", K_STR},
    [F_LIGHT_DIR] = {"direction", K_LIGHT},
    [F_LIGHT_POS] = {"position", K_LIGHT},
    [F_LIGHT_COLOR] = {"color", K_LIGHT_VEC3},
    [F_LIGHT_INTENSITY] = {"intensity", K_LIGHT_NUM},
    [F_CAMERA_POS] = {"camera.position", K_VEC3},
    [F_CAMERA_TARGET] = {"camera.target", K_VEC3},
    [F_CAMERA_DIR] = {"camera.direction", K_VEC3},
    [F_CAMERA_UP] = {"camera.up", K_VEC3},
    [F_FOV] = {"camera.fov_deg", K_NUM},
    [F_WIDTH] = {"width", K_INT},
    [F_HEIGHT] = {"height", K_INT},
    [F_SIZE] = {"width", K_SIZE},
    [F_METHOD] = {"method", K_STR},
    [F_SAMPLES] = {"samples", K_INT},
    [F_SAMPLING] = {"sampling", K_STR},
    [F_FALLBACK] = {"fallback", K_STR},
    [F_SINGLE_SCATTERING] = {"single_scattering", K_TRUE},
    [F_NO_SINGLE_SCATTERING] = {"single_scattering", K_FALSE},
    [F_PROJECTION_SIZE] = {"projection_size", K_INT},
    [F_SIDE_PROJECTION_SIZE] = {"side_projection_size", K_INT},
    [F_REFERENCE_POINTS] = {"reference.points", K_INT},
    [F_REFERENCE_THRESHOLD] = {"reference.threshold", K_NUM},
    [F_PATH_SAMPLES] = {"path.samples", K_INT},
    [F_PATH_TIME] = {"path.time_s", K_NUM},
    [F_PATH_BOUNDARY] = {"path.boundary", K_STR},
    [F_PATH_FILTER] = {"path.filter", K_STR},
    [F_PATH_SEED] = {"path.seed", K_INT},
    [F_BACKGROUND] = {"background", K_VEC4},
    [F_EXPOSURE] = {"exposure", K_NUM},
    [F_FORMAT] = {"format", K_STR},
};

const struct cli_option scene_options[] = {
    {"mesh", 0, "NAME|FILE|ID", "sphere, torus, protrusion or bunny; a local OBJ/PLY/STL/glTF/GLB file (uploaded once); or an uploaded mesh's id", F_MESH},
    {"mesh-triangles", 0, "N", "built-in mesh density: 0 = default, or 1000..2000000", F_MESH_TRIANGLES},
    {"scale-mm", 0, "MM", "millimetres per scene unit (default: the object is 50 mm across)", F_SCALE_MM},
    {"preset", 0, "NAME", "measured material (lucent materials lists them); default marble", F_PRESET},
    {"sigma-a", 0, "R,G,B", "absorption coefficients, mm^-1 (instead of --preset)", F_SIGMA_A},
    {"sigma-s-prime", 0, "R,G,B", "reduced scattering coefficients, mm^-1 (with --sigma-a)", F_SIGMA_S_PRIME},
    {"eta", 0, "X", "relative index of refraction, 1..3 (with coefficients)", F_ETA},
    {"g", 0, "X", "Henyey-Greenstein mean cosine for single scattering, -0.95..0.95", F_G},
    {"profile", 0, "P", "diffusion profile: dipole, better_dipole, burley or asymptotic_dipole (default: dipole; method auto chooses)", F_PROFILE},
    {"light-dir", 0, "X,Y,Z", "adds a directional light travelling along X,Y,Z (up to 4 lights)", F_LIGHT_DIR},
    {"light-pos", 0, "X,Y,Z", "adds a point light at X,Y,Z (up to 4 lights)", F_LIGHT_POS},
    {"light-color", 0, "R,G,B", "colour of the light added last (before any: the scene's first light)", F_LIGHT_COLOR},
    {"light-intensity", 0, "E", "intensity of the light added last (before any: the scene's first light)", F_LIGHT_INTENSITY},
    {"camera-pos", 0, "X,Y,Z", "camera position (with --camera-target)", F_CAMERA_POS},
    {"camera-target", 0, "X,Y,Z", "point the camera looks at", F_CAMERA_TARGET},
    {"camera-dir", 0, "X,Y,Z", "the way the camera looks, framed automatically (default: a three-quarter view)",
     F_CAMERA_DIR},
    {"camera-up", 0, "X,Y,Z", "camera up vector (default 0,1,0)", F_CAMERA_UP},
    {"fov", 0, "DEG", "vertical field of view in degrees (default 40)", F_FOV},
    {"width", 0, "PX", "image width (default 512)", F_WIDTH},
    {"height", 0, "PX", "image height (default 512)", F_HEIGHT},
    {"size", 0, "WxH", "image width and height, e.g. 256x256", F_SIZE},
    {"method", 0, "M", "five, single, auto, reference or path (default five)", F_METHOD},
    {"samples", 0, "N", "importance samples per channel, 1..64 (default 16)", F_SAMPLES},
    {"sampling", 0, "S", "shared or per_channel (default shared)", F_SAMPLING},
    {"fallback", 0, "F", "next_best or front (default next_best)", F_FALLBACK},
    {"single-scattering", 0, NULL, "add single scattering and light crossing unscattered", F_SINGLE_SCATTERING},
    {"no-single-scattering", 0, NULL, "leave it out (overrides a --scene file)", F_NO_SINGLE_SCATTERING},
    {"projection-size", 0, "N", "front projection image side in texels, 16..2048 (default 512)", F_PROJECTION_SIZE},
    {"side-projection-size", 0, "N", "side projection images' side (default half the front)", F_SIDE_PROJECTION_SIZE},
    {"reference-points", 0, "N", "method reference: irradiance points (0 = automatic)", F_REFERENCE_POINTS},
    {"reference-threshold", 0, "X", "method reference: hierarchical sum threshold, 0..1", F_REFERENCE_THRESHOLD},
    {"path-samples", 0, "N", "method path: walks per pixel and channel, 1..65536 (default 16)", F_PATH_SAMPLES},
    {"path-time", 0, "S", "method path: no further passes start after S seconds (default 0: no limit)", F_PATH_TIME},
    {"path-boundary", 0, "B", "method path: fresnel (smooth dielectric, default) or cycles (Blender Cycles' walk)",
     F_PATH_BOUNDARY},
    {"path-filter", 0, "F", "method path: point (pixel centres, default) or box (the whole pixel)", F_PATH_FILTER},
    {"path-seed", 0, "N", "method path: random seed, 0..2147483647 (default 0)", F_PATH_SEED},
    {"background", 0, "R,G,B,A", "linear RGBA composited under the object (default transparent)", F_BACKGROUND},
    {"exposure", 0, "STOPS", "output = radiance x 2^STOPS (default 0)", F_EXPOSURE},
    {"format", 0, "png|exr", "image format (default: -o's extension, else the --scene file's, else png)", F_FORMAT},
    {NULL, 0, NULL, NULL, 0},
};

int scene_load(const char *path, json_t **scene, lc_error *err)
{
    char *text = NULL;
    size_t len = 0;
    int rc = file_read_all(path, &text, &len, err);
    if (rc != LC_OK)
        return rc;
    json_error_t jerr;
    json_t *doc = json_loadb(text, len, JSON_REJECT_DUPLICATES, &jerr);
    free(text);
    if (!doc)
        return lc_fail(err, LC_E_USAGE, "--scene %s: line %d: %s", path, jerr.line, jerr.text);
    if (!json_is_object(doc)) {
        json_decref(doc);
        return lc_fail(err, LC_E_USAGE, "--scene %s: a scene document is a JSON object", path);
    }
    *scene = doc;
    return LC_OK;
}

/* The object holding the last component of a dotted path, created as needed; *key is that component. */
static json_t *parent_of(json_t *scene, const char *path, char *key, size_t key_cap, lc_error *err)
{
    const char *dot = strchr(path, '.');
    if (!dot) {
        snprintf(key, key_cap, "%s", path);
        return scene;
    }
    char head[32];
    snprintf(head, sizeof head, "%.*s", (int)(dot - path), path);
    snprintf(key, key_cap, "%s", dot + 1);
    json_t *obj = json_object_get(scene, head);
    if (!obj) {
        obj = json_object();
        if (!obj || json_object_set_new(scene, head, obj) != 0) {
            lc_fail(err, LC_E_INTERNAL, "out of memory");
            return NULL;
        }
    }
    if (!json_is_object(obj)) {
        lc_fail(err, LC_E_USAGE, "the scene's %s is not an object, so %s cannot be set", head, path);
        return NULL;
    }
    return obj;
}

static json_t *vector(const double *v, int n)
{
    json_t *a = json_array();
    for (int i = 0; a && i < n; i++)
        if (json_array_append_new(a, json_real(v[i])) != 0) {
            json_decref(a);
            return NULL;
        }
    return a;
}

/* The value of a plain field as JSON; NULL with err set when its syntax is wrong. */
static json_t *value_of(enum kind kind, const char *opt, const char *s, lc_error *err)
{
    double v[4];
    long n;
    json_t *out = NULL;
    switch (kind) {
    case K_NUM:
    case K_LIGHT_NUM:
        if (cli_number(opt, s, v, err) != LC_OK)
            return NULL;
        out = json_real(v[0]);
        break;
    case K_INT:
        if (cli_int(opt, s, INT_MIN, INT_MAX, &n, err) != LC_OK)
            return NULL;
        out = json_integer(n);
        break;
    case K_STR:
    case K_PRESET:
        out = json_string(s);
        break;
    case K_VEC3:
    case K_COEFF:
    case K_LIGHT:
    case K_LIGHT_VEC3:
        if (cli_vector(opt, s, 3, v, err) != LC_OK)
            return NULL;
        out = vector(v, 3);
        break;
    case K_VEC4:
        if (cli_vector(opt, s, 4, v, err) != LC_OK)
            return NULL;
        out = vector(v, 4);
        break;
    case K_TRUE:
        out = json_true();
        break;
    case K_FALSE:
    default: /* K_MESH and K_SIZE never get here: scene_apply handles them */
        out = json_false();
        break;
    }
    if (!out)
        lc_fail(err, LC_E_INTERNAL, "out of memory");
    return out;
}

static int set_path(json_t *scene, const char *path, json_t *value, lc_error *err)
{
    char key[64];
    json_t *parent = parent_of(scene, path, key, sizeof key, err);
    if (!parent) {
        json_decref(value);
        return err->code;
    }
    if (json_object_set_new(parent, key, value) != 0)
        return lc_fail(err, LC_E_INTERNAL, "out of memory");
    return LC_OK;
}

static int is_mesh_id(const char *s)
{
    if (strlen(s) != 64)
        return 0;
    for (; *s; s++)
        if (!((*s >= '0' && *s <= '9') || (*s >= 'a' && *s <= 'f')))
            return 0;
    return 1;
}

static int set_mesh(json_t *scene, const char *value, lc_error *err)
{
    static const char *const builtins[] = {"sphere", "torus", "protrusion", "bunny"};
    const char *source = "file";
    for (size_t i = 0; i < sizeof builtins / sizeof builtins[0]; i++)
        if (strcmp(value, builtins[i]) == 0)
            source = "builtin";
    if (is_mesh_id(value))
        source = "id";
    char key[64];
    json_t *mesh = parent_of(scene, "mesh.builtin", key, sizeof key, err);
    if (!mesh)
        return err->code;
    json_object_del(mesh, "builtin");
    json_object_del(mesh, "file");
    json_object_del(mesh, "id");
    return set_path(scene, strcmp(source, "builtin") == 0 ? "mesh.builtin" : strcmp(source, "id") == 0 ? "mesh.id" : "mesh.file",
                    json_string(value), err);
}

/* The light that --light-color / --light-intensity change: the one started last, else the scene's
 * first, else the daemon's default light made explicit. */
static json_t *current_light(json_t *scene, const struct scene_state *st, lc_error *err)
{
    json_t *lights = json_object_get(scene, "lights");
    if (lights && !json_is_array(lights)) {
        lc_fail(err, LC_E_USAGE, "the scene's lights is not an array");
        return NULL;
    }
    if (st->lights_started > 0 || json_array_size(lights) > 0) {
        json_t *light = json_array_get(lights, st->lights_started > 0 ? json_array_size(lights) - 1 : 0);
        if (!json_is_object(light))
            lc_fail(err, LC_E_USAGE, "the scene's lights[0] is not an object");
        return json_is_object(light) ? light : NULL;
    }
    json_t *light = json_pack("{s:[f,f,f]}", "direction", -1.0, -1.0, -1.0);
    lights = json_array();
    if (!light || !lights || json_array_append(lights, light) != 0 || json_object_set_new(scene, "lights", lights) != 0) {
        json_decref(light);
        json_decref(lights);
        lc_fail(err, LC_E_INTERNAL, "out of memory");
        return NULL;
    }
    json_decref(light); /* the array holds it */
    return light;
}

static int start_light(json_t *scene, struct scene_state *st, const char *key, json_t *value, lc_error *err)
{
    if (st->lights_started == 4) {
        json_decref(value);
        return lc_fail(err, LC_E_USAGE, "at most 4 lights (each --light-dir or --light-pos adds one)");
    }
    json_t *lights = st->lights_started == 0 ? json_array() : json_object_get(scene, "lights");
    json_t *light = json_pack("{s:s, s:o}", "type", strcmp(key, "direction") == 0 ? "directional" : "point", key, value);
    if (!lights || !light || json_array_append_new(lights, light) != 0) {
        if (st->lights_started == 0)
            json_decref(lights);
        return lc_fail(err, LC_E_INTERNAL, "out of memory");
    }
    if (st->lights_started == 0 && json_object_set_new(scene, "lights", lights) != 0)
        return lc_fail(err, LC_E_INTERNAL, "out of memory");
    st->lights_started++;
    return LC_OK;
}

int scene_apply(json_t *scene, struct scene_state *st, const struct cli_option *opt, const char *value,
                lc_error *err)
{
    char name[64];
    snprintf(name, sizeof name, "--%s", opt->name);
    enum kind kind = rules[opt->id].kind;
    const char *path = rules[opt->id].path;
    if (kind == K_MESH)
        return set_mesh(scene, value, err);
    if (kind == K_SIZE) {
        long w, h;
        if (cli_size(name, value, &w, &h, err) != LC_OK)
            return err->code;
        int rc = set_path(scene, "width", json_integer(w), err);
        return rc != LC_OK ? rc : set_path(scene, "height", json_integer(h), err);
    }
    json_t *v = value_of(kind, name, value, err);
    if (!v)
        return err->code;
    if (kind == K_LIGHT)
        return start_light(scene, st, path, v, err);
    if (kind == K_LIGHT_VEC3 || kind == K_LIGHT_NUM) {
        json_t *light = current_light(scene, st, err);
        if (!light) {
            json_decref(v);
            return err->code;
        }
        return json_object_set_new(light, path, v) == 0 ? LC_OK : lc_fail(err, LC_E_INTERNAL, "out of memory");
    }
    int rc = set_path(scene, path, v, err);
    if (rc != LC_OK)
        return rc;
    json_t *material = json_object_get(scene, "material");
    if (kind == K_PRESET) {
        /* A preset stands alone: coefficients from a --scene file would make the document invalid. */
        json_object_del(material, "sigma_a");
        json_object_del(material, "sigma_s_prime");
        json_object_del(material, "eta");
    } else if (kind == K_COEFF) {
        json_object_del(material, "preset");
    }
    return LC_OK;
}
