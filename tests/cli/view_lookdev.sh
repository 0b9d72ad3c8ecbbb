#!/usr/bin/env bash
# view_lookdev.sh BUILD_DIR - what a look-dev viewer's user relies on, under Xvfb with scripted
# input: F frames the model (its bounds in view, from far off), the zoom stays between the
# bounds and 10 x the framing distance, R restores every setting (the frame and PNG equal
# `softlight render`'s again), O toggles ambient occlusion (U the shadow maps, Y the sky maps, J
# the reflection occlusion), N/B pass the scene's N, the readout
# under the pointer equals the PFM `softlight render` writes at that pixel, T prints softlight trace's text, an edited scene
# file is reloaded (the camera kept), and --env / an environment alone render as render --env.
# CTest label: release-only
set -euo pipefail
source "$(dirname "$0")/view_common.bash"
view_setup "$@"
SCENE=scenes/default.json

"$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 -o "$T/ref.png" --hdr "$T/ref.hdr" --pfm "$T/ref.pfm" -q

# ---- framing, zoom limits, reset of every setting
{
    echo "settle"
    # lost: zoomed far out and panned off the model
    echo "wheel -300"
    for i in $(seq 1 40); do echo "key d"; done
    echo "settle"
    echo "screenshot $T/far"
    # depth view: the readout says whether a pixel holds geometry
    for i in 1 2 3 4 5 6; do echo "key v"; done
    echo "settle"
    echo "move 160 90"
    echo "readout"
    echo "key f"
    echo "settle"
    echo "screenshot $T/framed"
    # the centre column (the grid's centre itself is a gap between spheres)
    for y in $(seq 0 4 179); do echo "move 160 $y"; echo "readout"; done
    # the image's border: no pixel of the model may touch it
    for x in $(seq 0 4 319); do echo "move $x 0"; echo "readout"; echo "move $x 179"; echo "readout"; done
    for y in $(seq 0 4 179); do echo "move 0 $y"; echo "readout"; echo "move 319 $y"; echo "readout"; done
    echo "wheel 300"
    echo "settle"
    echo "screenshot $T/near"
    # every setting off the scene's, then R
    for k in n n e e c 1 2 3 l k g i o ] ] v; do echo "key $k"; done
    echo "drag 100 90 160 120"
    echo "wheel 3"
    echo "key r"
    echo "settle"
    echo "screenshot $T/reset"
    echo "quit"
} >"$T/frame.txt"
view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --script "$T/frame.txt"
view_expect_exit0 "framing"
eye_dist() { # NAME: distance from eye to target in NAME's screenshot line
    awk -v n="$1.png" '$0 ~ n { for (i = 1; i <= NF; i++) { if ($i == "eye") e = $(i + 1); if ($i == "target") t = $(i + 1) } }
        END { split(e, a, ","); split(t, b, ","); printf "%.4f\n", sqrt((a[1]-b[1])^2 + (a[2]-b[2])^2 + (a[3]-b[3])^2) }' "$T/out.txt"
}
far=$(eye_dist "$T/far") framed=$(eye_dist "$T/framed") near=$(eye_dist "$T/near")
echo "distances: 300 clicks out $far, framed $framed, 300 clicks in $near"
# default.json: unit spheres at y = 0 seen along +Y; the bounds' front face is y = -1
awk -v f="$far" -v fr="$framed" 'BEGIN { exit !(f <= 10.01 * fr && f > 5 * fr) }' ||
    fail "300 clicks out went to $far, not about 10 x the framing distance $framed"
awk -v n="$near" 'BEGIN { exit !(n > 1.0 && n < 2.0) }' || fail "300 clicks in went to $near: inside the bounds"
echo "ok: the zoom stays between the bounds and 10 x the framing distance"
grep -q "readout pixel 160,90 .*no geometry" "$T/out.txt" || fail "the lost camera still showed the model at the centre"
[ "$(grep -c 'readout pixel' "$T/out.txt")" -eq 296 ] || fail "expected 296 readouts"
grep 'readout pixel' "$T/out.txt" | sed -n 2,46p | grep "depth [0-9]" >/dev/null || fail "after F the centre column holds no geometry"
if grep 'readout pixel' "$T/out.txt" | tail -n 250 | grep "depth [0-9]" >/dev/null; then
    fail "after F the model touches the image's border"
fi
echo "ok: F brings the model back, its bounds inside the view"
view_same "$T/reset.hdr" "$T/ref.hdr" "R after changing every setting" 0
cmp -s "$T/reset.png" "$T/ref.png" || fail "after R the PNG differs (exposure, contrast or view not restored)"
grep -q "reset.png .*(320x180, final, N 8;" "$T/out.txt" || fail "after R the view or N is not the scene's"
echo "ok: R restores camera, N, exposure, contrast, toggles, rules, irradiance, rotation and view"

# ---- O: ambient occlusion off and on again, each still frame render's with and without --ao-radius
"$SL" render scenes/pbr.json --size "$VIEW_TEST_SIZE" -n 8 --ao-radius 0.5 --hdr "$T/ao-ref.hdr" -q
"$SL" render scenes/pbr.json --size "$VIEW_TEST_SIZE" -n 8 --hdr "$T/noao-ref.hdr" -q
printf 'settle\nkey o\nsettle\nscreenshot %s/ao-off\nkey o\nsettle\nscreenshot %s/ao-on\nquit\n' "$T" "$T" >"$T/ao.txt"
view_run scenes/pbr.json --size "$VIEW_TEST_SIZE" -n 8 --ao-radius 0.5 --script "$T/ao.txt"
view_expect_exit0 "O"
view_same "$T/ao-off.hdr" "$T/noao-ref.hdr" "O turns ambient occlusion off" 0
view_same "$T/ao-on.hdr" "$T/ao-ref.hdr" "O turns it on again with --ao-radius's radius" 0
echo "ok: O toggles ambient occlusion; each still frame is render's"

# toggle_on_off KEY SCENE WHAT OPTIONS...: KEY turns WHAT on and off again in a viewer started
# without OPTIONS; each still frame is render's with and without them
toggle_on_off() {
    local key=$1 scene=$2 what=$3 k
    shift 3
    k=$(echo "$key" | tr 'A-Z' 'a-z')
    "$SL" render "$scene" --size "$VIEW_TEST_SIZE" -n 8 "$@" --hdr "$T/$k-ref.hdr" -q
    "$SL" render "$scene" --size "$VIEW_TEST_SIZE" -n 8 --hdr "$T/no$k-ref.hdr" -q
    printf 'settle\nkey %s\nsettle\nscreenshot %s/%s-on\nkey %s\nsettle\nscreenshot %s/%s-off\nquit\n' \
        "$k" "$T" "$k" "$k" "$T" "$k" >"$T/$k.txt"
    view_run "$scene" --size "$VIEW_TEST_SIZE" -n 8 --script "$T/$k.txt"
    view_expect_exit0 "$key"
    view_same "$T/$k-on.hdr" "$T/$k-ref.hdr" "$key turns $what on" 0
    view_same "$T/$k-off.hdr" "$T/no$k-ref.hdr" "$key turns $what off again" 0
    echo "ok: $key toggles $what; each still frame is render's"
}

# ---- U: the point lights' shadow maps (--shadows); Y: the sky visibility maps (--sky-maps 32)
toggle_on_off U scenes/lamp.json "the shadow maps" --shadows
toggle_on_off Y scenes/bunny.json "the sky visibility maps" --sky-maps 32

# ---- J: the reflection occlusion, in a viewer started with it (its distance): off, then on again
"$SL" render scenes/grazing.json --size "$VIEW_TEST_SIZE" -n 8 --reflection-occlusion 5 --hdr "$T/j-ref.hdr" -q
"$SL" render scenes/grazing.json --size "$VIEW_TEST_SIZE" -n 8 --hdr "$T/noj-ref.hdr" -q
printf 'settle\nkey j\nsettle\nscreenshot %s/j-off\nkey j\nsettle\nscreenshot %s/j-on\nquit\n' "$T" "$T" >"$T/j.txt"
view_run scenes/grazing.json --size "$VIEW_TEST_SIZE" -n 8 --reflection-occlusion 5 --script "$T/j.txt"
view_expect_exit0 J
view_same "$T/j-off.hdr" "$T/noj-ref.hdr" "J turns the reflection occlusion off" 0
view_same "$T/j-on.hdr" "$T/j-ref.hdr" "J turns it on again with --reflection-occlusion's distance" 0
echo "ok: J toggles the reflection occlusion; each still frame is render's"

# ---- N/B and the scene's own N (40): up to 64 and back to 40
printf 'key n\nscreenshot %s/n-up\nkey b\nscreenshot %s/n-back\nkey b\nscreenshot %s/n-down\nquit\n' "$T" "$T" "$T" >"$T/n.txt"
view_run "$SCENE" --size 64x36 --script "$T/n.txt"
view_expect_exit0 "N/B"
for want in "n-up.png .*N 64;" "n-back.png .*N 40;" "n-down.png .*N 32;"; do
    grep -q "$want" "$T/out.txt" || fail "N/B: expected '$want'"
done
echo "ok: N/B step 40 -> 64 -> 40 -> 32"

# ---- the readout against render's PFM, and the trace against softlight trace
cat >"$T/probe.txt" <<SCRIPT
settle
move 88 28
readout
move 5 170
readout
move 88 28
key t
quit
SCRIPT
view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --script "$T/probe.txt"
view_expect_exit0 "readout"
python3 - "$T/ref.pfm" "$T/out.txt" <<'PY' || fail "the readout differs from render's PFM"
import re, struct, sys
with open(sys.argv[1], "rb") as f:
    assert f.readline().strip() == b"PF"
    w, h = map(int, f.readline().split())
    scale = float(f.readline())
    data = struct.unpack(("<" if scale < 0 else ">") + "%df" % (w * h * 3), f.read(w * h * 12))
n = 0
for line in open(sys.argv[2]):
    m = re.search(r"readout pixel (\d+),(\d+) of (\d+)x(\d+): radiance (\S+) (\S+) (\S+)", line)
    if not m:
        continue
    x, y = int(m.group(1)), int(m.group(2))
    got = [float(m.group(i)) for i in (5, 6, 7)]
    i = ((h - 1 - y) * w + x) * 3  # PFM rows run bottom to top
    want = data[i:i + 3]
    print("pixel %d,%d: readout %s, pfm %s" % (x, y, got, list(want)))
    if any(abs(a - b) > 1e-7 * max(1.0, abs(b)) for a, b in zip(got, want)):
        sys.exit(1)
    n += 1
sys.exit(0 if n == 2 else 1)
PY
echo "ok: the readout is the PFM's value at the pixel"
"$SL" trace "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --pixel 88,28 >"$T/trace-ref.txt"
awk '/softlight view: trace of pixel/ { on = 1; next } /^softlight view:/ { on = 0 } on' "$T/out.txt" >"$T/trace.txt"
diff "$T/trace-ref.txt" "$T/trace.txt" || fail "T's trace differs from softlight trace --pixel 88,28"
echo "ok: T prints softlight trace's text ($(wc -l <"$T/trace.txt") lines)"

# ---- reload: an edited scene file is picked up; a moved camera stays
sed "s#envmaps/studio.hdr#$PWD/scenes/envmaps/studio.hdr#" "$SCENE" >"$T/scene.json"
sed 's/"ks90-a100": {"kd": 0.05, "ks": 0.9/"ks90-a100": {"kd": 0.8, "ks": 0.1/' "$T/scene.json" >"$T/edited.json"
sed 's/"ks90-a1000": {"kd": 0.05, "ks": 0.9/"ks90-a1000": {"kd": 0.8, "ks": 0.1/' "$T/edited.json" >"$T/edited2.json"
cmp -s "$T/scene.json" "$T/edited.json" && fail "the edit did not apply"
"$SL" render "$T/edited.json" --size "$VIEW_TEST_SIZE" -n 8 --hdr "$T/edited-ref.hdr" -q
cat >"$T/reload.txt" <<SCRIPT
settle
screenshot $T/before
wait 3000
settle
screenshot $T/after
drag 160 90 200 100
settle
screenshot $T/moved
wait 3000
settle
screenshot $T/moved-after
quit
SCRIPT
(
    # the edits, each once the screenshot before it exists (cp: a new file's time, as editors save)
    for i in $(seq 1 300); do [ -s "$T/before.hdr" ] && break; sleep 0.1; done
    sleep 0.3 && cp "$T/edited.json" "$T/scene.json"
    for i in $(seq 1 300); do [ -s "$T/moved.hdr" ] && break; sleep 0.1; done
    sleep 0.3 && cp "$T/edited2.json" "$T/scene.json"
) &
editor=$!
view_run "$T/scene.json" --size "$VIEW_TEST_SIZE" -n 8 --script "$T/reload.txt"
wait "$editor"
view_expect_exit0 "reload"
view_same "$T/before.hdr" "$T/ref.hdr" "before the edit" 0
view_same "$T/after.hdr" "$T/edited-ref.hdr" "after the edit the frame is render's of the edited file" 0
cam() { grep "$1.png" "$T/out.txt" | sed 's/.*camera //'; }
[ "$(cam "$T/moved")" = "$(cam "$T/moved-after")" ] || fail "the reload moved the camera: $(cam "$T/moved") -> $(cam "$T/moved-after")"
view_differ "$T/moved-after.hdr" "$T/moved.hdr" "the second edit shows at the moved camera"
echo "ok: edits reload, the camera stays"

# ---- --env, and an environment alone
"$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --env scenes/envmaps/city.hdr --hdr "$T/city-ref.hdr" -q
printf 'screenshot %s/env\nquit\n' "$T" >"$T/env.txt"
view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --env scenes/envmaps/city.hdr --script "$T/env.txt"
view_expect_exit0 "--env"
view_same "$T/env.hdr" "$T/city-ref.hdr" "view --env equals render --env" 0
view_run scenes/envmaps/city.hdr --size "$VIEW_TEST_SIZE" -n 8 --script "$T/env.txt"
view_expect_exit0 "an environment alone"
view_same "$T/env.hdr" "$T/city-ref.hdr" "view ENV.hdr is the default scene under it" 0
echo "PASS view_lookdev"
