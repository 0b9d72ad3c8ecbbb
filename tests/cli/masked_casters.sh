#!/usr/bin/env bash
# masked_casters.sh BUILD_DIR - a masked material casts where its mask keeps it, in the shadow
# maps and in the visibility-aware truth (src/raster/coverage.h): a 2x2 quad 1 above a floor,
# its kd_map's alpha 0 over u < 1/2 and 1 over the rest (alpha_cutoff 0.5), lit by a point light
# with its cube map (--shadows) under a black sky, and by a sun of a black sky through the env
# lights' orthographic map (--env-lights 4 --shadows). Each floor pixel (from the AOV positions)
# whose ray to the light crosses the quad's plane inside the quad, away from its edges and the
# mask's, is classed by the half it crosses: through the cut-out half the floor stays lit (the
# image with the maps over the one without at least 0.9), under the kept half it is shadowed (at
# most 0.1), in at least 97% of each set's pixels; and the same for `softlight truth --visibility`
# (Embree, its filter reading the mask) against the blind truth. A mask that cast as its whole
# quad would shadow the cut-out half's set too and fail every check.
set -u
. "$(dirname "$0")/lib.bash"
cli_init masked_casters "$1"
S=160x90
export PYTHONPATH="$(dirname "$0")"
. "$(dirname "$0")/masked_casters.bash"

"$SL" render "$T/point.json" --size $S -q --aov "$T/aov" --pfm "$T/p0.pfm"
fates point "$T/aov"
"$SL" render "$T/point.json" --size $S -q --shadows --pfm "$T/p1.pfm"
line=$(judge point "$T/p1.pfm" "$T/p0.pfm") && ok "point light, cube map: $line" || bad "point light, cube map: $line"
"$SL" render "$T/sun.json" --size $S -q --env-lights 4 --pfm "$T/s0.pfm"
fates sun "$T/aov"
"$SL" render "$T/sun.json" --size $S -q --env-lights 4 --shadows --pfm "$T/s1.pfm"
line=$(judge sun "$T/s1.pfm" "$T/s0.pfm") && ok "sun, orthographic map: $line" || bad "sun, orthographic map: $line"

if "$SL" truth "$T/sun.json" --size 2x2 --visibility --pfm "$T/probe.pfm" >/dev/null 2>&1; then
    "$SL" truth "$T/point.json" --size $S --lights --pfm "$T/tp0.pfm" >/dev/null 2>&1
    "$SL" truth "$T/point.json" --size $S --lights --visibility --vis-level 0 --pfm "$T/tp1.pfm" >/dev/null 2>&1
    line=$(judge point "$T/tp1.pfm" "$T/tp0.pfm") && ok "point light, truth: $line" || bad "point light, truth: $line"
    "$SL" truth "$T/sun.json" --size $S --pfm "$T/ts0.pfm" >/dev/null 2>&1
    "$SL" truth "$T/sun.json" --size $S --visibility --vis-level 0 --pfm "$T/ts1.pfm" >/dev/null 2>&1
    line=$(judge sun "$T/ts1.pfm" "$T/ts0.pfm") && ok "sun, truth: $line" || bad "sun, truth: $line"
else
    echo "skip the truth: a build without Embree"
fi
cli_done masked_casters
