/* mesh_bundle.h - several files uploaded as one mesh (a glTF and the buffers it names, an OBJ and its
 * material library) as one canonical byte string: what the store hashes for the id and the importer reads. */
#ifndef LUCENT_MESH_BUNDLE_H
#define LUCENT_MESH_BUNDLE_H

#include "lucent.h"

#include <stddef.h>

#define MESH_BUNDLE_MAX_FILES 64
#define MESH_BUNDLE_NAME_MAX 255

/* Sorts files by name, then checks them: every name a relative path of at most MESH_BUNDLE_NAME_MAX
 * bytes of UTF-8 with no control character, backslash, empty, "." or ".." segment; no name twice;
 * exactly one mesh file (.gltf, .glb, .obj, .ply or .stl, any case), whose index and format go to
 * *main and *ext. Failures are LUCENT_E_INVALID naming the field "body". */
lucent_status mesh_bundle_check(lucent_mesh_file *files, size_t count, size_t *main, const char **ext,
                                lucent_error *err);

/* The encoding of checked files: a magic line, the count, then each name and its bytes, in name order;
 * the same files always give the same bytes. *out is malloc'd, the caller's. */
lucent_status mesh_bundle_encode(const lucent_mesh_file *files, size_t count, unsigned char **out, size_t *len,
                                 lucent_error *err);

/* The files of an encoding, as views into bytes (which must outlive them); anything but a well-formed
 * encoding in name order is LUCENT_E_INVALID. Check them with mesh_bundle_check before use. */
lucent_status mesh_bundle_decode(const unsigned char *bytes, size_t len, lucent_mesh_file files[MESH_BUNDLE_MAX_FILES],
                                 size_t *count, lucent_error *err);

/* Decodes, checks and imports an encoding: what lucent-import does with --format bundle. */
lucent_status mesh_bundle_import(const unsigned char *bytes, size_t len, lucent_mesh **out, lucent_error *err);

#endif
