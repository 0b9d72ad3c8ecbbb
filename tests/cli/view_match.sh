#!/usr/bin/env bash
# view_match.sh BUILD_DIR - `softlight view` shows what `softlight render` makes, and moves.
#
# Under Xvfb the viewer opens scenes/default.json in a 320x180 window at N = 8 and is driven by a
# script (view_script.c): a screenshot of the untouched view must equal `softlight render` of the
# scene's camera (linear .hdr to the last bit, and the PNG byte for byte); a left-button drag must
# change the image; R must bring back exactly the first image; the G-buffer views must change
# the PNG but not the linear screenshot. Also: exit status 0, one clear line and exit 2 with no
# display, and --help without a display.
# CTest label: release-only
set -euo pipefail
source "$(dirname "$0")/view_common.bash"
view_setup "$@"
SCENE=scenes/default.json

"$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 -o "$T/ref.png" --hdr "$T/ref.hdr" -q

cat >"$T/script.txt" <<SCRIPT
# the first frame: the scene's own camera
settle
screenshot $T/home
# orbit 60 pixels to the right and 20 down, in 30 motion events
drag 160 90 220 110 left 30
settle
screenshot $T/orbit
# keyboard orbit and zoom, then back home
key Left
key Up
key +
key r
screenshot $T/reset
# G-buffer views: normal, then back to final
key v
key v
screenshot $T/normal
key shift+v
key shift+v
key F1
screenshot $T/final-again
# each control against the command-line option that means the same
key 1
screenshot $T/no-diffuse
key 1
key 2
screenshot $T/no-specular
key 2
key k
screenshot $T/consistent
key k
screenshot $T/mf
key k
screenshot $T/splitsum
key k
screenshot $T/mis
key k
screenshot $T/cv
key k
screenshot $T/cvmis
key k
key l
screenshot $T/gems
key l
screenshot $T/pdf
key l
key l
key l
key i
screenshot $T/dp
key i
key i
screenshot $T/brute
key i
key n
screenshot $T/n16
key b
key g
screenshot $T/g-one
key g
screenshot $T/controls-back
# exposure changes what is shown, not the radiance
key e
key e
screenshot $T/brighter
quit
SCRIPT

view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --script "$T/script.txt"
view_expect_exit0 "scripted session"
view_same "$T/home.hdr" "$T/ref.hdr" "first frame equals softlight render" 0
cmp -s "$T/home.png" "$T/ref.png" || fail "home.png differs from softlight render's PNG"
echo "ok: first frame's PNG is byte-identical to softlight render's"
view_differ "$T/orbit.hdr" "$T/ref.hdr" "a drag orbits the camera"
# The drag's camera, derived by hand: 0.4 degrees a pixel, so 60 px right turns the eye 24 degrees
# clockwise about +Z (azimuth -90 -> -114) and 20 px down raises it 8 degrees, distance 20 kept.
awk '/orbit.png/ { for (i = 1; i <= NF; i++) if ($i == "eye") print $(i + 1) }' "$T/out.txt" | tr ',' ' ' |
    awk 'function rad(d) { return d * atan2(0, -1) / 180 }
         { ex = 20 * cos(rad(8)) * cos(rad(-114)); ey = 20 * cos(rad(8)) * sin(rad(-114)); ez = 20 * sin(rad(8))
           d = sqrt(($1 - ex)^2 + ($2 - ey)^2 + ($3 - ez)^2)
           printf "orbit eye (%s, %s, %s), expected (%.4f, %.4f, %.4f), off by %.2g\n", $1, $2, $3, ex, ey, ez, d
           exit !(d < 1e-3) }' || fail "the drag moved the camera to the wrong place"
view_same "$T/reset.hdr" "$T/ref.hdr" "R resets to the scene's camera" 0
view_same "$T/normal.hdr" "$T/ref.hdr" "the normal view's .hdr is still the radiance" 0
cmp -s "$T/normal.png" "$T/ref.png" && fail "the normal view's PNG equals the final image"
echo "ok: the normal view shows something else"
cmp -s "$T/final-again.png" "$T/ref.png" || fail "back in the final view (help open) the PNG differs"
echo "ok: the help overlay is not in the screenshot"
while read -r shot options; do
    # shellcheck disable=SC2086
    "$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 $options --hdr "$T/$shot-ref.hdr" -q
    view_same "$T/$shot.hdr" "$T/$shot-ref.hdr" "key for $options" 0
done <<LIST
no-diffuse --specular-only
no-specular --diffuse-only
consistent --estimator consistent
mf --estimator mf
splitsum --estimator splitsum
mis --estimator mis
cv --estimator cv
cvmis --estimator cvmis
gems --lod gems
pdf --lod pdf
dp --irradiance dp
brute --irradiance brute
n16 -n 16
g-one --g one
LIST
view_same "$T/controls-back.hdr" "$T/ref.hdr" "every control back where it was" 0
view_same "$T/brighter.hdr" "$T/ref.hdr" "exposure leaves the radiance alone" 0
cmp -s "$T/brighter.png" "$T/ref.png" && fail "two exposure steps did not change the PNG"
echo "ok: exposure changes the PNG"
grep -q "camera eye 0,-20,0 target 0,0,0" "$T/out.txt" || fail "the screenshot line does not print the camera"

# No display: one line, exit 2, and it names the render command.
set +e
msg=$(env -u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER "$SL" view "$SCENE" 2>&1)
status=$?
set -e
[ "$status" -eq 2 ] || fail "without a display: exit $status, expected 2"
[ "$(printf '%s\n' "$msg" | wc -l)" -eq 1 ] || fail "without a display: expected one line, got: $msg"
case "$msg" in
*"no display"*"softlight render $SCENE -o out.png"*) echo "ok: no display -> '$msg'" ;;
*) fail "without a display: unexpected message '$msg'" ;;
esac
env -u DISPLAY -u WAYLAND_DISPLAY "$SL" view --help | grep -- "--script" >/dev/null || fail "--help without a display"
echo "ok: --help needs no display"
echo "PASS view_match"
