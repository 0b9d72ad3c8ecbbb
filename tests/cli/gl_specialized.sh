#!/usr/bin/env bash
# gl_specialized.sh BUILD_DIR - softlight-gl lights each scene with a program of lighting.frag
# specialized for its options and features (the options as constants, the unused branches left
# out: src/gl/lighting_pass.c); $SL_GL_GENERAL compiles the general shader instead. The two must
# give the same image: specialization removes code, it does not change what the rest computes.
# Measured (160x90, llvmpipe): bit-identical on all but the env-lights case, max 6e-8 there
# (constant folding of the options' arithmetic). Cases cover each specialized feature: both lobe
# sets and the extra target (pbr), microfacet + octahedral chain + SH9 + rotation, env lights +
# gems lod + G = 1 + distortion + dual-paraboloid irradiance, split sum on GGX only, a scene with
# both lobe sets and a point light, and --gbuffer (the lobe sets read from softlight's G-buffer
# files: a program for Phong alone would shade the GGX sphere wrong, and the reverse).
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"

fail=0
# case LABEL ARGS...: specialized against general, max abs difference <= 1e-6
case_() {
    local label=$1
    shift
    "$GL" render "$@" --size 160x90 --pfm "$T/s.pfm" -o "$T/s.png"
    SL_GL_GENERAL=1 "$GL" render "$@" --size 160x90 --pfm "$T/g.pfm" -o "$T/g.png"
    if "$SL" compare "$T/s.pfm" "$T/g.pfm" --metric max --tolerance 1e-6 >"$T/cmp.txt"; then
        echo "ok: $label: max $(gl_field 'max abs error' "$T/cmp.txt")"
    else
        echo "FAIL: $label: specialized and general programs differ"
        sed -n 6,10p "$T/cmp.txt"
        fail=1
    fi
}
case_ "default" scenes/default.json
case_ "pbr (GGX only, extra target)" scenes/pbr.json
case_ "mf, oct chain, SH9, rotate" scenes/bunny.json --estimator mf --env-layout oct --irradiance sh9 --rotate
case_ "env lights, gems, G=1, distortion, DP" scenes/city-sun.json --env-lights 8 --lod gems --g one --distortion \
    --irradiance dp
case_ "split sum, GGX only" scenes/ggx.json --estimator splitsum
cat >"$T/mixed.json" <<JSON
{
  "camera": {"eye": [0, -8, 0], "target": [0, 0, 0], "up": [0, 0, 1], "fovy": 30, "near": 1, "far": 100},
  "environment": {"hdr": "$PWD/scenes/envmaps/studio.hdr", "intensity": 1, "rotation": 0},
  "materials": {
    "phong": {"kd": 0.3, "ks": 0.5, "alpha": 200},
    "ggx": {"brdf": "ggx", "kd": 0.3, "ks": 0.5, "roughness": 0.3}
  },
  "objects": [
    {"shape": "sphere", "material": "phong", "transform": {"translate": [-1.1, 0, 0]}},
    {"shape": "sphere", "material": "ggx", "transform": {"translate": [1.1, 0, 0]}}
  ],
  "lights": [{"position": [2, -4, 3], "color": [1, 1, 1], "intensity": 20}]
}
JSON
case_ "Phong + GGX, a point light" "$T/mixed.json"
"$SL" render "$T/mixed.json" --size 160x90 --aov "$T/aov" -o "$T/c.png" >/dev/null
case_ "--gbuffer (lobes from the files)" "$T/mixed.json" --gbuffer "$T/aov"
exit $fail
