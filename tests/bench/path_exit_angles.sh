#!/usr/bin/env bash
# path_exit_angles.sh - the diffuse exit against light itself: a half-space (a slab 200 mm wide, 100 mm thick)
# lit head-on and seen from 0 to 75 degrees off its normal; the centre (3x3 pixels of 9x9) of method
# "reference" over method "path" (boundary fresnel: the camera ray refracts into the walk, so the view side is
# exact), per channel. Prints a Markdown table and writes it to OUT. BEFORE_RENDER (optional) adds a column
# for another build's reference. Not a test; about a minute at 256 walks.
# usage: path_exit_angles.sh LUCENT_RENDER [OUT.md] [WALKS] [BEFORE_RENDER]
set -euo pipefail
bin=$1 out=${2:-path_exit_angles.md} walks=${3:-256} before=${4:-}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

# shellcheck source=slab_helpers.sh
. "$(dirname "${BASH_SOURCE[0]}")/slab_helpers.sh"
# half as thick as wide: far thicker than any preset's diffusion length at 200 mm
write_slab_obj "$dir/slab.obj" 0.25

{
    echo "A half-space lit head-on, seen at an angle, centre over method \"path\" ($walks walks), R / G / B."
    echo "CPU: $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1), $(nproc) threads."
    echo
    echo "| material | view angle | path centre (R G B) | reference / path |${before:+ reference before / path |}"
    echo "|---|---|---|---|${before:+---|}"
} > "$out"
for preset in marble skimmilk skin1; do
    for angle in 0 30 60 75; do
        view=$(awk -v a="$angle" 'BEGIN { r = a * 3.14159265358979 / 180; printf "[%.6f,0,%.6f]", sin(r), -cos(r) }')
        base="\"mesh\":{\"file\":\"$dir/slab.obj\"},\"scale_mm\":200,\"material\":{\"preset\":\"$preset\"},\"lights\":[{\"direction\":[0,0,-1],\"intensity\":1}],\"camera\":{\"direction\":$view,\"fov_deg\":10},\"width\":9,\"height\":9"
        echo "{$base,\"method\":\"path\",\"path\":{\"samples\":$walks}}" > "$dir/path.json"
        echo "{$base,\"method\":\"reference\"}" > "$dir/ref.json"
        "$bin" "$dir/path.json" -o "$dir/path.exr" > /dev/null
        "$bin" "$dir/ref.json" -o "$dir/ref.exr" > /dev/null
        p=$(centre "$dir/path.exr")
        row="| $preset | $angle | $p | $(ratios "$(centre "$dir/ref.exr")" "$p" 3) |"
        if [[ -n $before ]]; then
            "$before" "$dir/ref.json" -o "$dir/before.exr" > /dev/null
            row="$row $(ratios "$(centre "$dir/before.exr")" "$p" 3) |"
        fi
        echo "$row" | tee -a "$out"
    done
done
