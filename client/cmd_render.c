/* cmd_render.c - `lucent render`: builds the scene from --scene and flags, uploads a local mesh once,
 * POSTs /v1/render and writes the image atomically (nothing is left behind on failure). */
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "commands.h"
#include "file_io.h"
#include "mesh_upload.h"
#include "scene_build.h"
#include "server_problem.h"

enum { R_SCENE = 2000, R_OUTPUT };

static const struct cli_option render_options[] = {
    {"scene", 0, "FILE.json", "start from this scene document; flags override its fields", R_SCENE},
    {"output", 'o', "OUT", "write the image here (.png or .exr; - for standard output); required", R_OUTPUT},
    {NULL, 0, NULL, NULL, 0},
};

static void render_help(void)
{
    printf("Usage: lucent render [--scene FILE.json] [scene flags] -o OUT.png|OUT.exr\n"
           "\n"
           "Renders a scene on the server. Flags set scene fields (README, \"Scene document\"); with --scene\n"
           "they override that document's fields. A local mesh file is uploaded once: the client asks for its\n"
           "sha256 first and sends it only when the server does not have it. Lights: each --light-dir or\n"
           "--light-pos adds a light (and the first replaces the --scene file's lights).\n"
           "\nInput and output:\n");
    cli_print_options(render_options);
    printf("\nScene flags:\n");
    cli_print_options(scene_options);
    print_session_options();
    printf("\nExample:\n  lucent render --mesh protrusion --preset skin1 --light-dir -1,0,0 --light-intensity 4 \\\n"
           "      --camera-pos 0,3.5,3 --camera-target 0,0,0.25 --size 256x256 -o demo.png\n");
}

/* The format: --format (or the scene's), else the output's extension, else PNG. */
static int choose_format(json_t *scene, const char *out, int format_flag, lc_error *err)
{
    const char *dot = strrchr(out, '.');
    const char *from_ext = dot && strcasecmp(dot, ".png") == 0 ? "png" : dot && strcasecmp(dot, ".exr") == 0 ? "exr" : NULL;
    const json_t *given = json_object_get(scene, "format");
    if (given && !json_is_string(given))
        return lc_fail(err, LC_E_USAGE, "the scene's format must be \"png\" or \"exr\"");
    if ((format_flag || !from_ext) && given)
        return LC_OK;
    return json_object_set_new(scene, "format", json_string(from_ext ? from_ext : "png")) == 0
               ? LC_OK
               : lc_fail(err, LC_E_INTERNAL, "out of memory");
}

/* Replaces mesh.file (from --mesh FILE or the --scene document) by the id of the uploaded bytes. */
static int resolve_mesh(struct http_client *c, json_t *scene, lc_error *err)
{
    json_t *mesh = json_object_get(scene, "mesh");
    const json_t *file = json_object_get(mesh, "file");
    if (!file)
        return LC_OK;
    if (!json_is_string(file))
        return lc_fail(err, LC_E_USAGE, "the scene's mesh.file must be a path");
    char id[65];
    const char *path = json_string_value(file);
    int rc = mesh_ensure(c, path, id, err);
    if (rc == LC_E_FILE && !strchr(path, '/') && !strchr(path, '.')) {
        /* Most likely a misspelt built-in name rather than a file. */
        char why[sizeof err->message];
        snprintf(why, sizeof why, "%s", err->message);
        return lc_fail(err, rc, "mesh %s: not a built-in mesh (sphere, torus, protrusion, bunny) and %s", path, why);
    }
    if (rc != LC_OK)
        return rc;
    json_object_del(mesh, "file");
    return json_object_set_new(mesh, "id", json_string(id)) == 0 ? LC_OK : lc_fail(err, LC_E_INTERNAL, "out of memory");
}

static int post_render(struct http_client *c, json_t *scene, const char *out_path, lc_error *err)
{
    struct output_file out = {0};
    struct http_response rs = {0};
    char *body = json_dumps(scene, JSON_COMPACT);
    if (!body)
        return lc_fail(err, LC_E_INTERNAL, "out of memory");
    const char *format = json_string_value(json_object_get(scene, "format"));
    const char *type = format && strcmp(format, "exr") == 0 ? "image/x-exr" : "image/png";
    if (c->verbose)
        fprintf(stderr, "lucent: scene: %s\n", body);
    int rc = output_open(&out, out_path, err);
    if (rc != LC_OK)
        goto done;
    struct http_request rq = {.method = "POST", .path = "/v1/render", .body = body, .body_len = strlen(body),
                              .content_type = "application/json", .accept = type, .sink = out.fp};
    rc = http_perform(c, &rq, &rs, err);
    if (rc != LC_OK)
        goto done;
    if (rs.status != 200) {
        rc = server_problem(&rs, err);
        goto done;
    }
    if (!rs.content_type || strcasecmp(rs.content_type, type) != 0) {
        rc = lc_fail(err, LC_E_SERVER, "asked for %s, the server sent %s", type,
                     rs.content_type ? rs.content_type : "no Content-Type");
        goto done;
    }
    rc = output_commit(&out, err);
done:
    output_abort(&out);
    http_response_free(&rs);
    free(body);
    return rc;
}

int cmd_render(struct session *s, int argc, char **argv, lc_error *err)
{
    struct cli_parser p;
    struct cli_item it;
    const char *scene_path = NULL, *out_path = NULL;
    json_t *scene = NULL;
    struct http_client client = {0};
    struct scene_state st = {0};
    int format_flag = 0, n, rc = LC_OK;
    /* Scene flags apply after --scene is loaded, wherever it appears; keep them in order until then. */
    struct cli_item *flags = calloc((size_t)argc + 1, sizeof *flags);
    size_t nflags = 0;
    if (!flags)
        return lc_fail(err, LC_E_INTERNAL, "out of memory");
    cli_parser_init(&p, argc, argv, "render", render_options, scene_options, session_options);
    while ((n = cli_next(&p, &it, err)) == 1) {
        if (session_take(s, &it))
            continue;
        if (!it.opt) {
            rc = lc_fail(err, LC_E_USAGE, "render: unexpected argument '%s' (see lucent render --help)", it.value);
            goto done;
        }
        if (it.opt->id == R_SCENE)
            scene_path = it.value;
        else if (it.opt->id == R_OUTPUT)
            out_path = it.value;
        else
            flags[nflags++] = it;
    }
    if (n < 0) {
        rc = err->code;
        goto done;
    }
    if (s->help) {
        render_help();
        goto done;
    }
    if (!out_path) {
        rc = lc_fail(err, LC_E_USAGE, "render: -o OUT is required (OUT.png, OUT.exr, or - for standard output)");
        goto done;
    }
    rc = scene_path ? scene_load(scene_path, &scene, err) : LC_OK;
    if (rc != LC_OK)
        goto done;
    if (!scene && !(scene = json_object())) {
        rc = lc_fail(err, LC_E_INTERNAL, "out of memory");
        goto done;
    }
    for (size_t i = 0; i < nflags; i++) {
        format_flag |= strcmp(flags[i].opt->name, "format") == 0;
        rc = scene_apply(scene, &st, flags[i].opt, flags[i].value, err);
        if (rc != LC_OK)
            goto done;
    }
    rc = choose_format(scene, out_path, format_flag, err);
    if (rc != LC_OK)
        goto done;
    rc = session_connect(s, &client, err);
    if (rc != LC_OK)
        goto done;
    rc = resolve_mesh(&client, scene, err);
    if (rc != LC_OK)
        goto done;
    rc = post_render(&client, scene, out_path, err);
done:
    free(flags);
    json_decref(scene);
    http_client_cleanup(&client);
    return rc;
}
