/* mesh_upload.h - local mesh files on the daemon: upload, and the upload-once rule renders use (ask
 * for the file's sha256 first, send the bytes only when the daemon does not have them). */
#ifndef LUCENT_MESH_UPLOAD_H
#define LUCENT_MESH_UPLOAD_H

#include <jansson.h>

#include "cli_error.h"
#include "http_client.h"

/* POSTs the file (a .gltf naming files beside it: with them, as multipart/form-data); *answer is the
 * daemon's mesh metadata (owned by the caller). */
int mesh_upload(struct http_client *c, const char *path, json_t **answer, lc_error *err);
/* The id of the file's mesh on the daemon, uploading it only when the daemon answers 404 for it (a glTF
 * with files is always sent: its id is the daemon's hash of them all). */
int mesh_ensure(struct http_client *c, const char *path, char id[65], lc_error *err);

#endif
