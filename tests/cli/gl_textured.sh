#!/usr/bin/env bash
# gl_textured.sh BUILD_DIR - the textured G-buffer pass against OpenGL (llvmpipe) on
# scenes/textured.json: `softlight render --aov` against `softlight-gl render --aov`, channel by
# channel (tests/cli/gbuffer_diff.py), and `softlight trace` printing a textured pixel's fetches.
#
# Expected, and why (figures at 320x180 in docs/gl.md "Textured G-buffer"):
# - coverage identical (the leaf's discard included), depth within 1e-5 (gl_raster.sh's bound);
#   ks and alpha exact: their maps are unset and the constants are the same floats.
# - kd, normal: texture() results. Both pick the same lambda, one per 2x2 quad from the coarse
#   differences of uv, with the helper lanes' inputs extrapolated from the triangle's planes
#   (docs/shader-api.md "Level of detail"; measured on every quad of this scene at this size:
#   within 0.001 of llvmpipe's, float rounding of uv). What is left is filtering:
#   - kd (SRGB8 maps): the sRGB mips may differ from llvmpipe's by one code (texture.h), up to
#     2/255 of linear kd at the bright end, where a pixel reads a level past 0: measured max
#     0.0091, 4.5% of the objects' pixels over 1/255 (read at level 0 only, "filter":
#     "bilinear", the same pixels agree within 0.002, none over 1/255).
#   - normal (bumps_n.png, UNORM8): llvmpipe filters 8-bit textures in its 8-bit AoS path
#     (bilinear weights and each level's result in 8 bits, the mip weight truncated to 1/256),
#     so a texel value is off by up to about 2.5/255, twice that in n = rgb * 2 - 1: measured max
#     0.029, 32% over 1/255. With GALLIVM_PERF=no_aos_sampling llvmpipe filters in float, and the
#     second GL render below checks the normal against that within 0.01, 1.2% (measured 0.0070,
#     0.72%): the lambda check this test is for, apart from the 8-bit filter.
#   (Before the helpers were extrapolated unclamped, a quad at the sphere's seam or the floor's
#   far edge picked a lambda up to 1.4 off: normal max 0.30, kd 0.11.)
# - floor (near-clipped: each triangle is cut by the near plane and the guard band): position
#   within 1e-3 units (measured 2.8e-4 at 80 units away, float rounding on both sides; before the
#   exact-position attribute planes of setup.c it was 0.34). kd within 0.009: the tiles' sRGB
#   mips (as kd above), so pixels past level 0 (the far floor) can pass 1/255: measured max
#   0.0063, 14% of the floor's pixels over 1/255, all of them within 1.5/255 (bound: 20%).
#   Normal exact (no normal map on the floor).
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"

scene=scenes/textured.json
mkdir -p "$T/c" "$T/g"
"$SL" render "$scene" --size "$GL_TEST_SIZE" --samples 4 --aov "$T/c" -q -o "$T/c.png"
"$GL" render "$scene" --size "$GL_TEST_SIZE" --samples 4 --aov "$T/g" -o "$T/g.png" >/dev/null
fail=0
"$SL" compare "$T/c/mask.pfm" "$T/g/mask.pfm" --metric max --tolerance 0 >"$T/mask.txt" ||
    { echo "FAIL coverage differs"; grep '^worst' "$T/mask.txt" | head -5; fail=1; }
python3 tests/cli/gbuffer_diff.py "$T/c" "$T/g" >"$T/diff.txt"
echo "channel group pixels max share>1/255"
cat "$T/diff.txt"
bound() { gl_bound "$T/diff.txt" "$@"; } # CHANNEL GROUP MAX SHARE
bound depth objects 1e-5 0
bound depth floor 1e-5 0
bound ks objects 0 0
bound ks floor 0 0
bound alpha objects 0 0
bound alpha floor 0 0
bound position objects 0.01 0.001
bound position floor 0.001 0
bound kd objects 0.015 0.06
bound kd floor 0.009 0.20
bound normal objects 0.04 0.35
bound normal floor 0 0
# llvmpipe's float filtering path (no 8-bit AoS): the normal map's values then agree to float
# filtering, so this is where a wrong lambda would show
mkdir -p "$T/gf"
GALLIVM_PERF=no_aos_sampling "$GL" render "$scene" --size "$GL_TEST_SIZE" --samples 4 --aov "$T/gf" -o "$T/gf.png" >/dev/null
python3 tests/cli/gbuffer_diff.py "$T/c" "$T/gf" >"$T/diff_float.txt"
echo "against GALLIVM_PERF=no_aos_sampling:"
grep '^normal objects' "$T/diff_float.txt"
gl_bound "$T/diff_float.txt" normal objects 0.01 0.012

# softlight trace on a pixel of the floor prints its kd_map fetch (trilinear, the floor's
# tiles.png is SRGB8 with 9 levels), and the value it prints is the G-buffer's kd (kd = 1).
"$SL" trace "$scene" --size "$GL_TEST_SIZE" --samples 4 --pixel 160,145 >"$T/trace.txt"
for want in "texture fetches (G-buffer pass" "kd_map (SRGB8, 9 levels)" "dPdx" "lambda" "LINEAR_MIPMAP_LINEAR"; do
    grep -qF "$want" "$T/trace.txt" || { echo "FAIL trace: no '$want'"; fail=1; }
done
kd=$(awk '/^  kd /{ gsub(/[(),]/, " "); print $2; exit }' "$T/trace.txt")
value=$(awk '/^    value /{ gsub(/[(),]/, " "); print $2; exit }' "$T/trace.txt")
awk -v a="$kd" -v b="$value" 'BEGIN { d = a - b; exit !(a != "" && d < 1e-5 && d > -1e-5) }' ||
    { echo "FAIL trace: kd_map value '$value' is not the G-buffer's kd '$kd'"; fail=1; }
# an untextured pixel says so (the sky above the scene: no geometry)
"$SL" trace "$scene" --size "$GL_TEST_SIZE" --samples 4 --pixel 160,2 | grep "texture fetches: none" >/dev/null ||
    { echo "FAIL trace: a pixel without geometry lists fetches"; fail=1; }

[ "$fail" = 0 ] || { echo "gl_textured: FAILED"; exit 1; }
echo "gl_textured: coverage identical, every channel within its bound; trace prints the fetches"
