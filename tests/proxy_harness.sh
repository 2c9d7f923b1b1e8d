# proxy_harness.sh - nginx with deploy/nginx/lucent.conf in front of lucentd replicas on loopback, for
# test_deploy_proxy.sh and tests/bench/bench_replicas.sh. Sourced after lucentd_harness.sh (uses $work).
# start_proxy PORT1 PORT2 PORT3: rewrites the config's three upstream ports and its listen port (a free
# one), starts nginx, waits until it answers; sets $P (its base URL). stop_proxy stops it.

# to_replicas FILE PORT1 PORT2 PORT3: FILE with the deploy files' upstream addresses 127.0.0.1:8081-8083
# pointed at the three ports.
to_replicas() {
    sed -e "s/127\.0\.0\.1:8081/127.0.0.1:$2/; s/127\.0\.0\.1:8082/127.0.0.1:$3/; s/127\.0\.0\.1:8083/127.0.0.1:$4/" "$1"
}

start_proxy() {
    local proxy_port
    proxy_port=$(free_port)
    to_replicas "$harness_dir/../deploy/nginx/lucent.conf" "$@" |
        sed "s/listen 8080;/listen 127.0.0.1:$proxy_port;/" >"$work/lucent.conf"
    cat >"$work/nginx.conf" <<EOC
$( [[ $(id -u) == 0 ]] && echo "user root;" )
worker_processes 2;
pid $work/nginx.pid;
events { worker_connections 512; }
http {
    access_log $work/nginx-access.log;
    client_body_temp_path $work/nginx-body;
    proxy_temp_path $work/nginx-proxy;
    include $work/lucent.conf;
}
EOC
    proxy_check=$(nginx -t -e "$work/nginx-error.log" -p "$work" -c "$work/nginx.conf" 2>&1) || return 1
    nginx -e "$work/nginx-error.log" -p "$work" -c "$work/nginx.conf" || return 1
    P=http://127.0.0.1:$proxy_port
    for _ in $(seq 1 100); do [[ $(curl -s -o /dev/null -w '%{http_code}' "$P/healthz") == 200 ]] && return 0; sleep 0.1; done
    return 1
}

stop_proxy() {
    [[ -f $work/nginx.pid ]] && kill -QUIT "$(cat "$work/nginx.pid")" 2>/dev/null
    rm -f "$work/nginx.pid"
}
