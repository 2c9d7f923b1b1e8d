/* mesh_compact.h - the compact binary form of a lucent_mesh: what the mesh store keeps, so a render
 * loads a finished, validated mesh instead of re-parsing the original upload. */
#ifndef LUCENT_MESH_COMPACT_H
#define LUCENT_MESH_COMPACT_H

#include "mesh.h"

#include <stdio.h>

/* Layout (little-endian, no padding):
 *    0  magic "\x89LMESH\r\n" (as PNG's: a text-mode transfer or a 7-bit channel breaks it)
 *    8  u32 version = 1
 *   12  u32 flags: bit 0 convex, bit 1 closed
 *   16  u32 vertex_count, u32 triangle_count
 *   24  f64 center[3], f64 radius
 *   56  f32 positions[3 * vertex_count], f32 normals[3 * vertex_count], u32 indices[3 * triangle_count]
 *  end  u64 mesh_compact_checksum() of every byte before it */
#define MESH_COMPACT_MAGIC "\x89LMESH\r\n"
#define MESH_COMPACT_MAGIC_LEN 8
#define MESH_COMPACT_VERSION 1u
#define MESH_COMPACT_EXTENSION "lmesh"

/* Size in bytes of the compact form of a mesh with these counts. */
uint64_t mesh_compact_size(uint32_t vertex_count, uint32_t triangle_count);

/* Whether data starts with the magic (then mesh_compact_read is the only reader that applies). */
int mesh_compact_detect(const void *data, size_t len);

/* Writes a finished mesh (normals present); fails with LUCENT_E_IO when the stream does. */
lucent_status mesh_compact_write(const struct lucent_mesh *m, FILE *f, lucent_error *err);

/* Reads and validates the compact form: magic, version, counts within LUCENT_MAX_TRIANGLES, size
 * matching the counts, checksum, then finite values, radius > 0, indices in range, every vertex
 * inside the radius and unit normals. Damage fails with LUCENT_E_IO (LUCENT_E_LIMIT for counts over
 * the limit), field "mesh.file"; *out is set only on success. */
lucent_status mesh_compact_read(const void *data, size_t len, struct lucent_mesh **out, lucent_error *err);

/* The checksum the trailer holds: 64-bit, word at a time; a change confined to one 8-byte word
 * always changes it. */
uint64_t mesh_compact_checksum(const void *data, size_t len);

#endif
