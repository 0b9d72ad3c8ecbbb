#!/usr/bin/env bash
# subproject.sh BUILD_DIR - softlight as a subproject: tests/subproject add_subdirectory()s this
# source tree, is configured and built (Release, -j2, its two programs only, with the compiler of
# BUILD_DIR) in a temporary
# directory, and then: no softlight test is defined there (ctest -N lists the parent's one test),
# no benchmark target exists, the parent's own compile commands carry none of softlight's flags
# (-Werror, -march=native, -Wall), and its programs render a shipped scene and model given alone
# (the default environment found through the shared library's build-tree marker) to PNG files.
# It compiles the library once more: about a minute on 2 cores. A sanitized suite skips it: the
# subproject is a plain Release build with the same compiler as `make test`'s Release suite.
set -euo pipefail
if grep -q '^SL_SANITIZE:BOOL=ON' "${1:?usage: $0 BUILD_DIR}/CMakeCache.txt"; then
    echo "skip: a sanitized suite (the subproject builds Release with this compiler: the Release suite's run)"
    exit 0
fi
SRC=$PWD
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-subproject.XXXXXX")
trap 'rm -rf "$T"' EXIT
unset SOFTLIGHT_DATA_DIR SL_SHADER_DIR
fails=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fails=$((fails + 1)); }
png_ok() { [ -s "$1" ] && [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]; }

B=$T/build
CC=$(sed -n 's/^CMAKE_C_COMPILER:[A-Z]*=//p' "${1:?usage: $0 BUILD_DIR}/CMakeCache.txt")
if ! cmake -S tests/subproject -B "$B" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER="$CC" -DSOFTLIGHT_SOURCE_DIR="$SRC" >"$T/configure.log" 2>&1; then
    cat "$T/configure.log"; echo "FAIL configure"; exit 1
fi
if ! cmake --build "$B" -j2 --target parent_render parent_consumer >"$T/build.log" 2>&1; then
    tail -30 "$T/build.log"; echo "FAIL build"; exit 1
fi
ok "parent project configures and builds"

tests=$(cd "$B" && ctest -N | sed -n 's/^Total Tests: //p')
[ "$tests" = 1 ] && ok "ctest -N lists the parent's test only" || { (cd "$B" && ctest -N); bad "ctest -N: $tests tests"; }
targets=$(cmake --build "$B" --target help)
if printf '%s\n' "$targets" | grep -Eq '(^|\.\.\. )(bench_|test_|fuzz_)'; then bad "softlight's tests or benches are targets"; else ok "no test, bench or fuzz target"; fi
parent_cmd=$(grep -F '"command"' "$B/compile_commands.json" | grep -F 'render.c' | grep -v '/src/' || true)
if [ -z "$parent_cmd" ]; then
    bad "no compile command for the parent's render.c"
elif printf '%s\n' "$parent_cmd" | grep -Eq -- '-Werror|-march=native|-Wall|-ffp-contract'; then
    bad "softlight's flags reach the parent: $parent_cmd"
else
    ok "the parent's compile command carries none of softlight's flags"
fi
lib_cmd=$(grep -F '"command"' "$B/compile_commands.json" | grep -F '/src/core/data_dir.c' | head -1)
if printf '%s\n' "$lib_cmd" | grep -Eq -- '-Werror|-march=native'; then bad "-Werror or -march=native forced on a subproject"; else ok "no -Werror or -march=native in the subproject"; fi

if (cd "$T" && "$B/parent_render" "$SRC/scenes/default.json" "$T/default.png" 64 36) && png_ok "$T/default.png"; then
    ok "parent program renders scenes/default.json"
else
    bad "parent program: scenes/default.json"
fi
if (cd "$T" && "$B/parent_render" "$SRC/scenes/models/bunny.gltf" "$T/bunny.png" 48 36 2>"$T/err") && png_ok "$T/bunny.png"; then
    ok "parent program renders a model given alone"
elif grep -q SOFTLIGHT_DATA_DIR "$T/err" && (cd "$T" && SOFTLIGHT_DATA_DIR="$SRC" "$B/parent_render" "$SRC/scenes/models/bunny.gltf" "$T/bunny.png" 48 36) && png_ok "$T/bunny.png"; then
    ok "parent program renders a model given alone with SOFTLIGHT_DATA_DIR"
else
    bad "parent program: model alone: $(cat "$T/err")"
fi
if (cd "$T" && "$B/parent_consumer" "$T/consumer.png") && png_ok "$T/consumer.png"; then
    ok "parent program on the shared library finds the data through the build tree"
else
    bad "parent program on the shared library"
fi
[ "$fails" -eq 0 ] && echo "subproject: all passed" || { echo "subproject: $fails failed"; exit 1; }
