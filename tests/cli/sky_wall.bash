# sky_wall.bash - the scenes of the sky visibility maps' tests (sky_maps.sh, gl_sky_maps.sh): a
# constant white environment (a 256x128 PFM of ones), a 6x6 floor and a wall 4 tall and 0.2 thick
# along x = 0 across the whole floor, seen from above on the +x side, so that a floor point at the
# wall's foot sees half the sky; and the wall glossy (GGX, roughness 0.5) on a floor 24 wide, seen
# level from 1.5 above the floor, whose lobes reach across the horizon (gloss.json), and that wall
# alone (gloss-alone.json). Sourced; writes $T/white.pfm, $T/wall.json, $T/gloss.json and
# $T/gloss-alone.json.
python3 - "$T/white.pfm" <<'PY'
import struct, sys
w, h = 256, 128
with open(sys.argv[1], 'wb') as f:
    f.write(b'PF\n%d %d\n-1.0\n' % (w, h))
    f.write(struct.pack('<' + 'f' * (3 * w * h), *([1.0] * (3 * w * h))))
PY
cat >"$T/wall.json" <<JSON
{"camera": {"eye": [3.2, 0, 6], "target": [1.6, 0, 0], "up": [1, 0, 0], "fovy": 50},
 "environment": {"hdr": "$T/white.pfm"},
 "materials": {"m": {"kd": 1, "ks": 0, "alpha": 10}},
 "objects": [{"shape": "plane", "material": "m", "transform": {"scale": [3, 3, 1]}},
             {"shape": "box", "material": "m", "transform": {"translate": [0, 0, 2], "scale": [0.1, 3, 2]}}],
 "render": {"samples": 1}}
JSON
gloss() { # gloss OBJECTS: the glossy wall's scene with OBJECTS after the wall
    cat <<JSON
{"camera": {"eye": [4, -1, 1.5], "target": [0, 0.3, 1.5], "up": [0, 0, 1], "fovy": 50},
 "environment": {"hdr": "$T/white.pfm"},
 "materials": {"m": {"kd": 1, "ks": 0, "alpha": 10}, "g": {"brdf": "ggx", "kd": 0, "ks": 0.9, "roughness": 0.5}},
 "objects": [{"shape": "box", "material": "g", "transform": {"translate": [0, 0, 2], "scale": [0.1, 3, 2]}}$1],
 "render": {"samples": 64, "estimator": "mf"}}
JSON
}
gloss ', {"shape": "plane", "material": "m", "transform": {"scale": [12, 12, 1]}}' >"$T/gloss.json"
gloss '' >"$T/gloss-alone.json"
