/* test_frame_layout.c - prints where each member of struct frame_uniforms (renderer/core/frame_uniforms.h) lies,
 * for test_frame_layout.py to hold against the std140 offsets glslang reports for shaders/frame.glsl. */
#include "frame_uniforms.h"

#include <stddef.h>
#include <stdio.h>

#define MEMBER(name) printf("%s %zu\n", #name, offsetof(struct frame_uniforms, name))

int main(void)
{
    MEMBER(view_clip);
    MEMBER(view_origin);
    MEMBER(view_du);
    MEMBER(view_dv);
    MEMBER(view_dir);
    MEMBER(light_vec);
    MEMBER(light_rgb);
    MEMBER(light_clip);
    MEMBER(light_depth);
    MEMBER(params);
    MEMBER(camera_eye);
    MEMBER(profile_z);
    MEMBER(profile_sigma);
    MEMBER(profile_a);
    MEMBER(profile_b);
    MEMBER(rd_total);
    MEMBER(near_rd);
    MEMBER(single_albedo);
    MEMBER(single_sigma_t);
    MEMBER(owned);
    MEMBER(samples);
    MEMBER(through_pdf);
    MEMBER(through);
    MEMBER(sphere_factor);
    printf("(size) %zu\n", sizeof(struct frame_uniforms));
    return 0;
}
