#!/usr/bin/env bash
# test_client.sh - the lucent command-line client against real lucentd daemons on free loopback ports:
# renders to PNG/EXR (decoded), local meshes uploaded once (counted in the daemon's access log), the
# meshes/health/materials subcommands, -v, --scene with overrides, tokens, and every exit code.
# Usage: test_client.sh PATH/TO/lucentd PATH/TO/lucent BUNNY.obj
set -u
lucentd=$1
lucent=$2
bunny=$3
unset LUCENT_SERVER LUCENT_TOKEN_FILE

source "$(dirname "$0")/lucentd_harness.sh"

# run ARGS...: the client with stdout to $work/out and stderr to $work/err; sets $rc and echoes both briefly.
run() {
    "$lucent" "$@" >"$work/out" 2>"$work/err"
    rc=$?
    echo "     lucent $* -> exit $rc${1:+; stderr: $(head -c 300 "$work/err" | head -n 3 | tr '\n' '|')}"
}
# expect CODE PATTERN: the last run's exit code, and PATTERN (grep -E) on its stderr.
expect() { [[ $rc == "$1" ]] && grep -qE -- "$2" "$work/err"; }

# exr FILE W H: oiiotool decodes a float image of that size with the AOV channels and lit RGB.
exr() {
    local info stats
    info=$(oiiotool --info -v "$1" 2>&1) || { echo "     not an image: $info"; return 1; }
    stats=$(oiiotool --stats "$1" 2>&1 | grep -m1 'Max:')
    echo "     $(grep -m1 ' x ' <<<"$info"); $(grep -m1 'channel list' <<<"$info" | sed 's/^ *//'); $(sed "s/^ *//" <<<"$stats")"
    grep -qE ":  *$2 x  *$3, .*float" <<<"$info" && grep -q 'channel list: R, G, B, A, Z.*N.X' <<<"$info" &&
        awk '{ exit !($3 > 0 || $4 > 0 || $5 > 0) }' <<<"$stats"
}

posts() { grep -c ' POST /v1/meshes status=' "$1"; }
no_leftovers() { ! ls "$work"/*.tmp.* >/dev/null 2>&1; }

cube=$work/cube.obj
printf 'v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n' >"$cube"
printf 'f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n' >>"$cube"
cube_id=$(sha256sum "$cube" | cut -d' ' -f1)
fast=(--projection-size 128 --light-dir -1,0,0 --camera-dir 0,0,-1)  # head-on, lit from the right

# ---- daemon A: open ----
start A --store-dir "$work/store"
A=$base
A_log=$log
export LUCENT_SERVER=$A

run health
check "health: exit 0, alive and ready with the backend and device" \
    eval '[ $rc = 0 ] && grep -qE "^alive, ready: (vulkan|gl) device \"" "$work/out"' 
run materials
check "materials: exit 0, 12 presets in the table ($(grep -cE '^[a-z0-9]+ +[0-9]' "$work/out"))" \
    [ "$rc" = 0 -a "$(grep -cE '^[a-z0-9]+ +[0-9]' "$work/out")" = 12 ]
run materials --json
check "materials --json: the server's JSON, marble eta 1.5" python3 -c '
import json, sys
m = {x["name"]: x for x in json.load(open(sys.argv[1]))["materials"]}
sys.exit(0 if len(m) == 12 and abs(m["marble"]["eta"] - 1.5) < 1e-9 else 1)' "$work/out"

# Builtin mesh to PNG, EXR and standard output.
run render --mesh protrusion --preset marble "${fast[@]}" --size 96x80 -o "$work/a.png"
check "render builtin to PNG: exit 0, decoded 96x80" eval '[ $rc = 0 ] && pngs "$work/a.png:96:80"'
run render --mesh protrusion --preset marble "${fast[@]}" --size 96x80 -o "$work/a.exr"
check "render builtin to EXR (format from the extension): float 96x80 with AOVs" eval '[ $rc = 0 ] && exr "$work/a.exr" 96 80'
run render --mesh torus --preset skimmilk "${fast[@]}" --width 64 --height 72 --format exr -o -
check "render -o - --format exr: EXR bytes on stdout" eval '[ $rc = 0 ] && cp "$work/out" "$work/stdout.exr" && exr "$work/stdout.exr" 64 72'
check "no temp files left after successful renders" no_leftovers

# -v: what the server measured and modelled, and the request id.
run -v render --mesh sphere --preset skin1 --light-dir -1,0,0 --size 64x64 --method auto -o "$work/v.png"
check "-v prints Server-Timing with the passes" grep -qE '^lucent: Server-Timing: .*scatter;dur=' "$work/err"
check "-v prints Lucent-Modelled (what auto chose)" grep -qE '^lucent: Lucent-Modelled: \{.*"auto"' "$work/err"
check "-v prints the request id" grep -qE '^lucent: POST /v1/render -> 200 in [0-9]+ ms, request id [0-9a-f-]+' "$work/err"

# A local mesh file: uploaded once, then referenced by id.
before=$(posts "$A_log")
run -v render --mesh "$bunny" --preset marble "${fast[@]}" --size 64x64 -o "$work/bunny1.png"
first=$(( $(posts "$A_log") - before ))
check "local OBJ (bunny) rendered: 64x64 PNG, uploaded $first time(s)" eval '[ $rc = 0 ] && [ $first = 1 ] && pngs "$work/bunny1.png:64:64"'
run -v render --mesh "$bunny" --preset marble "${fast[@]}" --size 64x64 -o "$work/bunny2.png"
second=$(( $(posts "$A_log") - before - first ))
check "second render of the same file: $second more uploads, GET found it, same image" \
    eval '[ $rc = 0 ] && [ $second = 0 ] && grep -q "is stored as" "$work/err" && cmp -s "$work/bunny1.png" "$work/bunny2.png"'

# meshes upload / show / list / delete.
run meshes upload "$cube"
check "meshes upload: exit 0, id = sha256 of the file, 12 triangles" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
sys.exit(0 if d["id"] == sys.argv[2] and d["triangles"] == 12 else 1)' "$work/out" "$cube_id"
run meshes show "$cube_id"
check "meshes show ID: the metadata" eval '[ $rc = 0 ] && grep -q "\"vertices\"" "$work/out"'
run meshes show "$cube"
check "meshes show FILE: the same mesh by its sha256" eval '[ $rc = 0 ] && grep -q "$cube_id" "$work/out"'
run meshes list
check "meshes list: a JSON array of the stored meshes, the cube and the bunny among them" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
ids = [m["id"] for m in d]
sys.exit(0 if sys.argv[2] in ids and len(ids) >= 2 and ids == sorted(ids) and all("created" in m for m in d) else 1)' \
    "$work/out" "$cube_id"
before=$(posts "$A_log")
run render --mesh "$cube" --preset marble "${fast[@]}" --size 64x64 -o "$work/cube.png"
check "render of an already uploaded file: no upload" eval '[ $rc = 0 ] && [ $(posts "$A_log") = $before ] && pngs "$work/cube.png:64:64"'
run render --mesh "$cube_id" --preset marble "${fast[@]}" --size 64x64 -o "$work/cube_by_id.png"
check "render --mesh ID: the same image as by file" eval '[ $rc = 0 ] && cmp -s "$work/cube.png" "$work/cube_by_id.png"'
stored=$(curl -s -o /dev/null -w "%{http_code}" "$A/v1/meshes/$cube_id")
run meshes delete "$cube_id"
check "meshes delete: exit 0, the server answered $stored for it before and 404 now" \
    eval '[ $rc = 0 ] && [ $stored = 200 ] && [ $(curl -s -o /dev/null -w "%{http_code}" "$A/v1/meshes/$cube_id") = 404 ]' 
run meshes show "$cube_id"
check "meshes show after delete: exit 1, 404 naming mesh.id" expect 1 '^lucent: 404 .*mesh'
run render --mesh "$cube" --preset marble "${fast[@]}" --size 64x64 -o "$work/cube2.png"
check "render after delete uploads again ($(( $(posts "$A_log") - before )) upload)" \
    eval '[ $rc = 0 ] && [ $(( $(posts "$A_log") - before )) = 1 ] && pngs "$work/cube2.png:64:64"'

# A glTF whose buffer and texture are files beside it: upload sends them with it as a form (the daemon
# names the mesh by the three files' bundle), render finds it stored and draws it; one named file missing
# is the user's error before anything is sent.
gltf_dir=/usr/share/assimp/models/glTF2/BoxTextured-glTF
run -v meshes upload "$gltf_dir/BoxTextured.gltf"
check "meshes upload of a glTF with its buffer beside it: exit 0, 12 triangles, sent as a form" eval '[ $rc = 0 ] &&
    [ "$(json_field "$work/out" "[\"triangles\"]")" = 12 ] && grep -qi "multipart/form-data" "$work/err"'
before=$(posts "$A_log")
run render --mesh "$gltf_dir/BoxTextured.gltf" --preset marble "${fast[@]}" --size 48x48 -o "$work/box.png"
check "render --mesh the glTF: one form posted, answered as already stored, an image" \
    eval '[ $rc = 0 ] && [ $(( $(posts "$A_log") - before )) = 1 ] && pngs "$work/box.png:48:48"'
mkdir -p "$work/lonely" && cp "$gltf_dir/BoxTextured.gltf" "$work/lonely/"
run meshes upload "$work/lonely/BoxTextured.gltf"
check "a glTF whose buffer is missing beside it: exit 4 naming the file, nothing sent" \
    eval 'expect 4 "BoxTextured0.bin" && [ $(( $(posts "$A_log") - before )) = 1 ]'
sed 's|"BoxTextured0.bin"|"../BoxTextured0.bin"|' "$gltf_dir/BoxTextured.gltf" >"$work/lonely/up.gltf"
run meshes upload "$work/lonely/up.gltf"
check "a glTF naming a file outside its folder: exit 2, nothing sent" \
    eval 'expect 2 "not in its folder or below it" && [ $(( $(posts "$A_log") - before )) = 1 ]'

# --scene with overrides: the result equals the same scene given by flags alone.
cat >"$work/scene.json" <<JSON
{"mesh": {"builtin": "protrusion"}, "material": {"preset": "skin1"}, "lights": [{"direction": [0, -1, 0], "intensity": 2}],
 "width": 64, "height": 64, "projection_size": 128, "format": "exr"}
JSON
run render --scene "$work/scene.json" -o "$work/scene_only.png"
check "--scene alone: 64x64 (PNG from -o's extension over the file's format)" eval '[ $rc = 0 ] && pngs "$work/scene_only.png:64:64"'
run render --scene "$work/scene.json" --sigma-a 0.01,0.02,0.03 --sigma-s-prime 1,1.5,2 --light-dir -1,0,0 --size 80x72 -o "$work/scene_over.png"
run_over=$rc
run render --mesh protrusion --sigma-a 0.01,0.02,0.03 --sigma-s-prime 1,1.5,2 --light-dir -1,0,0 --size 80x72 --projection-size 128 -o "$work/flags.png"
check "--scene with overrides (coefficients replace the preset, lights replaced, size): same bytes as flags alone" \
    eval '[ $run_over = 0 ] && [ $rc = 0 ] && pngs "$work/scene_over.png:80:72" && cmp -s "$work/scene_over.png" "$work/flags.png"'
run render --scene "$work/scene.json" --light-intensity 8 -o "$work/brighter.png"
check "--light-intensity without a new light changes the scene's light (image differs)" \
    eval '[ $rc = 0 ] && pngs "$work/brighter.png:64:64" && ! cmp -s "$work/brighter.png" "$work/scene_only.png"'
printf '{"mesh": {"file": "%s"}, "width": 64, "height": 64, "projection_size": 128}' "$cube" >"$work/scene_file.json"
run render --scene "$work/scene_file.json" -o "$work/scene_file.png"
check "--scene with mesh.file uploads and renders it" eval '[ $rc = 0 ] && pngs "$work/scene_file.png:64:64"'

# Method path's flags: the same image as the same options in a --scene file, and the server modelled them.
path_flags=(--method path --path-samples 2 --path-boundary cycles --path-filter box --path-seed 7 --path-time 60)
cat >"$work/path.json" <<JSON
{"mesh": {"builtin": "sphere"}, "material": {"preset": "skin1"}, "lights": [{"direction": [-1, 0, 0], "intensity": 3}], "width": 32,
 "height": 32, "method": "path", "path": {"samples": 2, "boundary": "cycles", "filter": "box", "seed": 7, "time_s": 60}}
JSON
run -v render --mesh sphere --preset skin1 --light-dir -1,0,0 --light-intensity 3 --size 32x32 "${path_flags[@]}" -o "$work/path_flags.png"
check "--path-* flags: 32x32, Lucent-Modelled names method path with boundary cycles and filter box" \
    eval '[ $rc = 0 ] && pngs "$work/path_flags.png:32:32" &&
          grep -qE "^lucent: Lucent-Modelled: .*\"method\":\"path\".*\"boundary\":\"cycles\".*\"filter\":\"box\"" "$work/err"'
run render --scene "$work/path.json" -o "$work/path_scene.png"
check "the same options in a --scene file: the same bytes" \
    eval '[ $rc = 0 ] && cmp -s "$work/path_flags.png" "$work/path_scene.png"'
run render --scene "$work/path.json" --path-seed 8 -o "$work/path_seed.png"
check "--path-seed over the file's seed: another image" \
    eval '[ $rc = 0 ] && pngs "$work/path_seed.png:32:32" && ! cmp -s "$work/path_seed.png" "$work/path_scene.png"'
run render --mesh sphere --size 32x32 --method path --path-boundary glass -o "$work/x.png"
check "--path-boundary out of its set: exit 1, 400 naming path.boundary" expect 1 '^lucent: 400 .*path\.boundary'
run render --mesh sphere --size 32x32 --method path --path-samples 0 -o "$work/x.png"
check "--path-samples 0: exit 1, 400 naming path.samples" expect 1 '^lucent: 400 .*path\.samples'
run render --mesh sphere --size 32x32 --method path --path-samples two -o "$work/x.png"
check "--path-samples not an integer: exit 2 before anything is sent" expect 2 '--path-samples'

# Errors: exit codes and messages; no output file on failure.
run render --bogus -o "$work/x.png"
check "unknown flag: exit 2, names it" expect 2 "unknown option '--bogus'"
run render --light-dir 1,2 -o "$work/x.png"
check "malformed vector: exit 2" expect 2 '--light-dir: expected 3 comma-separated numbers'
run render --mesh sphere
check "missing -o: exit 2" expect 2 '-o OUT is required'
run frobnicate
check "unknown command: exit 2" expect 2 "unknown command 'frobnicate'"
run render --sigma-a 1,-1,1 --sigma-s-prime 1,1,1 --size 64x64 -o "$work/x.png"
check "400 from the server: exit 1, status and field in the message" expect 1 '^lucent: 400 Invalid request: material\.sigma_a\[1\]: '
run render --mesh sphere --size 4000x64 -o "$work/x.png"
check "413 from the server: exit 1, names width" expect 1 '^lucent: 413 .*: width: '
check "no output file and no temp file after server errors" eval '[ ! -e "$work/x.png" ] && no_leftovers'
run render --mesh "$work/missing.obj" -o "$work/x.png"
check "missing local mesh file: exit 4, names it" expect 4 "cannot open $work/missing.obj"
run render --mesh sphre -o "$work/x.png"
check "misspelt built-in: exit 4, lists the built-ins" expect 4 'not a built-in mesh \(sphere, torus, protrusion, bunny\)'
run render --scene "$work/nope.json" -o "$work/x.png"
check "missing --scene file: exit 4" expect 4 "cannot open $work/nope.json"
run render --mesh sphere --size 64x64 -o "$work/no/such/dir/x.png"
check "unwritable output: exit 4" expect 4 'cannot write'
run --server http://127.0.0.1:1 health
check "unreachable server: exit 3, says so and how to point elsewhere" expect 3 'cannot reach the server at http://127.0.0.1:1: .*--server or LUCENT_SERVER'
run --server ftp://example render -o "$work/x.png"
check "non-http --server: exit 2" expect 2 'expected an http'

# --help everywhere.
for c in "" render meshes health materials; do
    run $c --help
    check "lucent${c:+ $c} --help: exit 0, usage on stdout" eval '[ $rc = 0 ] && grep -q "^Usage: lucent" "$work/out"'
done
run render --help
check "render --help lists --sigma-s-prime, --light-pos, --camera-up, --background, --profile, --path-samples" \
    eval 'grep -q -- --sigma-s-prime "$work/out" && grep -q -- --light-pos "$work/out" && grep -q -- --camera-up "$work/out" && grep -q -- --background "$work/out" && grep -q -- --profile "$work/out" && grep -q -- --path-samples "$work/out"'

# ---- daemon B: token required ----
echo "s3cret-token" >"$work/token"
echo "wrong" >"$work/wrong"
start B --store-dir "$work/storeB" --token-file "$work/token"
export LUCENT_SERVER=$base
run materials
check "token daemon without --token-file: exit 1, 401 naming Authorization" expect 1 '^lucent: 401 .*Authorization'
run --token-file "$work/wrong" materials
check "wrong token: exit 1, 401" expect 1 '^lucent: 401 '
run --token-file "$work/token" materials
check "--token-file: exit 0, the 12 presets" eval '[ $rc = 0 ] && [ $(grep -cE "^[a-z0-9]+ +[0-9]" "$work/out") = 12 ]' 
LUCENT_TOKEN_FILE=$work/token run render --mesh "$cube" "${fast[@]}" --size 64x64 -o "$work/token.png"
check "LUCENT_TOKEN_FILE: upload and render with the token" eval '[ $rc = 0 ] && pngs "$work/token.png:64:64"'
run render --token-file "$work/absent" --mesh sphere -o "$work/x.png"
check "missing token file: exit 4" expect 4 'token-file: cannot open'

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
