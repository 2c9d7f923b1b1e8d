#!/usr/bin/env bash
# path_vs_cycles.sh - issue 16's first target: Lucent's random walk (method "path", boundary "cycles": no Fresnel,
# cosine entry and exit, as Cycles' random walk) against Blender Cycles' random walk on the same scenes (scenes.py).
#
# Usage:
#   tests/bench/cycles/path_vs_cycles.sh --lucent-render build/lucent-render [--bunny build/bunny.obj] --out DIR
#       [--size 256] [--cycles-samples 512] [--walks 64] [--scene NAME]... [--blender blender]
#
# Per scene: Cycles (Subsurface Scattering node) with seeds 0 and 1, averaged; its noise is the rel L2 between the
# two / 2 (of their mean). Lucent's path scored against that mean (lucent-render --compare: rel L2, mean ratio), its
# own noise from --stats (rel_std_error). Both are unbiased estimators of their own images, so what is left of the
# rel L2 once both noises are taken out, sqrt(rel^2 - cycles^2 - path^2), is their difference converged. Prints a
# Markdown table, writes DIR/path_vs_cycles.md. Not part of CI; minutes a scene (the walks and Cycles).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# shellcheck source=common.sh
. "$here/common.sh"
lucent=""; bunny=""; out=""; size=256; samples=512; walks=64; blender=blender
scenes=()
while [ $# -gt 0 ]; do
    case "$1" in
        --lucent-render) lucent="$2"; shift 2 ;;
        --bunny) bunny="$2"; shift 2 ;;
        --out) out="$2"; shift 2 ;;
        --size) size="$2"; shift 2 ;;
        --cycles-samples) samples="$2"; shift 2 ;;
        --walks) walks="$2"; shift 2 ;;
        --scene) scenes+=("$2"); shift 2 ;;
        --blender) blender="$2"; shift 2 ;;
        -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
        *) die "unknown argument $1 (see --help)" ;;
    esac
done
require_inputs
command -v oiiotool >/dev/null || die "oiiotool not found (apt-get install openimageio-tools)"
default_scenes skin1
write_scenes

table="$out/path_vs_cycles.md"
{
    echo "CPU: $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1), $(nproc) threads;" \
         "$("$blender" --version 2>/dev/null | head -1); ${size}x${size}; Cycles $samples samples/pixel x 2 seeds" \
         "(sss node); path $walks walks, boundary cycles."
    echo
    echo "| scene | Cycles s | path s | rel L2 | mean ratio | Cycles noise | path noise | w/o both noises |"
    echo "|---|---|---|---|---|---|---|---|"
} > "$table"
for name in "${scenes[@]}"; do
    dir="$out/$name"
    base="$dir/scene.json"
    cyc_s=0
    for seed in 0 1; do
        s=$(cycles "$base" "$dir/cycles$samples.$seed.exr" "$samples" "$seed" "$dir/cycles$samples.$seed.log") || exit 1
        cyc_s=$(awk -v a="$cyc_s" -v b="$s" 'BEGIN { print a + b }')
    done
    oiiotool "$dir/cycles$samples.0.exr" --ch R,G,B "$dir/cycles$samples.1.exr" --ch R,G,B --add --mulc 0.5 \
        -o "$dir/cycles$samples.mean.exr"
    diff2=$(squares "$dir/cycles$samples.0.exr" "$dir/cycles$samples.1.exr")
    ref2=$(squares "$dir/cycles$samples.mean.exr")
    cyc_noise=$(awk -v d="$diff2" -v r="$ref2" 'BEGIN { printf "%.4f", sqrt(d / r) / 2 }')

    variant "$base" "method=\"path\"" "path={\"samples\":$walks,\"boundary\":\"cycles\",\"seed\":1}" > "$dir/path-cycles.json"
    t0=$(now)
    "$lucent" "$dir/path-cycles.json" -o "$dir/path-cycles.exr" --stats --compare "$dir/cycles$samples.mean.exr" \
        > "$dir/path-cycles.stats" 2> "$dir/path-cycles.log"
    path_s=$(secs "$t0" "$(now)")
    row=$(awk -v n="$name" -v cs="$cyc_s" -v ps="$path_s" -v r="$(field "$dir/path-cycles.stats" rel_l2)" \
              -v m="$(field "$dir/path-cycles.stats" mean_ratio)" -v cn="$cyc_noise" \
              -v pn="$(field "$dir/path-cycles.stats" rel_std_error)" 'BEGIN {
        left = r * r - cn * cn - pn * pn
        printf "| %s | %.1f | %.1f | %.4f | %.4f | %.4f | %.4f | %s |", n, cs, ps, r, m, cn, pn,
               (left > 0 ? sprintf("%.4f", sqrt(left)) : "0 (within the noise)") }')
    echo "$row" >> "$table"
    echo "$row"
done
echo
cat "$table"
