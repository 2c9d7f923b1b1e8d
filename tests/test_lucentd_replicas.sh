#!/usr/bin/env bash
# test_lucentd_replicas.sh - several lucentd processes on one mesh store directory, as replicas on a
# shared volume: an upload through one renders on the others, a delete through one is a 404 on the
# others, uploads through all at once keep the byte budget and leave every entry whole, a replica that
# starts on the store serves its meshes at once, and one request gives the same bytes (PNG and EXR) on
# every replica and after a restart. Usage: test_lucentd_replicas.sh PATH/TO/lucentd
set -u
lucentd=$1
source "$(dirname "$0")/lucentd_harness.sh"

store=$work/store
# obj FILE N: a small tetrahedron of its own for each N.
obj() {
    printf 'v %d 0 0\nv %d 0 0\nv %d 1 0\nv %d 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' \
        "$2" "$(($2 + 1))" "$2" "$2" >"$1"
}
upload() { req "$3" POST "$1/v1/meshes" -H 'Content-Type: model/obj' --data-binary "@$2"; }

start R1 --store-dir "$store"
R1=$base R1_pid=$pid
start R2 --store-dir "$store"
R2=$base R2_pid=$pid

obj "$work/a.obj" 0
c=$(upload "$R1" "$work/a.obj" "$work/a.json")
a=$(json_field "$work/a.json" '["id"]')
c2=$(req "$work/a2.png" GET "$R2/v1/render?w=48&h=48&mesh=$a")
check "uploaded through R1 ($c), rendered by R2 ($c2)" [ "$c" = 201 -a "$c2" = 200 ]
c=$(upload "$R2" "$work/a.obj" "$work/again.json")
check "the same bytes uploaded through R2: $c (already stored)" [ "$c" = 200 ]

# One request, the same bytes from every replica (the strong ETag promises it), PNG and EXR.
q="w=64&h=64&mesh=$a&light_dir=-1,0,-1&preset=marble"
for fmt in png exr; do
    c1=$(req "$work/r1.$fmt" GET "$R1/v1/render?$q&format=$fmt")
    c2=$(req "$work/r2.$fmt" GET "$R2/v1/render?$q&format=$fmt")
    e1=$(header "$work/r1.$fmt" ETag) e2=$(header "$work/r2.$fmt" ETag)
    check "$fmt from R1 and R2 ($c1, $c2): byte-identical, one ETag $e1" \
        bash -c "[ $c1 = 200 -a $c2 = 200 ] && cmp -s '$work/r1.$fmt' '$work/r2.$fmt' && [ '$e1' = '$e2' ]"
done

# Uploads through both at once into a budget of about six meshes: the budget holds, every entry is whole.
stop "$R1_pid" >/dev/null
stop "$R2_pid" >/dev/null
one=$(( $(stat -c %s "$store/$a.lmesh") + $(stat -c %s "$store/$a.json") ))
budget=$(( 6 * one + one / 2 ))
# --max-imports 8: six uploads at once on each replica, none refused for want of an import slot
start R1 --store-dir "$store" --store-bytes "$budget" --max-imports 8
R1=$base R1_pid=$pid
start R2 --store-dir "$store" --store-bytes "$budget" --max-imports 8
R2=$base R2_pid=$pid
c1=$(req "$work/r1b.exr" GET "$R1/v1/render?$q&format=exr")
check "after a restart R1 gives the same EXR bytes ($c1)" cmp -s "$work/r1.exr" "$work/r1b.exr"
for i in $(seq 1 12); do obj "$work/m$i.obj" $((10 * i)); done
for i in $(seq 1 12); do
    if (( i % 2 )); then target=$R1; else target=$R2; fi
    upload "$target" "$work/m$i.obj" "$work/m$i.json" >"$work/m$i.code" &
done
wait_uploads() { for i in $(seq 1 12); do while [[ ! -s $work/m$i.code ]]; do sleep 0.05; done; done; }
wait_uploads
codes=$(for i in $(seq 1 12); do cat "$work/m$i.code"; echo; done | sort | uniq -c | tr -s ' ' | tr '\n' ';')
bytes=0 entries=0 whole=0
for meta in "$store"/*.json; do
    id=$(basename "$meta" .json)
    [[ -f $store/$id.lmesh ]] || continue
    entries=$((entries + 1))
    bytes=$((bytes + $(stat -c %s "$meta") + $(stat -c %s "$store/$id.lmesh")))
    c1=$(req "$work/w.png" GET "$R1/v1/render?w=32&h=32&mesh=$id")
    c2=$(req "$work/w.png" GET "$R2/v1/render?w=32&h=32&mesh=$id")
    [[ $c1 == 200 && $c2 == 200 ]] && whole=$((whole + 1))
done
temps=$(find "$store" -name '.tmp-*' | wc -l)
check "12 uploads through two replicas at once (codes: $codes) into $budget bytes: $entries entries, $bytes bytes, $whole render on both, $temps temporaries" \
    bash -c "[ '$codes' = ' 12 201;' ] && [ $bytes -le $budget -a $entries -ge 1 -a $whole = $entries -a $temps = 0 ]"

# A delete through one replica is a 404 on the other; a replica started on the store serves at once. The
# mesh deleted is one the budget kept (which of the twelve uploads were evicted depends on their order).
last=$id
c=$(req "$work/d" DELETE "$R2/v1/meshes/$last")
c1=$(req "$work/g" GET "$R1/v1/meshes/$last")
c2=$(req "$work/g.png" GET "$R1/v1/render?w=32&h=32&mesh=$last")
check "deleted through R2 ($c): R1 answers 404 for its metadata ($c1) and its render ($c2)" \
    [ "$c" = 204 -a "$c1" = 404 -a "$c2" = 404 ]
keep=$(basename "$(ls "$store"/*.json | head -1)" .json)
start R3 --store-dir "$store" --store-bytes "$budget"
c=$(req "$work/r3.png" GET "$base/v1/render?w=32&h=32&mesh=$keep")
check "R3, started on the store, renders a mesh stored before it started ($c)" [ "$c" = 200 ]
for p in "$pid" "$R1_pid" "$R2_pid"; do stop "$p" >/dev/null; done

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
