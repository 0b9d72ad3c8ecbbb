#!/usr/bin/env bash
# mis-front.sh - the MIS estimator's speed against error front (docs/accuracy.md "MIS"): the
# recipe (spec N40), the best microfacet settings at its cost (mf pdf+dist N32, and N16 with 64
# env lights or with those worth their cost, `auto`, which GGX scenes get by default, both also at
# the scenes' own N 40) and --estimator mis
# over N, alone and with 32 env lights, on shipped scenes and on environments that are not in the
# repository, which bench/check_environments.py writes into a temporary directory: a sun of 5e4 on
# a few texels in a dark sky, four small lamps (2e3..1e4) at night, a sun of 1e5 two degrees above
# the horizon (1024x512 PFM each).
#
#   bench/mis-front.sh [BUILD_DIR] [SCENE:SIZE ...]
#   MIS_FRONT_ONLY='^(spec|mf|cv|splitsum)' MIS_FRONT_MD=docs/accuracy/cv-front.md bench/mis-front.sh build ...
#
# The split sum and --estimator cv (its control variate, docs/lighting.md "Control variate") are
# on the front too, cv at the microfacet settings above and with lod none (the samples unfiltered,
# beside mf with lod none).
#
# Per scene: the ground truth (`softlight truth`, cached by content in out/ground-truth/mis/),
# then bench_mis_front's lighting CPU time (1 thread, median of 7 interleaved frames) and
# `softlight truth --compare` of each variant: nRMSE and the shares of pixels more than 1/255
# and 8/255 off after the scene's tone map (total radiance, point lights off). Writes the table
# to docs/accuracy/mis-front.md (bench/speed-vs-error.sh appends docs/accuracy/mis.md, the section
# that reads it, and the table to docs/accuracy.md) and rewrites that section's table at a glance
# (bench/mis_glance.py). The default list takes about half an hour on the 2-core machine, most of
# it the ground truth (the grazing scenes' a few minutes each); later runs reuse the cache.
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/cpu_frame.bash # vector_isa
source bench/front_rows.bash
build=${1:-build}
[ $# -gt 0 ] && shift
SL=$build/softlight
BENCH=$build/bench_mis_front
[ -x "$BENCH" ] || { echo "mis-front: $BENCH not found: build first" >&2; exit 2; }
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-mis-front.XXXXXX")
trap 'rm -rf "$T"' EXIT
cache=out/ground-truth/mis
mkdir -p "$cache" docs/accuracy

python3 bench/check_environments.py "$T"

scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(ggx:320x180 default:320x180 ggx-sun:320x180 ggx-night:320x180 ggx-horizon:320x180
    default-sun:192x108 default-night:192x108 grazing-horizon:192x108 city-sun:192x108 default-horizon:192x108
    grazing:192x108)
V=("spec-N40|spec|spec-d4|0|40" "mf-pdf+dist-N32|mf|pdf|1|32" "mf-pdf+dist+env64-N16|mf|pdf|1|16|64"
   "mf-pdf+dist+envauto-N16|mf|pdf|1|16|auto" "mf-pdf+dist+envauto-N40|mf|pdf|1|40|auto"
   "mis-N8|mis|none|0|8" "mis-N16|mis|none|0|16" "mis+env32-N16|mis|none|0|16|32" "mis-N24|mis|none|0|24"
   "mis-N40|mis|none|0|40" "mis+env32-N40|mis|none|0|40|32" "mis-N64|mis|none|0|64" "mis-N256|mis|none|0|256"
   "mis-N1024|mis|none|0|1024" "splitsum|splitsum|none|0|1" "mf-pdf+dist-N16|mf|pdf|1|16" "cv-pdf+dist-N16|cv|pdf|1|16"
   "cv-pdf+dist-N32|cv|pdf|1|32" "cv-pdf+dist+env8-N8|cv|pdf|1|8|8" "cv-pdf+dist+env8-N16|cv|pdf|1|16|8" "mf-pdf+dist+env64-N32|mf|pdf|1|32|64" "mf-pdf+dist+env64-N40|mf|pdf|1|40|64" "cv-pdf+dist+env64-N16|cv|pdf|1|16|64"
   "cv-pdf+dist+env64-N32|cv|pdf|1|32|64" "cv-none-N64|cv|none|0|64" "mf-none-N64|mf|none|0|64"
   "cvmis-N12|cvmis|none|0|12" "cvmis-N16|cvmis|none|0|16" "cvmis-N24|cvmis|none|0|24" "cvmis-N32|cvmis|none|0|32"
   "cvmis+env64-N16|cvmis|none|0|16|64")
# MIS_FRONT_ONLY=REGEX: only the variants whose name matches (a partial run); MIS_FRONT_MD=FILE:
# the table's file (a partial run writes its own, not the whole front's)
if [ -n "${MIS_FRONT_ONLY:-}" ]; then
    keep=()
    for v in "${V[@]}"; do [[ ${v%%|*} =~ $MIS_FRONT_ONLY ]] && keep+=("$v"); done
    V=("${keep[@]}")
fi
md=${MIS_FRONT_MD:-docs/accuracy/mis-front.md}
front_table_head bench/mis-front.sh "$md"
for entry in "${scenes[@]}"; do
    name=${entry%%:*} size=${entry#*:}
    scene=scenes/$name.json
    [ -f "$scene" ] || scene=$T/$name.json
    front_rows "$SL" "$BENCH" "$name" "$scene" "$size" "$cache/$name-$size.gt" "$T/$name" "$md" "${V[@]}"
done
echo "mis-front: table in $md" >&2
# the MIS section's table at a glance (docs/accuracy/mis.md), from the default table
if [ "$md" = docs/accuracy/mis-front.md ]; then
    python3 bench/mis_glance.py "$md" docs/accuracy/mis.md
fi
