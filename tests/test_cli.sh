#!/usr/bin/env bash
# test_cli.sh - drives lucent-render as a user would: renders builtins and the bunny to PNG and EXR,
# decodes the results with oiiotool, checks --stats, --compare (once and twice, with --twin), --backend and
# --device, and exit codes and messages for bad input.
# Every run goes through render(), which shows the run's whole standard error: ctest runs this script under the
# validation layer and fails it on any "vulkan validation" or "opengl validation" line, and the last check
# here counts those lines too, so that a report cannot hide in a captured stream.
set -u
bin=$1
bunny=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
unset LUCENT_DEVICE LUCENT_BACKEND # the device and backend checks set them themselves
passed=0 failed=0 runs=0 reports=0

check() {  # check DESCRIPTION COMMAND...
    local what=$1; shift
    if "$@"; then echo "ok   $what"; passed=$((passed + 1)); else echo "FAIL $what"; failed=$((failed + 1)); fi
}

# render ARGS...: runs lucent-render with stdout to $dir/out and stderr to $dir/err; sets and returns $rc
# and echoes the exit status and every line of stderr.
render() {
    "$bin" "$@" >"$dir/out" 2>"$dir/err"
    rc=$?
    runs=$((runs + 1))
    reports=$((reports + $(grep -cE 'vulkan validation (warning|error)|opengl validation [a-z]+: ' "$dir/err")))
    echo "     exit $rc"
    sed 's/^/     stderr: /' "$dir/err"
    return $rc
}

# expect_exit CODE PATTERN ARGS...: runs lucent-render, wants that exit code and PATTERN on stderr.
expect_exit() {
    local code=$1 pattern=$2; shift 2
    render "$@"
    [[ $rc -eq $code ]] && grep -q -- "$pattern" "$dir/err"
}

image_is() {  # image_is FILE WIDTH HEIGHT CHANNELS
    local info
    info=$(oiiotool --info "$1" 2>&1) || return 1
    echo "     $info"
    info=$(tr -s ' ' <<<"$info")
    [[ $info == *"$2 x $3, $4 channel"* ]]
}

scene() {  # scene MESH_JSON METHOD [MORE_FIELDS]
    printf '{"mesh":%s,"width":64,"height":48,"projection_size":64,"method":"%s"%s}' "$1" "$2" "${3:+,$3}"
}

# stats_are METHOD VIEWS SHADOW: the --stats JSON of the last run (with --verbose) names the device that
# --verbose logged, has every documented pass time (a number, >= 0, none above the total), and says what
# was modelled: METHOD, VIEWS views, and for the one light SHADOW ("shadow map" or "skipped...").
stats_are() {
    python3 - "$dir/out" "$dir/err" "$@" <<'PY'
import json, math, re, sys
out, err, method, views, shadow = sys.argv[1:]
s = json.load(open(out))
logged = re.search(r'device "([^"]*)"', open(err).read())
ms, m = s["ms"], s["modelled"]
print(f'     device "{s["device"]}" (--verbose: "{logged and logged[1]}"), ms {ms}, method {m["method"]}, '
      f'views {s["views"]}/{m["views"]}, shadows {m["shadows"]}, shadow_maps {s["shadow_maps"]}')
times_ok = all(isinstance(ms.get(k), (int, float)) and math.isfinite(ms[k]) and 0 <= ms[k] <= ms["total"]
               for k in ("shadow", "projection", "gbuffer", "scatter", "mesh_load", "readback", "total"))
sys.exit(0 if logged and s["device"] == logged[1] and times_ok and ms["scatter"] > 0 and m["method"] == method
         and s["views"] == m["views"] == int(views) and len(m["shadows"]) == 1 and m["shadows"][0].startswith(shadow)
         and s["shadow_maps"] == (shadow == "shadow map") else 1)
PY
}

# compare_in LO HI: the last run's --compare JSON has rel L2 in [LO, HI], over the whole image and over
# the silhouette band, on covered pixels with no coverage mismatch.
compare_in() {
    python3 - "$dir/out" "$@" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))["compare"]
lo, hi = map(float, sys.argv[2:])
band = c["silhouette_band"]
print(f'     rel_l2 {c["rel_l2"]} (band {band["rel_l2"]}) over {c["pixels"]} pixels ({band["pixels"]} in the band), '
      f'coverage mismatch {c["coverage_mismatch"]}; wanted [{lo}, {hi}]')
sys.exit(0 if c["pixels"] > 0 and band["pixels"] > 0 and c["coverage_mismatch"] == 0
         and lo <= c["rel_l2"] <= hi and lo <= band["rel_l2"] <= hi else 1)
PY
}

# without_noise_is REL NOISE WIDTH: the last run's "without_noise" (--compare twice) has rel L2 and noise at
# these values (within 1e-4), and an interval holding REL no wider than WIDTH.
without_noise_is() {
    python3 - "$dir/out" "$@" <<'PY'
import json, sys
n = json.load(open(sys.argv[1]))["without_noise"]
rel, noise, width = map(float, sys.argv[2:])
print(f'     without_noise {n}; wanted rel_l2 {rel}, noise {noise}, interval at most {width} wide')
sys.exit(0 if abs(n["rel_l2"] - rel) < 1e-4 and abs(n["noise"] - noise) < 1e-4 and n["low"] <= rel <= n["high"]
         and n["high"] - n["low"] <= width else 1)
PY
}

shadow_of() { [[ $1 == sphere ]] && echo "skipped: mesh is convex" || echo "shadow map"; }
for mesh in sphere torus protrusion; do
    for method in five single; do
        scene "{\"builtin\":\"$mesh\"}" "$method" >"$dir/$mesh-$method.json"
        render "$dir/$mesh-$method.json" -o "$dir/$mesh-$method.png" --stats --verbose
        check "$mesh/$method renders a 64x48 RGBA PNG" \
            eval '[[ $rc -eq 0 ]] && image_is "$dir/$mesh-$method.png" 64 48 4'
        [[ $method == five ]] && views=5 || views=1
        check "$mesh/$method --stats: device, every pass time, $views view(s), light: $(shadow_of $mesh)" \
            stats_are "$method" "$views" "$(shadow_of $mesh)"
    done
done

exr_has_aovs() {  # exr_has_aovs FILE
    oiiotool --info -v "$1" >"$dir/exr.txt" 2>&1 || return 1
    head -n 3 "$dir/exr.txt"
    grep -q 'N.X' "$dir/exr.txt" && grep -q 'view' "$dir/exr.txt" && grep -q 'Z' "$dir/exr.txt"
}
scene "{\"file\":\"$bunny\"}" five >"$dir/bunny.json"
check "bunny renders to EXR with AOV channels" \
    eval 'render "$dir/bunny.json" -o "$dir/bunny.exr" && exr_has_aovs "$dir/bunny.exr"'
scene "{\"file\":\"$bunny\"}" single >"$dir/bunny1.json"
check "bunny renders single-view to PNG" render "$dir/bunny1.json" -o "$dir/bunny1.png"

# The reference is the protrusion scene the fast methods rendered above, so --compare can use it.
scene '{"builtin":"protrusion"}' reference >"$dir/reference.json"
check "method reference renders to EXR with AOVs and reports its convergence" \
    eval 'render "$dir/reference.json" -o "$dir/reference.exr" --stats && head -c 400 "$dir/out" && echo &&
          grep -q estimated_rel_error "$dir/out" && image_is "$dir/reference.exr" 64 48 10'
five=$dir/protrusion-five.json
render "$five" -o "$dir/five.exr"
check "--compare against the same render reports zero error" \
    eval 'render "$five" -o "$dir/again.png" --compare "$dir/five.exr" && compare_in 0 0'
# Exposure 1 doubles the reference's radiance, so the error of the exposure-0 render is exactly
# |x - 2x| / |2x| = 0.5 everywhere (1.0 if image and reference were swapped).
scene '{"builtin":"protrusion"}' five '"exposure":1' >"$dir/bright.json"
render "$dir/bright.json" -o "$dir/bright.exr"
check "--compare against the same render at exposure 1 reports rel L2 0.5" \
    eval 'render "$five" -o "$dir/x.png" --compare "$dir/bright.exr" && compare_in 0.4999 0.5001'
# five against reference on this scene measured 0.035 (band 0.032). The range, a seventh to three times that, leaves
# room for changes to the scatter pass and still catches a comparison with the wrong image.
# Twice: two estimates of a truth, here both exactly the bright render, so there is no noise and the error
# without it is 0.5 as above. Its interval is not empty: the error differs from pixel to pixel, so the 64
# lattices' sums differ a little (measured 0.493-0.507; subsets of whole columns gave 0.409-0.577).
check "--compare given twice reports the error without noise: 0.5, noise 0, interval holding 0.5 within 0.03" \
    eval 'render "$five" -o "$dir/x.png" --compare "$dir/bright.exr" --compare "$dir/bright.exr" &&
          without_noise_is 0.5 0 0.03'
# --twin: the render's own second estimate, here the same five render written before, so the mean is that
# render and both sides' noise is 0: the same 0.5, and "test_noise" 0.
check "--twin with --compare twice: the error without both sides' noise 0.5, test_noise 0" \
    eval 'render "$five" -o "$dir/x.png" --compare "$dir/bright.exr" --compare "$dir/bright.exr" --twin "$dir/five.exr" &&
          without_noise_is 0.5 0 0.03 && grep -q "\"test_noise\":0}" "$dir/out"'
check "--twin without --compare twice: exit 2" expect_exit 2 "needs --compare twice" "$five" -o "$dir/x.png" \
    --compare "$dir/bright.exr" --twin "$dir/five.exr"
check "--compare a third time: exit 2" expect_exit 2 "unexpected argument" "$five" -o "$dir/x.png" \
    --compare "$dir/bright.exr" --compare "$dir/bright.exr" --compare "$dir/bright.exr"
check "--compare five against reference: rel L2 in [0.005, 0.11] (measured 0.035)" \
    eval 'render "$five" -o "$dir/x.png" --compare "$dir/reference.exr" && compare_in 0.005 0.11'
check "--compare with a missing reference: exit 1" \
    expect_exit 1 "cannot compare" "$five" -o "$dir/x.png" --compare "$dir/none.exr"
check "scene from standard input" render - -o "$dir/stdin.png" <"$five"

check "LUCENT_DEVICE picks the device by name" \
    eval 'LUCENT_DEVICE=llvmpipe render "$five" -o "$dir/dev.png" --verbose && grep -q "device \"llvmpipe" "$dir/err"'
check "LUCENT_DEVICE naming no device: exit 1" \
    eval 'LUCENT_DEVICE=no-such-gpu expect_exit 1 no-such-gpu "$five" -o "$dir/x.png"'
check "--device picks the device by name, over LUCENT_DEVICE" \
    eval 'LUCENT_DEVICE=no-such-gpu render "$five" -o "$dir/dev.png" --device llvmpipe --verbose &&
          grep -q "device \"llvmpipe" "$dir/err"'
check "--device naming no device: exit 1" expect_exit 1 '"no-such-gpu"' "$five" -o "$dir/x.png" --device no-such-gpu
check "--device longer than the device registry holds (200 bytes): exit 1" \
    expect_exit 1 "at most 127 bytes" "$five" -o "$dir/x.png" --device "$(printf 'x%.0s' $(seq 1 200))"
# backend_is NAME: the --stats JSON of the last run names backend NAME, in its stats and in what it modelled.
backend_is() {
    python3 - "$dir/out" "$1" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f'     backend {s["backend"]}, modelled {s["modelled"].get("backend")}, device "{s["device"]}"')
sys.exit(0 if s["backend"] == sys.argv[2] == s["modelled"]["backend"] and s["device"] else 1)
PY
}
check "--backend gl renders through OpenGL and EGL; --stats names it" \
    eval 'render "$five" -o "$dir/gl.png" --backend gl --stats --verbose && backend_is gl &&
          grep -q "OpenGL device \"llvmpipe" "$dir/err" && image_is "$dir/gl.png" 64 48 4'
check "--backend vulkan: --stats names it" eval 'render "$five" -o "$dir/vk.png" --backend vulkan --stats && backend_is vulkan'
check "LUCENT_BACKEND=gl picks OpenGL, --backend overrides it" \
    eval 'LUCENT_BACKEND=gl render "$five" -o "$dir/x.png" --stats && backend_is gl &&
          LUCENT_BACKEND=gl render "$five" -o "$dir/x.png" --stats --backend vulkan && backend_is vulkan'
check "auto without a Vulkan driver falls back to OpenGL and says why" \
    eval 'VK_ICD_FILENAMES=/nonexistent render "$five" -o "$dir/x.png" --stats && backend_is gl &&
          grep -q "no Vulkan device (.*); trying OpenGL through EGL" "$dir/err"'
check "--backend vulkan without a Vulkan driver: exit 1, no fallback" \
    eval 'VK_ICD_FILENAMES=/nonexistent expect_exit 1 "vkCreateInstance" "$five" -o "$dir/x.png" --backend vulkan'
check "--backend gl --device picks the EGL device by its renderer's name" \
    eval 'render "$five" -o "$dir/x.png" --backend gl --device llvmpipe --stats && backend_is gl'
check "--backend gl --device naming no device: exit 1 listing the devices found" \
    expect_exit 1 'no OpenGL device named like "no-such-gpu" (found: "llvmpipe' "$five" -o "$dir/x.png" --backend gl \
    --device no-such-gpu
check "LUCENT_EGL_PLATFORM=surfaceless: OpenGL on Mesa's surfaceless platform, named with --verbose" \
    eval 'LUCENT_EGL_PLATFORM=surfaceless render "$five" -o "$dir/x.png" --backend gl --stats --verbose &&
          backend_is gl && grep -q "through EGL, platform surfaceless" "$dir/err"'
check "LUCENT_EGL_PLATFORM other than device or surfaceless: exit 1 naming it" \
    eval 'LUCENT_EGL_PLATFORM=x11 expect_exit 1 "LUCENT_EGL_PLATFORM must be device or surfaceless" "$five" -o "$dir/x.png" --backend gl'
check "--backend other than vulkan, gl, auto: exit 2" expect_exit 2 "vulkan, gl or auto" "$five" -o "$dir/x.png" \
    --backend metal
check "no arguments: usage, exit 2" expect_exit 2 "usage"
check "unknown flag: exit 2" expect_exit 2 "unexpected argument" "$five" -o "$dir/x.png" --frobnicate
check "output extension must be png or exr: exit 2" expect_exit 2 ".png or .exr" "$five" -o "$dir/x.jpg"
check "missing scene file: exit 2" expect_exit 2 "cannot read scene" "$dir/nope.json" -o "$dir/x.png"
echo '{"width": -3}' >"$dir/bad.json"
check "invalid field is named: exit 2" expect_exit 2 "width" "$dir/bad.json" -o "$dir/x.png"
echo '{"width": 64,' >"$dir/bad.json"
check "malformed JSON: exit 2" expect_exit 2 "invalid scene" "$dir/bad.json" -o "$dir/x.png"
echo '{"mesh":{"file":"/nonexistent/mesh.obj"},"width":32,"height":32}' >"$dir/bad.json"
check "missing mesh file: exit 1 naming mesh.file" expect_exit 1 "mesh.file" "$dir/bad.json" -o "$dir/x.png"
printf 'solid x\nendsolid x\n' >"$dir/empty.stl"
echo "{\"mesh\":{\"file\":\"$dir/empty.stl\"},\"width\":32,\"height\":32}" >"$dir/bad.json"
check "mesh without triangles: exit 1" expect_exit 1 "mesh" "$dir/bad.json" -o "$dir/x.png"
check "unwritable output: exit 1" expect_exit 1 "cannot write" "$five" -o "/nonexistent-dir/x.png"

check "no validation reports (Vulkan or OpenGL) on stderr in $runs runs ($reports found)" [ "$reports" = 0 ]

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
