// gbuffer.vert - the camera's view of the mesh: where each pixel's surface point is and which way it faces.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "backend.glsl"
PUSH_CONSTANTS Push { mat4 clip_from_world; vec4 eye; } push;
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec4 in_normal_curvature;   // w: mesh_ball_curvature, 1 / scene units
layout(location = 0) out vec3 v_position;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out float v_curvature;
void main()
{
    v_position = in_position;
    v_normal = in_normal_curvature.xyz;
    v_curvature = in_normal_curvature.w;
    gl_Position = push.clip_from_world * vec4(in_position, 1.0);
}
