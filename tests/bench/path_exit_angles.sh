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

centre() {  # centre EXR: the mean R G B of the 3x3 centre pixels
    oiiotool "$1" --ch R,G,B --cut 3x3+3+3 --printinfo:stats=1 2>/dev/null | awk '/Stats Avg/ { print $3, $4, $5; exit }'
}
ratios() {  # ratios "r g b" "r g b": the first over the second, per channel
    awk -v a="$1" -v b="$2" 'BEGIN { split(a, x, " "); split(b, y, " ");
        printf "%.3f / %.3f / %.3f", (y[1] > 0 ? x[1] / y[1] : 0), (y[2] > 0 ? x[2] / y[2] : 0), (y[3] > 0 ? x[3] / y[3] : 0) }'
}

# tests/flat_cube.h's slab, half as thick as wide: far thicker than any preset's diffusion length at 200 mm
awk 'BEGIN { h = 0.25
    printf "v -0.5 -0.5 %s\nv 0.5 -0.5 %s\nv 0.5 0.5 %s\nv -0.5 0.5 %s\n", -h, -h, -h, -h
    printf "v -0.5 -0.5 %s\nv 0.5 -0.5 %s\nv 0.5 0.5 %s\nv -0.5 0.5 %s\n", h, h, h, h
    print "vn 1 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\nvn 0 0 1\nvn 0 0 -1"
    print "f 2//1 3//1 7//1\nf 2//1 7//1 6//1\nf 1//2 5//2 8//2\nf 1//2 8//2 4//2"
    print "f 4//3 8//3 7//3\nf 4//3 7//3 3//3\nf 1//4 2//4 6//4\nf 1//4 6//4 5//4"
    print "f 5//5 6//5 7//5\nf 5//5 7//5 8//5\nf 1//6 4//6 3//6\nf 1//6 3//6 2//6"
}' > "$dir/slab.obj"

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
        row="| $preset | $angle | $p | $(ratios "$(centre "$dir/ref.exr")" "$p") |"
        if [[ -n $before ]]; then
            "$before" "$dir/ref.json" -o "$dir/before.exr" > /dev/null
            row="$row $(ratios "$(centre "$dir/before.exr")" "$p") |"
        fi
        echo "$row" | tee -a "$out"
    done
done
