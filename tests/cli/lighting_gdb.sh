#!/usr/bin/env bash
# lighting_gdb.sh BUILD_DIR - a lighting program built with --debug-shader stops in the
# debugger in the user's own function, at its own source line (docs/lighting-programs.md
# "Debugging"). Skipped without gdb.
set -u
SL=${1:?usage: $0 BUILD_DIR}/softlight
if ! command -v gdb >/dev/null; then echo "skip: no gdb"; exit 0; fi
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-lgdb.XXXXXX")
trap 'rm -rf "$T"' EXIT
export XDG_CACHE_HOME=$T/cache
# the documented commands: the trace runs the program on one pixel, gdb breaks in toon_shade
gdb -batch -nx -ex "set breakpoint pending on" -ex "break toon_shade" -ex run -ex bt -ex "info locals" \
    --args "$SL" trace scenes/bunny.json --size 64x48 --lighting examples/shaders/toon.c --debug-shader -p 32,30 \
    >"$T/gdb.log" 2>&1
if grep -Eq "Breakpoint 1, toon_shade \(.*\) at examples/shaders/toon\.c:[0-9]+" "$T/gdb.log" &&
   grep -q "^#0  toon_shade" "$T/gdb.log"; then
    echo "ok   gdb stopped in toon_shade (examples/shaders/toon.c)"
    exit 0
fi
echo "FAIL gdb did not stop in toon_shade:"; cat "$T/gdb.log"
exit 1
