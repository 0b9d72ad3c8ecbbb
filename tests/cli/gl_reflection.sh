#!/usr/bin/env bash
# gl_reflection.sh BUILD_DIR - the reflection occlusion (--reflection-occlusion D, docs/lighting.md
# "Reflection occlusion") in OpenGL: lighting.frag's reflection_visibility traces the lobe's rays
# per pixel against the G-buffer textures, against softlight's pass (src/occlusion/reflection.c),
# whose plane the C port reads. softlight-gl lights softlight's G-buffer (--gbuffer), so what
# differs is the two sides' float arithmetic along the same rays:
# - scenes/grazing.json (a glossy floor at a grazing view reflecting two spheres), image-based light
#   only, --estimator mf --lod pdf --distortion -n 64, with --reflection-occlusion 5 alone (it scales
#   the specular) and with --ao-radius 1 (it joins the cone's specular factor by its rays' count),
#   and through the general shader ($SL_GL_GENERAL): the gl_shading.sh bounds (p99 relative error
#   <= 0.05, share more than 8/255 apart <= 0.1%); measured p99 0.0016, no pixel more than 1/255
#   apart, and at most 0.05% more than 1/255 apart (a GL without the lone pixels' own rays leaves
#   0.12% and, with --ao-radius 1, 0.22%);
# - scenes/textured.json (a normal-mapped ball, whose N leans past the silhouette at its rim), the
#   same options, and a floor whose vertex normals lean 15 degrees away from a camera 1 unit above
#   it (a mesh written here), a mirror (alpha 2000) and a glossy one (alpha 30): a ray above N's
#   horizon and below that of the facet (the G-buffer's facet.pfm) enters the surface and is not
#   counted, and every sample and env light under the facet is left out, on both sides; the same
#   bounds (measured on the mirror floor: p99 0.0022, no pixel more than 1/255 apart; a GL that
#   traces those rays: p99 0.25, 10% of pixels more than 1/255 apart; on the glossy floor p99
#   0.0023), where GL without the facet plane (the normal rebuilt from the positions, its rays
#   into the floor blocked, no sample left out) is far outside them (p99 0.38, 7.7% of pixels
#   more than 1/255 apart);
# - GL's image without the option is far outside those bounds against C's with it (p99 0.73): a
#   GL that ignores the option fails here, and so does one that counts its own ray alone (no cross);
#   one that takes the smaller of the two factors where C joins them fails grazing-ao (p99 0.072).
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"
fail=0

O0=(--no-lights --estimator mf --lod pdf --distortion -n 64)
O=("${O0[@]}" --reflection-occlusion 5)
case_of() { # case_of NAME SCENE [options...]
    local name=$1 scene=$2
    shift 2
    mkdir -p "$T/$name"
    "$SL" render "$scene" --size "$GL_TEST_SIZE" "${O[@]}" "$@" --aov "$T/$name" --pfm "$T/$name/c.pfm" -q
    "$GL" render "$scene" "${O[@]}" "$@" --gbuffer "$T/$name" --pfm "$T/$name/g.pfm"
    gl_within "$name" "$T/$name/c.pfm" "$T/$name/g.pfm" || { echo "FAIL $name: outside the bounds"; fail=1; }
}
case_of grazing scenes/grazing.json
case_of grazing-ao scenes/grazing.json --ao-radius 1
case_of textured scenes/textured.json
# tighter on grazing, whose pixels agree to the last display step: none more than 1/255 apart; a GL
# whose pixels with fewer than three rays in their block do not add their own other four leaves
# 0.12% and 0.22% (grazing-ao) more than 1/255 apart, within the shared bounds
for c in grazing grazing-ao; do
    share=$(gl_field "8-bit diff > 1" "$T/$c.txt")
    awk -v s="$share" 'BEGIN { exit !(s <= 0.05) }' ||
        { echo "FAIL $c: $share% of pixels more than 1/255 apart (allowed 0.05%)"; fail=1; }
done
# the leaning floor: 20 x 20 units in 800 triangles, one vertex normal tilted towards -x
awk 'BEGIN {
    n = 20; t = 15 * atan2(0, -1) / 180
    for (j = 0; j <= n; j++) for (i = 0; i <= n; i++) printf "v %g %g 0\n", -10 + i, -10 + j
    printf "vn %.6f 0 %.6f\n", -sin(t), cos(t)
    for (j = 0; j < n; j++) for (i = 0; i < n; i++) {
        a = j * (n + 1) + i + 1
        printf "f %d//1 %d//1 %d//1\nf %d//1 %d//1 %d//1\n", a, a + 1, a + n + 2, a, a + n + 2, a + n + 1
    }
}' >"$T/leaning.obj"
cat >"$T/leaning.json" <<JSON
{
  "camera": {"eye": [5, 0, 1], "target": [0, 0, 0], "up": [0, 0, 1], "fovy": 50, "near": 0.05, "far": 50},
  "environment": {"hdr": "$PWD/scenes/envmaps/studio.hdr"},
  "materials": {"glossy": {"kd": 0.05, "ks": 1, "alpha": 2000}},
  "objects": [{"mesh": "leaning.obj", "material": "glossy"}]
}
JSON
case_of leaning "$T/leaning.json"
# the glossy floor, whose lobes reach well under the facet: GL without the facet plane lights
# every sample of them
sed 's/"alpha": 2000/"alpha": 30/' "$T/leaning.json" >"$T/leaning-glossy.json"
case_of leaning-glossy "$T/leaning-glossy.json"
mkdir -p "$T/no-facet"
cp "$T/leaning-glossy"/*.pfm "$T/no-facet/"
rm "$T/no-facet/facet.pfm" "$T/no-facet/c.pfm"
"$GL" render "$T/leaning-glossy.json" "${O[@]}" --gbuffer "$T/no-facet" --pfm "$T/no-facet/g.pfm"
gl_outside "GL without the facet" "$T/leaning-glossy/c.pfm" "$T/no-facet/g.pfm" \
    "GL's image without the facet plane is within the bounds of C's with it: the test sees no facet" || fail=1
SL_GL_GENERAL=1 "$GL" render scenes/grazing.json "${O[@]}" --gbuffer "$T/grazing" --pfm "$T/grazing/general.pfm"
gl_within "grazing, general" "$T/grazing/c.pfm" "$T/grazing/general.pfm" ||
    { echo "FAIL grazing, the general shader: outside the bounds"; fail=1; }
"$GL" render scenes/grazing.json "${O0[@]}" --gbuffer "$T/grazing" --pfm "$T/grazing/g0.pfm"
gl_outside "GL without it" "$T/grazing/c.pfm" "$T/grazing/g0.pfm" \
    "GL's image without the reflection occlusion is within the bounds of C's with it: the test sees no occlusion" ||
    fail=1

[ "$fail" = 0 ] && echo "PASS gl_reflection" || exit 1
