/* mesh_upload.c - sends mesh files to the daemon. The file is read once into memory so the bytes
 * hashed are the bytes sent; the daemon's answer (its own sha256) is the id used afterwards. */
#include "mesh_upload.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "file_io.h"
#include "server_problem.h"
#include "sha256_hex.h"

static int post_bytes(struct http_client *c, const char *path, const char *data, size_t len, json_t **answer,
                      lc_error *err)
{
    struct http_request rq = {.method = "POST", .path = "/v1/meshes", .body = data, .body_len = len,
                              .content_type = "application/octet-stream", .accept = "application/json"};
    struct http_response rs;
    int rc = http_perform(c, &rq, &rs, err);
    if (rc != LC_OK)
        goto done;
    if (rs.status != 200 && rs.status != 201) {
        char why[sizeof err->message];
        server_problem(&rs, err);
        snprintf(why, sizeof why, "%s", err->message);
        rc = lc_fail(err, LC_E_SERVER, "uploading %s: %s", path, why);
        goto done;
    }
    json_t *doc = json_loadb(rs.body ? rs.body : "", rs.body_len, 0, NULL);
    if (!json_is_string(json_object_get(doc, "id"))) {
        json_decref(doc);
        rc = lc_fail(err, LC_E_SERVER, "uploading %s: the server's answer has no mesh id", path);
        goto done;
    }
    if (c->verbose)
        fprintf(stderr, "lucent: %s %s as %s\n", path, rs.status == 201 ? "uploaded" : "was already stored",
                json_string_value(json_object_get(doc, "id")));
    *answer = doc;
done:
    http_response_free(&rs);
    return rc;
}

int mesh_upload(struct http_client *c, const char *path, json_t **answer, lc_error *err)
{
    char *data = NULL;
    size_t len = 0;
    int rc = file_read_all(path, &data, &len, err);
    if (rc != LC_OK)
        return rc;
    rc = post_bytes(c, path, data, len, answer, err);
    free(data);
    return rc;
}

int mesh_ensure(struct http_client *c, const char *path, char id[65], lc_error *err)
{
    char *data = NULL;
    size_t len = 0;
    json_t *answer = NULL;
    struct http_response rs = {0};
    int rc = file_read_all(path, &data, &len, err);
    if (rc != LC_OK)
        return rc;
    rc = sha256_hex(data, len, id, err);
    if (rc != LC_OK)
        goto done;
    char route[96];
    snprintf(route, sizeof route, "/v1/meshes/%s", id);
    struct http_request rq = {.method = "GET", .path = route, .accept = "application/json"};
    rc = http_perform(c, &rq, &rs, err);
    if (rc != LC_OK)
        goto done;
    if (rs.status == 200) {
        if (c->verbose)
            fprintf(stderr, "lucent: %s is stored as %s; not uploading it\n", path, id);
        goto done;
    }
    if (rs.status != 404) {
        rc = server_problem(&rs, err);
        goto done;
    }
    rc = post_bytes(c, path, data, len, &answer, err);
    if (rc == LC_OK)
        snprintf(id, 65, "%s", json_string_value(json_object_get(answer, "id")));
done:
    json_decref(answer);
    http_response_free(&rs);
    free(data);
    return rc;
}
