#!/usr/bin/env bash
# vs-gl.sh - softlight against softlight-gl (the same scene through OpenGL; Mesa llvmpipe where
# there is no GPU), stage by stage, on every shipped scene.
#
#   bench/vs-gl.sh [BUILD_DIR] [ROUNDS] [FRAMES] [SCENE.json ...]
#     BUILD_DIR  where softlight and softlight-gl are (default build)
#     ROUNDS     alternating rounds per scene (default 5); the order C, GL / GL, C alternates
#     FRAMES     frames per run: `softlight render --repeat FRAMES` and `softlight-gl render
#                --time FRAMES` each report per-stage medians (default 5)
#     SCENE      scenes (default scenes/*.json)
#
# Each program runs the scene at its own size and N. Stages compared:
#   G-buffer   softlight raster         vs  softlight-gl gbuffer pass
#   lighting   softlight shading        vs  softlight-gl lighting pass (shaders/lighting.frag,
#              compiled for the scene's options and features: docs/gl.md "One program per scene";
#              SL_GL_GENERAL=1 in the environment times the general shader instead)
#   frame      raster + shading + tone map  vs  gbuffer + lighting (GL's tone map is not timed
#              separately by softlight-gl; it is left out, which favours GL)
# Printed per scene: the median over rounds of each program's per-run medians, and the median of
# the per-round ratios C/GL (below 1: softlight is faster). The machine is shared: only ratios
# measured in the same round mean anything, hence the alternation. OMP_WAIT_POLICY=passive is set
# for softlight (docs/performance.md: spinning OpenMP threads on a loaded machine hurt).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
ROUNDS=${2:-5}
FRAMES=${3:-5}
shift $(($# < 3 ? $# : 3))
SCENES=("$@")
[ ${#SCENES[@]} -gt 0 ] || SCENES=(scenes/*.json)
SL=$BUILD/softlight
GL=$BUILD/softlight-gl
for p in "$SL" "$GL"; do
    [ -x "$p" ] || { echo "vs-gl.sh: $p not built" >&2; exit 1; }
done
T=$(mktemp -d "${TMPDIR:-/tmp}/vs-gl.XXXXXX")
trap 'rm -rf "$T"' EXIT

# run_c SCENE -> "raster shading tonemap" (ms)
run_c() {
    OMP_WAIT_POLICY=passive "$SL" render "$1" --repeat "$FRAMES" -o "$T/c.png" | head -1 |
        sed -E 's/.*raster ([0-9.]+) ms, shading ([0-9.]+) ms, tone map ([0-9.]+) ms.*/\1 \2 \3/'
}
# run_gl SCENE -> "gbuffer lighting" (ms)
run_gl() {
    "$GL" render "$1" --time "$FRAMES" -o "$T/g.png" | grep '^time:' |
        sed -E 's/.*gbuffer ([0-9.]+) ms, lighting ([0-9.]+) ms.*/\1 \2/'
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

printf 'softlight vs softlight-gl (%s), %d rounds x %d frames, medians; ratio = C / GL\n' \
    "$("$GL" info 2>/dev/null | head -1 | sed 's/GL_RENDERER: //')" "$ROUNDS" "$FRAMES"
printf '%-10s | %9s %9s %6s | %9s %9s %6s | %9s %9s %6s\n' scene "C raster" "GL gbuf" ratio \
    "C light" "GL light" ratio "C frame" "GL frame" ratio
for scene in "${SCENES[@]}"; do
    : >"$T/rows"
    for ((r = 0; r < ROUNDS; r++)); do
        if ((r % 2 == 0)); then
            c=$(run_c "$scene")
            g=$(run_gl "$scene")
        else
            g=$(run_gl "$scene")
            c=$(run_c "$scene")
        fi
        echo "$c $g" >>"$T/rows" # raster shading tonemap gbuffer lighting
    done
    col() { awk -v e="$1" '{ print '"$2"' }' "$T/rows" | median; }
    printf '%-10s | %9.1f %9.1f %6.2f | %9.1f %9.1f %6.2f | %9.1f %9.1f %6.2f\n' "$(basename "$scene" .json)" \
        "$(col 0 '$1')" "$(col 0 '$4')" "$(col 0 '$1 / $4')" \
        "$(col 0 '$2')" "$(col 0 '$5')" "$(col 0 '$2 / $5')" \
        "$(col 0 '$1 + $2 + $3')" "$(col 0 '$4 + $5')" "$(col 0 '($1 + $2 + $3) / ($4 + $5)')"
done
