#!/usr/bin/env bash
# gl_mis.sh BUILD_DIR - --estimator mis: shaders/lighting.frag's specular_mis (OpenGL) against the
# C port, on softlight's G-buffer (--gbuffer), as gl_shading.sh does for the other sampling
# estimators. softlight-gl uploads softlight's own environment distribution (src/ibl/env_dist.h)
# as uEnvDist / uEnvDistMarginal, so both sides draw the same directions from the same CDFs and
# read the same level-0 texels; what differs is cos/sin/acos/atan and the float order of the
# weights, and a direction that lands on a texel edge may read the neighbour on one side.
# Scenes: ggx (GGX lobes r 0.1..1), city-sun (a small bright sun, rotation on), grazing (N.V near
# 0, the sun at the horizon), top-down with env lights (the distribution of the residual).
# Tolerances, gl_shading.sh's:
#   p99 of the per-pixel relative error (floor 1e-3)  <= P99_TOL
#   share of pixels more than 8/255 apart after the tone map <= OVER8_PERCENT
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"

P99_TOL=0.05
OVER8_PERCENT=0.1
fail=0
run() { # run NAME SCENE [options...]
    local name=$1 scene=$2
    shift 2
    gl_compare_estimator "$name" "$scene" mis "$P99_TOL" "$OVER8_PERCENT" "$@" || fail=1
}
run ggx scenes/ggx.json -n 16
run city-sun scenes/city-sun.json -n 16 --rotate --frame 2
run grazing scenes/grazing.json --specular-only -n 8
run top-env32 scenes/top-down.json --specular-only -n 8 --env-lights 32
# MIS must differ from the microfacet estimator (or GL ignored uEstimator 5).
mkdir -p "$T/mf"
"$GL" render scenes/ggx.json --estimator mf -n 16 --gbuffer "$T/ggx" --pfm "$T/mf/g.pfm" >/dev/null
if "$SL" compare "$T/ggx/g.pfm" "$T/mf/g.pfm" --metric p99rel --tolerance 1e-3 >/dev/null; then
    echo "FAIL: GL with --estimator mis equals GL with --estimator mf"
    fail=1
fi
exit $fail
