#!/usr/bin/env bash
# frame_ratio.sh - the frame time of one build over another's, measured side by side: runs each build's
# bench_frames on the same scene documents, alternating, ROUNDS times, and prints per scene the median
# total frame of each and their ratio (after / before), with the CPU and device bench_frames reports.
# usage: frame_ratio.sh BEFORE_BUILD AFTER_BUILD ROUNDS SCENE.json...   (builds: cmake build folders)
set -euo pipefail
if [[ $# -lt 4 ]] || ! [[ $3 =~ ^[1-9][0-9]*$ ]]; then
    echo "usage: $0 BEFORE_BUILD AFTER_BUILD ROUNDS SCENE.json..." >&2
    exit 2
fi
before=$1/tests/bench/bench_frames after=$2/tests/bench/bench_frames rounds=$3
shift 3
for b in "$before" "$after"; do [[ -x $b ]] || { echo "$0: no $b (cmake --build DIR --target bench_frames)" >&2; exit 2; }; done
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for ((i = 0; i < rounds; i++)); do
    "$before" 7 "$dir/before.$i.md" "$@"
    "$after" 7 "$dir/after.$i.md" "$@"
done
head -n 1 "$dir/after.0.md"
python3 - "$dir" "$rounds" <<'PY'
import statistics, sys
d, rounds = sys.argv[1], int(sys.argv[2])
def totals(build):
    out = {}
    for i in range(rounds):
        for line in open(f"{d}/{build}.{i}.md"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) == 4 and cells[0] not in ("scene", "---"):
                out.setdefault(cells[0], []).append(float(cells[1]))
    return out
b, a = totals("before"), totals("after")
print(f"\n| scene | before ms | after ms | after / before |\n|---|---|---|---|")
for scene in b:
    mb, ma = statistics.median(b[scene]), statistics.median(a[scene])
    print(f"| {scene} | {mb:.1f} | {ma:.1f} | {ma / mb:.2f} |")
PY
