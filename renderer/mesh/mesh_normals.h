/* mesh_normals.h - smooth vertex normals shared by mesh_finish (mesh.c) and the proxy simplifier.
 * Private to liblucent; kept out of mesh.h because only these two callers need it. */
#ifndef LUCENT_MESH_NORMALS_H
#define LUCENT_MESH_NORMALS_H

#include "mesh.h"

/* Makes every normal of m unit length. With m->normals == NULL all normals are allocated and
 * computed (area-weighted average of the adjacent faces); otherwise only the normals that are
 * non-finite or zero-length are replaced that way and the rest are normalized, and turned to the
 * side the winding calls outside where they point against their faces. Positions must
 * already be relative to m->center, which is the fallback direction at vertices whose adjacent
 * faces cancel out. Fails only with LUCENT_E_NOMEM. */
lucent_status mesh_fill_normals(struct lucent_mesh *m, lucent_error *err);

#endif
