#!/usr/bin/env bash
# test_deploy_proxy.sh - three lucentd replicas on one shared store behind nginx on 127.0.0.1, with
# deploy/nginx/lucent.conf (its upstream ports and listen port rewritten to free ones): affinity of GET
# renders by URI, a mesh uploaded through the proxy rendered by every replica, failover after kill -9,
# and a replica drained with SIGTERM under load without a client seeing an error; and HAProxy with
# deploy/haproxy/lucent.cfg in front of the same replicas: renders by URI, and its /readyz checks taking
# the killed and the drained replica out. Usage: test_deploy_proxy.sh LUCENTD
set -u
lucentd=$1
source "$(dirname "$0")/lucentd_harness.sh"
deploy=$harness_dir/../deploy

source "$harness_dir/proxy_harness.sh"

store=$work/store
ports=() rpids=()
for r in 1 2 3; do
    p=$(free_port)
    start "R$r" --port "$p" --store-dir "$store" --drain-timeout 30
    ports+=("$p") rpids+=("$pid")
done
start_proxy "${ports[@]}"; rc=$?
check "nginx -t accepts deploy/nginx/lucent.conf: $(echo "$proxy_check" | tail -1)" [ "$rc" = 0 ]
trap 'stop_proxy; cleanup' EXIT

# upstream FILE: the replica that answered (nginx's Lucent-Upstream header; the last one tried).
upstream() { header "$1" Lucent-Upstream | awk -F', ' '{print $NF}'; }

# ---- affinity: 60 distinct renders, each 3 times: one replica each, every replica a share, repeats hit ----
declare -A home
hits=0 moved=0 bad=0
for i in $(seq 1 60); do
    url="$P/v1/render?w=24&h=24&exposure=$i"
    for k in 1 2 3; do
        c=$(req "$work/a.png" GET "$url")
        u=$(upstream "$work/a.png")
        [[ $c == 200 ]] || bad=$((bad + 1))
        if [[ $k == 1 ]]; then home[$i]=$u; elif [[ $u != "${home[$i]}" ]]; then moved=$((moved + 1)); fi
        [[ $k != 1 ]] && grep -qi 'cache;desc=hit' "$work/a.png.h" && hits=$((hits + 1))
    done
done
shares=$(for i in "${!home[@]}"; do echo "${home[$i]}"; done | sort | uniq -c | awk '{print $1}' | tr '\n' ' ')
check "affinity: 180 requests ($bad failed), repeats on another replica $moved, cache hits $hits of 120, URLs per replica: $shares" \
    bash -c "[ $bad = 0 -a $moved = 0 -a $hits = 120 ] && [ \$(echo $shares | wc -w) = 3 ]"

# ---- shared store: an upload through the proxy renders on every replica ----
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/t.obj"
c=$(req "$work/t.json" POST "$P/v1/meshes" -H 'Content-Type: model/obj' --data-binary "@$work/t.obj")
id=$(json_field "$work/t.json" '["id"]')
declare -A seen
fails=0
for i in $(seq 1 30); do
    c2=$(req "$work/m.png" GET "$P/v1/render?w=24&h=24&mesh=$id&exposure=$i")
    [[ $c2 == 200 ]] || fails=$((fails + 1))
    seen[$(upstream "$work/m.png")]=1
done
check "a mesh uploaded through the proxy ($c) renders on ${#seen[@]} replicas, $fails of 30 renders failed" \
    [ "$c" = 201 -a "${#seen[@]}" = 3 -a "$fails" = 0 ]

# ---- HAProxy with deploy/haproxy/lucent.cfg (its ports rewritten) in front of the same replicas: renders
# by URI, each URL on one server; after the failover and the drain below, its /readyz checks have taken
# the two replicas out and every URL is still answered ----
out=$(haproxy -c -f "$deploy/haproxy/lucent.cfg" 2>&1); rc=$?
check "haproxy -c accepts deploy/haproxy/lucent.cfg ($rc): $(echo "$out" | tail -1)" [ "$rc" = 0 ]
hport=$(free_port)
to_replicas "$deploy/haproxy/lucent.cfg" "${ports[@]}" | sed "s/bind 127\.0\.0\.1:8080/bind 127.0.0.1:$hport/" \
    >"$work/haproxy.cfg"
haproxy -db -f "$work/haproxy.cfg" 2>"$work/haproxy.log" &
hapid=$!
pids+=("$hapid")
H=http://127.0.0.1:$hport
for _ in $(seq 1 100); do [[ $(curl -s -o /dev/null -w '%{http_code}' "$H/healthz") == 200 ]] && break; sleep 0.1; done
sleep 2.5 # two good checks (rise 2, inter 1 s) before a server takes requests
declare -A hhome
bad=0 moved=0
for i in $(seq 1 30); do
    for k in 1 2; do
        c=$(req "$work/h.png" GET "$H/v1/render?w=24&h=24&exposure=$i")
        u=$(header "$work/h.png" Lucent-Upstream)
        [[ $c == 200 ]] || bad=$((bad + 1))
        if [[ $k == 1 ]]; then hhome[$i]=$u; elif [[ $u != "${hhome[$i]}" ]]; then moved=$((moved + 1)); fi
    done
done
hshares=$(for i in "${!hhome[@]}"; do echo "${hhome[$i]}"; done | sort | uniq -c | awk '{print $2 "=" $1}' | tr '\n' ' ')
check "HAProxy: 60 requests ($bad failed), repeats on another server $moved, URLs per server: $hshares" \
    bash -c "[ $bad = 0 -a $moved = 0 ] && [ \$(echo $hshares | wc -w) -ge 2 ]"

# ---- failover: kill -9 one replica; every request still answered, the others keep their URLs ----
victim=127.0.0.1:${ports[2]}
kill -KILL "${rpids[2]}"
wait "${rpids[2]}" 2>/dev/null
bad=0 kept=0 survivors=0
for i in $(seq 1 60); do
    c=$(req "$work/f.png" GET "$P/v1/render?w=24&h=24&exposure=$i")
    [[ $c == 200 ]] || bad=$((bad + 1))
    if [[ ${home[$i]} != "$victim" ]]; then
        survivors=$((survivors + 1))
        [[ $(upstream "$work/f.png") == "${home[$i]}" ]] && kept=$((kept + 1))
    fi
done
check "failover: after kill -9 of $victim, $bad of 60 requests failed; $kept of $survivors URLs on the survivors kept their replica (>= 60%)" \
    [ "$bad" = 0 -a "$survivors" -gt 0 -a $((100 * kept)) -ge $((60 * survivors)) ]

# ---- drain: SIGTERM one replica under load; /readyz 503 at once, no client sees an error ----
drainee=${rpids[1]}
python3 - "$P" "$work/load.txt" <<'EOF' &
import sys, threading, time, urllib.request, urllib.error
base, out = sys.argv[1], sys.argv[2]
codes, stop = [], time.monotonic() + 6.0
def client(n):
    i = 0
    while time.monotonic() < stop:
        url = "%s/v1/render?w=40&h=40&method=reference&reference_points=1000&exposure=%d.%d" % (base, n, i)
        try:
            with urllib.request.urlopen(url, timeout=90) as r:
                r.read(); codes.append(r.status)
        except urllib.error.HTTPError as e:
            codes.append(e.code)
        except OSError:
            codes.append(-1)
        i += 1
threads = [threading.Thread(target=client, args=(n,)) for n in range(6)]
for t in threads: t.start()
for t in threads: t.join()
open(out, "w").write(" ".join(map(str, codes)))
EOF
load=$!
sleep 2
# /readyz on a connection opened before the signal (new connections wait unanswered while it drains)
read -r ready ms < <(python3 - "${ports[1]}" "$drainee" <<'EOF2'
import http.client, os, signal, sys, time
conn = http.client.HTTPConnection("127.0.0.1", int(sys.argv[1]), timeout=10)
conn.request("GET", "/healthz"); conn.getresponse().read()
os.kill(int(sys.argv[2]), signal.SIGTERM)
t0 = time.monotonic()
status = 0
while status != 503 and time.monotonic() - t0 < 2.0:  # the main loop sees the signal within its 20 ms tick
    conn.request("GET", "/readyz"); r = conn.getresponse(); r.read(); status = r.status
print(status, int((time.monotonic() - t0) * 1000))
EOF2
)
wait "$load"
wait "$drainee"; rc=$?
codes=$(tr ' ' '\n' <"$work/load.txt" | sort | uniq -c | tr -s ' ' | tr '\n' ';')
check "drain: /readyz $ready ${ms} ms after SIGTERM; the replica exited $rc; clients under load saw:$codes" \
    bash -c "[ '$ready' = 503 ] && [ $rc = 0 ] && ! tr ' ' '\n' <'$work/load.txt' | grep -qv '^200\$'"
bad=0
for i in $(seq 1 30); do
    c=$(req "$work/h.png" GET "$H/v1/render?w=24&h=24&exposure=$i")
    [[ $c == 200 ]] || bad=$((bad + 1))
done
down=$(grep -o 'Server lucent_[a-z_]*/r[0-9] is DOWN' "$work/haproxy.log" | sort -u | wc -l)
check "HAProxy after the kill and the drain: its checks took $down server entries down (2 replicas x 2 backends); $bad of 30 URLs failed" \
    [ "$bad" = 0 -a "$down" = 4 ]
kill -TERM "$hapid"
for p in "${rpids[0]}"; do stop "$p" >/dev/null; done

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
