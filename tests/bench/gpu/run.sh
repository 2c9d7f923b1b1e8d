#!/usr/bin/env bash
# run.sh - on a borrowed GPU machine: the GPU image tests (plain, under the Vulkan validation layer, and on
# OpenGL) and the frame-time benchmarks of a pack.sh archive, each with a time limit; logs under OUT_DIR.
#
# Usage: tests/bench/gpu/run.sh PACK.tar.xz OUT_DIR [BUDGET_S]
# Stops starting new steps once BUDGET_S (default 360) seconds have passed. Prints one line per step;
# OUT_DIR/gpu_results.tar.gz holds every log and table.
set -uo pipefail
pack="${1:?PACK.tar.xz}"; out="${2:?OUT_DIR}"; budget="${3:-360}"
root=/tmp/lucent-gpu; logs="$out/logs"
mkdir -p "$logs" "$out/trade"; rm -rf "$root"; tar -C /tmp -xJf "$pack" || exit 1
start=$SECONDS

# The driver's libraries and manifests, where this kind of machine keeps them.
nv=/usr/local/nvidia
export LD_LIBRARY_PATH="$root/lib:$nv/lib64:$nv/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
ldconfig -p | grep -q 'libstdc++.so.6 ' || LD_LIBRARY_PATH="$LD_LIBRARY_PATH:$root/fallback"
icd=$(ls "$nv"/share/vulkan/icd.d/nvidia_icd*.json /usr/share/vulkan/icd.d/nvidia_icd*.json \
         /etc/vulkan/icd.d/nvidia_icd*.json 2>/dev/null | head -1)
egl=$(ls "$nv"/share/glvnd/egl_vendor.d/*nvidia*.json /usr/share/glvnd/egl_vendor.d/*nvidia*.json 2>/dev/null | head -1)
[ -n "$icd" ] && export VK_ICD_FILENAMES="$icd"
[ -n "$egl" ] && export __EGL_VENDOR_LIBRARY_FILENAMES="$egl"
export VK_LAYER_PATH="$root/layers"
{
    echo "CPU: $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1), $(nproc) threads"
    nvidia-smi -L 2>&1; nvidia-smi --query-gpu=driver_version,clocks.sm,clocks.max.sm --format=csv 2>&1
    echo "Vulkan ICD: ${icd:-none found}; EGL vendor: ${egl:-none found}"
} | tee "$out/machine.txt"

# step NAME TIMEOUT_S FAIL_REGEX COMMAND...: runs one step with its log in $logs/NAME.log
fails=0
step() {
    local name="$1" limit="$2" fail="$3"; shift 3
    if [ $((SECONDS - start)) -ge "$budget" ]; then echo "SKIP $name (budget spent)"; return; fi
    local t0=$SECONDS rc
    timeout "$limit" "$@" > "$logs/$name.log" 2>&1; rc=$?
    if [ $rc -eq 0 ] && [ -n "$fail" ] && grep -Eq "$fail" "$logs/$name.log"; then rc=99; fi
    if [ $rc -eq 0 ]; then echo "PASS $name ($((SECONDS - t0)) s)"; else
        echo "FAIL $name rc=$rc ($((SECONDS - t0)) s): $(grep -v '^\s*$' "$logs/$name.log" | tail -2 | tr '\n' ' ')"
        fails=$((fails + 1)); fi
}
b="$root/bin"; bunny="$root/bunny.obj"
# mesh_arg TEST: the bunny for the tests that take it (as tests/CMakeLists.txt gives it)
mesh_arg() { case "$1" in render_modelled|fast_vs_reference|view_seams) echo "$bunny" ;; esac; }
scenes=("$root"/scenes/*/)

# Frame times first: what a borrowed machine is rarest for.
frames=()
for m in five single auto five1024; do for s in "${scenes[@]}"; do frames+=("$s$m.json"); done; done
step frames 120 "" "$b/bench_frames" 15 "$out/frames.md" "${frames[@]}"
step vulkan_render_analytic 60 "" "$b/test_render_analytic"
step vulkan_render_modelled 120 "" "$b/test_render_modelled" "$bunny"
step vulkan_render_extremes 120 "" "$b/test_render_extremes"
step vulkan_fast_vs_reference 120 "" "$b/test_fast_vs_reference" "$bunny"
step vulkan_view_seams 120 "" "$b/test_view_seams" "$bunny"
[ -x "$b/test_gpu_faults" ] && step vulkan_gpu_faults 60 "" "$b/test_gpu_faults"
step vulkan_renderer_memory 120 "" "$b/test_renderer_memory"
valid="vulkan validation (warning|error)"
for t in render_analytic render_modelled render_extremes; do
    step "validated_$t" 180 "$valid" env LUCENT_VALIDATION=1 \
        VK_LAYER_ENABLES=VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT "$b/test_$t" $(mesh_arg $t)
done
step backends_agree 120 "" "$b/test_backends_agree"
for t in render_analytic render_modelled render_extremes fast_vs_reference; do
    step "gl_$t" 120 "opengl validation [a-z]+: " env VK_ICD_FILENAMES=/nonexistent LUCENT_EXPECT_BACKEND=gl \
        LUCENT_VALIDATION=1 "$b/test_$t" $(mesh_arg $t)
done
step table2 120 "" "$b/bench_table2" "$out/table2.md" 15 512 --backend vulkan,gl
step trade 240 "" "$b/bench_trade" --quick --frames 7 --meshes sphere,bunny --lights side,back \
    --modes five,single,auto "$bunny" "$out/trade/trade"
echo "steps failed: $fails; $((SECONDS - start)) s"
tar -C "$out" -czf "$out/gpu_results.tar.gz" --exclude gpu_results.tar.gz . && rm -rf "$logs" "$out/trade"
