#!/usr/bin/env bash
# gl_shading.sh BUILD_DIR - shading alone: shaders/lighting.frag (OpenGL) against its C port.
#
# softlight renders each shipped scene and writes its G-buffer (--aov); softlight-gl lights that
# very G-buffer (--gbuffer), so rasterization is out of the picture and both sides get the same
# uniforms from the same C code. What is left is how the two evaluate the same shader:
#   - float ordering (GLSL compilers reassociate and fuse multiply-adds; the C is -ffp-contract=off)
#   - transcendental precision: llvmpipe's pow/exp2/log2/atan/acos are polynomial approximations
#     (relative errors around 1e-6 .. 1e-5); pow(N.H, alpha) multiplies log2's error by alpha (up
#     to 10000 in the material chart), and atan/acos move a sample's texel position by up to
#     ~1e-4 radians, which near a sharp, bright feature (a sun at 30000) changes that sample a lot;
#   - texture filtering arithmetic (llvmpipe's bilinear weights and lod fraction).
# Averaged over N samples this leaves ~0.1% typical and a few % worst-case per pixel (measured on
# the shipped scenes at 320x180, see docs/gl.md). Tolerances:
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
for scene in scenes/*.json; do
    name=$(basename "$scene" .json)
    mkdir -p "$T/$name"
    "$SL" render "$scene" --size "$GL_TEST_SIZE" --aov "$T/$name" --pfm "$T/$name/c.pfm" >/dev/null
    "$GL" render "$scene" --gbuffer "$T/$name" --pfm "$T/$name/g.pfm" >/dev/null
    status=0
    "$SL" compare "$T/$name/c.pfm" "$T/$name/g.pfm" --metric p99rel --tolerance "$P99_TOL" >"$T/$name.txt" || status=$?
    printf '%-10s p99 rel %-10s mean rel %-10s max abs %-10s >1/255 %s%%  >8/255 %s%%\n' "$name" \
        "$(gl_field "p99 rel error" "$T/$name.txt")" "$(gl_field "mean rel error" "$T/$name.txt")" \
        "$(gl_field "max abs error" "$T/$name.txt")" "$(gl_field "8-bit diff > 1" "$T/$name.txt")" \
        "$(gl_field "8-bit diff > 8" "$T/$name.txt")"
    if [ "$status" != 0 ]; then
        echo "FAIL $name: $(grep -E '^(PASS|FAIL)' "$T/$name.txt")"
        grep '^worst' "$T/$name.txt" || true
        fail=1
    fi
    gl_check_share "$name" "$T/$name.txt" "$OVER8_PERCENT" || fail=1
done
# Rotation on (lighting.frag uRotate, uFrame: the per-pixel hash in GLSL uint and C uint32_t):
# the default scene at frame 7 must agree as well, and must differ from rotation off (or GL
# ignored the uniforms, or the two hashes differ).
mkdir -p "$T/rotate"
"$SL" render scenes/default.json --size "$GL_TEST_SIZE" --rotate --frame 7 --aov "$T/rotate" --pfm "$T/rotate/c.pfm" >/dev/null
"$GL" render scenes/default.json --rotate --frame 7 --gbuffer "$T/rotate" --pfm "$T/rotate/g.pfm" >/dev/null
status=0
"$SL" compare "$T/rotate/c.pfm" "$T/rotate/g.pfm" --metric p99rel --tolerance "$P99_TOL" >"$T/rotate.txt" || status=$?
printf '%-10s p99 rel %-10s mean rel %s\n' "rotate" "$(gl_field "p99 rel error" "$T/rotate.txt")" \
    "$(gl_field "mean rel error" "$T/rotate.txt")"
if [ "$status" != 0 ]; then
    echo "FAIL rotate: $(grep -E '^(PASS|FAIL)' "$T/rotate.txt")"
    fail=1
fi
gl_check_share rotate "$T/rotate.txt" "$OVER8_PERCENT" || fail=1
if "$SL" compare "$T/default/g.pfm" "$T/rotate/g.pfm" --metric p99rel --tolerance 1e-3 >/dev/null; then
    echo "FAIL rotate: GL with --rotate --frame 7 equals GL without rotation"
    fail=1
fi
# The microfacet estimator (lighting.frag uEstimator = 3, specular_microfacet; C: lighting.c):
# the default scene with the default mip rule, and the city's sun with GPU Gems' rule, the
# distortion and rotation on. GL must agree, and must differ from the spec estimator (or GL
# ignored uEstimator).
mf_run() { # name, scene, options...
    local name=$1 scene=$2
    shift 2
    mkdir -p "$T/$name"
    "$SL" render "scenes/$scene.json" --size "$GL_TEST_SIZE" "$@" --aov "$T/$name" --pfm "$T/$name/c.pfm" >/dev/null
    "$GL" render "scenes/$scene.json" "$@" --gbuffer "$T/$name" --pfm "$T/$name/g.pfm" >/dev/null
    local status=0
    "$SL" compare "$T/$name/c.pfm" "$T/$name/g.pfm" --metric p99rel --tolerance "$P99_TOL" >"$T/$name.txt" || status=$?
    printf '%-10s p99 rel %-10s mean rel %s\n' "$name" "$(gl_field "p99 rel error" "$T/$name.txt")" \
        "$(gl_field "mean rel error" "$T/$name.txt")"
    if [ "$status" != 0 ]; then
        echo "FAIL $name: $(grep -E '^(PASS|FAIL)' "$T/$name.txt")"
        fail=1
    fi
    gl_check_share "$name" "$T/$name.txt" "$OVER8_PERCENT" || fail=1
}
mf_run mf-default default --estimator mf
mf_run mf-sun city-sun --estimator mf --lod gems --distortion --rotate --frame 3
# The pdf mip rule (uLodRule = 5: Gems' level without its +1), on the same sun, otherwise the
# run above: GL must agree, and must differ from gems (or GL treated 5 as gems).
mf_run mf-pdf city-sun --estimator mf --lod pdf --distortion --rotate --frame 3
if "$SL" compare "$T/mf-sun/g.pfm" "$T/mf-pdf/g.pfm" --metric p99rel --tolerance 1e-3 >/dev/null; then
    echo "FAIL mf-pdf: GL with --lod pdf equals GL with --lod gems"
    fail=1
fi
if "$SL" compare "$T/default/g.pfm" "$T/mf-default/g.pfm" --metric p99rel --tolerance 1e-3 >/dev/null; then
    echo "FAIL mf: GL with --estimator mf equals GL with the spec estimator"
    fail=1
fi
# Irradiance layouts (lighting.frag irradiance(): uIrradianceMethod 3 = octahedral, the default
# every run above uses, 4 = dual paraboloid, 0 = SH9, 1 = the lat-long brute map), diffuse only so
# the map is all there is: on the floor (N = +Z, the lat-long pole) under grazing.json's low sun,
# and on the bunny. GL must agree on each, and the layouts must differ from each other (or GL
# ignored uIrradianceMethod).
for irr in oct dp sh9 brute; do
    mf_run "irr-$irr" grazing --diffuse-only --irradiance "$irr"
done
mf_run irr-dp-bunny bunny --diffuse-only --irradiance dp
for irr in dp sh9 brute; do
    if "$SL" compare "$T/irr-oct/g.pfm" "$T/irr-$irr/g.pfm" --metric p99rel --tolerance 1e-6 >/dev/null; then
        echo "FAIL irr-$irr: GL with --irradiance $irr equals GL with oct"
        fail=1
    fi
done
# The octahedral specular chain (lighting.frag uEnvLayout = 2, env_lod's texelFetch filter with
# the fold at the edge; C: texture_lod.h sl_oct_*): the mirror floor and spheres looking straight
# down (R = +Z, the lat-long pole) at level 0 (--lod none) and with the default lod rule, so every
# level of the chain is read, each sample at its own; grazing.json's floor with the accurate mode
# (mf, pdf rule, the octahedral distortion). GL must agree, and differ from lat-long.
mf_run oct-top top-down --specular-only --env-layout oct --lod none
mf_run oct-top-lod top-down --specular-only --env-layout oct
mf_run oct-grazing grazing --specular-only --env-layout oct --estimator mf --lod pdf --distortion
mf_run ll-top top-down --specular-only --env-layout latlong --lod none
if "$SL" compare "$T/oct-top/g.pfm" "$T/ll-top/g.pfm" --metric p99rel --tolerance 1e-3 >/dev/null; then
    echo "FAIL oct-top: GL with --env-layout oct equals GL with latlong"
    fail=1
fi
if [ "$fail" != 0 ]; then
    echo "gl_shading: FAILED"
    exit 1
fi
echo "gl_shading: GL lighting on softlight's G-buffer within p99 rel $P99_TOL, >8/255 on <= $OVER8_PERCENT% of pixels"
