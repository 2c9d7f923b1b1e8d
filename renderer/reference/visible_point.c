/* visible_point.c - camera rays of the CPU methods: the hit, its normals turned to the camera, and the AOVs. */
#include "visible_point.h"
#include "linalg.h"

#include <math.h>

int visible_point_at(const struct view_frame *camera, const struct bvh *bvh, const struct lucent_mesh *mesh,
                     const float *vertex_curvature, double px, double py, int width, int height,
                     struct visible_point *out)
{
    struct bvh_hit hit;
    view_frame_ray_through(camera, px, py, width, height, out->dir);
    if (!bvh_closest(bvh, camera->eye, out->dir, INFINITY, &hit))
        return 0;
    mesh_surface_at(mesh, hit.triangle, hit.u, hit.v, out->p, out->n, out->g);
    out->curvature = vertex_curvature ? mesh_curvature_at(mesh, vertex_curvature, hit.triangle, hit.u, hit.v)
                                      : mesh_curvature(mesh, hit.triangle);
    if (v3_dot(out->g, out->dir) > 0.0) {
        for (int a = 0; a < 3; a++)
            out->n[a] = -out->n[a], out->g[a] = -out->g[a];
        out->curvature = -out->curvature;
    }
    out->t = hit.t;
    return 1;
}

void visible_point_write_aovs(lucent_image *img, size_t i, const struct visible_point *v)
{
    img->rgba[i * 4 + 3] = 1.0f;
    if (!img->depth)
        return;
    img->depth[i] = (float)v->t;
    for (int a = 0; a < 3; a++)
        img->normal[i * 3 + a] = (float)v->n[a];
    img->view[i] = 0.0f;
    img->facing[i] = (float)-v3_dot(v->n, v->dir);
}
