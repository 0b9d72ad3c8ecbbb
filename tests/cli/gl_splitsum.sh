#!/usr/bin/env bash
# gl_splitsum.sh BUILD_DIR - --estimator splitsum: shaders/lighting.frag's specular_splitsum
# (OpenGL) against the C port, on softlight's G-buffer (--gbuffer), as gl_shading.sh does for the
# sampling estimators. Both sides read the same prefiltered chains and the same table (softlight-gl
# uploads softlight's), so what differs is one trilinear fetch and one bilinear table read per
# pixel (llvmpipe's filtering weights) and atan/acos in sl_dir_to_uv: much less than N samples.
# Scenes: default (Phong, both G terms), ggx (the GGX chain and rows), grazing (N.V near 0, the
# table's first column). Tolerances, as gl_shading.sh's:
#   p99 of the per-pixel relative error (floor 1e-3)  <= P99_TOL
#   share of pixels more than 8/255 apart after the tone map <= OVER8_PERCENT
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"

P99_TOL=0.01
OVER8_PERCENT=0.1
fail=0
run() { # run NAME SCENE [options...]
    local name=$1 scene=$2
    shift 2
    gl_compare_estimator "$name" "$scene" splitsum "$P99_TOL" "$OVER8_PERCENT" "$@" || fail=1
}
run default scenes/default.json
run default-g-one scenes/default.json --g one
run ggx scenes/ggx.json
run grazing scenes/grazing.json --specular-only
# The split sum must differ from the sampled estimator (or GL ignored uEstimator).
mkdir -p "$T/spec"
"$GL" render scenes/default.json --gbuffer "$T/default" --pfm "$T/spec/g.pfm" >/dev/null
if "$SL" compare "$T/default/g.pfm" "$T/spec/g.pfm" --metric p99rel --tolerance 1e-3 >/dev/null; then
    echo "FAIL: GL with --estimator splitsum equals GL with the default estimator"
    fail=1
fi
exit $fail
