#!/usr/bin/env bash
# run.sh - builds the libFuzzer targets with clang (AddressSanitizer and UndefinedBehaviorSanitizer, no
# Vulkan: only the parsers), replays each one's seed corpus, then fuzzes each for SECONDS with its
# dictionary, and prints per target the executions and what it found. Any crash, leak or sanitizer
# report fails the run and leaves the input in OUT/crashes/TARGET/. CI runs it short (ctest "fuzz");
# run it long by hand:  bash tests/fuzz/run.sh build/fuzz 600
# usage: run.sh OUT_DIR SECONDS [TARGET...]     (targets: scene query sniff lmesh import image)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
if [[ $# -lt 2 ]] || ! [[ $2 =~ ^[0-9]+$ ]]; then
    echo "usage: $0 OUT_DIR SECONDS [TARGET...]" >&2
    exit 2
fi
out=$1 seconds=$2
shift 2
targets=("$@")
((${#targets[@]})) || targets=(scene query sniff lmesh import image)
command -v clang >/dev/null || { echo "$0: clang not found (apt-get install clang libclang-rt-14-dev)" >&2; exit 2; }

r=$top/renderer s=$top/server
c=$r/core m=$r/mesh i=$r/image
# Each target is fuzz_TARGET.c and these sources (.c as C11, .cpp as C++17), linked with clang++ (assimp
# and OpenImageIO are C++) against its pkg-config packages.
declare -A sources=(
    [scene]="$c/scene_parse.c $c/material_presets.c $c/error.c"
    [query]="$s/scene_query.c $s/url_unescape.c $c/scene_parse.c $c/material_presets.c $c/error.c"
    [sniff]="$s/mesh_format_sniff.c $c/error.c"
    [lmesh]="$m/mesh_compact.c $m/mesh.c $m/mesh_closed.c $c/error.c"
    [import]="$here/sandbox_new.cpp $m/mesh_import.c $m/mesh.c $m/mesh_closed.c $m/mesh_compact.c $c/error.c $s/mesh_bundle.c"
    [image]="$i/image_io.cpp $i/image.c $i/image_compare.c $c/json_text.c $c/error.c"
)
declare -A packages=([import]="assimp jansson" [image]="OpenImageIO jansson")
# libFuzzer flags beyond the common ones (later flags win). import: assimp's refusals are logged to
# stderr, a line an input (-close_fd_mask=2 closes it; libFuzzer's and the sanitizers' reports still
# print); -timeout=30 is lucentd's import-cpu. image: OpenImageIO and libpng print refusals too;
# OpenEXR 3.1 allocates an attribute's declared size (up to 2 GiB) before reading it, and a 4096^2
# reference with its AOVs takes 0.7 GB, so 4 GiB rather than 2.
declare -A flags=(
    [import]="-close_fd_mask=2 -timeout=30"
    [image]="-close_fd_mask=2 -rss_limit_mb=4096 -malloc_limit_mb=4096"
)
# Leaks inside assimp's readers and OpenImageIO, not Lucent's, are suppressed (import.lsan, image.lsan
# say which). The suppressions name frames the default frame-pointer unwinder does not reach through
# libraries built without frame pointers, hence the slow unwinder for those two.
# print_suppressions=0: else each suppressed leak check prints its table into the log.
slow_unwind="ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}fast_unwind_on_malloc=0"
suppress="LSAN_OPTIONS=${LSAN_OPTIONS:+$LSAN_OPTIONS:}print_suppressions=0:suppressions=$here"
declare -A environment=(
    [import]="$slow_unwind $suppress/import.lsan"
    [image]="$slow_unwind $suppress/image.lsan"
)
# shellcheck disable=SC2054  # the commas separate sanitizers, not array elements
common=(-g -O1 -fno-omit-frame-pointer -Wall -Wextra -Werror -fsanitize=fuzzer,address,undefined
        -fno-sanitize-recover=all -D_POSIX_C_SOURCE=200809L -I"$r" -I"$c" -I"$m" -I"$i" -I"$s")
mkdir -p "$out"
for t in "${targets[@]}"; do
    [[ -n ${sources[$t]:-} ]] || { echo "$0: unknown target $t" >&2; exit 2; }
    pkgs=${packages[$t]:-jansson}
    # shellcheck disable=SC2086  # package lists are words
    pkg-config --exists $pkgs || { echo "$0: fuzz_$t needs pkg-config packages $pkgs (deploy/setup.sh)" >&2; exit 2; }
    mkdir -p "$out/obj/$t"
    objects=()
    # shellcheck disable=SC2086,SC2046  # the source and package lists are words
    for src in "$here/fuzz_$t.c" ${sources[$t]}; do
        obj=$out/obj/$t/$(basename "$src").o
        case $src in
        *.cpp) clang++ -std=c++17 "${common[@]}" $(pkg-config --cflags $pkgs) -c "$src" -o "$obj" ;;
        *) clang -std=c11 "${common[@]}" $(pkg-config --cflags $pkgs) -c "$src" -o "$obj" ;;
        esac
        objects+=("$obj")
    done
    # shellcheck disable=SC2086,SC2046
    clang++ -fsanitize=fuzzer,address,undefined "${objects[@]}" -o "$out/fuzz_$t" $(pkg-config --libs $pkgs) -lm
done

status=0
for t in "${targets[@]}"; do
    work=$out/corpus/$t crashes=$out/crashes/$t
    mkdir -p "$work" "$crashes"
    dict=()
    [[ -f $here/$t.dict ]] && dict=(-dict="$here/$t.dict")
    # New inputs go to the work corpus; the seeds in the repository are only read.
    log=$out/fuzz_$t.log
    # shellcheck disable=SC2086  # the flag and environment lists are words
    if ! env ${environment[$t]:-} "$out/fuzz_$t" "$work" "$here/corpus/$t" "${dict[@]}" -max_total_time="$seconds" \
        -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 -artifact_prefix="$crashes/" \
        ${flags[$t]:-} >"$log" 2>&1; then
        status=1
        echo "fuzz_$t: FAILED, input in $crashes:"
        grep -E 'ERROR|SUMMARY|runtime error' "$log" | head -5 | sed 's/^/    /'
    fi
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    secs=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1)
    echo "fuzz_$t: ${runs:-?} executions in ${secs:-?} s, ${cov:-cov: ?}, corpus $(ls "$work" | wc -l) inputs (seeds $(ls "$here/corpus/$t" | wc -l))"
done
exit $status
