#!/usr/bin/env bash
# compare_sheet.sh - the project's before/after check for a change to a shader or pass: renders a fixed
# set of named scenes with method "reference" (once, with the --after binary; or --truth path: the random
# walks) and with the default method (or --method) with both binaries, and writes per scene one PNG sheet:
#
#   row 1: reference | before | after | |before - reference| x4 | |after - reference| x4
#   row 2: the same five, a 3x nearest-neighbour zoom of the region boxed in the reference
#
# All tiles share one exposure (the reference's 99th percentile, over covered pixels and the largest of
# R, G, B, maps to white; or --exposure). The renders are shown over a dim background, sRGB-encoded; the
# differences are |test - reference| under that exposure times --gain (4), shown linear (white = an
# error of 1/gain of the white point). --diff signed shows instead the luminance of test - reference:
# blue = too dark, red = too bright, black = equal, full colour at 1/gain of the white point. Prints
# each scene's --compare relative L2 (whole object and silhouette band; issue 10's "noise" and "mottle" where
# --compare reports them) and mean ratio of before and after against the reference, and writes them to
# OUT/summary.md. Needs oiiotool (openimageio-tools); labels need a TrueType font (fonts-dejavu-core).
# Not a test: it judges nothing, it makes the pictures to look at.
set -euo pipefail

prog=${0##*/}
all_scenes="bunny_side cube_edge protrusion_side bunny_back cube_edge_skin1 sphere_side bunny_back_single bunny_back_ketchup sphere_back_skimmilk"
default_scenes="bunny_side cube_edge protrusion_side bunny_back"

usage() {
    cat <<EOF
usage: $prog --before BIN_A --after BIN_B --out DIR [--bunny BUNNY.obj] [--size N]
       [--scene NAME...] [--exposure STOPS] [--gain G] [--diff abs|signed] [--keep-exr]
       [--method M] [--truth reference|path] [--walks N]

  --before BIN     lucent-render before the change (e.g. a build of the parent commit)
  --after BIN      lucent-render after the change; also renders the reference
  --out DIR        where the sheets (DIR/SCENE.png) and DIR/summary.md go (created)
  --bunny FILE     the bunny OBJ (build/bunny.obj, target bunny_obj); needed by the bunny scenes
  --size N         width and height of each render, 16..2048 (default 256)
  --scene NAME...  scenes to render (default: $default_scenes;
                   'all': $all_scenes)
  --exposure S     fixed exposure in stops (display = radiance x 2^S) instead of the automatic one
  --gain G         multiplier of the difference images (default 4; 16 shows subtle changes)
  --diff MODE      abs (default): |test - reference| in colour; signed: luminance of test - reference
  --keep-exr       also keep the EXRs in DIR/exr/
  --method M       the method before and after render (default: the scene's default, "five")
  --truth T        what they are held against: "reference" (default) or "path" (random walks, slow),
                   rendered by after
  --walks N        walks a pixel for --truth path (default 64)

Scenes (marble unless named; light "direction" is the way it travels; camera from +Z unless named):
  bunny_side       bunny, light from the camera's right ([-1,0,0]); zoom: the shadowed half
  cube_edge        flat-faced cube (each face its own 4 vertices and normal), only its +X face lit
                   ([-1,0,0]), seen from (2.6,2,4.4); zoom: the edge into the front face
  protrusion_side  builtin protrusion, light [-1,0,0]; zoom: the bump and the shadow side
  bunny_back       bunny, light from behind ([0,0,1]); zoom: the body
  cube_edge_skin1  cube_edge in skin1 (short mean free path)
  sphere_side      builtin sphere, light [-1,0,0]; zoom: the terminator
  bunny_back_single  bunny in skin1 from behind with single scattering; zoom: the ears
  bunny_back_ketchup bunny in ketchup from behind, single scattering not given (auto chooses); zoom: the ears
EOF
}
die() { echo "$prog: $*" >&2; exit 2; }
need_arg() { [[ $# -ge 2 && -n $2 && $2 != --* ]] || die "$1 needs a value (see --help)"; }

before='' after='' bunny='' out='' size=256 exposure='' gain=4 diff=abs keep_exr=0 scenes=() method='' truth=reference walks=64
[[ $# -gt 0 ]] || { usage >&2; exit 2; }
while [[ $# -gt 0 ]]; do
    case $1 in
    -h|--help) usage; exit 0 ;;
    --before) need_arg "$@"; before=$2; shift 2 ;;
    --after) need_arg "$@"; after=$2; shift 2 ;;
    --bunny) need_arg "$@"; bunny=$2; shift 2 ;;
    --out) need_arg "$@"; out=$2; shift 2 ;;
    --size) need_arg "$@"; size=$2; shift 2 ;;
    --exposure) [[ $# -ge 2 ]] || die "--exposure needs a value"; exposure=$2; shift 2 ;;
    --gain) need_arg "$@"; gain=$2; shift 2 ;;
    --diff) need_arg "$@"; diff=$2; shift 2 ;;
    --keep-exr) keep_exr=1; shift ;;
    --method) need_arg "$@"; method=$2; shift 2 ;;
    --truth) need_arg "$@"; truth=$2; shift 2 ;;
    --walks) need_arg "$@"; walks=$2; shift 2 ;;
    --scene)
        need_arg "$@"; shift
        while [[ $# -gt 0 && $1 != --* ]]; do
            if [[ $1 == all ]]; then read -ra s <<<"$all_scenes"; scenes+=("${s[@]}"); else scenes+=("$1"); fi
            shift
        done ;;
    *) die "unknown argument \"$1\" (see --help)" ;;
    esac
done

[[ -n $before ]] || die "--before BIN is required"
[[ -n $after ]] || die "--after BIN is required"
[[ -n $out ]] || die "--out DIR is required"
for b in "$before" "$after"; do [[ -x $b && -f $b ]] || die "not an executable file: $b"; done
if ! [[ $size =~ ^[0-9]+$ ]] || ((size < 16 || size > 2048)); then
    die "--size must be an integer 16..2048, got \"$size\""
fi
num='^-?[0-9]+([.][0-9]+)?([eE][-+]?[0-9]+)?$'
[[ -z $exposure || $exposure =~ $num ]] || die "--exposure must be a number of stops, got \"$exposure\""
if ! [[ $gain =~ $num ]] || ! awk -v g="$gain" 'BEGIN { exit !(g > 0) }'; then
    die "--gain must be a positive number, got \"$gain\""
fi
[[ $diff == abs || $diff == signed ]] || die "--diff must be abs or signed, got \"$diff\""
[[ $truth == reference || $truth == path ]] || die "--truth must be reference or path, got \"$truth\""
[[ $walks =~ ^[0-9]+$ ]] && ((walks >= 1)) || die "--walks must be a positive integer, got \"$walks\""
[[ $method =~ ^[a-z_]*$ ]] || die "--method must be a method name, got \"$method\""
command -v oiiotool >/dev/null || die "oiiotool not found (apt-get install openimageio-tools)"
((${#scenes[@]})) || read -ra scenes <<<"$default_scenes"
for s in "${scenes[@]}"; do
    [[ " $all_scenes " == *" $s "* ]] || die "unknown scene \"$s\" (known: $all_scenes)"
    if [[ $s == bunny_* ]]; then
        [[ -n $bunny ]] || die "scene $s needs --bunny FILE (build it: cmake --build build --target bunny_obj)"
        [[ -r $bunny ]] || die "cannot read the bunny: $bunny"
    fi
done
# Absolute paths: the scene documents are read from the temporary directory.
abspath() { case $1 in /*) printf '%s' "$1" ;; *) printf '%s/%s' "$PWD" "$1" ;; esac; }
before=$(abspath "$before") after=$(abspath "$after")
[[ -z $bunny ]] || bunny=$(abspath "$bunny")
[[ $bunny != *'"'* && $bunny != *\\* ]] || die "the bunny's path must not contain quotes or backslashes"

mkdir -p "$out"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/compare_sheet.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM
((keep_exr)) && mkdir -p "$out/exr"

# ---- the scenes ----
cube_obj=$tmp/cube.obj
write_cube() {  # a [-1,1]^3 cube, flat-shaded: each face has its own 4 vertices and one normal
    awk 'BEGIN {
        # per face: normal, then 4 corners counter-clockwise seen from outside
        f[1] = "1 0 0   1 -1 -1   1 1 -1   1 1 1   1 -1 1"
        f[2] = "-1 0 0  -1 -1 -1  -1 -1 1  -1 1 1  -1 1 -1"
        f[3] = "0 1 0   -1 1 -1   -1 1 1   1 1 1   1 1 -1"
        f[4] = "0 -1 0  -1 -1 -1  1 -1 -1  1 -1 1  -1 -1 1"
        f[5] = "0 0 1   -1 -1 1   1 -1 1   1 1 1   -1 1 1"
        f[6] = "0 0 -1  -1 -1 -1  -1 1 -1  1 1 -1  1 -1 -1"
        print "# flat-faced cube written by compare_sheet.sh"
        for (i = 1; i <= 6; i++) { split(f[i], a, " "); for (j = 0; j < 4; j++) print "v", a[4+3*j], a[5+3*j], a[6+3*j] }
        for (i = 1; i <= 6; i++) { split(f[i], a, " "); print "vn", a[1], a[2], a[3] }
        for (i = 1; i <= 6; i++) {
            b = 4 * (i - 1)
            printf "f %d//%d %d//%d %d//%d\n", b+1, i, b+2, i, b+3, i
            printf "f %d//%d %d//%d %d//%d\n", b+1, i, b+3, i, b+4, i
        }
    }' > "$cube_obj"
}
write_cube

side='"lights":[{"direction":[-1,0,0]}]'
cube_cam='"camera":{"position":[2.6,2.0,4.4],"target":[0,0,0]}'
front='"camera":{"direction":[0,0,-1]}'
scene_json() {  # scene_json NAME: the scene document without size and method (seen head-on unless named)
    [[ $1 == cube_edge* ]] || printf '%s,' "$front"
    case $1 in
    bunny_side) echo "\"mesh\":{\"file\":\"$bunny\"},\"material\":{\"preset\":\"marble\"},$side" ;;
    bunny_back) echo "\"mesh\":{\"file\":\"$bunny\"},\"material\":{\"preset\":\"marble\"},\"lights\":[{\"direction\":[0,0,1]}]" ;;
    cube_edge) echo "\"mesh\":{\"file\":\"$cube_obj\"},\"material\":{\"preset\":\"marble\"},$side,$cube_cam" ;;
    cube_edge_skin1) echo "\"mesh\":{\"file\":\"$cube_obj\"},\"material\":{\"preset\":\"skin1\"},$side,$cube_cam" ;;
    protrusion_side) echo "\"mesh\":{\"builtin\":\"protrusion\"},\"material\":{\"preset\":\"marble\"},$side" ;;
    sphere_side) echo "\"mesh\":{\"builtin\":\"sphere\"},\"material\":{\"preset\":\"marble\"},$side" ;;
    bunny_back_single) echo "\"mesh\":{\"file\":\"$bunny\"},\"material\":{\"preset\":\"skin1\"},\"single_scattering\":true,\"lights\":[{\"direction\":[0,0,1]}]" ;;
    bunny_back_ketchup) echo "\"mesh\":{\"file\":\"$bunny\"},\"material\":{\"preset\":\"ketchup\"},\"lights\":[{\"direction\":[0,0,1]}]" ;;
    sphere_back_skimmilk) echo "\"mesh\":{\"builtin\":\"sphere\"},\"material\":{\"preset\":\"skimmilk\"},\"lights\":[{\"direction\":[0,0,1]}]" ;;
    esac
}
scene_zoom() {  # scene_zoom NAME: left and top of the zoomed third, as fractions of the image
    case $1 in
    bunny_side) echo "0.22 0.40" ;;
    bunny_back) echo "0.30 0.38" ;;
    cube_edge|cube_edge_skin1) echo "0.42 0.24" ;;  # the corner where the lit face meets front and top
    protrusion_side) echo "0.36 0.33" ;;
    sphere_side) echo "0.30 0.33" ;;
    bunny_back_single) echo "0.30 0.10" ;;
    bunny_back_ketchup) echo "0.30 0.10" ;;
    sphere_back_skimmilk) echo "0.60 0.33" ;;   # the rim, where the light through the sphere comes out
    esac
}

# ---- labels: oiiotool --text needs a font it can open ----
font=
for f in "$(fc-match -f '%{file}' sans 2>/dev/null || true)" /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf DejaVuSans; do
    [[ -n $f ]] || continue
    if oiiotool --pattern constant:color=0,0,0 64x16 3 --text:x=2:y=12:size=10:font="$f" probe -o "$tmp/probe.png" 2>/dev/null; then
        font=$f; break
    fi
done
[[ -n $font ]] || echo "$prog: no usable font for oiiotool --text; sheets are unlabelled (order: reference, before, after, |before-ref|, |after-ref|)" >&2

label_h=$((size / 10 > 18 ? size / 10 : 18))
font_size=$((label_h * 6 / 10))
bg=0.012  # linear; about 29/255 in sRGB, so the silhouette shows against the unlit side
labelled() {  # labelled IN.png OUT.png TEXT: IN with a strip under it holding TEXT
    local w h
    read -r w h < <(oiiotool --info "$1" | sed -n 's/.*: *\([0-9]*\) x *\([0-9]*\),.*/\1 \2/p')
    # --paste puts the first image onto the second (the top of the stack); --crop alone would leave
    # the display window, which is what PNG writes, at the old size
    oiiotool "$1" --pattern constant:color=0,0,0 "${w}x$((h + label_h))" 3 --paste +0+0 -d uint8 -o "$2"
    if [[ -n $font ]]; then
        oiiotool "$2" --text:x=$((w / 2)):y=$((h + label_h * 3 / 4)):size=$font_size:color=1,1,1:xalign=center:font="$font" \
            "$3" -d uint8 -o "$2"
    fi
}

json_field() {  # json_field FILE KEY: the first number after "KEY": (the whole object's, in --compare)
    { grep -o "\"$2\":[-0-9.e+]*" "$1" || true; } | sed -n 1p | cut -d: -f2
}
band_field() {  # band_field FILE KEY: KEY of --compare's silhouette_band object
    { grep -o '"silhouette_band":{[^}]*}' "$1" || true; } | { grep -o "\"$2\":[-0-9.e+]*" || true; } | sed -n 1p | cut -d: -f2
}
render() {  # render BIN JSON OUT.exr [--compare REF.exr]: stdout to OUT.exr.out; stops with the message on failure
    local bin=$1 json=$2 exr=$3
    shift 3
    # builds older than camera.direction refuse it; their automatic camera is that front view already
    if ! "$bin" "$json" -o "$exr" "$@" > "$exr.out" 2> "$exr.err" && grep -q 'camera.direction' "$exr.err"; then
        sed 's/"camera":{"direction":\[0,0,-1\]},//' "$json" > "$json.front"
        json=$json.front
    fi
    if ! "$bin" "$json" -o "$exr" "$@" > "$exr.out" 2> "$exr.err"; then
        echo "$prog: rendering failed: $bin $json -o $exr $*" >&2
        sed 's/^/    /' "$exr.err" >&2
        echo "    scene: $(cat "$json")" >&2
        exit 1
    fi
}
mean_rgb() {  # mean_rgb EXR: the sum of the R, G, B averages (background pixels are 0)
    oiiotool --stats "$1" | awk '/Stats Avg:/ { print $3 + $4 + $5; exit }'
}

summary=$out/summary.md
{
    echo "Method ${method:-(default)} of before and after against \"$truth\" (rendered by after), ${size}x${size}."
    echo
    echo "- before: $before"
    echo "- after: $after"
    echo
    echo "| scene | rel L2 before | rel L2 after | band rel L2 before | band rel L2 after | noise before | noise after | mottle before | mottle after | mean ratio before | mean ratio after | sheet |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$summary"

for s in "${scenes[@]}"; do
    d=$tmp/$s
    mkdir -p "$d"
    base="{$(scene_json "$s"),\"width\":$size,\"height\":$size"
    if [[ $truth == path ]]; then
        echo "$base,\"method\":\"path\",\"path\":{\"samples\":$walks}}" > "$d/ref.json"
    else
        echo "$base,\"method\":\"reference\"}" > "$d/ref.json"
    fi
    if [[ -n $method ]]; then echo "$base,\"method\":\"$method\"}" > "$d/fast.json"; else echo "$base}" > "$d/fast.json"; fi
    echo "$s: rendering the $truth ..." >&2
    render "$after" "$d/ref.json" "$d/ref.exr"
    render "$before" "$d/fast.json" "$d/before.exr" --compare "$d/ref.exr"
    render "$after" "$d/fast.json" "$d/after.exr" --compare "$d/ref.exr"
    for v in ref before after; do oiiotool "$d/$v.exr" --ch R,G,B,A -o "$d/$v.rgba.exr"; done

    # Exposure: a fixed one, or the reference's 99th percentile (largest channel, covered pixels) -> 1.
    if [[ -n $exposure ]]; then
        k=$(awk -v e="$exposure" 'BEGIN { printf "%.9g", 2 ^ e }')
    else
        p99=$(oiiotool --dumpdata:empty=0 "$d/ref.rgba.exr" |
            awk '$1 == "Pixel" && $7 > 0 { m = $4; if ($5 > m) m = $5; if ($6 > m) m = $6; print m }' |
            sort -g | awk '{ v[NR] = $1 } END { if (NR) { i = int(0.99 * NR); if (i < 1) i = 1; print v[i] } }')
        awk -v p="${p99:-0}" 'BEGIN { exit !(p > 0) }' || die "$s: the reference is black (no covered pixel above 0); use --exposure"
        k=$(awk -v p="$p99" 'BEGIN { printf "%.9g", 1 / p }')
    fi
    stops=$(awk -v k="$k" 'BEGIN { printf "%+.2f", log(k) / log(2) }')

    # Display tiles: exposed, over the background, clamped, sRGB.
    for v in ref before after; do
        oiiotool "$d/$v.rgba.exr" --mulc "$k,$k,$k,1" --pattern constant:color=$bg,$bg,$bg,1 "${size}x${size}" 4 --over \
            --ch R,G,B --clamp:min=0:max=1 --colorconvert linear sRGB -d uint8 -o "$d/t_$v.png"
    done
    for v in before after; do
        if [[ $diff == abs ]]; then
            kg=$(awk -v k="$k" -v g="$gain" 'BEGIN { printf "%.9g", k * g }')
            oiiotool "$d/$v.rgba.exr" --ch R,G,B "$d/ref.rgba.exr" --ch R,G,B --absdiff --mulc "$kg" \
                --clamp:min=0:max=1 -d uint8 -o "$d/t_d$v.png"
        else
            kg=$(awk -v k="$k" -v g="$gain" 'BEGIN { printf "%.9g", 0.5 * k * g }')
            oiiotool "$d/$v.rgba.exr" --ch R,G,B "$d/ref.rgba.exr" --ch R,G,B --sub \
                --chsum:weight=0.2126,0.7152,0.0722 --mulc "$kg" --addc 0.5 --clamp:min=0:max=1 \
                --colormap 0.25,0.55,1,0,0,0,1,0.3,0.1 -d uint8 -o "$d/t_d$v.png"
        fi
    done

    # The zoomed third: nearest-neighbour, so single-pixel speckle stays single big pixels.
    read -r fx fy <<<"$(scene_zoom "$s")"
    c=$((size / 3))
    zx=$(awk -v f="$fx" -v n="$size" -v c="$c" 'BEGIN { x = int(f * n); if (x + c > n) x = n - c; print x }')
    zy=$(awk -v f="$fy" -v n="$size" -v c="$c" 'BEGIN { y = int(f * n); if (y + c > n) y = n - c; print y }')
    for v in ref before after dbefore dafter; do
        oiiotool "$d/t_$v.png" --cut "${c}x${c}+$zx+$zy" --resample:interp=0 "$((3 * c))x$((3 * c))" \
            --pattern constant:color=0,0,0 "${size}x${size}" 3 --paste +0+0 -d uint8 -o "$d/z_$v.png"
    done
    oiiotool "$d/t_ref.png" --box:color=1,0.8,0.1 "$zx,$zy,$((zx + c - 1)),$((zy + c - 1))" -d uint8 -o "$d/t_ref.png"

    if [[ $diff == abs ]]; then dl="|%s - ref| x$gain"; else dl="%s - ref, signed x$gain"; fi
    # shellcheck disable=SC2059
    labels=("$truth" "before" "after" "$(printf "$dl" before)" "$(printf "$dl" after)")
    tiles=()
    for row in t z; do   # the full images, then the zoomed ones
        suffix=""
        [[ $row == z ]] && suffix=", 3x"
        i=0
        for v in ref before after dbefore dafter; do
            labelled "$d/${row}_$v.png" "$d/l${row}_$v.png" "${labels[i]}$suffix"
            tiles+=("$d/l${row}_$v.png")
            i=$((i + 1))
        done
    done
    oiiotool "${tiles[@]}" --mosaic:pad=4 5x2 -d uint8 -o "$d/mosaic.png"

    # Numbers: --compare of each (whole object, then silhouette band) and the mean ratio.
    rb=$(json_field "$d/before.exr.out" rel_l2) ra=$(json_field "$d/after.exr.out" rel_l2)
    bb=$(band_field "$d/before.exr.out" rel_l2) ba=$(band_field "$d/after.exr.out" rel_l2)
    # "noise" (issue 10's high-pass error), where this lucent-render's --compare reports it
    nb=$(json_field "$d/before.exr.out" noise) na=$(json_field "$d/after.exr.out" noise)
    ob=$(json_field "$d/before.exr.out" mottle) oa=$(json_field "$d/after.exr.out" mottle)
    mref=$(mean_rgb "$d/ref.rgba.exr")
    mb=$(awk -v t="$(mean_rgb "$d/before.rgba.exr")" -v r="$mref" 'BEGIN { printf "%.4f", (r > 0 ? t / r : 0) }')
    ma=$(awk -v t="$(mean_rgb "$d/after.rgba.exr")" -v r="$mref" 'BEGIN { printf "%.4f", (r > 0 ? t / r : 0) }')
    title="$s  ${size}x${size}  exposure $stops stops  rel L2 before ${rb:-?} after ${ra:-?}  mean ratio before $mb after $ma"

    read -r mw mh < <(oiiotool --info "$d/mosaic.png" | sed -n 's/.*: *\([0-9]*\) x *\([0-9]*\),.*/\1 \2/p')
    if [[ -n $font ]]; then
        # --paste: the foreground (first) onto the background (second, the top of the stack)
        oiiotool "$d/mosaic.png" --pattern constant:color=0,0,0 "${mw}x$((mh + label_h))" 3 \
            --text:x=6:y=$((label_h * 3 / 4)):size=$font_size:color=1,1,1:font="$font" "$title" \
            --paste "+0+$label_h" -d uint8 -o "$out/$s.png"
    else
        cp "$d/mosaic.png" "$out/$s.png"
    fi
    if ((keep_exr)); then for v in ref before after; do cp "$d/$v.exr" "$out/exr/${s}_$v.exr"; done; fi

    printf '%s: rel L2 before %s after %s; band rel L2 before %s after %s; noise before %s after %s; mottle before %s after %s; mean ratio before %s after %s -> %s\n' \
        "$s" "${rb:-?}" "${ra:-?}" "${bb:-?}" "${ba:-?}" "${nb:--}" "${na:--}" "${ob:--}" "${oa:--}" "$mb" "$ma" "$out/$s.png"
    printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | [%s.png](%s.png) |\n' "$s" "${rb:-?}" "${ra:-?}" "${bb:-?}" \
        "${ba:-?}" "${nb:--}" "${na:--}" "${ob:--}" "${oa:--}" "$mb" "$ma" "$s" "$s" >> "$summary"
done

# shellcheck disable=SC2059
{
    echo
    echo "Each sheet: reference | before | after | $(printf "$dl" before) | $(printf "$dl" after), one exposure"
    echo "(reference's 99th percentile = white unless --exposure); renders sRGB-encoded over a dim background,"
    echo "differences linear; second row: the region boxed in the reference, 3x, nearest-neighbour."
    echo "rel L2, band (silhouette) rel L2, noise and mottle are lucent-render --compare's (noise, mottle: - where"
    echo "it does not report them); mean ratio is the sum of R+G+B over the image, test over reference (background is 0)."
} >> "$summary"
echo "summary: $summary" >&2
