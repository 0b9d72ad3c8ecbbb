#!/usr/bin/env bash
# occlusion.sh - what ambient occlusion (--ao-radius) costs in full: the occlusion pass and what
# it adds to the lighting (the cone's specular occlusion), on the shipped scenes that have
# something to occlude.
#
#   bench/occlusion.sh [BUILD_DIR] [ROUNDS] [SIZE] [RADIUS]    defaults: build 5 1280x720 0.5
#
# Each round renders every scene twice with --repeat 3 (render reports each stage's median of the
# three), once without --ao-radius and once with it, the order swapped from one round to the next
# so a drift in the machine's load falls on both. The table gives, per scene, the medians over the
# rounds of the frame (raster + occlusion + shading + tone map) without and with the occlusion,
# of the pass alone, of the shading stage's growth, and of the cost (frame with minus frame without: the pass and the shading
# it adds), and the cost's share of the frame with it. The default lighting (N = 40) is the
# frame's; a cheaper estimator makes the share larger.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
ROUNDS=${2:-5}
SIZE=${3:-1280x720}
RADIUS=${4:-0.5}
T=$(mktemp -d "${TMPDIR:-/tmp}/occlusion.XXXXXX")
trap 'rm -rf "$T"' EXIT
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# frame SCENE [ARGS...]: "frame pass shading" in ms, the frame the sum of the stages render reports
frame() {
    local s=$1
    shift
    "$BUILD/softlight" render "scenes/$s.json" --size "$SIZE" --repeat 3 -o "$T/f.png" "$@" |
        awk 'BEGIN { a = 0 }
             /raster/ { for (i = 1; i <= NF; i++) { if ($i == "raster") r = $(i + 1); if ($i == "shading") s = $(i + 1);
                                                    if ($i == "tone") t = $(i + 2) } }
             /ambient occlusion/ { for (i = 1; i <= NF; i++) if ($i == "ms") a = $(i - 1) }
             END { print r + s + t + a, a, s }'
}
SCENES="bunny pbr model default"
for round in $(seq 1 "$ROUNDS"); do
    for s in $SCENES; do
        if [ $((round % 2)) -eq 1 ]; then
            off=$(frame "$s")
            on=$(frame "$s" --ao-radius "$RADIUS")
        else
            on=$(frame "$s" --ao-radius "$RADIUS")
            off=$(frame "$s")
        fi
        read -r f0 _ s0 <<<"$off"
        echo "$f0 $on $s0" >>"$T/$s" # frame without, frame with, pass, shading with, shading without
    done
done
echo "| scene, $SIZE, radius $RADIUS | frame without | frame with | pass | shading added | cost (with - without) | share of the frame with |"
echo "|---|---|---|---|---|---|---|"
for s in $SCENES; do
    off=$(awk '{ print $1 }' "$T/$s" | median)
    on=$(awk '{ print $2 }' "$T/$s" | median)
    ao=$(awk '{ print $3 }' "$T/$s" | median)
    shade=$(awk '{ print $4 - $5 }' "$T/$s" | median)
    cost=$(awk '{ print $2 - $1 }' "$T/$s" | median)
    awk -v s="$s" -v f0="$off" -v f1="$on" -v a="$ao" -v sh="$shade" -v c="$cost" \
        'BEGIN { printf "| %s.json | %.1f ms | %.1f ms | %.1f ms | %.1f ms | %.1f ms | %.0f%% |\n", s, f0, f1, a, sh, c, 100 * c / f1 }'
done
echo "($(nproc) cores, $ROUNDS rounds, medians; bench/occlusion.sh $BUILD $ROUNDS $SIZE $RADIUS)"
