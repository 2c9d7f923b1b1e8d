/* view_frame.h - an eye, an orthonormal basis and a projection: the camera, the five projection images and
 * the shadow maps are all one of these. Vulkan's clip conventions (y down, depth 0..1), OpenGL's too. */
#ifndef LUCENT_VIEW_FRAME_H
#define LUCENT_VIEW_FRAME_H

struct view_frame {
    double eye[3];
    double right[3], down[3], forward[3];  /* right x down = forward */
    int perspective;
    double half_w, half_h;   /* orthographic: half extents; perspective: tangents of half angles */
    double near, far;        /* along forward, from the eye */
};

/* Sets eye and basis looking along forward with up as the screen's up; returns -1 when
 * forward is zero or parallel to up. */
int view_frame_look(struct view_frame *v, const double eye[3], const double forward[3],
                    const double up[3]);
/* Any up vector not parallel to forward (for views whose roll does not matter). */
void view_frame_any_up(const double forward[3], double up[3]);
/* Unit direction of the ray through the centre of pixel (x, y) of a width x height perspective image. */
void view_frame_pixel_ray(const struct view_frame *v, int x, int y, int width, int height, double dir[3]);
/* Unit direction of the ray through image position (px, py) in pixels from the top-left corner (pixel (x, y)
 * spans [x, x + 1) x [y, y + 1)). */
void view_frame_ray_through(const struct view_frame *v, double px, double py, int width, int height, double dir[3]);
/* World -> clip matrix, column-major. */
void view_frame_clip(const struct view_frame *v, double m[16]);

#endif
