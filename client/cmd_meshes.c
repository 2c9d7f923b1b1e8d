/* cmd_meshes.c - `lucent meshes upload FILE | show ID | delete ID | list`: the daemon's mesh store. show
 * and delete also take the mesh's file, whose sha256 is its id. */
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "file_io.h"
#include "mesh_upload.h"
#include "server_problem.h"
#include "sha256_hex.h"

static void meshes_help(void)
{
    printf("Usage: lucent meshes upload FILE\n"
           "       lucent meshes show ID|FILE\n"
           "       lucent meshes delete ID|FILE\n"
           "       lucent meshes list\n"
           "\n"
           "upload  sends an OBJ, PLY, STL, glTF (embedded buffers) or GLB file; prints the server's answer\n"
           "        (id = the sha256 of the bytes, triangles, vertices, bounds, bytes) as JSON\n"
           "show    prints a stored mesh's metadata as JSON (exit 1 with 404 when it is not stored)\n"
           "delete  removes a stored mesh\n"
           "list    prints every stored mesh's metadata as one JSON array, in id order\n"
           "ID is 64 lowercase hex digits; a FILE stands for the id of its bytes.\n");
    print_session_options();
}

static int is_id(const char *s)
{
    size_t n = strspn(s, "0123456789abcdef");
    return n == 64 && s[n] == 0;
}

/* The id named by the argument: itself, or the sha256 of the file it names. */
static int mesh_id_of(const char *arg, char id[65], lc_error *err)
{
    if (is_id(arg)) {
        memcpy(id, arg, 65);
        return LC_OK;
    }
    char *data = NULL;
    size_t len = 0;
    int rc = file_read_all(arg, &data, &len, err);
    if (rc != LC_OK)
        return lc_fail(err, rc, "%s is neither a mesh id (64 lowercase hex digits) nor a readable file", arg);
    rc = sha256_hex(data, len, id, err);
    free(data);
    return rc;
}

static int print_json(const json_t *doc, lc_error *err)
{
    char *text = json_dumps(doc, JSON_INDENT(2) | JSON_PRESERVE_ORDER);
    if (!text)
        return lc_fail(err, LC_E_INTERNAL, "out of memory");
    puts(text);
    free(text);
    return LC_OK;
}

static int show_or_delete(struct http_client *c, const char *method, const char *arg, lc_error *err)
{
    char id[65], route[96];
    struct http_response rs = {0};
    int rc = mesh_id_of(arg, id, err);
    if (rc != LC_OK)
        return rc;
    snprintf(route, sizeof route, "/v1/meshes/%s", id);
    struct http_request rq = {.method = method, .path = route, .accept = "application/json"};
    rc = http_perform(c, &rq, &rs, err);
    if (rc != LC_OK)
        goto done;
    if (rs.status != (strcmp(method, "GET") == 0 ? 200 : 204)) {
        rc = server_problem(&rs, err);
        goto done;
    }
    if (strcmp(method, "GET") == 0) {
        json_t *doc = json_loadb(rs.body ? rs.body : "", rs.body_len, 0, NULL);
        rc = doc ? print_json(doc, err) : lc_fail(err, LC_E_SERVER, "the server's mesh metadata is not JSON");
        json_decref(doc);
    }
done:
    http_response_free(&rs);
    return rc;
}

/* Every page of GET /v1/meshes, following "next", printed as one array. */
static int list_all(struct http_client *c, lc_error *err)
{
    json_t *all = json_array();
    char route[160] = "/v1/meshes?limit=1000";
    int rc = LC_OK;
    for (int more = 1; more && rc == LC_OK;) {
        struct http_response rs = {0};
        struct http_request rq = {.method = "GET", .path = route, .accept = "application/json"};
        rc = http_perform(c, &rq, &rs, err);
        if (rc == LC_OK && rs.status != 200)
            rc = server_problem(&rs, err);
        json_t *doc = rc == LC_OK ? json_loadb(rs.body ? rs.body : "", rs.body_len, 0, NULL) : NULL;
        json_t *page = json_object_get(doc, "meshes");
        const char *next = json_string_value(json_object_get(doc, "next"));
        if (rc == LC_OK && !json_is_array(page))
            rc = lc_fail(err, LC_E_SERVER, "the server's mesh listing is not the JSON it should be");
        if (rc == LC_OK)
            json_array_extend(all, page);
        more = rc == LC_OK && next && is_id(next);
        if (more)
            snprintf(route, sizeof route, "/v1/meshes?limit=1000&after=%s", next);
        json_decref(doc);
        http_response_free(&rs);
    }
    if (rc == LC_OK)
        rc = print_json(all, err);
    json_decref(all);
    return rc;
}

int cmd_meshes(struct session *s, int argc, char **argv, lc_error *err)
{
    struct cli_parser p;
    struct cli_item it;
    const char *args[3] = {NULL, NULL, NULL};
    int nargs = 0, n, rc;
    struct http_client client = {0};
    cli_parser_init(&p, argc, argv, "meshes", session_options, NULL, NULL);
    while ((n = cli_next(&p, &it, err)) == 1) {
        if (session_take(s, &it))
            continue;
        if (nargs == 2)
            return lc_fail(err, LC_E_USAGE, "meshes: unexpected argument '%s' (see lucent meshes --help)",
                           it.value);
        args[nargs++] = it.value;
    }
    if (n < 0)
        return err->code;
    if (s->help) {
        meshes_help();
        return LC_OK;
    }
    int upload = args[0] && strcmp(args[0], "upload") == 0;
    int show = args[0] && strcmp(args[0], "show") == 0;
    int del = args[0] && strcmp(args[0], "delete") == 0;
    int list = args[0] && strcmp(args[0], "list") == 0;
    if (!upload && !show && !del && !list)
        return lc_fail(err, LC_E_USAGE, "meshes: expected upload, show, delete or list%s%s (see lucent meshes --help)",
                       args[0] ? ", got " : "", args[0] ? args[0] : "");
    if (list && args[1])
        return lc_fail(err, LC_E_USAGE, "meshes list: unexpected argument '%s'", args[1]);
    if (!list && !args[1])
        return lc_fail(err, LC_E_USAGE, "meshes %s: expected %s", args[0], upload ? "FILE" : "ID or FILE");
    rc = session_connect(s, &client, err);
    if (rc != LC_OK)
        return rc;
    if (list) {
        rc = list_all(&client, err);
    } else if (upload) {
        json_t *answer = NULL;
        rc = mesh_upload(&client, args[1], &answer, err);
        if (rc == LC_OK)
            rc = print_json(answer, err);
        json_decref(answer);
    } else {
        rc = show_or_delete(&client, show ? "GET" : "DELETE", args[1], err);
    }
    http_client_cleanup(&client);
    return rc;
}
