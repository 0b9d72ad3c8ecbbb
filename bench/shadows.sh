#!/usr/bin/env bash
# shadows.sh - what shadows and occlusion cost: the shadow maps (--shadows) of the point lights
# and of the env lights (--env-lights 32: the environment's brightest texels, a sun), per frame
# (the lookups and the shading they change) and once per scene (drawing the maps); the ambient
# occlusion (--ao-radius 0.5); and the share of the frame the two take together.
#
#   bench/shadows.sh [BUILD_DIR] [ROUNDS] [SIZE]    defaults: build 3 1280x720
#
# Scenes: the shipped ones with point lights (bunny, ggx, lamp: their lights' cube maps; ggx is
# GGX, whose default takes no env lights under its studio map) and two with a sun or bright lamps in the environment
# (pbr, city-sun: every frame with --env-lights 32, the setting the maps need, so the frame
# without maps has the same env lights). The "maps of" column is what render reports drawing.
# A frame's cost is CPU time on one thread (-j 1: no OpenMP spinning counted), which a loaded
# machine inflates far less than wall time: per scene and setting (none, --shadows,
# --ao-radius 0.5, both), user + system seconds of `render --repeat 4` less those of
# `render --repeat 1`, over 3 (the setup, the environment's mips, the env lights and the maps
# cancel). Each round runs every scene and setting in that order; the table gives the medians over
# the rounds, the shadows' share of the frame that has them, the share of shadows and occlusion
# together, and the maps' draw time as render prints it (wall).
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/cpu_frame.bash
frame_bench_args shadows "$@"
# base SCENE: the options every frame of the scene has
base() { case $1 in pbr | city-sun) echo "--env-lights 32" ;; esac; }
SCENES="bunny ggx lamp pbr city-sun"
for _ in $(seq 1 "$ROUNDS"); do
    for s in $SCENES; do
        for setting in none shadows ao both; do
            read -r -a opts <<<"$(base "$s")"
            case $setting in
            shadows) opts+=(--shadows) ;;
            ao) opts+=(--ao-radius 0.5) ;;
            both) opts+=(--shadows --ao-radius 0.5) ;;
            esac
            one=$(cpu "$s" 1 "${opts[@]}")
            four=$(cpu "$s" 4 "${opts[@]}")
            # both kinds of maps print a line "... shadow maps ... N ms ..."
            maps=$(awk '/shadow maps/ { for (i = 1; i <= NF; i++) if ($i == "ms") m += $(i - 1) } END { print m + 0 }' "$T/out.txt")
            awk -v a="$one" -v b="$four" -v m="$maps" 'BEGIN { print 1000 * (b - a) / 3, m }' >>"$T/$s-$setting"
            # which maps the frame has: render's lines name them
            [ "$setting" = shadows ] &&
                awk '/^shadow maps/ { k = k (k ? " and " : "") "point lights (" $3 " cube" ($3 == 1 ? "" : "s") ")" }
                     /^env-light shadow maps: [0-9]/ { k = k (k ? " and " : "") "env lights (" $4 " map" ($4 == 1 ? "" : "s") ")" }
                     END { print k }' "$T/out.txt" >"$T/$s-kind"
        done
    done
done
echo "| scene, $SIZE, CPU ms a frame on one thread | maps of | frame | with --shadows | shadows' share | with --ao-radius 0.5 | with both | share of both | maps, once per scene |"
echo "|---|---|---|---|---|---|---|---|---|"
for s in $SCENES; do
    none=$(awk '{ print $1 }' "$T/$s-none" | median)
    sh=$(awk '{ print $1 }' "$T/$s-shadows" | median)
    ao=$(awk '{ print $1 }' "$T/$s-ao" | median)
    both=$(awk '{ print $1 }' "$T/$s-both" | median)
    maps=$(awk '{ print $2 }' "$T/$s-shadows" | median)
    kind=$(cat "$T/$s-kind")
    awk -v s="$s" -v k="$kind" -v n="$none" -v h="$sh" -v a="$ao" -v b="$both" -v m="$maps" 'BEGIN {
        printf "| %s.json | %s | %.0f ms | %.0f ms | %.1f%% | %.0f ms | %.0f ms | %.1f%% | %.0f ms |\n",
               s, k, n, h, 100 * (h - n) / h, a, b, 100 * (b - n) / b, m }'
done
echo "($(nproc) cores, $(vector_isa), load average $(cut -d' ' -f1-3 /proc/loadavg) at the end, $ROUNDS rounds, medians; bash bench/shadows.sh $BUILD $ROUNDS $SIZE)"
