#!/usr/bin/env bash
# test_lucentd.sh - lucentd over HTTP with curl: every endpoint, every error status with its problem+json
# body, caching, CORS, meshes of every format across a restart, importers that crash or hang, 32 parallel
# renders, a full queue, deadlines, the server's limits and SIGTERM with and without a drain deadline.
# Usage: test_lucentd.sh PATH/TO/lucentd PATH/TO/hostile_importer (tests/hostile_importer.c: an importer that
# misbehaves as the upload's first line says). Images are decoded and checked for size and content
# (tests/check_png.py). Waits are on observable state (/metrics, /readyz, log lines), each with a generous
# outer limit, never on a fixed sleep.
set -u
lucentd=$1
hostile_importer=$2
source "$(dirname "$0")/lucentd_harness.sh"

# exr FILE W H: oiiotool decodes it as a float image of that size.
exr() {
    local info
    info=$(oiiotool --info "$1" 2>&1) || { echo "   not an image: $info"; return 1; }
    echo "   $info"
    [[ $info =~ :\ +$2\ x\ +$3,.*float ]]
}

# logged_before LOG A B: the first line matching A comes before the first line matching B.
logged_before() {
    local a b
    a=$(grep -n -m1 -e "$2" "$1" | cut -d: -f1); b=$(grep -n -m1 -e "$3" "$1" | cut -d: -f1)
    echo "   log lines: \"$2\" at ${a:-none}, \"$3\" at ${b:-none}"
    [[ -n $a && -n $b ]] && (( a < b ))
}

# A closed cube, and an OBJ with vertices but no faces.
cube=$work/cube.obj
printf 'v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n' >"$cube"
printf 'f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n' >>"$cube"
tetra=$work/tetra.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$tetra"
printf 'v 0 0 0\nv 1 0 0\n' >"$work/nofaces.obj"
fast='projection_size=128'
scene_json='{"mesh":{"builtin":"protrusion"},"material":{"preset":"marble"},"lights":[{"direction":[-1,0,0]}],"width":96,"height":80,"projection_size":128}'
scene_query="mesh=protrusion&preset=marble&light_dir=-1,0,0&w=96&h=80&$fast"

# The image check itself must be able to fail: a fully covered image of RGB 3 and a 64x64 image with one
# white pixel, each a valid PNG of the right size.
python3 - "$work" <<'EOF2'
import struct, sys, zlib
def png(path, w, h, pixel):
    raw = b"".join(b"\0" + b"".join(pixel(x, y) for x in range(w)) for y in range(h))
    chunk = lambda kind, body: struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
                           chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
png(sys.argv[1] + "/dark.png", 64, 64, lambda x, y: b"\3\3\3\xff")
png(sys.argv[1] + "/dot.png", 64, 64, lambda x, y: b"\xff\xff\xff\xff" if (x, y) == (32, 32) else b"\0\0\0\0")
EOF2
pngs "$work/dark.png:64:64"; dark=$?
pngs "$work/dot.png:64:64"; dot=$?
check "check_png.py refuses a near-black image ($dark) and a one-pixel image ($dot)" [ $dark = 1 -a $dot = 1 ]

# ---- daemon A: no image cache (so GET and POST both render), CORS for one origin, small limits ----
store=$work/store
start A --store-dir "$store" --cache-bytes 0 --queue-length 40 --cors-origins 'https://app.example' \
    --max-width 1024 --max-triangles 100000 --max-body-bytes 65536
A=$base
A_pid=$pid

c=$(req "$work/h" GET "$A/healthz"); check "healthz 200 ($c)" [ "$c" = 200 ]
c=$(req "$work/r" GET "$A/readyz"); check "readyz 200 ($c) names the backend and device" grep -qE '"backend": ?"(vulkan|gl)".*"device"' "$work/r"
c=$(req "$work/o" GET "$A/openapi.json")
check "openapi.json 200 ($c), OpenAPI 3 with every route" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
need = {"/v1/render", "/v1/meshes", "/v1/meshes/{id}", "/v1/materials", "/healthz", "/readyz", "/metrics", "/openapi.json"}
sys.exit(0 if d["openapi"].startswith("3.") and need <= set(d["paths"]) else 1)' "$work/o"
c=$(req "$work/m" GET "$A/v1/materials")
check "materials 200 ($c): 12 presets, marble has coefficients" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))["materials"]
m = [x for x in d if x["name"] == "marble"][0]
print("   %d presets; marble sigma_a %s" % (len(d), m["sigma_a"]))
sys.exit(0 if len(d) == 12 and len(m["sigma_a"]) == 3 and m["eta"] > 1 else 1)' "$work/m"

# Render: GET and POST of one scene are byte-identical (both rendered: no cache on A).
t0=$(date +%s%N)
c=$(req "$work/get.png" GET "$A/v1/render?$scene_query")
t1=$(date +%s%N)
echo "   GET render took $(( (t1 - t0) / 1000000 )) ms; Server-Timing: $(header "$work/get.png" Server-Timing)"
check "GET /v1/render 200 ($c) image/png" [ "$(header "$work/get.png" Content-Type)" = image/png ]
check "GET render is a 96x80 lit PNG" pngs "$work/get.png:96:80"
c=$(req "$work/post.png" POST "$A/v1/render" -H 'Content-Type: application/json' -d "$scene_json")
check "POST /v1/render 200 ($c)" [ "$c" = 200 ]
check "GET and POST give byte-identical images" cmp -s "$work/get.png" "$work/post.png"
etag=$(header "$work/get.png" ETag)
check "GET and POST give the same strong ETag ($etag)" [ "$etag" = "$(header "$work/post.png" ETag)" -a "${etag:0:1}" = '"' ]
check "Cache-Control immutable" grep -qi '^cache-control: public, max-age=31536000, immutable' "$work/get.png.h"
check "Server-Timing has queue, passes and encode" grep -qiE '^server-timing: queue;dur=.*projection;dur=.*scatter;dur=.*encode;dur=' "$work/get.png.h"
check "Lucent-Modelled is the renderer's JSON" python3 -c 'import json,sys; d=json.loads(sys.argv[1]); sys.exit(0 if "method" in d else 1)' "$(header "$work/get.png" Lucent-Modelled)"
c=$(req "$work/id.png" GET "$A/v1/render?$scene_query" -H 'X-Request-Id: test-id-42')
check "request id echoed and logged" [ "$(header "$work/id.png" X-Request-Id)" = test-id-42 ]
long_id=$(printf 'r%.0s' $(seq 1 64))
c=$(req "$work/id" GET "$A/v1/render?w=abc" -H "X-Request-Id: $long_id")
check "a 64-character request id is the problem's instance in full ($c)" \
    [ "$(json_field "$work/id" '["instance"]')" = "urn:lucent:request:$long_id" -a "$(header "$work/id" X-Request-Id)" = "$long_id" ]
renders_before=$(METRIC='lucentd_render_seconds_count{method="five"}' metric "$A/metrics")
c=$(req "$work/304" GET "$A/v1/render?$scene_query" -H "If-None-Match: $etag")
check "If-None-Match -> 304 ($c), empty body, same ETag" [ "$c" = 304 -a ! -s "$work/304" -a "$(header "$work/304" ETag)" = "$etag" ]
renders_after=$(METRIC='lucentd_render_seconds_count{method="five"}' metric "$A/metrics")
check "304 rendered nothing (render count $renders_before -> $renders_after)" [ "$renders_before" = "$renders_after" ]
c=$(req "$work/exr" GET "$A/v1/render?$scene_query" -H 'Accept: image/x-exr')
check "Accept: image/x-exr -> 200 ($c) image/x-exr" [ "$(header "$work/exr" Content-Type)" = image/x-exr ]
check "EXR decodes as 96x80 float" exr "$work/exr" 96 80
c=$(req "$work/fmt" GET "$A/v1/render?$scene_query&format=exr" -H 'Accept: image/*')
check "format=exr with Accept image/* -> 200 ($c) EXR" [ "$(header "$work/fmt" Content-Type)" = image/x-exr ]
# light_type reaches the renderer: a point light inside the bounding sphere is the one light whose shadow
# map is skipped for that reason, and the renderer says so.
c=$(req "$work/pt.png" GET "$A/v1/render?mesh=protrusion&light_type=point&light_pos=0,0,0.2&w=48&h=48&$fast")
shadows=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["shadows"])' "$(header "$work/pt.png" Lucent-Modelled)")
check "light_type=point -> 200 ($c), modelled shadows $shadows" [ "$c" = 200 -a "$shadows" = "['skipped: point light inside the bounding sphere (unshadowed)']" ]

# Errors, each with its problem+json body and field.
c=$(req "$work/e" POST "$A/v1/render" -H 'Content-Type: application/json' -d '{"width": 64,')
check "400 malformed JSON ($c)" problem "$work/e" 400 ""
c=$(req "$work/e" POST "$A/v1/render" -H 'Content-Type: application/json' -d '{"material":{"sigma_a":[0.1,-1,0.1],"sigma_s_prime":[1,1,1]}}')
check "400 invalid value names material.sigma_a[1] ($c)" problem "$work/e" 400 "material.sigma_a[1]"
c=$(req "$work/e" GET "$A/v1/render?w=abc")
check "400 bad query value names w ($c)" problem "$work/e" 400 w
c=$(req "$work/e" GET "$A/v1/render?light_dir=0,0,0")
check "400 parser error renamed to the query field light_dir ($c)" problem "$work/e" 400 light_dir
c=$(req "$work/e" GET "$A/v1/render?colour=red")
check "400 unknown query field ($c)" problem "$work/e" 400 colour
# A NUL (%00) stays part of the value, key or path it was sent in: validated as sent, never cut there.
c=$(req "$work/e" GET "$A/v1/render?w=16%00abc&h=16")
check "400 w=16%00abc names w ($c), not a 16 px render" problem_with "$work/e" 400 w '16%00abc'
c=$(req "$work/e" GET "$A/v1/render?method=five%00x&w=16&h=16")
check "400 method=five%00x names method ($c)" problem "$work/e" 400 method
c=$(req "$work/e" GET "$A/v1/render?mesh=sphere%00.obj&w=16&h=16")
check "400 mesh=sphere%00.obj names mesh ($c)" problem "$work/e" 400 mesh
c=$(req "$work/e" GET "$A/v1/render?w%00junk=16")
check "400 key w%00junk is an unknown query field ($c)" problem_with "$work/e" 400 query 'w%00junk'
c=$(req "$work/e" GET "$A/v1/render%00x?w=16&h=16")
check "404 path /v1/render%00x ($c)" problem "$work/e" 404 ""
# The client does not pick the status: an unknown key named like a header is still a 400.
c=$(req "$work/e" GET "$A/v1/render?Content-Type=1")
check "400 (not 415) for the query key Content-Type ($c)" problem "$work/e" 400 query
c=$(req "$work/e" POST "$A/v1/render" -H 'Content-Type: application/json' -d '{"mesh":{"file":"/etc/passwd"}}')
check "400 file meshes refused ($c)" problem "$work/e" 400 mesh.file
c=$(req "$work/e" GET "$A/v1/render?w=2000&h=64")
check "413 width over the server's limit ($c)" problem "$work/e" 413 w
c=$(req "$work/e" POST "$A/v1/render" -H 'Content-Type: application/json' -d '{"width":64,"height":3000}')
check "413 height over the limit, POST names height ($c)" problem "$work/e" 413 height
c=$(req "$work/e" GET "$A/v1/render?mesh=sphere&mesh_triangles=200000&w=64&h=64")
check "413 triangles over the limit ($c)" problem "$work/e" 413 mesh_triangles
head -c 70000 /dev/zero >"$work/big"
c=$(req "$work/e" POST "$A/v1/render" -H 'Content-Type: application/json' --data-binary @"$work/big")
check "413 body over max-body-bytes, from Content-Length ($c)" problem "$work/e" 413 Content-Length
c=$(req "$work/e" GET "$A/nowhere")
check "404 unknown route ($c)" problem "$work/e" 404 ""
c=$(req "$work/e" GET "$A/v1/render?mesh=$(printf '%064d' 0)&w=64&h=64")
check "404 unknown mesh id ($c)" problem "$work/e" 404 mesh.id
c=$(req "$work/e" DELETE "$A/v1/render")
check "405 ($c) with Allow: $(header "$work/e" Allow)" problem "$work/e" 405 ""
check "405 Allow lists GET and POST" grep -qi '^allow: GET, HEAD, POST, OPTIONS' "$work/e.h"
c=$(req "$work/e" GET "$A/v1/render?$scene_query" -H 'Accept: text/html')
check "406 for Accept: text/html ($c)" problem "$work/e" 406 Accept
c=$(req "$work/e" GET "$A/v1/render?$scene_query&format=exr" -H 'Accept: image/png')
check "406 for format=exr with Accept: image/png ($c)" problem "$work/e" 406 format
c=$(req "$work/e" POST "$A/v1/render" -H 'Content-Type: image/png' -d '{}')
check "415 scene sent as image/png ($c)" problem "$work/e" 415 Content-Type
c=$(req "$work/e" POST "$A/v1/meshes" -H 'Content-Type: application/octet-stream' --data-binary 'not a mesh at all')
check "415 unknown mesh format ($c)" problem "$work/e" 415 Content-Type
c=$(req "$work/e" POST "$A/v1/meshes" -H 'Content-Type: model/obj' --data-binary @"$work/nofaces.obj")
check "422 mesh without triangles ($c)" problem "$work/e" 422 mesh

# CORS.
c=$(req "$work/pf" OPTIONS "$A/v1/render" -H 'Origin: https://app.example' -H 'Access-Control-Request-Method: POST' \
    -H 'Access-Control-Request-Headers: content-type')
check "preflight 204 ($c) allows the origin and POST" [ "$c" = 204 -a "$(header "$work/pf" Access-Control-Allow-Origin)" = https://app.example ]
check "preflight lists methods and headers" grep -qi '^access-control-allow-methods: .*POST' "$work/pf.h"
c=$(req "$work/pf2" OPTIONS "$A/v1/render" -H 'Origin: https://evil.example' -H 'Access-Control-Request-Method: POST')
# Answered (204) yet without CORS headers: a preflight that got no answer at all must not pass.
check "preflight from another origin: 204 ($c) and no CORS headers" \
    bash -c "[ '$c' = 204 ] && ! grep -qi '^access-control-allow-origin' '$work/pf2.h'"
c=$(req "$work/cors.png" GET "$A/v1/render?$scene_query" -H 'Origin: https://app.example')
exposed=$(header "$work/cors.png" Access-Control-Expose-Headers)
check "GET with Origin ($c) exposes \"$exposed\", Lucent-Modelled among them" \
    [ "$c" = 200 -a "$exposed" = "ETag, Server-Timing, Lucent-Modelled, X-Request-Id, Retry-After" ]

# Meshes: upload (201, then 200 for the same bytes), metadata, render, delete.
c=$(req "$work/up" POST "$A/v1/meshes" --data-binary @"$cube")
cube_id=$(json_field "$work/up" '["id"]')
check "upload cube 201 ($c), id = sha256 of the bytes" [ "$c" = 201 -a "$cube_id" = "$(sha256sum "$cube" | cut -c1-64)" ]
check "upload reports 12 triangles, 8 vertices, bounds" [ "$(json_field "$work/up" '["triangles"], d["vertices"], d["bounds"]["max"]')" = "(12, 8, [1.0, 1.0, 1.0])" ]
check "Location names the mesh" [ "$(header "$work/up" Location)" = "/v1/meshes/$cube_id" ]
c=$(req "$work/up2" POST "$A/v1/meshes" -H 'Content-Type: model/obj' --data-binary @"$cube")
check "same bytes again: 200 ($c), same id" [ "$c" = 200 -a "$(json_field "$work/up2" '["id"]')" = "$cube_id" ]
c=$(req "$work/mi" GET "$A/v1/meshes/$cube_id")
check "GET mesh metadata 200 ($c)" [ "$(json_field "$work/mi" '["triangles"]')" = 12 ]
c=$(req "$work/cube.png" GET "$A/v1/render?mesh=$cube_id&w=64&h=64&light_dir=-1,-0.5,-1&$fast")
check "uploaded cube rendered 200 ($c)" pngs "$work/cube.png:64:64"
c=$(req "$work/e" DELETE "$A/v1/meshes/$cube_id%00.json")
c2=$(req "$work/mi2" GET "$A/v1/meshes/$cube_id")
check "DELETE .../<id>%00.json is 404 ($c) and the mesh stays ($c2)" [ "$c" = 404 -a "$c2" = 200 ]
# Media types: a type that is no mesh type (legacy application/x-ply) lets the bytes decide; a mesh type
# the bytes contradict is refused.
c=$(req "$work/e" POST "$A/v1/meshes" -H 'Content-Type: application/x-ply' --data-binary @/usr/share/assimp/models/PLY/cube_binary.ply)
check "binary PLY as application/x-ply sniffed: 201 ($c)" [ "$c" = 201 ]
c=$(req "$work/e" POST "$A/v1/meshes" -H 'Content-Type: model/ply' --data-binary @"$cube")
check "OBJ declared model/ply: 415 naming the contradiction ($c)" problem_with "$work/e" 415 Content-Type 'says ply but the bytes are obj'
c=$(req "$work/up3" POST "$A/v1/meshes" -H 'Content-Type: model/obj' --data-binary @"$tetra")
tetra_id=$(json_field "$work/up3" '["id"]')
c=$(req "$work/del" DELETE "$A/v1/meshes/$tetra_id")
check "DELETE mesh 204 ($c)" [ "$c" = 204 ]
c=$(req "$work/e" GET "$A/v1/meshes/$tetra_id")
check "deleted mesh is 404 ($c)" problem "$work/e" 404 mesh.id
c=$(req "$work/e" GET "$A/v1/meshes/NOT-HEX")
check "malformed mesh id is 404 ($c)" problem "$work/e" 404 mesh.id
# Every other format from Debian's assimp-testmodels, each uploaded and rendered: the PLY and the GLB with
# no Content-Type (format sniffed from the bytes), the STL and the glTF (embedded buffers) labelled.
models=/usr/share/assimp/models
uploaded=()
codes=
for spec in "PLY/cube.ply::12" "STL/sphereWithHole.stl:model/stl:285" \
    "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf:model/gltf+json:12" "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb::12"; do
    IFS=: read -r file type triangles <<<"$spec"
    name=${file##*/}
    c=$(req "$work/up_$name" POST "$A/v1/meshes" ${type:+-H "Content-Type: $type"} --data-binary @"$models/$file")
    read -r got id < <(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(d["triangles"], d["id"])' \
        "$work/up_$name" 2>/dev/null)
    check "upload $name (${type:-sniffed}): 201 ($c), ${got:-no} triangles (expected $triangles)" [ "$c" = 201 -a "${got:-}" = "$triangles" ]
    codes+=" $(req "$work/$name.png" GET "$A/v1/render?mesh=${id:-none}&w=48&h=48&$fast")"
    uploaded+=("$work/$name.png:48:48")
done
check "the four uploaded meshes rendered ($codes)" pngs "${uploaded[@]}"

# A glTF whose buffer is a file of its own, sent with it as multipart/form-data (curl -F): stored under
# the sha256 of the files' canonical bundle, so another order or boundary names the same mesh; one file
# in a form is that file. Forms with a field that is no file, a name climbing out, or a missing buffer
# are refused naming what is wrong.
box=$models/glTF2/BoxTextured-glTF
c=$(req "$work/form1" POST "$A/v1/meshes" -F "mesh=@$box/BoxTextured.gltf" -F "buffer=@$box/BoxTextured0.bin")
form_id=$(json_field "$work/form1" '["id"]' 2>/dev/null)
check "a glTF and its buffer as a form: $c, $(json_field "$work/form1" '["triangles"]' 2>/dev/null) triangles" \
    [ "$c" = 201 -a "$(json_field "$work/form1" '["triangles"]' 2>/dev/null)" = 12 ]
c2=$(req "$work/form2" POST "$A/v1/meshes" -F "buffer=@$box/BoxTextured0.bin;type=application/octet-stream" \
    -F "model=@$box/BoxTextured.gltf;type=model/gltf+json")
check "the same files in the other order, other field names and types: $c2, the same id" \
    [ "$c2" = 200 -a "$(json_field "$work/form2" '["id"]' 2>/dev/null)" = "$form_id" ]
c3=$(req "$work/form.png" GET "$A/v1/render?mesh=${form_id:-none}&w=48&h=48&$fast")
check "the form's mesh renders ($c3)" pngs "$work/form.png:48:48"
c=$(req "$work/bunny.png" GET "$A/v1/render?mesh=bunny&w=48&h=48&$fast")
c2=$(req "$work/e" GET "$A/v1/render?mesh=bunny&mesh_triangles=5000&w=48&h=48&$fast")
check "the built-in Stanford bunny renders ($c); at another density it is a 400 naming mesh_triangles ($c2)" \
    eval 'pngs "$work/bunny.png:48:48" && problem "$work/e" 400 mesh_triangles'

c=$(req "$work/form3" POST "$A/v1/meshes" -F "mesh=@$models/PLY/cube.ply")
check "one file in a form ($c) is that file: id = sha256 of its bytes" \
    [ "$c" = 200 -a "$(json_field "$work/form3" '["id"]' 2>/dev/null)" = "$(sha256sum "$models/PLY/cube.ply" | cut -c1-64)" ]
c=$(req "$work/e" POST "$A/v1/meshes" -F "mesh=@$box/BoxTextured.gltf" -F "mesh=@$box/CesiumLogoFlat.png")
check "a glTF sent without the buffer it names: $c naming it" problem_with "$work/e" 422 mesh 'BoxTextured0.bin'
c=$(req "$work/e" POST "$A/v1/meshes" -F "mesh=@$box/BoxTextured.gltf" -F "buffer=@$box/BoxTextured0.bin" -F note=hello)
check "a form field that is not a file: $c" problem "$work/e" 400 body
c=$(req "$work/e" POST "$A/v1/meshes" -F "mesh=@$box/BoxTextured.gltf" -F "buffer=@$box/BoxTextured0.bin;filename=../BoxTextured0.bin")
check "a file named ../BoxTextured0.bin: $c" problem_with "$work/e" 400 body '\.\.'
c=$(req "$work/e" POST "$A/v1/meshes" -H 'Content-Type: multipart/form-data; boundary=xyz' --data-binary 'not a form')
check "a body that is no multipart/form-data: $c" problem "$work/e" 400 body
# Hostile forms: cut off before the closing boundary, 65 parts, no boundary parameter.
part() { printf -- '--XB\r\nContent-Disposition: form-data; name="f"; filename="%s"\r\n\r\n%s\r\n' "$1" "$2"; }
{ part a.gltf '{}'; printf -- '--XB\r\nContent-Disposition: form-data; name="f"; filename="b.bin"\r\n\r\nxx'; } >"$work/cut.form"
c1=$(req "$work/e1" POST "$A/v1/meshes" -H 'Content-Type: multipart/form-data; boundary=XB' --data-binary @"$work/cut.form")
{ for i in $(seq 1 65); do part "f$i.bin" x; done; printf -- '--XB--\r\n'; } >"$work/many.form"
c2=$(req "$work/e2" POST "$A/v1/meshes" -H 'Content-Type: multipart/form-data; boundary=XB' --data-binary @"$work/many.form")
c3=$(req "$work/e3" POST "$A/v1/meshes" -H 'Content-Type: multipart/form-data' --data-binary @"$work/many.form")
check "a form cut short ($c1), one of 65 files ($c2), one without a boundary ($c3): 400, 400, 415, the daemon alive" \
    eval 'problem "$work/e1" 400 body && problem "$work/e2" 400 body && problem "$work/e3" 415 Content-Type &&
          [ "$(curl -s -o /dev/null -w "%{http_code}" "$A/healthz")" = 200 ]'
# assimp-testmodels' glTFs that name files, each sent with them (tests/upload_models.py): none refused for
# a missing file but MissingBin, whose buffer is missing on purpose (two are over this daemon's 64 KiB
# body limit; with the default limit 19 of the 36 are accepted, the rest are broken on purpose)
python3 "$(dirname "$0")/upload_models.py" "$A" --named-files-only >"$work/models.txt"
sed 's/^/   /' "$work/models.txt"
missing=$(grep '^refused' "$work/models.txt" | grep -c 'not among the files sent\|refers to other files')
missing_bin=$(grep '^refused' "$work/models.txt" | grep 'not among the files sent\|refers to other files' | grep -c 'MissingBin/')
accepted=$(sed -n 's/.* \([0-9]*\) of those accepted/\1/p' "$work/models.txt")
check "assimp-testmodels' glTFs naming files: ${accepted:-no} accepted with them; refused for a missing file: $missing (MissingBin: $missing_bin)" \
    [ "${accepted:-0}" -ge 17 -a "$missing" = 1 -a "$missing_bin" = 1 ]

# The listing: every stored mesh with its metadata, in id order, a page at a time (after, limit, next,
# Link); bad paging fields are 400s naming them.
python3 - "$A" >"$work/list.txt" <<'EOF2'
import json, sys, urllib.request, urllib.error
base, ids, after, pages, links = sys.argv[1], [], None, 0, 0
while True:
    url = base + "/v1/meshes?limit=2" + ("&after=" + after if after else "")
    with urllib.request.urlopen(url) as r:
        doc, link = json.load(r), r.headers.get("Link")
    pages += 1
    ids += [m["id"] for m in doc["meshes"]]
    assert all({"id", "triangles", "vertices", "bounds", "bytes", "created"} <= set(m) for m in doc["meshes"])
    after = doc.get("next")
    links += bool(link and after and ("after=%s&limit=2" % after) in link)
    if not after:
        break
with urllib.request.urlopen(base + "/v1/meshes") as r:
    whole = [m["id"] for m in json.load(r)["meshes"]]
print(len(ids), pages, links, int(ids == sorted(ids) == whole and len(set(ids)) == len(ids)))
EOF2
read -r listed pages links ordered <"$work/list.txt"
stored=$(ls "$store"/*.json 2>/dev/null | wc -l)
check "GET /v1/meshes: $listed meshes in $pages pages of 2 ($links Link headers), in id order, the same as one page; $stored stored" \
    [ "$listed" = "$stored" -a "$ordered" = 1 -a "$links" = $((pages - 1)) -a "$listed" -ge 5 ]
c1=$(req "$work/e1" GET "$A/v1/meshes?limit=0")
c2=$(req "$work/e2" GET "$A/v1/meshes?after=xyz")
c3=$(req "$work/e3" GET "$A/v1/meshes?page=2")
check "listing: limit=0 $c1 (limit), after=xyz $c2 (after), page=2 $c3 (page)" \
    eval 'problem "$work/e1" 400 limit && problem "$work/e2" 400 after && problem "$work/e3" 400 page'
# Numbers are the shortest text that reads back to the same double (0.003, not 0.0030000000000000001).
check "materials: every number as short as it reads back ($(grep -o '"sigma_a":\[[^]]*\]' "$work/m" | head -1))" python3 -c '
import re, sys
text = open(sys.argv[1]).read()
digits = lambda t: re.sub(r"^0+|0+$", "", re.sub(r"[eE].*$|[-.]", "", t))
bad = [t for t in re.findall(r"-?\d+\.\d+(?:[eE][-+]?\d+)?", text) if len(digits(t)) > len(digits(repr(float(t))))]
print("   longer than needed:", bad[:5])
sys.exit(1 if bad else 0)' "$work/m"

# 32 parallel renders of 32 different scenes: all 200, all valid, each its own size.
t0=$(date +%s%N)
curls=()
for i in $(seq 1 32); do
    w=$((48 + i)); h=$((40 + i))
    curl -s -o "$work/par$i.png" -w '%{http_code}' "$A/v1/render?mesh=sphere&w=$w&h=$h&light_dir=-1,$i,-1&$fast" >"$work/par$i.code" &
    curls+=($!)
done
wait "${curls[@]}"
t1=$(date +%s%N)
codes=0
files=()
for i in $(seq 1 32); do
    [[ $(cat "$work/par$i.code") == 200 ]] && codes=$((codes + 1))
    files+=("$work/par$i.png:$((48 + i)):$((40 + i))")
done
echo "   32 parallel renders answered in $(( (t1 - t0) / 1000000 )) ms, $codes with 200"
check "32 parallel requests all answered 200" [ "$codes" = 32 ]
check "... each a valid, lit PNG of its own size" pngs "${files[@]}"

# Metrics.
curl -s "$A/metrics" >"$work/metrics"
check "metrics: build info names the backend and device" \
    grep -qE '^lucentd_build_info\{version="[^"]*",backend="(vulkan|gl)",device="[^"]+"\} 1' "$work/metrics"
check "metrics: requests by route and status" grep -q '^lucentd_http_requests_total{route="render",code="200"} [1-9]' "$work/metrics"
check "metrics: 4xx counted" grep -q '^lucentd_http_requests_total{route="render",code="413"} [1-9]' "$work/metrics"
check "metrics: render histogram counts the parallel renders" awk '$1 == "lucentd_render_seconds_count{method=\"five\"}" && $2 >= 36 { f = 1 } END { exit !f }' "$work/metrics"
check "metrics: queue wait and encode histograms, queue depth, store bytes" bash -c "grep -q '^lucentd_queue_wait_seconds_bucket' '$work/metrics' && grep -q '^lucentd_encode_seconds_sum' '$work/metrics' && grep -q '^lucentd_queue_depth 0' '$work/metrics' && grep -q '^lucentd_mesh_store_bytes [1-9]' '$work/metrics'"
check "access log has one line per request with the request id" grep -q 'access id=test-id-42 GET /v1/render status=200' "$work/A.log"

# Web pages and DNS rebinding (issue 13): the API answers only for loopback Host names; a POST sent by a
# page of a foreign origin (a CORS-simple text/plain upload needs no preflight) is refused before its body
# is read; the daemon's own page and the configured origin may.
port=${A##*:}
c=$(req "$work/h" GET "$A/metrics" -H "Host: rebound.example:$port")
check "forged Host (DNS rebinding) on /metrics: $c" problem "$work/h" 421 Host
c=$(req "$work/h" GET "$A/v1/render?w=16&h=16" -H "Host: rebound.example:$port")
check "forged Host on a render: $c" problem "$work/h" 421 Host
c1=$(req "$work/h" GET "$A/healthz" -H "Host: 10.1.2.3:$port")
c2=$(req "$work/h.png" GET "$A/v1/render?w=16&h=16&preset=apple" -H "Host: localhost:$port")
check "probes answer any Host ($c1); localhost:$port is served ($c2)" [ "$c1" = 200 -a "$c2" = 200 ]
tetra_obj='v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1.25
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
'
printf '%s' "$tetra_obj" >"$work/web.obj"
web_id=$(sha256sum "$work/web.obj" | cut -d' ' -f1)
c=$(req "$work/o" POST "$A/v1/meshes" -H 'Content-Type: text/plain' -H 'Origin: http://attacker.example' \
    --data-binary "@$work/web.obj")
problem "$work/o" 403 Origin; refused=$?
c2=$(req "$work/o2" GET "$A/v1/meshes/$web_id")
check "text/plain upload sent by a foreign page: $c, and nothing stored ($c2)" [ "$refused" = 0 -a "$c2" = 404 ]
c=$(req "$work/o.png" POST "$A/v1/render" -H 'Content-Type: text/plain' -H 'Origin: null' -d '{"width":16,"height":16}')
check "a render POSTed by a sandboxed page (Origin: null): $c" problem "$work/o.png" 403 Origin
c1=$(req "$work/o" POST "$A/v1/meshes" -H 'Content-Type: text/plain' -H "Origin: http://127.0.0.1:$port" \
    --data-binary "@$work/web.obj")
c2=$(req "$work/o.png" POST "$A/v1/render" -H 'Content-Type: application/json' -H 'Origin: https://app.example' \
    -d '{"width":16,"height":16}')
check "the daemon's own page may upload ($c1); the configured origin may render ($c2)" [ "$c1" = 201 -a "$c2" = 200 ]

stop "$A_pid"; rc=$?
check "A: SIGTERM -> exit 0 ($rc)" [ "$rc" = 0 ]

# ---- A again on the same store: the uploaded mesh survived; the image cache is on ----
start A2 --store-dir "$store" --mesh-cache-bytes 4194304
A=$base
c=$(req "$work/e" GET "$A/v1/render?mesh=sphere&mesh_triangles=400000&w=32&h=32")
check "413 mesh larger than the renderer's mesh cache ($c): $(json_field "$work/e" '["detail"]' | cut -c1-70)" problem "$work/e" 413 mesh
c=$(req "$work/mi2" GET "$A/v1/meshes/$cube_id")
check "restart keeps the uploaded mesh ($c)" [ "$c" = 200 ]
c=$(req "$work/cube2.png" GET "$A/v1/render?mesh=$cube_id&w=64&h=64&light_dir=-1,-0.5,-1&$fast")
check "restarted daemon renders it, byte-identical to before ($c)" cmp -s "$work/cube.png" "$work/cube2.png"
c=$(req "$work/hit.png" GET "$A/v1/render?mesh=$cube_id&w=64&h=64&light_dir=-1,-0.5,-1&$fast")
check "second request is a cache hit ($c): $(header "$work/hit.png" Server-Timing)" grep -qi '^server-timing: cache;desc=hit' "$work/hit.png.h"
check "cache hit is byte-identical" cmp -s "$work/cube2.png" "$work/hit.png"
check "metrics count the hit" bash -c "curl -s '$A/metrics' | grep -q '^lucentd_image_cache_hits_total 1'"
# A stored mesh damaged on disk fails its MAC before the renderer sees it: 500, the mesh is removed, then
# business as usual.
python3 -c "import sys; p=sys.argv[1]; b=bytearray(open(p,'rb').read()); b[len(b)//2] ^= 0xff; open(p,'wb').write(b)" \
    "$store/$cube_id.lmesh"
c=$(req "$work/e" GET "$A/v1/render?mesh=$cube_id&w=64&h=64&light_dir=-1,-0.5,-1&exposure=1&$fast")
check "a damaged stored mesh -> 500 ($c): $(json_field "$work/e" '["detail"]' | cut -c1-90)" \
    problem_with "$work/e" 500 mesh.id 'failed its integrity check'
c=$(req "$work/m" GET "$A/v1/meshes/$cube_id")
check "then it is no longer stored ($c)" [ "$c" = 404 ]
c=$(req "$work/after.png" GET "$A/v1/render?w=64&h=64&exposure=2&$fast")
# exposure=2 is four times the radiance; after sRGB encoding the covered pixels' mean brightness goes from
# 81.9 (exposure 0) to 156.3 (1: 113.7), so a minimum of 100 shows the exposure was applied.
check "the daemon renders on after the 500 ($c), exposure=2 bright" pngs --lit 100 "$work/after.png:64:64"
# Memory stays flat: 500 distinct renders (16x16, each its own ETag) on one keep-alive connection (100 under
# AddressSanitizer, where only the answers are checked; lucentd_memory soaks 5000 requests).
renders=500; [ -n "${LUCENT_TEST_SANITIZED:-}" ] && renders=100
python3 - "$A" "$pid" "$renders" >"$work/rss.txt" <<'EOF2'
import http.client, sys, urllib.parse
base, pid, renders = urllib.parse.urlparse(sys.argv[1]), sys.argv[2], int(sys.argv[3])
conn = http.client.HTTPConnection(base.hostname, base.port, timeout=60)
def rss_kb():
    for line in open("/proc/%s/status" % pid):
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
bad, marks = 0, {}
for i in range(renders):
    conn.request("GET", "/v1/render?w=16&h=16&samples=4&projection_size=64&exposure=%.4f" % (i / 1000.0))
    r = conn.getresponse()
    r.read()
    bad += r.status != 200
    if i + 1 in (renders // 5, renders):
        marks[i + 1] = rss_kb()
print(bad, marks[renders // 5], marks[renders])
EOF2
read -r rss_bad rss_first rss_last <"$work/rss.txt"
# Under AddressSanitizer resident memory grows with its quarantine of freed blocks (16 MB here once), so
# there only the renders are checked and LeakSanitizer stands in for the bound.
if [ -n "${LUCENT_TEST_SANITIZED:-}" ]; then
    check "$renders renders: $rss_bad failed; resident memory ${rss_first} kB after $((renders / 5)), ${rss_last} kB after $renders (not bounded under ASan)" \
        [ "$rss_bad" = 0 ]
else
    check "$renders renders: $rss_bad failed; resident memory ${rss_first} kB after $((renders / 5)), ${rss_last} kB after $renders (growth < 4 MB)" \
        [ "$rss_bad" = 0 -a $(( rss_last - rss_first )) -lt 4096 ]
fi
# SIGTERM while a render runs (default drain timeout, 30 s): the render is answered. A reference render of
# 1000 points (1.7 s here) is in flight long after the poll sees it, and the log's order shows it was still
# running when the daemon noticed SIGTERM. The query's reference_points and reference_threshold come back
# in what the renderer reports.
A2_pid=$pid
req "$work/drain.png" GET "$A/v1/render?method=reference&w=192&h=192&reference_points=1000&reference_threshold=0.5" \
    -H 'X-Request-Id: drain-render' >"$work/drain.code" &
drain_curl=$!
wait_in_flight 1 "$A"; seen=$?
check "A2: the reference render is in flight ${waited_ms} ms after it was sent" [ $seen = 0 ]
kill -TERM "$A2_pid"
wait "$drain_curl"
check "A2: the render in flight at SIGTERM was answered: $(cat "$work/drain.code")" pngs "$work/drain.png:192:192"
modelled=$(python3 -c 'import json,sys; d=json.loads(sys.argv[1]); print(d["points"], d["threshold"], d["sum"])' \
    "$(header "$work/drain.png" Lucent-Modelled)")
check "A2: reference_points=1000, reference_threshold=0.5 rendered as points, threshold, sum: $modelled" \
    [ "$modelled" = "1000 0.5 hierarchical" ]
check "A2: it finished after the daemon noticed SIGTERM" \
    logged_before "$work/A2.log" 'SIGTERM: draining' 'access id=drain-render GET /v1/render status=200'
stop "$A2_pid"; rc=$?
check "A2: exit 0 after the render ($rc)" [ "$rc" = 0 ]

# ---- B: a queue of one, a token, a drain deadline of 1 s: 503 when full; SIGTERM answers what is left ----
echo "s3cret-token" >"$work/token"
start B --store-dir "$work/storeB" --queue-length 1 --token-file "$work/token" --retry-after 2 --drain-timeout 1
B=$base
B_pid=$pid
auth=(-H 'Authorization: Bearer s3cret-token')
c=$(req "$work/e" GET "$B/v1/materials")
check "401 without the token ($c), WWW-Authenticate: $(header "$work/e" WWW-Authenticate)" problem "$work/e" 401 Authorization
missing_title=$(json_field "$work/e" '["title"]')
c=$(req "$work/e" GET "$B/v1/materials" -H 'Authorization: Bearer wrong')
wrong_title=$(json_field "$work/e" '["title"]')
check "401 with a wrong token ($c), titled apart from a missing one (\"$wrong_title\" / \"$missing_title\"), WWW-Authenticate: $(header "$work/e" WWW-Authenticate)" \
    bash -c "[ '$c' = 401 -a '$wrong_title' != '$missing_title' ] && grep -qi '^www-authenticate: .*error=\"invalid_token\"' '$work/e.h'"
c=$(req "$work/mat" GET "$B/v1/materials" "${auth[@]}")
check "200 with the token ($c); /healthz needs none" [ "$c" = 200 -a "$(curl -s -o /dev/null -w '%{http_code}' "$B/healthz")" = 200 ]
# A reference render with automatic points at 1024^2 would run for minutes (24 s at 384^2 on 2 cores; it
# uses every core), far longer than the 2 s this part of the test needs: the queue stays full until SIGTERM's
# drain deadline ends it, however fast or loaded the machine.
req "$work/long" GET "$B/v1/render?method=reference&w=1024&h=1024" "${auth[@]}" >"$work/long.code" &
long_curl=$!
wait_in_flight 1 "$B" "${auth[@]}"; seen=$?
check "the long render is in flight ${waited_ms} ms after it was sent" [ $seen = 0 ]
c=$(req "$work/r" GET "$B/readyz")
check "readyz 503 ($c) while the queue is full: $(cat "$work/r")" grep -q '"queue full"' "$work/r"
c=$(req "$work/e" GET "$B/v1/render?w=64&h=64" "${auth[@]}")
kind=$(problem_type "$work/e"); retry=$(header "$work/e" Retry-After)
check "queue full -> 503 ($c) $kind with the configured Retry-After: $retry" [ "$kind" = queue-full -a "$retry" = 2 ]
check "... a problem+json body" problem "$work/e" 503 ""
# SIGTERM from a connection opened before it: new connections are no longer accepted, so /readyz and a
# render are asked on this one (http.client keeps it alive).
python3 - "$B" "$B_pid" >"$work/sigterm.txt" <<'EOF2'
import http.client, json, os, signal, sys, time, urllib.parse
base, pid = urllib.parse.urlparse(sys.argv[1]), int(sys.argv[2])
conn = http.client.HTTPConnection(base.hostname, base.port, timeout=30)
auth = {"Authorization": "Bearer s3cret-token"}
def get(path, headers={}):
    conn.request("GET", path, headers=headers)
    r = conn.getresponse()
    return r.status, r.getheader("Retry-After"), r.read()
get("/readyz")
os.kill(pid, signal.SIGTERM)
t0 = time.monotonic()
while True:
    status, _, body = get("/readyz")
    reason = json.loads(body).get("reason")
    if reason == "draining" or time.monotonic() - t0 > 30:
        break
    time.sleep(0.01)
print("readyz", status, reason, "%.0f" % ((time.monotonic() - t0) * 1e3))
status, retry, body = get("/v1/render?w=64&h=64", auth)
print("render", status, json.loads(body).get("type", "").rsplit(":", 1)[-1], retry)
_, _, body = get("/metrics", auth)
print("in_flight", [l.split()[1] for l in body.decode().splitlines() if l.startswith("lucentd_renders_in_flight ")][0])
conn.close()
EOF2
read -r _ ready_status ready_reason ready_ms <<<"$(grep ^readyz "$work/sigterm.txt")"
read -r _ late_status late_type late_retry <<<"$(grep ^render "$work/sigterm.txt")"
check "after SIGTERM /readyz says $ready_status $ready_reason (within $ready_ms ms)" [ "$ready_status" = 503 -a "$ready_reason" = draining ]
check "after SIGTERM a render on an open connection is refused: $late_status $late_type, Retry-After $late_retry" \
    [ "$late_status" = 503 -a "$late_type" = not-ready -a "$late_retry" = 2 ]
check "while draining the long render is still running: $(grep ^in_flight "$work/sigterm.txt")" grep -q '^in_flight 1$' "$work/sigterm.txt"
c=$(curl -s -o /dev/null -w '%{http_code}' --max-time 30 "$B/healthz")
check "after SIGTERM a new connection gets no answer ($c)" [ "$c" = 000 ]
wait "$long_curl"
c=$(cat "$work/long.code"); kind=$(problem_type "$work/long"); retry=$(header "$work/long" Retry-After)
check "at the drain deadline the long render is answered $c $kind with Retry-After $retry" \
    [ "$c" = 503 -a "$kind" = not-ready -a "$retry" = 2 ]
stop "$B_pid"; rc=$?
check "B: exit 0 after the drain deadline ($rc)" [ "$rc" = 0 ]
# The drain lasts --drain-timeout: not less (renders get their time), and not much more (1.006-1.015 s measured;
# the bound allows 1 s of scheduling delay, far below the default 30 s or the render's own minute). Measured
# between the daemon's own log lines (ms timestamps).
drain_s=$(python3 - "$work/B.log" <<'EOF2'
import datetime, sys
def when(text):
    line = next(l for l in open(sys.argv[1]) if text in l)
    return datetime.datetime.strptime(line.split()[0], "%Y-%m-%dT%H:%M:%S.%fZ")
print("%.3f" % (when("drain deadline reached; answering 1 unfinished") - when("SIGTERM: draining")).total_seconds())
EOF2
)
check "B: the drain deadline came ${drain_s} s after SIGTERM (--drain-timeout 1: at least 1.0 s, under 2.0 s)" \
    python3 -c "import sys; sys.exit(not 1.0 <= float(sys.argv[1]) < 2.0)" "${drain_s:-0}"
check "B log says draining, deadline reached, stopped" \
    bash -c "grep -q 'SIGTERM: draining (up to 1 s)' '$work/B.log' && grep -q 'drain deadline reached' '$work/B.log' && grep -q 'stopped' '$work/B.log'"

# ---- C: a render deadline shorter than the render; limits up to what the device can do; other limits;
# CORS for every origin; an importer that crashes, hangs or runs out of memory ----
start C --store-dir "$work/storeC" --render-timeout 0.1 --retry-after 3 --max-width 4096 --max-height 4096 \
    --max-samples 16 --max-lights 2 --max-projection-size 512 --cors-origins '*' --import-tool "$hostile_importer" --import-wall 1 --log-level debug
C=$base
C_pid=$pid
c=$(req "$work/e" GET "$C/v1/render?w=4000&h=4000")
check "413 image larger than the device renders ($c): $(json_field "$work/e" '["detail"]')" problem "$work/e" 413 w
# Above the default 16 samples but below the parser's caps (64 samples, 4 lights): only --max-samples 16 and
# --max-lights 2 refuse these.
c=$(req "$work/e" GET "$C/v1/render?w=64&h=64&samples=17")
check "413 samples=17 over --max-samples 16 ($c): $(json_field "$work/e" '["detail"]')" problem "$work/e" 413 samples
c=$(req "$work/e" POST "$C/v1/render" -H 'Content-Type: application/json' \
    -d '{"width":64,"height":64,"lights":[{"direction":[-1,0,0]},{"direction":[0,-1,0]},{"direction":[0,0,-1]}]}')
check "413 three lights over --max-lights 2 ($c): $(json_field "$work/e" '["detail"]')" problem "$work/e" 413 lights
c=$(req "$work/e" GET "$C/v1/render?w=32&h=32&projection_size=1024")
check "413 projection_size=1024 over --max-projection-size 512 ($c): $(json_field "$work/e" '["detail"]')" \
    problem "$work/e" 413 projection_size
c=$(req "$work/pf" OPTIONS "$C/v1/render" -H 'Origin: https://any.example' -H 'Access-Control-Request-Method: POST')
check "--cors-origins '*': preflight from any origin 204 ($c), Allow-Origin $(header "$work/pf" Access-Control-Allow-Origin)" \
    [ "$c" = 204 -a "$(header "$work/pf" Access-Control-Allow-Origin)" = '*' ]
c=$(req "$work/h" GET "$C/healthz" -H 'Origin: https://other.example')
allow=$(header "$work/h" Access-Control-Allow-Origin); vary=$(header "$work/h" Vary)
# One answer for every origin, so no Vary: Origin (which would split caches per origin for nothing).
check "--cors-origins '*': a GET ($c) gets Allow-Origin $allow, Vary \"$vary\"" [ "$c" = 200 -a "$allow" = '*' -a -z "$vary" ]
# 1000 irradiance points at 512^2: the render takes 6.5 s on 2 cores (measured), 65 times the deadline; its
# set-up is short. With automatic points (up to 400k) the serial point-tree build, which is not cancellable,
# delays the stop (290-490 ms measured here); with 1000 what is measured is the cancellation itself.
c=$(req "$work/e" GET "$C/v1/render?method=reference&w=512&h=512&reference_points=1000")
deadline_code=$c; kind=$(problem_type "$work/e"); retry=$(header "$work/e" Retry-After)
check "render over render-timeout -> 503 ($c) $kind with the configured Retry-After $retry: $(json_field "$work/e" '["detail"]' | cut -c1-60)" \
    [ "$c" = 503 -a "$kind" = deadline -a "$retry" = 3 ]
# The overdue render is cancelled, so the worker is free again soon (README: about 0.1 s; 17-36 ms measured
# here with 10 ms polls). The bound, 500 ms, leaves room for a loaded 2-core machine; the daemon's debug line
# says the render was cancelled rather than finished, and after how long it stopped.
wait_in_flight 0 "$C"; seen=$?
cancelled=$(grep -o 'the reference render was cancelled in [0-9.]* ms' "$work/C.log")
check "the overdue render was cancelled: no render in flight $waited_ms ms after its 503 (bound 500 ms); \"${cancelled:-no log line}\"" \
    [ "$deadline_code" = 503 -a $seen = 0 -a "$waited_ms" -lt 500 -a -n "$cancelled" ]
c=$(req "$work/e" POST "$C/v1/meshes" -H 'Content-Type: model/obj' --data-binary 'crash')
check "an importer that crashes -> 422 ($c): $(json_field "$work/e" '["detail"]')" problem_with "$work/e" 422 mesh crashed
t0=$(date +%s%N)
c=$(req "$work/e" POST "$C/v1/meshes" -H 'Content-Type: model/obj' --data-binary 'hang')
check "an importer that hangs is stopped at --import-wall 1 s -> 422 ($c) after $(ms_since "$t0") ms: $(json_field "$work/e" '["detail"]')" \
    problem_with "$work/e" 422 mesh 'took longer than 1 s'
c=$(req "$work/e" POST "$C/v1/meshes" -H 'Content-Type: model/obj' --data-binary 'nomem')
check "an importer out of memory -> 413 ($c): $(json_field "$work/e" '["detail"]')" problem_with "$work/e" 413 mesh 'more than'
c=$(req "$work/e" POST "$C/v1/meshes" -H 'Content-Type: model/obj' --data-binary 'forge')
forged=$(grep -c '^2026-01-01T00:00:00.000Z info lucentd: access id=forged' "$work/C.log")
relayed=$(grep -c 'lucent: mesh importer: 2026-01-01T00:00:00.000Z info lucentd: access id=forged' "$work/C.log")
escaped=$(grep -c 'lucent: mesh importer: \\x1b\[2Khidden' "$work/C.log")
check "an importer's stderr cannot forge log lines ($c): $forged forged, $relayed relayed as the importer's, $escaped escape sequence shown escaped" \
    [ "$forged" = 0 -a "$relayed" = 1 -a "$escaped" = 1 ]
children=$(pgrep -P "$C_pid" | wc -l)
c=$(req "$work/h" GET "$C/healthz")
check "the daemon lives on ($c) with no importer left running ($children children)" [ "$c" = 200 -a "$children" = 0 ]
stop "$C_pid"; rc=$?
check "C: exit 0 after a deadline and three failed imports ($rc)" [ "$rc" = 0 ]

# ---- R: --rate-limit 0.5 a second, bursts of 4, per client: after an upload, the fourth quick request gets
# 429; and an importer that tries to escape its sandbox: refused, counted, logged, the daemon serves on ----
"$lucentd" --port 0 --store-dir "$work/storeR" --import-tool "$work/no-such-importer" 2>"$work/noimp.log" &
noimp=$!; pids+=("$noimp")
for _ in $(seq 1 300); do kill -0 "$noimp" 2>/dev/null || break; sleep 0.1; done
kill -0 "$noimp" 2>/dev/null && rc=running || { wait "$noimp"; rc=$?; }
check "a missing importer stops lucentd at start (exit $rc): $(grep -o 'cannot open the mesh importer[^:]*' "$work/noimp.log")" \
    bash -c "[ '$rc' = 1 ] && grep -q 'cannot open the mesh importer' '$work/noimp.log'"
start R --store-dir "$work/storeR" --rate-limit 0.5 --rate-burst 4 --import-tool "$hostile_importer"
R=$base
R_pid=$pid
c=$(req "$work/e" POST "$R/v1/meshes" -H 'Content-Type: model/obj' --data-binary $'open\nv 0 0 0')
check "an importer opening /etc/passwd: upload $c: $(json_field "$work/e" '["detail"]' | cut -c1-60)" \
    problem_with "$work/e" 422 mesh 'stopped by its sandbox'
METRIC=lucentd_import_sandbox_violations_total
v=$(metric "$R/metrics")
check "reported: $METRIC $v, and the log says $(grep -c 'SANDBOX VIOLATION' "$log") time(s)" \
    bash -c "[ '$v' = 1 ] && [ \$(grep -c 'SANDBOX VIOLATION' '$log') = 1 ]"
codes=
for i in 1 2 3; do codes+=" $(req "$work/r$i" GET "$R/v1/materials")"; done
retry=$(header "$work/r3" Retry-After)
check "after the upload and /metrics two requests pass, the next is 429 ($codes) of type $(problem_type "$work/r3") with Retry-After $retry (1-2 s)" \
    bash -c "[ '$codes' = ' 200 200 429' ] && [ '$(problem_type "$work/r3")' = rate-limited ] && [ '${retry:-0}' -ge 1 -a '${retry:-0}' -le 2 ]"
c=$(req "$work/h" GET "$R/healthz")
check "the probes are not limited ($c)" [ "$c" = 200 ]
sleep "${retry:-2}"
c=$(req "$work/r5" GET "$R/v1/materials")
check "after Retry-After the client passes again ($c)" [ "$c" = 200 ]
stop "$R_pid"; rc=$?
check "R: exit 0 ($rc)" [ "$rc" = 0 ]

# ---- N: a machine that refuses namespaces. lucentd runs as an unprivileged user in a user namespace
# whose parent allows no further one (user.max_user_namespaces 1, taken by its own): it says so at
# start and in /readyz, imports through the rest of the sandbox, and the seccomp filter still stops
# an escaping importer ----
if unshare -Ur true 2>/dev/null; then
    printf '%s\n' '#!/bin/sh' \
        "exec unshare -Ur sh -c 'echo 1 >/proc/sys/user/max_user_namespaces && exec unshare -U --map-user=1000 --map-group=1000 \"\$0\" \"\$@\"' '$lucentd' \"\$@\"" \
        >"$work/no-namespaces"
    chmod +x "$work/no-namespaces"
    real_lucentd=$lucentd
    lucentd=$work/no-namespaces
    start N --store-dir "$work/storeN"
    N=$base
    N_pid=$pid
    ns=$(curl -s "$N/readyz" | python3 -c 'import json,sys; print(json.load(sys.stdin)["import_sandbox"]["namespaces"] or "none")')
    said=$(grep -o 'namespaces refused here ([^)]*)' "$log" | head -1)
    check "namespaces refused: /readyz import_sandbox.namespaces = $ns, the log says \"$said\"" \
        [ "$ns" = none -a -n "$said" ]
    c=$(req "$work/e" POST "$N/v1/meshes" -H 'Content-Type: model/obj' --data-binary "@$cube")
    check "without namespaces an upload is imported ($c)" [ "$c" = 201 ]
    stop "$N_pid"
    start N2 --store-dir "$work/storeN2" --import-tool "$hostile_importer"
    lucentd=$real_lucentd
    c=$(req "$work/e" POST "$base/v1/meshes" -H 'Content-Type: model/obj' --data-binary $'connect\nv 0 0 0')
    check "without namespaces an importer connecting a socket is still stopped ($c): $(json_field "$work/e" '["detail"]' | cut -c1-50)" \
        problem_with "$work/e" 422 mesh 'stopped by its sandbox'
    stop "$pid"
else
    echo "   (N skipped: this machine makes no user namespace, so every daemon above ran without one)"
fi

# ---- K: budgets a client cannot exhaust: connections per client, the whole-request deadline, the body
# budget over all connections, and an endless chunked body (tests/hostile_clients.py) ----
start K --store-dir "$work/storeK" --max-connections 16 --max-connections-per-client 8 --request-timeout 3 \
    --max-body-bytes 1048576 --max-body-total 3000000
port=${base##*:}
r=$(python3 "$harness_dir/hostile_clients.py" slowloris "$port" 20)
echo "   slowloris: $r"
field() { python3 -c "import json,sys; print(json.loads(sys.argv[1])[sys.argv[2]])" "$r" "$1"; }
check "20 trickling connections from one address: $(field refused_at_once) closed at once, $(field held) held (limit 8)" \
    [ "$(field refused_at_once)" = 12 -a "$(field held)" = 8 ]
check "another client reaches /healthz meanwhile ($(field healthz_meanwhile))" [ "$(field healthz_meanwhile)" = 200 ]
METRIC=lucentd_slow_requests_closed_total
check "the trickling ones closed after $(field closed_after_s) s (--request-timeout 3: 3-8 s): $(field closed) of 8, counted $(metric "$base/metrics")" \
    bash -c "[ '$(field closed)' = 8 ] && python3 -c 'import sys; sys.exit(not 3 <= $(field closed_after_s) < 8)' && [ '$(metric "$base/metrics")' = 8 ]"
r=$(python3 "$harness_dir/hostile_clients.py" bodies "$port" 1000000 3)
echo "   bodies: $r"
check "3 uploads declaring 1 MB hold $(field charged_while_held) of --max-body-total 3000000; a fourth: $(field status_line), $(field type), Retry-After $(field retry_after)" \
    bash -c "[ '$(field charged_while_held)' = 3000000 ] && [[ '$(field status_line)' == *' 503 '* ]] && [[ '$(field type)' == *bodies-full ]] && [ -n '$(field retry_after)' ]"
METRIC=lucentd_request_body_bytes
for _ in $(seq 1 100); do [ "$(metric "$base/metrics")" = 0 ] && break; sleep 0.05; done
c=$(req "$work/k" POST "$base/v1/meshes" -H 'Content-Type: model/obj' --data-binary @"$tetra")
check "once they are gone the budget is free again ($(metric "$base/metrics") bytes held) and an upload is stored ($c)" \
    [ "$(metric "$base/metrics")" = 0 -a "$c" = 201 ]
# Renders whose clients gave up while they waited are skipped, not rendered for no one.
curl -s -o "$work/slow.png" "$base/v1/render?method=reference&w=128&h=128&reference_points=20000" &   # 3.3 s here
slow=$!
for _ in $(seq 1 200); do [ "$(METRIC=lucentd_renders_in_flight metric "$base/metrics")" = 1 ] && break; sleep 0.05; done
for e in 1 2 3; do curl -s -o /dev/null --max-time 0.3 "$base/v1/render?w=64&h=64&exposure=$e"; done
wait "$slow"
METRIC=lucentd_queue_depth
for _ in $(seq 1 600); do [ "$(metric "$base/metrics")" = 0 ] && break; sleep 0.05; done
METRIC=lucentd_renders_abandoned_total
check "3 renders whose clients left while a slow one ran: $(metric "$base/metrics") skipped, $(grep -c 'skipped: its client closed' "$log") logged" \
    bash -c "[ '$(metric "$base/metrics")' = 3 ] && [ \$(grep -c 'skipped: its client closed' '$log') = 3 ]"
sent=$(head -c 67108864 /dev/zero | curl -s -o /dev/null -w '%{size_upload}' -H 'Transfer-Encoding: chunked' \
    -H 'Content-Type: model/obj' --data-binary @- "$base/v1/meshes")
check "a 64 MiB chunked body over --max-body-bytes 1 MiB: the connection is closed after $sent bytes (under 8 MiB), logged" \
    bash -c "[ '$sent' -lt 8388608 ] && grep -q 'connection closed after [0-9]* bytes of its body: over --max-body-bytes' '$log'"
stop "$pid"

# --allowed-hosts: the names a deployment serves under, and no others (loopback included).
start H --store-dir "$work/storeH" --allowed-hosts 'render.example, lucent.internal'
c1=$(req "$work/h" GET "$base/v1/materials" -H "Host: lucent.internal:${base##*:}")
c2=$(req "$work/h2" GET "$base/v1/materials")
check "--allowed-hosts: lucent.internal served ($c1), 127.0.0.1 not ($c2)" [ "$c1" = 200 -a "$c2" = 421 ]
stop "$pid"

# Without a Vulkan driver (the loader pointed at none), the automatic backend is OpenGL through EGL: the daemon
# says so and why, and serves the same API on it.
VK_ICD_FILENAMES=/nonexistent start G --store-dir "$work/storeG"
c=$(req "$work/g.png" GET "$base/v1/render?mesh=bunny&w=96&h=80")
check "no Vulkan driver: ready on OpenGL (logged why), /readyz and Lucent-Modelled name it, a render ($c)" \
    eval 'grep -q "no Vulkan device (.*); trying OpenGL through EGL" "$log" && grep -q "ready: gl device" "$log" &&
          curl -s "$base/readyz" | grep -q "\"backend\": *\"gl\"" && grep -qi "^Lucent-Modelled: .*\"backend\":\"gl\"" "$work/g.png.h" &&
          pngs "$work/g.png:96:80"'
# Method "path" through GET: its query fields reach the render, and Lucent-Modelled says what it did.
c=$(req "$work/p.png" GET "$base/v1/render?method=path&w=40&h=32&path_samples=3&path_boundary=cycles&path_filter=box&path_seed=5")
check "method=path with path_samples, path_boundary, path_filter, path_seed ($c): modelled says so" \
    eval 'grep -qi "^Lucent-Modelled: .*\"method\":\"path\".*\"boundary\":\"cycles\",\"filter\":\"box\",\"samples\":3,\"samples_asked\":3,\"seed\":5" "$work/p.png.h" &&
          pngs "$work/p.png:40:32"'
stop "$pid"

echo "whole test: $SECONDS s"
echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
