// projection.frag - light entering the surface (irradiance x Fresnel transmittance, shadowed) per texel,
// stored per unit of projection-image area so the scatter pass can sum texels as area elements; and
// the surface normal, from which the ownership pass shares each point among the views that see it.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "backend.glsl"
#extension GL_EXT_control_flow_attributes : require
#include "frame.glsl"
layout(set = 0, binding = 1) uniform sampler2DArrayShadow shadow_maps;
PUSH_CONSTANTS Push { int view_base; } push;
layout(location = 0) in vec3 v_position;
layout(location = 1) in vec3 v_normal;
layout(location = 0) out vec4 out_flux_depth;
layout(location = 1) out vec4 out_normal;

// Specialized per frame shape (pipelines.c): CPU drivers run both sides of every branch, so lights
// that do not exist and shadow lookups that cannot matter must not exist in the code either.
layout(constant_id = 0) const int LIGHT_COUNT = 1;
layout(constant_id = 1) const int SHADOW_MASK = 0;

// Fraction of light l reaching p: one hardware-filtered comparison (2x2 PCF). The bias is applied
// to the linear depth (scene units) and converted back to the map's depth encoding.
float shadow_visibility(int l, vec3 p)
{
    int layer = int(frame.light_rgb[l].w);
    vec4 clip = frame.light_clip[l] * vec4(p, 1.0);
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))))
        return 1.0;
    vec4 d = frame.light_depth[l];   // near, far, perspective, bias
    float ref;
    if (d.z > 0.5) {
        float z = max(clip.w - d.w, d.x);
        ref = d.y * (z - d.x) / ((d.y - d.x) * z);
    } else {
        ref = clip.z - d.w / (d.y - d.x);
    }
    return texture(shadow_maps, vec4(uv, float(layer), ref));
}

void main()
{
    vec3 n = normalize(v_normal);
    if (!gl_FrontFacing)
        n = -n;
    float eta = frame.params.x;
    vec3 entering = vec3(0.0);
    [[unroll]] for (int l = 0; l < LIGHT_COUNT; l++) {
        vec4 lv = frame.light_vec[l];
        vec3 d = lv.w > 0.5 ? lv.xyz - v_position : -lv.xyz;
        float dist2 = max(dot(d, d), 1e-30);
        float falloff = lv.w > 0.5 ? 1.0 / dist2 : 1.0;
        float cos_l = max(dot(n, d * inversesqrt(dist2)), 0.0);
        vec3 light = frame.light_rgb[l].rgb * (falloff * cos_l * fresnel_transmittance(eta, cos_l));
        if ((SHADOW_MASK & (1 << l)) != 0)
            light *= shadow_visibility(l, v_position);
        entering += light;
    }
    int view = VIEW_INDEX + push.view_base;
    vec3 dir = frame.view_dir[view].xyz;
    float area = 1.0 / max(dot(n, -dir), MIN_AREA_COS);
    float depth = dot(v_position - frame.view_origin[view].xyz, dir);
    // A light view that sees an open sheet's back sees the points the camera sees, from behind: lit
    // there, their light would cross no thickness at all. The reference lights the side the normals
    // give, so a sheet lit from behind stays dark in both (closed meshes show no back faces).
    if (!gl_FrontFacing && view >= CAMERA_VIEWS)
        entering = vec3(0.0);
    out_flux_depth = vec4(entering * area, depth);
    out_normal = vec4(n, 0.0);
}
