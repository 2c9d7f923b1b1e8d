/* stanford_bunny.h - the Stanford bunny (Turk and Levoy, Stanford 3D Scanning Repository) as the npm package
 * "bunny" ships it, converted to C at build time by stanford_bunny.cmake; built as mesh_builtin.c's "bunny". */
#ifndef LUCENT_STANFORD_BUNNY_H
#define LUCENT_STANFORD_BUNNY_H

#include <stdint.h>

extern const float stanford_bunny_positions[][3];
extern const uint32_t stanford_bunny_vertex_count;
extern const uint32_t stanford_bunny_triangles[][3]; /* vertex indices, counter-clockwise seen from outside */
extern const uint32_t stanford_bunny_triangle_count;

#endif
