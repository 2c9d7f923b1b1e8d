#!/usr/bin/env bash
# path_vs_dipole.sh - how far the dipole model is from light itself: method "path" (random walks, boundary
# "fresnel") renders the bunny and the sphere, side- and back-lit, in marble and skin1; method "reference"
# (the dipole's ground truth) and "five" are scored against it (relative L2, mean ratio, noise), beside the
# path image's own relative standard error, which bounds how much of that error is the walks' noise. Prints a
# Markdown table and writes it to OUT (not a test; minutes: the walks dominate).
# usage: path_vs_dipole.sh LUCENT_RENDER BUNNY_OBJ [OUT.md] [SIZE] [WALKS]
set -euo pipefail
bin=$1 bunny=$2 out=${3:-path_vs_dipole.md} size=${4:-64} walks=${5:-64}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

field() {  # field FILE KEY: the first number after "KEY":
    grep -o "\"$2\":[-0-9.e+]*" "$1" | head -1 | cut -d: -f2
}

{
    echo "Method \"path\" (boundary fresnel, $walks walks a pixel and channel) against the dipole at ${size}x${size};"
    echo "CPU: $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1), $(nproc) threads."
    echo
    echo "| scene | path ms | path rel std error | path steps/walk | reference rel L2 | reference mean ratio | five rel L2 | five mean ratio |"
    echo "|---|---|---|---|---|---|---|---|"
} > "$out"
cat "$out"

for mesh in "{\"file\":\"$bunny\"}" '{"builtin":"sphere"}'; do
    for light in side back; do
        for preset in marble skin1; do
            name=$(sed 's/.*"builtin":"\([a-z]*\)".*/\1/; s/.*"file".*/bunny/' <<<"$mesh")
            dir_json='[-1,0,0]'
            [[ $light == back ]] && dir_json='[0,0,1]'
            base="\"mesh\":$mesh,\"material\":{\"preset\":\"$preset\"},\"lights\":[{\"direction\":$dir_json,\"intensity\":3}],\"camera\":{\"direction\":[0,0,-1]},\"width\":$size,\"height\":$size"
            echo "{$base,\"method\":\"path\",\"path\":{\"samples\":$walks}}" > "$dir/path.json"
            "$bin" "$dir/path.json" -o "$dir/path.exr" --stats > "$dir/path.stats"
            row="| $name, $light light, $preset | $(field "$dir/path.stats" total) | $(field "$dir/path.stats" rel_std_error) | $(field "$dir/path.stats" mean_steps)"
            for method in reference five; do
                echo "{$base,\"method\":\"$method\"}" > "$dir/m.json"
                "$bin" "$dir/m.json" -o "$dir/m.png" --compare "$dir/path.exr" > "$dir/m.cmp"
                row="$row | $(field "$dir/m.cmp" rel_l2) | $(field "$dir/m.cmp" mean_ratio)"
            done
            echo "$row |" | tee -a "$out"
        done
    done
done
