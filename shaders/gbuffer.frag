// gbuffer.frag - writes position + camera distance and normal + coverage for the scatter pass; coverage is
// 1 + the convex curvature the sphere factor takes (1 / scene units, mesh_ball_curvature), 0 where nothing was drawn.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "backend.glsl"
PUSH_CONSTANTS Push { mat4 clip_from_world; vec4 eye; } push;
layout(location = 0) in vec3 v_position;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in float v_curvature;
layout(location = 0) out vec4 out_position_depth;
layout(location = 1) out vec4 out_normal_coverage;
void main()
{
    vec3 n = normalize(v_normal);
    float curvature = v_curvature;
    // Open meshes and flipped windings show their inside: shade the side that faces the camera.
    if (!gl_FrontFacing)
        n = -n, curvature = -curvature;
    out_position_depth = vec4(v_position, length(v_position - push.eye.xyz));
    out_normal_coverage = vec4(n, 1.0 + max(curvature, 0.0));
}
