/* lucent.h - public interface of liblucent, the translucent-object renderer.
 * Plain structs in, images out; every fallible call returns a lucent_status and fills a lucent_error. */
#ifndef LUCENT_H
#define LUCENT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lucent_status {
    LUCENT_OK = 0,
    LUCENT_E_INVALID,   /* the request or scene is wrong: error.field names what */
    LUCENT_E_MESH,      /* a mesh could not be read or has no usable triangles */
    LUCENT_E_LIMIT,     /* a value is outside a documented limit */
    LUCENT_E_IO,        /* a file could not be read or written */
    LUCENT_E_NOMEM,
    LUCENT_E_GPU,       /* the GPU side (Vulkan, OpenGL or EGL) failed; the message says which call */
    LUCENT_E_INTERNAL,
    LUCENT_E_CANCELLED, /* lucent_render_cancel() stopped the render */
    LUCENT_E_DEVICE_LOST, /* the GPU device was lost (driver reset, hang): this renderer refuses every
                           * frame from now on; destroy it and create another (which gets a new device) */
    LUCENT_E_NOSPACE      /* a file system is full (ENOSPC, EDQUOT); what was there is intact */
} lucent_status;

/* What went wrong, in words a user can act on. `field` is a JSON path such as
 * "material.sigma_a[1]" when one input is to blame, else empty. */
typedef struct lucent_error {
    lucent_status status;
    char field[96];
    char message[320];
} lucent_error;

/* Fills err (when not NULL) and returns status; printf-style message. */
lucent_status lucent_fail(lucent_error *err, lucent_status status, const char *field,
                          const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
const char *lucent_status_name(lucent_status s);
/* The status of a failed file operation: LUCENT_E_NOSPACE for a full file system, else LUCENT_E_IO. */
lucent_status lucent_io_status(int errnum);

/* ---- Limits (documented in README; enforced by the scene parser) ---- */
#define LUCENT_MAX_LIGHTS 4
#define LUCENT_MAX_IMAGE_SIDE 4096
#define LUCENT_MIN_PROJECTION_SIZE 16
#define LUCENT_MAX_PROJECTION_SIZE 2048
#define LUCENT_MAX_SAMPLES 64
#define LUCENT_MAX_TRIANGLES 4000000u
#define LUCENT_MAX_BUILTIN_TRIANGLES 2000000u
#define LUCENT_MIN_BUILTIN_TRIANGLES 1000u  /* below this no tessellation lands within 2% of a request */
#define LUCENT_MIN_ETA 1.0
#define LUCENT_MAX_ETA 3.0
#define LUCENT_MAX_SIGMA 1.0e5       /* mm^-1 */
#define LUCENT_MIN_SIGMA_S_PRIME 1.0e-6
#define LUCENT_MIN_SCALE_MM 1.0e-6
#define LUCENT_MAX_SCALE_MM 1.0e9
#define LUCENT_MAX_INTENSITY 1.0e12
#define LUCENT_MAX_EXPOSURE 64.0     /* stops, either way */
#define LUCENT_MAX_REFERENCE_POINTS 4000000u
#define LUCENT_MAX_PATH_SAMPLES 65536u     /* method "path": walks per pixel and channel */
#define LUCENT_MAX_PATH_TIME_S 86400.0
#define LUCENT_MAX_G 0.95             /* |g|: sigma_s = sigma_s' / (1 - g) grows without bound at 1 */
#define LUCENT_MAX_COORD 1.0e15       /* |x| of positions and directions: squared lengths stay finite */
#define LUCENT_MAX_COLOR 1.0e6
#define LUCENT_MIN_FOV_DEG 1.0        /* exclusive: tan(fov / 2) degenerates at 0 and 180 */
#define LUCENT_MAX_FOV_DEG 170.0

/* ---- Scene ---- */
/* five, single: the image-space method (GPU); reference: the model without image-space shortcuts,
 * on the CPU in double precision (the ground truth the others are scored against); auto: the
 * image-space method with views, samples, sampling scheme and projection size chosen from the
 * scene (the choices are reported in lucent_stats.modelled); path: light's transport in the medium
 * itself by Monte Carlo random walks on the CPU (no diffusion approximation; noisy, slow). */
typedef enum lucent_method {
    LUCENT_METHOD_FIVE = 0, LUCENT_METHOD_SINGLE, LUCENT_METHOD_REFERENCE, LUCENT_METHOD_AUTO, LUCENT_METHOD_PATH
} lucent_method;
/* Method "path"'s surface (renderer/reference/path.c): fresnel, a smooth dielectric of index eta with
 * internal reflection; cycles, Blender Cycles' random walk (diffuse entry and exit, no Fresnel). */
typedef enum lucent_path_boundary { LUCENT_PATH_FRESNEL = 0, LUCENT_PATH_CYCLES } lucent_path_boundary;
/* Method "path"'s pixel filter: point, every walk from the pixel centre's ray (as the other methods see
 * it); box, each pass through a uniform random point of the pixel (an anti-aliased image whose coverage is
 * the pixel's share hit, as a renderer with a one-pixel box filter, Cycles' included, makes it). */
typedef enum lucent_path_filter { LUCENT_PATH_FILTER_POINT = 0, LUCENT_PATH_FILTER_BOX } lucent_path_filter;
/* Where a pixel's point hidden in its best-facing view is integrated: next_best tries the other
 * facing views in order of n.v, then the front; front is the paper's choice. */
typedef enum lucent_fallback { LUCENT_FALLBACK_NEXT_BEST = 0, LUCENT_FALLBACK_FRONT } lucent_fallback;
typedef enum lucent_format { LUCENT_FORMAT_PNG = 0, LUCENT_FORMAT_EXR } lucent_format;
/* shared: every fetched texel feeds all three channels (multiple importance sampling over the
 * three channels' profiles), `samples` fetches a pixel; per_channel: the paper's scheme, each
 * channel samples its own profile, 3 x `samples` fetches. */
typedef enum lucent_sampling { LUCENT_SAMPLING_SHARED = 0, LUCENT_SAMPLING_PER_CHANNEL } lucent_sampling;
typedef enum lucent_light_type { LUCENT_LIGHT_DIRECTIONAL = 0, LUCENT_LIGHT_POINT } lucent_light_type;
/* STORED: a mesh uploaded to the daemon's store, named by the sha256 of its bytes; the daemon
 * resolves it to a file before rendering (the library never maps ids to paths itself). */
typedef enum lucent_mesh_source { LUCENT_MESH_BUILTIN = 0, LUCENT_MESH_FILE, LUCENT_MESH_STORED } lucent_mesh_source;
#define LUCENT_MESH_ID_LEN 64

typedef struct lucent_mesh_ref {
    lucent_mesh_source source;
    char builtin[32];      /* "sphere", "torus", "protrusion" */
    uint32_t triangles;    /* builtin only; 0 = the mesh's default density */
    char file[1024];       /* LUCENT_MESH_FILE: path on the local disk */
    char id[LUCENT_MESH_ID_LEN + 1];  /* LUCENT_MESH_STORED: lowercase hex sha256 */
} lucent_mesh_ref;

/* The diffusion profile R(r) the image-space methods and the reference integrate (renderer/core/profile.h):
 * dipole, Jensen et al. 2001's (the paper's); better_dipole, d'Eon 2012's (Grosjean's diffusion
 * coefficient, Fresnel-moment boundary, exitance from fluence and flux); burley, Christensen and Burley
 * 2015's normalized diffusion (two exponentials fitted to Monte Carlo, at photon beam diffusion's total
 * albedo); asymptotic_dipole, the dipole decaying at the transport equation's own rate (asymptotic
 * diffusion) with the dipole's total reflectance. DEFAULT (not given): the dipole, except that method
 * "auto" chooses. Method "path" simulates the medium itself and uses none. */
typedef enum lucent_profile {
    LUCENT_PROFILE_DIPOLE = 0, LUCENT_PROFILE_BETTER_DIPOLE, LUCENT_PROFILE_BURLEY, LUCENT_PROFILE_ASYMPTOTIC_DIPOLE,
    LUCENT_PROFILE_DEFAULT
} lucent_profile;

/* Coefficients in mm^-1 per RGB channel (Jensen et al. 2001). */
typedef struct lucent_material {
    char preset[32];       /* "" when given as coefficients */
    double sigma_a[3];
    double sigma_s_prime[3];
    double eta;
    double g;              /* Henyey-Greenstein mean cosine, for single scattering only:
                            * sigma_s = sigma_s' / (1 - g) */
    lucent_profile profile;
} lucent_material;

typedef struct lucent_light {
    lucent_light_type type;
    double direction[3];   /* directional: the way the light travels (normalized by the parser) */
    double position[3];    /* point: scene units */
    double color[3];       /* linear RGB */
    double intensity;      /* directional: irradiance on a surface facing it;
                            * point: irradiance at one scene unit, falling off as 1/d^2 */
} lucent_light;

typedef struct lucent_camera {
    int given;             /* 1: position and target; 0: automatic framing along direction */
    double position[3], target[3], up[3];
    double direction[3];   /* the way an automatically framed camera looks (unit); default a three-quarter view */
    double fov_deg;        /* vertical */
} lucent_camera;

/* A setting left to method "auto". */
#define LUCENT_CHOSEN (-1)

typedef struct lucent_scene {
    lucent_mesh_ref mesh;
    double scale_mm;       /* millimetres per scene unit; 0 = bounding-sphere diameter becomes 50 mm */
    lucent_material material;
    lucent_light lights[LUCENT_MAX_LIGHTS];
    int light_count;
    lucent_camera camera;
    int width, height;
    lucent_method method;
    int samples;           /* per channel */
    lucent_sampling sampling;
    lucent_fallback fallback;
    int single_scattering;  /* 1: add Jensen 2001's single-scattering term; 0: not; LUCENT_CHOSEN: method
                             * "auto" chooses (a scene document for "auto" without the key) */
    int projection_size;   /* side of the front projection image, texels */
    int side_projection_size;  /* side of the four side images; 0 = projection_size / 2 */
    double background[4];  /* linear RGBA composited under the object on output */
    double exposure;       /* stops: output = radiance * 2^exposure */
    lucent_format format;
    /* method "reference" only */
    uint32_t reference_points;     /* irradiance points over the surface; 0 = automatic */
    double reference_threshold;    /* hierarchical sum's node size / distance; 0 = brute force,
                                    * < 0 = default */
    /* method "path" only */
    uint32_t path_samples;         /* walks per pixel and channel */
    double path_time_s;            /* 0: none; else no further pass starts after this long */
    lucent_path_boundary path_boundary;
    lucent_path_filter path_filter;
    uint32_t path_seed;
} lucent_scene;

/* Fills every field with its documented default. */
void lucent_scene_defaults(lucent_scene *scene);

/* Parses a scene document (the HTTP request body uses the same schema).
 * allow_files = 0 rejects {"mesh": {"file": ...}} (the server passes 0). */
lucent_status lucent_scene_parse(const char *json, size_t len, int allow_files,
                                 lucent_scene *out, lucent_error *err);

/* Looks up one of Jensen et al. 2001's measured materials by name (case-insensitive): g 0, profile DEFAULT. */
lucent_status lucent_material_preset(const char *name, lucent_material *out);
/* Name of preset i (0-based) or NULL past the end. */
const char *lucent_material_preset_name(int i);
/* material.profile's name for p, as the scene document spells it ("dipole", "better_dipole", "burley",
 * "asymptotic_dipole");
 * DEFAULT is the dipole. */
const char *lucent_profile_name(lucent_profile p);

/* ---- Images ---- */
/* Linear float image with the AOVs the renderer produces. Arrays are row-major, top row first.
 * rgba: 4 floats/pixel (radiance, coverage alpha); depth: camera distance in scene units
 * (0 where uncovered); normal: 3 floats/pixel, world space; view: chosen projection image
 * 0 front, 1 left, 2 right, 3 top, 4 bottom, -1 uncovered; facing: cosine between the normal and
 * the direction to the eye (0 where uncovered; near 0 at silhouettes). Any AOV may be NULL. */
typedef struct lucent_image {
    int width, height;
    float *rgba;
    float *depth;
    float *normal;
    float *view;
    float *facing;
} lucent_image;

/* Allocates a zeroed image; with_aovs = 0 leaves depth, normal, view and facing NULL. */
lucent_status lucent_image_alloc(lucent_image *img, int width, int height, int with_aovs, lucent_error *err);
void lucent_image_free(lucent_image *img);

/* Encodes to PNG (8-bit sRGB, straight alpha = coverage) or EXR (float RGBA + AOV channels),
 * applying exposure and compositing the background. *bytes is malloc'd; the caller frees it. */
lucent_status lucent_image_encode(const lucent_image *img, lucent_format format, double exposure,
                                  const double background[4], unsigned char **bytes, size_t *len,
                                  lucent_error *err);
lucent_status lucent_image_write(const char *path, const lucent_image *img, lucent_format format,
                                 double exposure, const double background[4], lucent_error *err);
/* Reads a PNG or EXR back (EXR: RGBA and any AOV channels present, else NULL). */
lucent_status lucent_image_load(const char *path, lucent_image *out, lucent_error *err);

/* Error of an image against a reference, over the pixels covered in both (RGB radiance). rel_l2 is
 * ||test - ref|| / ||ref|| over all those values; per-pixel relative error is |test - ref| / |ref|
 * (RGB vectors, the reference floored at 1e-3 of its mean so black pixels do not divide by 0).
 * `band` repeats the measures for the silhouette band: pixels whose normal is 70 to 90 degrees
 * from the view direction (reference facing AOV below cos 70 deg; absent AOV: no band). */
typedef struct lucent_error_measures {
    int pixels;
    double rel_l2, mean_abs, max_abs, p99_rel, share_over_10pct;
} lucent_error_measures;

/* The whole object's error split by what a viewer sees, over the interior: covered pixels whose 5x5
 * neighbourhood is covered in both images (silhouettes, where coverage differs, are left out).
 * noise = ||hp(test) - hp(ref)|| / ||ref|| with hp(x) = x - box3x3(x): speckle; low_frequency_rel_l2
 * = ||box5x5(test) - box5x5(ref)|| / ||box5x5(ref)||: what survives a small blur (missing light,
 * seams). mean_ratio = summed RGB of test / of ref over every pixel covered in both (the energy;
 * 0 where the reference is black). mottle = ||bp(test) - bp(ref)|| / ||ref|| with bp(x) = box3x3(x) -
 * box25x25(x), over the pixels whose 25x25 neighbourhood is covered in both (NaN where none is): blotches up
 * to about 12 pixels across, three far blocks, which noise's 3x3 high-pass hardly sees. */
typedef struct lucent_image_error {
    lucent_error_measures object;   /* every pixel covered in both images */
    lucent_error_measures band;     /* the silhouette band */
    int coverage_mismatch;          /* pixels covered in one image only */
    int interior_pixels;            /* the pixels noise and low_frequency_rel_l2 are taken over */
    double noise, low_frequency_rel_l2, mean_ratio;
    int mottle_pixels;              /* the pixels mottle is taken over */
    double mottle;
} lucent_image_error;

lucent_status lucent_image_compare(const lucent_image *test, const lucent_image *ref, lucent_image_error *out,
                                   lucent_error *err);
/* Against a truth seen only through two independent noisy estimates of it, a and b (method "path" under
 * two seeds), over the pixels covered in all, RGB, relative to the truth's norm estimated by sum a.b.
 * rel L2 against their mean adds their noise, and taking a noise estimate out of it leaves the error
 * divided by sqrt(1 + noise^2) or worse; the cross sum below cancels the noise in expectation instead. */
typedef struct lucent_noisy_error {
    double rel_l2;      /* sqrt(sum (test - a).(test - b) / sum a.b), 0 where the sum falls below 0 */
    double rel_l2_low;  /* the same with the sum 2 standard errors lower (0 where the noise hides the error) */
    double rel_l2_high; /* and 2 standard errors higher: the error is below this */
    double noise;       /* sqrt(sum ((a - b) / 2)^2 / sum a.b), the noise of the estimates' mean */
    double test_noise;  /* the same of the test's two estimates (compare_noisy_pair; 0 for one test) */
} lucent_noisy_error;

/* The standard error comes from the spread of the cross sum over 64 pixel lattices (every 8th pixel
 * across and down); where the noise is far above 1 a few samples carry the sum and it is understated (at
 * 2.5 an interval ended at 0.11 and three times the walks read 0.26). test NULL: only noise. Every member
 * NAN where sum a.b <= 0. */
lucent_status lucent_image_compare_noisy(const lucent_image *test, const lucent_image *a, const lucent_image *b,
                                         lucent_noisy_error *out, lucent_error *err);
/* The same where the test is noisy too, seen through two independent estimates t1 and t2 (one renderer's
 * random walk against another's): the cross sum pairs (t1 - a).(t2 - b) and (t2 - a).(t1 - b), so both
 * sides' noise cancels and what is left is the difference of the two truths. t1 == t2 is compare_noisy;
 * both NULL: only noise. */
lucent_status lucent_image_compare_noisy_pair(const lucent_image *t1, const lucent_image *t2, const lucent_image *a,
                                              const lucent_image *b, lucent_noisy_error *out, lucent_error *err);
/* into = (into + other) / 2 in RGB, alpha and AOVs kept: the mean of two such estimates, for the
 * measures against it. LUCENT_E_INVALID where the two differ in size. */
lucent_status lucent_image_average(lucent_image *into, const lucent_image *other, lucent_error *err);
/* Writes the measures as one JSON object; returns the length or -1 if cap is too small. */
int lucent_image_error_json(const lucent_image_error *e, char *buf, size_t cap);

/* ---- Meshes ---- */
typedef struct lucent_mesh lucent_mesh;

lucent_status lucent_mesh_builtin(const char *name, uint32_t triangles, lucent_mesh **out,
                                  lucent_error *err);
lucent_status lucent_mesh_import_file(const char *path, lucent_mesh **out, lucent_error *err);
/* ext_hint is the format's file extension ("obj", "ply", "stl", "gltf", "glb"). */
lucent_status lucent_mesh_import_memory(const void *data, size_t len, const char *ext_hint,
                                        lucent_mesh **out, lucent_error *err);
/* One file of a multi-file mesh: name is a relative path, '/'-separated, with no empty, "." or ".."
 * segment (the form a reference is resolved to). */
typedef struct lucent_mesh_file {
    const char *name;
    const void *data;
    size_t len;
} lucent_mesh_file;
/* Imports files[main] (format ext_hint) and serves the files it refers to (glTF buffers, an OBJ's
 * material library), resolved against its folder, from `files` only: nothing is read from disk. */
lucent_status lucent_mesh_import_files(const lucent_mesh_file *files, size_t count, size_t main,
                                       const char *ext_hint, lucent_mesh **out, lucent_error *err);
uint32_t lucent_mesh_triangle_count(const lucent_mesh *mesh);
void lucent_mesh_free(lucent_mesh *mesh);

/* ---- Renderer ---- */
typedef struct lucent_renderer lucent_renderer;

typedef struct lucent_renderer_desc {
    const char *backend;      /* "vulkan", "gl" (OpenGL through EGL) or "auto" (Vulkan, else OpenGL);
                               * NULL = $LUCENT_BACKEND or "auto" */
    const char *device_name;  /* substring of the device's name (Vulkan's, or OpenGL's GL_RENDERER);
                               * NULL = $LUCENT_DEVICE or automatic */
    int verbose;              /* log the chosen device and resource creation to stderr */
    uint64_t mesh_cache_bytes; /* meshes kept loaded (GPU buffers and CPU copies); 0 = 512 MiB */
} lucent_renderer_desc;

/* Time of each pass (ms, measured on the device where it supports timestamps) and what was
 * modelled. `modelled` holds a JSON object written by the renderer. */
typedef struct lucent_stats {
    double ms_mesh_load, ms_shadow, ms_projection, ms_gbuffer, ms_scatter, ms_readback, ms_total;
    uint32_t triangles, proxy_triangles;
    int shadow_maps, views;
    uint64_t mesh_cache_bytes;  /* what the renderer's cached meshes hold after this frame */
    uint64_t device_bytes;      /* device memory the renderer holds after this frame: cached meshes,
                                 * the render targets of this frame's sizes, buffers */
    char backend[16];           /* "vulkan" or "gl" */
    char device[256];
    char modelled[2048];
    lucent_profile profile;     /* the diffusion profile integrated (modelled's "profile"); DEFAULT for
                                 * method path, which uses none */
    int single_scattering;      /* 1 when the single-scattering term was added (modelled's
                                 * "single_scattering"; method auto chooses it) */
} lucent_stats;

/* Renderers of one process share a Vulkan device (or an EGL display, each with its own OpenGL context) per
 * requested device name; it stays warm after the last renderer is destroyed, until lucent_shutdown()
 * (call it before exit to release it). */
lucent_renderer *lucent_renderer_create(const lucent_renderer_desc *desc, lucent_error *err);
void lucent_renderer_destroy(lucent_renderer *r);
/* Releases the devices no renderer uses any more. */
void lucent_shutdown(void);
/* 1 when name is a backend lucent_renderer_desc takes: "vulkan", "gl" or "auto". */
int lucent_backend_valid(const char *name);
/* The backend the renderer opened ("vulkan" or "gl") and its device's name. */
const char *lucent_renderer_backend(const lucent_renderer *r);
const char *lucent_renderer_device(const lucent_renderer *r);
/* The largest width x height the image-space methods can render on this renderer's device: the
 * scatter pass writes 16 bytes a pixel through one storage-buffer range (Vulkan's maxStorageBufferRange,
 * OpenGL's GL_MAX_SHADER_STORAGE_BLOCK_SIZE; 128 MiB on lavapipe and llvmpipe: 2896^2). Larger images
 * are refused with LUCENT_E_LIMIT naming that limit. */
uint64_t lucent_renderer_max_pixels(const lucent_renderer *r);
/* Renders one frame. out is allocated here (AOVs only when scene->format is EXR); free with
 * lucent_image_free. stats may be NULL. */
lucent_status lucent_render(lucent_renderer *r, const lucent_scene *scene, lucent_image *out,
                            lucent_stats *stats, lucent_error *err);
/* Asks the render running on r to stop; safe from any thread. The reference method stops within a
 * row of pixels and returns LUCENT_E_CANCELLED; image-space frames are short and finish. A request
 * made while no render runs is forgotten when the next one starts. */
void lucent_render_cancel(lucent_renderer *r);
/* Writes stats as one JSON object; returns the length or -1 if cap is too small. */
int lucent_stats_json(const lucent_stats *stats, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif
#endif
