#!/usr/bin/env python3
# jensen_to_cycles.py - converts a Lucent material (sigma_a, sigma_s' in mm^-1, eta, g, mm per scene unit) into
# Blender 3.4 Cycles random-walk ("radius as specified") subsurface settings; --selftest round-trips Cycles' own mapping.
"""Lucent material -> Blender 3.4 (Debian 12's 3.4.1) Cycles random-walk subsurface settings.

Everything below is read from Cycles' source at tag v3.4.0 of github.com/blender/cycles (the standalone
mirror of blender/intern/cycles; paths below are relative to intern/cycles/, which is src/ there).

How Cycles 3.4 turns node inputs into the walk's medium (per RGB channel):

1. kernel/svm/closure.h, svm_node_closure_bsdf():
   * Principled BSDF (case CLOSURE_BSDF_PRINCIPLED_ID):
       mixed_ss_base_color = subsurface_color * subsurface + base_color * (1 - subsurface)
       bssrdf->radius      = subsurface_radius * subsurface         ("Subsurface" scales the radius too)
       bssrdf->albedo      = mixed_ss_base_color
       bssrdf->roughness   = roughness                              (!= FLT_MAX: Disney entry/exit terms)
       subsurface_ior      = clamp(Subsurface IOR, 1.01, 3.8)
       bssrdf->anisotropy  = clamp(Subsurface Anisotropy, 0.0, 0.9)
   * Subsurface Scattering node (case CLOSURE_BSSRDF_RANDOM_WALK_FIXED_RADIUS_ID):
       bssrdf->radius = Radius * Scale;  bssrdf->albedo = Color;  bssrdf->roughness = FLT_MAX;
       same IOR and anisotropy clamps.
2. kernel/closure/bssrdf.h, bssrdf_setup() -> bssrdf_setup_radius(): for CLOSURE_BSSRDF_BURLEY_ID and
   CLOSURE_BSSRDF_RANDOM_WALK_FIXED_RADIUS_ID:  radius *= 0.25 * M_1_PI_F  (i.e. d = radius / (4 pi));
   the IOR is only used by the other method (RANDOM_WALK, Jensen's Rd inversion), so with
   RANDOM_WALK_FIXED_RADIUS the Subsurface IOR has NO effect. A channel with radius < BSSRDF_MIN_RADIUS
   (1e-8, kernel/types.h) becomes a diffuse BSDF.
3. kernel/integrator/subsurface_random_walk.h:
   subsurface_random_walk_remap(albedo, d, g):
       alpha   = fit(albedo, g)  (Wrenninge/Villemin/Hery 2017 polynomials; clamped to [0, 0.999999])
       sigma_t = (1 / max(d, 1e-16)) / (1 - g)
   subsurface_random_walk_coefficients(): throughput /= albedo (the closure weight's colour is divided out),
       and if alpha < 0.2 then throughput *= alpha / 0.2 and alpha = 0.2 (NOT equivalent to the medium).
   subsurface_random_walk(): sigma_s = sigma_t * alpha; Henyey-Greenstein phase with g for the first
       SUBSURFACE_RANDOM_WALK_SIMILARITY_LEVEL (9) bounces, then isotropic with sigma_s* = sigma_s (1 - g)
       (similarity theory); at most BSSRDF_MAX_BOUNCES (256) scattering events, then the path is lost.

Lucent's medium (renderer/reference/path.c): sigma_t = sigma_a + sigma_s' / (1 - g), single-scattering albedo
sigma_s / sigma_t with sigma_s = sigma_s' / (1 - g), Henyey-Greenstein g. Matching Cycles' sigma_t and alpha
to it (scene units: coefficients x scale_mm):

    1/d   = (1 - g) * sigma_t * scale_mm = scale_mm * ((1 - g) sigma_a + sigma_s')    [= sigma_t' for g = 0]
    alpha = sigma_s / sigma_t = sigma_s' / ((1 - g) sigma_a + sigma_s')               [= alpha'  for g = 0]
    Radius (scene units) = 4 pi d / Subsurface,    colour A = fit^-1(alpha, g)  (bisection)

For g = 0 this is exactly sigma_t' = 1/d and alpha' = sigma_s' / (sigma_s' + sigma_a).
"""

import math
import os
import re
import sys

# ---- Cycles' forward mapping, transcribed from v3.4.0 -------------------------------------------------------

BSSRDF_MIN_RADIUS = 1e-8        # kernel/types.h
BSSRDF_MAX_BOUNCES = 256        # kernel/types.h
MIN_ALPHA = 0.2                 # subsurface_random_walk_coefficients(): min_alpha
MAX_ALPHA = 0.999999            # subsurface_random_walk_remap(): clamp(*alpha, 0.0f, 0.999999f)
IOR_RANGE = (1.01, 3.8)         # svm/closure.h: clamp(subsurface_ior, 1.01f, 3.8f)
ANISOTROPY_RANGE = (0.0, 0.9)   # svm/closure.h: clamp(subsurface_anisotropy, 0.0f, 0.9f)
FIXED_RADIUS_SCALE = 0.25 / math.pi  # bssrdf.h bssrdf_setup_radius(): radius *= 0.25f * M_1_PI_F


def cycles_remap_alpha(albedo, g):
    """subsurface_random_walk_remap() (kernel/integrator/subsurface_random_walk.h, v3.4.0): the
    single-scattering albedo Cycles gives the medium for surface albedo `albedo` and anisotropy g."""
    def poly(*c):   # c[0] + c[1] g + ... + c[7] g^7, as Cycles writes each fit
        return sum(ci * g ** i for i, ci in enumerate(c))

    A = poly(1.8260523782, -1.28451056436, -1.79904629312, 9.19393289202, -22.8215585862, 32.0234874259,
             -23.6264803333, 7.21067002658)
    B = 4.98511194385 + 0.127355959438 * math.exp(
        poly(0.0, 31.1491581433, -201.847017512, 841.576016723, -2018.09288505, 2731.71560286, -1935.41424244,
             559.009054474))
    C = poly(1.09686102424, -0.394704063468, 1.05258115941, -8.83963712726, 28.8643230661, -46.8802913581,
             38.5402837518, -12.7181042538)
    D = poly(0.496310210422, 0.360146581622, -2.15139309747, 17.8896899217, -55.2984010333, 82.065982243,
             -58.5106008578, 15.8478295021)
    E = 4.23190299701 + 0.00310603949088 * math.exp(
        poly(0.0, 76.7316253952, -594.356773233, 2448.8834203, -5576.68528998, 7116.60171912, -4763.54467887,
             1303.5318055))
    F = poly(2.40602999408, -2.51814844609, 9.18494908356, -79.2191708682, 259.082868209, -403.613804597,
             302.85712436, -87.4370473567)
    blend = albedo ** 0.25
    alpha = ((1.0 - blend) * A * math.atan(B * albedo) ** C +
             blend * D * math.atan(E * albedo) ** F)
    return min(max(alpha, 0.0), MAX_ALPHA)


def cycles_medium(node, settings, channel):
    """Cycles' forward mapping for one channel: node inputs -> (sigma_t, sigma_s, g) in scene units^-1 of the
    random walk's FIRST bounces, and the throughput factor of the alpha < 0.2 trick. `node` is
    "principled" or "sss"; `settings` a dict of that node's inputs as convert() returns them."""
    if node == "principled":
        sub = settings["Subsurface"]
        albedo = settings["Subsurface Color"][channel] * sub + settings["Base Color"][channel] * (1.0 - sub)
        radius = settings["Subsurface Radius"][channel] * sub          # svm/closure.h
        aniso = settings["Subsurface Anisotropy"]
    else:
        albedo = settings["Color"][channel]
        radius = settings["Radius"][channel] * settings["Scale"]         # svm/closure.h (param1 = Scale)
        aniso = settings["Anisotropy"]
    g = min(max(aniso, ANISOTROPY_RANGE[0]), ANISOTROPY_RANGE[1])
    if radius < BSSRDF_MIN_RADIUS:
        return None                                                      # bssrdf_setup(): diffuse instead
    d = radius * FIXED_RADIUS_SCALE                                      # bssrdf_setup_radius()
    alpha = cycles_remap_alpha(albedo, g)
    sigma_t = (1.0 / max(d, 1e-16)) / (1.0 - g)                          # subsurface_random_walk_remap()
    throughput = 1.0
    if alpha < MIN_ALPHA:                                                # subsurface_random_walk_coefficients()
        throughput = alpha / MIN_ALPHA
        alpha = MIN_ALPHA
    return {"sigma_t": sigma_t, "sigma_s": sigma_t * alpha, "alpha": alpha, "g": g, "throughput": throughput}


# ---- the inverse ----------------------------------------------------------------------------------------------

def invert_remap(alpha, g, tol=1e-15):
    """The surface albedo A in [0, 1] with cycles_remap_alpha(A, g) = alpha, by bisection (the fit rises
    monotonically in A; checked by the self-test). Returns (A, reachable)."""
    lo, hi = 0.0, 1.0
    if alpha >= cycles_remap_alpha(hi, g):
        return hi, alpha <= MAX_ALPHA
    if alpha <= 0.0:
        return 0.0, True
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if cycles_remap_alpha(mid, g) < alpha:
            lo = mid
        else:
            hi = mid
        if hi - lo < tol:
            break
    return 0.5 * (lo + hi), True


def convert(sigma_a, sigma_s_prime, eta=1.3, g=0.0, scale_mm=1.0, subsurface=1.0):
    """Lucent material -> Blender 3.4 Cycles settings, method RANDOM_WALK_FIXED_RADIUS.

    sigma_a, sigma_s_prime: 3 values each, mm^-1 (R, G, B); eta: Lucent's relative IOR; g: Henyey-Greenstein
    mean cosine; scale_mm: millimetres per scene (= Blender) unit; subsurface: the Principled "Subsurface"
    factor to use (it multiplies the radius, so the radius given is divided by it).

    Returns a dict: "principled" (Principled BSDF inputs by socket name, plus "subsurface_method"),
    "sss" (Subsurface Scattering node inputs, plus "falloff"), "target" (the medium per channel in scene
    units: sigma_t, sigma_s, alpha, and for g = 0 also sigma_t_prime, alpha_prime), "warnings" (where Cycles
    cannot represent the material exactly)."""
    if not (0.0 < subsurface <= 1.0):
        raise ValueError("subsurface factor must be in (0, 1] (Blender's socket range)")
    warnings = []
    radius, colour = [], []
    target = {"sigma_t": [], "sigma_s": [], "alpha": [], "sigma_t_prime": [], "alpha_prime": []}
    g_cycles = min(max(g, ANISOTROPY_RANGE[0]), ANISOTROPY_RANGE[1])
    if g_cycles != g:
        warnings.append("g = %g is clamped by Cycles to [0, 0.9] (svm/closure.h): phase function differs" % g)
    if g != 0.0:
        warnings.append("g != 0: after %d bounces Cycles switches to isotropic scattering with sigma_s (1 - g) "
                        "(SUBSURFACE_RANDOM_WALK_SIMILARITY_LEVEL), Lucent keeps Henyey-Greenstein" % 9)
    for c in range(3):
        sa, ssp = float(sigma_a[c]), float(sigma_s_prime[c])
        sigma_s = ssp / (1.0 - g)                       # mm^-1, Lucent path.c
        sigma_t = sa + sigma_s
        alpha = sigma_s / sigma_t
        inv_d = scale_mm * ((1.0 - g_cycles) * sigma_t)  # Cycles: sigma_t = (1/d) / (1 - g)
        d = 1.0 / inv_d                                 # scene units
        r = d / FIXED_RADIUS_SCALE / subsurface         # undo bssrdf_setup_radius() and the Subsurface factor
        A, reachable = invert_remap(alpha, g_cycles)
        if not reachable:
            warnings.append("channel %d: alpha = %.9g exceeds Cycles' clamp %g (subsurface_random_walk_remap): "
                            "Cycles absorbs more" % (c, alpha, MAX_ALPHA))
        if alpha < MIN_ALPHA:
            warnings.append("channel %d: alpha = %.4g < %g: Cycles raises it to 0.2 and scales throughput by "
                            "alpha/0.2 (subsurface_random_walk_coefficients): not the same medium" % (c, alpha, MIN_ALPHA))
        if r * subsurface < BSSRDF_MIN_RADIUS:
            warnings.append("channel %d: radius %g < BSSRDF_MIN_RADIUS: Cycles renders it diffuse" % (c, r))
        if r > 100.0:
            warnings.append("channel %d: radius %g exceeds Blender's socket maximum 100: use a larger scale"
                            % (c, r))
        radius.append(r)
        colour.append(A)
        target["sigma_t"].append(scale_mm * sigma_t)
        target["sigma_s"].append(scale_mm * sigma_s)
        target["alpha"].append(alpha)
        target["sigma_t_prime"].append(scale_mm * (sa + ssp))
        target["alpha_prime"].append(ssp / (sa + ssp))
    ior = min(max(eta, IOR_RANGE[0]), IOR_RANGE[1])
    if ior != eta:
        warnings.append("eta %g is outside Cycles' Subsurface IOR clamp [1.01, 3.8]" % eta)
    # Subsurface IOR is unused by RANDOM_WALK_FIXED_RADIUS (bssrdf_setup_radius); set for completeness.
    principled = {
        "subsurface_method": "RANDOM_WALK_FIXED_RADIUS",
        "Base Color": tuple(colour),             # unused with Subsurface = 1; equal for safety
        "Subsurface": subsurface,
        "Subsurface Radius": tuple(radius),
        "Subsurface Color": tuple(colour),
        "Subsurface IOR": ior,
        "Subsurface Anisotropy": g_cycles,
        "Metallic": 0.0,
        "Specular": 0.0,                         # no microfacet layer (svm/closure.h: specular > cutoff)
        "Specular Tint": 0.0,
        "Roughness": 0.0,                        # zero retro-reflection lobe (bsdf_principled_diffuse.h)
        "Anisotropic": 0.0,
        "Sheen": 0.0,
        "Clearcoat": 0.0,
        "Transmission": 0.0,
        "IOR": max(eta, 1.0),
        "Emission Strength": 0.0,
        "Alpha": 1.0,
    }
    sss = {
        "falloff": "RANDOM_WALK_FIXED_RADIUS",
        "Color": tuple(colour),
        "Scale": 1.0,
        "Radius": tuple(r * subsurface for r in radius),
        "IOR": ior,
        "Anisotropy": g_cycles,
    }
    return {"principled": principled, "sss": sss, "target": target, "warnings": warnings}


# ---- Lucent's presets (parsed from the C table, so there is one source of truth) -------------------------------

def default_presets_path():
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.normpath(os.path.join(here, "..", "..", "..", "renderer", "core", "material_presets.c"))


def load_presets(path=None):
    """{name: {"sigma_s_prime": [3], "sigma_a": [3], "eta": x}} from renderer/core/material_presets.c."""
    text = open(path or default_presets_path()).read()
    num = r"([-+0-9.eE]+)"
    vec = r"\{\s*" + num + r"\s*,\s*" + num + r"\s*,\s*" + num + r"\s*\}"
    pat = re.compile(r'\{\s*"([a-z0-9_]+)"\s*,\s*' + vec + r"\s*,\s*" + vec + r"\s*,\s*" + num + r"\s*\}")
    presets = {}
    for m in pat.finditer(text):
        v = [float(x) for x in m.groups()[1:]]
        presets[m.group(1)] = {"sigma_s_prime": v[0:3], "sigma_a": v[3:6], "eta": v[6]}
    if not presets:
        raise RuntimeError("no presets found in " + (path or default_presets_path()))
    return presets


def material_from_scene(material, presets=None):
    """Lucent's scene "material" object -> (sigma_a, sigma_s_prime, eta, g), as scene_parse.c resolves it."""
    material = material or {"preset": "marble"}
    g = float(material.get("g", 0.0))
    if "preset" in material:
        p = (presets or load_presets())[material["preset"].lower()]
        return p["sigma_a"], p["sigma_s_prime"], p["eta"], g
    return material["sigma_a"], material["sigma_s_prime"], float(material.get("eta", 1.3)), g


# ---- self-test ----------------------------------------------------------------------------------------------------

def _f32(x):
    import struct
    return struct.unpack("f", struct.pack("f", x))[0]


def selftest():
    presets = load_presets()
    failures = 0
    # The fit must rise monotonically in A for the bisection (checked on a fine grid, for several g).
    for g in (0.0, 0.3, 0.6, 0.9):
        prev = -1.0
        for i in range(1, 20001):
            a = cycles_remap_alpha(i / 20000.0, g)
            if a < prev - 1e-15:
                print("FAIL: remap not monotonic at A=%g g=%g" % (i / 20000.0, g))
                failures += 1
                break
            prev = a
    # The research note's spot values at g = 0 (shared/research/translucency.md section 4.1).
    for A, want in ((0.05, 0.2161), (0.2, 0.6134), (0.5, 0.9137), (0.8, 0.99175), (0.9, 0.99923)):
        got = cycles_remap_alpha(A, 0.0)
        if abs(got - want) > 6e-5:
            print("FAIL: remap(%g) = %.6f, expected %.5f" % (A, got, want))
            failures += 1
    cases = [(name, 0.0, 1.0) for name in sorted(presets)] + [("marble", 0.0, 25.0), ("skin1", 0.0, 25.0),
                                                               ("skin1", 0.5, 10.0), ("marble", 0.8, 3.0)]
    for name, g, scale in cases:
        p = presets[name]
        res = convert(p["sigma_a"], p["sigma_s_prime"], p["eta"], g, scale)
        for node in ("principled", "sss"):
            worst_t = worst_a = worst_t32 = worst_a32 = 0.0
            exact = True
            for c in range(3):
                med = cycles_medium(node, res[node], c)
                t = res["target"]
                alpha_ok = MIN_ALPHA <= t["alpha"][c] <= MAX_ALPHA
                exact &= alpha_ok
                et = abs(med["sigma_t"] - t["sigma_t"][c]) / t["sigma_t"][c]
                ea = abs(med["alpha"] - t["alpha"][c])
                if g == 0.0:   # the brief's quantities: sigma_t' = 1/d and alpha'
                    d = res[node]["Radius" if node == "sss" else "Subsurface Radius"][c] * FIXED_RADIUS_SCALE
                    if node == "principled":
                        d *= res[node]["Subsurface"]
                    et = max(et, abs(1.0 / d - t["sigma_t_prime"][c]) / t["sigma_t_prime"][c])
                    ea = max(ea, abs(med["alpha"] - t["alpha_prime"][c]))
                # What Blender actually stores: float32 socket values.
                s32 = dict(res[node])
                for key in ("Color", "Radius", "Subsurface Color", "Subsurface Radius", "Base Color"):
                    if key in s32:
                        s32[key] = tuple(_f32(x) for x in s32[key])
                m32 = cycles_medium(node, s32, c)
                if alpha_ok:
                    worst_t, worst_a = max(worst_t, et), max(worst_a, ea)
                    worst_t32 = max(worst_t32, abs(m32["sigma_t"] - t["sigma_t"][c]) / t["sigma_t"][c])
                    worst_a32 = max(worst_a32, abs(m32["alpha"] - t["alpha"][c]))
            ok = worst_t <= 1e-6 and worst_a <= 1e-6
            failures += not ok
            if node == "sss":
                print("%-4s %-10s g=%.1f scale=%-4g  max rel err sigma_t %.1e, abs err alpha %.1e "
                      "(float32 sockets: %.1e, %.1e)%s" % ("ok" if ok else "FAIL", name, g, scale, worst_t, worst_a,
                                                            worst_t32, worst_a32,
                                                            "" if exact else "  [clamped channel(s) not compared]"))
        for w in res["warnings"]:
            print("       warning: " + w)
    for name in ("marble", "skin1"):
        p = presets[name]
        for scale in (1.0, 25.0):
            res = convert(p["sigma_a"], p["sigma_s_prime"], p["eta"], 0.0, scale)
            print("\n%s (sigma_a %s, sigma_s' %s mm^-1, eta %g, g 0), scale_mm = %g:" % (
                name, p["sigma_a"], p["sigma_s_prime"], p["eta"], scale))
            print(format_settings(res))
    print("\nselftest: %s" % ("PASS" if failures == 0 else "%d FAILURE(S)" % failures))
    return failures == 0


def format_settings(res):
    pr, t = res["principled"], res["target"]
    lines = [
        "  Principled BSDF: subsurface_method %s, Subsurface %g, Subsurface Radius (%s) scene units," % (
            pr["subsurface_method"], pr["Subsurface"], ", ".join("%.6g" % r for r in pr["Subsurface Radius"])),
        "    Subsurface Color = Base Color (%s), Subsurface IOR %g (unused by this method), Subsurface Anisotropy %g," % (
            ", ".join("%.6f" % a for a in pr["Subsurface Color"]), pr["Subsurface IOR"], pr["Subsurface Anisotropy"]),
        "    Specular 0, Roughness 0, Metallic 0, Sheen 0, Clearcoat 0, Transmission 0",
        "  Subsurface Scattering node: falloff %s, Scale 1, Radius = the same, Color = the same" % res["sss"]["falloff"],
        "  medium (scene units): sigma_t' = (%s), alpha' = (%s)" % (
            ", ".join("%.6g" % x for x in t["sigma_t_prime"]), ", ".join("%.6f" % x for x in t["alpha_prime"])),
    ]
    lines += ["  warning: " + w for w in res["warnings"]]
    return "\n".join(lines)


def main(argv):
    if len(argv) > 1 and argv[1] == "--selftest":
        return 0 if selftest() else 1
    if len(argv) == 3 and argv[1] == "--preset":
        p = load_presets()[argv[2]]
        print(format_settings(convert(p["sigma_a"], p["sigma_s_prime"], p["eta"])))
        return 0
    print("usage: jensen_to_cycles.py --selftest | --preset NAME   (module: convert(...))", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
