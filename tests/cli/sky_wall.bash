# sky_wall.bash - the scene of the sky visibility maps' tests (sky_maps.sh, gl_sky_maps.sh): a
# constant white environment (a 256x128 PFM of ones), a 6x6 floor and a wall 4 tall and 0.2 thick
# along x = 0 across the whole floor, seen from above on the +x side, so that a floor point at the
# wall's foot sees half the sky. Sourced; writes $T/white.pfm and $T/wall.json.
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
