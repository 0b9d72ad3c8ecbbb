#!/usr/bin/env bash
# gl_cv.sh BUILD_DIR - --estimator cv and cvmis: shaders/lighting.frag's specular_cv and
# specular_cv with mis (OpenGL) against the C port, on softlight's G-buffer (--gbuffer), through
# gl_common.bash's gl_compare_estimator as gl_splitsum.sh and gl_mis.sh. cv is the chain's exact
# levels read along the lookup direction (the same chains and table on both sides, softlight-gl
# uploads softlight's; the Catmull-Rom read by texelFetch) plus the microfacet samples less the
# kernel's term, so what differs is the filtering's float order plus gl_shading.sh's per-sample
# trigonometry; cvmis takes the kernel's term off mis's pairs instead (gl_mis.sh). Scenes: default
# (Phong), ggx (the GGX chain), grazing (N.V near 0), top-down with env lights (the chain and the
# samples of the residual); ggx and top-down again with cvmis. Tolerances, gl_mis.sh's:
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
run() { # run NAME SCENE ESTIMATOR [options...]
    local name=$1 scene=$2 estimator=$3
    shift 3
    gl_compare_estimator "$name" "$scene" "$estimator" "$P99_TOL" "$OVER8_PERCENT" "$@" || fail=1
}
run default scenes/default.json cv -n 16 --lod pdf --distortion
run ggx scenes/ggx.json cv -n 16 --lod pdf --distortion
run grazing scenes/grazing.json cv --specular-only -n 8
run top-env32 scenes/top-down.json cv --specular-only -n 8 --env-lights 32
run ggx-cvmis scenes/ggx.json cvmis -n 16
run top-env32-cvmis scenes/top-down.json cvmis --specular-only -n 8 --env-lights 32
# cv must differ from the microfacet estimator (or GL ignored uEstimator 6).
mkdir -p "$T/mf"
"$GL" render scenes/default.json --estimator mf -n 16 --lod pdf --distortion --gbuffer "$T/default" --pfm "$T/mf/g.pfm" >/dev/null
if "$SL" compare "$T/default/g.pfm" "$T/mf/g.pfm" --metric p99rel --tolerance 1e-3 >/dev/null; then
    echo "FAIL: GL with --estimator cv equals GL with --estimator mf"
    fail=1
fi
exit $fail
