/* mesh_import_sandbox.h - imports an uploaded mesh in a separate, resource-limited lucent-import
 * process, so an assimp crash, hang or memory blow-up costs one upload, not the daemon. */
#ifndef LUCENT_MESH_IMPORT_SANDBOX_H
#define LUCENT_MESH_IMPORT_SANDBOX_H

#include "lucent.h"

#include <stddef.h>
#include <stdint.h>

/* Every field must be positive. The importer's output file is limited to the compact size of
 * max_triangles triangles; it has 16 descriptors, no core dumps and no child processes. */
struct import_limits {
    size_t address_space_bytes; /* RLIMIT_AS of the importer */
    int cpu_seconds;            /* RLIMIT_CPU */
    int wall_seconds;           /* killed after this long, whatever it is doing */
    uint32_t max_triangles;     /* larger meshes are refused with LUCENT_E_LIMIT */
};

/* What the importer reports about a mesh; bounds in the upload's own coordinates. */
struct mesh_info {
    uint32_t triangles, vertices;
    double bounds_min[3], bounds_max[3];
    uint64_t bytes;  /* size of the upload */
    int64_t created; /* Unix time the store kept it; 0 from mesh_import_isolated */
};

struct import_jail;

/* Runs lucent-import in the jail (import_jail.h) as `lucent-import --format EXT --max-triangles N`
 * (EXT: obj, ply, stl, gltf, glb, or bundle for mesh_bundle.h's encoding of several files),
 * the bytes on its standard input, mesh_fd (a regular file, empty, open for reading and writing) as
 * its fd 3, under the limits. Its answer is not trusted: the daemon reads the mesh back from mesh_fd
 * and it must be sound and match the answer; info is then filled. A crash, a timeout, exceeding the
 * CPU limit, a sandbox violation (counted, and logged) or unsound output fail with LUCENT_E_MESH; the
 * importer's own refusals keep their status and message (out of memory becomes LUCENT_E_LIMIT); all
 * of these name the field "mesh", the upload as a whole. An ext other than the six is
 * LUCENT_E_INVALID ("Content-Type"); failing to run the importer is LUCENT_E_INTERNAL. */
lucent_status mesh_import_isolated(const struct import_jail *jail, const struct import_limits *lim,
                                   const void *bytes, size_t len, const char *ext, int mesh_fd,
                                   struct mesh_info *info, lucent_error *err);

/* Imports a built-in triangle through the whole sandbox, its output in memory: run at start, so that
 * a sandbox this machine cannot set up stops the daemon then, with the reason, not every upload. */
lucent_status mesh_import_self_test(const struct import_jail *jail, const struct import_limits *lim,
                                    lucent_error *err);

/* Importers the sandbox stopped (killed for a forbidden system call) since the daemon started. */
uint64_t mesh_import_violations(void);

/* obj/ply/stl/gltf/glb of an upload: a mesh Content-Type (parameters ignored) names it unless the
 * first bytes are recognizably another format (then NULL: they contradict it); any other type,
 * generic or unknown, or none, lets the first bytes decide. NULL when neither names a format. */
const char *mesh_format_sniff(const char *content_type, const void *bytes, size_t len);
/* The format a mesh Content-Type names (NULL: not a mesh type), and the format the first bytes show
 * (NULL: none recognized); mesh_format_sniff combines them. */
const char *mesh_format_of_type(const char *content_type);
const char *mesh_format_of_bytes(const void *bytes, size_t len);
/* mesh_format_sniff, or NULL with the reason in err (field "Content-Type"). */
const char *mesh_upload_format(const char *content_type, const void *bytes, size_t len, lucent_error *err);

#endif
