#!/usr/bin/env bash
# path_slabs.sh - light through slabs lit from behind, against light itself: slabs 50 mm wide and 3, 10 and
# 25 mm thick, seen face-on from the unlit side, in marble and skin1; the centre (3x3 pixels of 9x9) of
# methods "reference" and "five" over method "path" (boundary fresnel), per channel. Prints a Markdown
# table and writes it to OUT. BEFORE_RENDER (optional) adds a column for another build's reference.
# Not a test; minutes (the walks).
# usage: path_slabs.sh LUCENT_RENDER [OUT.md] [WALKS] [BEFORE_RENDER]
set -euo pipefail
bin=$1 out=${2:-path_slabs.md} walks=${3:-1024} before=${4:-}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

# shellcheck source=slab_helpers.sh
. "$(dirname "${BASH_SOURCE[0]}")/slab_helpers.sh"

{
    echo "Slabs 50 mm wide lit from behind, centre of the unlit face, over method \"path\" ($walks walks), R / G / B."
    echo "CPU: $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1), $(nproc) threads."
    echo
    echo "| slab | path centre (R G B) | reference / path | five / path |${before:+ reference before / path |}"
    echo "|---|---|---|---|${before:+---|}"
} > "$out"
for thick in 3 10 25; do
    half=$(awk -v t="$thick" 'BEGIN { printf "%.6g", t / 100 }')   # half the thickness at 50 mm a unit
    write_slab_obj "$dir/slab.obj" "$half"
    for preset in marble skin1; do
        base="\"mesh\":{\"file\":\"$dir/slab.obj\"},\"scale_mm\":50,\"material\":{\"preset\":\"$preset\"},\"lights\":[{\"direction\":[0,0,1],\"intensity\":1}],\"camera\":{\"direction\":[0,0,-1]},\"width\":9,\"height\":9"
        echo "{$base,\"method\":\"path\",\"path\":{\"samples\":$walks}}" > "$dir/path.json"
        echo "{$base,\"method\":\"reference\"}" > "$dir/ref.json"
        echo "{$base,\"method\":\"five\"}" > "$dir/five.json"
        "$bin" "$dir/path.json" -o "$dir/path.exr" > /dev/null
        "$bin" "$dir/ref.json" -o "$dir/ref.exr" > /dev/null
        "$bin" "$dir/five.json" -o "$dir/five.exr" > /dev/null
        p=$(centre "$dir/path.exr")
        row="| $thick mm $preset | $p | $(ratios "$(centre "$dir/ref.exr")" "$p") | $(ratios "$(centre "$dir/five.exr")" "$p") |"
        if [[ -n $before ]]; then
            "$before" "$dir/ref.json" -o "$dir/before.exr" > /dev/null
            row="$row $(ratios "$(centre "$dir/before.exr")" "$p") |"
        fi
        echo "$row" | tee -a "$out"
    done
done
