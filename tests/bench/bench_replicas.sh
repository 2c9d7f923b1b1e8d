#!/usr/bin/env bash
# bench_replicas.sh - renders a second through nginx (deploy/nginx/lucent.conf) in front of 1 and of 3
# lucentd replicas on the same machine, cache off so every request renders, each request its own URI
# (so the hash spreads them): requests/s, p50 and p99 with wrk, and the median render time the
# replicas report. Usage: bench_replicas.sh LUCENTD OUT.md [SECONDS]
set -u
lucentd=$1
out=$2
seconds=${3:-10}
command -v wrk >/dev/null || { echo "bench_replicas: wrk not found (apt-get install wrk)" >&2; exit 2; }
source "$(dirname "$0")/../lucentd_harness.sh"
source "$harness_dir/proxy_harness.sh"
trap 'stop_proxy; cleanup' EXIT

cat >"$work/distinct.lua" <<'EOF'
-- each request its own exposure, so its own URI (and replica, and no cache could answer it)
counter = 0
request = function()
  counter = counter + 1
  return wrk.format("GET", "/v1/render?w=128&h=128&mesh=protrusion&preset=skin1&light_dir=-1,0,0&exposure=0." .. counter)
end
EOF

# run REPLICAS: starts them on one store, the proxy in front, wrk for $seconds; one table row.
run() {
    local n=$1 ports=() rp=() p
    for r in $(seq 1 "$n"); do
        p=$(free_port)
        start "B$n-$r" --port "$p" --store-dir "$work/store" --cache-bytes 0 --queue-length 64 >/dev/null
        ports+=("$p") rp+=("$pid")
    done
    while (( ${#ports[@]} < 3 )); do ports+=("${ports[0]}"); done
    start_proxy "${ports[@]}" || { echo "bench_replicas: nginx did not start: $proxy_check" >&2; exit 1; }
    wrk -t2 -c6 -d"${seconds}s" --latency -s "$work/distinct.lua" "$P" >"$work/wrk$n.txt"
    stop_proxy
    local rps p50 p99 render
    rps=$(awk '/Requests\/sec/ {print $2}' "$work/wrk$n.txt")
    p50=$(awk '$1 == "50%" {print $2}' "$work/wrk$n.txt")
    p99=$(awk '$1 == "99%" {print $2}' "$work/wrk$n.txt")
    render=$(cat "$work"/B"$n"-*.log | grep -o 'render_ms=[0-9.]*' | cut -d= -f2 | sort -n |
             awk '{v[NR] = $1} END {if (NR) print v[int((NR + 1) / 2)]; else print "-"}')
    echo "| $n | $rps | $p50 | $p99 | $render |" >>"$work/rows.md"
    for p in "${rp[@]}"; do stop "$p" >/dev/null; done
}

run 1
run 3
device=$(grep -o 'device "[^"]*"' "$work"/B1-1.log | head -1)
{
    echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores; $device;"
    echo "nginx in front, 6 connections, ${seconds} s, 128^2 PNG renders of distinct URIs, image cache off"
    echo
    echo "| replicas | requests/s | p50 | p99 | median render (ms, replicas' log) |"
    echo "|---|---|---|---|---|"
    cat "$work/rows.md"
} | tee "$out"
