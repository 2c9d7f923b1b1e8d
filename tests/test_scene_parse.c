/* test_scene_parse.c - table-driven test of the scene parser, its defaults and the material presets.
 * Prints one line per case with the parser's message; the last line is "N passed, N failed". */
#include "lucent.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct parse_case {
    const char *json;
    int allow_files;
    lucent_status want;
    const char *field; /* expected err.field when want != LUCENT_OK */
} parse_case;

#define OK LUCENT_OK
#define INV LUCENT_E_INVALID
#define LIM LUCENT_E_LIMIT

static const parse_case cases[] = {
    /* whole document */
    {"{}", 0, OK, ""},
    {"", 0, INV, ""},
    {"{", 0, INV, ""},
    {"{\"width\": 512,}", 0, INV, ""},
    {"[]", 0, INV, ""},
    {"5", 0, INV, ""},
    {"\"scene\"", 0, INV, ""},
    {"{} x", 0, INV, ""},
    {"{\"width\": 1e999}", 0, INV, ""},
    {"{\"exposure\": -1e999}", 0, INV, ""},
    {"{\"exposure\": NaN}", 0, INV, ""},
    {"{\"exposure\": Infinity}", 0, INV, ""},
    {"{\"width\": 99999999999999999999}", 0, INV, ""},
    {"{\"width\": 64, \"width\": 128}", 0, INV, ""},
    {"{\"material\": {\"preset\": \"apple\", \"preset\": \"cream\"}}", 0, INV, ""},
    {"{\"format\": \"\xff\"}", 0, INV, ""},
    {"{\"format\": \"p\\u0000ng\"}", 0, INV, ""},
    /* unknown keys at every level */
    {"{\"widht\": 512}", 0, INV, "widht"},
    {"{\"Width\": 512}", 0, INV, "Width"},
    {"{\"gr\xc3\xb6\xc3\x9f" "e\": 1}", 0, INV, "gr????e"},
    {"{\"mesh\": {\"builtin\": \"sphere\", \"tris\": 5}}", 0, INV, "mesh.tris"},
    {"{\"material\": {\"sigma_a\": [0,0,0], \"sigma_s_prime\": [1,1,1], \"gee\": 0.5}}", 0, INV,
     "material.gee"},
    {"{\"lights\": [{\"direction\": [0,0,-1]}, {\"direction\": [0,0,-1], \"colour\": [1,1,1]}]}", 0,
     INV, "lights[1].colour"},
    {"{\"lights\": [{\"type\": \"point\", \"position\": [0,2,0], \"direction\": [0,-1,0]}]}", 0, INV,
     "lights[0].direction"},
    {"{\"lights\": [{\"direction\": [0,-1,0], \"position\": [0,2,0]}]}", 0, INV,
     "lights[0].position"},
    {"{\"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], \"fov\": 30}}", 0, INV,
     "camera.fov"},
    /* mesh */
    {"{\"mesh\": {\"builtin\": \"torus\"}}", 0, OK, ""},
    {"{\"mesh\": {\"builtin\": \"Protrusion\", \"triangles\": 1000}}", 0, OK, ""},
    {"{\"mesh\": {\"builtin\": \"sphere\", \"triangles\": 2000000}}", 0, OK, ""},
    {"{\"mesh\": {\"builtin\": \"sphere\", \"triangles\": 2000001}}", 0, LIM, "mesh.triangles"},
    {"{\"mesh\": {\"builtin\": \"sphere\", \"triangles\": -1}}", 0, INV, "mesh.triangles"},
    {"{\"mesh\": {\"builtin\": \"sphere\", \"triangles\": 999}}", 0, INV, "mesh.triangles"},
    {"{\"mesh\": {\"builtin\": \"sphere\", \"triangles\": 1.5}}", 0, INV, "mesh.triangles"},
    {"{\"mesh\": {\"builtin\": \"cube\"}}", 0, INV, "mesh.builtin"},
    {"{\"mesh\": {\"builtin\": 5}}", 0, INV, "mesh.builtin"},
    {"{\"mesh\": {}}", 0, INV, "mesh"},
    {"{\"mesh\": \"sphere\"}", 0, INV, "mesh"},
    {"{\"mesh\": {\"builtin\": \"sphere\", \"file\": \"a.obj\"}}", 1, INV, "mesh"},
    {"{\"mesh\": {\"file\": \"bunny.obj\"}}", 0, INV, "mesh.file"},
    {"{\"mesh\": {\"file\": \"bunny.obj\"}}", 1, OK, ""},
    {"{\"mesh\": {\"file\": \"\"}}", 1, INV, "mesh.file"},
    {"{\"mesh\": {\"file\": 7}}", 1, INV, "mesh.file"},
    {"{\"mesh\": {\"file\": \"a.obj\", \"triangles\": 5}}", 1, INV, "mesh.triangles"},
    {"{\"mesh\": {\"id\": \"0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef\"}}", 0, OK, ""},
    {"{\"mesh\": {\"id\": \"0123456789ABCDEF0123456789ABCDEF0123456789ABCDEF0123456789ABCDEF\"}}", 0, INV, "mesh.id"},
    {"{\"mesh\": {\"id\": \"0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcde\"}}", 0, INV, "mesh.id"},
    {"{\"mesh\": {\"id\": \"../../etc/passwd\"}}", 0, INV, "mesh.id"},
    {"{\"mesh\": {\"id\": 7}}", 0, INV, "mesh.id"},
    {"{\"mesh\": {\"id\": \"0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef\", \"builtin\": \"sphere\"}}", 0, INV, "mesh"},
    {"{\"mesh\": {\"id\": \"0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef\", \"triangles\": 5000}}", 0, INV, "mesh.triangles"},
    /* scale */
    {"{\"scale_mm\": 10}", 0, OK, ""},
    {"{\"scale_mm\": 0}", 0, INV, "scale_mm"},
    {"{\"scale_mm\": -1}", 0, INV, "scale_mm"},
    {"{\"scale_mm\": 2e9}", 0, INV, "scale_mm"},
    {"{\"scale_mm\": \"10\"}", 0, INV, "scale_mm"},
    /* material */
    {"{\"material\": {\"preset\": \"MARBLE\"}}", 0, OK, ""},
    {"{\"material\": {\"preset\": \"jade\"}}", 0, INV, "material.preset"},
    {"{\"material\": {\"preset\": 3}}", 0, INV, "material.preset"},
    {"{\"material\": {\"preset\": \"skin1\", \"eta\": 1.4}}", 0, INV, "material.eta"},
    {"{\"material\": {\"sigma_a\": [0,0,0], \"preset\": \"skin1\"}}", 0, INV, "material.sigma_a"},
    {"{\"material\": {\"sigma_a\": [0.03,0.17,0.48], \"sigma_s_prime\": [0.74,0.88,1.01]}}", 0, OK,
     ""},
    {"{\"material\": {\"sigma_a\": [0,0,0], \"sigma_s_prime\": [11.6,20.4,14.9], \"eta\": 1}}", 0,
     OK, ""},
    {"{\"material\": {\"sigma_a\": [-0.1,0,0], \"sigma_s_prime\": [1,1,1]}}", 0, INV,
     "material.sigma_a[0]"},
    {"{\"material\": {\"sigma_a\": [1e6,0,0], \"sigma_s_prime\": [1,1,1]}}", 0, INV,
     "material.sigma_a[0]"},
    {"{\"material\": {\"sigma_a\": [0,0,\"x\"], \"sigma_s_prime\": [1,1,1]}}", 0, INV,
     "material.sigma_a[2]"},
    {"{\"material\": {\"sigma_a\": [0,0], \"sigma_s_prime\": [1,1,1]}}", 0, INV,
     "material.sigma_a"},
    {"{\"material\": {\"sigma_a\": [0,0,0], \"sigma_s_prime\": [1,0,1]}}", 0, INV,
     "material.sigma_s_prime[1]"},
    {"{\"material\": {\"sigma_a\": [0,0,0], \"sigma_s_prime\": [1,1,-2]}}", 0, INV,
     "material.sigma_s_prime[2]"},
    {"{\"material\": {\"sigma_a\": [0,0,0], \"sigma_s_prime\": [1,1,1], \"eta\": 0.9}}", 0, INV,
     "material.eta"},
    {"{\"material\": {\"sigma_a\": [0,0,0], \"sigma_s_prime\": [1,1,1], \"eta\": 3.5}}", 0, INV,
     "material.eta"},
    {"{\"material\": {\"sigma_a\": [0,0,0]}}", 0, INV, "material.sigma_s_prime"},
    {"{\"material\": {}}", 0, INV, "material.sigma_a"},
    {"{\"material\": null}", 0, INV, "material"},
    /* lights */
    {"{\"lights\": []}", 0, INV, "lights"},
    {"{\"lights\": {\"direction\": [0,0,-1]}}", 0, INV, "lights"},
    {"{\"lights\": [{\"direction\": [0,0,-1]}, {\"direction\": [0,0,-1]}, "
     "{\"direction\": [0,0,-1]}, {\"direction\": [0,0,-1]}]}",
     0, OK, ""},
    {"{\"lights\": [{\"direction\": [0,0,-1]}, {\"direction\": [0,0,-1]}, "
     "{\"direction\": [0,0,-1]}, {\"direction\": [0,0,-1]}, {\"direction\": [0,0,-1]}]}",
     0, LIM, "lights"},
    {"{\"lights\": [5]}", 0, INV, "lights[0]"},
    {"{\"lights\": [{\"direction\": [0,0,0]}]}", 0, INV, "lights[0].direction"},
    {"{\"lights\": [{\"color\": [1,1,1]}]}", 0, INV, "lights[0].direction"},
    {"{\"lights\": [{\"direction\": true}]}", 0, INV, "lights[0].direction"},
    {"{\"lights\": [{\"direction\": [0,null,1]}]}", 0, INV, "lights[0].direction[1]"},
    {"{\"lights\": [{\"type\": \"spot\", \"direction\": [0,0,-1]}]}", 0, INV, "lights[0].type"},
    {"{\"lights\": [{\"type\": \"POINT\", \"position\": [0,3,0], \"intensity\": 9}]}", 0, OK, ""},
    {"{\"lights\": [{\"type\": \"point\"}]}", 0, INV, "lights[0].position"},
    {"{\"lights\": [{\"direction\": [0,0,-1], \"color\": [1,-1,1]}]}", 0, INV,
     "lights[0].color[1]"},
    {"{\"lights\": [{\"direction\": [0,0,-1], \"color\": [2e6,1,1]}]}", 0, INV,
     "lights[0].color[0]"},
    {"{\"lights\": [{\"direction\": [0,0,-1], \"intensity\": -1}]}", 0, INV,
     "lights[0].intensity"},
    {"{\"lights\": [{\"direction\": [0,0,-1], \"intensity\": 1e13}]}", 0, INV,
     "lights[0].intensity"},
    {"{\"lights\": [{\"direction\": [0,0,-1], \"intensity\": \"1\"}]}", 0, INV,
     "lights[0].intensity"},
    {"{\"lights\": [{\"type\": \"point\", \"position\": [1e16,0,0]}]}", 0, INV,
     "lights[0].position[0]"},
    /* camera */
    {"{\"camera\": {\"position\": [0,0,5], \"target\": [0,0,0]}}", 0, OK, ""},
    {"{\"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], \"up\": [1,0,0], \"fov_deg\": "
     "169.9}}",
     0, OK, ""},
    {"{\"camera\": {\"position\": [0,0,5]}}", 0, INV, "camera.target"},
    {"{\"camera\": {\"fov_deg\": 30}}", 0, INV, "camera.position"},
    {"{\"camera\": {\"position\": [1,2,3], \"target\": [1,2,3]}}", 0, INV, "camera.target"},
    {"{\"camera\": {\"position\": [0,5,0], \"target\": [0,0,0]}}", 0, INV, "camera.up"},
    {"{\"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], \"up\": [0,0,-2]}}", 0, INV,
     "camera.up"},
    {"{\"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], \"up\": [0,0,0]}}", 0, INV,
     "camera.up"},
    {"{\"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], \"up\": [1e-6,0,-1]}}", 0, OK,
     ""},
    {"{\"mesh\": {\"builtin\": \"bunny\"}}", 0, OK, ""},
    {"{\"mesh\": {\"builtin\": \"bunny\", \"triangles\": 5000}}", 0, INV, "mesh.triangles"},
    /* camera.direction: framed automatically along it; not with position or target */
    {"{\"camera\": {\"direction\": [1,-1,-1]}}", 0, OK, ""},
    {"{\"camera\": {\"direction\": [0,0,-1], \"up\": [1,0,0], \"fov_deg\": 30}}", 0, OK, ""},
    {"{\"camera\": {\"direction\": [0,0,-1], \"position\": [0,0,5]}}", 0, INV, "camera.direction"},
    {"{\"camera\": {\"direction\": [0,0,-1], \"target\": [0,0,0]}}", 0, INV, "camera.direction"},
    {"{\"camera\": {\"direction\": [0,0,0]}}", 0, INV, "camera.direction"},
    {"{\"camera\": {\"direction\": [0,-3,0]}}", 0, INV, "camera.up"},
    {"{\"camera\": {\"direction\": [0,0,\"x\"]}}", 0, INV, "camera.direction[2]"},
    {"{\"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], \"fov_deg\": 170}}", 0, INV,
     "camera.fov_deg"},
    {"{\"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], \"fov_deg\": 1}}", 0, INV,
     "camera.fov_deg"},
    {"{\"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], \"fov_deg\": 0.5}}", 0, INV,
     "camera.fov_deg"},
    {"{\"camera\": {\"position\": [1e16,0,5], \"target\": [0,0,0]}}", 0, INV,
     "camera.position[0]"},
    {"{\"camera\": []}", 0, INV, "camera"},
    /* image size and quality */
    {"{\"width\": 4096, \"height\": 1}", 0, OK, ""},
    {"{\"width\": 512.0}", 0, OK, ""},
    {"{\"width\": 0}", 0, INV, "width"},
    {"{\"width\": -5}", 0, INV, "width"},
    {"{\"width\": 4097}", 0, LIM, "width"},
    {"{\"width\": 1.5}", 0, INV, "width"},
    {"{\"width\": \"512\"}", 0, INV, "width"},
    {"{\"width\": true}", 0, INV, "width"},
    {"{\"width\": null}", 0, INV, "width"},
    {"{\"height\": 5000}", 0, LIM, "height"},
    {"{\"samples\": 64}", 0, OK, ""},
    {"{\"samples\": 0}", 0, INV, "samples"},
    {"{\"samples\": 65}", 0, LIM, "samples"},
    {"{\"projection_size\": 16}", 0, OK, ""},
    {"{\"projection_size\": 15}", 0, INV, "projection_size"},
    {"{\"projection_size\": 2049}", 0, LIM, "projection_size"},
    {"{\"side_projection_size\": 16}", 0, OK, ""},
    {"{\"projection_size\": 256, \"side_projection_size\": 256}", 0, OK, ""},
    {"{\"projection_size\": 256, \"side_projection_size\": 257}", 0, LIM, "side_projection_size"},
    {"{\"side_projection_size\": 8}", 0, INV, "side_projection_size"},
    {"{\"sampling\": \"per_channel\"}", 0, OK, ""},
    {"{\"sampling\": \"Shared\"}", 0, OK, ""},
    {"{\"sampling\": \"mis\"}", 0, INV, "sampling"},
    {"{\"method\": \"single\"}", 0, OK, ""},
    {"{\"method\": \"reference\", \"reference\": {\"points\": 20000, \"threshold\": 0}}", 0, OK, ""},
    {"{\"reference\": {\"points\": 500}}", 0, INV, "reference.points"},
    {"{\"reference\": {\"points\": 4000001}}", 0, LIM, "reference.points"},
    {"{\"reference\": {\"threshold\": 1.5}}", 0, INV, "reference.threshold"},
    {"{\"reference\": {\"octree\": 1}}", 0, INV, "reference.octree"},
    {"{\"reference\": 3}", 0, INV, "reference"},
    {"{\"method\": \"path\", \"path\": {\"samples\": 64, \"time_s\": 30, \"boundary\": \"cycles\", \"seed\": 7}}", 0, OK, ""},
    {"{\"path\": {\"samples\": 0}}", 0, INV, "path.samples"},
    {"{\"path\": {\"samples\": 65537}}", 0, LIM, "path.samples"},
    {"{\"path\": {\"samples\": 2.5}}", 0, INV, "path.samples"},
    {"{\"path\": {\"time_s\": -1}}", 0, INV, "path.time_s"},
    {"{\"path\": {\"boundary\": \"rough\"}}", 0, INV, "path.boundary"},
    {"{\"path\": {\"filter\": \"gaussian\"}}", 0, INV, "path.filter"},
    {"{\"method\": \"path\", \"path\": {\"filter\": \"box\"}}", 0, OK, ""},
    {"{\"path\": {\"seed\": -1}}", 0, INV, "path.seed"},
    {"{\"path\": {\"bounces\": 3}}", 0, INV, "path.bounces"},
    {"{\"path\": []}", 0, INV, "path"},
    {"{\"method\": \"FIVE\"}", 0, OK, ""},
    {"{\"method\": \"three\"}", 0, INV, "method"},
    {"{\"method\": \"auto\"}", 0, OK, ""},
    {"{\"method\": \"auto\", \"samples\": 8}", 0, INV, "samples"},
    {"{\"method\": \"auto\", \"projection_size\": 256}", 0, INV, "projection_size"},
    {"{\"method\": \"auto\", \"sampling\": \"shared\"}", 0, INV, "sampling"},
    {"{\"method\": \"auto\", \"single_scattering\": true, \"fallback\": \"front\"}", 0, OK, ""},
    {"{\"fallback\": \"next_best\"}", 0, OK, ""},
    {"{\"fallback\": \"blend\"}", 0, INV, "fallback"},
    {"{\"single_scattering\": 1}", 0, INV, "single_scattering"},
    {"{\"single_scattering\": false}", 0, OK, ""},
    {"{\"material\": {\"sigma_a\": [0,0,0], \"sigma_s_prime\": [1,1,1], \"g\": 0.9}}", 0, OK, ""},
    {"{\"material\": {\"preset\": \"skin1\", \"g\": -0.5}}", 0, OK, ""},
    {"{\"material\": {\"preset\": \"skin1\", \"g\": 0.96}}", 0, INV, "material.g"},
    {"{\"material\": {\"preset\": \"skin1\", \"profile\": \"burley\"}}", 0, OK, ""},
    {"{\"material\": {\"sigma_a\": [0,0,0], \"sigma_s_prime\": [1,1,1], \"profile\": \"Better_Dipole\"}}", 0, OK, ""},
    {"{\"material\": {\"preset\": \"skin1\", \"profile\": \"multipole\"}}", 0, INV, "material.profile"},
    {"{\"material\": {\"preset\": \"skin1\", \"profile\": 2}}", 0, INV, "material.profile"},
    {"{\"material\": {\"sigma_a\": [0,0,0], \"sigma_s_prime\": [1,1,1], \"g\": 1}}", 0, INV, "material.g"},
    {"{\"format\": \"exr\"}", 0, OK, ""},
    {"{\"format\": \"jpg\"}", 0, INV, "format"},
    /* output */
    {"{\"background\": [2,2,2,1]}", 0, OK, ""},
    {"{\"background\": [0,0,0]}", 0, INV, "background"},
    {"{\"background\": [1,1,1,2]}", 0, INV, "background[3]"},
    {"{\"background\": [-1,0,0,0]}", 0, INV, "background[0]"},
    {"{\"exposure\": -64}", 0, OK, ""},
    {"{\"exposure\": 65}", 0, INV, "exposure"},
    {"{\"exposure\": \"1\"}", 0, INV, "exposure"},
};

static int passed, failed;

static void check(int ok, const char *what)
{
    if (ok)
        passed++;
    else
        failed++;
    printf("%s  %s\n", ok ? "ok  " : "FAIL", what);
}

/* Messages end up in JSON bodies and logs: printable ASCII only, never empty. */
static int printable_text(const char *s)
{
    for (; *s; s++)
        if (*s < 0x20 || *s > 0x7e)
            return 0;
    return 1;
}

static void run_case(int n, const parse_case *c)
{
    lucent_scene scene;
    lucent_error err = {0};
    lucent_status st = lucent_scene_parse(c->json, strlen(c->json), c->allow_files, &scene, &err);
    int ok = st == c->want;
    if (c->want != LUCENT_OK)
        ok = ok && strcmp(err.field, c->field) == 0 && err.message[0] &&
             printable_text(err.message) && printable_text(err.field);
    if (ok)
        passed++;
    else
        failed++;
    printf("%s  #%-3d %-60.60s -> %s", ok ? "ok  " : "FAIL", n, c->json, lucent_status_name(st));
    if (st != LUCENT_OK)
        printf(" [%s] %s", err.field, err.message);
    if (!ok)
        printf("   (wanted %s [%s])", lucent_status_name(c->want), c->field);
    printf("\n");
}

static int near(double a, double b, double tol)
{
    return fabs(a - b) <= tol;
}

#define M_PI_VALUE 3.14159265358979323846

static int is_default_scene(const lucent_scene *s)
{
    lucent_material marble;
    double d = -1.0 / sqrt(3.0);
    const lucent_light *l = &s->lights[0];
    int ok = lucent_material_preset("marble", &marble) == LUCENT_OK;
    ok = ok && s->mesh.source == LUCENT_MESH_BUILTIN && strcmp(s->mesh.builtin, "sphere") == 0 &&
         s->mesh.triangles == 0 && s->mesh.file[0] == '\0' && s->scale_mm == 0.0;
    ok = ok && strcmp(s->material.preset, "marble") == 0 && s->material.eta == 1.5 &&
         memcmp(s->material.sigma_a, marble.sigma_a, sizeof marble.sigma_a) == 0 &&
         memcmp(s->material.sigma_s_prime, marble.sigma_s_prime, sizeof marble.sigma_s_prime) == 0 &&
         s->material.g == 0.0 && s->material.profile == LUCENT_PROFILE_DEFAULT;
    ok = ok && s->light_count == 1 && l->type == LUCENT_LIGHT_DIRECTIONAL &&
         near(l->direction[0], d, 1e-15) && near(l->direction[1], d, 1e-15) &&
         near(l->direction[2], d, 1e-15) && l->color[0] == 1 && l->color[1] == 1 &&
         l->color[2] == 1 && l->intensity == 1;
    /* the three-quarter view: from 35 degrees left of +Z and 25 degrees above, looking at the centre */
    double az = 35 * M_PI_VALUE / 180, el = 25 * M_PI_VALUE / 180;
    ok = ok && s->camera.given == 0 && s->camera.fov_deg == 40 && s->camera.up[1] == 1 &&
         near(s->camera.direction[0], sin(az) * cos(el), 1e-15) && near(s->camera.direction[1], -sin(el), 1e-15) &&
         near(s->camera.direction[2], -cos(az) * cos(el), 1e-15);
    ok = ok && s->width == 512 && s->height == 512 && s->method == LUCENT_METHOD_FIVE &&
         s->samples == 16 && s->projection_size == 512 && s->exposure == 0 &&
         s->format == LUCENT_FORMAT_PNG;
    for (int i = 0; i < 4; i++)
        ok = ok && s->background[i] == 0;
    return ok;
}

static int parse(const char *json, lucent_scene *s)
{
    lucent_error err;
    return lucent_scene_parse(json, strlen(json), 0, s, &err) == LUCENT_OK;
}

static void test_defaults(void)
{
    lucent_scene s;
    lucent_scene_defaults(&s);
    check(is_default_scene(&s), "lucent_scene_defaults fills every documented default");
    memset(&s, 0x5a, sizeof s);
    check(parse("{}", &s) && is_default_scene(&s), "{} parses to exactly the defaults");
    check(parse(" {\"width\": 64}garbage", &s) == 0, "trailing bytes inside len are rejected");
    check(lucent_scene_parse("{\"width\": 64}garbage", 13, 0, &s, NULL) == LUCENT_OK &&
              s.width == 64,
          "bytes past len are ignored; err may be NULL");
}

static void test_values(void)
{
    lucent_scene s;
    const char *full =
        "{\"mesh\": {\"builtin\": \"TORUS\", \"triangles\": 5000}, \"scale_mm\": 2.5,"
        " \"material\": {\"sigma_a\": [-0.0, 0.5, 1], \"sigma_s_prime\": [1, 2, 3]},"
        " \"lights\": [{\"direction\": [0, -3, 4], \"color\": [1, 0.5, 0.25], \"intensity\": 2},"
        "              {\"type\": \"point\", \"position\": [1, 2, 3]},"
        "              {\"direction\": [1e-300, 0, 0]}, {\"direction\": [1e15, -1e15, 0]}],"
        " \"camera\": {\"position\": [0, 0, 5], \"target\": [0, 1, 0], \"up\": [0, 2, 0],"
        "              \"fov_deg\": 30},"
        " \"width\": 640.0, \"height\": 480, \"method\": \"single\", \"samples\": 8,"
        " \"projection_size\": 256, \"background\": [0.1, 0.2, 0.3, 0.5], \"exposure\": -1.5,"
        " \"format\": \"EXR\"}";
    check(parse(full, &s), "a scene giving every field parses");
    check(strcmp(s.mesh.builtin, "torus") == 0 && s.mesh.triangles == 5000 && s.scale_mm == 2.5,
          "mesh and scale land in their fields, builtin name canonical");
    check(s.material.preset[0] == '\0' && s.material.eta == 1.3 && s.material.sigma_a[0] == 0 &&
              !signbit(s.material.sigma_a[0]) && s.material.sigma_a[2] == 1 &&
              s.material.sigma_s_prime[1] == 2,
          "coefficient material: eta defaults to 1.3, -0 stored as +0");
    check(s.light_count == 4 && s.lights[0].direction[0] == 0 &&
              near(s.lights[0].direction[1], -0.6, 1e-15) &&
              near(s.lights[0].direction[2], 0.8, 1e-15) && s.lights[0].color[2] == 0.25 &&
              s.lights[0].intensity == 2,
          "direction [0,-3,4] is normalized to [0,-0.6,0.8]");
    check(s.lights[1].type == LUCENT_LIGHT_POINT && s.lights[1].position[2] == 3 &&
              s.lights[1].intensity == 1 && s.lights[1].color[1] == 1,
          "point light keeps its position; colour and intensity default");
    check(s.lights[2].direction[0] == 1 && near(s.lights[3].direction[0], sqrt(0.5), 1e-15) &&
              near(s.lights[3].direction[1], -sqrt(0.5), 1e-15),
          "tiny and huge directions normalize without underflow or overflow");
    check(s.camera.given == 1 && s.camera.target[1] == 1 && s.camera.up[1] == 2 &&
              s.camera.fov_deg == 30,
          "camera fields are stored as given");
    check(s.width == 640 && s.height == 480 && s.method == LUCENT_METHOD_SINGLE && s.samples == 8 &&
              s.projection_size == 256 && s.background[3] == 0.5 && s.exposure == -1.5 &&
              s.format == LUCENT_FORMAT_EXR,
          "output settings land in their fields");
    check(!parse("{\"width\": 0}", &s) && s.width == 640, "a rejected document leaves *out as it was");
    check(parse("{\"camera\": {\"direction\": [0, -3, 4]}}", &s) && s.camera.given == 0 &&
              s.camera.direction[0] == 0 && near(s.camera.direction[1], -0.6, 1e-15) &&
              near(s.camera.direction[2], 0.8, 1e-15),
          "camera.direction: framed automatically (given 0), normalized");
    check(parse("{\"material\": {\"preset\": \"marble\", \"profile\": \"BURLEY\"}}", &s) &&
              s.material.profile == LUCENT_PROFILE_BURLEY && strcmp(s.material.preset, "marble") == 0 &&
              parse("{\"material\": {\"preset\": \"marble\"}}", &s) && s.material.profile == LUCENT_PROFILE_DEFAULT &&
              strcmp(lucent_profile_name(s.material.profile), "dipole") == 0,
          "material.profile with a preset; without one DEFAULT (the dipole, or method auto's choice)");
    check(parse("{\"material\": {\"preset\": \"skin1\", \"profile\": \"asymptotic_dipole\"}}", &s) &&
              s.material.profile == LUCENT_PROFILE_ASYMPTOTIC_DIPOLE &&
              strcmp(lucent_profile_name(s.material.profile), "asymptotic_dipole") == 0,
          "material.profile asymptotic_dipole");
    check(parse("{\"method\": \"auto\"}", &s) && s.single_scattering == LUCENT_CHOSEN &&
              parse("{\"method\": \"auto\", \"single_scattering\": false}", &s) && s.single_scattering == 0 &&
              parse("{\"method\": \"five\"}", &s) && s.single_scattering == 0,
          "single_scattering: left to method auto when it is not given (LUCENT_CHOSEN), else as given");
}

/* Total diffuse reflectance of the dipole (research notes §1.3), used to check the transcription
 * of every preset against the notes' computed Rd column. */
static double rd_total(double sigma_a, double sigma_s_prime, double eta)
{
    double alpha = sigma_s_prime / (sigma_a + sigma_s_prime);
    double fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    double a = (1 + fdr) / (1 - fdr), s = sqrt(3 * (1 - alpha));
    return alpha / 2 * (1 + exp(-4.0 / 3.0 * a * s)) * exp(-s);
}

static void test_presets(void)
{
    /* translucency.md §2 "Rd formula" column; marble at its eta 1.5 (§1.7). */
    static const struct {
        const char *name;
        double rd[3];
    } expect[] = {
        {"apple", {0.846, 0.841, 0.528}},    {"chicken1", {0.314, 0.156, 0.126}},
        {"chicken2", {0.321, 0.160, 0.108}}, {"cream", {0.976, 0.900, 0.725}},
        {"ketchup", {0.164, 0.006, 0.002}},  {"marble", {0.830, 0.791, 0.753}},
        {"potato", {0.764, 0.613, 0.213}},   {"skimmilk", {0.815, 0.813, 0.682}},
        {"skin1", {0.436, 0.227, 0.131}},    {"skin2", {0.623, 0.433, 0.343}},
        {"spectralon", {1.000, 1.000, 1.000}}, {"wholemilk", {0.908, 0.881, 0.759}},
    };
    char line[200], json[100];
    int count = 0;
    while (lucent_material_preset_name(count))
        count++;
    check(count == 12 && lucent_material_preset_name(-1) == NULL, "12 presets, NULL outside 0..11");
    for (int i = 0; i < 12; i++) {
        lucent_material m = {0};
        lucent_scene s;
        const char *name = lucent_material_preset_name(i);
        int ok = name && strcmp(name, expect[i].name) == 0 &&
                 lucent_material_preset(name, &m) == LUCENT_OK;
        snprintf(json, sizeof json, "{\"material\": {\"preset\": \"%s\"}}", expect[i].name);
        ok = ok && parse(json, &s) && memcmp(&s.material, &m, sizeof m) == 0;
        ok = ok && m.eta == (strcmp(expect[i].name, "marble") == 0 ? 1.5 : 1.3);
        for (int c = 0; c < 3; c++)
            ok = ok && near(rd_total(m.sigma_a[c], m.sigma_s_prime[c], m.eta), expect[i].rd[c],
                            0.0006);
        snprintf(line, sizeof line, "preset %-10s parses; Rd %.3f %.3f %.3f matches the notes",
                 expect[i].name, rd_total(m.sigma_a[0], m.sigma_s_prime[0], m.eta),
                 rd_total(m.sigma_a[1], m.sigma_s_prime[1], m.eta),
                 rd_total(m.sigma_a[2], m.sigma_s_prime[2], m.eta));
        check(ok, line);
    }
    lucent_material m;
    check(lucent_material_preset("SkIn1", &m) == LUCENT_OK && strcmp(m.preset, "skin1") == 0 &&
              m.sigma_a[0] == 0.032 && m.sigma_s_prime[2] == 1.01,
          "preset lookup is case-insensitive and stores the lowercase name");
    check(lucent_material_preset("jade", &m) == LUCENT_E_INVALID &&
              lucent_material_preset(NULL, &m) == LUCENT_E_INVALID,
          "unknown or NULL preset name is LUCENT_E_INVALID");
}

int main(void)
{
    int n = (int)(sizeof cases / sizeof cases[0]);
    for (int i = 0; i < n; i++)
        run_case(i, &cases[i]);
    test_defaults();
    test_values();
    test_presets();
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
