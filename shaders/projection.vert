// projection.vert - draws the mesh into the projection images; multiview renders all of them in one pass.
#version 450
#extension GL_EXT_multiview : require
#extension GL_GOOGLE_include_directive : require
#include "frame.glsl"
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 0) out vec3 v_position;
layout(location = 1) out vec3 v_normal;
void main()
{
    v_position = in_position;
    v_normal = in_normal;
    gl_Position = frame.view_clip[gl_ViewIndex] * vec4(in_position, 1.0);
}
