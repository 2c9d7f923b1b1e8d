#!/usr/bin/env bash
# bench_http.sh - lucentd under load with wrk on loopback: requests per second and latency p50/p99 for
# 256^2 and 512^2 PNG renders, cache off and cache hit, at 1, 4 and 16 connections, and the overhead ratio
# (request latency / the server's own render + encode time). Usage: bench_http.sh LUCENTD OUT.md [SECONDS]
set -euo pipefail
lucentd=$1
out=$2
seconds=${3:-10}
command -v wrk >/dev/null || { echo "bench_http: wrk not found (apt-get install wrk)" >&2; exit 2; }
work=$(mktemp -d)
pid=
cleanup() {
    [[ -n $pid ]] && kill -TERM "$pid" 2>/dev/null && wait "$pid" 2>/dev/null
    rm -rf "$work"
}
trap cleanup EXIT

# start CACHE_BYTES: lucentd on a free port with a queue deep enough for 16 connections; sets $base.
start() {
    [[ -n $pid ]] && kill -TERM "$pid" 2>/dev/null && wait "$pid" 2>/dev/null
    "$lucentd" --port 0 --log-level info --queue-length 64 --cache-bytes "$1" --store-dir "$work/store" \
        2>"$work/lucentd.log" &
    pid=$!
    base=
    for _ in $(seq 1 300); do
        base=$(grep -o "listening on http://127.0.0.1:[0-9]*" "$work/lucentd.log" | head -1 | sed "s/listening on //" || true)
        [[ -n $base ]] && [[ $(curl -s -o /dev/null -w '%{http_code}' "$base/readyz") == 200 ]] && return 0
        sleep 0.1
    done
    echo "bench_http: lucentd did not become ready" >&2
    cat "$work/lucentd.log" >&2
    exit 1
}

url() { echo "$base/v1/render?mesh=protrusion&preset=skin1&light_dir=-1,0,0&light_intensity=3&w=$1&h=$1&format=png"; }

# server_ms FROM_LINE: medians of render, encode and render + encode (ms) over the renders the access log
# recorded after line FROM_LINE: the server's own account of the requests wrk just timed.
server_ms() {
    local pairs
    pairs=$(tail -n +"$(( $1 + 1 ))" "$work/lucentd.log" | grep 'GET /v1/render status=200' |
        sed -E 's/.*render_ms=([0-9.]+) encode_ms=([0-9.]+).*/\1 \2/')
    [[ -z $pairs ]] && { echo "- - -"; return; }
    median() { awk "{ print $1 }" <<<"$pairs" | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
    echo "$(median '$1') $(median '$2') $(median '$1 + $2')"
}

# to_ms VALUE: wrk's latency ("812.00us", "12.34ms", "1.20s") in milliseconds.
to_ms() {
    awk -v v="$1" 'BEGIN { n=v+0; if (v ~ /us$/) n/=1000; else if (v ~ /ms$/) n=n; else if (v ~ /s$/) n*=1000; printf "%.2f", n }'
}

# load SIZE CONNECTIONS: "rps p50_ms p99_ms errors" from one wrk run.
load() {
    local threads=$(( $2 < 2 ? $2 : 2 )) log=$work/wrk.txt
    wrk -t "$threads" -c "$2" -d "${seconds}s" --latency "$(url "$1")" >"$log"
    local rps p50 p99 errors
    rps=$(awk '/^Requests\/sec/ {print $2}' "$log")
    p50=$(to_ms "$(awk '$1 == "50%" {print $2}' "$log")")
    p99=$(to_ms "$(awk '$1 == "99%" {print $2}' "$log")")
    errors=$(awk '/Non-2xx/ {print $NF} /Socket errors/ {print "socket"}' "$log" | paste -sd, -)
    echo "$rps $p50 $p99 ${errors:-0}"
}

{
    echo "## lucentd under wrk ($(date -u +%F), ${seconds} s per run, loopback, $(nproc) cores)"
    echo
    echo "Render and encode are the server's own medians for the requests of that run (its access log); overhead"
    echo "is the request p50 at 1 connection over render + encode. With more connections requests queue behind"
    echo "the one render worker, so latency grows with the queue while throughput stays at one render at a time."
    echo
    echo "| size | cache | connections | req/s | p50 ms | p99 ms | non-2xx | render ms | encode ms | overhead p50 |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
} >"$out"

for cache in off hit; do
    start "$([[ $cache == off ]] && echo 0 || echo 268435456)"
    for size in 256 512; do
        curl -s -o /dev/null "$(url "$size")"   # compiles this size's pipelines; warms the cache for "hit"
        for c in 1 4 16; do
            from=$(wc -l <"$work/lucentd.log")
            read -r rps p50 p99 errors < <(load "$size" "$c")
            read -r render encode both < <(server_ms "$from")
            overhead=-
            [[ $c == 1 && $cache == off ]] && overhead=$(awk -v a="$p50" -v b="$both" 'BEGIN { printf "%.2fx", a / b }')
            echo "| $size | $cache | $c | $rps | $p50 | $p99 | $errors | $render | $encode | $overhead |" >>"$out"
        done
    done
done
cat "$out"
