#!/usr/bin/env bash
# busy.sh - each stage of a frame at 1 and 2 threads, on an idle machine and beside one busy
# process, as a user's machine often is (a build, a browser).
#
#   bench/busy.sh [BUILD_DIR] [ROUNDS] [SCENE] [SIZE] [AO_RADIUS]
#                 defaults: build 7 scenes/default.json 1280x720 0 (AO_RADIUS > 0: with ambient
#                 occlusion, --ao-radius, and a row for its pass)
#
# Runs `softlight render SCENE --size SIZE -j T --repeat REPEAT` ROUNDS times for each (condition,
# T), alternating T = 1 and T = 2 within a round so that both see the same moments of the machine,
# and prints the median of each stage's time (raster, shading, tone map, as render reports them:
# each render's median over its REPEAT frames, default 3, so a steady frame as the viewer draws
# them and not a first frame's page faults) and the ratio
# 2 threads / 1 thread, and of the whole frame (the stages' sum). The busy process is a shell loop
# that spins one core for the whole condition. A stage whose ratio passes 1 beside the busy process
# is one whose parallel region waits for a descheduled thread. The tone map runs inside the
# lighting pass's region (each band tone mapped as soon as it is lit): its row is its share of
# that region, and its barrier is the shading's.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
ROUNDS=${2:-7}
SCENE=${3:-scenes/default.json}
SIZE=${4:-1280x720}
AO=${5:-0}
REPEAT=${REPEAT:-3}
export OMP_WAIT_POLICY=passive
T=$(mktemp -d "${TMPDIR:-/tmp}/busy.XXXXXX")
busy_pid=
cleanup() { [ -n "$busy_pid" ] && kill "$busy_pid" 2>/dev/null; rm -rf "$T"; }
trap cleanup EXIT
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print "nan"; else print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

run() { # run CONDITION THREADS: one render, its stage times appended to T/CONDITION-THREADS
    "$BUILD/softlight" render "$SCENE" --size "$SIZE" -j "$2" --ao-radius "$AO" --repeat "$REPEAT" -o "$T/frame.png" 2>&1 |
        awk '/raster/ { for (i = 1; i <= NF; i++) { if ($i == "raster") r = $(i + 1); if ($i == "shading") s = $(i + 1);
                                                    if ($i == "tone") t = $(i + 2) } }
             /ambient occlusion/ { for (i = 1; i <= NF; i++) if ($i == "ms") a = $(i - 1) }
             END { print r, s, t, a + 0, r + s + t + a }' >>"$T/$1-$2"
}

for condition in idle busy; do
    if [ "$condition" = busy ]; then
        bash -c 'while :; do :; done' &
        busy_pid=$!
    fi
    for ((r = 0; r < ROUNDS; r++)); do
        run "$condition" 1
        run "$condition" 2
    done
    if [ -n "$busy_pid" ]; then kill "$busy_pid"; wait "$busy_pid" 2>/dev/null || true; busy_pid=; fi
done

echo "$SCENE $SIZE, median of $ROUNDS renders each; $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg) after"
echo '| stage | idle, 1 thread ms | idle, 2 threads ms | ratio | busy, 1 thread ms | busy, 2 threads ms | ratio |'
echo '|---|---:|---:|---:|---:|---:|---:|'
stage=(raster shading "tone map" "ambient occlusion" "frame (all stages)")
columns="1 2 3 5"
awk -v a="$AO" 'BEGIN { exit !(a > 0) }' && columns="1 2 3 4 5"
for s in $columns; do
    row="| ${stage[$((s - 1))]}"
    for condition in idle busy; do
        a=$(awk -v c=$s '{ print $c }' "$T/$condition-1" | median)
        b=$(awk -v c=$s '{ print $c }' "$T/$condition-2" | median)
        row="$row | $a | $b | $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.2f", b / a }')"
    done
    echo "$row |"
done
