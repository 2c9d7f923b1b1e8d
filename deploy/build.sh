#!/usr/bin/env bash
# Installs what Lucent needs (setup.sh) and builds it into ./build (or $LUCENT_BUILD_DIR).
# Extra arguments go to CMake's configure step, e.g. -DLUCENT_WERROR=ON.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${LUCENT_BUILD_DIR:-$top/build}
bash "$top/deploy/setup.sh"
cmake -S "$top" -B "$build" "$@"
cmake --build "$build" -j "$(nproc)"
