// views.glsl - where a surface point lands in projection image k and whether that image sees it,
// shared by the scatter and ownership passes. Needs frame.glsl and `projection_images` declared first.

vec2 texel_coord(int k, vec3 p)
{
    vec3 rel = p - frame.view_origin[k].xyz;
    vec3 du = frame.view_du[k].xyz, dv = frame.view_dv[k].xyz;
    return vec2(dot(rel, du) / dot(du, du), dot(rel, dv) / dot(dv, dv));
}

bool inside(int k, ivec2 t)
{
    int side = int(frame.view_du[k].w);
    return t.x >= 0 && t.y >= 0 && t.x < side && t.y < side;
}

// How squarely view k faces a surface of normal n (the cosine; <= 0: the view sees its back).
float view_score(int k, vec3 n)
{
    return dot(n, -frame.view_dir[k].xyz);
}

// The depth view k stores for p (the alpha of its projection images).
float view_depth(int k, vec3 p)
{
    return dot(p - frame.view_origin[k].xyz, frame.view_dir[k].xyz);
}

// Depth change per texel along x and y on the tangent plane of normal n in view k; grazing slopes
// are capped (cosine 0.1).
vec2 tangent_slope(int k, vec3 n)
{
    return vec2(dot(frame.view_du[k].xyz, n), dot(frame.view_dv[k].xyz, n)) / max(view_score(k, n), 0.1);
}

// How far a stored depth may lie from a surface's own depth and still be that surface: it grows with
// the surface's slope in view k (cosine `facing`, capped at 0.1) and the proxy mesh's offset.
float depth_tolerance(int k, float facing)
{
    return frame.view_dv[k].w * (1.5 + 1.0 / max(facing, 0.1)) + frame.params.z;
}

// The point is visible in view k when the depth stored at its texel is its own depth.
bool visible_in(int k, vec3 p, vec3 n)
{
    ivec2 t = ivec2(floor(texel_coord(k, p)));
    if (!inside(k, t))
        return false;
    float stored = texelFetch(projection_images, ivec3(t, k), 0).a;
    return stored >= 0.0 && abs(stored - view_depth(k, p)) <= depth_tolerance(k, view_score(k, n));
}

// A view's weight in the share of a surface point among the views that see it (ownership.comp): its
// facing cosine to the 8th power, so the share passes smoothly from one view to the next over about
// 30 degrees and the owned images have no hard edges for the mip chain to blur.
float facing_weight(float c)
{
    float c2 = c * c, c4 = c2 * c2;
    return c4 * c4;
}
