/* mesh_upload.c - sends mesh files to the daemon. The file is read once into memory so the bytes
 * hashed are the bytes sent; the daemon's answer (its own sha256) is the id used afterwards. A glTF that
 * names files beside it (buffers, images) goes as multipart/form-data with them. */
#include "mesh_upload.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "file_io.h"
#include "server_problem.h"
#include "sha256_hex.h"

/* Sends rq (a POST to /v1/meshes) and takes the mesh metadata from the answer. */
static int post_upload(struct http_client *c, const char *path, const struct http_request *rq, json_t **answer,
                       lc_error *err)
{
    struct http_response rs;
    int rc = http_perform(c, rq, &rs, err);
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

static int post_bytes(struct http_client *c, const char *path, const char *data, size_t len, json_t **answer,
                      lc_error *err)
{
    struct http_request rq = {.method = "POST", .path = "/v1/meshes", .body = data, .body_len = len,
                              .content_type = "application/octet-stream", .accept = "application/json"};
    return post_upload(c, path, &rq, answer, err);
}

/* Whether a name the glTF gives stays in its folder or below: a relative path without empty, "." or ".."
 * segments or backslashes (what the daemon accepts as a file name). */
static int relative_below(const char *name)
{
    if (strchr(name, '\\'))
        return 0;
    for (const char *seg = name;; seg++) {
        size_t n = strcspn(seg, "/");
        if (n == 0 || (n == 1 && seg[0] == '.') || (n == 2 && seg[0] == '.' && seg[1] == '.'))
            return 0;
        seg += n;
        if (!*seg)
            return 1;
    }
}

/* The files a glTF document names (buffers and images other than data: URIs), percent-decoded, as a
 * JSON array of strings; an empty array for anything that is not such a document. */
static int gltf_named_files(struct http_client *c, const char *path, const char *data, size_t len, json_t **names,
                            lc_error *err)
{
    static const char *const lists[] = {"buffers", "images"};
    *names = json_array();
    size_t plen = strlen(path);
    json_t *doc = plen > 5 && strcasecmp(path + plen - 5, ".gltf") == 0 ? json_loadb(data, len, 0, NULL) : NULL;
    for (size_t l = 0; l < 2; l++) {
        size_t i;
        json_t *item;
        json_array_foreach(json_object_get(doc, lists[l]), i, item) {
            const char *uri = json_string_value(json_object_get(item, "uri"));
            if (!uri || strncmp(uri, "data:", 5) == 0)
                continue;
            char *name = curl_easy_unescape(c->curl, uri, 0, NULL);
            int outside = !name || !relative_below(name);
            if (outside) {
                lc_fail(err, LC_E_USAGE, "%s names \"%s\", which is not in its folder or below it; Lucent sends "
                        "only those files with a glTF", path, uri);
                curl_free(name);
                json_decref(doc);
                return err->code;
            }
            json_array_append_new(*names, json_string(name));
            curl_free(name);
        }
    }
    json_decref(doc);
    return LC_OK;
}

/* Adds the file at `file` to the form as `name`; a missing file is the user's error, said before sending. */
static int add_named_file(curl_mime *form, const char *gltf_path, const char *name, lc_error *err)
{
    const char *slash = strrchr(gltf_path, '/');
    int dir_len = slash ? (int)(slash - gltf_path + 1) : 0;
    char file[4096];
    struct stat st;
    snprintf(file, sizeof file, "%.*s%s", dir_len, gltf_path, name);
    if (stat(file, &st) != 0 || !S_ISREG(st.st_mode))
        return lc_fail(err, LC_E_FILE, "%s names \"%s\", but %s is not a file", gltf_path, name, file);
    curl_mimepart *part = curl_mime_addpart(form);
    if (!part || curl_mime_name(part, "file") != CURLE_OK || curl_mime_filedata(part, file) != CURLE_OK ||
        curl_mime_filename(part, name) != CURLE_OK || curl_mime_type(part, "application/octet-stream") != CURLE_OK)
        return lc_fail(err, LC_E_INTERNAL, "out of memory building the upload of %s", gltf_path);
    return LC_OK;
}

/* The glTF (its bytes in data) and the files it names, as one multipart/form-data upload. */
static int post_form(struct http_client *c, const char *path, const char *data, size_t len, json_t *names,
                     json_t **answer, lc_error *err)
{
    const char *slash = strrchr(path, '/');
    int rc = LC_OK;
    curl_mime *form = curl_mime_init(c->curl);
    curl_mimepart *part = form ? curl_mime_addpart(form) : NULL;
    if (!part || curl_mime_name(part, "mesh") != CURLE_OK || curl_mime_data(part, data, len) != CURLE_OK ||
        curl_mime_filename(part, slash ? slash + 1 : path) != CURLE_OK ||
        curl_mime_type(part, "model/gltf+json") != CURLE_OK)
        rc = lc_fail(err, LC_E_INTERNAL, "out of memory building the upload of %s", path);
    size_t i;
    json_t *name;
    json_array_foreach(names, i, name) {
        if (rc == LC_OK)
            rc = add_named_file(form, path, json_string_value(name), err);
    }
    struct http_request rq = {.method = "POST", .path = "/v1/meshes", .form = form, .accept = "application/json"};
    if (rc == LC_OK && c->verbose)
        fprintf(stderr, "lucent: sending %s with the %zu files it names as multipart/form-data\n", path,
                json_array_size(names));
    if (rc == LC_OK)
        rc = post_upload(c, path, &rq, answer, err);
    curl_mime_free(form);
    return rc;
}

/* Posts the file as it is, or with the files it names. */
static int post_file(struct http_client *c, const char *path, const char *data, size_t len, json_t **answer,
                     lc_error *err)
{
    json_t *names = NULL;
    int rc = gltf_named_files(c, path, data, len, &names, err);
    if (rc == LC_OK && json_array_size(names) > 0)
        rc = post_form(c, path, data, len, names, answer, err);
    else if (rc == LC_OK)
        rc = post_bytes(c, path, data, len, answer, err);
    json_decref(names);
    return rc;
}

int mesh_upload(struct http_client *c, const char *path, json_t **answer, lc_error *err)
{
    char *data = NULL;
    size_t len = 0;
    int rc = file_read_all(path, &data, &len, err);
    if (rc != LC_OK)
        return rc;
    rc = post_file(c, path, data, len, answer, err);
    free(data);
    return rc;
}

int mesh_ensure(struct http_client *c, const char *path, char id[65], lc_error *err)
{
    char *data = NULL;
    size_t len = 0;
    json_t *answer = NULL, *names = NULL;
    struct http_response rs = {0};
    int rc = file_read_all(path, &data, &len, err);
    if (rc != LC_OK)
        return rc;
    /* a glTF with files is stored under its files' bundle (server/mesh_bundle.h), which the daemon
     * computes: it is sent, and answered 200 without a second import when stored */
    if ((rc = gltf_named_files(c, path, data, len, &names, err)) != LC_OK)
        goto done;
    if (json_array_size(names) > 0) {
        rc = post_form(c, path, data, len, names, &answer, err);
        goto take_id;
    }
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
take_id:
    if (rc == LC_OK)
        snprintf(id, 65, "%s", json_string_value(json_object_get(answer, "id")));
done:
    json_decref(names);
    json_decref(answer);
    http_response_free(&rs);
    free(data);
    return rc;
}
