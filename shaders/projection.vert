// projection.vert - draws the mesh into the projection images: the front view alone, or the four side
// views in one multiview pass (view_base 1 maps multiview's view 0 to image 1; OpenGL draws one view at a time).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "backend.glsl"
#include "frame.glsl"
PUSH_CONSTANTS Push { int view_base; } push;
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec4 in_normal_curvature;   // w unused here
layout(location = 0) out vec3 v_position;
layout(location = 1) out vec3 v_normal;
void main()
{
    v_position = in_position;
    v_normal = in_normal_curvature.xyz;
    gl_Position = frame.view_clip[VIEW_INDEX + push.view_base] * vec4(in_position, 1.0);
}
