#!/usr/bin/env bash
# Installs every Debian package Lucent needs to build, run and test, plus the npm
# test data (Stanford bunny). Idempotent; safe to run on a fresh Debian 12.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/.." && pwd)

sudo_cmd=()
[[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)

packages=(
  build-essential cmake pkg-config git ca-certificates
  libvulkan-dev mesa-vulkan-drivers vulkan-tools glslang-tools vulkan-validationlayers
  libegl-dev libopengl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  libjansson-dev
  libassimp-dev assimp-testmodels
  libmeshoptimizer-dev
  libopenimageio-dev openimageio-tools
  libmicrohttpd-dev libcurl4-openssl-dev
  curl python3 wrk
  libssl-dev
  libseccomp-dev
  systemd strace nginx haproxy mmdebstrap
  gnuplot-nox
  clang libclang-rt-14-dev
  nodejs
  chromium
)

export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${packages[@]}"
# Debian's npm package drags in hundreds of node-* packages; machines that already
# have npm (as this project's CI machines do) keep theirs.
command -v npm >/dev/null || "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends npm

# The Stanford bunny ships in the npm package "bunny" (positions + cells in
# index.js); tests convert it to OBJ at build time, it is never committed.
# playwright-core (no bundled browser) drives Debian's chromium in tests/test_web.js;
# kubernetes-models, yaml and fast-json-patch check deploy/kubernetes in tests/test_kubernetes.mjs.
if [[ ! -f "$top/tests/data/node_modules/bunny/index.js" ||
      ! -f "$top/tests/data/node_modules/playwright-core/package.json" ||
      ! -f "$top/tests/data/node_modules/kubernetes-models/package.json" ||
      ! -f "$top/tests/data/node_modules/yaml/package.json" ||
      ! -f "$top/tests/data/node_modules/fast-json-patch/package.json" ]]; then
  (cd "$top/tests/data" && npm install --no-package-lock --no-audit --no-fund --silent)
fi
