#!/usr/bin/env bash
# fast_vs_cycles.sh - issue 16's time target: Lucent's default fast method against Blender Cycles at a few samples
# a pixel (16), on the same machine and scenes (scenes.py), each scored against the truth of its own boundary.
#
# Usage:
#   tests/bench/cycles/fast_vs_cycles.sh --lucent-render build/lucent-render --bench-frames
#       build/tests/bench/bench_frames --bunny build/bunny.obj --out DIR [--size 256] [--cycles-samples 16]
#       [--walks 16] [--method five] [--scene NAME]... [--blender blender]
#
# Per scene: Cycles (Subsurface Scattering node, no Fresnel) twice, seeds 0 and 1: its error against its own
# converged image is its noise, rel L2 between the two / sqrt(2) (unbiased: the same estimator, other samples).
# Lucent: the method's warm frame (bench_frames, median of 7: what a warm lucentd spends on a request) and
# lucent-render's cold run (start, shader compile, one frame); its error against method "path" (boundary fresnel,
# the physics the method models; two halves of the walks under seeds 1 and 2, the error against their mean), and
# with the walks' noise cancelled (lucent-render --compare given both halves: sqrt(sum (test - a).(test - b) /
# sum a.b), with its interval of 2 standard errors).
# Time ratio: Cycles' render (bpy render call: scene sync, BVH, sampling; not Blender's start) over the warm
# frame, and process over process. Prints a Markdown table, writes DIR/fast_vs_cycles.md. Not part of CI.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# shellcheck source=common.sh
. "$here/common.sh"
lucent=""; frames=""; bunny=""; out=""; size=256; samples=16; walks=16; method=five; blender=blender
scenes=()
while [ $# -gt 0 ]; do
    case "$1" in
        --lucent-render) lucent="$2"; shift 2 ;;
        --bench-frames) frames="$2"; shift 2 ;;
        --bunny) bunny="$2"; shift 2 ;;
        --out) out="$2"; shift 2 ;;
        --size) size="$2"; shift 2 ;;
        --cycles-samples) samples="$2"; shift 2 ;;
        --walks) walks="$2"; shift 2 ;;
        --method) method="$2"; shift 2 ;;
        --scene) scenes+=("$2"); shift 2 ;;
        --blender) blender="$2"; shift 2 ;;
        -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
        *) die "unknown argument $1 (see --help)" ;;
    esac
done
require_inputs
[ -n "$frames" ] && [ -x "$frames" ] || die "--bench-frames PATH (build/tests/bench/bench_frames) is required"
(( walks >= 2 && walks % 2 == 0 )) || die "--walks must be even and at least 2 (two halves)"
command -v oiiotool >/dev/null || die "oiiotool not found (apt-get install openimageio-tools)"
default_scenes marble skin1
write_scenes

cpu="$(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1)"
table="$out/fast_vs_cycles.md"
{
    echo "CPU: $cpu, $(nproc) threads; $("$blender" --version 2>/dev/null | head -1); ${size}x${size};" \
         "Cycles $samples samples/pixel (sss node), seeds 0 and 1; Lucent \`$method\` (dipole); path $walks walks in two halves (seeds 1, 2), boundary fresnel."
    echo
    echo "| scene | Cycles render s | Cycles process s | Cycles noise (rel L2) | $method warm ms | $method process s | $method rel L2 vs path | w/o path noise | its bound (2 standard errors) | path noise | render ratio | process ratio |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$table"
for name in "${scenes[@]}"; do
    dir="$out/$name"
    base="$dir/scene.json"
    device=""
    cyc_s=(); cyc_wall=()
    for seed in 0 1; do
        t0=$(now)
        cyc_s+=("$(cycles "$base" "$dir/cycles$samples.$seed.exr" "$samples" "$seed" "$dir/cycles$samples.$seed.log")") ||
            exit 1
        cyc_wall+=("$(secs "$t0" "$(now)")")
    done
    diff2=$(squares "$dir/cycles$samples.0.exr" "$dir/cycles$samples.1.exr")
    ref2=$(squares "$dir/cycles$samples.1.exr")
    cyc_noise=$(awk -v d="$diff2" -v r="$ref2" 'BEGIN { printf "%.4f", sqrt(d / r / 2) }')

    # The walks are the slow part: kept while their scene documents are unchanged.
    for seed in 1 2; do
        variant "$base" "method=\"path\"" "path={\"samples\":$((walks / 2)),\"boundary\":\"fresnel\",\"seed\":$seed}" |
            write_if_changed "$dir/path$seed.json"
        [ -s "$dir/path$seed.exr" ] && [ "$dir/path$seed.exr" -nt "$dir/path$seed.json" ] ||
            "$lucent" "$dir/path$seed.json" -o "$dir/path$seed.exr" --stats > "$dir/path$seed.stats" 2> "$dir/path$seed.log"
    done

    variant "$base" "method=\"$method\"" > "$dir/$method.json"
    t0=$(now)
    "$lucent" "$dir/$method.json" -o "$dir/$method.exr" --compare "$dir/path1.exr" --compare "$dir/path2.exr" \
        > "$dir/$method.cmp" 2> "$dir/$method.log"
    t1=$(now)
    fast_wall=$(secs "$t0" "$t1")
    rel=$(field "$dir/$method.cmp" rel_l2)
    # "without_noise" is null where the walks are black (too few of them): "-" then.
    grep -o '"without_noise":.*' "$dir/$method.cmp" > "$dir/$method.wn" || true
    clean=$(field "$dir/$method.wn" rel_l2 || true) high=$(field "$dir/$method.wn" high || true)
    path_noise=$(field "$dir/$method.wn" noise || true)
    "$frames" 7 "$dir/$method.frames.md" "$dir/$method.json" > /dev/null 2>> "$dir/$method.log"
    device=$(head -1 "$dir/$method.frames.md")
    warm=$(awk -F'|' 'NF > 4 && $2 != " scene " && $2 !~ /^-+$/ { gsub(/ /, "", $3); print $3 }' "$dir/$method.frames.md")
    row=$(awk -v n="$name" -v cs="${cyc_s[0]}" -v cw="${cyc_wall[0]}" -v cn="$cyc_noise" -v w="$warm" \
              -v fw="$fast_wall" -v r="$rel" -v c="${clean:--}" -v h="${high:--}" -v pn="${path_noise:--}" 'BEGIN {
        printf "| %s | %.2f | %.2f | %.4f | %.1f | %.2f | %.4f | %s | %s | %s | %.0fx | %.1fx |", n, cs, cw, cn, w,
               fw, r, c, h, pn, cs * 1000 / w, cw / fw }')
    echo "$row" >> "$table"
    echo "$row"
done
echo >> "$table"
echo "Lucent $device" >> "$table"
echo
cat "$table"
