# scenes.py - the Cycles comparison scenes as Lucent scene documents (compare.sh, fast_vs_cycles.sh): a unit
# icosphere OBJ with exact normals and the bunny, side- or back-lit, each written to OUT/<name>/scene.json.
# usage: python3 scenes.py OUT SIZE BUNNY_OBJ_OR_EMPTY [--sphere-level L] NAME...
#        (NAME: {sphere,bunny}-{marble,skin1}-{side,back}; L: the icosphere's subdivisions, 5 by default: 20480
#        triangles in OUT/icosphere.obj, another level 20 x 4^L in OUT/icosphere-L.obj)
import json, math, os, sys
out, size, bunny = sys.argv[1], int(sys.argv[2]), sys.argv[3]
names = sys.argv[4:]
level = 5
if names[:1] == ["--sphere-level"]:
    level, names = int(names[1]), names[2:]

def icosphere(level):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        cache, nf = {}, []
        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                p = [(v[a][k] + v[b][k]) / 2 for k in range(3)]
                n = math.sqrt(sum(x * x for x in p))
                v.append(tuple(x / n for x in p))
                cache[key] = len(v) - 1
            return cache[key]
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return v, f

sphere = os.path.join(out, "icosphere.obj" if level == 5 else "icosphere-%d.obj" % level)
if not os.path.exists(sphere):
    v, f = icosphere(level)
    with open(sphere, "w") as fh:
        fh.write("# unit icosphere, %d triangles, exact normals (tests/bench/cycles/scenes.py)\n" % len(f))
        for p in v:
            fh.write("v %.9f %.9f %.9f\n" % p)
        for p in v:
            fh.write("vn %.9f %.9f %.9f\n" % p)
        for a, b, c in f:
            fh.write("f %d//%d %d//%d %d//%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1))

def bounds(path):
    vs = [list(map(float, l.split()[1:4])) for l in open(path) if l.startswith("v ")]
    lo = [min(p[k] for p in vs) for k in range(3)]
    hi = [max(p[k] for p in vs) for k in range(3)]
    c = [(lo[k] + hi[k]) / 2 for k in range(3)]
    r = max(math.sqrt(sum((p[k] - c[k]) ** 2 for k in range(3))) for p in vs)
    return c, r

def norm(d):
    n = math.sqrt(sum(x * x for x in d))
    return [x / n for x in d]

lights = {"side": norm([-1, 0, 0]), "back": norm([-0.5, -0.25, 1])}
for name in names:
    shape, preset, light = name.split("-")
    mesh = sphere if shape == "sphere" else bunny
    if shape not in ("sphere", "bunny") or light not in lights or not mesh:
        sys.exit("scenes.py: unknown scene %s (or no --bunny)" % name)
    c, r = bounds(mesh)
    fov = 40.0
    dist = r * 1.02 / math.sin(math.radians(fov / 2))
    doc = {"mesh": {"file": mesh}, "material": {"preset": preset},
           "lights": [{"type": "directional", "direction": lights[light], "intensity": 3.0, "color": [1, 1, 1]}],
           "camera": {"position": [c[0], c[1], c[2] + dist], "target": c, "up": [0, 1, 0], "fov_deg": fov},
           "width": size, "height": size}
    os.makedirs(os.path.join(out, name), exist_ok=True)
    path, text = os.path.join(out, name, "scene.json"), json.dumps(doc, indent=1)
    if not os.path.exists(path) or open(path).read() != text:   # unchanged: its age keeps Cycles' image
        with open(path, "w") as fh:
            fh.write(text)
