/* cmd_server.c - `lucent health` and `lucent materials`: what the daemon says about itself. */
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "server_problem.h"

enum { M_JSON = 3000 };

static const struct cli_option materials_options[] = {
    {"json", 0, NULL, "print the server's JSON instead of a table", M_JSON},
    {NULL, 0, NULL, NULL, 0},
};

/* Parses a subcommand that takes no arguments; *json (when asked for) is set by --json. */
static int parse_plain(struct session *s, int argc, char **argv, const char *command,
                       const struct cli_option *extra, int *json, lc_error *err)
{
    struct cli_parser p;
    struct cli_item it;
    int n;
    cli_parser_init(&p, argc, argv, command, session_options, extra, NULL);
    while ((n = cli_next(&p, &it, err)) == 1) {
        if (session_take(s, &it))
            continue;
        if (!it.opt)
            return lc_fail(err, LC_E_USAGE, "%s: unexpected argument '%s' (see lucent %s --help)", command, it.value,
                           command);
        if (it.opt->id == M_JSON && json)
            *json = 1;
    }
    return n < 0 ? err->code : LC_OK;
}

static int get_json(struct http_client *c, const char *route, json_t **doc, long *status, lc_error *err)
{
    struct http_response rs;
    struct http_request rq = {.method = "GET", .path = route, .accept = "application/json"};
    int rc = http_perform(c, &rq, &rs, err);
    if (rc != LC_OK)
        goto done;
    *status = rs.status;
    /* /readyz answers 503 with a JSON reason, not a problem: the caller reads it. */
    *doc = json_loadb(rs.body ? rs.body : "", rs.body_len, 0, NULL);
    if (!*doc)
        rc = rs.status / 100 == 2 ? lc_fail(err, LC_E_SERVER, "GET %s: the answer is not JSON", route)
                                  : server_problem(&rs, err);
    else if (rs.status / 100 != 2 && !json_object_get(*doc, "ready")) {
        rc = server_problem(&rs, err);
        json_decref(*doc);
        *doc = NULL;
    }
done:
    http_response_free(&rs);
    return rc;
}

int cmd_health(struct session *s, int argc, char **argv, lc_error *err)
{
    struct http_client c = {0};
    json_t *alive = NULL, *ready = NULL;
    long status = 0;
    int rc = parse_plain(s, argc, argv, "health", NULL, NULL, err);
    if (rc != LC_OK)
        return rc;
    if (s->help) {
        printf("Usage: lucent health\n\n"
               "Asks the server whether it is alive (/healthz) and ready to render (/readyz). Prints\n"
               "\"alive, ready\" with the device and queue depth and exits 0; exits 1 with the reason\n"
               "(starting, draining, queue full) when it is not ready.\n");
        print_session_options();
        return LC_OK;
    }
    rc = session_connect(s, &c, err);
    if (rc == LC_OK)
        rc = get_json(&c, "/healthz", &alive, &status, err);
    if (rc == LC_OK)
        rc = get_json(&c, "/readyz", &ready, &status, err);
    if (rc != LC_OK)
        goto done;
    if (!json_is_true(json_object_get(ready, "ready"))) {
        const char *reason = json_string_value(json_object_get(ready, "reason"));
        rc = lc_fail(err, LC_E_SERVER, "alive, not ready: %s (%ld)", reason ? reason : "no reason given", status);
        goto done;
    }
    const char *backend = json_string_value(json_object_get(ready, "backend"));
    const char *device = json_string_value(json_object_get(ready, "device"));
    printf("alive, ready: %s device \"%s\", queue depth %lld\n", backend ? backend : "?", device ? device : "?",
           (long long)json_integer_value(json_object_get(ready, "queue_depth")));
done:
    json_decref(alive);
    json_decref(ready);
    http_client_cleanup(&c);
    return rc;
}

static void print_rgb(const json_t *a)
{
    printf(" %9.4g %9.4g %9.4g", json_number_value(json_array_get(a, 0)), json_number_value(json_array_get(a, 1)),
           json_number_value(json_array_get(a, 2)));
}

int cmd_materials(struct session *s, int argc, char **argv, lc_error *err)
{
    struct http_client c = {0};
    json_t *doc = NULL;
    long status = 0;
    int json = 0;
    int rc = parse_plain(s, argc, argv, "materials", materials_options, &json, err);
    if (rc != LC_OK)
        return rc;
    if (s->help) {
        printf("Usage: lucent materials [--json]\n\n"
               "Lists the server's material presets (for --preset) with their coefficients in mm^-1.\n\nOptions:\n");
        cli_print_options(materials_options);
        print_session_options();
        return LC_OK;
    }
    rc = session_connect(s, &c, err);
    if (rc == LC_OK)
        rc = get_json(&c, "/v1/materials", &doc, &status, err);
    if (rc != LC_OK)
        goto done;
    const json_t *list = json_object_get(doc, "materials");
    if (!json_is_array(list)) {
        rc = lc_fail(err, LC_E_SERVER, "GET /v1/materials: the answer has no materials list");
        goto done;
    }
    if (json) {
        char *text = json_dumps(doc, JSON_INDENT(2) | JSON_PRESERVE_ORDER);
        if (!text) {
            rc = lc_fail(err, LC_E_INTERNAL, "out of memory");
            goto done;
        }
        puts(text);
        free(text);
        goto done;
    }
    const char *units = json_string_value(json_object_get(doc, "units"));
    printf("%-12s %29s %29s %5s\n", "preset", "sigma_a (R G B)", "sigma_s' (R G B)", "eta");
    size_t i;
    const json_t *m;
    json_array_foreach(list, i, m) {
        printf("%-12s", json_string_value(json_object_get(m, "name")));
        print_rgb(json_object_get(m, "sigma_a"));
        print_rgb(json_object_get(m, "sigma_s_prime"));
        printf(" %5.2f\n", json_number_value(json_object_get(m, "eta")));
    }
    printf("(coefficients in %s)\n", units ? units : "mm^-1");
done:
    json_decref(doc);
    http_client_cleanup(&c);
    return rc;
}
