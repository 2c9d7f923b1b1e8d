/* mesh_store.h - the daemon's content-addressed store of uploaded meshes: <dir>/<id>.lmesh (compact
 * form) and <dir>/<id>.json (metadata, MAC), id = sha256 of the upload; durable, budgeted, thread-safe. */
#ifndef LUCENT_MESH_STORE_H
#define LUCENT_MESH_STORE_H

#include "lucent.h"
#include "mesh_import_sandbox.h"

#include <stddef.h>
#include <stdint.h>

struct mesh_store;

/* Opens (creating the directory, one level, if needed) and indexes the store. Left-overs of an
 * interrupted write (temporary files, a mesh without metadata, metadata without a mesh or that does
 * not parse) are removed. The MAC key is key_file (NULL or "": <dir>/store.key), created if missing
 * (store_integrity.h). Uploads are imported in the jail (which must outlive the store) under lim. */
lucent_status mesh_store_open(const char *dir, uint64_t byte_budget, const char *key_file,
                              const struct import_jail *jail, const struct import_limits *lim,
                              struct mesh_store **out, lucent_error *err);
void mesh_store_close(struct mesh_store *s);

/* Imports the upload (format: obj, ply, stl, gltf, glb as mesh_upload_format names it, or bundle,
 * mesh_bundle.h) in isolation and stores it under id_out. Idempotent: when the id exists, nothing is
 * imported or written, *created = 0 and info is the stored one. When it does not fit the byte budget,
 * the least recently used meshes (by put or get; after a restart, by creation) are evicted until it
 * does. Unknown formats fail with LUCENT_E_INVALID (field "Content-Type"); files without usable
 * triangles, crashes and timeouts with LUCENT_E_MESH; a mesh larger than the whole budget with
 * LUCENT_E_LIMIT. */
lucent_status mesh_store_put(struct mesh_store *s, const void *bytes, size_t len, const char *format,
                             char id_out[65], struct mesh_info *info, int *created, lucent_error *err);

/* Fills info and the path of the compact file, once the file is checked against its MAC (again only
 * when it is no longer the version last checked). An id that is malformed or absent fails with
 * LUCENT_E_INVALID, field "mesh.id" (message "no mesh with id ..." when absent); a mesh that fails
 * the check is removed from the store and fails with LUCENT_E_IO, field "mesh.id". info may be NULL. */
lucent_status mesh_store_get(struct mesh_store *s, const char *id, struct mesh_info *info, char *path, size_t cap,
                             lucent_error *err);

/* Removes a mesh; the same errors as mesh_store_get. */
lucent_status mesh_store_delete(struct mesh_store *s, const char *id, lucent_error *err);

/* One entry of a listing. */
struct mesh_listing {
    char id[65];
    struct mesh_info info;
};

/* A page of the stored meshes in id order, read from disk (so uploads through every replica sharing the
 * store are included): up to `limit` entries whose ids sort after `after` (NULL or "": from the first);
 * *more says whether others follow. Entries whose metadata cannot be read are left out. The caller
 * frees *out. */
lucent_status mesh_store_list(struct mesh_store *s, const char *after, size_t limit, struct mesh_listing **out,
                              size_t *count, int *more, lucent_error *err);

/* Bytes the stored files take (what the budget counts). */
uint64_t mesh_store_bytes(struct mesh_store *s);

/* Whether id is exactly 64 lowercase hexadecimal digits. */
int mesh_id_valid(const char *id);

#endif
