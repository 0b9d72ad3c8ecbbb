#!/usr/bin/env bash
# textured_quad_form.sh BUILD_DIR - the textured G-buffer program's quad form
# (sl_gbuffer_tex_frag_quad: one call a 2x2 quad, derivatives between its lanes) against its
# reference form run through the generic quad rounds (sl_gbuffer_tex_frag): `softlight render`
# takes the quad form on its span path and the rounds with --plain, and every G-buffer channel
# must be byte-identical. Scenes: the shipped textured.json (kd maps: sRGB and linear, repeat and
# clamp, minified and magnified; a normal map; an alpha-masked leaf), and a variant whose every
# material binds all five maps (ks, alpha and mask too, each with its own uv transform, filter
# and wrap), so that every slot of the quad form and the mask_map discard are covered.
set -u
SL=${1:?usage: $0 BUILD_DIR}/softlight
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-quadform.XXXXXX")
trap 'rm -rf "$T"' EXIT
cd "$(dirname "$0")/../.."

# Every material of textured.json gets the maps it lacks (paths relative to the scene's folder).
python3 - scenes/textured.json "$T/all-maps.json" <<'PY'
import json, os, sys
src, dst = sys.argv[1], sys.argv[2]
scene = json.load(open(src))
base = os.path.dirname(os.path.abspath(src))
def path(p): return os.path.join(base, p)
if "environment" in scene and "hdr" in scene["environment"]:
    scene["environment"]["hdr"] = path(scene["environment"]["hdr"])
for m in scene["materials"].values():
    for k in ("kd_map", "normal_map"):
        if isinstance(m.get(k), str):
            m[k] = path(m[k])
        elif isinstance(m.get(k), dict):
            m[k]["file"] = path(m[k]["file"])
    m.setdefault("kd_map", {"file": path("textures/tiles.png"), "uv_scale": [3, 2]})
    m["ks_map"] = {"file": path("textures/ramp.png"), "wrap": "mirror", "uv_scale": [2.5, 1.5], "uv_offset": [0.3, -0.2]}
    m["alpha_map"] = {"file": path("textures/bumps_n.png"), "srgb": False, "filter": "bilinear", "uv_scale": [4, 4]}
    m.setdefault("normal_map", {"file": path("textures/bumps_n.png"), "uv_scale": [5, 2], "filter": "nearest"})
    m["mask_map"] = {"file": path("textures/leaf.png"), "srgb": False, "wrap": "clamp", "uv_scale": [1.3, 1.3]}
    m["alpha_cutoff"] = 0.5
json.dump(scene, open(dst, "w"))
PY

fails=0
for s in scenes/textured.json "$T/all-maps.json"; do
    name=$(basename "$s" .json)
    "$SL" render "$s" --size 320x180 -n 1 -q --aov "$T/quad" -o "$T/quad.png" &&
    "$SL" render "$s" --size 320x180 -n 1 -q --aov "$T/rounds" -o "$T/rounds.png" --plain || {
        echo "FAIL $name: render failed"; fails=$((fails + 1)); continue; }
    same=1
    for c in position normal kd ks alpha depth mask; do
        cmp -s "$T/quad/$c.pfm" "$T/rounds/$c.pfm" || { echo "FAIL $name: $c.pfm differs between the quad form and the rounds"; same=0; }
    done
    if [ "$same" -eq 1 ]; then echo "ok   $name: every G-buffer channel identical"; else fails=$((fails + 1)); fi
done
[ "$fails" -eq 0 ] && echo "textured_quad_form: ok" || { echo "textured_quad_form: FAILED"; exit 1; }
