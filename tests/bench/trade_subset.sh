#!/usr/bin/env bash
# trade_subset.sh - a five-minute subset of the trade for before/after comparisons of the integration:
# sphere, torus, protrusion, bunny and a flat-faced cube x front and side light x marble and skin1 at
# 256^2 (or SIZE^2), default five (both builds) and single and auto (after), scored against "reference"
# with --compare; writes every case to OUT.csv and prints the medians and worst cases (not a test).
# usage: trade_subset.sh BEFORE/lucent-render AFTER/lucent-render BUNNY.obj OUT.csv [SIZE]
set -euo pipefail
if [[ $# -ne 4 && $# -ne 5 ]] || ! [[ ${5:-256} =~ ^[0-9]+$ ]]; then
    echo "usage: $0 BEFORE/lucent-render AFTER/lucent-render BUNNY.obj OUT.csv [SIZE]" >&2
    exit 2
fi
before=$1 after=$2 bunny=$3 out=$4 size=${5:-256}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

# A unit cube with a normal per face (each face its own four vertices); the camera sees +X, +Y and +Z.
python3 - "$dir/cube.obj" <<'PY'
import sys
axes = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
lines = []
for a in axes:
    k = [i for i in range(3) if a[i]][0]
    u = [0, 0, 0]
    u[(k + 1) % 3] = 1
    v = [a[1] * u[2] - a[2] * u[1], a[2] * u[0] - a[0] * u[2], a[0] * u[1] - a[1] * u[0]]
    for cu, cv in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
        lines.append("v %d %d %d" % tuple(a[i] + cu * u[i] + cv * v[i] for i in range(3)))
    lines.append("vn %d %d %d" % a)
for f in range(6):
    b, n = 4 * f, f + 1
    lines += ["f %d//%d %d//%d %d//%d" % (b + 1, n, b + 2, n, b + 3, n),
              "f %d//%d %d//%d %d//%d" % (b + 1, n, b + 3, n, b + 4, n)]
open(sys.argv[1], "w").write("\n".join(lines) + "\n")
PY

score() {  # score BIN SCENE.json REF.exr CASE MODE BUILD: one CSV row from --compare
    "$1" "$2" -o "$dir/t.exr" --compare "$3" 2>/dev/null | python3 -c '
import json, sys
c = json.load(sys.stdin)["compare"]
print(",".join(map(str, sys.argv[1:] + [c["rel_l2"], c["silhouette_band"]["rel_l2"], c.get("noise", ""),
                                        c.get("mean_ratio", "")])))' "$4" "$5" "$6"
}

echo "case,mode,build,rel_l2,band_rel_l2,noise,mean_ratio" > "$out"
for mesh in sphere torus protrusion bunny cube; do
    cam=',"camera":{"direction":[0,0,-1]}'
    case $mesh in
        bunny) m="{\"file\":\"$bunny\"}" ;;
        cube) m="{\"file\":\"$dir/cube.obj\"}"; cam=',"camera":{"position":[2.6,2,4.4],"target":[0,0,0]}' ;;
        *) m="{\"builtin\":\"$mesh\"}" ;;
    esac
    for light in 'front:[0,0,-1]' 'side:[-1,0,0]'; do
        for material in marble skin1; do
            name="$mesh-${light%%:*}-$material"
            base="\"mesh\":$m,\"material\":{\"preset\":\"$material\"},\"lights\":[{\"direction\":${light#*:}}],\"width\":$size,\"height\":$size,\"format\":\"exr\"$cam"
            echo "{$base,\"method\":\"reference\"}" > "$dir/ref.json"
            "$after" "$dir/ref.json" -o "$dir/ref.exr" >/dev/null
            echo "{$base}" > "$dir/five.json"
            score "$before" "$dir/five.json" "$dir/ref.exr" "$name" five before >> "$out"
            for mode in five single auto; do
                echo "{$base,\"method\":\"$mode\"}" > "$dir/mode.json"
                score "$after" "$dir/mode.json" "$dir/ref.exr" "$name" "$mode" after >> "$out"
            done
            echo "$name done" >&2
        done
    done
done

python3 - "$out" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("| mode | build | rel L2 median / worst | band rel L2 median | noise median / worst | mean ratio median (range) |")
print("|---|---|---|---|---|---|")
for mode, build in [("five", "before"), ("five", "after"), ("single", "after"), ("auto", "after")]:
    sel = [r for r in rows if r["mode"] == mode and r["build"] == build]
    if not sel:
        continue
    col = lambda k: [float(r[k]) for r in sel if r[k] != ""]
    rel, band, noise, mean = col("rel_l2"), col("band_rel_l2"), col("noise"), col("mean_ratio")
    fmt = lambda v, f: f(v) if v else "-"
    print(f"| {mode} | {build} | {statistics.median(rel):.3f} / {max(rel):.3f} | {statistics.median(band):.3f} | "
          f"{fmt(noise, lambda v: f'{statistics.median(v):.3f} / {max(v):.3f}')} | "
          f"{fmt(mean, lambda v: f'{statistics.median(v):.3f} ({min(v):.3f}-{max(v):.3f})')} |")
PY
