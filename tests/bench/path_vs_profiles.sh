#!/usr/bin/env bash
# path_vs_profiles.sh - how far each diffusion profile is from light itself: method "path" (random walks,
# boundary "fresnel") renders the bunny and the sphere, side- and back-lit, in marble and skin1; for every
# profile (dipole, better_dipole, burley, asymptotic_dipole) methods "reference" and "five" are scored against it: relative L2,
# the same with the walks' own noise taken out (sqrt(rel_l2^2 - noise^2), noise the path image's relative
# standard error), and the mean ratio. Prints a Markdown table with the medians per profile and method, writes
# it to OUT, and a sheet per scene (path | each profile's reference | five) to OUT's folder.
# Not a test; minutes: the walks dominate.
# usage: path_vs_profiles.sh LUCENT_RENDER BUNNY_OBJ [OUT.md] [SIZE] [WALKS]
set -euo pipefail
bin=$1 bunny=$2 out=${3:-path_vs_profiles.md} size=${4:-64} walks=${5:-64}
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
    echo "rel L2 w/o noise: sqrt(rel L2^2 - (path rel std error)^2), the error left when the walks' noise is taken out."
    echo
    echo "| scene | path ms | path rel std error | profile | reference rel L2 | w/o noise | mean ratio | five rel L2 | w/o noise | mean ratio |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
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
            echo "{$base,\"material\":{\"preset\":\"$preset\"},\"method\":\"path\",\"path\":{\"samples\":$walks}}" > "$dir/path.json"
            "$bin" "$dir/path.json" -o "$dir/path.exr" --stats > "$dir/path.stats"
            noise=$(field "$dir/path.stats" rel_std_error)
            tiles=("$dir/path.exr")
            for profile in $profiles; do
                row="| $name, $light light, $preset | $(field "$dir/path.stats" total) | $noise | $profile"
                for method in reference five; do
                    echo "{$base,\"material\":{\"preset\":\"$preset\",\"profile\":\"$profile\"},\"method\":\"$method\"}" > "$dir/m.json"
                    "$bin" "$dir/m.json" -o "$dir/$method-$profile.exr" --compare "$dir/path.exr" > "$dir/m.cmp"
                    l2=$(field "$dir/m.cmp" rel_l2) ratio=$(field "$dir/m.cmp" mean_ratio)
                    clean=$(awk -v a="$l2" -v n="$noise" 'BEGIN { d = a * a - n * n; printf "%.4g", (d > 0 ? sqrt(d) : 0) }')
                    row="$row | $l2 | $clean | $ratio"
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
            awk -v p="$profile" -v m="$method" '$1 == p && $2 == m { l2[n] = $3; c[n] = $4; r[n++] = $5 }
                function median(a, n,    i, j, t) {
                    for (i = 0; i < n; i++) for (j = i + 1; j < n; j++) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
                    return n % 2 ? a[(n - 1) / 2] : (a[n / 2 - 1] + a[n / 2]) / 2
                }
                END { printf "| %s | %s | %.3f | %.3f | %.3f |\n", p, m, median(l2, n), median(c, n), median(r, n) }' "$dir/rows"
        done
    done
} | tee -a "$out"
