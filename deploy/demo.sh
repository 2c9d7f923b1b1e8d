#!/usr/bin/env bash
# The README's first command: install, build, and render the demo scene (the paper's failure case:
# a protrusion lit from the side at 90 degrees) to demo.png, printing what was modelled.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${LUCENT_BUILD_DIR:-$top/build}
bash "$top/deploy/build.sh"
"$build/lucent-render" "$top/deploy/demo_scene.json" -o "$top/demo.png" --stats --verbose
echo "wrote $top/demo.png"
