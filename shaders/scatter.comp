// scatter.comp - the final passes: integrate the diffusion profile over the prefiltered flux of the
// projection images. The far annulus of the profile is integrated once per block of pixels (PASS_FAR),
// gathered from every view's share of the surface (or, with one view or the paper's fallback, from the
// view a point chooses); PASS_FAR_FILTER averages it over neighbouring blocks on the same surface; the
// compose pass adds the near disc per pixel, upsamples the far part guided by position and normal,
// and applies the exit Fresnel term.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "backend.glsl"
#extension GL_EXT_control_flow_attributes : require
#include "frame.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 1) uniform sampler2DArray projection_images;
layout(set = 0, binding = 2) uniform sampler2D gbuffer_position;
layout(set = 0, binding = 3) uniform sampler2D gbuffer_normal;
layout(std430, set = 0, binding = 4) writeonly buffer OutColor { vec4 out_color[]; };
layout(std430, set = 0, binding = 5) writeonly buffer OutNormalView { vec4 out_normal_view[]; };
layout(std430, set = 0, binding = 6) writeonly buffer OutDepth { float out_depth[]; };
// Per block of FAR_BLOCK^2 pixels: diffuse light from the far annulus (rgb; w: the normal where it was
// integrated, octahedral, packed) and that pixel's position (w: x + 4096 y, exact in a float for sides
// up to LUCENT_MAX_IMAGE_SIDE 4096; -1: no pixel covered).
struct FarSample { vec4 diffuse; vec4 position; };
layout(std430, set = 0, binding = 7) buffer Far { FarSample far_samples[]; };
// The far samples after PASS_FAR_FILTER; for blocks of one pixel, not filtered, the same range as binding 7.
layout(std430, set = 0, binding = 11) buffer FarFiltered { FarSample far_filtered[]; };
layout(set = 0, binding = 8) uniform sampler2DArray owned_images;
layout(set = 0, binding = 9) uniform sampler2DArray projection_normals;
PUSH_CONSTANTS Push { ivec2 size; } push;

// Specialized per request (pipelines.c): constant loop bounds unroll, and CPU drivers pay for
// untaken branches, so the sampling scheme is chosen at pipeline creation.
layout(constant_id = 0) const int SAMPLES = 16;          // per channel; 0: diffuse limit
layout(constant_id = 1) const int VIEW_COUNT = 5;
layout(constant_id = 2) const bool SHARED_SAMPLES = true;
layout(constant_id = 3) const bool FRONT_FALLBACK = false; // the paper's: hidden in the best view -> front
layout(constant_id = 4) const bool SINGLE_SCATTERING = false;
layout(constant_id = 5) const int PASS = 0;               // SCATTER_* of pipelines.h
const bool PASS_FAR = PASS == 1, PASS_FAR_FILTER = PASS == 2;
layout(constant_id = 6) const int FAR_BLOCK = 4;          // pixels per side of a block (frame_plan.c)
// With five views and the default fallback the far annulus is gathered from every view (and the views
// along lights whose light enters where no camera view faces the surface: transmission), over each
// view's share of the surface (ownership.comp), so light crosses edges and view boundaries and
// through the object; else from the one or two views the pixel chooses, over the whole projection
// images.
const bool OWNED = VIEW_COUNT >= CAMERA_VIEWS && !FRONT_FALLBACK;
// Light views are planned (frame_plan.c): light can reach p through the object.
const bool TRANSMISSION = OWNED && VIEW_COUNT > CAMERA_VIEWS;
// Distances along the view ray at which single scattering gathers light through the object
// (single_through): per channel, fading with sigma_t, and shared, spread evenly.
const int SINGLE_FADING_SAMPLES = 4, SINGLE_EVEN_SAMPLES = 8;
const int UNSCATTERED_STEPS = 8, UNSCATTERED_HALVINGS = 6;   // finding where unscattered light enters
// Views whose facing cosines differ by less than this are blended.
const float VIEW_BLEND = 0.2;
// A sample reads the mip level whose texels are half the side of the area it stands for, a quarter
// where the far part is integrated per block and filtered (FAR_BLOCK > 1): measured on the side-lit bunny,
// sphere and protrusion, 0 blurs the terminator and -1 brings back noise unfiltered (back-lit 128^2:
// the skin1 sphere behind a point light 0.127 -> 0.212); filtered, -1 took every scene of
// compare_sheet.sh nearer the reference (256^2: back-lit skim-milk sphere 0.049 -> 0.033, side-lit
// bunny 0.060 -> 0.056, a back-lit ear's light 0.965 -> 0.984 of it) and -1.5 raised the mottle.
const float LOD_BIAS = FAR_BLOCK > 1 ? -1.0 : -0.5;
#include "views.glsl"

// Best-facing camera view in which the point is visible; views facing away are never used.
// Falls back to the front view (0), as the paper does, when no facing view sees the point, or at
// once when FRONT_FALLBACK is set. `except` is a view not to choose (-1: none); returns -1 when no
// other facing view sees the point.
int choose_view(vec3 p, vec3 n, int except)
{
    uint tried = except >= 0 ? 1u << except : 0u;
    for (int attempt = 0; attempt < (FRONT_FALLBACK ? 1 : min(VIEW_COUNT, CAMERA_VIEWS)); attempt++) {
        int best = -1;
        float best_score = 0.0;
        for (int k = 0; k < VIEW_COUNT && k < CAMERA_VIEWS; k++) {
            float score = view_score(k, n);
            if ((tried & (1u << k)) == 0u && score > best_score) {
                best = k;
                best_score = score;
            }
        }
        if (best < 0)
            break;
        if (visible_in(best, p, n))
            return best;
        tried |= 1u << best;
    }
    return except >= 0 ? -1 : 0;
}

// Texels hold irradiance per unit of image area (projection.frag); per unit of surface area it is
// smaller by the cosine to the view, with the same floor.
vec3 surface_irradiance(int k, ivec2 t, vec3 n)
{
    return texelFetch(projection_images, ivec3(t, k), 0).rgb * max(view_score(k, n), MIN_AREA_COS);
}

// Beyond this distance (mm) R_d is 0 in fp32, and squares of it overflow: inf x 0 made NaN (a sphere
// 1e12 units wide at 1e9 mm a unit, an extremes case).
const float FAR_MM = 1e18;

// (1 - e^(-x)) / x, 1 at x = 0; the series where the difference would cancel in floats.
float fraction(float x)
{
    return x < 1e-2 ? 1.0 - x * (0.5 - x / 6.0) : (1.0 - exp(-x)) / x;
}

// e^(-s d0) / d0 - e^(-s d1) / d1 for d1 >= d0 > 0, given gap = d1 - d0 (C: falloff_difference).
float falloff_difference(float s, float d0, float d1, float gap)
{
    return exp(-s * d0) * gap * (1.0 + s * d0 * fraction(s * gap)) / (d0 * d1);
}

// The better dipole's fluence terms: a_1 = -a_0 at one rate (C: paired).
bool paired(int c)
{
    return frame.profile_a[0][c] != 0.0 && frame.profile_a[1][c] == -frame.profile_a[0][c] &&
           frame.profile_sigma[0][c] == frame.profile_sigma[1][c];
}

// The diffusion profile R(r) of channel c (frame.glsl; C: profile_rd). The floor on the distance
// keeps normalized diffusion's sources at the exit point finite and its cube a normal float.
float profile_rd(int c, float r)
{
    if (!(r < FAR_MM))
        return 0.0;
    float d[2], sum = 0.0;
    for (int k = 0; k < 2; k++) {
        float z = frame.profile_z[k][c], s = frame.profile_sigma[k][c];
        d[k] = max(sqrt(r * r + z * z), 1e-12);
        sum += frame.profile_b[k][c] * exp(-s * d[k]) * (s * d[k] + 1.0) / (d[k] * d[k] * d[k]);
    }
    if (paired(c)) {
        float z0 = frame.profile_z[0][c], z1 = frame.profile_z[1][c];
        float gap = (z1 - z0) * (z1 + z0) / (d[0] + d[1]);
        return sum + frame.profile_a[0][c] * falloff_difference(frame.profile_sigma[0][c], d[0], d[1], gap);
    }
    for (int k = 0; k < 2; k++)
        sum += frame.profile_a[k][c] * exp(-frame.profile_sigma[k][c] * d[k]) / d[k];
    return sum;
}

// The paired fluence terms' integral outside radius t, over 2 pi (C: profile_tail).
float paired_tail(int c, float t)
{
    float z0 = frame.profile_z[0][c], z1 = frame.profile_z[1][c], s = frame.profile_sigma[0][c];
    float d0 = sqrt(t * t + z0 * z0), d1 = sqrt(t * t + z1 * z1), gap = (z1 - z0) * (z1 + z0) / (d0 + d1);
    return frame.profile_a[0][c] * exp(-s * d0) * gap * fraction(s * gap);
}

// Rotation of the sample pattern per block. The far filter averages each block with its eight neighbours,
// so every 3x3 window of blocks takes the nine evenly spaced turns (interleaved sampling): together they
// sample each ring at nine angles instead of nine random ones (random turns left a mottle three blocks
// wide). The filter weighs the nine alike, so their order matters only to the compose pass's blend of
// four blocks: this one, searched for 1-2-1 weights, measured within 0.004 of the natural order either
// way. Blocks of one pixel, which are not filtered, take a hash: a regular pattern there shows.
const int WINDOW_TURNS[9] = int[9](0, 5, 7, 6, 3, 1, 2, 8, 4);

float pixel_rotation(ivec2 px)
{
    if (FAR_BLOCK > 1)
        return (float(WINDOW_TURNS[px.x % 3 + 3 * (px.y % 3)]) + 0.5) / 9.0 * 2.0 * PI;
    uint h = uint(px.x) * 1973u + uint(px.y) * 9277u + 26699u;
    h = (h ^ (h >> 13)) * 1274126177u;
    return float(h & 0xffffu) / 65536.0 * 2.0 * PI;
}

vec3 profile_rd3(float r)
{
    return vec3(profile_rd(0, r), profile_rd(1, r), profile_rd(2, r));
}

// One source's share of R at the exit point, at signed depth h (mm) below the exit's tangent plane and
// distance d (C: source_term).
float source_term(float a, float c, float s, float h, float d)
{
    return exp(-s * d) * (a / d + c * h * (1.0 + s * d) / (d * d * d));
}

// Channel c's two sources placed for light entering with normal n_in at d (mm) from the exit point of
// normal n_out (d = exit - entry): the real one's depth and the virtual one's height under the exit's
// tangent plane, as held, their distances and their images' (C: place_sources, where the reasons are),
// and their coefficients.
struct Sources {
    float h0, h1, i0, i1, w;  // depth, height, their images' depths, weight of the exit's images
    float d0, d1, e0, e1;     // distances from the exit point: the sources, their images
    float a0, a1, c0, c1, s0, s1;
};

Sources place_sources(int c, vec3 d, vec3 n_out, vec3 n_in)
{
    Sources q;
    float z0 = frame.profile_z[0][c], z1 = frame.profile_z[1][c], tilt = dot(n_in, n_out);
    vec3 real = d + z0 * n_in, virt = d - z1 * n_in;
    float depth = dot(real, n_out);
    float zb = 0.5 * (z1 - z0);
    q.h0 = max(depth, z0);
    q.h1 = min(-dot(virt, n_out), q.h0 + 2.0 * zb);
    q.w = 0.5 * (1.0 - tilt);
    float shallow = clamp((z0 - depth) / z0, 0.0, 1.0) * clamp(1.0 + tilt, 0.0, 1.0);
    q.d0 = max(max(max(length(real), 1e-12), q.h0), shallow * sqrt(dot(d, d) + z0 * z0));
    q.d1 = max(max(length(virt), sqrt(dot(d, d) + z1 * z1)), abs(q.h1));
    float across0 = q.d0 * q.d0 - q.h0 * q.h0, across1 = max(q.d1 * q.d1 - q.h1 * q.h1, 0.0);
    q.i0 = q.h0 + 2.0 * zb;
    q.i1 = q.h1 - 2.0 * zb;
    q.e0 = max(sqrt(across0 + q.i0 * q.i0), 1e-12);
    q.e1 = max(sqrt(across1 + q.i1 * q.i1), z0);
    q.a0 = frame.profile_a[0][c];
    q.a1 = frame.profile_a[1][c];
    q.c0 = frame.profile_b[0][c] / z0;
    q.c1 = frame.profile_b[1][c] / z1;
    q.s0 = frame.profile_sigma[0][c];
    q.s1 = frame.profile_sigma[1][c];
    return q;
}

// The exit point's curvature as the sphere factor takes it (1/mm; 0 flat or concave; less where the part is
// thinner than its radius of curvature: mesh_ball_curvature), set by far_main and compose_main.
float exit_curvature_mm = 0.0;

float sphere_table(int c, int i, int j)
{
    int e = (c * SPHERE_TABLE_T + i) * SPHERE_TABLE_G + j;
    return frame.sphere_factor[e >> 2][e & 3];
}

// Diffusion in the sphere through both points over R between them, weighted by how much the exit's surface
// curves like that sphere (C: sphere_factor, where the reasons are).
float sphere_factor(int c, vec3 d, vec3 n_out, vec3 n_in)
{
    float depth = 0.5 * (dot(d, n_out) - dot(d, n_in)), len_in = length(n_in);
    if (exit_curvature_mm <= 0.0 || depth <= 0.0 || len_in <= 0.0)
        return 1.0;
    float a = dot(d, d) / (2.0 * depth), weight = min(exit_curvature_mm * a, 1.0);
    float t = clamp(frame.profile_sigma[0][c] * a, SPHERE_T_MIN, SPHERE_T_MAX);
    float u = log(t / SPHERE_T_MIN) / log(SPHERE_T_MAX / SPHERE_T_MIN) * float(SPHERE_TABLE_T - 1);
    float v = acos(clamp(dot(n_in, n_out) / len_in, -1.0, 1.0)) / PI * float(SPHERE_TABLE_G - 1);
    int i = min(int(u), SPHERE_TABLE_T - 2), j = min(int(v), SPHERE_TABLE_G - 2);
    float fu = u - float(i), fv = v - float(j);
    float f = mix(mix(sphere_table(c, i, j), sphere_table(c, i, j + 1), fv),
                  mix(sphere_table(c, i + 1, j), sphere_table(c, i + 1, j + 1), fv), fu);
    return 1.0 + weight * (f - 1.0);
}

// The surface's convex curvature at a pixel in 1/mm, as the G-buffer's coverage holds it (1 + curvature in
// 1 / scene units: mesh_ball_curvature, interpolated; 0 where concave), as the reference takes it.
float gbuffer_curvature(vec4 normal_coverage)
{
    return max(normal_coverage.w - 1.0, 0.0) / frame.params.y;
}

// R of channel c from light entering with normal n_in at d (mm) from the exit point of normal n_out:
// both sources and their images across the exit's boundary, their light through the exit's tangent plane,
// times the sphere's factor where the surface curves around them.
float profile_rd_between(int c, vec3 d, vec3 n_out, vec3 n_in)
{
    float z0 = frame.profile_z[0][c], z1 = frame.profile_z[1][c];
    if (z0 <= 0.0 || !(length(d) < FAR_MM))
        return profile_rd(c, length(d));
    Sources q = place_sources(c, d, n_out, n_in);
    float sum = source_term(q.a0, q.c0, q.s0, q.h0, q.d0) + source_term(q.a1, q.c1, q.s1, q.h1, q.d1);
    sum += q.w * (source_term(-q.a0, q.c0, q.s0, q.i0, q.e0) + source_term(-q.a1, q.c1, q.s1, q.i1, q.e1));
    return max(sum, 0.0) * sphere_factor(c, d, n_out, n_in);
}

vec3 profile_rd_between3(vec3 d, vec3 n_out, vec3 n_in)
{
    return vec3(profile_rd_between(0, d, n_out, n_in), profile_rd_between(1, d, n_out, n_in),
                profile_rd_between(2, d, n_out, n_in));
}

// The normal of view k's surface at texel t; `otherwise` where the texel holds none.
vec3 texel_normal(int k, ivec2 t, vec3 otherwise)
{
    vec3 n = texelFetch(projection_normals, ivec3(t, k), 0).xyz;
    return dot(n, n) > 0.0 ? normalize(n) : otherwise;
}

// Exit point minus a sample's entry point (mm), the sample `offset` texels across view k's image from p
// and `dz` mm deeper along the view.
vec3 entry_offset(int k, vec2 offset, float dz)
{
    return -((offset.x * frame.view_du[k].xyz + offset.y * frame.view_dv[k].xyz) * frame.params.y +
             dz * frame.view_dir[k].xyz);
}

// R integrated over a disc of radius `radius` (mm) on a plane `dz` (mm) off the point, parallel to
// the disc: T(|dz|) - T(sqrt(radius^2 + dz^2)) term by term so that narrow discs do not cancel; a wide
// disc's paired fluence terms as the difference of their tails (C: profile_disc_offset).
vec3 rd_disc_offset(float radius, float dz)
{
    radius = min(radius, FAR_MM);
    dz = clamp(dz, -FAR_MM, FAR_MM);
    vec3 sum = vec3(0.0);
    for (int c = 0; c < 3; c++) {
        bool wide_pair = paired(c) && radius > frame.profile_z[1][c];
        for (int k = 0; k < 2; k++) {
            float z = frame.profile_z[k][c], s = frame.profile_sigma[k][c], b = frame.profile_b[k][c];
            float inner = sqrt(dz * dz + z * z), outer = sqrt(dz * dz + z * z + radius * radius);
            float delta = outer > 0.0 ? radius * radius / (inner + outer) : 0.0;
            if (b != 0.0)
                sum[c] += b * falloff_difference(s, inner, outer, delta);
            if (!wide_pair)
                sum[c] += frame.profile_a[k][c] * exp(-s * inner) * delta * fraction(s * delta);
        }
        if (wide_pair)
            sum[c] += paired_tail(c, abs(dz)) - paired_tail(c, sqrt(radius * radius + dz * dz));
    }
    return 2.0 * PI * sum;
}

// One source's share of R integrated over a disc of radius `radius` (mm) centred on the exit's normal, the
// source at signed depth h and no nearer than `nearest`: 2 pi (a (e^(-s h) - e^(-s D)) / s + c h
// (e^(-s h) / h - e^(-s D) / D)), D = sqrt(radius^2 + h^2), written not to cancel.
float source_disc(float a, float c, float s, float h, float radius, float nearest)
{
    float inner = max(abs(h), nearest), outer = sqrt(radius * radius + inner * inner);
    float delta = radius * radius / (inner + outer);
    return 2.0 * PI * (a * exp(-s * inner) * delta * fraction(s * delta) +
                       c * h * falloff_difference(s, inner, outer, delta));
}

// How near a disc's light lies for source_disc: the disc, its centre `distance` (mm) from the exit point and
// `depth` under its tangent plane, taken as the annulus around the exit's normal of its area that ends at its
// centre's distance (C: disc_nearest).
float disc_nearest(float distance, float depth, float radius)
{
    return sqrt(max(distance * distance - radius * radius, depth * depth));
}

// profile_rd_between integrated over a disc of radius `radius` (mm) on the entry's surface, its centre at
// d (mm, exit - centre) from the exit point (a face across an edge or the far side of a thin part, seen in
// the view p lands in; C: profile_disc_between). Each source and image counts the disc at its own distance:
// taken under the exit point, a face beside p facing as p does lit p as if it lay beneath it (bluish spots
// on a side-lit bunny's shaded chest, lit by its flank 19 mm away).
vec3 rd_disc_between(float radius, vec3 d, vec3 n_out, vec3 n_in)
{
    radius = min(radius, FAR_MM);
    vec3 sum = vec3(0.0);
    for (int c = 0; c < 3; c++) {
        float z0 = frame.profile_z[0][c], z1 = frame.profile_z[1][c];
        if (z0 <= 0.0 || !(length(d) < FAR_MM)) {
            sum[c] = rd_disc_offset(radius, length(d))[c];
            continue;
        }
        Sources q = place_sources(c, d, n_out, n_in);
        sum[c] = source_disc(q.a0, q.c0, q.s0, q.h0, radius, disc_nearest(q.d0, q.h0, radius)) +
                 source_disc(q.a1, q.c1, q.s1, q.h1, radius, disc_nearest(q.d1, q.h1, radius)) +
                 q.w * (source_disc(-q.a0, q.c0, q.s0, q.i0, radius, disc_nearest(q.e0, q.i0, radius)) +
                        source_disc(-q.a1, q.c1, q.s1, q.i1, radius, disc_nearest(q.e1, q.i1, radius)));
        sum[c] *= sphere_factor(c, d, n_out, n_in);
    }
    return max(sum, vec3(0.0));
}

// Mean flux density over about `area_texels` texels of view k's projection image around `at`, from
// the mip chain of the gathered images (bilinear within the nearest level). A far sample stands for
// its whole ring segment, so it returns that segment's mean instead of one texel (the prefiltering of
// translucent shadow maps). The owned images have a lower resolution (frame.view_origin[k].w), and their alpha
// weighs the flux by its depth (ownership.comp, footprint_light).
// Reads stay inside the view's corner of its layer, the only part of the side layers' levels that is
// written.
vec4 prefiltered(int k, vec2 at, float area_texels)
{
    int shift = OWNED ? int(frame.view_origin[k].w) : 0, layer_shift = OWNED ? int(frame.owned.x) : 0;
    float scale = exp2(-float(shift));
    int side = int(frame.view_du[k].w) >> shift;
    float lod = clamp(0.5 * log2(max(area_texels * scale * scale, 1.0)) + LOD_BIAS, 0.0, float(findMSB(side)));
    int finer = int(lod);   // the sampler rounds lod to the nearest level, this one or the next
    float level_side = float(side >> finer), layer_side = float((int(frame.view_du[0].w) >> layer_shift) >> finer);
    vec3 uvw = vec3(clamp(at * scale * exp2(-float(finer)), vec2(1.0), vec2(max(level_side - 1.0, 1.0))) / layer_side,
                    float(k));
    if (OWNED)
        return textureLod(owned_images, uvw, lod);
    return textureLod(projection_images, uvw, lod);
}

vec3 prefiltered_flux(int k, vec2 at, float area_texels)
{
    return prefiltered(k, at, area_texels).rgb;
}

// The owned flux over a footprint and how far its light lies behind `depth` (the depth of its
// flux's exponentially weighted mean, ownership.comp, minus `depth`, in the view's scene units);
// false where the footprint holds no light.
bool footprint_light(int k, vec2 at, float area_texels, float depth, out vec3 flux, out float step)
{
    vec4 f = prefiltered(k, at, area_texels);
    float lit = f.r + f.g + f.b;
    flux = f.rgb;
    step = lit > 0.0 && f.a > 0.0 ? frame.owned.w + log(f.a / lit) / frame.owned.z - depth : 0.0;
    return lit > 0.0 && f.a > 0.0;
}

// With light views, light arrives through the object from where the profile's samples are sparse (a
// sphere lit from behind glows at the front with light from its rim, 15-25 mm away): the light views,
// and the camera views that see p, add the evenly spread samples of the annulus, each its cell's flux
// at the cell's flux-weighted depth, weighed against the profile's samples by the balance heuristic
// (the weight over both sets' densities). Measured on a marble sphere lit from behind: the mean went
// from 0.20 of the reference's to 0.82.
vec3 light_through(int k, vec2 center, float depth, mat2 rotate, float mm_per_texel, vec3 n)
{
    vec3 sum = vec3(0.0);
    for (int j = 0; j < (FAR_BLOCK > 1 ? THROUGH_SAMPLES / 2 : THROUGH_SAMPLES); j++) {   // frame_through_samples()
        vec4 s = frame.through[j];
        vec2 offset = (rotate * s.zw) * (s.x / mm_per_texel), at = center + offset;
        if (!inside(k, ivec2(floor(at))))
            continue;
        vec3 flux;
        float step;
        if (!footprint_light(k, at, min(s.y, s.x * s.x) / (mm_per_texel * mm_per_texel), depth, flux, step))
            continue;
        vec3 n_in = texel_normal(k, ivec2(floor(at)), -frame.view_dir[k].xyz);
        vec3 rd = profile_rd_between3(entry_offset(k, offset, step * frame.params.y), n, n_in), at_r = profile_rd3(s.x);
        vec3 profile = SHARED_SAMPLES ? vec3(dot(at_r, 1.0 / (3.0 * frame.rd_total.rgb)) / frame.through_pdf.w)
                                      : at_r / frame.through_pdf.rgb;
        sum += flux * rd / (float(SAMPLES) * profile + 1.0 / s.y);
    }
    return sum;
}

// Sums flux x R_d x weight over the far annulus's sample pattern around p in projection image k; each
// sample's weight is the surface area (mm^2) it stands for. Each sample lies at its exact lateral offset
// plus a depth difference from p, with its texel's normal (R between them: profile_rd_between; on p's
// tangent plane where the image holds no better surface). Where view k sees p (`seen`): within a texel
// of p the image cannot resolve the surface better than p's tangent plane, so the depth comes from that plane;
// farther out it is the depth of the texel the sample lands in, moved from the texel centre to the
// sample along the tangent plane and compared with the image's own surface at p (the plane where that
// texel is empty but the prefiltered flux is not). Texel quantization, facets and a proxy mesh's
// offset from the true surface then add no false depth, and kernels narrower than a texel integrate
// to the right energy. Where view k does not see p (a face across an edge), a sample's depth is its
// texel's, and empty texels add nothing; with light views (transmission: light through the object), a
// sample's flux and depth are its whole footprint's (the owned images' weighted mean depth),
// so light reaching p from the edge of a footprint is not lost with the texel at its centre. Samples
// within a texel of p read the projection image's own texel, times `share`, the view's share of p's
// surface (ownership.comp's weight at p).
vec3 scattered_light(int k, vec3 p, vec3 n, ivec2 px, bool seen, float share)
{
    vec2 center = texel_coord(k, p);
    float mm_per_texel = frame.params.y * frame.view_dv[k].w;
    float rotation = pixel_rotation(px);
    mat2 rotate = mat2(cos(rotation), sin(rotation), -sin(rotation), cos(rotation));
    float depth = view_depth(k, p);
    vec2 slope = seen ? tangent_slope(k, n) : vec2(0.0);
    ivec2 home = ivec2(floor(center));
    float home_depth = inside(k, home) ? texelFetch(projection_images, ivec3(home, k), 0).a : -1.0;
    if (seen && home_depth >= 0.0)
        depth = home_depth + dot(center - (vec2(home) + 0.5), slope);
    float texels_per_mm2 = 1.0 / (mm_per_texel * mm_per_texel);
    bool through = TRANSMISSION && (seen || k >= CAMERA_VIEWS);
    vec3 sum = vec3(0.0);
    // The near disc is p's own light (the compose pass) only in the views that see p; across an edge
    // it holds another face, taken as a plane lit like the texel p lands on, at that texel's depth.
    if (!seen && home_depth >= 0.0)
        sum += prefiltered_flux(k, center, 1.0) *
               rd_disc_between(frame.rd_total.w, entry_offset(k, vec2(0.0), (home_depth - depth) * frame.params.y), n,
                               texel_normal(k, home, -frame.view_dir[k].xyz));
    for (int c = 0; c < (SHARED_SAMPLES ? 1 : 3); c++) {
        for (int j = 0; j < SAMPLES; j++) {
            vec4 s = frame.samples[c * MAX_SAMPLES + j];
            vec2 offset = (rotate * s.zw) * (s.x / mm_per_texel), at = center + offset;
            ivec2 t = ivec2(floor(at));
            if (!inside(k, t))
                continue;
            // A footprint no wider than the sample's distance from p: the inner samples' areas are
            // as wide as their rings, and a footprint that size reached back to p's own light
            // (side-lit sphere 2.5% bright, 1.2% with this bound).
            float footprint = min(s.y, s.x * s.x) * texels_per_mm2;
            vec3 flux, n_in;
            float step;
            if (TRANSMISSION && !seen) {
                if (!footprint_light(k, at, footprint, depth, flux, step))
                    continue;
                n_in = texel_normal(k, t, -frame.view_dir[k].xyz);
            } else {
                vec4 texel = texelFetch(projection_images, ivec3(t, k), 0);
                if (!seen && texel.a < 0.0)
                    continue;
                flux = s.x < mm_per_texel ? texel.rgb * share : prefiltered_flux(k, at, footprint);
                bool on_plane = seen && (s.x < mm_per_texel || texel.a < 0.0);
                step = on_plane ? dot(at - center, slope) : texel.a + dot(at - (vec2(t) + 0.5), slope) - depth;
                n_in = on_plane ? n : texel_normal(k, t, seen ? n : -frame.view_dir[k].xyz);
            }
            vec3 d = entry_offset(k, offset, step * frame.params.y);
            float weight = through ? 1.0 / (1.0 / s.y + 1.0 / frame.through[0].y) : s.y;
            if (SHARED_SAMPLES)
                sum += flux * profile_rd_between3(d, n, n_in) * weight;
            else
                sum[c] += flux[c] * profile_rd_between(c, d, n, n_in) * weight;
        }
    }
    if (through)
        sum += light_through(k, center, depth, rotate, mm_per_texel, n);
    return sum;
}

float refracted_cosine(float cos_out)
{
    float eta = frame.params.x;
    return sqrt(max(1.0 - (1.0 - cos_out * cos_out) / (eta * eta), 0.0));
}

// Irradiance entering at p from light l, unshadowed: colour x falloff x cos x Ft; w: the cosine.
vec4 light_at(int l, vec3 p, vec3 n, out vec3 to_light)
{
    vec4 lv = frame.light_vec[l];
    vec3 d = lv.w > 0.5 ? lv.xyz - p : -lv.xyz;
    float falloff = lv.w > 0.5 ? 1.0 / max(dot(d, d), 1e-30) : 1.0;
    to_light = normalize(d);
    float c = dot(n, to_light);
    return vec4(frame.light_rgb[l].rgb * falloff * c * fresnel_transmittance(frame.params.x, c), c);
}

float henyey_greenstein(float g, float mu)
{
    return (1.0 - g * g) / (4.0 * PI * pow(max(1.0 + g * g - 2.0 * g * mu, 1e-6), 1.5));
}

// Jensen et al. 2001's single-scattering term with the surface taken as flat at p: light refracted
// in along one straight path, scattered once (Henyey-Greenstein), attenuated by sigma_t both ways:
// L = albedo p(g) Ft_in Ft_out E cos_i / (cos'_i + cos'_o). Shadowed lights are scaled by p's own
// texel in the projection image over their unshadowed irradiance, which is exact for one light.
vec3 single_scattered(vec3 p, vec3 n, vec3 to_eye, vec3 lit)
{
    float cos_o = dot(n, to_eye);
    if (cos_o <= 0.0)
        return vec3(0.0);
    float eta = frame.params.x, g = frame.single_albedo.w;
    float cos_o_in = refracted_cosine(cos_o);
    vec3 out_dir = -refract(-to_eye, n, 1.0 / eta);   // travel direction inside, towards the exit
    vec3 free_sum = vec3(0.0), shadowed_sum = vec3(0.0), free_e = vec3(0.0), shadowed_e = vec3(0.0);
    for (int l = 0; l < int(frame.params.w); l++) {
        vec3 to_light;
        vec4 e = light_at(l, p, n, to_light);
        if (e.w <= 0.0)
            continue;
        float hg = henyey_greenstein(g, dot(refract(-to_light, n, 1.0 / eta), out_dir));
        vec3 term = e.rgb * hg / (refracted_cosine(e.w) + cos_o_in);
        bool has_shadow_map = frame.light_rgb[l].w >= 0.0;
        free_sum += has_shadow_map ? vec3(0.0) : term;
        free_e += has_shadow_map ? vec3(0.0) : e.rgb;
        shadowed_sum += has_shadow_map ? term : vec3(0.0);
        shadowed_e += has_shadow_map ? e.rgb : vec3(0.0);
    }
    vec3 visible = clamp((lit - free_e) / max(shadowed_e, vec3(1e-30)), 0.0, 1.0);
    return (free_sum + visible * shadowed_sum) * frame.single_albedo.rgb * fresnel_transmittance(eta, cos_o);
}

// View k's texels around image position `at`, bilinearly weighted over those that hold a surface
// (alpha: depth; -1 where none holds one): a ray stepping across the image reads no texel steps (its
// path inside is e^(-sigma_t) sensitive: a texel's depth step speckled a skin1 ear).
vec4 covered_bilinear(int k, vec2 at)
{
    vec2 grid = at - 0.5;
    ivec2 base = ivec2(floor(grid));
    vec2 f = grid - vec2(base);
    vec4 sum = vec4(0.0);
    float weights = 0.0;
    for (int i = 0; i < 4; i++) {
        ivec2 q = base + ivec2(i & 1, i >> 1);
        vec4 texel = inside(k, q) ? texelFetch(projection_images, ivec3(q, k), 0) : vec4(-1.0);
        float w = ((i & 1) != 0 ? f.x : 1.0 - f.x) * ((i >> 1) != 0 ? f.y : 1.0 - f.y);
        if (texel.a >= 0.0) {
            sum += w * texel;
            weights += w;
        }
    }
    return weights > 0.0 ? sum / weights : vec4(-1.0);
}

// The light that light view k shows entering the object, scattered once at x (at t scene units along
// p's refracted view ray `into`) towards p, per unit length and sigma_s, per channel: the view's
// texels where x lands hold the light entering there and, with their depth and normal, its path
// inside (Jensen's refraction correction). 0 where x lies outside, in front of the surface the light
// meets.
vec3 scattered_once(int k, vec3 p, vec3 into, float t)
{
    vec3 x = p + into * t;
    vec2 at = texel_coord(k, x);
    ivec2 q = ivec2(floor(at));
    vec4 texel = covered_bilinear(k, at);
    float inside_path = view_depth(k, x) - texel.a;
    vec3 ni = inside(k, q) ? texelFetch(projection_normals, ivec3(q, k), 0).xyz : vec3(0.0);
    if (texel.a < 0.0 || inside_path <= 0.0 || dot(ni, ni) == 0.0)
        return vec3(0.0);   // (the nearest texel can be empty where a neighbour is not)
    ni = normalize(ni);
    float eta = frame.params.x, cos_i = view_score(k, ni), cos_in = max(refracted_cosine(cos_i), 1e-6);
    if (cos_i <= 0.0)
        return vec3(0.0);
    // texel: entering light per unit image area (projection.frag); inside, per unit area across the
    // refracted beam, it is that x cos / cos_in, over the longer refracted path.
    vec3 fluence = texel.rgb * (max(cos_i, MIN_AREA_COS) / cos_in);
    float path_mm = (inside_path * cos_i / cos_in + t) * frame.params.y;
    float hg = henyey_greenstein(frame.single_albedo.w, dot(refract(frame.view_dir[k].xyz, ni, 1.0 / eta), -into));
    return hg * fluence * exp(-frame.single_sigma_t.rgb * path_mm);
}

// Single scattering of the light that enters where light view k sees the surface and crosses the
// object to p's refracted view ray, as the reference finds it by ray casting. Two sets of distances
// along the ray, weighed by the balance heuristic: stratified over e^(-sigma_t t) per channel (light
// fading along the ray, as where it enters beside p), and spread evenly up to where the ray meets the
// surface the light enters (estimated at p's texel; light through a thin part travels about the same
// path in and out wherever it scatters: alone, the first set was 37% dark on a 3 mm skin1 slab in
// blue). The texels hold every light's entering light, taken as arriving along this view. Where the
// light view sees p itself, its light enters at p (single_scattered).
vec3 single_through(int k, vec3 p, vec3 n, vec3 to_eye)
{
    if (visible_in(k, p, n) && view_score(k, n) > 0.0)
        return vec3(0.0);
    float extent = 2.0 * frame.view_du[k].w * frame.view_dv[k].w, mm = frame.params.y;
    vec3 into = refract(-to_eye, n, 1.0 / frame.params.x), sigma_t = frame.single_sigma_t.rgb;
    float entry = covered_bilinear(k, texel_coord(k, p)).a;
    float towards = -dot(into, frame.view_dir[k].xyz), thickness = view_depth(k, p) - entry;
    float span = entry >= 0.0 && thickness > 0.0 && towards > 0.1 ? min(thickness / towards, extent) : extent;
    float even_density = float(SINGLE_EVEN_SAMPLES) / (span * mm);   // per mm
    vec3 sum = vec3(0.0);
    for (int c = 0; c < 3; c++)
        for (int j = 0; j < SINGLE_FADING_SAMPLES; j++) {
            float t_mm = -log(1.0 - (float(j) + 0.5) / float(SINGLE_FADING_SAMPLES)) / sigma_t[c];
            if (!(t_mm < extent * mm))
                break;   // beyond the object (and sigma_t 0)
            float fading_density = float(SINGLE_FADING_SAMPLES) * sigma_t[c] * exp(-sigma_t[c] * t_mm);
            sum[c] += scattered_once(k, p, into, t_mm / mm)[c] / (fading_density + (t_mm < span * mm ? even_density : 0.0));
        }
    for (int j = 0; j < SINGLE_EVEN_SAMPLES; j++) {
        float t_mm = (float(j) + 0.5) / float(SINGLE_EVEN_SAMPLES) * span * mm;
        vec3 fading_density = float(SINGLE_FADING_SAMPLES) * sigma_t * exp(-sigma_t * t_mm);
        sum += scattered_once(k, p, into, t_mm / mm) / (fading_density + even_density);
    }
    return sum * frame.single_albedo.rgb * sigma_t * fresnel_transmittance(frame.params.x, dot(n, to_eye));
}

// How far x lies behind the surface view k sees at x's place (scene units along the view's direction; -1 where
// the view holds no surface there), and that surface's texel.
float behind_seen(int k, vec3 x, out vec4 texel)
{
    texel = covered_bilinear(k, texel_coord(k, x));
    return texel.a < 0.0 ? -1.0 : view_depth(k, x) - texel.a;
}

// One step of the search for where a ray leaves (unscattered_through): the point t along it is tested, and
// becomes the bracket's near end (still behind what view k sees; its texel kept) or its far end.
void exit_bracket(int k, vec3 p, vec3 into, float t, inout float lo, inout float behind_lo, inout vec4 texel_lo,
                  inout float hi, inout float behind_hi, inout bool hi_seen)
{
    vec4 texel;
    float b = behind_seen(k, p + into * t, texel);
    if (b > 0.0)
        lo = t, behind_lo = b, texel_lo = texel;
    else
        hi = t, behind_hi = b, hi_seen = texel.a >= 0.0;
}

// Light from light view k that crosses the medium unscattered along p's refracted view ray and meets the
// surface the view sees, where it leaves as method path's walks leave (the adjoint of entering there and
// crossing): through the Fresnel transmittance from inside, spread by the diffuse exit's weight. It is what
// makes a thin part of an absorbing medium glow from behind (a ketchup bunny's ears).
vec3 unscattered_through(int k, vec3 p, vec3 n, vec3 to_eye)
{
    if (visible_in(k, p, n) && view_score(k, n) > 0.0)
        return vec3(0.0);
    vec3 into = refract(-to_eye, n, 1.0 / frame.params.x);
    float towards = -dot(into, frame.view_dir[k].xyz);
    vec4 texel;
    float behind = behind_seen(k, p, texel);
    if (towards <= 0.1 || behind <= 0.0)
        return vec3(0.0);
    // The ray leaves where it stops being behind what the view sees: marched up to twice where a surface
    // facing the ray squarely would be, then the step that crosses halved. One step from the flat estimate
    // left a thin part the light meets at a grazing angle (a bunny's far ear) in total internal reflection.
    float reach = 2.0 * behind / towards, lo = 0.0, hi = -1.0, behind_lo = behind, behind_hi = 0.0;
    bool hi_seen = false;
    for (int i = 1; i <= UNSCATTERED_STEPS && hi < 0.0; i++)
        exit_bracket(k, p, into, reach * float(i) / float(UNSCATTERED_STEPS), lo, behind_lo, texel, hi, behind_hi,
                     hi_seen);
    if (hi < 0.0)
        return vec3(0.0);
    for (int i = 0; i < UNSCATTERED_HALVINGS; i++)
        exit_bracket(k, p, into, 0.5 * (lo + hi), lo, behind_lo, texel, hi, behind_hi, hi_seen);
    // Within the last step the surface is taken as flat where the view holds it on both sides.
    float t = hi_seen ? mix(lo, hi, behind_lo / (behind_lo - behind_hi)) : 0.5 * (lo + hi);
    ivec2 q = ivec2(floor(texel_coord(k, p + into * lo)));
    vec3 ni = inside(k, q) ? texelFetch(projection_normals, ivec3(q, k), 0).xyz : vec3(0.0);
    if (dot(ni, ni) == 0.0)
        return vec3(0.0);
    ni = normalize(ni);
    float cos_i = view_score(k, ni), cos_y = dot(into, ni), k_in = 1.0 / frame.params.x;
    if (cos_i <= 0.0 || cos_y <= 0.0 || k_in * k_in - 1.0 + cos_y * cos_y <= 0.0)
        return vec3(0.0);   // total internal reflection: the ray does not leave there
    // texel x cos_i: the light entering there per unit of surface, which is what the exit connects to.
    float leave = fresnel_transmittance(k_in, cos_y) * frame.camera_eye.w;
    return texel.rgb * (cos_i * leave * fresnel_transmittance(frame.params.x, dot(n, to_eye))) *
           exp(-frame.single_sigma_t.rgb * (t * frame.params.y));
}

// The irradiance entering at p as view k saw it (its texel; 0 where the view does not see p).
vec3 own_irradiance(int k, vec3 p, vec3 n)
{
    ivec2 home = ivec2(floor(texel_coord(k, p)));
    bool seen = inside(k, home) && texelFetch(projection_images, ivec3(home, k), 0).a >= 0.0;
    return seen ? surface_irradiance(k, home, n) : vec3(0.0);
}

// R_d integrated over what the far samples leave out, the disc of radius rd_total.w in the
// projection plane of a view facing the surface by cosine c: on the surface an ellipse, tabulated
// over the tilt by frame_plan.c. The near part of the integral is the point's own irradiance times
// this. Kernels far below a texel (the diffuse limit) are all near part.
vec3 rd_near(float c)
{
    if (SAMPLES == 0)
        return frame.rd_total.rgb;
    float at = (1.0 / max(c, MIN_AREA_COS) - 1.0) / (1.0 / MIN_AREA_COS - 1.0) * float(NEAR_TABLE - 1);
    int i = min(int(at), NEAR_TABLE - 2);
    return mix(frame.near_rd[i].rgb, frame.near_rd[i + 1].rgb, at - float(i));
}

// Weight of the second view where the next best view faces the point almost as well: both are
// integrated and blended, half and half where they face it equally, so the choice of view changes
// the image smoothly. Returns 0 (and k2 -1) where no blend applies.
float second_view(vec3 p, vec3 n, int k, out int k2)
{
    k2 = -1;
    if (VIEW_COUNT == 1 || FRONT_FALLBACK)
        return 0.0;
    k2 = choose_view(p, n, k);
    return k2 < 0 ? 0.0 : 0.5 * clamp(1.0 - (view_score(k, n) - view_score(k2, n)) / VIEW_BLEND, 0.0, 1.0);
}

// The far annulus at p: gathered from every view's share of the surface (OWNED), else from the view
// the pixel chose, blended with the second where both face p almost equally.
vec3 far_light(vec3 p, vec3 n, ivec2 px)
{
    if (OWNED) {
        vec3 far = vec3(0.0);
        bool seen[MAX_VIEWS];
        float weight[MAX_VIEWS], total = 0.0;
        for (int k = 0; k < VIEW_COUNT; k++) {
            seen[k] = view_score(k, n) > 0.0 && visible_in(k, p, n);
            weight[k] = seen[k] ? facing_weight(view_score(k, n)) : 0.0;
            total += weight[k];
        }
        for (int k = 0; k < VIEW_COUNT; k++)
            far += scattered_light(k, p, n, px, seen[k], weight[k] / max(total, 1e-30));
        return far;
    }
    int k = choose_view(p, n, -1), k2;
    float w2 = second_view(p, n, k, k2);
    vec3 far = scattered_light(k, p, n, px, true, 1.0);
    if (w2 > 0.0)
        far = mix(far, scattered_light(k2, p, n, px, true, 1.0), w2);
    return far;
}

// Unit vectors in two numbers (octahedral map), to keep a far sample in two vec4.
vec2 octahedral(vec3 n)
{
    n /= abs(n.x) + abs(n.y) + abs(n.z);
    vec2 o = n.xy;
    if (n.z < 0.0)
        o = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return o;
}

vec3 from_octahedral(vec2 o)
{
    vec3 n = vec3(o, 1.0 - abs(o.x) - abs(o.y));
    float t = max(-n.z, 0.0);
    n.xy -= t * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

// Blocks across the image (frame_far_blocks() in frame_plan.c), the last row and column partial.
ivec2 far_blocks()
{
    return (push.size + FAR_BLOCK - 1) / FAR_BLOCK;
}

// One block of FAR_BLOCK^2 pixels: the far annulus integrated at its covered pixel nearest the block's
// centre. CPU drivers run a loop body as often as its slowest lane: the pixel is found first.
void far_main()
{
    ivec2 blocks = far_blocks(), bp = ivec2(gl_GlobalInvocationID.xy);
    if (bp.x >= blocks.x || bp.y >= blocks.y)
        return;
    uint idx = uint(bp.y * blocks.x + bp.x);
    ivec2 px = ivec2(-1);
    float nearest = 1e9;
    [[unroll]] for (int i = 0; i < FAR_BLOCK * FAR_BLOCK; i++) {
        ivec2 in_block = ivec2(i % FAR_BLOCK, i / FAR_BLOCK), at = FAR_BLOCK * bp + in_block;
        vec2 off = vec2(in_block) - 0.5 * float(FAR_BLOCK - 1);
        float dist = dot(off, off);
        if (at.x < push.size.x && at.y < push.size.y && dist < nearest && texelFetch(gbuffer_normal, at, 0).w != 0.0) {
            px = at;
            nearest = dist;
        }
    }
    if (px.x < 0) {
        far_samples[idx] = FarSample(vec4(0.0), vec4(0.0, 0.0, 0.0, -1.0));
        return;
    }
    vec3 p = texelFetch(gbuffer_position, px, 0).xyz;
    vec4 normal_coverage = texelFetch(gbuffer_normal, px, 0);
    vec3 n = normalize(normal_coverage.xyz);
    exit_curvature_mm = gbuffer_curvature(normal_coverage);
    far_samples[idx] = FarSample(vec4(far_light(p, n, bp), uintBitsToFloat(packSnorm2x16(octahedral(n)))),
                                 vec4(p, float(px.x + 4096 * px.y)));
}

vec3 sample_normal(FarSample f)
{
    return from_octahedral(unpackSnorm2x16(floatBitsToUint(f.diffuse.w)));
}

// How far a far sample stands for the surface at p (normal n): it must lie on p's tangent plane and
// share p's normal, so light does not leak across depth steps and creases. The plane's tolerance is
// the near disc's radius, or half the distance to the sample where that is larger (neighbouring
// blocks, and blocks of one pixel, which have no disc).
float same_surface(vec3 p, vec3 n, FarSample f)
{
    vec3 d = f.position.xyz - p;
    float tolerance = max(frame.rd_total.w / frame.params.y, 0.5 * length(d));
    float plane = dot(n, d) / max(tolerance, 1e-30);
    float facing = max(dot(n, sample_normal(f)), 0.0);
    facing *= facing;
    return max(1.0 - plane * plane, 0.0) * facing * facing;
}

// The far part of each block averaged with its eight neighbours' where they lie on the same surface.
// The nine blocks of a window hold the nine turns of the sample pattern (pixel_rotation), so equal
// weights sample every ring evenly (1-2-1 weights drew a grid three blocks wide); the far part itself
// changes little over a block or two (no light nearer than the near disc), so the average keeps the light.
void far_filter_main()
{
    ivec2 blocks = far_blocks(), bp = ivec2(gl_GlobalInvocationID.xy);
    if (bp.x >= blocks.x || bp.y >= blocks.y)
        return;
    uint idx = uint(bp.y * blocks.x + bp.x);
    FarSample c = far_samples[idx];
    if (c.position.w < 0.0) {
        far_filtered[idx] = c;
        return;
    }
    vec3 n = sample_normal(c);
    vec3 sum = vec3(0.0);
    float weights = 0.0;
    [[unroll]] for (int i = 0; i < 9; i++) {
        ivec2 off = ivec2(i % 3, i / 3) - 1, q = bp + off;
        if (q.x < 0 || q.y < 0 || q.x >= blocks.x || q.y >= blocks.y)
            continue;
        FarSample f = far_samples[q.y * blocks.x + q.x];
        float w = f.position.w >= 0.0 ? same_surface(c.position.xyz, n, f) : 0.0;
        sum += f.diffuse.rgb * w;
        weights += w;
    }
    far_filtered[idx] = FarSample(vec4(sum / weights, c.diffuse.w), c.position);
}

// The far part at a pixel: the four filtered block samples around it, weighted by a tent of one
// block's radius over the pixels they were integrated at and by how well they share p's surface.
// Where few samples share p's surface (edges, creases, thin parts), it leans on `local`, the far part
// of a plane lit as p is.
vec3 upsampled_far(ivec2 px, vec3 p, vec3 n, vec3 local)
{
    ivec2 blocks = far_blocks();
    ivec2 first = ivec2(floor((vec2(px) + 0.5) / float(FAR_BLOCK) - 0.5));
    vec3 sum = vec3(0.0);
    float weights = 0.0, tents = 0.0;
    [[unroll]] for (int i = 0; i < 4; i++) {
        ivec2 q = clamp(first + ivec2(i & 1, i >> 1), ivec2(0), blocks - 1);
        FarSample f = far_filtered[q.y * blocks.x + q.x];
        int at = int(f.position.w);
        vec2 d = max(1.0 - abs(vec2(at & 4095, at >> 12) - vec2(px)) / float(FAR_BLOCK), 0.0);
        float tent = at >= 0 ? d.x * d.y : 0.0;
        float w = tent * same_surface(p, n, f);
        sum += f.diffuse.rgb * w;
        weights += w;
        tents += tent;
    }
    float trust = smoothstep(0.0, 0.5, weights / max(tents, 1e-6));
    return mix(local, sum / max(weights, 1e-12), trust);
}

// The share of the near disc that lies on p's own surface in view k, from four taps at 3/4 of its
// radius: at a sharp edge or a silhouette part of the disc hangs over the edge, where p's light does
// not spread (the lit face of a cube lit on one face was 1.2-1.3x bright along its edges; cube rel L2
// 0.057 -> 0.043 at 256^2).
float disc_coverage(int k, vec3 p, vec3 n)
{
    vec2 center = texel_coord(k, p);
    float radius = 0.75 * frame.rd_total.w / (frame.params.y * frame.view_dv[k].w);   // texels
    vec2 slope = tangent_slope(k, n);
    float depth = view_depth(k, p), tolerance = depth_tolerance(k, view_score(k, n));
    float covered = 0.0;
    [[unroll]] for (int i = 0; i < 4; i++) {
        vec2 offset = radius * 0.70710678 * vec2((i & 1) != 0 ? 1.0 : -1.0, (i & 2) != 0 ? 1.0 : -1.0);
        ivec2 t = ivec2(floor(center + offset));
        float stored = inside(k, t) ? texelFetch(projection_images, ivec3(t, k), 0).a : -1.0;
        covered += stored >= 0.0 && abs(stored - depth - dot(offset, slope)) <= tolerance ? 0.25 : 0.0;
    }
    return covered;
}

void compose_main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (px.x >= push.size.x || px.y >= push.size.y)
        return;
    uint idx = uint(px.y * push.size.x + px.x);
    vec4 normal_coverage = texelFetch(gbuffer_normal, px, 0);
    if (normal_coverage.w == 0.0) {
        out_color[idx] = vec4(0.0);
        out_normal_view[idx] = vec4(0.0, 0.0, 0.0, -1.0);
        out_depth[idx] = 0.0;
        return;
    }
    vec4 position_depth = texelFetch(gbuffer_position, px, 0);
    vec3 p = position_depth.xyz;
    vec3 n = normalize(normal_coverage.xyz);
    exit_curvature_mm = gbuffer_curvature(normal_coverage);
    int k = choose_view(p, n, -1), k2;
    float w2 = second_view(p, n, k, k2);
    vec3 irradiance = own_irradiance(k, p, n), near = rd_near(view_score(k, n));
    if (w2 > 0.0) {
        irradiance = mix(irradiance, own_irradiance(k2, p, n), w2);
        near = mix(near, rd_near(view_score(k2, n)), w2);
    }
    vec3 diffuse = irradiance * near * (FAR_BLOCK > 1 ? disc_coverage(k, p, n) : 1.0);
    if (SAMPLES > 0)
        diffuse += upsampled_far(px, p, n, irradiance * (frame.rd_total.rgb - near));
    vec3 to_eye = normalize(frame.camera_eye.xyz - p);
    vec3 radiance = diffuse * (fresnel_transmittance(frame.params.x, dot(n, to_eye)) * frame.camera_eye.w);
    if (SINGLE_SCATTERING)
        radiance += single_scattered(p, n, to_eye, irradiance);
    if (SINGLE_SCATTERING && TRANSMISSION)
        for (int k = CAMERA_VIEWS; k < VIEW_COUNT; k++)
            radiance += single_through(k, p, n, to_eye) + unscattered_through(k, p, n, to_eye);
    out_color[idx] = vec4(radiance, 1.0);
    out_normal_view[idx] = vec4(n, float(k));
    out_depth[idx] = position_depth.w;
}

void main()
{
    if (PASS_FAR)
        far_main();
    else if (PASS_FAR_FILTER)
        far_filter_main();
    else
        compose_main();
}
