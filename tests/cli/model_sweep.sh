#!/usr/bin/env bash
# model_sweep.sh BUILD_DIR - scripts/model-sweep.sh on a small folder made here: a model that
# renders, one refused in one line, one whose only triangle has no area (an empty picture, with
# the warning), and files that are no models (an image, a text, an .mtl), which it skips. Its
# TSV has a row per model with the status, the error lines and the coverage, its summary the
# counts, and its exit status is 0 when nothing broke the promise.
set -u
. "$(dirname "$0")/lib.bash"
cli_init model_sweep "$@"
build=$(cd "${1:?}" && pwd)
models="$T/models"
mkdir -p "$models/sub"
printf 'v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 2 3 4\n' >"$models/quad.obj"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n' >"$models/sub/range.off"
printf 'v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n' >"$models/line.obj"
cp scenes/textures/tiles.png "$models/tiles.png"
printf 'notes\n' >"$models/notes.txt"
printf 'newmtl m\nKd 1 1 1\n' >"$models/m.mtl"

SWEEP_JOBS=2 bash scripts/model-sweep.sh "$build" "$models" "$T/out" >"$T/summary" 2>"$T/log"
status=$?
tsv="$T/out/sweep.tsv"
[ "$status" -eq 0 ] && ok "exit status 0" || bad "exit status $status: $(cat "$T/log" "$T/summary")"
rows=$(($(wc -l <"$tsv") - 1))
[ "$rows" -eq 3 ] && ok "three models, the rest skipped" || bad "$rows rows: $(cut -f2 "$tsv")"

# row NAME: the TSV row of the model whose path ends in NAME.
row() { awk -F'\t' -v n="$1" 'NR > 1 && substr($2, length($2) - length(n) + 1) == n' "$tsv"; }
IFS=$'\t' read -r _ _ st lines _ rss covered left warned san first <<<"$(row quad.obj)"
if [ "$st" = 0 ] && [ "$covered" -gt 0 ] && [ "$left" = 0 ] && [ "$warned" = 0 ] && [ "$san" = 0 ] && [ "$rss" -gt 0 ]; then
    ok "quad.obj: rendered, $covered pixels covered, ${rss} MiB"
else
    bad "quad.obj: $(row quad.obj)"
fi
IFS=$'\t' read -r _ _ st lines _ _ covered left _ _ first <<<"$(row range.off)"
if [ "$st" = 2 ] && [ "$lines" = 1 ] && [ "$covered" = -1 ] && [ "$left" = 0 ] && [[ "$first" == *"out of range"* ]]; then
    ok "range.off: refused in one line"
else
    bad "range.off: $(row range.off)"
fi
IFS=$'\t' read -r _ _ st _ _ _ covered _ warned _ _ <<<"$(row line.obj)"
[ "$st" = 0 ] && [ "$covered" = 0 ] && [ "$warned" = 1 ] && ok "line.obj: empty, with the warning" ||
    bad "line.obj: $(row line.obj)"
grep -qE '^rendered \(exit 0\) +2$' "$T/summary" && grep -qE '^  of them empty, with the warning +1$' "$T/summary" &&
    grep -qE '^refused in one line \(exit 2, 1 line\) +1$' "$T/summary" && ok "the summary's counts" ||
    bad "summary: $(cat "$T/summary")"

cli_done model_sweep
