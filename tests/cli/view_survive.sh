#!/usr/bin/env bash
# view_survive.sh BUILD_DIR - the viewer survives bad drops, a 1x1 window, input floods and
# being closed in the middle of a refinement, and exits 0 each time.
#
# Every check ends in a screenshot compared with `softlight render` where the state is known:
# after the bad drops the scene and environment must be exactly the old ones; after the 1x1
# window the full-size frame must be exact again. Good drops must change the image.
set -euo pipefail
source "$(dirname "$0")/view_common.bash"
view_setup "$@"
SCENE=scenes/default.json

"$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 -o "$T/ref.png" --hdr "$T/ref.hdr" -q

# Corrupt inputs: a truncated RLE .hdr, a .hdr of random bytes, broken JSON, a scene naming a
# mesh that does not exist, a missing file, an unsupported type, and a directory.
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 64 +X 64\n\002\002\000\100\377' >"$T/truncated.hdr"
head -c 3000 /dev/urandom >"$T/random.hdr"
printf '{"camera": {"eye": [0, -5, 1], ' >"$T/broken.json"
printf '{"objects": [{"mesh": "nowhere.obj", "material": "m"}], "materials": {"m": {"kd": 0.5}}}' >"$T/missing-mesh.json"
echo "hello" >"$T/notes.txt"
mkdir -p "$T/dir.hdr"

cat >"$T/drops.txt" <<SCRIPT
settle
drop $T/truncated.hdr
drop $T/random.hdr
drop $T/broken.json
drop $T/missing-mesh.json
drop $T/does-not-exist.hdr
drop $T/notes.txt
drop $T/dir.hdr
settle
screenshot $T/after-bad
resize 1 1
settle
screenshot $T/tiny
resize 320 180
settle
screenshot $T/restored
drop scenes/envmaps/city.hdr
settle
screenshot $T/city
drop scenes/top-down.json
settle
screenshot $T/top-down
drop scenes/meshes/bunny.obj
settle
screenshot $T/bunny
quit
SCRIPT
view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --script "$T/drops.txt"
view_expect_exit0 "bad drops"
view_same "$T/after-bad.hdr" "$T/ref.hdr" "bad drops leave scene and environment as they were" 0
for f in truncated.hdr random.hdr broken.json missing-mesh.json does-not-exist.hdr notes.txt dir.hdr; do
    grep -q "$f" "$T/err.txt" || fail "no error line on stderr for the dropped $f"
done
echo "ok: each bad drop got an error line on stderr"
head -c 24 "$T/tiny.png" | od -An -tx1 | tr -d ' \n' | grep '0000000d4948445200000001' >/dev/null ||
    fail "the 1x1 window's screenshot is not a 1x1 PNG"
echo "ok: a 1x1 window renders a 1x1 frame"
view_same "$T/restored.hdr" "$T/ref.hdr" "back at 320x180 the frame is exact again" 0
view_differ "$T/city.hdr" "$T/ref.hdr" "dropping city.hdr changes the lighting"
view_differ "$T/top-down.hdr" "$T/city.hdr" "dropping top-down.json loads that scene"
"$SL" render scenes/top-down.json --size "$VIEW_TEST_SIZE" -n 8 --hdr "$T/top-down-ref.hdr" -q
"$SL" render scenes/top-down.json --size "$VIEW_TEST_SIZE" -n 40 --hdr "$T/top-down-ref40.hdr" -q
# The dropped scene brings its own settings (N 40) unless the command line set them (-n 8 here).
view_same "$T/top-down.hdr" "$T/top-down-ref.hdr" "the dropped scene renders as softlight render renders it" 0

# A model dropped: the default scene around it, as `softlight render MODEL` renders it.
"$SL" render scenes/meshes/bunny.obj --size "$VIEW_TEST_SIZE" -n 8 --hdr "$T/bunny-ref.hdr" -q
view_same "$T/bunny.hdr" "$T/bunny-ref.hdr" "a dropped model renders as softlight render MODEL renders it" 0

# A flood: 300 drags of 4 motion events, 200 key presses of every kind, wheel spins, without a
# pause, then a reset of everything that was touched and a check that the frame is exact.
{
    echo "settle"
    for i in $(seq 1 300); do echo "drag $((i % 300)) $((i % 170)) $(((i * 7) % 320)) $(((i * 3) % 180)) $([ $((i % 3)) -eq 0 ] && echo right || echo left) 4"; done
    for i in $(seq 1 20); do
        for k in e q c x n b bracketright bracketleft 1 1 2 2 3 3 l k k k g v h F1 i; do
            case $k in bracketright) echo "key ]" ;; bracketleft) echo "key [" ;; *) echo "key $k" ;; esac
        done
        echo "wheel $((i % 5 - 2))"
    done
    # Every toggle was pressed an even number of times and every cycle went round whole (20 x
    # lod over 5, 60 x estimator over 4, 20 x G over 2, 20 x irradiance over oct/dp/sh9/brute),
    # N went up and down, the environment +15 -15; only the view (20 mod 8 = 4: ks) and the
    # camera are off.
    echo "settle"
    echo "screenshot $T/flood-ks"
    for k in v v v v r; do echo "key $k"; done
    echo "screenshot $T/flood"
    echo "quit"
} >"$T/flood.txt"
view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --script "$T/flood.txt"
view_expect_exit0 "input flood"
grep -q "flood-ks.png .*(320x180, ks," "$T/out.txt" || fail "after the flood the view is not 'ks'"
view_same "$T/flood.hdr" "$T/ref.hdr" "after $(wc -l <"$T/flood.txt") scripted commands in a burst and a reset" 0

# Closed mid-refinement: a large N makes the full frame slow; quit arrives while it is refining.
printf 'drag 100 90 140 90\nwait 700\nquit\n' >"$T/close.txt"
view_run "$SCENE" --size 640x360 -n 1024 --script "$T/close.txt"
view_expect_exit0 "closed mid-refinement"
awk -v s="$secs" 'BEGIN { exit !(s < 20) }' || fail "closing mid-refinement took ${secs}s"
echo "ok: closed mid-refinement in ${secs}s"

# --frames, and no font: the viewer runs without HUD text and says so once.
view_run "$SCENE" --size 160x90 -n 4 --frames 3 --font "$T/no-such-font.ttf"
view_expect_exit0 "--frames with a missing font"
[ "$(grep -c 'running without HUD text' "$T/err.txt")" -eq 1 ] || fail "the missing font was not reported once"
echo "ok: missing font reported once, --frames 3 quits"
echo "PASS view_survive"
