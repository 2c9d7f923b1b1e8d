# common.sh - shell helpers of the Cycles comparisons (compare.sh, fast_vs_cycles.sh, path_vs_cycles.sh): clocks,
# arguments, scene documents and variants, Cycles renders with their own timing, squared-error sums with oiiotool. Sourced.

die() { echo "${0##*/}: $*" >&2; exit 2; }

# require_inputs: the arguments every script needs ($lucent an executable, $out) and Blender ($blender)
require_inputs() {
    [ -n "$lucent" ] && [ -x "$lucent" ] || die "--lucent-render PATH (an executable lucent-render) is required"
    [ -n "$out" ] || die "--out DIR is required"
    command -v "$blender" >/dev/null || die "blender not found (Debian 12: apt-get install blender, 3.4.1)"
}

# default_scenes MATERIAL...: unless --scene named some, the sphere's side- and back-lit scenes in each material,
# then the bunny's when $bunny is given
default_scenes() {
    [ ${#scenes[@]} -eq 0 ] || return 0
    local shape material
    for shape in sphere ${bunny:+bunny}; do
        for material in "$@"; do
            scenes+=("$shape-$material-side" "$shape-$material-back")
        done
    done
}

now() { date +%s%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", (b - a) / 1e9 }'; }

# variant BASE KEY=JSON...: the scene BASE with top-level keys replaced (profile= sets material.profile), to stdout
variant() {
    python3 -c 'import json, sys
doc = json.load(open(sys.argv[1]))
for kv in sys.argv[2:]:
    k, v = kv.split("=", 1)
    if k == "profile":
        doc["material"]["profile"] = v
    else:
        doc[k] = json.loads(v)
print(json.dumps(doc, indent=1))' "$@"
}

# write_scenes: makes $out and $bunny absolute and writes the documents of the scenes ${scenes[@]} under $out
# (scenes.py; needs $here and $size; the icosphere's level is ${sphere_level:-5})
write_scenes() {
    mkdir -p "$out"; out="$(cd "$out" && pwd)"
    [ -z "$bunny" ] || bunny="$(cd "$(dirname "$bunny")" && pwd)/$(basename "$bunny")"
    python3 "$here/scenes.py" "$out" "$size" "${bunny:-}" --sphere-level "${sphere_level:-5}" "${scenes[@]}"
}

# write_if_changed FILE: stdin into FILE unless FILE already holds it (its age then says what is stale)
write_if_changed() {
    local new="$1.new"
    cat > "$new"
    if cmp -s "$new" "$1"; then rm "$new"; else mv "$new" "$1"; fi
}

# squares A [B]: the per-channel means of (A - B)^2 (of A^2 without B) over R, G, B, summed
squares() {
    if [ -n "${2:-}" ]; then
        oiiotool "$1" --ch R,G,B "$2" --ch R,G,B --sub --dup --mul --printstats
    else
        oiiotool "$1" --ch R,G,B --dup --mul --printstats
    fi | awk '/Stats Avg:/ { for (i = 3; i <= 5; i++) s += $i } END { printf "%.10g", s }'
}

# field FILE KEY: the first numeric value of "KEY": in FILE (lucent-render's --stats and --compare JSON)
field() { grep -o "\"$2\":[-0-9.e+]*" "$1" | head -1 | cut -d: -f2; }

# cycles SCENE OUT.exr SAMPLES SEED LOG [FILTER]: renders with Blender (scene.py, Subsurface Scattering node, pixel
# filter point (default) or box); prints the seconds Cycles itself reports (scene sync, BVH, sampling; not
# Blender's start). Needs $blender and $here.
# Cycles is deterministic for a seed, so an image newer than its scene, scene.py and jensen_to_cycles.py, with
# its log, is kept and its seconds read from that log (scenes.py rewrites a scene only when it changes);
# remove DIR to render everything again (another Blender, thread count or machine).
cycles() {
    local dep fresh=1
    for dep in "$1" "$here/scene.py" "$here/jensen_to_cycles.py"; do
        [ -s "$2" ] && [ "$2" -nt "$dep" ] || fresh=0
    done
    if [ "$fresh" -eq 0 ] || ! grep -q '^CYCLES_INFO ' "$5" 2>/dev/null; then
        "$blender" -b --factory-startup -P "$here/scene.py" -- "$1" "$2" --samples "$3" --seed "$4" \
            --filter "${6:-point}" > "$5" 2>&1 &&
            [ -s "$2" ] || { echo "Cycles failed on $1 (see $5)" >&2; return 1; }
    fi
    grep '^CYCLES_INFO ' "$5" | grep -o '"seconds": [0-9.]*' | cut -d' ' -f2
}
