#!/usr/bin/env bash
# plain.sh BUILD_DIR - the fast paths against the plain reference paths, end to end through
# `softlight render --plain` (per-pixel raster, the line-by-line port of lighting.frag): the
# G-buffers must be byte-identical (the span raster computes every value with the per-pixel
# expression), and the radiance may differ only by what the batched lighting path does
# differently (its own transcendentals, and its compact texels, each channel within 1/511.5 of
# the texel's max channel: src/ibl/texel_e5.h; test_lighting_fast bounds both per option): p99
# relative error at most 2.5e-3 (measured 1.9e-4 .. 1.3e-3; 1.6e-6 .. 7.8e-5 with float texels) and
# no pixel more than 1/255 apart after the tone map.
set -u
SL=${1:?usage: $0 BUILD_DIR}/softlight
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-plain.XXXXXX")
trap 'rm -rf "$T"' EXIT
fails=0; passes=0
for s in default bunny city-sun top-down grazing; do
    "$SL" render "scenes/$s.json" --size 240x136 -n 16 --pfm "$T/fast.pfm" --aov "$T/fast" -q &&
    "$SL" render "scenes/$s.json" --size 240x136 -n 16 --pfm "$T/plain.pfm" --aov "$T/plain" -q --plain || {
        echo "FAIL $s: render failed"; fails=$((fails + 1)); continue; }
    same=1
    for c in position normal kd ks alpha depth mask; do
        cmp -s "$T/fast/$c.pfm" "$T/plain/$c.pfm" || { echo "FAIL $s: $c.pfm differs between the span and per-pixel raster"; same=0; }
    done
    "$SL" compare "$T/fast.pfm" "$T/plain.pfm" --metric p99rel --tolerance 2.5e-3 >"$T/cmp.txt"
    status=$?
    share=$(awk '/^8-bit diff > 1 /{ v = $5; sub("%", "", v); print v }' "$T/cmp.txt")
    p99=$(awk '/^p99 rel error/{ print $4 }' "$T/cmp.txt")
    if [ "$same" -eq 1 ] && [ "$status" -eq 0 ] && awk -v s="$share" 'BEGIN { exit !(s == 0) }'; then
        echo "ok   $s: G-buffer identical; radiance p99 rel $p99, $share% of pixels > 1/255 apart"
        passes=$((passes + 1))
    else
        echo "FAIL $s: radiance p99 rel $p99 (max 2.5e-3), $share% > 1/255 apart (max 0)"
        sed 's/^/    /' "$T/cmp.txt"; fails=$((fails + 1))
    fi
done
echo "$passes passed, $fails failed"
[ "$fails" -eq 0 ]
