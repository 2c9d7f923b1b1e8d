#!/usr/bin/env bash
# accuracy_headline.sh - the headline of the speed/accuracy trade: single and five-view (both samplings)
# against method "reference" on the side-lit protrusion and bunny, whole object and silhouette band,
# with each mode's one-shot time (a cold process: includes shader compilation; warm timings are
# bench_table2's). Prints a Markdown table and writes it to OUT (not a test).
# usage: accuracy_headline.sh LUCENT_RENDER BUNNY_OBJ [OUT.md] [SIZE]
set -euo pipefail
bin=$1 bunny=$2 out=${3:-accuracy_headline.md} size=${4:-256}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

json_field() {  # json_field FILE KEY [SECOND-MATCH]: the first (or the band's) number after "KEY":
    grep -o "\"$2\":[-0-9.e+]*" "$1" | sed -n "${3:-1}p" | cut -d: -f2
}

{
    echo "Accuracy against \"reference\" at ${size}x${size}, light from the camera's right at 90 degrees, marble."
    echo
    echo "| scene | mode | one-shot ms | rel L2 | p99 rel | share >10% | band rel L2 | band p99 rel | band share >10% |"
    echo "|---|---|---|---|---|---|---|---|---|"
} > "$out"

for mesh in '{"builtin":"protrusion"}' "{\"file\":\"$bunny\"}"; do
    name=$(sed 's/.*"builtin":"\([a-z]*\)".*/\1/; s/.*"file".*/bunny/' <<<"$mesh")
    base="\"mesh\":$mesh,\"material\":{\"preset\":\"marble\"},\"lights\":[{\"direction\":[-1,0,0],\"intensity\":3}],\"camera\":{\"direction\":[0,0,-1]},\"width\":$size,\"height\":$size"
    echo "{$base,\"method\":\"reference\"}" > "$dir/ref.json"
    "$bin" "$dir/ref.json" -o "$dir/ref.exr" --stats > "$dir/ref.stats"
    ref_ms=$(json_field "$dir/ref.stats" total)
    echo "| $name | reference | $ref_ms | 0 | 0 | 0 | 0 | 0 | 0 |" >> "$out"
    for mode in '"method":"single"' '"method":"five"' '"method":"single","sampling":"per_channel"' \
                '"method":"five","sampling":"per_channel"' '"method":"five","samples":64'; do
        echo "{$base,$mode}" > "$dir/m.json"
        "$bin" "$dir/m.json" -o "$dir/m.png" --stats --compare "$dir/ref.exr" > "$dir/m.out"
        grep '"compare"' "$dir/m.out" > "$dir/cmp"
        ms=$(json_field "$dir/m.out" total)
        label=$(tr -d '"' <<<"$mode" | sed 's/method://; s/,sampling:/ /; s/,samples:/ samples /')
        printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$label" "$ms" \
            "$(json_field "$dir/cmp" rel_l2)" "$(json_field "$dir/cmp" p99_rel)" \
            "$(json_field "$dir/cmp" share_over_10pct)" "$(json_field "$dir/cmp" rel_l2 2)" \
            "$(json_field "$dir/cmp" p99_rel 2)" "$(json_field "$dir/cmp" share_over_10pct 2)" >> "$out"
    done
done
cat "$out"
