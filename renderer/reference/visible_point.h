/* visible_point.h - the surface point a pixel's camera ray hits, as the CPU methods (reference, path) shade
 * it, and the coverage and AOVs they write for it. */
#ifndef LUCENT_VISIBLE_POINT_H
#define LUCENT_VISIBLE_POINT_H

#include "bvh.h"
#include "lucent.h"
#include "mesh.h"
#include "view_frame.h"

struct visible_point {
    double dir[3];   /* the camera ray, unit */
    double p[3];     /* the point hit */
    double n[3], g[3];   /* shading and geometric normals, both turned to face the camera */
    double t;        /* distance from the eye */
    double curvature;   /* the surface's curvature there, signed for the side facing the camera */
};

/* 1 and *out when the ray through image position (px, py) (pixels from the top-left corner: pixel (x, y)'s
 * centre is (x + 0.5, y + 0.5)) of a width x height image sees the mesh; 0 on the background. A back face
 * in view (open mesh, or the eye inside) is shaded from the side facing the camera, as the raster passes
 * do with gl_FrontFacing. Curvature: interpolated from vertex_curvature (mesh_vertex_curvature), or where
 * that is NULL the hit triangle's mesh_curvature. */
int visible_point_at(const struct view_frame *camera, const struct bvh *bvh, const struct lucent_mesh *mesh,
                     const float *vertex_curvature, double px, double py, int width, int height,
                     struct visible_point *out);
/* Marks pixel i covered and, where the image has AOVs, writes its depth, normal, view (0) and facing. */
void visible_point_write_aovs(lucent_image *img, size_t i, const struct visible_point *v);

#endif
