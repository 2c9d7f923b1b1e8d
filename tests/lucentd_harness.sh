# lucentd_harness.sh - shared by the shell tests that talk to a real lucentd (test_lucentd.sh, test_client.sh):
# ok/bad/check bookkeeping, free ports, starting a daemon on a free loopback port, and decoding PNGs.
# Sourced; the caller sets $lucentd (the binary). $work is a temp dir and $pids the daemons, both gone at exit.
passed=0
failed=0
harness_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
work=$(mktemp -d)
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null; done
    rm -rf "$work"
}
trap cleanup EXIT

ok() { passed=$((passed + 1)); echo "ok   $1"; }
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
bad() { failed=$((failed + 1)); echo "FAIL $1"; }
# check NAME COMMAND...: passes when the command succeeds.
check() { local name=$1; shift; if "$@"; then ok "$name"; else bad "$name"; fi; }

# start NAME ARGS...: starts lucentd on a free port, waits until /readyz answers 200; sets $base, $pid and
# $log (its stderr, one access line per request).
start() {
    local name=$1; shift
    log=$work/$name.log
    "$lucentd" --port 0 --log-level info "$@" 2>"$log" &
    pid=$!
    pids+=("$pid")
    base=
    for _ in $(seq 1 300); do
        base=$(grep -o 'listening on http://127.0.0.1:[0-9]*' "$log" | head -1 | sed 's/listening on //')
        if [[ -n $base ]] && [[ $(curl -s -o /dev/null -w '%{http_code}' "$base/readyz") == 200 ]]; then
            echo "started $name at $base (pid $pid): $(grep -oE 'ready: [a-z]+ device "[^"]*", renderer warm in [0-9]* ms' "$log")"
            return 0
        fi
        sleep 0.1
    done
    echo "lucentd $name did not become ready:"; cat "$log"
    exit 1
}

# pngs [--lit LEVEL] FILE:W:H...: each a valid 8-bit RGBA PNG of that size showing a lit object
# (tests/check_png.py: covered share and mean brightness at least the minimums, both printed).
pngs() { python3 "$harness_dir/check_png.py" "$@"; }

# stop PID: SIGTERM, then the exit status (124 when it did not exit within 60 s).
stop() {
    kill -TERM "$1" 2>/dev/null
    for _ in $(seq 1 600); do
        if ! kill -0 "$1" 2>/dev/null; then wait "$1"; return $?; fi
        sleep 0.1
    done
    return 124
}

# req OUT METHOD URL [curl args...]: body to OUT, headers to OUT.h, prints the status.
req() {
    local out=$1 method=$2 url=$3; shift 3
    curl -s -X "$method" -o "$out" -D "$out.h" -w '%{http_code}' "$@" "$url"
}

header() { grep -i "^$2:" "$1.h" | head -1 | cut -d' ' -f2- | tr -d '\r'; }

# problem FILE STATUS FIELD: a problem+json body with that status and field ("" = no field).
problem() {
    python3 - "$1" "$2" "$3" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
ok = doc.get("status") == int(sys.argv[2]) and doc.get("type", "").startswith("tag:lucent") and doc.get("title") \
     and doc.get("detail") and doc.get("field", "") == sys.argv[3]
if not ok:
    print("   got", doc)
sys.exit(0 if ok else 1)
EOF
    local rc=$?
    [[ $rc == 0 ]] && grep -qi '^content-type: application/problem+json' "$1.h"
}
# problem_with FILE STATUS FIELD TEXT: such a problem body, and TEXT in it (which of several 422s it is).
problem_with() { problem "$1" "$2" "$3" && grep -q "$4" "$1"; }

json_field() { python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(eval("d"+sys.argv[2]))' "$1" "$2"; }
metric() { curl -s "$@" | awk -v m="$METRIC" '$1 == m { print $2 }'; }
# problem_type FILE: the last part of a problem body's type ("queue-full", "deadline", "not-ready", ...).
problem_type() { json_field "$1" '["type"].rsplit(":", 1)[-1]'; }
ms_since() { echo $(( ($(date +%s%N) - $1) / 1000000 )); }

# wait_in_flight N URL [curl args...]: polls /metrics every 10 ms until lucentd_renders_in_flight is N, for
# up to 60 s; sets $waited_ms and fails when it never was.
wait_in_flight() {
    local want=$1 url=$2 t0; shift 2
    t0=$(date +%s%N)
    while [[ $(METRIC=lucentd_renders_in_flight metric "$@" "$url/metrics") != "$want" ]]; do
        if (( $(ms_since "$t0") > 60000 )); then waited_ms=$(ms_since "$t0"); return 1; fi
        sleep 0.01
    done
    waited_ms=$(ms_since "$t0")
}
