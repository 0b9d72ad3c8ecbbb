#!/usr/bin/env bash
# view_gl_compare.sh BUILD_DIR - the viewer's comparison with the GL version (key M,
# docs/viewer.md): once the frame is exact, softlight-gl lights its G-buffer from the viewer's
# camera with the same settings, and the window shows GL's image, then the difference.
#
# Under Xvfb, on scenes/default.json at 320x180, N 8:
# - GL's image agrees with the exact C frame as tightly as gl_shading.sh asks of lighting.frag
#   and its port (p99 relative error <= 0.05, no pixel more than 8/255 apart), and the readout
#   shows both values;
# - the difference's linear image is |C - GL|;
# - after the camera orbits, the environment turns (]) and the point lights go off (3), the new
#   C frame (which differs from the first) and its GL image still agree: the camera, the
#   rotation and the toggles reach softlight-gl;
# - a lighting program and its GLSL twin (examples/shaders/toon.c, --glsl toon.frag) agree within
#   the bound gl_check.sh states for them (share > 8/255 <= 0.5%);
# - with the shadow maps on (U, scenes/lamp.json), softlight-gl draws its own and its image agrees
#   as the scene's view does (the frame compared without them is far outside: p99 rel 0.8); so
#   does the env lights' (U on scenes/city-sun.json with --env-lights 32);
# - a softlight-gl that cannot run is a message, and the viewer goes on (exit 0); --glsl without
#   --lighting, or naming no file, is one line and exit 2.
# CTest label: release-only
set -euo pipefail
source "$(dirname "$0")/view_common.bash"
view_setup "$@"
source "$(dirname "$0")/gl_common.bash"
GL=$BUILD/softlight-gl
if ! why=$("$GL" info 2>&1 >/dev/null); then
    echo "SKIP: softlight-gl cannot create an OpenGL context here: $why"
    exit 0
fi
SCENE=scenes/default.json
export XDG_CACHE_HOME=$T/cache

# agree A B LABEL [MAX_OVER8_PERCENT]: the gl_shading.sh bounds
agree() {
    "$SL" compare "$1" "$2" >"$T/cmp.txt" 2>&1 || true
    local p99
    p99=$(gl_field "p99 rel error" "$T/cmp.txt")
    awk -v p="$p99" 'BEGIN { exit !(p <= 0.05) }' || { cat "$T/cmp.txt"; fail "$3: p99 rel $p99 > 0.05"; }
    gl_check_share "$3" "$T/cmp.txt" "${4:-0}" || { cat "$T/cmp.txt"; fail "$3"; }
    echo "ok: $3 (p99 rel $p99)"
}

cat >"$T/script.txt" <<SCRIPT
settle
snapshot $T/c
key m
settle
snapshot $T/gl
readout
key m
settle
snapshot $T/diff
key m
key Left
key ]
key 3
settle
snapshot $T/c2
key m
settle
snapshot $T/gl2
quit
SCRIPT
view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --script "$T/script.txt"
[ "$rc" = 0 ] || fail "the viewer exited $rc"
agree "$T/c.pfm" "$T/gl.pfm" "GL's image of the scene's view"
grep -E '^softlight view: readout pixel [0-9]+,[0-9]+ of 320x180: C [-0-9.e]+ [-0-9.e]+ [-0-9.e]+, GL ' "$T/out.txt" >/dev/null ||
    fail "the readout does not show C and GL"
echo "ok: the readout shows both"
grep -E '^softlight view: compare: softlight-gl \(.*\) lit the 320x180 frame in [0-9.]+ s: p99 rel ' "$T/out.txt" >/dev/null ||
    fail "no line for the comparison's run on stdout"
echo "ok: each run's figures on stdout"
PYTHONPATH="$(dirname "$0")" python3 - "$T/c.pfm" "$T/gl.pfm" "$T/diff.pfm" <<'PY' || fail "the difference's image is not |C - GL|"
import sys
from pfm import read_pfm
c, g, d = (read_pfm(p)[3] for p in sys.argv[1:4])
worst = max(abs(abs(a - b) - e) for a, b, e in zip(c, g, d))
sys.exit(0 if worst <= 1e-6 else 1)
PY
echo "ok: the difference's linear image is |C - GL|"
view_differ "$T/c.pfm" "$T/c2.pfm" "orbit, environment rotation and no point lights change the frame"
agree "$T/c2.pfm" "$T/gl2.pfm" "GL's image after orbit, ] and 3"

# a lighting program and its twin
cat >"$T/toon.txt" <<SCRIPT
settle
snapshot $T/toon-c
key m
settle
snapshot $T/toon-gl
quit
SCRIPT
view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --lighting examples/shaders/toon.c --glsl examples/shaders/toon.frag \
    --script "$T/toon.txt"
[ "$rc" = 0 ] || fail "the viewer with toon.c exited $rc"
agree "$T/toon-c.pfm" "$T/toon-gl.pfm" "toon.c against toon.frag" 0.5

# a softlight-gl that cannot run: a message, the viewer goes on
cat >"$T/missing.txt" <<SCRIPT
key m
settle
snapshot $T/still-c
quit
SCRIPT
SOFTLIGHT_GL=$T/no-such-program view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --script "$T/missing.txt"
[ "$rc" = 0 ] || fail "the viewer with no softlight-gl exited $rc"
grep "compare: cannot run $T/no-such-program" "$T/err.txt" >/dev/null || fail "no message for a missing softlight-gl"
[ -s "$T/still-c.pfm" ] || fail "no snapshot after the failed comparison"
echo "ok: a missing softlight-gl is a message"

# shadow maps (U): GL draws its own, and the two images agree
cat >"$T/shadows.txt" <<SCRIPT
key u
settle
snapshot $T/sh-c
key m
settle
snapshot $T/sh-gl
quit
SCRIPT
view_run scenes/lamp.json --size "$VIEW_TEST_SIZE" -n 8 --script "$T/shadows.txt"
[ "$rc" = 0 ] || fail "the viewer with shadows exited $rc"
agree "$T/sh-c.pfm" "$T/sh-gl.pfm" "GL's image with the shadow maps (U)"
# ... and the env lights' maps (U with --env-lights): scenes/city-sun.json's sun
view_run scenes/city-sun.json --size "$VIEW_TEST_SIZE" -n 8 --env-lights 32 --script "$T/shadows.txt"
[ "$rc" = 0 ] || fail "the viewer with the env lights' shadows exited $rc"
view_differ "$T/sh-c.pfm" "$T/c.pfm" "city-sun's frame is not the default scene's"
agree "$T/sh-c.pfm" "$T/sh-gl.pfm" "GL's image with the env lights' shadow maps (U, --env-lights 32)"

for args in "--glsl examples/shaders/toon.frag" "--lighting examples/shaders/toon.c --glsl $T/none.frag"; do
    # shellcheck disable=SC2086
    set +e
    "$SL" view "$SCENE" $args >"$T/o" 2>"$T/e"
    status=$?
    set -e
    [ "$status" = 2 ] && [ "$(wc -l <"$T/e")" = 1 ] && grep -- "--glsl" "$T/e" >/dev/null ||
        fail "view $args: exit $status, $(cat "$T/e")"
    echo "ok: view $args: $(cat "$T/e")"
done
