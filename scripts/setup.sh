#!/usr/bin/env bash
# setup.sh - install the Debian 12 packages softlight needs, only those missing.
# As root it runs apt-get; otherwise it prints the exact apt-get line and fails.
# Nothing is downloaded from anywhere but Debian's archive.
set -euo pipefail

packages=(
  build-essential cmake pkg-config      # compiler, build
  clang libclang-rt-14-dev libomp-dev   # fuzz targets (libFuzzer) and OpenMP for clang
  libpng-dev libjpeg62-turbo-dev        # PNG and JPEG textures (libpng, libjpeg-turbo)
  libstb-dev libcjson-dev               # PNG writing (stb_image_write), scene files
  libopenexr-dev                        # .exr environments and --exr (its C library, OpenEXRCore)
  libassimp-dev                         # model import (glTF 2.0, OBJ+MTL, ...)
  libembree-dev                         # ray-traced visibility of the ground truth (truth --visibility)
  libsdl2-dev libsdl2-ttf-dev fonts-dejavu-core  # viewer and its HUD font
  libcmocka-dev                         # unit tests
  libegl-dev libepoxy-dev libgl1-mesa-dri libegl-mesa0  # softlight-gl on Mesa (llvmpipe)
  gnuplot-nox                           # benchmark plots
  time python3                          # tests/cli/image_limits.sh: peak memory (/usr/bin/time), its .hdr generator
  xvfb xdotool xauth                    # viewer end-to-end test without a display
  parallel                              # running shards (tests/cli/shard.sh, docs/sharding.md)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

line="apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "setup: missing Debian packages; run as root:" >&2
  echo "  apt-get update && $line" >&2
  exit 1
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
# shellcheck disable=SC2086
$line -qq
