#!/usr/bin/env bash
# path_vs_profiles.sh - how far each diffusion profile is from light itself: method "path" (random walks,
# boundary "fresnel") renders the bunny and the sphere, side- and back-lit, in marble and skin1; for every
# profile (dipole, better_dipole, burley, asymptotic_dipole) methods "reference" and "five" are scored against it: relative L2
# against the walks, the same with the walks' own noise cancelled (the walks are two halves under seeds 1 and 2,
# lucent-render --compare given both: sqrt(sum (test - a).(test - b) / sum a.b)) and its interval of 2 standard
# errors, and the mean ratio. Prints a Markdown table with the medians per profile and method, writes
# it to OUT, and a sheet per scene (path | each profile's reference | five) to OUT's folder.
# Not a test; minutes: the walks dominate.
# usage: path_vs_profiles.sh LUCENT_RENDER BUNNY_OBJ [OUT.md] [SIZE] [WALKS (even)]
set -euo pipefail
bin=$1 bunny=$2 out=${3:-path_vs_profiles.md} size=${4:-64} walks=${5:-64}
(( walks >= 2 && walks % 2 == 0 )) || { echo "path_vs_profiles.sh: WALKS must be even and at least 2" >&2; exit 2; }
sheets=$(dirname "$out")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
profiles="dipole better_dipole burley asymptotic_dipole"

field() {  # field FILE KEY: the first number after "KEY":
    grep -o "\"$2\":[-0-9.e+]*" "$1" | head -1 | cut -d: -f2
}

{
    echo "Method \"path\" (boundary fresnel, $walks walks a pixel and channel) against each profile at ${size}x${size};"
    echo "CPU: $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1), $(nproc) threads."
    echo "rel L2 against the walks (two halves of $((walks / 2)), seeds 1 and 2, averaged); w/o noise: sqrt(sum (test - a).(test - b)"
    echo "/ sum a.b) over the halves a, b, in which their noise cancels, with its interval of 2 standard errors; noise: ||(a - b) / 2|| / ||truth||."
    echo
    echo "| scene | path ms | path noise | profile | reference rel L2 | w/o noise | interval | mean ratio | five rel L2 | w/o noise | interval | mean ratio |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$out"
cat "$out"
: > "$dir/rows"

for mesh in "{\"file\":\"$bunny\"}" '{"builtin":"sphere"}'; do
    for light in side back; do
        for preset in marble skin1; do
            name=$(sed 's/.*"builtin":"\([a-z]*\)".*/\1/; s/.*"file".*/bunny/' <<<"$mesh")
            dir_json='[-1,0,0]'
            [[ $light == back ]] && dir_json='[0,0,1]'
            base="\"mesh\":$mesh,\"lights\":[{\"direction\":$dir_json,\"intensity\":3}],\"camera\":{\"direction\":[0,0,-1]},\"width\":$size,\"height\":$size"
            path_ms=0
            for seed in 1 2; do
                echo "{$base,\"material\":{\"preset\":\"$preset\"},\"method\":\"path\",\"path\":{\"samples\":$((walks / 2)),\"seed\":$seed}}" > "$dir/path.json"
                "$bin" "$dir/path.json" -o "$dir/path$seed.exr" --stats > "$dir/path.stats"
                path_ms=$(awk -v a="$path_ms" -v b="$(field "$dir/path.stats" total)" 'BEGIN { printf "%.0f", a + b }')
            done
            oiiotool "$dir/path1.exr" "$dir/path2.exr" --add --mulc 0.5 -o "$dir/path.exr"  # the sheet's tile
            tiles=("$dir/path.exr")
            for profile in $profiles; do
                row="| $name, $light light, $preset | $path_ms | NOISE | $profile"
                for method in reference five; do
                    echo "{$base,\"material\":{\"preset\":\"$preset\",\"profile\":\"$profile\"},\"method\":\"$method\"}" > "$dir/m.json"
                    "$bin" "$dir/m.json" -o "$dir/$method-$profile.exr" --compare "$dir/path1.exr" \
                        --compare "$dir/path2.exr" > "$dir/m.cmp"
                    l2=$(field "$dir/m.cmp" rel_l2) ratio=$(field "$dir/m.cmp" mean_ratio)
                    # "without_noise" is null where the walks are black (too few of them): "-" then.
                    grep -o '"without_noise":.*' "$dir/m.cmp" > "$dir/wn" || true
                    clean=$(field "$dir/wn" rel_l2 || true) low=$(field "$dir/wn" low || true)
                    high=$(field "$dir/wn" high || true) noise=$(field "$dir/wn" noise || true)
                    interval="$low-$high"
                    [[ -n $low ]] || interval=-
                    clean=${clean:--} noise=${noise:--}
                    row="${row/NOISE/$noise} | $l2 | $clean | $interval | $ratio"
                    echo "$profile $method $l2 $clean $ratio" >> "$dir/rows"
                done
                tiles+=("$dir/reference-$profile.exr")
                echo "$row |" | tee -a "$out"
            done
            tiles+=("$dir/five-dipole.exr")
            # One exposure for the sheet: path | dipole | better dipole | burley references | dipole five.
            oiiotool "${tiles[@]}" --mosaic 5x1 --mulc 2 --colorconvert linear sRGB \
                -o "$sheets/path_vs_profiles_${name}_${light}_${preset}.png" 2>/dev/null || true
        done
    done
done

{
    echo
    echo "Medians over the scenes:"
    echo
    echo "| profile | method | rel L2 | w/o noise | mean ratio |"
    echo "|---|---|---|---|---|"
    for profile in $profiles; do
        for method in reference five; do
            awk -v p="$profile" -v m="$method" '$1 == p && $2 == m { l2[n] = $3; r[n++] = $5 }
                $1 == p && $2 == m && $4 != "-" { c[nc++] = $4 }
                function median(a, n,    i, j, t) {
                    for (i = 0; i < n; i++) for (j = i + 1; j < n; j++) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
                    return n % 2 ? a[(n - 1) / 2] : (a[n / 2 - 1] + a[n / 2]) / 2
                }
                END { printf "| %s | %s | %.3f | %.3f | %.3f |\n", p, m, median(l2, n), median(c, nc), median(r, n) }' "$dir/rows"
        done
    done
} | tee -a "$out"
