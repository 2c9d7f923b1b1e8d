#!/usr/bin/env bash
# test_lucentd_memory.sh - lucentd's resident memory under a mixed soak (tests/soak_memory.py: renders of
# many sizes up to the limit, cache hits, uploads, bad requests): within the README's budget, flat over
# the soak, and a second pass of the same traffic adds nothing. Usage: test_lucentd_memory.sh PATH/TO/lucentd
set -u
lucentd=$1
source "$(dirname "$0")/lucentd_harness.sh"
soak() { /usr/bin/env python3 "$harness_dir/soak_memory.py" "$base" "$pid" "$@" --max-size "$max_size" --renders 240; }
renders_done() { curl -s "$base/metrics" | awk '$1 == "lucentd_image_cache_misses_total" { print $2 }'; }
field() { python3 -c 'import json,sys; print(eval("json.loads(sys.argv[1])" + sys.argv[2]))' "$1" "$2"; }
rss_kib() { awk '/^VmRSS:/ { print $2 }' "/proc/$pid/status"; }

# Small caches, as a hostile client would meet them; sizes up to 256^2 keep a render under a second.
# 2000 requests a pass in CI (LUCENT_SOAK_REQUESTS=10000 for the full soak): 1000 + 2 x 4000 took 4.3
# minutes of CI's 30 on a slow machine (10,000 a pass took 10 on another).
max_size=256 max_projection=512 cache=$((16 << 20)) mesh_cache=$((32 << 20)) requests=${LUCENT_SOAK_REQUESTS:-2000}
max_triangles=20000   # the soak's largest mesh
start soak --store-dir "$work/store" --max-width $max_size --max-height $max_size \
    --max-projection-size $max_projection --cache-bytes $cache --mesh-cache-bytes $mesh_cache \
    --max-triangles $max_triangles
ready_kib=$(rss_kib)

# The budget (README, "Robustness"): resident at ready + the caches + the largest frame's render targets
# (18 MiB + 76 B a pixel + 330 B a projection texel) + 32 kept pipelines (2 MiB each) + one frame's
# readback and encoding (64 B a pixel) + the BVH a mesh's thickness is measured with while it loads (270 B a
# triangle).
pixels=$((max_size * max_size))
budget_kib=$(( ready_kib + (cache + mesh_cache + (18 << 20) + 76 * pixels + 330 * max_projection * max_projection \
    + (64 << 20) + 64 * pixels + 270 * max_triangles) / 1024 ))
echo "     resident at ready $((ready_kib / 1024)) MiB; budget $((budget_kib / 1024)) MiB"

# Warm-up: the first 1000 requests of the same traffic (first renders, pipelines, first uploads).
warm=$(soak 1000)
echo "     warm-up: $(field "$warm" '["requests"]') requests in $(field "$warm" '["seconds"]') s, resident $(( $(rss_kib) / 1024 )) MiB"
misses0=$(renders_done)
first=$(soak $requests)
misses1=$(renders_done)
second=$(soak $requests)
misses2=$(renders_done)
rendered_first=$((misses1 - misses0)) rendered_second=$((misses2 - misses1))
for pass in first second; do
    r=${!pass} rendered=rendered_$pass
    echo "     $pass pass: $(field "$r" '["requests"]') requests in $(field "$r" '["seconds"]') s, ${!rendered} rendered (not in the cache)," \
        "statuses $(field "$r" '["statuses"]')," \
        "resident max by quarter (KiB) $(field "$r" '["rss_kib_quarter_max"]')"
    check "$pass pass: every answer as expected (unexpected: $(field "$r" '["unexpected"]'))" \
        [ "$(field "$r" '["unexpected"]')" = "[]" ]
done
q1=$(field "$first" '["rss_kib_quarter_max"][0]') q4=$(field "$first" '["rss_kib_quarter_max"][3]')
growth=$(python3 -c "print(f'{100 * ($q4 - $q1) / $q1:.1f}')")
check "resident memory grew $growth% from the first to the last quarter of $requests requests (limit 10%)" \
    python3 -c "import sys; sys.exit(0 if $q4 - $q1 < 0.10 * $q1 else 1)"
peak_of() { python3 -c 'import json,sys; print(max(json.loads(sys.argv[1])["rss_kib_quarter_max"]))' "$1"; }
max1=$(peak_of "$first") max2=$(peak_of "$second")
check "a second pass of the same traffic added $(( (max2 - max1) / 1024 )) MiB at its peak (limit 10)" \
    [ $((max2 - max1)) -lt $((10 << 10)) ]
peak=$(( max1 > max2 ? max1 : max2 ))
check "peak resident $((peak / 1024)) MiB within the budget of $((budget_kib / 1024)) MiB" [ "$peak" -le "$budget_kib" ]
check "the daemon still answers /healthz" [ "$(curl -s -o /dev/null -w '%{http_code}' "$base/healthz")" = 200 ]

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
