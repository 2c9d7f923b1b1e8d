#!/usr/bin/env bash
# The README's second command (and what .ci/run runs): install, build with warnings as errors,
# and run every test with ctest.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${LUCENT_BUILD_DIR:-$top/build}
bash "$top/deploy/build.sh" -DLUCENT_WERROR=ON -DLUCENT_FAULT_INJECTION=ON
cd "$build"
ctest --output-on-failure --timeout 900 -j 1
