#!/usr/bin/env bash
# sun-shadows.sh - what the env lights' shadow maps (--shadows with --env-lights 32) cost: per
# frame, the lookups and the shading they change (the frame with maps against the frame with the
# same env lights and none), and once per scene and environment, drawing the orthographic maps.
#
#   bench/sun-shadows.sh [BUILD_DIR] [ROUNDS] [SIZE]    defaults: build 3 1280x720
#
# A frame's cost is CPU time on one thread (-j 1), as bench/shadows.sh measures it: user + system
# seconds of `render --repeat 4` less those of `render --repeat 1`, over 3 (the setup, the
# environment's mips, the env lights and the maps cancel). Each round runs every scene and
# setting in turn; the table gives the medians over the rounds, the maps' share of the frame that
# has them, and the maps' draw time as render prints it (wall, one thread).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
ROUNDS=${2:-3}
SIZE=${3:-1280x720}
T=$(mktemp -d "${TMPDIR:-/tmp}/sun-shadows.XXXXXX")
trap 'rm -rf "$T"' EXIT
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# cpu SCENE REPEAT OPTIONS...: user + system seconds of one render
cpu() {
    local s=$1 n=$2; shift 2
    /usr/bin/time -f "%U %S" -o "$T/time" "$BUILD/softlight" render "scenes/$s.json" --size "$SIZE" -j 1 "$@" \
        --repeat "$n" -o "$T/f.png" >"$T/out.txt"
    awk '{ print $1 + $2 }' "$T/time"
}
SCENES="pbr city-sun"
for _ in $(seq 1 "$ROUNDS"); do
    for s in $SCENES; do
        for setting in lights maps; do
            case $setting in
            lights) opts=(--env-lights 32) ;;
            maps) opts=(--env-lights 32 --shadows) ;;
            esac
            one=$(cpu "$s" 1 "${opts[@]}")
            four=$(cpu "$s" 4 "${opts[@]}")
            maps=$(awk '/env-light shadow maps/ { for (i = 1; i <= NF; i++) if ($i == "ms") m = $(i - 1) } END { print m + 0 }' "$T/out.txt")
            awk -v a="$one" -v b="$four" -v m="$maps" 'BEGIN { print 1000 * (b - a) / 3, m }' >>"$T/$s-$setting"
        done
    done
done
echo "| scene, $SIZE, CPU ms a frame on one thread | --env-lights 32 | with --shadows | maps' share | maps, once |"
echo "|---|---|---|---|---|"
for s in $SCENES; do
    a=$(awk '{ print $1 }' "$T/$s-lights" | median)
    b=$(awk '{ print $1 }' "$T/$s-maps" | median)
    m=$(awk '{ print $2 }' "$T/$s-maps" | median)
    awk -v s="$s" -v a="$a" -v b="$b" -v m="$m" 'BEGIN {
        printf "| %s.json | %.0f ms | %.0f ms | %.1f%% | %.0f ms |\n", s, a, b, 100 * (b - a) / b, m }'
done
echo "($(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end, $ROUNDS rounds, medians; bash bench/sun-shadows.sh $BUILD $ROUNDS $SIZE)"
