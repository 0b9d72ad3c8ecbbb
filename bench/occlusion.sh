#!/usr/bin/env bash
# occlusion.sh - what ambient occlusion (--ao-radius) costs: its share of the frame on the shipped
# scenes that have something to occlude.
#
#   bench/occlusion.sh [BUILD_DIR] [ROUNDS] [SIZE] [RADIUS]    defaults: build 5 1280x720 0.5
#
# Each round renders every scene once with --repeat 3 (render reports each stage's median of the
# three), and the table gives, per scene, the median over the rounds of the occlusion pass's time
# and of the whole frame's (raster + occlusion + shading + tone map), and the share. The default
# lighting (N = 40) is the frame's; a cheaper estimator makes the share larger.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
ROUNDS=${2:-5}
SIZE=${3:-1280x720}
RADIUS=${4:-0.5}
T=$(mktemp -d "${TMPDIR:-/tmp}/occlusion.XXXXXX")
trap 'rm -rf "$T"' EXIT
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
SCENES="bunny pbr model default"
for round in $(seq 1 "$ROUNDS"); do
    for s in $SCENES; do
        "$BUILD/softlight" render "scenes/$s.json" --size "$SIZE" --ao-radius "$RADIUS" --repeat 3 -o "$T/f.png" |
            awk '/raster/ { for (i = 1; i <= NF; i++) { if ($i == "raster") r = $(i + 1); if ($i == "shading") s = $(i + 1);
                                                        if ($i == "tone") t = $(i + 2) } }
                 /ambient occlusion/ { for (i = 1; i <= NF; i++) if ($i == "ms") a = $(i - 1) }
                 END { print r, s, t, a }' >>"$T/$s"
    done
done
echo "| scene, $SIZE, radius $RADIUS | occlusion | frame | share |"
echo "|---|---|---|---|"
for s in $SCENES; do
    ao=$(awk '{ print $4 }' "$T/$s" | median)
    frame=$(awk '{ print $1 + $2 + $3 + $4 }' "$T/$s" | median)
    awk -v s="$s" -v a="$ao" -v f="$frame" 'BEGIN { printf "| %s.json | %.1f ms | %.1f ms | %.0f%% |\n", s, a, f, 100 * a / f }'
done
echo "($(nproc) cores, $ROUNDS rounds, medians; bench/occlusion.sh $BUILD $ROUNDS $SIZE $RADIUS)"
