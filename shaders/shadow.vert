// shadow.vert - depth-only pass from a light, for lights that can be occluded by the mesh itself.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "backend.glsl"
PUSH_CONSTANTS Push { mat4 clip_from_world; } push;
layout(location = 0) in vec3 in_position;
void main()
{
    gl_Position = push.clip_from_world * vec4(in_position, 1.0);
}
