#!/usr/bin/env bash
# gl_sun_shadows.sh BUILD_DIR - the env lights' orthographic shadow maps in OpenGL
# (src/gl/shadow_pass.c draws them with shaders/shadow_depth.vert and shadow_sun.frag from
# src/shadow's clusters and frames, lighting.frag's shadow_sun_visibility reads them) against
# softlight's (src/shadow). softlight-gl lights softlight's G-buffer (--gbuffer) with the maps GL
# drew, so what differs is GL's rasterization of the maps and how the two evaluate the lookup:
# - a floor with a floating slab and a box standing on it under a made sky (sun_sky.py: black
#   but for a sun of two texels, so the env lights hold all the light), the environment turned
#   by 30 degrees, --env-lights 32 --shadows: the bounds of gl_shading.sh (p99 relative error
#   <= 0.05, share more than 8/255 apart <= 0.1%); a pixel in the slab's shadow and one in the
#   box's keep under 5% of their value without shadows in both, an open floor pixel keeps it to
#   1e-4 in both; the sun's visibility, the image with the maps over the image without (each
#   side's own), differs by more than 0.01 at no more than 0.5% of the pixels it lights;
# - the same through the general shader ($SL_GL_GENERAL: every option a uniform);
# - GL's image without maps is far outside those bounds against C's with them: a GL that
#   ignores its maps fails here;
# - a sun's glow: a glossy floor facing a sun in a glare that two env lights leave to the samples
#   (sun_sky.py), a box's shadow across its reflection, --env-lights 2 --shadows, the default
#   estimator and MIS: within the same bounds (a GL that left the glare in the shadow lit would
#   be a third of the light apart over a seventh of the image: sun_shadows.sh);
# - scenes/city-sun.json with --env-lights 32 --shadows within the same bounds, also with
#   --ao-radius 1 (the lights' part of the irradiance taken out along the bent direction), and
#   `softlight check` on it passes.
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"
fail=0


# ---- the made sky: a floor, a slab floating over it, a box standing on it
python3 tests/cli/sun_sky.py "$T/sky.pfm" 40 30
cat >"$T/occ.json" <<JSON
{"camera": {"eye": [0, -3.5, 3.5], "target": [0, 0, 0], "up": [0, 0, 1], "fovy": 45},
 "environment": {"hdr": "$T/sky.pfm", "rotation": 30},
 "materials": {"m": {"kd": 0.6, "ks": 0.04, "alpha": 10}},
 "objects": [{"shape": "plane", "material": "m", "transform": {"scale": [2, 2, 1]}},
   {"shape": "box", "material": "m", "transform": {"translate": [0.3, 0.1, 0.7], "scale": [0.3, 0.3, 0.05]}},
   {"shape": "box", "material": "m", "transform": {"translate": [-0.7, -0.5, 0.25], "scale": 0.25}}]}
JSON
O=(--env-lights 32)
mkdir -p "$T/occ"
"$SL" render "$T/occ.json" --size "$GL_TEST_SIZE" "${O[@]}" --shadows --aov "$T/occ" --pfm "$T/occ/c.pfm" -q
"$SL" render "$T/occ.json" --size "$GL_TEST_SIZE" "${O[@]}" -q --pfm "$T/occ/c0.pfm"
"$GL" render "$T/occ.json" "${O[@]}" --shadows --gbuffer "$T/occ" --pfm "$T/occ/g.pfm"
"$GL" render "$T/occ.json" "${O[@]}" --gbuffer "$T/occ" --pfm "$T/occ/g0.pfm"
SL_GL_GENERAL=1 "$GL" render "$T/occ.json" "${O[@]}" --shadows --gbuffer "$T/occ" --pfm "$T/occ/general.pfm"
gl_within "made sun" "$T/occ/c.pfm" "$T/occ/g.pfm" || { echo "FAIL made sun: outside the bounds"; fail=1; }
gl_within "made sun, general" "$T/occ/c.pfm" "$T/occ/general.pfm" ||
    { echo "FAIL made sun, the general shader: outside the bounds"; fail=1; }
gl_outside "GL without maps" "$T/occ/c.pfm" "$T/occ/g0.pfm" \
    "GL's image without shadow maps is within the bounds of C's with them: the test sees no shadow" || fail=1
# the sun's visibility per pixel, C's against GL's; the darkest shadowed pixels and the open floor
PYTHONPATH=tests/cli python3 - "$T/occ" <<'PY' || fail=1
import sys
from pfm import read_pfms
w, h, (c, c0, g, g0) = read_pfms(sys.argv[1], "c", "c0", "g", "g0")
bad = 0
lit = far = shadowed = edge = 0
worst = 0.0
for i in range(1, w * h * 3, 3):  # green
    if c0[i] <= 1e-3 or g0[i] <= 1e-3:
        continue
    vc, vg = c[i] / c0[i], g[i] / g0[i]
    lit += 1
    shadowed += vc < 0.05
    edge += 0.05 <= vc <= 0.95
    worst = max(worst, abs(vc - vg))
    far += abs(vc - vg) > 0.01
print(f"visibility: {lit} lit pixels ({shadowed} shadowed, {edge} on an edge), |C - GL| > 0.01 at {far}, "
      f"at most {worst:.2g}")
if shadowed < 200 or far > 0.005 * lit:
    print("FAIL the sun's visibility: too few shadowed pixels or C and GL apart at too many")
    bad = 1
# pixels (x, y from the top, at 320x180): the slab's shadow, the box's, open floor
for name, x, y, want in (("slab's shadow", 154, 109, "dark"), ("box's shadow", 106, 128, "dark"),
                         ("open floor", 160, 150, "open")):
    k = ((h - 1 - y) * w + x) * 3 + 1
    rc, rg = c[k] / c0[k], g[k] / g0[k]
    ok = rc < 0.05 and rg < 0.05 if want == "dark" else abs(rc - 1) < 1e-4 and abs(rg - 1) < 1e-4
    print(f"{name} ({x}, {y}): C keeps {rc:.4g}, GL {rg:.4g} of its value without shadows")
    if not ok:
        print(f"FAIL {name}: want {'under 0.05' if want == 'dark' else 'within 1e-4 of 1'} in both")
        bad = 1
sys.exit(bad)
PY

# ---- a sun's glow
source tests/cli/glare_scene.bash
glare_scene "$T"
for est in spec mis; do
    mkdir -p "$T/glare-$est"
    "$SL" render "$T/glare.json" --size "$GL_TEST_SIZE" --env-lights 2 --shadows --estimator $est \
        --aov "$T/glare-$est" --pfm "$T/glare-$est/c.pfm" -q
    "$GL" render "$T/glare.json" --env-lights 2 --shadows --estimator $est --gbuffer "$T/glare-$est" \
        --pfm "$T/glare-$est/g.pfm"
    gl_within "glare, $est" "$T/glare-$est/c.pfm" "$T/glare-$est/g.pfm" ||
        { echo "FAIL a sun's glow, --estimator $est: outside the bounds"; fail=1; }
done

# ---- scenes/city-sun.json, and softlight check
mkdir -p "$T/city"
"$SL" render scenes/city-sun.json --size "$GL_TEST_SIZE" "${O[@]}" --shadows --aov "$T/city" --pfm "$T/city/c.pfm" -q
"$GL" render scenes/city-sun.json "${O[@]}" --shadows --gbuffer "$T/city" --pfm "$T/city/g.pfm"
gl_within "city-sun" "$T/city/c.pfm" "$T/city/g.pfm" || { echo "FAIL city-sun: outside the bounds"; fail=1; }
mkdir -p "$T/city-ao"
"$SL" render scenes/city-sun.json --size "$GL_TEST_SIZE" "${O[@]}" --shadows --ao-radius 1 --aov "$T/city-ao" \
    --pfm "$T/city-ao/c.pfm" -q
"$GL" render scenes/city-sun.json "${O[@]}" --shadows --ao-radius 1 --gbuffer "$T/city-ao" --pfm "$T/city-ao/g.pfm"
gl_within "city-sun-ao" "$T/city-ao/c.pfm" "$T/city-ao/g.pfm" || { echo "FAIL city-sun --ao-radius 1: outside the bounds"; fail=1; }
if "$SL" check scenes/city-sun.json --size "$GL_TEST_SIZE" "${O[@]}" --shadows >"$T/check.txt" 2>&1; then
    echo "softlight check city-sun --env-lights 32 --shadows: $(tail -1 "$T/check.txt")"
else
    cat "$T/check.txt"
    echo "FAIL softlight check city-sun --env-lights 32 --shadows"
    fail=1
fi

[ "$fail" = 0 ] && echo "PASS gl_sun_shadows" || exit 1
