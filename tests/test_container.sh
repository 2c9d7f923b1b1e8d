#!/usr/bin/env bash
# test_container.sh - the image deploy/container/Containerfile describes, built and run as far as this
# machine allows: a Debian 12 root file system made by mmdebstrap from the Containerfile's own package
# line, the user and directories its RUN line makes, and this build's programs installed into it;
# lucentd started in it with chroot in new mount and PID namespaces, as uid 10001, the root read-only,
# a tmpfs at /tmp and the store on a bind-mounted volume; then the HEALTHCHECK command, a render, an
# upload and a drain over loopback. `podman import` of the root file system is tried too; `podman run`
# is not (its setrlimit is refused here). Usage: test_container.sh LUCENTD BUILD_DIR
set -u
lucentd=$1
build=$2
source "$(dirname "$0")/lucentd_harness.sh"
containerfile=$harness_dir/../deploy/container/Containerfile
rootfs=$work/rootfs
volume=$work/volume

packages=$(sed -n 's/^ARG RUNTIME_PACKAGES="\(.*\)"/\1/p' "$containerfile")
t0=$(date +%s)
mmdebstrap --variant=apt --include="$(echo "$packages" | tr ' ' ,)" bookworm "$rootfs" >"$work/mmdebstrap.log" 2>&1
rc=$?
check "mmdebstrap: Debian 12 with the Containerfile's packages ($packages) in $(( $(date +%s) - t0 )) s, $(du -sh "$rootfs" 2>/dev/null | cut -f1)" \
    [ "$rc" = 0 ]
[[ $rc == 0 ]] || { tail -20 "$work/mmdebstrap.log"; echo "$passed passed, $failed failed"; exit 1; }
# The Containerfile's RUN line (user, store directory) and its COPY of the installed programs.
chroot "$rootfs" useradd --system --uid 10001 --user-group --home-dir /var/lib/lucent --shell /usr/sbin/nologin lucent
chroot "$rootfs" install -d -o lucent -g lucent -m 0700 /var/lib/lucent
cmake --install "$build" --prefix "$work/install" >/dev/null
cp -a "$work/install/bin/." "$rootfs/usr/local/bin/"
check "the programs installed: $(ls "$rootfs/usr/local/bin" | tr '\n' ' ')" \
    [ -x "$rootfs/usr/local/bin/lucentd" -a -x "$rootfs/usr/local/bin/lucent-import" ]
missing=$(chroot "$rootfs" sh -c 'for b in /usr/local/bin/*; do ldd "$b"; done' 2>&1 | grep -c 'not found')
check "every library they link is in the image ($missing not found)" [ "$missing" = 0 ]

# podman import: the root file system as an image with the Containerfile's user and entry point.
if command -v podman >/dev/null; then
    if tar -C "$rootfs" -c . | podman import --change 'USER 10001:10001' \
        --change 'ENTRYPOINT ["lucentd", "--listen", "0.0.0.0", "--port", "8080", "--store-dir", "/var/lib/lucent/store"]' \
        - localhost/lucent-test:ci >"$work/podman.log" 2>&1; then
        user=$(podman image inspect --format '{{.Config.User}}' localhost/lucent-test:ci 2>/dev/null)
        check "podman import: an image of $(podman image inspect --format '{{.Size}}' localhost/lucent-test:ci) bytes, user $user" \
            [ "$user" = 10001:10001 ]
        podman rmi -f localhost/lucent-test:ci >/dev/null 2>&1
    else
        echo "   (podman import not exercised: $(tail -1 "$work/podman.log"))"
    fi
else
    echo "   (podman import not exercised: no podman)"
fi

# The container: new mount and PID namespaces, the root read-only, /proc, /dev from the host (podman
# would give a minimal one), a tmpfs /tmp, the volume; lucentd as uid 10001 with the entry point's
# arguments, but on 127.0.0.1 and a free port (the network is the host's here).
mkdir -p "$volume"
chown 10001:10001 "$volume"
port=$(free_port)
cat >"$work/container.sh" <<EOC
#!/bin/sh
set -e
mount --bind "$rootfs" "$rootfs"
mount -t proc proc "$rootfs/proc"
mount --bind /dev "$rootfs/dev"
mount -t tmpfs -o mode=1777,size=64m tmpfs "$rootfs/tmp"
mount --bind "$volume" "$rootfs/var/lib/lucent"
mount -o remount,bind,ro "$rootfs"
exec chroot --userspec=10001:10001 "$rootfs" /usr/local/bin/lucentd --listen 127.0.0.1 --port $port \
    --store-dir /var/lib/lucent/store --log-level info
EOC
chmod +x "$work/container.sh"
unshare --mount --pid --fork --kill-child "$work/container.sh" 2>"$work/C.log" &
cpid=$!
pids+=("$cpid")
base=http://127.0.0.1:$port
for _ in $(seq 1 600); do [[ $(curl -s -o /dev/null -w '%{http_code}' "$base/readyz") == 200 ]] && break; sleep 0.2; done
inner=$(pgrep -f "^/usr/local/bin/lucentd --listen 127.0.0.1 --port $port" | head -1)
uid=$(awk '/^Uid:/ {print $2}' "/proc/${inner:-0}/status" 2>/dev/null)
check "lucentd in the container is ready ($(grep -oE 'ready: [a-z]+ device "[^"]*"' "$work/C.log")) as uid ${uid:-?}" \
    [ -n "$inner" -a "$uid" = 10001 ]
health=$(sed -n 's/^HEALTHCHECK .*CMD \[\(.*\)\]$/\1/p' "$containerfile" | tr -d '",' | sed "s/:8080/:$port/")
nsenter -t "$inner" -m chroot --userspec=10001:10001 "$rootfs" $health; rc=$?
check "the HEALTHCHECK command, run in the image ($health): exit $rc" [ "$rc" = 0 ]
ro=$(nsenter -t "$inner" -m sh -c "touch '$rootfs/usr/local/bin/x' 2>&1" | grep -c 'Read-only')
check "its root file system is read-only ($ro 'Read-only file system')" [ "$ro" = 1 ]
c=$(req "$work/r.png" GET "$base/v1/render?w=64&h=64&mesh=protrusion&preset=marble&light_dir=-1,0,0")
check "a render through it ($c)" pngs "$work/r.png:64:64"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/t.obj"
c=$(req "$work/t.json" POST "$base/v1/meshes" -H 'Content-Type: model/obj' --data-binary "@$work/t.obj")
id=$(json_field "$work/t.json" '["id"]')
c2=$(req "$work/t.png" GET "$base/v1/render?w=48&h=48&mesh=$id")
owner=$(stat -c %u "$volume/store/$id.lmesh" 2>/dev/null)
check "an upload imported in its sandbox ($c; $(grep -o '; no namespaces.*\|; namespaces [a-z,]*' "$work/C.log" | head -1 | cut -c3-)), rendered ($c2), stored on the volume as uid ${owner:-?}" \
    [ "$c" = 201 -a "$c2" = 200 -a "$owner" = 10001 ]
kill -TERM "$inner"
wait "$cpid"; rc=$?
check "SIGTERM: the container's lucentd exits $rc" [ "$rc" = 0 ]

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
