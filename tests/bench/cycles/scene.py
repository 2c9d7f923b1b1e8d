# scene.py - Blender 3.4 script: renders a Lucent scene document (OBJ mesh, material, directional lights, camera)
# with Cycles' random-walk subsurface scattering to a linear float EXR, for the peer comparison (compare.sh).
"""Usage (Blender 3.4.1, Debian 12 package `blender`):

    blender -b --factory-startup -P scene.py -- SCENE.json OUT.exr [--samples N] [--shader sss|principled]
            [--seed S] [--threads T] [--filter point|box|default] [--max-bounces B] [--terminator-offset X]
    blender -b --factory-startup -P scene.py -- --check-lambert [--samples N]

Conventions (Lucent -> Blender):
* One Blender unit = one Lucent scene unit; the OBJ is imported without axis conversion
  (bpy.ops.wm.obj_import(forward_axis='Y', up_axis='Z') is the identity in 3.4; checked against the file's
  own "v" lines at run time). Subsurface radii are mm / scale_mm; scale_mm absent or 0 means Lucent's
  automatic scale: the bounding sphere (centre = bounding-box centre, radius = farthest vertex from it,
  renderer/mesh/mesh.c recentre()) gets a 50 mm diameter (renderer/core/frame_plan.c frame_scale_mm()).
* Normals: the file's vn if present (custom split normals), else area-weighted vertex normals as Lucent
  computes them (renderer/mesh/mesh_normals.h), set as custom normals; smooth shading.
* Material: jensen_to_cycles.convert(). --shader sss (default) uses the Subsurface Scattering node: entry
  with no Fresnel, plain Lambert exit (svm/closure.h sets roughness = FLT_MAX, so subsurface.h
  subsurface_shader_data_setup() puts a bsdf_diffuse at the exit) = Lucent's path boundary "cycles".
  --shader principled uses the Principled BSDF (Specular 0, Roughness 0): its exit is
  PRINCIPLED_DIFFUSE_LAMBERT_EXIT, which multiplies the light by (1 - 0.5 (1 - cos_l)^5).
* Directional light {"direction", "intensity" E, "color"}: a Sun lamp, angle 0, travelling along direction,
  strength E x max(color), colour colour / max(colour). Cycles' sun of strength E gives a white Lambertian
  surface facing it radiance E / pi, as Lucent does (--check-lambert shows 1/pi = 0.3183 for E = 1).
* Camera {"position", "target", "up", "fov_deg"}: look-at with Lucent's basis (right = forward x up,
  renderer/core/view_frame.c view_frame_look()), sensor_fit VERTICAL, vertical angle = fov_deg.
  "direction" or no camera: framed as Lucent frames it (frame_plan.c frame_camera(), margin 1.02).
* Film: transparent (alpha = coverage), world black, view transform Standard, look None, exposure 0,
  gamma 1, Cycles film exposure 1. Pixel filter: --filter point (default) = Blackman-Harris of width
  0.01 px (a box would be forced to width 1 by Blender's sync_film()), i.e. every sample within 0.01 px of
  the pixel centre, as Lucent's CPU methods cast one ray through each pixel centre
  (renderer/core/view_frame.c view_frame_pixel_ray()); --filter box: a box of one pixel (what Blender forces a
  box to), uniform over the pixel, as Lucent's path with "filter": "box" (premultiplied, alpha = share hit);
  --filter default keeps Blackman-Harris 1.5. The 0.01 px filter is not quite a point: about 200 silhouette
  pixels of the 256^2 sphere come out partly covered (a silhouette within its reach, or rays slipping between
  grazing triangles), and where a one-pixel rim holds most of the light (the back-lit sphere) sub-pixel
  differences move it by 10-20% a pixel; the box filter makes both renderers integrate the same area.
* Shadow rays: from the flat triangles, as Lucent casts them (renderer/reference/ref_lights.c: from the hit
  point moved off its triangle along the geometric normal). Cycles by default lifts the origin of shadow rays
  leaving grazing triangles onto a smooth surface through the vertex normals (object setting
  shadow_terminator_geometry_offset, 0.1; kernel/light/sample.h shadow_ray_offset()), which lights a band
  along the terminator that the flat triangles shadow; --terminator-offset X sets it (default 0: off). Where
  walks leave near the terminator it matters: the back-lit skin1 sphere is 0.8% / 1.5% / 1.6% (R / G / B)
  brighter with Cycles' default (128^2, 512 samples, same seed).
* Integrator: CPU, N samples (default 2048), fixed seed, no adaptive sampling, no denoising, no light
  clamping, light threshold 0, max bounces 0 (default): the random walk itself does not count as a
  bounce in Cycles (subsurface_bounce() does not call path_state_next()), so 0 still gives the walk and
  the direct light at its exit, and nothing more -- as Lucent's path method (no inter-reflection).
"""

import json
import math
import os
import sys
import time

import bpy
import mathutils

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jensen_to_cycles  # noqa: E402

FRAME_FIT_MARGIN = 1.02          # renderer/core/frame_plan.h
DEFAULT_FOV_DEG = 40.0           # renderer/core/scene_parse.c
DEFAULT_AZIMUTH_DEG = 35.0
DEFAULT_ELEVATION_DEG = 25.0
DEFAULT_SIDE = 512


def fail(msg):
    print("scene.py: error: " + msg, file=sys.stderr)
    sys.stderr.flush()
    os._exit(2)


def parse_args(argv):
    args = {"samples": 2048, "shader": "sss", "seed": 0, "threads": 0, "filter": "point", "max_bounces": 0,
            "terminator_offset": 0.0, "check_lambert": False, "positional": []}
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--check-lambert":
            args["check_lambert"] = True
        elif a in ("--samples", "--seed", "--threads", "--max-bounces"):
            if i + 1 >= len(argv):
                fail(a + " needs a value")
            args[a[2:].replace("-", "_")] = int(argv[i + 1])
            i += 1
        elif a == "--terminator-offset":
            if i + 1 >= len(argv):
                fail(a + " needs a value")
            try:
                args["terminator_offset"] = float(argv[i + 1])
            except ValueError:
                fail(a + " needs a number")
            if not 0.0 <= args["terminator_offset"] <= 1.0:
                fail(a + " must be within [0, 1] (Blender's range)")
            i += 1
        elif a in ("--shader", "--filter"):
            if i + 1 >= len(argv):
                fail(a + " needs a value")
            args[a[2:]] = argv[i + 1]
            i += 1
        elif a.startswith("--"):
            fail("unknown option " + a)
        else:
            args["positional"].append(a)
        i += 1
    if args["shader"] not in ("sss", "principled"):
        fail("--shader must be sss or principled")
    if args["filter"] not in ("point", "box", "default"):
        fail("--filter must be point, box or default")
    if not args["check_lambert"] and len(args["positional"]) != 2:
        fail("usage: blender -b --factory-startup -P scene.py -- SCENE.json OUT.exr [--samples N] ...")
    return args


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras):
        for block in list(coll):
            coll.remove(block)


def setup_render(scene, width, height, args):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = args["samples"]
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.use_preview_denoising = False
    c.seed = args["seed"]
    c.use_animated_seed = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.max_bounces = args["max_bounces"]
    for name in ("diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces"):
        setattr(c, name, args["max_bounces"])
    c.transparent_max_bounces = max(8, args["max_bounces"])
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.film_exposure = 1.0
    if args["filter"] == "point":
        # Not BOX: Blender's sync forces a box filter to width 1 (intern/cycles/blender/sync.cpp sync_film()).
        # Blackman-Harris at the smallest width Blender allows, 0.01 px, puts every sample within 0.01 px of
        # the pixel centre (scene/film.cpp filter_table(): support = 2 x width).
        c.pixel_filter_type = "BLACKMAN_HARRIS"
        c.filter_width = 0.01
    elif args["filter"] == "box":
        c.pixel_filter_type = "BOX"
        c.filter_width = 1.0
    c.use_auto_tile = False
    scene.render.film_transparent = True
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.render.use_border = False
    if args["threads"] > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = args["threads"]
    vs = scene.view_settings
    try:
        vs.view_transform = "Standard"
    except TypeError as e:
        print("scene.py: warning: view transform Standard unavailable (%s); EXR output is linear anyway" % e)
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    img = scene.render.image_settings
    img.file_format = "OPEN_EXR"
    img.color_mode = "RGBA"
    img.color_depth = "32"
    img.exr_codec = "ZIP"
    # World: black, strength 0.
    world = scene.world or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes.get("Background")
    if bg:
        bg.inputs["Color"].default_value = (0, 0, 0, 1)
        bg.inputs["Strength"].default_value = 0.0


def look_at_matrix(position, target, up):
    """Camera-to-world rotation with Lucent's basis: -Z = forward, X = forward x up, Y = X x forward."""
    f = (mathutils.Vector(target) - mathutils.Vector(position))
    if f.length == 0:
        fail("camera: position equals target")
    f.normalize()
    r = f.cross(mathutils.Vector(up))
    if r.length < 1e-9 * mathutils.Vector(up).length:
        fail("camera.up is parallel to the viewing direction")
    r.normalize()
    u = r.cross(f)
    m = mathutils.Matrix((r, u, -f)).transposed()   # columns: camera X, Y, Z in world space
    # Cross-check with to_track_quat('-Z', 'Y') (which keeps Y toward world +Z): same -Z axis.
    q = f.to_track_quat("-Z", "Y")
    assert (q.to_matrix() @ mathutils.Vector((0, 0, -1)) - f).length < 1e-6
    # The image's up (camera +Y) leans toward Lucent's up, and X is Lucent's "right".
    assert (m @ mathutils.Vector((0, 1, 0))).dot(mathutils.Vector(up)) > 0
    assert (m @ mathutils.Vector((1, 0, 0)) - r).length < 1e-9
    return m


def add_camera(scene, cam_doc, centre, radius, width, height):
    cam_doc = cam_doc or {}
    fov = float(cam_doc.get("fov_deg", DEFAULT_FOV_DEG))
    up = cam_doc.get("up", [0.0, 1.0, 0.0])
    if "position" in cam_doc and "target" in cam_doc:
        position, target = cam_doc["position"], cam_doc["target"]
    else:
        if "direction" in cam_doc:
            d = mathutils.Vector(cam_doc["direction"]).normalized()
        else:
            az, el = math.radians(DEFAULT_AZIMUTH_DEG), math.radians(DEFAULT_ELEVATION_DEG)
            d = mathutils.Vector((math.sin(az) * math.cos(el), -math.sin(el), -math.cos(az) * math.cos(el)))
        tan_v = math.tan(math.radians(fov) / 2)
        tan_h = tan_v * width / height
        dist = radius * FRAME_FIT_MARGIN / math.sin(math.atan(min(tan_v, tan_h)))
        position = list(mathutils.Vector(centre) - dist * d)
        target = list(mathutils.Vector(centre) + d)
    data = bpy.data.cameras.new("Camera")
    data.type = "PERSP"
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(fov)
    data.clip_start = 1e-4 * radius
    data.clip_end = 1e4 * radius
    data.shift_x = data.shift_y = 0.0
    cam = bpy.data.objects.new("Camera", data)
    scene.collection.objects.link(cam)
    m = look_at_matrix(position, target, up).to_4x4()
    m.translation = mathutils.Vector(position)
    cam.matrix_world = m
    scene.camera = cam
    # Check: vertical field of view as Blender will use it.
    got = 2 * math.atan(data.sensor_height / (2 * data.lens))
    if abs(got - math.radians(fov)) > 1e-5:
        fail("camera fov mismatch: %g vs %g" % (math.degrees(got), fov))
    return cam


def add_sun(scene, light, index):
    if light.get("type", "directional") != "directional":
        fail("lights[%d]: only directional lights are supported" % index)
    d = mathutils.Vector(light["direction"])
    if d.length == 0:
        fail("lights[%d].direction is zero" % index)
    d.normalize()
    color = light.get("color", [1.0, 1.0, 1.0])
    peak = max(color)
    data = bpy.data.lights.new("Sun%d" % index, type="SUN")
    data.angle = 0.0
    data.energy = float(light.get("intensity", 1.0)) * peak
    data.color = [c / peak for c in color] if peak > 0 else [1.0, 1.0, 1.0]
    data.cycles.cast_shadow = True
    data.cycles.max_bounces = 1024
    obj = bpy.data.objects.new("Sun%d" % index, data)
    scene.collection.objects.link(obj)
    obj.rotation_mode = "QUATERNION"
    obj.rotation_quaternion = d.to_track_quat("-Z", "Y")   # a sun emits along its local -Z
    bpy.context.view_layer.update()
    travel = obj.matrix_world.to_3x3() @ mathutils.Vector((0, 0, -1))
    if (travel - d).length > 1e-6:
        fail("sun orientation mismatch")
    return obj


def read_obj(path):
    verts, has_vn = [], False
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append(tuple(float(x) for x in line.split()[1:4]))
            elif line.startswith("vn "):
                has_vn = True
    return verts, has_vn


def import_mesh(scene, path):
    file_verts, has_vn = read_obj(path)
    before = set(bpy.data.objects)
    bpy.ops.wm.obj_import(filepath=path, forward_axis="Y", up_axis="Z", global_scale=1.0,
                          clamp_size=0.0, validate_meshes=False)
    objs = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
    if len(objs) != 1:
        fail("%s: expected one mesh object, imported %d" % (path, len(objs)))
    obj = objs[0]
    if obj.matrix_world != mathutils.Matrix.Identity(4):
        fail("the OBJ importer set a non-identity object transform")
    me = obj.data
    # Identity check: every imported vertex equals a file vertex (importer keeps file order in 3.4).
    n = min(len(me.vertices), len(file_verts))
    worst = max((mathutils.Vector(me.vertices[i].co) - mathutils.Vector(file_verts[i])).length
                for i in range(0, n, max(1, n // 2000)))
    if len(me.vertices) != len(file_verts) or worst > 1e-5 * (1 + max(abs(c) for v in file_verts for c in v)):
        fail("OBJ import is not the identity (vertices %d vs %d, worst %g)" % (len(me.vertices), len(file_verts),
                                                                           worst))
    for p in me.polygons:
        p.use_smooth = True
    me.use_auto_smooth = True
    me.auto_smooth_angle = math.pi
    if not (has_vn and me.has_custom_normals):
        # Lucent's mesh_fill_normals(): area-weighted average of the adjacent faces' normals.
        acc = [mathutils.Vector((0.0, 0.0, 0.0)) for _ in me.vertices]
        for p in me.polygons:
            vs = [me.vertices[i].co for i in p.vertices]
            for k in range(1, len(vs) - 1):
                n_face = (vs[k] - vs[0]).cross(vs[k + 1] - vs[0])   # length: twice the area
                for i in (p.vertices[0], p.vertices[k], p.vertices[k + 1]):
                    acc[i] += n_face
        normals = [a.normalized() if a.length > 0 else mathutils.Vector((0, 0, 1)) for a in acc]
        me.normals_split_custom_set_from_vertices(normals)
    # Lucent's bounding sphere (renderer/mesh/mesh.c recentre()): bbox centre, farthest vertex.
    lo = [min(v.co[k] for v in me.vertices) for k in range(3)]
    hi = [max(v.co[k] for v in me.vertices) for k in range(3)]
    centre = [(lo[k] + hi[k]) / 2 for k in range(3)]
    radius = max((mathutils.Vector(v.co) - mathutils.Vector(centre)).length for v in me.vertices)
    return obj, centre, radius, has_vn


def empty_material(name):
    """A node material with nothing but its output node."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    for node in list(nt.nodes):
        nt.nodes.remove(node)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    return mat, nt, out


def make_material(res, shader):
    mat, nt, out = empty_material("Lucent")
    out.target = "CYCLES"
    if shader == "principled":
        node = nt.nodes.new("ShaderNodeBsdfPrincipled")
        settings = res["principled"]
        node.subsurface_method = settings["subsurface_method"]
        node.distribution = "GGX"
    else:
        node = nt.nodes.new("ShaderNodeSubsurfaceScattering")
        settings = res["sss"]
        node.falloff = settings["falloff"]
    for key, value in settings.items():
        if key in ("subsurface_method", "falloff"):
            continue
        sock = node.inputs[key]
        if isinstance(value, tuple):
            want = list(value) + ([1.0] if len(sock.default_value) == 4 else [])
            sock.default_value = want
            got = list(sock.default_value)
        else:
            sock.default_value = value
            want, got = [value], [sock.default_value]
        for w, g in zip(want, got):
            if abs(w - g) > 1e-6 * max(1.0, abs(w)):
                fail("material input %r: set %r, Blender kept %r" % (key, want, got))
    nt.links.new(node.outputs[0], out.inputs["Surface"])
    return mat


def check_lambert(args):
    clear_scene()
    scene = bpy.context.scene
    setup_render(scene, 16, 16, dict(args, samples=min(args["samples"], 256)))
    bpy.ops.mesh.primitive_plane_add(size=2.0, location=(0, 0, 0))
    plane = bpy.context.active_object
    mat, nt, out = empty_material("White")
    diff = nt.nodes.new("ShaderNodeBsdfDiffuse")
    diff.inputs["Color"].default_value = (1, 1, 1, 1)
    diff.inputs["Roughness"].default_value = 0.0
    nt.links.new(diff.outputs[0], out.inputs["Surface"])
    plane.data.materials.append(mat)
    add_camera(scene, {"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 20}, [0, 0, 0],
               1.0, 16, 16)
    add_sun(scene, {"direction": [0, 0, -1], "intensity": 1.0}, 0)
    path = os.path.join(os.environ.get("TMPDIR", "/tmp"), "lucent_check_lambert_%d.exr" % os.getpid())
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(path)
    px = list(img.pixels)
    w, h = img.size
    i = ((h // 2) * w + w // 2) * 4
    rgba = px[i:i + 4]
    os.remove(path)
    print("check-lambert: Blender %s, white Lambertian square facing a sun of strength 1: centre pixel "
          "RGBA = (%.5f, %.5f, %.5f, %.3f); expected 1/pi = %.5f; ratio %.5f" % (
              bpy.app.version_string, rgba[0], rgba[1], rgba[2], rgba[3], 1 / math.pi, rgba[0] * math.pi))
    return abs(rgba[0] * math.pi - 1) < 0.01


def render_scene(args):
    scene_path, out_path = args["positional"]
    with open(scene_path) as f:
        doc = json.load(f)
    mesh = doc.get("mesh", {})
    if "file" not in mesh:
        fail("mesh: only {\"file\": PATH.obj} is supported (export builtin meshes to OBJ)")
    mesh_path = mesh["file"]
    if not os.path.isabs(mesh_path) and not os.path.exists(mesh_path):
        mesh_path = os.path.join(os.path.dirname(os.path.abspath(scene_path)), mesh_path)
    width = int(doc.get("width", DEFAULT_SIDE))
    height = int(doc.get("height", DEFAULT_SIDE))
    clear_scene()
    scene = bpy.context.scene
    setup_render(scene, width, height, args)
    obj, centre, radius, has_vn = import_mesh(scene, os.path.abspath(mesh_path))
    obj.cycles.shadow_terminator_geometry_offset = args["terminator_offset"]
    obj.cycles.shadow_terminator_offset = 0.0
    scale_mm = float(doc.get("scale_mm", 0.0) or 0.0)
    auto = scale_mm <= 0.0
    if auto:
        scale_mm = 50.0 / (2.0 * radius)   # frame_plan.c frame_scale_mm()
    sigma_a, sigma_s_prime, eta, g = jensen_to_cycles.material_from_scene(doc.get("material"))
    res = jensen_to_cycles.convert(sigma_a, sigma_s_prime, eta, g, scale_mm)
    for w in res["warnings"]:
        print("scene.py: warning: " + w)
    obj.data.materials.clear()
    obj.data.materials.append(make_material(res, args["shader"]))
    lights = doc.get("lights") or [{"direction": [-1, -1, -1], "intensity": 1.0}]
    for i, light in enumerate(lights):
        add_sun(scene, light, i)
    add_camera(scene, doc.get("camera"), centre, radius, width, height)
    scene.render.filepath = os.path.abspath(out_path)
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    seconds = time.time() - t0
    info = {"cycles": {"blender": bpy.app.version_string, "seconds": round(seconds, 3), "samples": args["samples"],
                       "shader": args["shader"], "filter": args["filter"], "max_bounces": args["max_bounces"],
                       "terminator_offset": obj.cycles.shadow_terminator_geometry_offset,
                       "threads": scene.render.threads, "scale_mm": scale_mm, "scale_auto": auto,
                       "bounding_radius": radius, "file_normals": has_vn,
                       "radius": list(res["sss"]["Radius"]), "color": list(res["sss"]["Color"]),
                       "warnings": res["warnings"], "out": os.path.abspath(out_path)}}
    print("CYCLES_INFO " + json.dumps(info))
    return True


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = parse_args(argv)
    ok = check_lambert(args) if args["check_lambert"] else render_scene(args)
    sys.stdout.flush()
    os._exit(0 if ok else 1)


main()
