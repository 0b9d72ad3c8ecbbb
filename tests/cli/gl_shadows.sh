#!/usr/bin/env bash
# gl_shadows.sh BUILD_DIR - the point lights' cube shadow maps in OpenGL (src/gl/shadow_pass.c
# draws them with shaders/shadow_depth.vert/.frag, lighting.frag's shadow_point_visibility reads
# them) against softlight's (src/shadow). softlight-gl lights softlight's G-buffer (--gbuffer)
# with the maps GL drew, so what differs is GL's rasterization of the maps and how the two
# evaluate the lookup:
# - scenes/lamp.json with --shadows, and with its light's own "shadow" key instead: the bounds of
#   gl_shading.sh (p99 relative error <= 0.05, share more than 8/255 apart <= 0.1%); a pixel in
#   the ball's shadow and one in the wall's keep under 5% of their value without shadows in both,
#   and a floor pixel in the open keeps it to 1e-4 in both; the light's visibility, its term
#   with the maps over its term without (each side's own), differs by more than 0.01 at no more
#   than 0.5% of the pixels it lights (measured: at none; 6.4e-7 at most over 36081 pixels, 1715
#   of them shadowed and 293 on an edge);
# - lamp.json with four lights, the "shadow" key on the second and the fourth: within the same
#   bounds (light i's layers are found by its index, not its rank among those that cast), and
#   far from GL's image with all four casting;
# - GL's image without maps is far outside those bounds against C's with them (p99 rel 0.79,
#   3% of pixels over 8/255): a GL that ignores its maps fails here;
# - a light inside a closed box over a floor, no environment: GL's image with --shadows is its
#   image with --no-lights (the light reaches nothing), as C's is;
# - a light 0.02 over a floor, grazing it: GL's image with --shadows is its image without (no
#   acne: every tap of every pixel passes), as C's is;
# - `softlight check scenes/lamp.json --shadows` compares them too, and passes.
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"
fail=0

# pair NAME SCENE OPTIONS...: C (with its G-buffer) and GL on that G-buffer, compared with the
# gl_shading.sh bounds into $T/NAME.txt; 1 when outside them
pair() {
    local name=$1 scene=$2
    shift 2
    mkdir -p "$T/$name"
    "$SL" render "$scene" --size "$GL_TEST_SIZE" "$@" --aov "$T/$name" --pfm "$T/$name/c.pfm" -q
    "$GL" render "$scene" "$@" --gbuffer "$T/$name" --pfm "$T/$name/g.pfm"
    gl_within "$name" "$T/$name/c.pfm" "$T/$name/g.pfm"
}

# ---- scenes/lamp.json: the flag, then the light's own key
pair lamp scenes/lamp.json --shadows || { echo "FAIL lamp --shadows: outside the bounds"; fail=1; }
sed -e 's/"intensity": 12}/"intensity": 12, "shadow": true}/' -e "s|\"envmaps/|\"$PWD/scenes/envmaps/|" \
    scenes/lamp.json >"$T/lamp-key.json"
grep -q '"shadow": true' "$T/lamp-key.json" || { echo "FAIL lamp-key.json has no \"shadow\" key"; exit 1; }
pair lamp-key "$T/lamp-key.json" || { echo "FAIL lamp, \"shadow\": true: outside the bounds"; fail=1; }
# without maps on the G-buffer the shadowed frame was drawn with (the lights unshadowed), and
# without the light at all
"$GL" render scenes/lamp.json --gbuffer "$T/lamp" --pfm "$T/lamp/g0.pfm"
"$GL" render scenes/lamp.json --gbuffer "$T/lamp" --no-lights --pfm "$T/lamp/g-env.pfm"
"$SL" render scenes/lamp.json --size "$GL_TEST_SIZE" -q --pfm "$T/lamp/c0.pfm"
"$SL" render scenes/lamp.json --size "$GL_TEST_SIZE" -q --no-lights --pfm "$T/lamp/c-env.pfm"
gl_outside "lamp, GL no maps" "$T/lamp/c.pfm" "$T/lamp/g0.pfm" \
    "GL's image without shadow maps is within the bounds of C's with them: the test sees no shadow" || fail=1
# dark and lit pixels (x, y from the top, at 320x180): the ball's shadow, the wall's, open floor;
# the light's term is the image less the one without the light
PYTHONPATH=tests/cli python3 - "$T/lamp" "$GL_TEST_SIZE" <<'PY' || fail=1
import sys
from pfm import read_pfms
w, h, (c, g, g0, env, c0, cenv) = read_pfms(sys.argv[1], "c", "g", "g0", "g-env", "c0", "c-env")
bad = 0
# the light's visibility per pixel, C's against GL's
term = lambda img, base, i: sum(img[3 * i + k] - base[3 * i + k] for k in range(3))
lit = shadowed = edge = off = 0
worst = 0.0
for i in range(w * h):
    bc, bg = term(c0, cenv, i), term(g0, env, i)
    if bc < 1e-3 or bg < 1e-3:
        continue
    vc, vg = term(c, cenv, i) / bc, term(g, env, i) / bg
    lit += 1
    shadowed += vc < 0.5
    edge += 0.01 < vc < 0.99
    off += abs(vc - vg) > 0.01
    worst = max(worst, abs(vc - vg))
ok = lit > 1000 and shadowed > 100 and off <= 0.005 * lit
print("%s visibility: %d pixels lit by the light, %d in shadow, %d on an edge (C); C and GL more than "
      "0.01 apart at %d, at most %.3g" % ("ok  " if ok else "FAIL", lit, shadowed, edge, off, worst))
bad += not ok
if sys.argv[2] != "320x180":
    print("skip the pixel checks: they are placed at 320x180")
    sys.exit(1 if bad else 0)
at = lambda img, x, y: term(img, env, (h - 1 - y) * w + x)
for x, y, what, dark in ((130, 132, "the ball's shadow", True), (80, 95, "the wall's shadow", True),
                         (250, 150, "open floor", False)):
    blind, cv, gv = at(g0, x, y), at(c, x, y), at(g, x, y)
    if dark:
        ok = blind > 0.1 and cv < 0.05 * blind and gv < 0.05 * blind
    else:
        ok = blind > 0.1 and abs(cv - blind) < 1e-4 * blind and abs(gv - blind) < 1e-4 * blind
    print("%s %-18s (%d, %d): the light's term without shadows %.5g, C %.5g, GL %.5g"
          % ("ok  " if ok else "FAIL", what, x, y, blind, cv, gv))
    bad += not ok
sys.exit(1 if bad else 0)
PY

# ---- four lights, two casting by their key
python3 - "$T/four.json" "$PWD" <<'PY'
import json, sys
s = json.load(open(sys.argv[2] + "/scenes/lamp.json"))
s["environment"]["hdr"] = sys.argv[2] + "/scenes/envmaps/" + s["environment"]["hdr"].split("/")[-1]
s["lights"] = [{"position": [0.1, -0.2, 2.2], "intensity": 6}, {"position": [-1.5, 1.0, 1.2], "intensity": 3, "shadow": True},
               {"position": [1.5, -1.0, 1.0], "intensity": 3}, {"position": [1.2, 1.5, 0.8], "intensity": 2, "shadow": True}]
json.dump(s, open(sys.argv[1], "w"))
PY
pair four "$T/four.json" || { echo "FAIL four lights, two casting: outside the bounds"; fail=1; }
"$GL" render "$T/four.json" --shadows --gbuffer "$T/four" --pfm "$T/four/g-all.pfm"
gl_outside "four, GL all cast" "$T/four/c.pfm" "$T/four/g-all.pfm" \
    "four lights: GL's image with all four casting is within the bounds of C's with two (the case is void)" || fail=1

# ---- hard cases, lit by one point light alone (shadow_scene.bash)
source tests/cli/shadow_scene.bash
# same NAME A B WHAT: byte for byte
same() {
    if cmp -s "$2" "$3"; then echo "ok   $1: $4"; else echo "FAIL $1: not $4"; fail=1; fi
}

shadow_scene box 1.0 '{"shape": "box", "material": "m", "transform": {"translate": [0, -0.3, 1], "scale": 0.4}}'
pair box "$T/box.json" --shadows || { echo "FAIL light in a box: outside the bounds"; fail=1; }
"$GL" render "$T/box.json" --no-lights --gbuffer "$T/box" --pfm "$T/box/g-none.pfm"
"$GL" render "$T/box.json" --gbuffer "$T/box" --pfm "$T/box/g-blind.pfm"
same "light in a box" "$T/box/g.pfm" "$T/box/g-none.pfm" "GL's image is the one without lights"
cmp -s "$T/box/g-blind.pfm" "$T/box/g-none.pfm" &&
    { echo "FAIL light in a box: without shadows the light reaches nothing either (the case is void)"; fail=1; }

shadow_scene grazing 0.02
pair grazing "$T/grazing.json" --shadows || { echo "FAIL grazing light: outside the bounds"; fail=1; }
"$GL" render "$T/grazing.json" --gbuffer "$T/grazing" --pfm "$T/grazing/g-blind.pfm"
same "grazing light" "$T/grazing/g.pfm" "$T/grazing/g-blind.pfm" "GL's floor is fully lit: the image without shadows"

# ---- softlight check with the maps
if "$SL" check scenes/lamp.json --shadows --size "$GL_TEST_SIZE" >"$T/check.txt" 2>&1; then
    echo "ok   softlight check --shadows: $(grep -E '^PASS' "$T/check.txt")"
else
    echo "FAIL softlight check --shadows: $(tail -1 "$T/check.txt")"
    fail=1
fi

[ "$fail" = 0 ] && echo "PASS gl_shadows"
exit "$fail"
