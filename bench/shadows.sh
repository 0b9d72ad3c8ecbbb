#!/usr/bin/env bash
# shadows.sh - what the point lights' shadow maps (--shadows) cost: per frame, the lookups in the
# lighting (the frame with shadows against the frame without), and once per scene, drawing the
# cube maps; with ambient occlusion beside them, the share of the frame the two take together.
#
#   bench/shadows.sh [BUILD_DIR] [ROUNDS] [SIZE]    defaults: build 5 1280x720
#
# Each round renders every scene once per setting (none, --shadows, --ao-radius 0.5, both), in
# that order, with --repeat 3 (render reports each stage's median of the three); the table gives
# per scene the medians over the rounds of the frame (raster + occlusion + shading + tone map),
# the shadows' share of the frame that has them, the share of shadows and occlusion together, and
# the maps' draw time. The scenes are the shipped ones with point lights.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
ROUNDS=${2:-5}
SIZE=${3:-1280x720}
T=$(mktemp -d "${TMPDIR:-/tmp}/shadows.XXXXXX")
trap 'rm -rf "$T"' EXIT
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
SCENES="bunny ggx lamp"
for _ in $(seq 1 "$ROUNDS"); do
    for s in $SCENES; do
        for setting in none shadows ao both; do
            case $setting in
            none) opts=() ;;
            shadows) opts=(--shadows) ;;
            ao) opts=(--ao-radius 0.5) ;;
            both) opts=(--shadows --ao-radius 0.5) ;;
            esac
            "$BUILD/softlight" render "scenes/$s.json" --size "$SIZE" "${opts[@]}" --repeat 3 -o "$T/f.png" |
                awk '/raster/ { for (i = 1; i <= NF; i++) { if ($i == "raster") r = $(i + 1); if ($i == "shading") s = $(i + 1);
                                                            if ($i == "tone") t = $(i + 2) } }
                     /ambient occlusion/ { for (i = 1; i <= NF; i++) if ($i == "ms") a = $(i - 1) }
                     /shadow maps/ { for (i = 1; i <= NF; i++) if ($i == "ms") m = $(i - 1) }
                     END { print r + s + t + a, m + 0 }' >>"$T/$s-$setting"
        done
    done
done
echo "| scene, $SIZE | frame | with --shadows | shadows' share | with --ao-radius 0.5 | with both | share of both | maps, once per scene |"
echo "|---|---|---|---|---|---|---|---|"
for s in $SCENES; do
    none=$(awk '{ print $1 }' "$T/$s-none" | median)
    sh=$(awk '{ print $1 }' "$T/$s-shadows" | median)
    ao=$(awk '{ print $1 }' "$T/$s-ao" | median)
    both=$(awk '{ print $1 }' "$T/$s-both" | median)
    maps=$(awk '{ print $2 }' "$T/$s-shadows" | median)
    awk -v s="$s" -v n="$none" -v h="$sh" -v a="$ao" -v b="$both" -v m="$maps" 'BEGIN {
        printf "| %s.json | %.1f ms | %.1f ms | %.0f%% | %.1f ms | %.1f ms | %.0f%% | %.1f ms |\n",
               s, n, h, 100 * (h - n) / h, a, b, 100 * (b - n) / b, m }'
done
echo "($(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg), $ROUNDS rounds, medians; bench/shadows.sh $BUILD $ROUNDS $SIZE)"
