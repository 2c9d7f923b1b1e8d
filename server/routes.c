/* routes.c - the HTTP API: the route table and one handler per route. Handlers validate, answer from the
 * ETag or the image cache when they can, else hand the work to a queue; errors go through problem.c. */
#include "routes.h"

#include "accept_header.h"
#include "http_server.h"
#include "json_text.h"
#include "image_cache.h"
#include "connection_guard.h"
#include "import_jail.h"
#include "mesh_store.h"
#include "metrics.h"
#include "problem.h"
#include "render_queue.h"
#include "scene_canonical.h"
#include "scene_query.h"
#include "server.h"
#include "upload_form.h"
#include "upload_queue.h"

#include "lucentd_build.h"

#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

extern const unsigned char lucentd_openapi_json[];
extern const size_t lucentd_openapi_json_len;

/* ---- static files: the web preview page (issue 5), client/web/ embedded by server/CMakeLists.txt ---- */
#define WEB_FILE(name) extern const unsigned char lucentd_web_##name[]; extern const size_t lucentd_web_##name##_len;
WEB_FILE(index_html)
WEB_FILE(app_js)
WEB_FILE(style_css)
WEB_FILE(lucent_js)
WEB_FILE(embed_example_html)
#undef WEB_FILE

struct static_file {
    const char *path;
    const char *content_type;
    const unsigned char *bytes;
    const size_t *len;
};

static const struct static_file static_files[] = {
    {"/", "text/html; charset=utf-8", lucentd_web_index_html, &lucentd_web_index_html_len},
    {"/app.js", "text/javascript; charset=utf-8", lucentd_web_app_js, &lucentd_web_app_js_len},
    {"/style.css", "text/css; charset=utf-8", lucentd_web_style_css, &lucentd_web_style_css_len},
    {"/lucent.js", "text/javascript; charset=utf-8", lucentd_web_lucent_js, &lucentd_web_lucent_js_len},
    {"/embed-example.html", "text/html; charset=utf-8", lucentd_web_embed_example_html,
     &lucentd_web_embed_example_html_len},
};

static const struct static_file *static_file_find(const char *path)
{
    for (size_t i = 0; i < sizeof static_files / sizeof static_files[0]; i++)
        if (strcmp(path, static_files[i].path) == 0)
            return &static_files[i];
    return NULL;
}
/* ---- end of static files' table ---- */

static enum MHD_Result handle_render(struct request *req);
static enum MHD_Result handle_materials(struct request *req);
static enum MHD_Result handle_healthz(struct request *req);
static enum MHD_Result handle_readyz(struct request *req);
static enum MHD_Result handle_metrics(struct request *req);
static enum MHD_Result handle_openapi(struct request *req);
static enum MHD_Result handle_meshes(struct request *req);
static enum MHD_Result handle_mesh(struct request *req);
static enum MHD_Result handle_static(struct request *req);

static const struct route routes[] = {
    {"render", "/v1/render", 0, M_GET | M_HEAD | M_POST, 0, handle_render},
    {"materials", "/v1/materials", 0, M_GET | M_HEAD, 0, handle_materials},
    {"healthz", "/healthz", 0, M_GET | M_HEAD, 1, handle_healthz},
    {"readyz", "/readyz", 0, M_GET | M_HEAD, 1, handle_readyz},
    {"metrics", "/metrics", 0, M_GET | M_HEAD, 0, handle_metrics},
    {"openapi", "/openapi.json", 0, M_GET | M_HEAD, 0, handle_openapi},
    {"meshes", "/v1/meshes", 0, M_GET | M_HEAD | M_POST, 0, handle_meshes},
    {"mesh", "/v1/meshes/", 1, M_GET | M_HEAD | M_DELETE, 0, handle_mesh},
    /* Matches every path of static_files[]; open: the page holds no secret and asks for the token itself. */
    {"static", "/", 0, M_GET | M_HEAD, 1, handle_static},
};
#define ROUTE_COUNT ((int)(sizeof routes / sizeof routes[0]))

const char *const route_labels[] = {"render",  "materials", "healthz", "readyz",
                                    "metrics", "openapi",   "meshes",  "mesh", "static", "unmatched"};
const int route_label_count = ROUTE_COUNT + 1;
_Static_assert(sizeof route_labels / sizeof route_labels[0] == sizeof routes / sizeof routes[0] + 1,
               "one metrics label per route, plus unmatched");

const struct route *route_match(const char *path, int *index)
{
    for (int i = 0; i < ROUTE_COUNT; i++) {
        size_t n = strlen(routes[i].path);
        int hit = routes[i].handler == handle_static ? static_file_find(path) != NULL
                  : routes[i].prefix ? strncmp(path, routes[i].path, n) == 0 && path[n] && !strchr(path + n, '/')
                                     : strcmp(path, routes[i].path) == 0;
        if (hit) {
            *index = i;
            return &routes[i];
        }
    }
    *index = ROUTE_UNMATCHED;
    return NULL;
}

void route_allow(unsigned methods, char *buf, size_t cap)
{
    static const struct { unsigned bit; const char *name; } names[] = {
        {M_GET, "GET"}, {M_HEAD, "HEAD"}, {M_POST, "POST"}, {M_DELETE, "DELETE"}, {M_OPTIONS, "OPTIONS"}};
    size_t used = 0;
    buf[0] = 0;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if ((methods | M_OPTIONS) & names[i].bit) {
            int n = snprintf(buf + used, cap - used, "%s%s", used ? ", " : "", names[i].name);
            if (n < 0 || (size_t)n >= cap - used)
                return;
            used += (size_t)n;
        }
}

/* Sends a JSON document (consumed); extra_name/value add one header when not NULL. */
static enum MHD_Result send_json(struct request *req, unsigned status, json_t *doc, const char *extra_name,
                                 const char *extra_value)
{
    char *text = doc ? json_text(doc) : NULL;
    json_decref(doc);
    if (!text)
        return http_send_problem(req, LUCENT_E_NOMEM, NULL, "out of memory writing the answer");
    size_t len = strlen(text);
    struct MHD_Response *resp = MHD_create_response_from_buffer(len, text, MHD_RESPMEM_MUST_FREE);
    if (!resp) {
        free(text);
        return MHD_NO;
    }
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    if (extra_name)
        MHD_add_response_header(resp, extra_name, extra_value);
    req->bytes_out = len;
    return http_send(req, status, resp);
}

/* ---- /v1/render ---- */

static const char *const content_types[] = {[LUCENT_FORMAT_PNG] = "image/png", [LUCENT_FORMAT_EXR] = "image/x-exr"};

/* Picks the output format: the scene's "format" when given, else the better of PNG and EXR by Accept
 * (PNG on a tie). Returns -1 when the Accept header rules out what is possible. */
static int negotiate(struct request *req, lucent_scene *scene, int format_given)
{
    const char *accept = http_header(req, MHD_HTTP_HEADER_ACCEPT);
    if (!accept || !*accept)
        return 0;
    double png = accept_q(accept, content_types[LUCENT_FORMAT_PNG]);
    double exr = accept_q(accept, content_types[LUCENT_FORMAT_EXR]);
    if (format_given)
        return (scene->format == LUCENT_FORMAT_PNG ? png : exr) > 0 ? 0 : -1;
    if (png <= 0 && exr <= 0)
        return -1;
    scene->format = exr > png ? LUCENT_FORMAT_EXR : LUCENT_FORMAT_PNG;
    return 0;
}

/* The server's limits, stricter than the parser's; their errors name the field as the client wrote it. */
static int check_limits(const struct server *srv, const lucent_scene *s, int query, lucent_error *err)
{
    const struct config *cfg = &srv->cfg;
    uint64_t pixels = (uint64_t)s->width * (uint64_t)s->height;
    if (s->width > cfg->max_width)
        return lucent_fail(err, LUCENT_E_LIMIT, query ? "w" : "width", "at most %d on this server (got %d)",
                           cfg->max_width, s->width);
    if (s->height > cfg->max_height)
        return lucent_fail(err, LUCENT_E_LIMIT, query ? "h" : "height", "at most %d on this server (got %d)",
                           cfg->max_height, s->height);
    if (pixels > srv->max_pixels)
        return lucent_fail(err, LUCENT_E_LIMIT, query ? "w" : "width",
                           "%dx%d is %llu pixels; the device \"%s\" renders at most %llu", s->width, s->height,
                           (unsigned long long)pixels, srv->device, (unsigned long long)srv->max_pixels);
    if (s->samples > cfg->max_samples)
        return lucent_fail(err, LUCENT_E_LIMIT, "samples", "at most %d on this server (got %d)", cfg->max_samples,
                           s->samples);
    if (s->light_count > cfg->max_lights)
        return lucent_fail(err, LUCENT_E_LIMIT, "lights", "at most %d on this server (got %d)", cfg->max_lights,
                           s->light_count);
    if (s->projection_size > cfg->max_projection_size)
        return lucent_fail(err, LUCENT_E_LIMIT, "projection_size", "at most %d on this server (got %d)",
                           cfg->max_projection_size, s->projection_size);
    if (s->mesh.source == LUCENT_MESH_BUILTIN && s->mesh.triangles > cfg->max_triangles)
        return lucent_fail(err, LUCENT_E_LIMIT, query ? "mesh_triangles" : "mesh.triangles",
                           "at most %u on this server (got %u)", cfg->max_triangles, s->mesh.triangles);
    return LUCENT_OK;
}

/* curl -d sends application/x-www-form-urlencoded unless told otherwise; the body is still the scene. */
static int scene_content_type_ok(const char *ct)
{
    static const char *const ok[] = {"application/json", "application/x-www-form-urlencoded", "text/plain"};
    if (!ct)
        return 1;
    size_t n = strcspn(ct, "; ");
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++)
        if (n == strlen(ok[i]) && strncasecmp(ct, ok[i], n) == 0)
            return 1;
    return 0;
}

#define MAX_QUERY_FIELDS 64

struct query_collect {
    struct query_field fields[MAX_QUERY_FIELDS];
    int count, overflow;
};

static enum MHD_Result collect_query(void *cls, enum MHD_ValueKind kind, const char *key, const char *value)
{
    (void)kind;
    struct query_collect *c = cls;
    if (c->count == MAX_QUERY_FIELDS) {
        c->overflow = 1;
        return MHD_NO;
    }
    c->fields[c->count++] = (struct query_field){key, value};
    return MHD_YES;
}

static lucent_status parse_request_scene(struct request *req, lucent_scene *scene, int *format_given,
                                         lucent_error *err)
{
    if (req->method_bit == M_POST) {
        if (!scene_content_type_ok(http_header(req, MHD_HTTP_HEADER_CONTENT_TYPE)))
            return lucent_fail(err, LUCENT_E_INVALID, "Content-Type", "send the scene as application/json");
        if (req->body_len == 0)
            return lucent_fail(err, LUCENT_E_INVALID, "body", "send the scene document (JSON) as the body");
        lucent_status st = lucent_scene_parse((const char *)req->body, req->body_len, 0, scene, err);
        if (st == LUCENT_OK) {
            json_t *doc = json_loadb((const char *)req->body, req->body_len, 0, NULL);
            *format_given = json_object_get(doc, "format") != NULL;
            json_decref(doc);
        }
        return st;
    }
    struct query_collect c = {.count = 0};
    MHD_get_connection_values(req->connection, MHD_GET_ARGUMENT_KIND, collect_query, &c);
    if (c.overflow)
        return lucent_fail(err, LUCENT_E_INVALID, "", "at most %d query fields", MAX_QUERY_FIELDS);
    return scene_query_parse(c.fields, c.count, scene, format_given, err);
}

/* An If-None-Match list naming our tag (weak comparison, RFC 9110 13.1.2), or "*". */
static int etag_matches(const char *inm, const char *etag)
{
    char quoted[70];
    snprintf(quoted, sizeof quoted, "\"%s\"", etag);
    return inm && (strcmp(inm, "*") == 0 || strstr(inm, quoted) != NULL);
}

static void add_cache_headers(struct MHD_Response *resp, const char *etag)
{
    char quoted[70];
    snprintf(quoted, sizeof quoted, "\"%s\"", etag);
    MHD_add_response_header(resp, MHD_HTTP_HEADER_ETAG, quoted);
    /* The tag names the scene, the renderer build and the device: the bytes behind it never change. */
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CACHE_CONTROL, "public, max-age=31536000, immutable");
    MHD_add_response_header(resp, MHD_HTTP_HEADER_VARY, "Accept");
}

/* Header values must be visible ASCII and spaces; the renderer's JSON already is, this makes sure. */
static void header_safe(const char *in, char *out, size_t cap)
{
    size_t i = 0;
    for (; in[i] && i + 1 < cap; i++)
        out[i] = (unsigned char)in[i] < 0x20 || (unsigned char)in[i] > 0x7e ? ' ' : in[i];
    out[i] = 0;
}

static enum MHD_Result send_image(struct request *req, const unsigned char *bytes, size_t len, lucent_format format,
                                  const char *etag, const char *timing, const char *modelled)
{
    struct MHD_Response *resp = MHD_create_response_from_buffer(len, (void *)bytes, MHD_RESPMEM_MUST_COPY);
    if (!resp)
        return MHD_NO;
    char safe[sizeof ((lucent_stats *)0)->modelled];
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, content_types[format]);
    add_cache_headers(resp, etag);
    MHD_add_response_header(resp, "Server-Timing", timing);
    if (modelled && modelled[0]) {
        header_safe(modelled, safe, sizeof safe);
        MHD_add_response_header(resp, "Lucent-Modelled", safe);
    }
    req->bytes_out = len;
    return http_send(req, MHD_HTTP_OK, resp);
}

/* The second call, after the queue resumed the connection. */
static enum MHD_Result finish_render(struct request *req)
{
    struct render_job *job = req->job;
    const struct config *cfg = &req->srv->cfg;
    switch (job->outcome) {
    case JOB_RENDERED: {
        const lucent_stats *s = &job->stats;
        req->queue_ms = job->queue_ms;
        req->render_ms = s->ms_total;
        req->encode_ms = job->encode_ms;
        char timing[512];
        snprintf(timing, sizeof timing,
                 "queue;dur=%.2f, mesh_load;dur=%.2f, shadow;dur=%.2f, projection;dur=%.2f, gbuffer;dur=%.2f, "
                 "scatter;dur=%.2f, readback;dur=%.2f, render;dur=%.2f, encode;dur=%.2f",
                 job->queue_ms, s->ms_mesh_load, s->ms_shadow, s->ms_projection, s->ms_gbuffer, s->ms_scatter,
                 s->ms_readback, s->ms_total, job->encode_ms);
        return send_image(req, job->bytes, job->len, job->scene.format, job->etag, timing, s->modelled);
    }
    case JOB_FAILED:
        return http_send_error(req, &job->err);
    case JOB_DEADLINE:
        return http_send_problem(req, PROBLEM_DEADLINE, NULL,
                                 "the render did not finish within %g s (render-timeout); try a smaller image, "
                                 "fewer samples or later",
                                 cfg->render_timeout_s);
    case JOB_CANCELLED:
    case JOB_PENDING:
        break;
    }
    return http_send_problem(req, PROBLEM_NOT_READY, NULL, "the daemon is shutting down; retry on another instance");
}

static enum MHD_Result handle_render(struct request *req)
{
    struct server *srv = req->srv;
    if (req->job)
        return finish_render(req);
    if (atomic_load(&srv->phase) != PHASE_SERVING)
        return http_send_problem(req, PROBLEM_NOT_READY, NULL, "the daemon is %s",
                                 atomic_load(&srv->phase) == PHASE_STARTING ? "starting" : "shutting down");
    lucent_scene scene;
    lucent_error err = {0};
    int format_given = 0;
    int query = req->method_bit != M_POST;
    if (parse_request_scene(req, &scene, &format_given, &err) != LUCENT_OK ||
        check_limits(srv, &scene, query, &err) != LUCENT_OK)
        return http_send_error(req, &err);
    if (negotiate(req, &scene, format_given) != 0)
        return http_send_problem(req, PROBLEM_NOT_ACCEPTABLE, format_given ? "format" : "Accept",
                                 "this resource is image/png or image/x-exr (Accept: %.80s)",
                                 http_header(req, MHD_HTTP_HEADER_ACCEPT));
    /* Resolved before the ETag and cache checks, so a deleted mesh is a 404, not an old image. */
    struct mesh_info info;
    char mesh_path[sizeof scene.mesh.file];
    if (scene.mesh.source == LUCENT_MESH_STORED) {
        if (mesh_store_get(srv->store, scene.mesh.id, &info, mesh_path, sizeof mesh_path, &err) != LUCENT_OK)
            return http_send_error(req, &err);
        if (info.triangles > srv->cfg.max_triangles)
            return http_send_problem(req, LUCENT_E_LIMIT, "mesh", "the mesh has %u triangles; at most %u on this server",
                                     info.triangles, srv->cfg.max_triangles);
    }
    char etag[65], renderer[sizeof srv->backend + sizeof srv->device + 1];
    snprintf(renderer, sizeof renderer, "%s:%s", srv->backend, srv->device);   /* backends round differently */
    if (scene_etag(&scene, renderer, etag) != 0)
        return http_send_problem(req, LUCENT_E_INTERNAL, NULL, "cannot serialize the scene");
    if (scene.mesh.source == LUCENT_MESH_STORED) {
        scene.mesh.source = LUCENT_MESH_FILE; /* the renderer reads files, never ids */
        memcpy(scene.mesh.file, mesh_path, sizeof mesh_path);
    }
    if (etag_matches(http_header(req, MHD_HTTP_HEADER_IF_NONE_MATCH), etag)) {
        struct MHD_Response *resp = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
        if (!resp)
            return MHD_NO;
        add_cache_headers(resp, etag);
        req->cache = "etag";
        return http_send(req, MHD_HTTP_NOT_MODIFIED, resp);
    }
    unsigned char *bytes = NULL;
    size_t len = 0;
    char modelled[sizeof ((lucent_stats *)0)->modelled];
    double t0 = monotonic_seconds();
    if (image_cache_get(srv->cache, etag, &bytes, &len, modelled, sizeof modelled)) {
        metrics_cache(srv->metrics, 1);
        req->cache = "hit";
        char timing[64];
        snprintf(timing, sizeof timing, "cache;desc=hit;dur=%.2f", (monotonic_seconds() - t0) * 1e3);
        enum MHD_Result r = send_image(req, bytes, len, scene.format, etag, timing, modelled);
        free(bytes);
        return r;
    }
    metrics_cache(srv->metrics, 0);
    req->cache = "miss";
    struct render_job *job = render_job_new();
    if (!job)
        return http_send_problem(req, LUCENT_E_NOMEM, NULL, "out of memory queueing the render");
    job->scene = scene;
    memcpy(job->etag, etag, sizeof etag);
    job->connection = req->connection;
    const union MHD_ConnectionInfo *fd = MHD_get_connection_info(req->connection, MHD_CONNECTION_INFO_CONNECTION_FD);
    job->client_fd = fd ? fd->connect_fd : -1;
    job->deadline = monotonic_seconds() + srv->cfg.render_timeout_s;
    if (render_queue_submit(srv->queue, job) != 0) {
        render_job_release(srv->queue, job);
        if (render_queue_recovering(srv->queue))
            return http_send_problem(req, PROBLEM_NOT_READY, NULL,
                                     "the GPU device was lost; the renderer is being re-created");
        return http_send_problem(req, PROBLEM_QUEUE_FULL, NULL, "%d renders are queued or running; retry later",
                                 srv->cfg.queue_length);
    }
    req->job = job;
    return MHD_YES;
}

/* ---- small routes ---- */

static enum MHD_Result handle_materials(struct request *req)
{
    json_t *list = json_array();
    for (int i = 0; lucent_material_preset_name(i); i++) {
        lucent_material m;
        if (lucent_material_preset(lucent_material_preset_name(i), &m) != LUCENT_OK)
            continue;
        json_array_append_new(list, json_pack("{s:s, s:[f,f,f], s:[f,f,f], s:f}", "name", lucent_material_preset_name(i),
                                              "sigma_a", m.sigma_a[0], m.sigma_a[1], m.sigma_a[2], "sigma_s_prime",
                                              m.sigma_s_prime[0], m.sigma_s_prime[1], m.sigma_s_prime[2], "eta", m.eta));
    }
    json_t *doc = json_pack("{s:o, s:s, s:s}", "materials", list, "units", "mm^-1",
                            "source", "Jensen et al. 2001, measured parameters");
    return send_json(req, MHD_HTTP_OK, doc, NULL, NULL);
}

static enum MHD_Result handle_healthz(struct request *req)
{
    return send_json(req, MHD_HTTP_OK, json_pack("{s:s}", "status", "alive"), NULL, NULL);
}

static enum MHD_Result handle_readyz(struct request *req)
{
    struct server *srv = req->srv;
    int phase = atomic_load(&srv->phase);
    int depth = render_queue_depth(srv->queue, NULL);
    const char *reason = phase == PHASE_STARTING                ? "starting"
                         : phase == PHASE_DRAINING              ? "draining"
                         : render_queue_recovering(srv->queue)  ? "recovering from a lost GPU device"
                         : depth >= srv->cfg.queue_length       ? "queue full"
                                                                : NULL;
    char secs[16];
    snprintf(secs, sizeof secs, "%d", srv->cfg.retry_after_s);
    if (reason)
        return send_json(req, MHD_HTTP_SERVICE_UNAVAILABLE,
                         json_pack("{s:b, s:s, s:i}", "ready", 0, "reason", reason, "queue_depth", depth),
                         MHD_HTTP_HEADER_RETRY_AFTER, secs);
    return send_json(req, MHD_HTTP_OK,
                     json_pack("{s:b, s:s, s:s, s:i, s:{s:s, s:s, s:s}}", "ready", 1, "backend", srv->backend,
                               "device", srv->device, "queue_depth",
                               depth, "import_sandbox", "user", import_jail_user(srv->jail), "namespaces",
                               import_jail_namespaces(srv->jail), "description", import_jail_describe(srv->jail)),
                     NULL, NULL);
}

static enum MHD_Result handle_metrics(struct request *req)
{
    struct server *srv = req->srv;
    struct metrics_gauges g = {.backend = srv->backend, .device = srv->device, .version = LUCENTD_VERSION};
    g.queue_depth = render_queue_depth(srv->queue, &g.in_flight);
    g.ready = atomic_load(&srv->phase) == PHASE_SERVING && !render_queue_recovering(srv->queue);
    g.cache_bytes = image_cache_bytes(srv->cache);
    g.store_bytes = mesh_store_bytes(srv->store);
    g.import_violations = mesh_import_violations();
    g.body_bytes = srv->body_bytes;
    g.slow_closed = connection_guard_closed(srv->guard);
    g.abandoned = render_queue_abandoned(srv->queue);
    size_t len = 0;
    char *text = metrics_text(srv->metrics, &g, &len);
    if (!text)
        return http_send_problem(req, LUCENT_E_NOMEM, NULL, "out of memory writing metrics");
    struct MHD_Response *resp = MHD_create_response_from_buffer(len, text, MHD_RESPMEM_MUST_FREE);
    if (!resp) {
        free(text);
        return MHD_NO;
    }
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, "text/plain; version=0.0.4; charset=utf-8");
    req->bytes_out = len;
    return http_send(req, MHD_HTTP_OK, resp);
}

static enum MHD_Result handle_openapi(struct request *req)
{
    return http_send_bytes(req, MHD_HTTP_OK, "application/json", lucentd_openapi_json, lucentd_openapi_json_len);
}

/* ---- /v1/meshes ---- */

static json_t *mesh_json(const char *id, const struct mesh_info *info)
{
    return json_pack("{s:s, s:I, s:I, s:{s:[f,f,f], s:[f,f,f]}, s:I, s:I}", "id", id, "triangles",
                     (json_int_t)info->triangles, "vertices", (json_int_t)info->vertices, "bounds", "min",
                     info->bounds_min[0], info->bounds_min[1], info->bounds_min[2], "max", info->bounds_max[0],
                     info->bounds_max[1], info->bounds_max[2], "bytes", (json_int_t)info->bytes, "created",
                     (json_int_t)info->created);
}

#define LIST_DEFAULT 100
#define LIST_MAX 1000

/* GET /v1/meshes?after=ID&limit=N: a page of the store in id order, and the link to the next. */
static enum MHD_Result handle_list(struct request *req)
{
    struct query_collect c = {.count = 0};
    MHD_get_connection_values(req->connection, MHD_GET_ARGUMENT_KIND, collect_query, &c);
    if (c.overflow)
        return http_send_problem(req, LUCENT_E_INVALID, "", "at most %d query fields", MAX_QUERY_FIELDS);
    const char *after = NULL;
    long limit = LIST_DEFAULT;
    for (int i = 0; i < c.count; i++) {
        const char *key = c.fields[i].key, *value = c.fields[i].value ? c.fields[i].value : "";
        char *end = NULL;
        if (strcmp(key, "after") == 0 && (mesh_id_valid(value) || !value[0]))
            after = value;
        else if (strcmp(key, "after") == 0)
            return http_send_problem(req, LUCENT_E_INVALID, "after", "after names a mesh id: 64 lowercase hex digits");
        else if (strcmp(key, "limit") == 0 && ((limit = strtol(value, &end, 10)) < 1 || limit > LIST_MAX || *end ||
                                               end == value))
            return http_send_problem(req, LUCENT_E_INVALID, "limit", "limit is a whole number from 1 to %d",
                                     LIST_MAX);
        else if (strcmp(key, "after") != 0 && strcmp(key, "limit") != 0)
            return http_send_problem(req, LUCENT_E_INVALID, query_key_field(key),
                                     "unknown query field: a listing takes after and limit");
    }
    struct mesh_listing *page;
    size_t count;
    int more;
    lucent_error err = {0};
    if (mesh_store_list(req->srv->store, after, (size_t)limit, &page, &count, &more, &err) != LUCENT_OK)
        return http_send_error(req, &err);
    json_t *items = json_array();
    for (size_t i = 0; i < count; i++)
        json_array_append_new(items, mesh_json(page[i].id, &page[i].info));
    char link[160] = "";
    if (more && count > 0)
        snprintf(link, sizeof link, "</v1/meshes?after=%s&limit=%ld>; rel=\"next\"", page[count - 1].id, limit);
    json_t *doc = json_pack("{s:o, s:s?}", "meshes", items, "next", link[0] ? page[count - 1].id : NULL);
    free(page);
    return send_json(req, MHD_HTTP_OK, doc, link[0] ? "Link" : NULL, link[0] ? link : NULL);
}

/* The second call, after the import thread resumed the connection. */
static enum MHD_Result finish_upload(struct request *req)
{
    struct upload_job *job = req->upload;
    if (job->done < 0)
        return http_send_problem(req, PROBLEM_NOT_READY, NULL, "the daemon is shutting down; the upload may be stored, "
                                                               "send it again to another instance");
    if (job->status != LUCENT_OK)
        return http_send_error(req, &job->err);
    char location[96];
    snprintf(location, sizeof location, "/v1/meshes/%s", job->id);
    /* 201 the first time; the same bytes again name the same mesh, answered 200. */
    return send_json(req, job->created ? MHD_HTTP_CREATED : MHD_HTTP_OK, mesh_json(job->id, &job->info),
                     MHD_HTTP_HEADER_LOCATION, location);
}

static enum MHD_Result handle_upload(struct request *req)
{
    struct server *srv = req->srv;
    if (req->upload)
        return finish_upload(req);
    if (atomic_load(&srv->phase) == PHASE_DRAINING)
        return http_send_problem(req, PROBLEM_NOT_READY, NULL, "the daemon is shutting down");
    if (req->body_len == 0)
        return http_send_problem(req, LUCENT_E_INVALID, "body", "send the mesh file (OBJ, PLY, STL, glTF or GLB) as the body, or "
                                                                  "a glTF and the files it names as multipart/form-data");
    unsigned char *bytes = req->body;
    size_t len = req->body_len;
    const char *format;
    lucent_error err = {0};
    const char *ct = http_header(req, MHD_HTTP_HEADER_CONTENT_TYPE);
    if (upload_form_is_form(ct)) {
        if (upload_form_read(req->connection, req->body, req->body_len, &bytes, &len, &format, &err) != LUCENT_OK)
            return http_send_error(req, &err);
        /* the files (no larger than the form) stand in for it under the request's body charge */
        free(req->body);
    } else {
        /* curl --data-binary labels any file a form; that says nothing about the format, so it is sniffed. */
        if (ct && strncasecmp(ct, "application/x-www-form-urlencoded", 33) == 0)
            ct = NULL;
        if (!(format = mesh_upload_format(ct, bytes, len, &err)))
            return http_send_error(req, &err);
    }
    req->body = NULL; /* the job owns the bytes now */
    req->body_len = 0;
    struct upload_job *job = upload_job_new(bytes, len, format);
    if (!job)
        return http_send_problem(req, LUCENT_E_NOMEM, NULL, "out of memory taking the upload");
    job->connection = req->connection;
    if (upload_queue_submit(srv->uploads, job) != 0) {
        upload_job_release(srv->uploads, job);
        return http_send_problem(req, PROBLEM_QUEUE_FULL, NULL, "other uploads are being imported; retry later");
    }
    req->upload = job;
    return MHD_YES;
}

static enum MHD_Result handle_meshes(struct request *req)
{
    return req->method_bit == M_POST ? handle_upload(req) : handle_list(req);
}

static enum MHD_Result handle_mesh(struct request *req)
{
    struct server *srv = req->srv;
    const char *id = req->path + strlen("/v1/meshes/");
    lucent_error err = {0};
    if (!mesh_id_valid(id))
        return http_send_problem(req, LUCENT_E_INVALID, "mesh.id", "mesh ids are 64 lowercase hex digits (sha256 of the upload)");
    if (req->method_bit == M_DELETE) {
        if (mesh_store_delete(srv->store, id, &err) != LUCENT_OK)
            return http_send_error(req, &err);
        return http_send(req, MHD_HTTP_NO_CONTENT, MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT));
    }
    struct mesh_info info;
    char path[1024];
    if (mesh_store_get(srv->store, id, &info, path, sizeof path, &err) != LUCENT_OK)
        return http_send_error(req, &err);
    return send_json(req, MHD_HTTP_OK, mesh_json(id, &info), NULL, NULL);
}

/* ---- static files: the web preview page (issue 5) ---- */

/* FNV-1a 64 of the bytes: they are fixed at build time, so the tag changes only with a new build. */
static void static_etag(const struct static_file *f, char out[17])
{
    uint64_t h = 0xcbf29ce484222325u;
    for (size_t i = 0; i < *f->len; i++)
        h = (h ^ f->bytes[i]) * 0x100000001b3u;
    snprintf(out, 17, "%016llx", (unsigned long long)h);
}

static enum MHD_Result handle_static(struct request *req)
{
    const struct static_file *f = static_file_find(req->path);
    char etag[17], quoted[20];
    static_etag(f, etag);
    snprintf(quoted, sizeof quoted, "\"%s\"", etag);
    int fresh = etag_matches(http_header(req, MHD_HTTP_HEADER_IF_NONE_MATCH), etag);
    struct MHD_Response *resp = fresh ? MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT)
                                      : MHD_create_response_from_buffer(*f->len, (void *)f->bytes, MHD_RESPMEM_PERSISTENT);
    if (!resp)
        return MHD_NO;
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, f->content_type);
    MHD_add_response_header(resp, MHD_HTTP_HEADER_ETAG, quoted);
    /* Revalidated on every load (a 304 while this build runs), so an upgraded daemon serves its own page. */
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CACHE_CONTROL, "no-cache");
    MHD_add_response_header(resp, "X-Content-Type-Options", "nosniff");
    if (strncmp(f->content_type, "text/html", 9) == 0)
        MHD_add_response_header(resp, "Content-Security-Policy",
                                "default-src 'self'; img-src 'self' blob:; connect-src 'self' blob:; object-src 'none'; "
                                "base-uri 'none'; "
                                "frame-ancestors 'none'");
    req->bytes_out = fresh ? 0 : *f->len;
    return http_send(req, fresh ? MHD_HTTP_NOT_MODIFIED : MHD_HTTP_OK, resp);
}
