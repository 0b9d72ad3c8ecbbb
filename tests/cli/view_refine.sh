#!/usr/bin/env bash
# view_refine.sh BUILD_DIR - how `softlight view` refines: the moving stage, the accumulation of
# rotated frames while the camera is still, and the exact frame it ends with.
#
# Under Xvfb the viewer opens scenes/default.json in a 320x180 window at N = 32, so a still camera
# gets 4 accumulation frames of N = 8 (ceil(32 / 8)) and then the exact N = 32 frame. The script's
# `accumulated K` runs in the first turn after the K-th frame, before the next one starts, and
# `snapshot` writes what is on screen (PNG) and the linear image behind it (PFM, float32, so the
# checks below are exact).
# With --accumulate-lod frame (each frame filtered as for its own 8 samples, so each frame is
# something `softlight render` can make):
#   - accumulation frame 0 is `softlight render --rotate --frame 0 -n 8`, to the last bit;
#   - after 2 frames the image is the mean of frames 0 and 1: m - f0 = (f1 - f0) / 2, so its RMS
#     distance to each of them is half theirs (to float rounding, checked to 0.1%);
#   - the changes shrink: for a running mean of independent frames E|m4 - m2|^2 = s^2 / 4 and
#     E|m2 - m1|^2 = s^2 / 2, so the first RMS is about 0.71 of the second (checked below 0.85).
# With the default (frames filtered as for the total N = 32): the mean of 4 frames is far closer
# to the exact frame than with `frame` (measured 0.008 against 0.10 RMS; checked below a quarter),
# and closer than the first frame alone (it converges towards what the window ends with).
# Both: the converged image is `softlight render -n 32`, to the last bit (PFM and .hdr) and byte
# for byte (PNG); while moving (a drag, --move-div 2) the frame is half size, lit with the split
# sum (the default) or, with --move-estimator user, N 8 rotated; the converged image is exact
# either way (the moving estimator never reaches the exact stage).
# Also: --benchmark runs and reports its figures (no timing is asserted: the machine is shared).
set -euo pipefail
source "$(dirname "$0")/view_common.bash"
view_setup "$@"
SCENE=scenes/default.json

for k in 0 1; do
    "$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --rotate --frame $k --pfm "$T/f$k.pfm" -o "$T/f$k.png" -q
done
"$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 32 -o "$T/ref.png" --hdr "$T/ref.hdr" --pfm "$T/ref.pfm" -q

for lod in frame total; do
    cat >"$T/script-$lod.txt" <<SCRIPT
accumulated 1
snapshot $T/$lod-acc1
accumulated 2
snapshot $T/$lod-acc2
accumulated 4
snapshot $T/$lod-acc4
settle
snapshot $T/$lod-done
screenshot $T/$lod-final
drag 100 90 140 90 left 8
snapshot $T/$lod-moving
quit
SCRIPT
    move=(); [ $lod = frame ] && move=(--move-estimator user)
    view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 32 --move-div 2 "${move[@]}" --accumulate-lod $lod --script "$T/script-$lod.txt"
    view_expect_exit0 "scripted refinement, --accumulate-lod $lod"
    cp "$T/out.txt" "$T/out-$lod.txt"
done

rmse() { "$SL" compare "$1" "$2" | sed -n 's/^rmse *\([0-9.eE+-]*\).*/\1/p'; }
"$SL" compare "$T/f0.pfm" "$T/f1.pfm" >"$T/cmp.txt"
grep -q "^rmse" "$T/cmp.txt" || { cat "$T/cmp.txt"; fail "softlight compare printed no rmse"; }

view_same "$T/frame-acc1.pfm" "$T/f0.pfm" "accumulation frame 0 is softlight render --rotate --frame 0 -n 8" 0
cmp -s "$T/frame-acc1.png" "$T/f0.png" || fail "frame-acc1.png differs from softlight render --rotate --frame 0"
grep -q "frame-acc1.png .*(320x180, accumulating, N 8 rotated, frame 0, 1 frames averaged)" "$T/out-frame.txt" ||
    fail "the first snapshot line does not say: accumulating, N 8 rotated, frame 0, 1 frame"
grep -q "frame-acc2.png .*frame 1, 2 frames averaged)" "$T/out-frame.txt" ||
    fail "the second snapshot is not the mean of 2 frames"

d01=$(rmse "$T/f0.pfm" "$T/f1.pfm")
d0=$(rmse "$T/frame-acc2.pfm" "$T/f0.pfm")
d1=$(rmse "$T/frame-acc2.pfm" "$T/f1.pfm")
awk -v a="$d01" -v b="$d0" -v c="$d1" 'BEGIN {
    printf "rmse(f0, f1) %s, rmse(mean2, f0) %s, rmse(mean2, f1) %s: ratios %.5f %.5f (expected 0.5)\n", a, b, c, b / a, c / a
    exit !(a > 1e-4 && b / a > 0.4995 && b / a < 0.5005 && c / a > 0.4995 && c / a < 0.5005) }' ||
    fail "after 2 frames the image is not the mean of frames 0 and 1"
echo "ok: after 2 frames the image is the mean of frames 0 and 1"

d42=$(rmse "$T/frame-acc4.pfm" "$T/frame-acc2.pfm")
d21=$(rmse "$T/frame-acc2.pfm" "$T/frame-acc1.pfm")
awk -v a="$d42" -v b="$d21" 'BEGIN {
    printf "rmse(mean4, mean2) %s against rmse(mean2, mean1) %s: ratio %.3f (expected about 0.71)\n", a, b, a / b
    exit !(a > 0 && a / b < 0.85) }' || fail "the accumulation does not converge (changes do not shrink)"
echo "ok: the mean converges"

view_differ "$T/total-acc1.pfm" "$T/f0.pfm" "with the total N's mip levels, frame 0 is filtered differently"
e_frame=$(rmse "$T/frame-acc4.pfm" "$T/ref.pfm")
e_total=$(rmse "$T/total-acc4.pfm" "$T/ref.pfm")
e_first=$(rmse "$T/total-acc1.pfm" "$T/ref.pfm")
awk -v f="$e_frame" -v t="$e_total" -v one="$e_first" 'BEGIN {
    printf "distance of the 4-frame mean to the exact frame: %s (total lod), %s (frame lod); first frame alone %s\n", t, f, one
    exit !(t < 0.25 * f && t < one) }' || fail "the default accumulation does not converge towards the exact frame"
echo "ok: the default accumulation converges towards the exact frame"

for lod in frame total; do
    view_same "$T/$lod-done.pfm" "$T/ref.pfm" "$lod: the converged image is softlight render -n 32 (PFM)" 0
    view_same "$T/$lod-final.hdr" "$T/ref.hdr" "$lod: the converged screenshot is softlight render -n 32 (.hdr)" 0
    cmp -s "$T/$lod-final.png" "$T/ref.png" || fail "$lod: the converged PNG differs from softlight render -n 32"
    echo "ok: $lod: the converged PNG is byte-identical to softlight render's"
    grep -q "$lod-done.png .*(320x180, exact, N 32, frame 0, 1 frames averaged, exact)" "$T/out-$lod.txt" ||
        fail "$lod: the converged snapshot line does not say: exact, N 32"
done
grep -q "frame-moving.png .*(160x90, moving, N 8 rotated, frame" "$T/out-frame.txt" ||
    fail "--move-estimator user: while moving the snapshot is not the half-size N 8 rotated frame"
echo "ok: --move-estimator user: while moving the frame is 160x90, N 8, rotated"
grep -q "total-moving.png .*(160x90, moving, split sum, frame" "$T/out-total.txt" ||
    fail "while moving the snapshot is not the half-size split-sum frame"
echo "ok: while moving the frame is 160x90, split sum (the default)"

# --benchmark: a steady orbit, timed from present to present; the report names its figures.
view_run "$SCENE" --size "$VIEW_TEST_SIZE" --benchmark 20
view_expect_exit0 "--benchmark"
grep -Eq "benchmark: 20 moving frames in a 320x180 window .* split sum: frame median [0-9.]+ ms, p90 [0-9.]+ ms, worst [0-9.]+ ms" \
    "$T/out.txt" || fail "--benchmark did not report its figures"
cat "$T/out.txt"
echo "ok: --benchmark reports median, p90 and worst frame times"
echo "PASS view_refine"
