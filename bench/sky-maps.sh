#!/usr/bin/env bash
# sky-maps.sh - what the sky visibility maps (--sky-maps K, docs/lighting.md "Sky visibility
# maps") are worth and cost.
#
#   bash bench/sky-maps.sh errors [BUILD_DIR] [--scenes bunny,pbr,...]
#       per scene and setting, the nRMSE of the diffuse (--diffuse-only against --part diffuse) and
#       of the total against `softlight truth --visibility` at 80x45, image-based light only
#       (--no-lights), mf pdf+dist N256. The truths are cached in out/sky-maps/ (SCENE-vis.gt;
#       integrated on the first run, about 20 s each on 2 cores).
#   bash bench/sky-maps.sh cost [BUILD_DIR] [--other BUILD_DIR2] [--scenes bunny,pbr,city-sun]
#       CPU seconds (user + sys) of one 1280x720 frame on one thread, the scene's own settings,
#       without and with the maps: (--repeat 4 less --repeat 1) / 3, the median of 3 runs; and the
#       maps' one-off time (their cells' weights and draw) as `render` prints it. --other: a
#       second build (e.g. configured with -DCMAKE_C_FLAGS=-DSL_SKY_MAP_SIZE=256) measured with
#       --sky-maps 32 too.
#
# Prints markdown tables. About 3 minutes for errors, 10 for cost on 2 loaded cores.
set -euo pipefail
cd "$(dirname "$0")/.."
MODE=${1:?usage: bench/sky-maps.sh errors|cost [BUILD_DIR] [--scenes LIST] [--other BUILD_DIR2]}
shift
BUILD=build
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then BUILD=$1; shift; fi
OTHER=""
SCENES=""
while [ $# -gt 0 ]; do
    case $1 in
    --scenes) SCENES=$2; shift 2 ;;
    --other) OTHER=$2; shift 2 ;;
    *) echo "sky-maps.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
SL=$BUILD/softlight
TMP=$(mktemp -d "${TMPDIR:-/tmp}/sky-maps.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

if [ "$MODE" = errors ]; then
    SCENES=${SCENES:-bunny,pbr,model,textured,top-down,grazing,city-sun}
    BEST="--size 80x45 --no-lights --estimator mf --lod pdf --distortion -n 256 -q"
    SUN="--env-lights 32 --shadows"
    settings=("" "--ao-radius 1" "--sky-maps 32" "--sky-maps 32 --ao-radius 1" "--ao-radius 1 $SUN"
        "--sky-maps 32 --ao-radius 1 $SUN" "--sky-maps 16 --ao-radius 1" "--sky-maps 64 --ao-radius 1"
        "--sky-maps 64 --ao-radius 1 $SUN")
    mkdir -p out/sky-maps
    nrmse() { # SCENE PART RENDER.pfm
        "$SL" truth "scenes/$1.json" --size 80x45 --visibility --cache "out/sky-maps/$1-vis.gt" --part "$2" \
            --compare "$3" 2>/dev/null | sed -n 's/.*nrmse \([0-9.]*\),.*/\1/p'
    }
    echo "| scene | setting | diffuse nRMSE | total nRMSE |"
    echo "|---|---|---:|---:|"
    IFS=, read -r -a scenes <<<"$SCENES"
    for s in "${scenes[@]}"; do
        "$SL" truth "scenes/$s.json" --size 80x45 --visibility --cache "out/sky-maps/$s-vis.gt" >/dev/null 2>&1 ||
            { echo "sky-maps.sh: the visibility truth of $s failed" >&2; exit 2; }
        for set in "${settings[@]}"; do
            # shellcheck disable=SC2086
            "$SL" render "scenes/$s.json" $BEST $set --diffuse-only --pfm "$TMP/d.pfm"
            # shellcheck disable=SC2086
            "$SL" render "scenes/$s.json" $BEST $set --pfm "$TMP/t.pfm"
            echo "| $s | ${set:-none} | $(nrmse "$s" diffuse "$TMP/d.pfm") | $(nrmse "$s" total "$TMP/t.pfm") |"
        done
    done
elif [ "$MODE" = cost ]; then
    SCENES=${SCENES:-bunny,pbr,city-sun}
    cpu() { /usr/bin/time -f "%U %S" "$@" 2>&1 >/dev/null | tail -1 | awk '{print $1 + $2}'; }
    runs=("$BUILD|" "$BUILD|--sky-maps 16" "$BUILD|--sky-maps 32" "$BUILD|--sky-maps 64")
    [ -n "$OTHER" ] && runs+=("$OTHER|--sky-maps 32")
    echo "| scene | build | setting | CPU s a frame (median) | runs | maps' one-off ms |"
    echo "|---|---|---|---:|---|---:|"
    IFS=, read -r -a scenes <<<"$SCENES"
    for s in "${scenes[@]}"; do
        for run in "${runs[@]}"; do
            B=${run%%|*} o=${run#*|}
            vals=""
            for _ in 1 2 3; do
                # shellcheck disable=SC2086
                a=$(cpu "$B/softlight" render "scenes/$s.json" --size 1280x720 -j 1 --repeat 4 $o -q --pfm "$TMP/c.pfm")
                # shellcheck disable=SC2086
                b=$(cpu "$B/softlight" render "scenes/$s.json" --size 1280x720 -j 1 --repeat 1 $o -q --pfm "$TMP/c.pfm")
                vals="$vals $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.3f", (a - b) / 3 }')"
            done
            med=$(echo $vals | tr ' ' '\n' | sort -n | sed -n 2p)
            draw=-
            # shellcheck disable=SC2086
            [ -n "$o" ] && draw=$("$B/softlight" render "scenes/$s.json" --size 1280x720 -j 1 $o --pfm "$TMP/c.pfm" |
                sed -n 's/^sky visibility maps:.*drawn in \([0-9.]*\) ms.*/\1/p')
            echo "| $s | $B | ${o:-none} | $med | $vals | $draw |"
        done
    done
else
    echo "sky-maps.sh: unknown mode $MODE (errors, cost)" >&2
    exit 2
fi
