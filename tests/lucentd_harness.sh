# lucentd_harness.sh - shared by the shell tests that talk to a real lucentd (test_lucentd.sh, test_client.sh):
# ok/bad/check bookkeeping, starting a daemon on a free loopback port, and decoding PNGs. Sourced; the
# caller sets $lucentd (the binary). $work is a temp dir and $pids the daemons, both gone at exit.
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
            echo "started $name at $base (pid $pid): $(grep -o 'ready: device "[^"]*", renderer warm in [0-9]* ms' "$log")"
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
