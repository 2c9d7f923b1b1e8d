// backend.glsl - the few lines that differ between a shader's Vulkan and OpenGL builds (LUCENT_GL defined):
// OpenGL has no push constants (a uniform block at binding 12 holds them) and no multiview (the side and
// light views are drawn one at a time there, each with its own view_base).
#ifdef LUCENT_GL
#define PUSH_CONSTANTS layout(std140, binding = 12) uniform
#define VIEW_INDEX 0
#else
#extension GL_EXT_multiview : require
#define PUSH_CONSTANTS layout(push_constant) uniform
#define VIEW_INDEX gl_ViewIndex
#endif
