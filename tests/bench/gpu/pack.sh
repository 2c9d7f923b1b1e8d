#!/usr/bin/env bash
# pack.sh - one archive that lets a machine without Lucent's libraries (a borrowed GPU machine) run the GPU
# tests and benchmarks of a build: binaries, their libraries, the validation layer and the benchmark scenes.
#
# Usage: tests/bench/gpu/pack.sh BUILD_DIR OUT.tar.xz
# Unpacks to /tmp/lucent-gpu (the scenes name their meshes there); tests/bench/gpu/run.sh runs it.
# glibc stays behind (the other machine's is as new or newer); libstdc++ and libgcc_s travel in fallback/,
# used only where that machine has none.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="$(cd "${1:?BUILD_DIR}" && pwd)"; out="${2:?OUT.tar.xz}"
root=/tmp/lucent-gpu
rm -rf "$root"; mkdir -p "$root"/{bin,lib,fallback,layers,scenes}

tests=(test_render_analytic test_render_modelled test_render_extremes test_fast_vs_reference test_view_seams
       test_backends_agree test_renderer_memory test_gpu_faults)
benches=(bench_frames bench_table2 bench_trade)
for t in "${tests[@]}"; do  # test_gpu_faults only in builds with -DLUCENT_FAULT_INJECTION=ON
    [ -x "$build/tests/$t" ] && strip -o "$root/bin/$t" "$build/tests/$t"
done
for b in "${benches[@]}"; do strip -o "$root/bin/$b" "$build/tests/bench/$b"; done
cp "$build/bunny.obj" "$root/"

# The libraries the binaries and the layer load, resolved here.
layer=/usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so
ldd "$root"/bin/* "$layer" | awk '$2 == "=>" && $3 ~ /^\// { print $3 }' | sort -u | while read -r lib; do
    case "$(basename "$lib")" in
        libc.so.*|libm.so.*|libpthread.so.*|libdl.so.*|librt.so.*|ld-linux*) ;;
        libstdc++.so.*|libgcc_s.so.*) cp -L "$lib" "$root/fallback/" ;;
        *) cp -L "$lib" "$root/lib/" ;;
    esac
done
cp "$layer" "$root/layers/"
sed 's#"library_path": *"[^"]*"#"library_path": "./libVkLayer_khronos_validation.so"#' \
    /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json > "$root/layers/VkLayer_khronos_validation.json"

# The Cycles comparison's scenes (issue 16's time target), each with method five, single and auto.
names=(sphere-skin1-side sphere-skin1-back bunny-marble-side bunny-marble-back bunny-skin1-side bunny-skin1-back)
python3 "$here/../cycles/scenes.py" "$root/scenes" 256 "$root/bunny.obj" "${names[@]}"
for n in "${names[@]}"; do
    for m in five single auto; do
        python3 -c 'import json, sys
doc = json.load(open(sys.argv[1])); doc["method"] = sys.argv[2]
if len(sys.argv) > 3: doc["width"] = doc["height"] = int(sys.argv[3])
print(json.dumps(doc))' "$root/scenes/$n/scene.json" "$m" > "$root/scenes/$n/$m.json"
    done
    python3 -c 'import json, sys
doc = json.load(open(sys.argv[1])); doc["method"] = "five"; doc["width"] = doc["height"] = 1024
print(json.dumps(doc))' "$root/scenes/$n/scene.json" > "$root/scenes/$n/five1024.json"
done
tar -C /tmp -cJf "$out" lucent-gpu
echo "packed $(du -h "$out" | cut -f1) into $out"
