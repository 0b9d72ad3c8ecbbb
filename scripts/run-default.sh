#!/usr/bin/env bash
# run-default.sh BUILD_DIR SCENE - what `make run` does after building: open the viewer when a
# display is present, otherwise render the scene to out/<scene>.png and print its path.
set -euo pipefail
build=$1; scene=$2
name=$(basename "$scene" .json)
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ] && "$build/softlight" view --help >/dev/null 2>&1; then
  exec "$build/softlight" view "$scene"
fi
mkdir -p out
"$build/softlight" render "$scene" -o "out/$name.png" --hdr "out/$name.hdr"
echo "rendered $(pwd)/out/$name.png"
