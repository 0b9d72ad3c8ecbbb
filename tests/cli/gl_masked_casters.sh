#!/usr/bin/env bash
# gl_masked_casters.sh BUILD_DIR - masked casters in OpenGL's shadow maps (shaders/shadow_depth.vert,
# shadow_depth.frag and shadow_sun.frag discard where the mask cuts the caster away, as
# src/shadow's depth programs do: src/raster/coverage.h). softlight-gl lights softlight's G-buffer
# (--gbuffer) with the maps GL drew:
# - masked_casters.bash's quad over a floor, by a point light (cube map) and by a sun (the env
#   lights' orthographic map): GL's images keep the floor lit through the cut-out half and dark
#   under the kept half, as masked_casters.sh asks of softlight's, and are within the gl_shading.sh
#   bounds (p99 relative error <= 0.05, share more than 8/255 apart <= 0.1%) of softlight's;
# - scenes/textured.json, whose leaf is alpha-masked, with --env-lights 32 --shadows --sky-maps 32,
#   within the same bounds (a GL that casts the leaf's whole quad: p99 0.115, outside).
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"
export PYTHONPATH=tests/cli
source tests/cli/masked_casters.bash
fail=0

mkdir -p "$T/aov"
"$SL" render "$T/point.json" --size "$GL_TEST_SIZE" --aov "$T/aov" --shadows --pfm "$T/cp.pfm" -q
"$SL" render "$T/sun.json" --size "$GL_TEST_SIZE" --env-lights 4 --shadows --pfm "$T/cs.pfm" -q
fates point "$T/aov"
fates sun "$T/aov"
"$GL" render "$T/point.json" --gbuffer "$T/aov" --pfm "$T/gp0.pfm"
"$GL" render "$T/point.json" --gbuffer "$T/aov" --shadows --pfm "$T/gp1.pfm"
"$GL" render "$T/sun.json" --gbuffer "$T/aov" --env-lights 4 --pfm "$T/gs0.pfm"
"$GL" render "$T/sun.json" --gbuffer "$T/aov" --env-lights 4 --shadows --pfm "$T/gs1.pfm"
for kind in point sun; do
    k=${kind:0:1}
    if line=$(judge "$kind" "$T/g${k}1.pfm" "$T/g${k}0.pfm"); then
        echo "ok   GL, $kind: $line"
    else
        echo "FAIL GL, $kind: $line"
        fail=1
    fi
    gl_within "masked $kind" "$T/c$k.pfm" "$T/g${k}1.pfm" || { echo "FAIL masked $kind: outside the bounds"; fail=1; }
done

O=(--no-lights --env-lights 32 --shadows --sky-maps 32 -n 16)
mkdir -p "$T/textured"
"$SL" render scenes/textured.json --size "$GL_TEST_SIZE" "${O[@]}" --aov "$T/textured" --pfm "$T/textured/c.pfm" -q
"$GL" render scenes/textured.json "${O[@]}" --gbuffer "$T/textured" --pfm "$T/textured/g.pfm"
gl_within "textured" "$T/textured/c.pfm" "$T/textured/g.pfm" || { echo "FAIL textured: outside the bounds"; fail=1; }
[ $fail = 0 ] && echo "PASS gl_masked_casters"
exit $fail
