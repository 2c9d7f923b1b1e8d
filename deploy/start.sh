#!/usr/bin/env bash
# Installs what Lucent needs, builds it, and runs the daemon lucentd in the foreground on
# http://127.0.0.1:8080 with its defaults (uploaded meshes kept in ./lucent-store). Ctrl-C or SIGTERM
# drains and stops it. Extra arguments go to lucentd (see `lucentd --help`), e.g. --port 9000.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${LUCENT_BUILD_DIR:-$top/build}
bash "$top/deploy/build.sh"
cd "$top"
echo "try: curl -o marble.png 'http://127.0.0.1:8080/v1/render?mesh=protrusion&preset=marble&light_dir=-1,0,0&w=256&h=256'"
exec "$build/server/lucentd" "$@"
