#!/usr/bin/env bash
# test_systemd_unit.sh - deploy/systemd/lucentd.service checked as far as a machine without systemd
# running allows: systemd-analyze verify, its offline security score (stated, and held under a
# threshold), and the unit's system-call, socket-family and namespace filters applied to an strace of
# the real lucentd through start, renders, an upload (the importer), metrics and a drain.
# Usage: test_systemd_unit.sh PATH/TO/lucentd
set -u
lucentd=$1
source "$(dirname "$0")/lucentd_harness.sh"
unit_src=$harness_dir/../deploy/systemd/lucentd.service

# The unit names the installed binary; verify checks that ExecStart= exists, so point it at this build.
unit=$work/lucentd.service
sed "s#/usr/local/bin/lucentd#$lucentd#" "$unit_src" >"$unit"
out=$(systemd-analyze verify "$unit" 2>&1); rc=$?
check "systemd-analyze verify: exit $rc${out:+: $out}" [ "$rc" = 0 -a -z "$out" ]
# Exposure is printed 0.0-10.0; --threshold takes tenths of it.
systemd-analyze security --offline=true --threshold=25 "$unit" >"$work/security.txt" 2>&1; rc=$?
score=$(grep -o 'Overall exposure level for [^:]*: [0-9.]* [A-Z]*' "$work/security.txt" | sed 's/.*: //')
check "systemd-analyze security --offline=true: exposure $score (threshold 2.5; exit $rc)" [ "$rc" = 0 -a -n "$score" ]
grep '^✗' "$work/security.txt" | sed 's/  */ /g; s/^/   /' | cut -c1-110

# lucentd under strace -f: every system call it and its importer make, then the unit's filters.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/tetra.obj"
real_lucentd=$lucentd
printf '#!/bin/sh\nexec strace -f -qq -o "%s" "%s" "$@"\n' "$work/trace" "$real_lucentd" >"$work/traced"
chmod +x "$work/traced"
lucentd=$work/traced
# --import-user "": the unit runs lucentd unprivileged (DynamicUser=), where it switches no user
start T --store-dir "$work/store" --drain-timeout 30 --import-user ""
lucentd=$real_lucentd
c1=$(req "$work/a.png" GET "$base/v1/render?w=64&h=64")
c2=$(req "$work/up.json" POST "$base/v1/meshes" -H 'Content-Type: model/obj' --data-binary "@$work/tetra.obj")
id=$(json_field "$work/up.json" '["id"]')
c3=$(req "$work/b.exr" GET "$base/v1/render?w=64&h=64&mesh=$id&format=exr&method=reference&reference_points=1000")
c4=$(req "$work/m" GET "$base/metrics")
check "traced lucentd: render $c1, upload $c2, reference EXR of the upload $c3, metrics $c4" \
    [ "$c1" = 200 -a "$c2" = 201 -a "$c3" = 200 -a "$c4" = 200 ]
# SIGTERM to lucentd itself (strace would detach on its own); strace exits with lucentd's status.
kill -TERM "$(pgrep -P "$pid" | head -1)"
wait "$pid"; rc=$?
check "traced lucentd: SIGTERM -> exit $rc" [ "$rc" = 0 ]
check "the unit's filters allow everything lucentd did" python3 "$harness_dir/unit_sandbox_check.py" "$unit" "$work/trace"

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
