/* test_lucentd_units.c - the daemon's pure parts without HTTP or Vulkan: the ETag changes with every scene
 * field, GET query fields build the same scene as the POST document, the error table, the image LRU. */
#include "accept_header.h"
#include "image_cache.h"
#include "problem.h"
#include "rate_limit.h"
#include "request_origin.h"
#include "scene_canonical.h"
#include "scene_query.h"
#include "test_support.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static lucent_scene parse(const char *json)
{
    lucent_scene s;
    lucent_error err = {0};
    if (lucent_scene_parse(json, strlen(json), 0, &s, &err) != LUCENT_OK) {
        fprintf(stderr, "test scene rejected: %s: %s\n", err.field, err.message);
        exit(1);
    }
    return s;
}

/* One scene per field, each differing from the defaults in that field only. */
static const char *const variants[] = {
    "{}",
    "{\"mesh\":{\"builtin\":\"torus\"}}",
    "{\"mesh\":{\"builtin\":\"sphere\",\"triangles\":5000}}",
    "{\"mesh\":{\"id\":\"0000000000000000000000000000000000000000000000000000000000000000\"}}",
    "{\"mesh\":{\"id\":\"0000000000000000000000000000000000000000000000000000000000000001\"}}",
    "{\"scale_mm\":10}",
    "{\"material\":{\"preset\":\"skin1\"}}",
    "{\"material\":{\"sigma_a\":[0.0021,0.0041,0.0071],\"sigma_s_prime\":[2.19,2.62,3.00],\"eta\":1.5}}",
    "{\"material\":{\"sigma_a\":[0.0022,0.0041,0.0071],\"sigma_s_prime\":[2.19,2.62,3.00],\"eta\":1.5}}",
    "{\"material\":{\"sigma_a\":[0.0021,0.0042,0.0071],\"sigma_s_prime\":[2.19,2.62,3.00],\"eta\":1.5}}",
    "{\"material\":{\"sigma_a\":[0.0021,0.0041,0.0072],\"sigma_s_prime\":[2.19,2.62,3.00],\"eta\":1.5}}",
    "{\"material\":{\"sigma_a\":[0.0021,0.0041,0.0071],\"sigma_s_prime\":[2.2,2.62,3.00],\"eta\":1.5}}",
    "{\"material\":{\"sigma_a\":[0.0021,0.0041,0.0071],\"sigma_s_prime\":[2.19,2.63,3.00],\"eta\":1.5}}",
    "{\"material\":{\"sigma_a\":[0.0021,0.0041,0.0071],\"sigma_s_prime\":[2.19,2.62,3.01],\"eta\":1.5}}",
    "{\"material\":{\"sigma_a\":[0.0021,0.0041,0.0071],\"sigma_s_prime\":[2.19,2.62,3.00],\"eta\":1.4}}",
    "{\"material\":{\"preset\":\"marble\",\"g\":0.5}}",
    "{\"lights\":[{\"direction\":[-1,-1,-1]},{\"direction\":[1,0,0]}]}",
    "{\"lights\":[{\"direction\":[-1,0,0]}]}",
    "{\"lights\":[{\"direction\":[0,-1,0]}]}",
    "{\"lights\":[{\"direction\":[0,0,-1]}]}",
    "{\"lights\":[{\"type\":\"point\",\"position\":[1,0,0]}]}",
    "{\"lights\":[{\"type\":\"point\",\"position\":[0,1,0]}]}",
    "{\"lights\":[{\"type\":\"point\",\"position\":[0,0,1]}]}",
    "{\"lights\":[{\"direction\":[-1,-1,-1],\"color\":[0.5,1,1]}]}",
    "{\"lights\":[{\"direction\":[-1,-1,-1],\"color\":[1,0.5,1]}]}",
    "{\"lights\":[{\"direction\":[-1,-1,-1],\"color\":[1,1,0.5]}]}",
    "{\"lights\":[{\"direction\":[-1,-1,-1],\"intensity\":2}]}",
    "{\"camera\":{\"position\":[0,0,5],\"target\":[0,0,0]}}",
    "{\"camera\":{\"position\":[0,0,6],\"target\":[0,0,0]}}",
    "{\"camera\":{\"position\":[0,0,5],\"target\":[0,0.1,0]}}",
    "{\"camera\":{\"position\":[0,0,5],\"target\":[0,0,0],\"up\":[1,0,0]}}",
    "{\"camera\":{\"position\":[0,0,5],\"target\":[0,0,0],\"fov_deg\":30}}",
    "{\"width\":256}",
    "{\"height\":256}",
    "{\"method\":\"single\"}",
    "{\"method\":\"reference\"}",
    "{\"method\":\"auto\"}",
    "{\"samples\":8}",
    "{\"sampling\":\"per_channel\"}",
    "{\"fallback\":\"front\"}",
    "{\"single_scattering\":true}",
    "{\"projection_size\":256}",
    "{\"side_projection_size\":128}",
    "{\"background\":[0.1,0,0,0]}",
    "{\"background\":[0,0.1,0,0]}",
    "{\"background\":[0,0,0.1,0]}",
    "{\"background\":[0,0,0,0.5]}",
    "{\"exposure\":1}",
    "{\"format\":\"exr\"}",
    "{\"method\":\"reference\",\"reference\":{\"points\":2000}}",
    "{\"method\":\"reference\",\"reference\":{\"threshold\":0.5}}",
    "{\"method\":\"path\"}",
    "{\"method\":\"path\",\"path\":{\"samples\":4}}",
    "{\"method\":\"path\",\"path\":{\"time_s\":2}}",
    "{\"method\":\"path\",\"path\":{\"boundary\":\"cycles\"}}",
    "{\"method\":\"path\",\"path\":{\"seed\":7}}",
};
#define VARIANTS ((int)(sizeof variants / sizeof variants[0]))

static void etags_cover_every_field(void)
{
    static char tags[VARIANTS][65];
    int distinct = 1;
    for (int i = 0; i < VARIANTS; i++) {
        lucent_scene s = parse(variants[i]);
        if (scene_etag(&s, "device", tags[i]) != 0) {
            test_check(0, "etag of %s", variants[i]);
            return;
        }
        for (int j = 0; j < i; j++)
            if (strcmp(tags[i], tags[j]) == 0) {
                distinct = 0;
                printf("   same etag: %s and %s\n", variants[i], variants[j]);
            }
    }
    test_check(distinct, "%d scenes differing in one field each have %d different ETags", VARIANTS, VARIANTS);
    lucent_scene a = parse("{\"lights\":[{\"direction\":[-1,-1,-1]}]}");
    lucent_scene b = parse("{\"lights\":[{\"direction\":[-2,-2,-2],\"intensity\":1.0}]}");
    char ta[65], tb[65], tc[65];
    scene_etag(&a, "device", ta);
    scene_etag(&b, "device", tb);
    test_check(strcmp(ta, tb) == 0, "scenes equal after parsing share one ETag (%.12s, %.12s)", ta, tb);
    scene_etag(&a, "other device", tc);
    test_check(strcmp(ta, tc) != 0, "the device is part of the ETag");
    a.exposure = -0.0;
    b.exposure = 0.0;
    scene_etag(&a, "device", ta);
    scene_etag(&b, "device", tb);
    test_check(strcmp(ta, tb) == 0, "-0 and 0 give one ETag");
    char text[4096];
    int n = scene_canonical(&a, text, sizeof text);
    test_check(n > 0 && scene_canonical(&a, text, 16) == -1, "canonical text is %d bytes; a small buffer is refused", n);
}

static lucent_status query(const char *const *kv, int count, lucent_scene *s, lucent_error *err)
{
    struct query_field f[64];   /* MAX_QUERY_FIELDS of routes.c */
    for (int i = 0; i < count; i++)
        f[i] = (struct query_field){kv[2 * i], kv[2 * i + 1]};
    int format_given = 0;
    return scene_query_parse(f, count, s, &format_given, err);
}

static void query_matches_document(void)
{
    static const char *const kv[] = {
        "mesh", "torus", "mesh_triangles", "3000", "scale_mm", "20", "sigma_a", "0.01,0.02,0.03",
        "sigma_s_prime", "1,2,3", "eta", "1.4", "g", "0.2", "light_type", "point", "light_pos", "3,4,5",
        "light_color", "1,0.5,0.25", "light_intensity", "7", "camera_pos", "0,1,5", "camera_target", "0,0.5,0",
        "camera_up", "0,1,0.1", "fov", "35", "w", "200", "h", "100", "method", "single", "samples", "12",
        "sampling", "per_channel", "fallback", "front", "single_scattering", "true", "projection_size", "256",
        "side_projection_size", "64", "background", "0.1,0.2,0.3,0.4", "exposure", "-1.5", "format", "exr",
        "reference_points", "2000", "reference_threshold", "0.25", "path_samples", "32", "path_time_s", "5",
        "path_boundary", "cycles", "path_seed", "9"};
    const char *doc = "{\"mesh\":{\"builtin\":\"torus\",\"triangles\":3000},\"scale_mm\":20,"
                      "\"material\":{\"sigma_a\":[0.01,0.02,0.03],\"sigma_s_prime\":[1,2,3],\"eta\":1.4,\"g\":0.2},"
                      "\"lights\":[{\"type\":\"point\",\"position\":[3,4,5],\"color\":[1,0.5,0.25],\"intensity\":7}],"
                      "\"camera\":{\"position\":[0,1,5],\"target\":[0,0.5,0],\"up\":[0,1,0.1],\"fov_deg\":35},"
                      "\"width\":200,\"height\":100,\"method\":\"single\",\"samples\":12,\"sampling\":\"per_channel\","
                      "\"fallback\":\"front\",\"single_scattering\":true,\"projection_size\":256,"
                      "\"side_projection_size\":64,\"background\":[0.1,0.2,0.3,0.4],\"exposure\":-1.5,\"format\":\"exr\","
                      "\"reference\":{\"points\":2000,\"threshold\":0.25},"
                      "\"path\":{\"samples\":32,\"time_s\":5,\"boundary\":\"cycles\",\"seed\":9}}";
    lucent_scene q, d = parse(doc);
    lucent_error err = {0};
    lucent_status st = query(kv, (int)(sizeof kv / sizeof kv[0] / 2), &q, &err);
    char tq[4096] = "", td[4096] = "";
    if (st == LUCENT_OK)
        scene_canonical(&q, tq, sizeof tq);
    scene_canonical(&d, td, sizeof td);
    test_check(st == LUCENT_OK && strcmp(tq, td) == 0, "%zu query fields build the POST document's scene%s%s",
               sizeof kv / sizeof kv[0] / 2, st == LUCENT_OK ? "" : ": ", st == LUCENT_OK ? "" : err.message);

    static const char *const framed[] = {"camera_dir", "1,-1,-2", "fov", "30"};
    lucent_scene fd = parse("{\"camera\":{\"direction\":[1,-1,-2],\"fov_deg\":30}}");
    st = query(framed, 2, &q, &err);
    if (st == LUCENT_OK)
        scene_canonical(&q, tq, sizeof tq);
    scene_canonical(&fd, td, sizeof td);
    test_check(st == LUCENT_OK && strcmp(tq, td) == 0 && q.camera.given == 0,
               "camera_dir builds the document's automatically framed camera%s%s", st == LUCENT_OK ? "" : ": ",
               st == LUCENT_OK ? "" : err.message);
    static const char *const both[] = {"camera_dir", "0,0,-1", "camera_pos", "0,0,5", "camera_target", "0,0,0"};
    st = query(both, 3, &q, &err);
    test_check(st == LUCENT_E_INVALID && strcmp(err.field, "camera_dir") == 0,
               "camera_dir with camera_pos and camera_target: %s naming \"%s\"", lucent_status_name(st), err.field);

    static const char *const id[] = {"mesh", "00000000000000000000000000000000000000000000000000000000000000ab"};
    st = query(id, 1, &q, &err);
    test_check(st == LUCENT_OK && q.mesh.source == LUCENT_MESH_STORED && strcmp(q.mesh.id, id[1]) == 0,
               "mesh=<64 hex> names a stored mesh");

    static const struct {
        const char *key, *value, *field;
    } bad[] = {
        {"light_dir", "0,0,0", "light_dir"},     {"background", "0,0,0,2", "background[3]"}, {"w", "1.5", "w"},
        {"w", "abc", "w"},                       {"mesh", "cube", "mesh"},            {"eta", "nan", "eta"},
        {"single_scattering", "yes", "single_scattering"}, {"colour", "red", "colour"},
        {"mesh_triangles", "5000", "mesh"},      {"w", "0x10", "w"},                  {"w", " 64", "w"},
        {"exposure", "+1", "exposure"},          {"exposure", "1.", "exposure"},      {"exposure", "01", "exposure"},
        {"background", "0,,0,1", "background"}, {"background", "0,0,0,", "background"},
        {"light_type", "spot", "light_type"},   {"reference_points", "500", "reference_points"},
        {"reference_threshold", "2", "reference_threshold"},
        {"path_samples", "0", "path_samples"},  {"path_boundary", "rough", "path_boundary"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        const char *kv1[] = {bad[i].key, bad[i].value};
        memset(&err, 0, sizeof err);
        st = query(kv1, 1, &q, &err);
        test_check(st != LUCENT_OK && strcmp(err.field, bad[i].field) == 0, "%s=%s refused naming \"%s\" (got \"%s\": %s)",
                   bad[i].key, bad[i].value, bad[i].field, err.field, err.message);
    }
    /* light_pos alone implies a point light; an explicit light_type wins, so a directional light with a
     * position and no direction is refused rather than quietly turned into a point light. */
    const char *typed[] = {"light_type", "directional", "light_pos", "3,4,5"};
    memset(&err, 0, sizeof err);
    st = query(typed, 2, &q, &err);
    test_check(st == LUCENT_E_INVALID && strcmp(err.field, "light_pos") == 0,
               "light_type=directional&light_pos=3,4,5 refused naming \"light_pos\", not a point light (\"%s\": %s)",
               err.field, err.message);
    const char *twice[] = {"w", "10", "w", "20"};
    st = query(twice, 2, &q, &err);
    test_check(st == LUCENT_E_INVALID && strcmp(err.field, "w") == 0, "a repeated field is refused");
}

static void problem_table(void)
{
    static const struct {
        int code;
        const char *field;
        unsigned http;
    } rows[] = {
        {LUCENT_E_INVALID, "width", 400},       {LUCENT_E_INVALID, "Content-Type", 415},
        {LUCENT_E_INVALID, "mesh.id", 404},     {LUCENT_E_MESH, "mesh", 422},
        {LUCENT_E_LIMIT, "width", 413},         {LUCENT_E_IO, "", 500},
        {LUCENT_E_GPU, "", 500},             {LUCENT_E_INTERNAL, "", 500},
        {PROBLEM_NO_ROUTE, "", 404},            {PROBLEM_METHOD, "", 405},
        {PROBLEM_NOT_ACCEPTABLE, "Accept", 406}, {PROBLEM_UNAUTHORIZED, "", 401},
        {PROBLEM_TOKEN_WRONG, "", 401},         {PROBLEM_RATE_LIMITED, "", 429},
        {PROBLEM_QUEUE_FULL, "", 503},          {PROBLEM_DEADLINE, "", 503},
        {PROBLEM_BODY_TOO_LARGE, "", 413},      {9999, "", 500},
    };
    int ok = 1;
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        const struct problem_kind *k = problem_lookup(rows[i].code, rows[i].field);
        if (!k || k->http_status != rows[i].http) {
            ok = 0;
            printf("   code %d field %s: got %u, expected %u\n", rows[i].code, rows[i].field, k ? k->http_status : 0,
                   rows[i].http);
        }
    }
    test_check(ok, "%zu error codes map to their HTTP statuses (unknown codes to 500)", sizeof rows / sizeof rows[0]);
    lucent_error err = {0};
    lucent_fail(&err, LUCENT_E_INVALID, "material.eta", "bad \xff byte \"quoted\"");
    size_t len = 0;
    char *body = problem_json(problem_lookup(err.status, err.field), &err, "req-1", &len);
    test_check(body && strstr(body, "\"field\":\"material.eta\"") && strstr(body, "\"status\":400") &&
                   strstr(body, "bad ? byte \\\"quoted\\\""),
               "problem body: %s", body ? body : "(null)");
    free(body);
}

static int cached(struct image_cache *c, const char *key)
{
    unsigned char *bytes = NULL;
    size_t len = 0;
    char meta[16];
    int hit = image_cache_get(c, key, &bytes, &len, meta, sizeof meta);
    free(bytes);
    return hit;
}

static void image_cache_lru(void)
{
    unsigned char block[400];
    memset(block, 7, sizeof block);
    struct image_cache *c = image_cache_create(1200);
    image_cache_put(c, "a", block, 400, "ma");
    image_cache_put(c, "b", block, 400, "mb");
    unsigned char *bytes = NULL;
    size_t len = 0;
    char meta[16] = "";
    int hit = image_cache_get(c, "a", &bytes, &len, meta, sizeof meta); /* a is now the most recent */
    test_check(hit && len == 400 && bytes[399] == 7 && strcmp(meta, "ma") == 0, "hit returns the bytes and metadata");
    free(bytes);
    image_cache_put(c, "c", block, 400, "mc");
    test_check(cached(c, "a") && !cached(c, "b") && cached(c, "c") && image_cache_bytes(c) > 800 &&
                   image_cache_bytes(c) <= 1200,
               "over budget the least recently used entry goes (%llu bytes counted of 1200 for two 400-byte images)",
               (unsigned long long)image_cache_bytes(c));
    image_cache_destroy(c);
    /* tiny images with 2 KiB of metadata each (Lucent-Modelled can be that long): 10,000 of them would
     * have fitted a 64 KiB budget when only image bytes counted (10 KB), holding 20 MB */
    enum { PUT = 10000, BUDGET = 64 * 1024 };
    char long_meta[2049], key[32];
    memset(long_meta, 'm', 2048);
    long_meta[2048] = 0;
    c = image_cache_create(BUDGET);
    for (int i = 0; i < PUT; i++) {
        snprintf(key, sizeof key, "k%d", i);
        image_cache_put(c, key, block, 1, long_meta);
    }
    int kept = 0;
    for (int i = 0; i < PUT; i++) {
        snprintf(key, sizeof key, "k%d", i);
        kept += cached(c, key);
    }
    int newest = cached(c, "k9999") && !cached(c, "k0");
    test_check(kept > 0 && (uint64_t)kept * 2049 <= BUDGET && image_cache_bytes(c) <= BUDGET && newest,
               "%d one-byte images with 2 KiB of metadata in a 64 KiB budget: %d kept (%llu bytes counted), "
               "the most recent ones", PUT, kept, (unsigned long long)image_cache_bytes(c));
    image_cache_destroy(c);
    c = image_cache_create(300);
    image_cache_put(c, "a", block, 400, "");
    test_check(!cached(c, "a") && image_cache_bytes(c) == 0, "an image larger than the budget is not stored");
    image_cache_destroy(c);
    c = image_cache_create(0);
    image_cache_put(c, "a", block, 1, "");
    test_check(!cached(c, "a"), "budget 0 stores nothing");
    image_cache_destroy(c);
}

static struct sockaddr_in ipv4(uint32_t host)
{
    struct sockaddr_in a = {.sin_family = AF_INET};
    a.sin_addr.s_addr = htonl(host);
    return a;
}

/* Token buckets: a burst, then one request per 1/rate seconds; clients apart; the table bounded. */
static void rate_limit_buckets(void)
{
    struct rate_limit *rl = rate_limit_new(2.0, 3.0);
    struct sockaddr_in a = ipv4(0x7f000001), b = ipv4(0x7f000002);
    const struct sockaddr *pa = (const struct sockaddr *)&a, *pb = (const struct sockaddr *)&b;
    double w[6] = {rate_limit_take(rl, pa, 0.0), rate_limit_take(rl, pa, 0.0), rate_limit_take(rl, pa, 0.0),
                   rate_limit_take(rl, pa, 0.0), rate_limit_take(rl, pb, 0.0), rate_limit_take(rl, pa, 0.5)};
    test_check(w[0] == 0 && w[1] == 0 && w[2] == 0 && w[3] == 0.5 && w[4] == 0 && w[5] == 0,
               "burst of 3 passes, the 4th waits %g s (0.5 at 2/s), another client passes (%g), and the first again "
               "after 0.5 s (%g)", w[3], w[4], w[5]);
    /* 100000 clients: each starts with a full bucket; the first, forgotten or not, is never over its rate */
    int refused = 0;
    for (uint32_t i = 0; i < 100000; i++) {
        struct sockaddr_in c = ipv4(0x0a000000u + i);
        refused += rate_limit_take(rl, (const struct sockaddr *)&c, 1.0) > 0;
    }
    test_check(refused == 0, "100000 clients at once in a fixed table: %d refused (want 0)", refused);
    rate_limit_free(rl);
}

/* The Host and Origin rules against DNS rebinding and web pages driving the daemon. */
static void hosts_and_origins(void)
{
    static const struct {
        const char *host, *allowed, *listen;
        int want;
    } hosts[] = {
        {"127.0.0.1:8080", "", "127.0.0.1", 1},     {"localhost:8080", "", "127.0.0.1", 1},
        {"LOCALHOST", "", "127.0.0.1", 1},          {"[::1]:8080", "", "::1", 1},
        {NULL, "", "127.0.0.1", 1},                 {"evil.example:8080", "", "127.0.0.1", 0},
        {"127.0.0.1.evil.example", "", "127.0.0.1", 0}, {"localhost:80x", "", "127.0.0.1", 0},
        {"[::1]x", "", "127.0.0.1", 0},             {"evil.example", "", "0.0.0.0", 1},
        {"render.example:443", "render.example, other", "0.0.0.0", 1}, {"evil.example", "render.example", "0.0.0.0", 0},
        {"localhost", "render.example", "127.0.0.1", 0}, {"anything", "*", "127.0.0.1", 1},
    };
    int wrong = 0;
    for (size_t i = 0; i < sizeof hosts / sizeof hosts[0]; i++)
        if (host_allowed(hosts[i].host, hosts[i].allowed, hosts[i].listen) != hosts[i].want) {
            printf("     Host %s with --allowed-hosts \"%s\", listening on %s: want %d\n",
                   hosts[i].host ? hosts[i].host : "(none)", hosts[i].allowed, hosts[i].listen, hosts[i].want);
            wrong++;
        }
    test_check(wrong == 0, "%zu Host cases (loopback names by default, ports, IPv6, lists, *): %d wrong",
               sizeof hosts / sizeof hosts[0], wrong);
    static const struct {
        const char *origin, *host, *cors;
        int want;
    } origins[] = {
        {NULL, "127.0.0.1:8080", "", 1},                          {"http://127.0.0.1:8080", "127.0.0.1:8080", "", 1},
        {"http://evil.example", "127.0.0.1:8080", "", 0},         {"null", "127.0.0.1:8080", "", 0},
        {"https://127.0.0.1:8080", "127.0.0.1:8080", "", 0},      {"http://127.0.0.1:9090", "127.0.0.1:8080", "", 0},
        {"https://app.example", "127.0.0.1:8080", "https://app.example", 1},
        {"http://evil.example", "127.0.0.1:8080", "*", 1},        {"http://localhost:8080", NULL, "", 0},
    };
    wrong = 0;
    for (size_t i = 0; i < sizeof origins / sizeof origins[0]; i++)
        if (origin_allowed(origins[i].origin, origins[i].host, origins[i].cors) != origins[i].want) {
            printf("     Origin %s to Host %s with --cors-origins \"%s\": want %d\n",
                   origins[i].origin ? origins[i].origin : "(none)", origins[i].host ? origins[i].host : "(none)",
                   origins[i].cors, origins[i].want);
            wrong++;
        }
    test_check(wrong == 0, "%zu Origin cases (none, the daemon's own, foreign, null, configured, *): %d wrong",
               sizeof origins / sizeof origins[0], wrong);
}

/* Accept items of any length, and only a parameter named q as the q-value. */
static void accept_values(void)
{
    char long_params[400];
    snprintf(long_params, sizeof long_params, "image/png;%0300d=1;q=0, */*", 0);
    static const struct {
        const char *accept, *type;
        double want;
    } cases[] = {
        {"image/png", "image/png", 1},          {"image/png;q=0.5", "image/png", 0.5},
        {"image/png ; Q = 0.25", "image/png", 0.25}, {"image/png;sq=0", "image/png", 1},
        {"image/png;q=0, image/*", "image/png", 0}, {"image/*;q=0.3, */*", "image/x-exr", 0.3},
        {"text/html", "image/png", 0},          {"IMAGE/PNG;q=2", "image/png", 1},
        {"*/*;q=0.1", "image/x-exr", 0.1},      {"", "image/png", 0},
    };
    int wrong = 0;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        if (accept_q(cases[i].accept, cases[i].type) != cases[i].want) {
            printf("     Accept \"%s\" for %s: %g, want %g\n", cases[i].accept, cases[i].type,
                   accept_q(cases[i].accept, cases[i].type), cases[i].want);
            wrong++;
        }
    double q = accept_q(long_params, "image/png");
    test_check(wrong == 0 && q == 0, "%zu Accept cases (q=, sq=, spaces, case, specificity) %d wrong; q=0 after "
               "300 bytes of parameters honoured (%g)", sizeof cases / sizeof cases[0], wrong, q);
}

int main(void)
{
    etags_cover_every_field();
    query_matches_document();
    problem_table();
    image_cache_lru();
    rate_limit_buckets();
    hosts_and_origins();
    accept_values();
    return test_finish();
}
