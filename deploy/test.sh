#!/usr/bin/env bash
# The README's second command (and what .ci/run runs): install, build with warnings as errors and
# faults injectable, and run every test with ctest (the container image test beside the next build);
# then build again with AddressSanitizer and UndefinedBehaviorSanitizer and run every test that can run
# under them (tests/CMakeLists.txt).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${LUCENT_BUILD_DIR:-$top/build}
bash "$top/deploy/build.sh" -DLUCENT_WERROR=ON -DLUCENT_FAULT_INJECTION=ON
cd "$build"
# Two tests at a time on CI's two cores: alone, a test keeps them 59% busy (daemons waiting on clients,
# processes starting); two at a time took the suite from 18.0 to 14.2 minutes here (2026-12-07).
jobs=$(nproc)
ctest --output-on-failure --timeout 900 -j "$jobs" -E '^container$'
# The container image test is mostly downloading and unpacking Debian packages: it runs beside the
# sanitizer build, and its output is shown once that build is done.
ctest --output-on-failure --timeout 900 -R '^container$' >"$build/container-test.log" 2>&1 &
container=$!
sanitized=$build-sanitize
cmake -S "$top" -B "$sanitized" -DLUCENT_WERROR=ON -DLUCENT_FAULT_INJECTION=ON -DLUCENT_SANITIZE=ON \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build "$sanitized" -j "$(nproc)"
container_rc=0
wait "$container" || container_rc=$?
cat "$build/container-test.log"
cd "$sanitized"
ctest --output-on-failure --timeout 900 -j "$jobs"
exit "$container_rc"
