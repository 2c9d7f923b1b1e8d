#!/usr/bin/env bash
# path_vs_cycles.sh - issue 16's first target: Lucent's random walk (method "path", boundary "cycles": no Fresnel,
# cosine entry and exit, as Cycles' random walk) against Blender Cycles' random walk on the same scenes (scenes.py).
#
# Usage:
#   tests/bench/cycles/path_vs_cycles.sh --lucent-render build/lucent-render [--bunny build/bunny.obj] --out DIR
#       [--size 256] [--cycles-samples 512] [--walks 64] [--filter point|box] [--sphere-level 5] [--scene NAME]...
#       [--blender blender]
#
# Per scene: Cycles (Subsurface Scattering node) with seeds 0 and 1 (c0, c1), and path as two halves of --walks
# under seeds 1 and 2 (p1, p2). Both are unbiased estimators of their own images, so
# sqrt(sum (p1 - c0).(p2 - c1) / sum c0.c1) (both pairings; lucent-render --compare twice with --twin) is their
# difference with both noises cancelled, not estimated and subtracted; with an interval of 2 standard errors.
# Also the rel L2 and mean ratio of path's mean against Cycles' mean and each side's noise. Prints a Markdown
# table, writes DIR/path_vs_cycles.md (path_vs_cycles-box.md with --filter box). --filter: point (default), one ray
# through each pixel centre (Cycles' narrowest filter, 0.01 px); box, both renderers over the whole pixel (Cycles'
# box, path's "filter": "box"), where silhouettes holding most of the light (back-lit) are not sub-pixel
# sensitive. --sphere-level: the icosphere's subdivisions (5: 20480 triangles; 6: 81920, where the back-lit
# sphere's rim follows the facets less; use another DIR per level, as the scenes keep their names).
# Not part of CI; minutes a scene (the walks and Cycles; Cycles' images are kept across runs).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# shellcheck source=common.sh
. "$here/common.sh"
lucent=""; bunny=""; out=""; size=256; samples=512; walks=64; blender=blender; filter=point; sphere_level=5
scenes=()
while [ $# -gt 0 ]; do
    case "$1" in
        --lucent-render) lucent="$2"; shift 2 ;;
        --bunny) bunny="$2"; shift 2 ;;
        --out) out="$2"; shift 2 ;;
        --size) size="$2"; shift 2 ;;
        --cycles-samples) samples="$2"; shift 2 ;;
        --walks) walks="$2"; shift 2 ;;
        --filter) filter="$2"; shift 2 ;;
        --sphere-level) sphere_level="$2"; shift 2 ;;
        --scene) scenes+=("$2"); shift 2 ;;
        --blender) blender="$2"; shift 2 ;;
        -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
        *) die "unknown argument $1 (see --help)" ;;
    esac
done
require_inputs
[ $((walks % 2)) -eq 0 ] && [ "$walks" -ge 2 ] || die "--walks must be even (two halves), got $walks"
case "$filter" in point) tag="" ;; box) tag="-box" ;; *) die "--filter must be point or box, got $filter" ;; esac
[[ $sphere_level =~ ^[0-7]$ ]] || die "--sphere-level must be 0..7, got $sphere_level"
default_scenes skin1
write_scenes

table="$out/path_vs_cycles$tag.md"
{
    echo "CPU: $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1), $(nproc) threads;" \
         "$("$blender" --version 2>/dev/null | head -1); ${size}x${size}; Cycles $samples samples/pixel x 2 seeds" \
         "(sss node); path $walks walks as 2 halves of $((walks / 2)), boundary cycles; pixel filter $filter;" \
         "sphere: icosphere level $sphere_level ($((20 << (2 * sphere_level))) triangles)."
    echo
    echo "| scene | Cycles s | path s | rel L2 of the means | mean ratio | Cycles noise | path noise |" \
         "w/o both noises | interval |"
    echo "|---|---|---|---|---|---|---|---|---|"
} > "$table"
for name in "${scenes[@]}"; do
    dir="$out/$name"
    base="$dir/scene.json"
    cyc_s=0
    for seed in 0 1; do
        s=$(cycles "$base" "$dir/cycles$samples$tag.$seed.exr" "$samples" "$seed" "$dir/cycles$samples$tag.$seed.log" \
                   "$filter") || exit 1
        cyc_s=$(awk -v a="$cyc_s" -v b="$s" 'BEGIN { print a + b }')
    done
    t0=$(now)
    for seed in 1 2; do
        variant "$base" "method=\"path\"" \
            "path={\"samples\":$((walks / 2)),\"boundary\":\"cycles\",\"filter\":\"$filter\",\"seed\":$seed}" \
            > "$dir/path-cycles$tag.$seed.json"
    done
    "$lucent" "$dir/path-cycles$tag.1.json" -o "$dir/path-cycles$tag.1.exr" 2> "$dir/path-cycles$tag.1.log"
    "$lucent" "$dir/path-cycles$tag.2.json" -o "$dir/path-cycles$tag.2.exr" --twin "$dir/path-cycles$tag.1.exr" \
        --compare "$dir/cycles$samples$tag.0.exr" --compare "$dir/cycles$samples$tag.1.exr" \
        > "$dir/path-cycles$tag.cmp" 2> "$dir/path-cycles$tag.2.log"
    path_s=$(secs "$t0" "$(now)")
    grep -o '"without_noise":.*' "$dir/path-cycles$tag.cmp" > "$dir/path-cycles$tag.wn" || die "$name: Cycles' image is black"
    row=$(awk -v n="$name" -v cs="$cyc_s" -v ps="$path_s" -v r="$(field "$dir/path-cycles$tag.cmp" rel_l2)" \
              -v m="$(field "$dir/path-cycles$tag.cmp" mean_ratio)" -v cn="$(field "$dir/path-cycles$tag.wn" noise)" \
              -v pn="$(field "$dir/path-cycles$tag.wn" test_noise)" -v w="$(field "$dir/path-cycles$tag.wn" rel_l2)" \
              -v lo="$(field "$dir/path-cycles$tag.wn" low)" -v hi="$(field "$dir/path-cycles$tag.wn" high)" 'BEGIN {
        printf "| %s | %.1f | %.1f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f-%.4f |", n, cs, ps, r, m, cn, pn, w, lo, hi }')
    echo "$row" >> "$table"
    echo "$row"
done
echo
cat "$table"
