#!/usr/bin/env bash
# install.sh BUILD_DIR - softlight installed into a temporary prefix and used from outside the
# source tree: the layout (headers, both libraries, programs, data, softlight.pc, the CMake
# package); a consumer program (tests/consumer) built with find_package (shared and static
# library) and with pkg-config (shared, and --static against libsoftlight.a), each finding the
# data directory by itself and writing a PNG; the installed softlight run from / with
# SOFTLIGHT_DATA_DIR unset, rendering the installed default scene and a model given alone (whose
# environment comes from PREFIX/share/softlight, not from the source tree).
set -euo pipefail
BUILD=$(cd "${1:?usage: $0 BUILD_DIR}" && pwd)
SRC=$PWD
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-install.XXXXXX")
trap 'rm -rf "$T"' EXIT
unset SOFTLIGHT_DATA_DIR SL_SHADER_DIR
P=$T/prefix
. "$SRC/tests/cli/lib.bash"
consumer_toolchain "$BUILD" # the consumers are built as the library was
fails=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fails=$((fails + 1)); }
png_ok() { [ -s "$1" ] && [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]; }

cmake --install "$BUILD" --prefix "$P" >"$T/install.log"
pc=$(find "$P" -name softlight.pc)
libdir=$(dirname "$(dirname "$pc")")
for f in include/softlight/version.h include/softlight/data.h bin/softlight \
         share/softlight/shaders/lighting.frag share/softlight/scenes/default.json \
         share/softlight/scenes/envmaps/studio.hdr "${libdir#"$P"/}/libsoftlight.a" \
         "${libdir#"$P"/}/libsoftlight.so.0" "${libdir#"$P"/}/cmake/softlight/softlightConfig.cmake"; do
    if [ -e "$P/$f" ]; then ok "installed $f"; else bad "not installed: $f"; fi
done
if grep -q "^prefix=$P\$" "$pc"; then ok "softlight.pc names the prefix installed into"; else bad "softlight.pc prefix: $(grep ^prefix= "$pc")"; fi
# The source tree's build marker stays in the build tree.
if find "$P" -name softlight-data-dir | grep . >/dev/null; then bad "the build tree's softlight-data-dir was installed"; fi

# ---- find_package: softlight::softlight (shared) and softlight::softlight_static ----
if cmake -S tests/consumer -B "$T/cmake-consumer" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$P" \
        -DCMAKE_C_COMPILER="$CC" -DCMAKE_C_FLAGS="$CFLAGS" -DSOFTLIGHT_SOURCE_INCLUDE="$SRC/src" >"$T/cmake.log" 2>&1 &&
   cmake --build "$T/cmake-consumer" -j2 >>"$T/cmake.log" 2>&1; then
    ok "find_package(softlight) consumer builds"
else
    cat "$T/cmake.log"; bad "find_package(softlight) consumer does not build"
fi
(cd / && "$T/cmake-consumer/consumer" "$T/cmake-shared.png") && png_ok "$T/cmake-shared.png" &&
    ok "find_package consumer (libsoftlight.so, data found beside the library)" || bad "find_package consumer (shared)"
if readelf -d "$T/cmake-consumer/consumer" | grep 'NEEDED.*libsoftlight.so.0' >/dev/null; then ok "consumer needs libsoftlight.so.0"; else bad "consumer does not link libsoftlight.so.0"; fi
(cd / && SOFTLIGHT_DATA_DIR="$P/share/softlight" "$T/cmake-consumer/consumer_static" "$T/cmake-static.png") &&
    png_ok "$T/cmake-static.png" && ok "find_package consumer (softlight::softlight_static)" || bad "find_package consumer (static)"

# ---- pkg-config ----
export PKG_CONFIG_PATH=$(dirname "$pc")
cflags=$(pkg-config --cflags softlight)
# shellcheck disable=SC2086
if "$CC" -std=c11 $CFLAGS tests/consumer/consumer.c $cflags -I"$SRC/src" $(pkg-config --libs softlight) -o "$T/pc-shared" &&
   (cd / && LD_LIBRARY_PATH="$libdir" "$T/pc-shared" "$T/pc-shared.png") && png_ok "$T/pc-shared.png"; then
    ok "pkg-config consumer (shared)"
else
    bad "pkg-config consumer (shared)"
fi
# --static: libsoftlight.a and the dependencies of Requires.private / Libs.private; installed as
# PREFIX/bin/ so that it finds PREFIX/share/softlight beside itself.
static_libs=$(pkg-config --libs --static softlight | sed 's/-lsoftlight\b/-l:libsoftlight.a/')
# shellcheck disable=SC2086
if "$CC" -std=c11 $CFLAGS tests/consumer/consumer.c $cflags -I"$SRC/src" $static_libs -o "$P/bin/sl-consumer" &&
   ! readelf -d "$P/bin/sl-consumer" | grep libsoftlight >/dev/null &&
   (cd / && "$P/bin/sl-consumer" "$T/pc-static.png") && png_ok "$T/pc-static.png"; then
    ok "pkg-config --static consumer (data found beside the program)"
else
    bad "pkg-config --static consumer"
fi

# ---- the installed programs, away from the source tree ----
v=$("$P/bin/softlight" --version)
if [ "$v" = "softlight $(sed -n 's/^#define SL_VERSION_STRING "\(.*\)"/\1/p' include/softlight/version.h)" ]; then ok "--version: $v"; else bad "--version: $v"; fi
if (cd / && "$P/bin/softlight" render "$P/share/softlight/scenes/default.json" -o "$T/default.png" --size 96x54 -q) &&
   png_ok "$T/default.png"; then
    ok "installed softlight renders the installed default scene"
else
    bad "installed softlight: default scene"
fi
mkdir "$T/model"
cp scenes/models/bunny.gltf scenes/models/bunny.bin scenes/models/fur.png scenes/models/brass.png "$T/model/"
if (cd / && "$P/bin/softlight" info "$T/model/bunny.gltf" >"$T/info.txt" 2>&1) &&
   (cd / && "$P/bin/softlight" render "$T/model/bunny.gltf" -o "$T/bunny.png" --size 64x48 -q) && png_ok "$T/bunny.png"; then
    ok "installed softlight renders a model given alone (default environment from the prefix)"
else
    cat "$T/info.txt"; bad "installed softlight: model alone"
fi
if grep -q "$SRC" "$T/info.txt"; then bad "softlight info names the source tree: $(grep "$SRC" "$T/info.txt")"; fi
if [ -x "$P/bin/softlight-gl" ]; then
    [ "$("$P/bin/softlight-gl" --version)" = "$v" ] && ok "softlight-gl --version" || bad "softlight-gl --version"
    if gl=$(cd / && "$P/bin/softlight-gl" info 2>/dev/null); then
        shaders=$(printf '%s\n' "$gl" | sed -n 's/^shaders: //p')
        [ "$shaders" = "$(cd "$P/share/softlight/shaders" && pwd -P)" ] && ok "softlight-gl reads the installed shaders" ||
            bad "softlight-gl shaders: $shaders"
    else
        echo "skip softlight-gl info: no OpenGL context here"
    fi
fi
# With the data directory gone, a model alone fails with one line naming the way out.
mv "$P/share/softlight" "$P/share/softlight.away"
if (cd / && "$P/bin/softlight" render "$T/model/bunny.gltf" -o "$T/none.png" -q 2>"$T/err"); then
    bad "model alone rendered with no data directory"
elif grep -q SOFTLIGHT_DATA_DIR "$T/err" && [ ! -e "$T/none.png" ]; then
    ok "no data directory: $(cat "$T/err")"
else
    bad "no data directory: $(cat "$T/err")"
fi
[ "$fails" -eq 0 ] && echo "install: all passed" || { echo "install: $fails failed"; exit 1; }
