// ownership.comp - each projection image's share of the surface it shows. The owned images hold, at
// 2^-frame.view_origin[k].w the projection images' resolution, their mean flux times the view's weight
// among the views that see that surface point: a partition of unity over the views, by how squarely
// each faces the point, so the far pass can gather from every view and count each lit point once.
// Alpha is the mean over the texels an owned texel stands for of their flux's r + g + b times
// e^(rate (depth - centre)) (frame.owned.zw), times the share, so that the mip chain's mean of it over
// the mean flux is the depth where the light is, weighted as R_d weighs it (exponentially: the nearest
// light counts most; 0 where there is none).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "backend.glsl"
#include "frame.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 1) uniform sampler2DArray projection_images;
layout(set = 0, binding = 9) uniform sampler2DArray projection_normals;
layout(set = 0, binding = 10, rgba32f) uniform writeonly image2DArray owned_images;
// x: the first view of the dispatch (0: the front view; 1: the side and light views, one per z).
PUSH_CONSTANTS Push { ivec2 first_view; } push;
#include "views.glsl"

// A light view sees every point its light reaches, squarely where the light falls squarely: on surface
// facing away from the camera, which the camera views see obliquely if at all, it takes the points it
// sees unless it sees them 5x more obliquely than a camera view. Sharing those by facing alone (a
// sphere lit from behind) counted its back 1.2x; taking the camera's side too made a rim-lit sphere's
// error twice what it was without light views.
float share_weight(int k, float facing, vec3 n)
{
    bool behind = dot(n, frame.view_dir[0].xyz) > 0.0;
    return facing_weight(facing) * (k >= CAMERA_VIEWS && behind ? 1e6 : 1.0);
}

// The mean flux of the block x block texels at q (rgb; uncovered texels hold none) and the mean of their
// r + g + b times e^(rate (depth - centre)) (a), each texel at its own depth. One depth for the block (its
// centre texel's) put a thin part's light at the depth of whatever lay behind it in the same block (a
// back-lit bunny's ear 0.92 of the reference's light, 0.94 with this, at 256^2).
vec4 block_flux(int k, ivec2 q, int block)
{
    vec4 sum = vec4(0.0);
    for (int y = 0; y < block; y++)
        for (int x = 0; x < block; x++) {
            vec4 f = texelFetch(projection_images, ivec3(q * block + ivec2(x, y), k), 0);
            if (f.a >= 0.0)
                sum += vec4(f.rgb, (f.r + f.g + f.b) * exp(frame.owned.z * (f.a - frame.owned.w)));
        }
    return sum / float(block * block);
}

void main()
{
    int k = push.first_view.x + int(gl_GlobalInvocationID.z);
    ivec2 q = ivec2(gl_GlobalInvocationID.xy);
    int shift = int(frame.view_origin[k].w), side = int(frame.view_du[k].w) >> shift;
    if (q.x >= side || q.y >= side)
        return;
    int block = 1 << shift;
    vec4 flux = block_flux(k, q, block);
    // The share is decided at the first covered texel of the four at the block's centre, else of its
    // corners; texels differ from it only where the view's own silhouette crosses the block.
    ivec2 t = q * block;
    vec4 texel = vec4(0.0, 0.0, 0.0, -1.0);
    for (int i = 0; i < 8 && texel.a < 0.0 && flux.rgb != vec3(0.0); i++) {
        ivec2 corner = ivec2(i & 1, (i >> 1) & 1);
        t = q * block + (i < 4 ? max(block / 2 - 1, 0) + corner * min(block - 1, 1) : corner * (block - 1));
        texel = texelFetch(projection_images, ivec3(t, k), 0);
    }
    if (texel.a < 0.0 || flux.rgb == vec3(0.0)) {
        imageStore(owned_images, ivec3(q, k), vec4(0.0));
        return;
    }
    vec3 n = normalize(texelFetch(projection_normals, ivec3(t, k), 0).xyz);
    vec3 p = frame.view_origin[k].xyz + (float(t.x) + 0.5) * frame.view_du[k].xyz +
             (float(t.y) + 0.5) * frame.view_dv[k].xyz + texel.a * frame.view_dir[k].xyz;
    // The texel's own view always counts, however grazing: a point no other view sees stays its.
    // Views whose weight could not change the share by a thousandth are not looked up.
    float own = share_weight(k, max(view_score(k, n), 1e-3), n), total = own;
    for (int j = 0; j < int(frame.owned.y); j++) {
        float w = share_weight(j, max(view_score(j, n), 0.0), n);
        if (j != k && w > 1e-3 * own && visible_in(j, p, n))
            total += w;
    }
    imageStore(owned_images, ivec3(q, k), flux * (own / total));
}
