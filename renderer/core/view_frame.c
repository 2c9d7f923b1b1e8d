/* view_frame.c - builds view bases and clip matrices for every raster pass.
 * The screen's y axis points down so Vulkan's framebuffer row 0 is the image's top row. */
#include "view_frame.h"

#include "linalg.h"

int view_frame_look(struct view_frame *v, const double eye[3], const double forward[3],
                    const double up[3])
{
    double f[3] = {forward[0], forward[1], forward[2]};
    if (v3_normalize(f) == 0.0)
        return -1;
    double r[3];
    v3_cross(f, up, r);
    if (v3_normalize(r) < 1e-9 * v3_length(up))
        return -1;
    double d[3];
    v3_cross(f, r, d);
    for (int i = 0; i < 3; i++) {
        v->eye[i] = eye[i];
        v->forward[i] = f[i];
        v->right[i] = r[i];
        v->down[i] = d[i];
    }
    return 0;
}

void view_frame_any_up(const double forward[3], double up[3])
{
    double ax = fabs(forward[0]), ay = fabs(forward[1]), az = fabs(forward[2]);
    up[0] = up[1] = up[2] = 0.0;
    if (ay <= ax && ay <= az)
        up[1] = 1.0;
    else if (az <= ax)
        up[2] = 1.0;
    else
        up[0] = 1.0;
}

void view_frame_pixel_ray(const struct view_frame *v, int x, int y, int width, int height, double dir[3])
{
    view_frame_ray_through(v, x + 0.5, y + 0.5, width, height, dir);
}

void view_frame_ray_through(const struct view_frame *v, double px, double py, int width, int height, double dir[3])
{
    double ndc_x = 2.0 * px / width - 1.0, ndc_y = 2.0 * py / height - 1.0;
    for (int i = 0; i < 3; i++)
        dir[i] = v->forward[i] + v->right[i] * ndc_x * v->half_w + v->down[i] * ndc_y * v->half_h;
    v3_normalize(dir);
}

void view_frame_clip(const struct view_frame *v, double m[16])
{
    const double *axes[3] = {v->right, v->down, v->forward};
    double view[16] = {0};
    for (int row = 0; row < 3; row++) {
        for (int c = 0; c < 3; c++)
            view[c * 4 + row] = axes[row][c];
        view[12 + row] = -v3_dot(axes[row], v->eye);
    }
    view[15] = 1.0;

    double proj[16] = {0};
    double depth = v->far - v->near;
    if (v->perspective) {
        proj[0] = 1.0 / v->half_w;
        proj[5] = 1.0 / v->half_h;
        proj[10] = v->far / depth;
        proj[14] = -v->far * v->near / depth;
        proj[11] = 1.0;
    } else {
        proj[0] = 1.0 / v->half_w;
        proj[5] = 1.0 / v->half_h;
        proj[10] = 1.0 / depth;
        proj[14] = -v->near / depth;
        proj[15] = 1.0;
    }
    m4_mul(proj, view, m);
}
