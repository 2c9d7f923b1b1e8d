#!/usr/bin/env bash
# test_cli.sh - drives lucent-render as a user would: renders builtins and the bunny to PNG and EXR,
# decodes the results with oiiotool, and checks exit codes and messages for bad input.
set -u
bin=$1
bunny=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
passed=0 failed=0

check() {  # check DESCRIPTION COMMAND...
    local what=$1; shift
    if "$@"; then echo "ok   $what"; passed=$((passed + 1)); else echo "FAIL $what"; failed=$((failed + 1)); fi
}

# expect_exit CODE PATTERN ARGS...: runs lucent-render, wants that exit code and PATTERN on stderr.
expect_exit() {
    local code=$1 pattern=$2; shift 2
    "$bin" "$@" >"$dir/out" 2>"$dir/err"
    local rc=$?
    echo "     exit $rc: $(head -c 200 "$dir/err" | head -n 1)"
    [[ $rc -eq $code ]] && grep -q -- "$pattern" "$dir/err"
}

image_is() {  # image_is FILE WIDTH HEIGHT CHANNELS
    local info
    info=$(oiiotool --info "$1" 2>&1) || return 1
    echo "     $info"
    info=$(tr -s ' ' <<<"$info")
    [[ $info == *"$2 x $3, $4 channel"* ]]
}

scene() {  # scene MESH_JSON METHOD
    printf '{"mesh":%s,"width":64,"height":48,"projection_size":64,"method":"%s"}' "$1" "$2"
}

for mesh in sphere torus protrusion; do
    for method in five single; do
        scene "{\"builtin\":\"$mesh\"}" "$method" > "$dir/s.json"
        check "$mesh/$method renders a 64x48 RGBA PNG" \
            bash -c "'$bin' '$dir/s.json' -o '$dir/$mesh-$method.png' && $(declare -f image_is); image_is '$dir/$mesh-$method.png' 64 48 4"
    done
done

scene "{\"file\":\"$bunny\"}" five > "$dir/bunny.json"
check "bunny renders to EXR with AOV channels" \
    bash -c "'$bin' '$dir/bunny.json' -o '$dir/bunny.exr' && oiiotool --info -v '$dir/bunny.exr' | tee '$dir/exr.txt' | head -n 3 && grep -q 'N.X' '$dir/exr.txt' && grep -q 'view' '$dir/exr.txt' && grep -q 'Z' '$dir/exr.txt'"
scene "{\"file\":\"$bunny\"}" single > "$dir/bunny1.json"
check "bunny renders single-view to PNG" "$bin" "$dir/bunny1.json" -o "$dir/bunny1.png"

check "--stats prints pass times and what was modelled" \
    bash -c "'$bin' '$dir/s.json' -o '$dir/x.png' --stats > '$dir/stats.json' && cat '$dir/stats.json' && grep -q '\"scatter\"' '$dir/stats.json' && grep -q '\"modelled\"' '$dir/stats.json'"
check "method reference renders to EXR with AOVs and reports its convergence" \
    bash -c "printf '{\"mesh\":{\"builtin\":\"sphere\"},\"width\":32,\"height\":24,\"method\":\"reference\"}' > '$dir/ref.json' && '$bin' '$dir/ref.json' -o '$dir/reference.exr' --stats | tee '$dir/ref.stats' | head -c 400 && echo && grep -q 'estimated_rel_error' '$dir/ref.stats' && $(declare -f image_is); image_is '$dir/reference.exr' 32 24 10"
check "--compare against the same render reports zero error" \
    bash -c "'$bin' '$dir/s.json' -o '$dir/ref.exr' && '$bin' '$dir/s.json' -o '$dir/again.png' --compare '$dir/ref.exr' > '$dir/cmp.json' && cat '$dir/cmp.json' && grep -q '\"rel_l2\":0,' '$dir/cmp.json' && grep -q 'silhouette_band' '$dir/cmp.json'"
check "--compare with a missing reference: exit 1" expect_exit 1 "cannot compare" "$dir/s.json" -o "$dir/x.png" --compare "$dir/none.exr"
check "scene from standard input" bash -c "'$bin' - -o '$dir/stdin.png' < '$dir/s.json'"

check "LUCENT_DEVICE picks the device by name" \
    bash -c "LUCENT_DEVICE=llvmpipe '$bin' '$dir/s.json' -o '$dir/dev.png' --verbose 2>&1 | grep -q 'device \"llvmpipe'"
check "LUCENT_DEVICE naming no device: exit 1" env LUCENT_DEVICE=no-such-gpu bash -c \
    "$(declare -f expect_exit); bin='$bin' dir='$dir' expect_exit 1 'no-such-gpu' '$dir/s.json' -o '$dir/x.png'"
check "no arguments: usage, exit 2" expect_exit 2 "usage" 
check "unknown flag: exit 2" expect_exit 2 "unexpected argument" "$dir/s.json" -o "$dir/x.png" --frobnicate
check "output extension must be png or exr: exit 2" expect_exit 2 ".png or .exr" "$dir/s.json" -o "$dir/x.jpg"
check "missing scene file: exit 2" expect_exit 2 "cannot read scene" "$dir/nope.json" -o "$dir/x.png"
echo '{"width": -3}' > "$dir/bad.json"
check "invalid field is named: exit 2" expect_exit 2 "width" "$dir/bad.json" -o "$dir/x.png"
echo '{"width": 64,' > "$dir/bad.json"
check "malformed JSON: exit 2" expect_exit 2 "invalid scene" "$dir/bad.json" -o "$dir/x.png"
echo '{"mesh":{"file":"/nonexistent/mesh.obj"},"width":32,"height":32}' > "$dir/bad.json"
check "missing mesh file: exit 1 naming mesh.file" expect_exit 1 "mesh.file" "$dir/bad.json" -o "$dir/x.png"
printf 'solid x\nendsolid x\n' > "$dir/empty.stl"
echo "{\"mesh\":{\"file\":\"$dir/empty.stl\"},\"width\":32,\"height\":32}" > "$dir/bad.json"
check "mesh without triangles: exit 1" expect_exit 1 "mesh" "$dir/bad.json" -o "$dir/x.png"
check "unwritable output: exit 1" expect_exit 1 "cannot write" "$dir/s.json" -o "/nonexistent-dir/x.png"

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
