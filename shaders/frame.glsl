// frame.glsl - the per-frame uniform block shared by the projection and scatter shaders.
// Mirrors struct frame_uniforms in renderer/frame_uniforms.h; std140, all world positions mesh-centred.
#define MAX_VIEWS 7             // FRAME_MAX_VIEWS
#define CAMERA_VIEWS 5          // FRAME_CAMERA_VIEWS: front and four sides; then views along lights
#define MAX_LIGHTS 4
#define MAX_SAMPLES 64
#define NEAR_TABLE 17          // FRAME_NEAR_TABLE
#define THROUGH_SAMPLES 16     // FRAME_THROUGH_SAMPLES
#define SPHERE_TABLE_T 24      // sphere_diffusion.h: sigma_tr a, log-spaced over SPHERE_T_MIN..SPHERE_T_MAX
#define SPHERE_TABLE_G 24      // the angle between the normals, 0..pi
#define SPHERE_T_MIN 0.02
#define SPHERE_T_MAX 16.0
#define PI 3.14159265358979
// Texel footprint on the surface grows as 1/cos to the view; past this cosine the estimate is
// dominated by noise from grazing texels that other views cover better. FRAME_MIN_AREA_COS.
const float MIN_AREA_COS = 0.1;

layout(std140, set = 0, binding = 0) uniform Frame {
    mat4 view_clip[MAX_VIEWS];     // world -> clip of projection image k (orthographic)
    vec4 view_origin[MAX_VIEWS];   // world position of texel corner (0,0) on the depth-0 plane; w: the view's
                                   // owned image is its side >> w
    vec4 view_du[MAX_VIEWS];       // xyz: world step of one texel along x; w: image side (texels)
    vec4 view_dv[MAX_VIEWS];       // xyz: world step of one texel along y; w: texel size (scene units)
    vec4 view_dir[MAX_VIEWS];      // direction view k looks along; depth = dot(p - origin, dir)
    vec4 light_vec[MAX_LIGHTS];    // xyz: travel direction or position; w: 0 directional, 1 point
    vec4 light_rgb[MAX_LIGHTS];    // rgb: colour * intensity; w: shadow map layer
    mat4 light_clip[MAX_LIGHTS];   // world -> shadow map clip
    vec4 light_depth[MAX_LIGHTS];  // x near, y far, z 1 = perspective, w bias (scene units)
    vec4 params;                   // x eta, y mm per scene unit, z depth tolerance (scene units), w lights
    vec4 camera_eye;               // xyz camera position; w the diffuse exit's F_t(cos) weight, 1 / (pi F_t,diffuse)
    // The diffusion profile (renderer/core/profile.h), per channel: two sources k at depth z (mm) with
    // rate sigma (mm^-1), fluence coefficient a and flux coefficient b:
    // R(r) = sum_k e^(-sigma_k D_k) (a_k / D_k + b_k (1 + sigma_k D_k) / D_k^3), D_k = sqrt(r^2 + z_k^2).
    vec4 profile_z[2];
    vec4 profile_sigma[2];
    vec4 profile_a[2];
    vec4 profile_b[2];
    vec4 rd_total;                 // xyz: R_d integrated out to the truncation radius; w: near disc radius (mm)
    // xyz: R_d integrated over the near disc's preimage on a surface tilted to the view by cosine c,
    // at 1 / c = 1 + (i / (NEAR_TABLE - 1)) (1 / MIN_AREA_COS - 1).
    vec4 near_rd[NEAR_TABLE];
    vec4 single_albedo;            // xyz: sigma_s / sigma_t (single scattering); w: g
    vec4 single_sigma_t;           // xyz: sigma_t = sigma_s + sigma_a (mm^-1)
    vec4 owned;                    // x: the owned images' layers are the front projection image's side >> x;
                                   // y: views drawn
    // The far annulus (outside the near disc), per channel (c * MAX_SAMPLES + j) or shared (first
    // n): x radius (mm), y weight (1 / (n pdf)), zw unit direction on the projection plane.
    vec4 samples[3 * MAX_SAMPLES];
    // What the far samples' density is, to combine them with `through` (multiple importance sampling):
    // samples x density = R_d(r) / through_pdf[c] per channel, or, shared, the sum over the channels
    // of R_d(r) / (3 rd_total[c]) over through_pdf.w.
    vec4 through_pdf;
    // Samples spread evenly over the annulus's area (x radius, y area each, zw direction), which the
    // light views add where they do not see the point: light through the object arrives from where
    // the surface profile's samples are sparse, where the far side comes closest (a sphere's rim).
    vec4 through[THROUGH_SAMPLES];
    // Diffusion in a sphere over R between points, channel c's factor at t index i and angle index j:
    // element (c * SPHERE_TABLE_T + i) * SPHERE_TABLE_G + j, four to a row (1 where the profile has no sources).
    vec4 sphere_factor[3 * SPHERE_TABLE_T * SPHERE_TABLE_G / 4];
} frame;

// Unpolarized Fresnel transmittance entering a medium of relative index eta >= 1.
float fresnel_transmittance(float eta, float cos_i)
{
    float c = clamp(cos_i, 0.0, 1.0);
    if (c <= 0.0)
        return 0.0;
    float g = sqrt(eta * eta - 1.0 + c * c);
    float a = (g - c) / (g + c);
    float b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return 1.0 - min(0.5 * a * a * (1.0 + b * b), 1.0);
}
