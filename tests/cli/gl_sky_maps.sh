#!/usr/bin/env bash
# gl_sky_maps.sh BUILD_DIR - the sky visibility maps (--sky-maps K, docs/lighting.md "Sky
# visibility maps") in OpenGL: src/gl/shadow_pass.c draws them with shaders/shadow_depth.vert and
# shadow_sun.frag from src/shadow/sky.c's directions, weights and frames, lighting.frag's
# sky_visibility reads them, against softlight's (src/shadow/sky.c). softlight-gl lights
# softlight's G-buffer (--gbuffer) with the maps GL drew, so what differs is GL's rasterization of
# the maps and how the two evaluate the lookup:
# - sky_maps.sh's floor beside a tall wall under a constant white environment, --diffuse-only
#   --no-lights --sky-maps 32, where the image is E V: V per pixel, each side's image with the
#   maps over its image without, differs by more than 0.01 at no more than 0.05% of the pixels
#   (a lookup without the per-tap receiver plane puts 0.29% there), the wall's foot is near 0.5
#   in both, and the images keep the gl_shading.sh bounds (p99 relative error <= 0.05, share more
#   than 8/255 apart <= 0.1%); measured: p99 0, V at most 0.0049 apart (C fills V between
#   anchors where its pixels are fine enough, src/shading/sky_plane.c; GL looks it up per pixel);
# - GL's image without the maps is far outside those bounds against C's with them: a GL that
#   ignores its maps fails here;
# - scenes/bunny.json and scenes/pbr.json with --env-lights 32 --shadows --sky-maps 32 (the maps
#   weighted by the env lights' residual), bunny also with --ao-radius 1 (the cone: the diffuse
#   read about N, times the material's occlusion alone) and through the general shader
#   ($SL_GL_GENERAL): the same bounds; measured p99 0.019 (bunny), 0.019 (bunny, AO), 0.0045 (pbr);
# - the specular's part across the horizon (lighting.frag horizon_visible): sky_wall.bash's glossy
#   wall on its floor, --specular-only --no-lights --sky-maps 32, within the bounds, and C's image
#   without the maps far outside them against GL's with (a GL that keeps the part fails here);
#   scenes/model.json with --ao-radius 1 (the cone's factor on R's side, the material's occlusion
#   on the part across, and the floor's wide lobes' factor at most the map of R's cell,
#   lighting.frag lobe_map_factor), the same bounds; measured p99 0.00012 (the wall), 0.0015
#   (model);
# - `softlight check` on the wall with --sky-maps 32 passes.
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"
fail=0


# ---- the wall under a constant white environment (sky_wall.bash)
source tests/cli/sky_wall.bash
W=(--no-lights --diffuse-only)
mkdir -p "$T/wall"
"$SL" render "$T/wall.json" --size "$GL_TEST_SIZE" "${W[@]}" --sky-maps 32 --aov "$T/wall" --pfm "$T/wall/c.pfm" -q
"$SL" render "$T/wall.json" --size "$GL_TEST_SIZE" "${W[@]}" --pfm "$T/wall/c0.pfm" -q
"$GL" render "$T/wall.json" "${W[@]}" --sky-maps 32 --gbuffer "$T/wall" --pfm "$T/wall/g.pfm"
"$GL" render "$T/wall.json" "${W[@]}" --gbuffer "$T/wall" --pfm "$T/wall/g0.pfm"
gl_within "wall" "$T/wall/c.pfm" "$T/wall/g.pfm" || { echo "FAIL wall: outside the bounds"; fail=1; }
gl_outside "GL without maps" "$T/wall/c.pfm" "$T/wall/g0.pfm" \
    "GL's image without the sky maps is within the bounds of C's with them: the test sees no occlusion" || fail=1
# V per pixel, C's against GL's; the wall's foot
PYTHONPATH=tests/cli python3 - "$T/wall" <<'PY' || fail=1
import sys
from pfm import read_pfms
w, h, (c, c0, g, g0) = read_pfms(sys.argv[1], "c", "c0", "g", "g0")
lit = far = occluded = 0
worst = 0.0
rows_c, rows_g = {}, {}
for y in range(h):
    for x in range(w):
        i = 3 * (y * w + x) + 1  # green
        if c0[i] <= 0.5 or g0[i] <= 0.5:  # the background reads the environment: 1; the floor ~1
            continue
        vc, vg = c[i] / c0[i], g[i] / g0[i]
        lit += 1
        occluded += vc < 0.9
        worst = max(worst, abs(vc - vg))
        far += abs(vc - vg) > 0.01
        if w // 3 <= x < 2 * w // 3:
            rows_c.setdefault(y, []).append(vc)
            rows_g.setdefault(y, []).append(vg)
def foot(rows):  # sky_maps.sh's rule: the least row median above 0.2 (the wall's top is open)
    meds = [sorted(v)[len(v) // 2] for v in rows.values()]
    return min(m for m in meds if m > 0.2)
fc, fg = foot(rows_c), foot(rows_g)
print(f"V: {lit} pixels ({occluded} under 0.9), |C - GL| > 0.01 at {far}, at most {worst:.2g}; "
      f"the wall's foot: C {fc:.3f}, GL {fg:.3f}")
bad = 0
if occluded < 0.1 * lit or far > 0.0005 * lit:
    print("FAIL V: too few occluded pixels or C and GL apart at too many")
    bad = 1
if abs(fc - 0.5) > 0.1 or abs(fg - 0.5) > 0.1:
    print("FAIL V at the wall's foot: want 0.5 +- 0.1 in both")
    bad = 1
sys.exit(bad)
PY

# ---- scenes: env lights with their maps, the sky maps weighted by the residual
O=(--env-lights 32 --shadows --sky-maps 32)
scene() { # scene NAME FILE [options...]
    local name=$1 file=$2
    shift 2
    mkdir -p "$T/$name"
    "$SL" render "$file" --size "$GL_TEST_SIZE" "${O[@]}" "$@" --aov "$T/$name" --pfm "$T/$name/c.pfm" -q
    "$GL" render "$file" "${O[@]}" "$@" --gbuffer "$T/$name" --pfm "$T/$name/g.pfm"
    gl_within "$name" "$T/$name/c.pfm" "$T/$name/g.pfm" || { echo "FAIL $name: outside the bounds"; fail=1; }
}
scene bunny scenes/bunny.json
scene bunny-ao scenes/bunny.json --ao-radius 1
scene pbr scenes/pbr.json
scene model-ao scenes/model.json --ao-radius 1

# ---- the specular's part across the horizon: the glossy wall on its floor
G=(--no-lights --specular-only)
mkdir -p "$T/gloss"
"$SL" render "$T/gloss.json" --size "$GL_TEST_SIZE" "${G[@]}" --sky-maps 32 --aov "$T/gloss" --pfm "$T/gloss/c.pfm" -q
"$SL" render "$T/gloss.json" --size "$GL_TEST_SIZE" "${G[@]}" --pfm "$T/gloss/c0.pfm" -q
"$GL" render "$T/gloss.json" "${G[@]}" --sky-maps 32 --gbuffer "$T/gloss" --pfm "$T/gloss/g.pfm"
gl_within "gloss" "$T/gloss/c.pfm" "$T/gloss/g.pfm" || { echo "FAIL gloss: outside the bounds"; fail=1; }
gl_outside "C without maps" "$T/gloss/c0.pfm" "$T/gloss/g.pfm" \
    "C's glossy wall without the maps is within the bounds of GL's with them: the test sees no part across" || fail=1
SL_GL_GENERAL=1 "$GL" render scenes/bunny.json "${O[@]}" --gbuffer "$T/bunny" --pfm "$T/bunny/general.pfm"
gl_within "bunny, general" "$T/bunny/c.pfm" "$T/bunny/general.pfm" ||
    { echo "FAIL bunny, the general shader: outside the bounds"; fail=1; }

if "$SL" check "$T/wall.json" --size "$GL_TEST_SIZE" "${W[@]}" --sky-maps 32 >"$T/check.txt" 2>&1; then
    echo "softlight check wall --sky-maps 32: $(tail -1 "$T/check.txt")"
else
    cat "$T/check.txt"
    echo "FAIL softlight check wall --sky-maps 32"
    fail=1
fi

[ "$fail" = 0 ] && echo "PASS gl_sky_maps" || exit 1
