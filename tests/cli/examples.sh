#!/usr/bin/env bash
# examples.sh BUILD_DIR - examples/ as a newcomer builds them (docs/getting-started.md): softlight
# installed into a temporary prefix, examples/ built out of tree against it twice, with its CMake
# package (find_package, softlight::softlight) and with pkg-config (examples/Makefile), each
# example run at 160x90 from / (so the data directory is found beside the installed library)
# and its PNG compared with tests/golden/examples/.
#
# Tolerance: the two builds must give the same bytes (the same library and the same shader code:
# anything else is a build difference). Against the references, at most 0.5% of the pixels may
# have a channel more than 2/255 apart. The build that made the references reproduces them
# exactly; the slack is for another compiler or instruction set reordering float arithmetic
# (the lighting's sums move smooth shading by a code, and a pixel on a silhouette, a checker
# edge or a toon band's edge can flip whole, hence a share of pixels rather than a largest
# difference). A real change (a lost term, a wrong normal, moved geometry) moves far more.
#
# After an intended change of the pictures: SL_EXAMPLES_UPDATE=1 bash tests/cli/examples.sh build
# writes the references (and say why in the commit).
set -euo pipefail
BUILD=$(cd "${1:?usage: $0 BUILD_DIR}" && pwd)
SRC=$PWD
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-examples.XXXXXX")
trap 'rm -rf "$T"' EXIT
unset SOFTLIGHT_DATA_DIR
P=$T/prefix
. "$SRC/tests/cli/lib.bash"
consumer_toolchain "$BUILD" # the consumers are built as the library was
fails=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fails=$((fails + 1)); }

cmake --install "$BUILD" --prefix "$P" >"$T/install.log"
pc=$(find "$P" -name softlight.pc)

if cmake -S examples -B "$T/cmake" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$P" \
        -DCMAKE_C_COMPILER="$CC" -DCMAKE_C_FLAGS="$CFLAGS" >"$T/cmake.log" 2>&1 &&
   cmake --build "$T/cmake" -j2 >>"$T/cmake.log" 2>&1; then
    ok "examples build with find_package(softlight)"
else
    cat "$T/cmake.log"; bad "examples do not build with find_package(softlight)"
fi
if PKG_CONFIG_PATH=$(dirname "$pc") make -f examples/Makefile OUT="$T/pc" CC="$CC" CFLAGS="-O2 $CFLAGS" \
        >"$T/make.log" 2>&1; then
    ok "examples build with pkg-config (examples/Makefile)"
else
    cat "$T/make.log"; bad "examples do not build with pkg-config"
fi

# name and arguments after OUT.png; models from the source tree, the default scene from the prefix
runs=("forward 160x90 $SRC/scenes/meshes/bunny.obj" "gbuffer_program 160x90" "toon_lighting 160x90 $SRC/scenes/bunny.json")
for run in "${runs[@]}"; do
    read -r name args <<<"$run"
    for b in cmake pc; do
        # shellcheck disable=SC2086
        if ! (cd / && "$T/$b/$name" "$T/$b-$name.png" $args) 2>"$T/err"; then
            bad "$name ($b build) failed: $(cat "$T/err")"; continue 2
        fi
    done
    if ! cmp -s "$T/cmake-$name.png" "$T/pc-$name.png"; then
        bad "$name: the CMake and pkg-config builds give different images"; continue
    fi
    ref=tests/golden/examples/$name.png
    if [ "${SL_EXAMPLES_UPDATE:-0}" = 1 ]; then
        mkdir -p tests/golden/examples && cp "$T/cmake-$name.png" "$ref" && ok "$name: wrote $ref"; continue
    fi
    if report=$(python3 tests/cli/png_compare.py "$T/cmake-$name.png" "$ref" 0.5); then
        ok "$name: both builds alike; against $ref: $report"
    else
        bad "$name against $ref: $report (at most 0.5% of pixels more than 2/255 apart)"
        mkdir -p out && cp "$T/cmake-$name.png" "out/examples-$name.png" && echo "    image: out/examples-$name.png"
    fi
done
[ "$fails" -eq 0 ] && echo "examples: all passed" || { echo "examples: $fails failed"; exit 1; }
