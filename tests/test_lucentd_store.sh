#!/usr/bin/env bash
# test_lucentd_store.sh - the mesh store through faults: lucentd killed (-9) during an upload and during a
# render (no partial mesh served, the restart cleans up and serves what was stored), a full file system
# (507, stored meshes intact), a store that turns read-only (a clear 500), and a read-only or impossible
# store directory at start (a loud exit). Runs in its own mount namespace, on small tmpfs mounts.
# Usage: test_lucentd_store.sh PATH/TO/lucentd
set -u
if [[ -z ${LUCENT_STORE_TEST_NS:-} ]]; then
    export LUCENT_STORE_TEST_NS=1
    # root: a mount namespace; otherwise an unprivileged user namespace may mount tmpfs too
    if unshare -m true 2>/dev/null; then exec unshare -m "$0" "$@"; fi
    if unshare -rm true 2>/dev/null; then exec unshare -rm "$0" "$@"; fi
    echo "FAIL cannot make a mount namespace (needs root or unprivileged user namespaces)"
    exit 1
fi
lucentd=$1
source "$(dirname "$0")/lucentd_harness.sh"

# tetra FILE SEED: a small closed OBJ, different bytes for each seed.
tetra() {
    python3 - "$1" "$2" <<'EOF'
import random, sys
r = random.Random(int(sys.argv[2]))
p = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
with open(sys.argv[1], "w") as f:
    for v in p:
        f.write("v %.6f %.6f %.6f\n" % tuple(c + r.uniform(-0.2, 0.2) for c in v))
    f.write("f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
EOF
}
upload() { req "$2" POST "$base/v1/meshes" -H 'Content-Type: model/obj' --data-binary "@$1"; }
mesh_id() { json_field "$1" '["id"]'; }
sha() { sha256sum "$1" | cut -d' ' -f1; }
temporaries() { find "$1" -name '.tmp-*' | wc -l; }
render_mesh() { req "$work/r.png" GET "$base/v1/render?w=48&h=48&mesh=$1&preset=$2"; }
# importers_of PID: the lucent-import processes (run by descriptor, their command line starts with the
# name) descended from PID. Other tests run importers at the same time (import_sandbox under ctest -j2),
# so counting every one on the machine once failed this test.
importers_of() {
    local p q
    for p in $(pgrep -f '^lucent-import --format'); do
        q=$p
        while [[ -n $q && $q != 1 && $q != "$1" ]]; do q=$(awk '/^PPid:/ { print $2 }' "/proc/$q/status" 2>/dev/null); done
        [[ $q == "$1" ]] && echo "$p"
    done
}
# alive PID...: how many of these are still lucent-import processes (not exited, not zombies).
alive() {
    local p n=0
    for p in "$@"; do tr '\0' ' ' <"/proc/$p/cmdline" 2>/dev/null | grep -q '^lucent-import --format' && n=$((n + 1)); done
    echo "$n"
}

# ---- kill -9 during an upload ----
store=$work/store
tetra "$work/a.obj" 1
python3 - "$work/big.obj" <<'EOF'
import math, sys
n = 400  # a 400 x 400 grid on a sphere: 320k triangles, a second or two of importing
with open(sys.argv[1], "w") as f:
    for i in range(n + 1):
        t = math.pi * i / n
        for j in range(n):
            p = 2 * math.pi * j / n
            f.write("v %.6f %.6f %.6f\n" % (math.sin(t) * math.cos(p), math.cos(t), math.sin(t) * math.sin(p)))
    for i in range(n):
        for j in range(n):
            a, b = i * n + j + 1, i * n + (j + 1) % n + 1
            f.write("f %d %d %d\nf %d %d %d\n" % (a, a + n, b, b, a + n, b + n))
EOF
start S1 --store-dir "$store"
c=$(upload "$work/a.obj" "$work/a.json"); a=$(mesh_id "$work/a.json")
check "mesh A stored ($c)" [ "$c" = 201 ]
upload "$work/big.obj" "$work/big.json" >/dev/null &
ours=()
for _ in $(seq 1 600); do mapfile -t ours < <(importers_of "$pid"); (( ${#ours[@]} > 0 )) && break; sleep 0.05; done
check "an upload is being imported: ${#ours[@]} importer, $(temporaries "$store") temporaries in the store" \
    [ "${#ours[@]}" -ge 1 ]
kill -KILL "$pid"; wait "$pid" 2>/dev/null
# The importer dies with the daemon (PR_SET_PDEATHSIG); a restart must cope with what it leaves.
t0=$(date +%s%N)
for _ in $(seq 1 600); do (( $(alive "${ours[@]}") == 0 )) && break; sleep 0.02; done
gone_ms=$(ms_since "$t0")
check "the importer died with the daemon: $(alive "${ours[@]}") left after $gone_ms ms (bound 1000 ms; the import takes seconds)" \
    [ "$(alive "${ours[@]}")" = 0 -a "$gone_ms" -lt 1000 ]
left=$(temporaries "$store")
start S2 --store-dir "$store"
removed=$(grep -c 'removed the unfinished or damaged file' "$log")
check "restarted after kill -9 during the upload: $left temporaries left, $removed removed, $(temporaries "$store") now" \
    [ "$(temporaries "$store")" = 0 -a "$removed" = "$left" ]
c=$(req "$work/m" GET "$base/v1/meshes/$(sha "$work/big.obj")")
check "the interrupted upload is not served ($c)" [ "$c" = 404 ]
c=$(render_mesh "$a" marble)
check "mesh A renders after the restart ($c)" [ "$c" = 200 ]
c=$(upload "$work/big.obj" "$work/big.json"); big=$(mesh_id "$work/big.json")
check "the same upload again is stored ($c)" [ "$c" = 201 ]

# ---- kill -9 during a render ----
req "$work/slow.png" GET "$base/v1/render?method=reference&w=256&h=256&mesh=$big&reference_points=20000" >/dev/null &
wait_in_flight 1 "$base"; seen=$?
check "a slow render of mesh big in flight (seen after ${waited_ms} ms)" [ "$seen" = 0 ]
kill -KILL "$pid"; wait "$pid" 2>/dev/null
start S3 --store-dir "$store"
c=$(render_mesh "$a" skin1); ca=$c
c=$(render_mesh "$big" skin1)
check "restarted after kill -9 during a render: both meshes render ($ca, $c), $(temporaries "$store") temporaries" \
    [ "$ca" = 200 -a "$c" = 200 -a "$(temporaries "$store")" = 0 ]
stop "$pid"

# ---- a full file system ----
small=$work/small
mkdir -p "$small" && mount -t tmpfs -o size=2m tmpfs "$small" || { bad "cannot mount a tmpfs"; exit 1; }
start F --store-dir "$small/store"
c=$(upload "$work/a.obj" "$work/fa.json")
check "mesh A stored on a 2 MiB file system ($c)" [ "$c" = 201 ]
head -c 4M /dev/zero >"$small/filler" 2>/dev/null
tetra "$work/b.obj" 2
c=$(upload "$work/b.obj" "$work/fb.json")
check "the file system full ($(df --output=avail -k "$small" | tail -1 | tr -d ' ') KiB free): upload 507 ($c): $(json_field "$work/fb.json" '["detail"]' 2>/dev/null)" \
    problem "$work/fb.json" 507 mesh
check "nothing half-written left: $(temporaries "$small/store") temporaries" [ "$(temporaries "$small/store")" = 0 ]
c=$(req "$work/m" GET "$base/v1/meshes/$a"); cr=$(render_mesh "$a" ketchup)
check "mesh A intact: GET $c, render $cr" [ "$c" = 200 -a "$cr" = 200 ]
rm -f "$small/filler"
c=$(upload "$work/b.obj" "$work/fb.json")
check "with room again the same upload is stored ($c)" [ "$c" = 201 ]

# ---- the store turns read-only under a running daemon ----
mount -o remount,ro "$small"
tetra "$work/c.obj" 3
c=$(upload "$work/c.obj" "$work/fc.json")
check "read-only store: upload $c: $(json_field "$work/fc.json" '["detail"]' 2>/dev/null)" \
    problem_with "$work/fc.json" 500 "" "Read-only file system"
cr=$(render_mesh "$a" apple)
check "stored meshes still render ($cr)" [ "$cr" = 200 ]
stop "$pid"

# ---- unusable store directories at start ----
for dir in "$small/store" "$work/a.obj/store"; do
    "$lucentd" --port 0 --store-dir "$dir" 2>"$work/bad.log" &
    p=$!
    pids+=("$p")
    stop_rc=0
    for _ in $(seq 1 300); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
    if kill -0 "$p" 2>/dev/null; then stop_rc=running; kill -KILL "$p"; else wait "$p"; stop_rc=$?; fi
    msg=$(grep -m1 'error lucentd' "$work/bad.log" | sed 's/.*error lucentd: //')
    check "--store-dir $dir: exits $stop_rc at start: $msg" [ "$stop_rc" = 1 -a -n "$msg" ]
done
umount "$small"

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
