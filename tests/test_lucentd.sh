#!/usr/bin/env bash
# test_lucentd.sh - lucentd over HTTP with curl: every endpoint, every error status with its problem+json
# body, caching, CORS, meshes across a restart, 32 parallel renders, a full queue, deadlines and SIGTERM.
# Usage: test_lucentd.sh PATH/TO/lucentd. Images are decoded with oiiotool and checked for size and content.
set -u
lucentd=$1
work=$(mktemp -d)
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null; done
    rm -rf "$work"
}
trap cleanup EXIT
source "$(dirname "$0")/lucentd_harness.sh"

# stop PID: SIGTERM, then the exit status (124 when it did not exit within 60 s).
stop() {
    kill -TERM "$1" 2>/dev/null
    for _ in $(seq 1 600); do
        if ! kill -0 "$1" 2>/dev/null; then wait "$1"; return $?; fi
        sleep 0.1
    done
    return 124
}

# req OUT METHOD URL [curl args...]: body to OUT, headers to OUT.h, prints the status.
req() {
    local out=$1 method=$2 url=$3; shift 3
    curl -s -X "$method" -o "$out" -D "$out.h" -w '%{http_code}' "$@" "$url"
}

header() { grep -i "^$2:" "$1.h" | head -1 | cut -d' ' -f2- | tr -d '\r'; }

# problem FILE STATUS FIELD: a problem+json body with that status and field ("" = no field).
problem() {
    python3 - "$1" "$2" "$3" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
ok = doc.get("status") == int(sys.argv[2]) and doc.get("type", "").startswith("tag:lucent") and doc.get("title") \
     and doc.get("detail") and doc.get("field", "") == sys.argv[3]
if not ok:
    print("   got", doc)
sys.exit(0 if ok else 1)
EOF
    local rc=$?
    [[ $rc == 0 ]] && grep -qi '^content-type: application/problem+json' "$1.h"
}

# exr FILE W H: oiiotool decodes it as a float image of that size.
exr() {
    local info
    info=$(oiiotool --info "$1" 2>&1) || { echo "   not an image: $info"; return 1; }
    echo "   $info"
    [[ $info =~ :\ +$2\ x\ +$3,.*float ]]
}

json_field() { python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(eval("d"+sys.argv[2]))' "$1" "$2"; }
metric() { curl -s "$@" | awk -v m="$METRIC" '$1 == m { print $2 }'; }

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

# ---- daemon A: no image cache (so GET and POST both render), CORS for one origin, small limits ----
store=$work/store
start A --store-dir "$store" --cache-bytes 0 --queue-length 40 --cors-origins 'https://app.example' \
    --max-width 1024 --max-triangles 100000 --max-body-bytes 65536
A=$base
A_pid=$pid

c=$(req "$work/h" GET "$A/healthz"); check "healthz 200 ($c)" [ "$c" = 200 ]
c=$(req "$work/r" GET "$A/readyz"); check "readyz 200 ($c) names the device" grep -q '"device"' "$work/r"
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
check "preflight from another origin gets no CORS headers" bash -c "! grep -qi '^access-control-allow-origin' '$work/pf2.h'"
c=$(req "$work/cors.png" GET "$A/v1/render?$scene_query" -H 'Origin: https://app.example')
check "GET with Origin exposes ETag and Server-Timing" grep -qi '^access-control-expose-headers: ETag, Server-Timing' "$work/cors.png.h"

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
c=$(req "$work/up3" POST "$A/v1/meshes" -H 'Content-Type: model/obj' --data-binary @"$tetra")
tetra_id=$(json_field "$work/up3" '["id"]')
c=$(req "$work/del" DELETE "$A/v1/meshes/$tetra_id")
check "DELETE mesh 204 ($c)" [ "$c" = 204 ]
c=$(req "$work/e" GET "$A/v1/meshes/$tetra_id")
check "deleted mesh is 404 ($c)" problem "$work/e" 404 mesh.id
c=$(req "$work/e" GET "$A/v1/meshes/NOT-HEX")
check "malformed mesh id is 404 ($c)" problem "$work/e" 404 mesh.id

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
check "metrics: build info names the device" grep -q '^lucentd_build_info{version="[^"]*",device="[^"]\+"} 1' "$work/metrics"
check "metrics: requests by route and status" grep -q '^lucentd_http_requests_total{route="render",code="200"} [1-9]' "$work/metrics"
check "metrics: 4xx counted" grep -q '^lucentd_http_requests_total{route="render",code="413"} [1-9]' "$work/metrics"
check "metrics: render histogram counts the parallel renders" awk '$1 == "lucentd_render_seconds_count{method=\"five\"}" && $2 >= 36 { f = 1 } END { exit !f }' "$work/metrics"
check "metrics: queue wait and encode histograms, queue depth, store bytes" bash -c "grep -q '^lucentd_queue_wait_seconds_bucket' '$work/metrics' && grep -q '^lucentd_encode_seconds_sum' '$work/metrics' && grep -q '^lucentd_queue_depth 0' '$work/metrics' && grep -q '^lucentd_mesh_store_bytes [1-9]' '$work/metrics'"
check "access log has one line per request with the request id" grep -q 'access id=test-id-42 GET /v1/render status=200' "$work/A.log"

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
# A stored mesh damaged on disk is an internal failure the daemon survives: 500, then business as usual.
python3 -c "import sys; p=sys.argv[1]; b=bytearray(open(p,'rb').read()); b[len(b)//2] ^= 0xff; open(p,'wb').write(b)" \
    "$store/$cube_id.lmesh"
c=$(req "$work/e" GET "$A/v1/render?mesh=$cube_id&w=64&h=64&light_dir=-1,-0.5,-1&exposure=1&$fast")
check "a damaged stored mesh -> 500 ($c): $(json_field "$work/e" '["detail"]' | cut -c1-70)" problem "$work/e" 500 mesh.file
c=$(req "$work/after.png" GET "$A/v1/render?w=64&h=64&exposure=2&$fast")
check "the daemon renders on after the 500 ($c)" pngs "$work/after.png:64:64"
# Memory stays flat: 1000 distinct renders (16x16, each its own ETag) on one keep-alive connection.
python3 - "$A" "$pid" >"$work/rss.txt" <<'EOF2'
import http.client, sys, urllib.parse
base, pid = urllib.parse.urlparse(sys.argv[1]), sys.argv[2]
conn = http.client.HTTPConnection(base.hostname, base.port, timeout=60)
def rss_kb():
    for line in open("/proc/%s/status" % pid):
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
bad, marks = 0, {}
for i in range(1000):
    conn.request("GET", "/v1/render?w=16&h=16&samples=4&projection_size=64&exposure=%.4f" % (i / 1000.0))
    r = conn.getresponse()
    r.read()
    bad += r.status != 200
    if i + 1 in (200, 1000):
        marks[i + 1] = rss_kb()
print(bad, marks[200], marks[1000])
EOF2
read -r rss_bad rss_200 rss_1000 <"$work/rss.txt"
check "1000 renders: $rss_bad failed; resident memory ${rss_200} kB after 200, ${rss_1000} kB after 1000 (growth < 4 MB)" \
    [ "$rss_bad" = 0 -a $(( rss_1000 - rss_200 )) -lt 4096 ]
stop "$pid"; rc=$?
check "A2: SIGTERM -> exit 0 ($rc)" [ "$rc" = 0 ]

# ---- B: a queue of one, a token, slow renders: 503 when full, SIGTERM lets the render finish ----
echo "s3cret-token" >"$work/token"
start B --store-dir "$work/storeB" --queue-length 1 --token-file "$work/token" --retry-after 2
B=$base
B_pid=$pid
auth=(-H 'Authorization: Bearer s3cret-token')
slow="method=reference&w=96&h=96"
c=$(req "$work/e" GET "$B/v1/materials")
check "401 without the token ($c), WWW-Authenticate: $(header "$work/e" WWW-Authenticate)" problem "$work/e" 401 Authorization
c=$(req "$work/e" GET "$B/v1/materials" -H 'Authorization: Bearer wrong')
check "401 with a wrong token ($c)" [ "$c" = 401 ]
c=$(req "$work/mat" GET "$B/v1/materials" "${auth[@]}")
check "200 with the token ($c); /healthz needs none" [ "$c" = 200 -a "$(curl -s -o /dev/null -w '%{http_code}' "$B/healthz")" = 200 ]
curl -s -o "$work/slow1.png" -w '%{http_code}' "${auth[@]}" "$B/v1/render?$slow" >"$work/slow1.code" &
slow_pid=$!
for _ in $(seq 1 100); do [[ $(curl -s -o /dev/null -w '%{http_code}' "$B/readyz") == 503 ]] && break; sleep 0.05; done
c=$(req "$work/r" GET "$B/readyz")
check "readyz 503 ($c) while the queue is full: $(cat "$work/r")" grep -q '"queue full"' "$work/r"
c=$(req "$work/e" GET "$B/v1/render?w=64&h=64" "${auth[@]}")
check "queue full -> 503 ($c) with Retry-After: $(header "$work/e" Retry-After)" problem "$work/e" 503 ""
check "Retry-After is the configured 2" [ "$(header "$work/e" Retry-After)" = 2 ]
wait "$slow_pid"
check "the slow render finished: 200 $(cat "$work/slow1.code")" pngs "$work/slow1.png:96:96"
# SIGTERM while a render runs: it is answered, new requests are not, and the exit status is 0.
curl -s -o "$work/slow2.png" -w '%{http_code}' "${auth[@]}" "$B/v1/render?$slow&exposure=1" >"$work/slow2.code" &
slow_pid=$!
for _ in $(seq 1 100); do
    [[ $(curl -s "${auth[@]}" "$B/metrics" | awk '$1 == "lucentd_renders_in_flight" { print $2 }') == 1 ]] && break
    sleep 0.05
done
t0=$(date +%s%N)
kill -TERM "$B_pid"
sleep 0.2
late=$(curl -s -o /dev/null -w '%{http_code}' "${auth[@]}" "$B/v1/render?w=64&h=64")
check "after SIGTERM new renders are refused (status $late: 503 or no connection)" [ "$late" = 503 -o "$late" = 000 ]
wait "$slow_pid"
check "the render in flight at SIGTERM finished: 200 $(cat "$work/slow2.code")" pngs "$work/slow2.png:96:96"
stop "$B_pid"; rc=$?
t1=$(date +%s%N)
check "B: exit 0 after draining ($rc, $(( (t1 - t0) / 1000000 )) ms after SIGTERM)" [ "$rc" = 0 ]
check "B log says draining then stopped" bash -c "grep -q 'SIGTERM: draining' '$work/B.log' && grep -q 'stopped' '$work/B.log'"

# ---- C: a render deadline shorter than the render; limits up to what the device can do ----
start C --store-dir "$work/storeC" --render-timeout 0.1 --max-width 4096 --max-height 4096
c=$(req "$work/e" GET "$base/v1/render?w=4000&h=4000")
check "413 image larger than the device renders ($c): $(json_field "$work/e" '["detail"]')" problem "$work/e" 413 w
c=$(req "$work/e" GET "$base/v1/render?method=reference&w=384&h=384")
check "render over render-timeout -> 503 ($c): $(json_field "$work/e" '["detail"]' | cut -c1-60)" problem "$work/e" 503 ""
# The overdue reference render (many seconds) is cancelled, so the worker is free again at once.
t0=$(date +%s%N)
for _ in $(seq 1 60); do
    [[ $(curl -s "$base/metrics" | awk '$1 == "lucentd_renders_in_flight" { print $2 }') == 0 ]] && break
    sleep 0.05
done
t1=$(date +%s%N)
check "the overdue render was cancelled: no render in flight $(( (t1 - t0) / 1000000 )) ms after its 503 (< 3000)" \
    [ $(( (t1 - t0) / 1000000 )) -lt 3000 ]
c=$(req "$work/h" GET "$base/healthz")
check "daemon still healthy after a deadline ($c)" [ "$c" = 200 ]
stop "$pid"; rc=$?
check "C: exit 0 with a render still running at the deadline ($rc)" [ "$rc" = 0 ]

echo "whole test: $SECONDS s"
echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
