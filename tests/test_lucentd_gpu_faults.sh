#!/usr/bin/env bash
# test_lucentd_gpu_faults.sh - lucentd through GPU faults injected by a test build (LUCENT_FAULTS, see
# renderer/gpu/gpu_faults.h): a lost device (503 with Retry-After, /readyz 503 while a new renderer is made,
# renders refused meanwhile, then served again), a failed submit (500, the next frame fine), a fence
# that times out (500, the next frame waits for it and is correct), and a driver stuck in a call (SIGTERM
# still ends the daemon in bounded time); and a connection resumed late during shutdown. Usage:
# test_lucentd_gpu_faults.sh lucentd
set -u
lucentd=$1
source "$(dirname "$0")/lucentd_harness.sh"

type_of() { problem_type "$1" 2>/dev/null; }
ready() { curl -s -o "$work/ready" -w '%{http_code}' "$base/readyz"; }
render() { req "$work/$1.png" GET "$base/v1/render?w=64&h=64&preset=$1"; }

# Frames count from 1 over the process, the warm-up first. Frame 3 is lost, and so is frame 4, the new
# renderer's warm-up, so the re-creation is retried after a second (a window renders must be refused in).
export LUCENT_FAULTS="lost@3,lost@4,submit@6,timeout@8"
start F --store-dir "$work/store"

c=$(render marble)
check "frame 2 renders ($c)" [ "$c" = 200 ]
c=$(render skin1)
check "frame 3, device lost: 503 ($c) of type $(type_of "$work/skin1.png") with Retry-After $(header "$work/skin1.png" Retry-After)" \
    [ "$c" = 503 -a "$(type_of "$work/skin1.png")" = device-lost -a -n "$(header "$work/skin1.png" Retry-After)" ]
c=$(ready)
check "/readyz right after it: $c $(cat "$work/ready")" grep -q '"recovering from a lost GPU device"' "$work/ready"
c=$(render ketchup)
check "a render while the renderer is re-created: $c of type $(type_of "$work/ketchup.png"), Retry-After $(header "$work/ketchup.png" Retry-After)" \
    [ "$c" = 503 -a "$(type_of "$work/ketchup.png")" = not-ready -a -n "$(header "$work/ketchup.png" Retry-After)" ]
t0=$(date +%s%N)
for _ in $(seq 1 600); do [[ $(ready) == 200 ]] && break; sleep 0.1; done
check "/readyz 200 again after $(( ($(date +%s%N) - t0) / 1000000 )) ms (the first re-creation lost too, retried)" [ "$(ready)" = 200 ]
check "the log tells the loss, the failed retry and the new renderer" \
    bash -c "grep -q 're-creating the renderer\$' '$log' && grep -q 'retrying in 1 s' '$log' && grep -q 'renderer re-created on vulkan device' '$log'"
c=$(render apple)
check "frame 6, submit fails: $c of type $(type_of "$work/apple.png")" [ "$c" = 500 -a "$(type_of "$work/apple.png")" = render-failed ]
c=$(render cream)
check "frame 7 renders ($c)" [ "$c" = 200 ]
c=$(render potato)
check "frame 8, fence wait times out: $c of type $(type_of "$work/potato.png")" [ "$c" = 500 -a "$(type_of "$work/potato.png")" = render-failed ]
c=$(render skimmilk)
check "frame 9 waits for frame 8's work first, then renders ($c)" [ "$c" = 200 ]
check "the images rendered are whole" pngs "$work/marble.png:64:64" "$work/cream.png:64:64" "$work/skimmilk.png:64:64"
lost=$(curl -s "$base/metrics" | awk '$1 == "lucentd_devices_lost_total" { print $2 }')
check "lucentd_devices_lost_total $lost" [ "$lost" = 1 ]
kill -TERM "$pid"; wait "$pid"; rc=$?
check "SIGTERM: exit status $rc" [ "$rc" = 0 ]

# A driver stuck in a call (the wait of frame 2 never returns): the render's deadline answers it, and
# SIGTERM still ends the daemon within --drain-timeout and the worker's 5 s, exit status 1 and why.
export LUCENT_FAULTS="hang@2"
start G --store-dir "$work/storeG" --render-timeout 1 --drain-timeout 1
c=$(render apple)
check "frame 2 hangs: the render's deadline answers it: $c of type $(type_of "$work/apple.png")" \
    [ "$c" = 503 -a "$(type_of "$work/apple.png")" = deadline ]
t0=$(date +%s%N)
stop "$pid"; rc=$?
ms=$(ms_since "$t0")
check "SIGTERM with the worker stuck: exit $rc after $ms ms (bound 15000), the log says why" \
    bash -c "[ $rc = 1 ] && [ $ms -lt 15000 ] && grep -q 'render worker did not stop within 5 s' '$log'"

# A worker that finished a render just before shutdown and is slow to resume its connection (a test
# build sleeps $LUCENTD_FAULT_RESUME_DELAY_MS first: 3 s, past the drain's 2 s flush). lucentd stops
# HTTP only once that resume has returned; before, it stopped first and the resume used freed memory
# (AddressSanitizer reports it in the sanitizer run).
unset LUCENT_FAULTS
LUCENTD_FAULT_RESUME_DELAY_MS=3000 start S --store-dir "$work/storeS" --drain-timeout 10 --log-level debug
curl -s -o "$work/s.png" "$base/v1/render?w=64&h=64" &
client=$!
for _ in $(seq 1 600); do grep -q 'render [0-9a-f]*: rendered' "$log" && break; sleep 0.05; done
t0=$(date +%s%N)
stop "$pid"; rc=$?
ms=$(ms_since "$t0")
wait "$client"
check "SIGTERM while a finished render's connection is being resumed: exit $rc after $ms ms (3000-8000), stopped cleanly" \
    bash -c "[ $rc = 0 ] && [ $ms -ge 3000 -a $ms -lt 8000 ] && grep -q 'lucentd: stopped' '$log' && ! grep -q 'ERROR: AddressSanitizer' '$log'"

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
