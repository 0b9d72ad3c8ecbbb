# masked_casters.bash - the scenes and checks of the masked casters' tests (masked_casters.sh,
# gl_masked_casters.sh; src/raster/coverage.h): a 2x2 quad 1 above a floor, its kd_map's alpha 0
# over u < 1/2 and 1 over the rest (alpha_cutoff 0.5), lit by a point light under a black sky
# ($T/point.json) or by a sun of a black sky ($T/sun.json, for the env lights); which floor
# pixels each half of the quad shadows (fates) and whether an image with the maps keeps the first
# lit and the second dark against one without (judge). Sourced after $T is set, with PYTHONPATH
# holding tests/cli.
MASKED_DIR=$(dirname "${BASH_SOURCE[0]}")

python3 - "$T" <<'PY'
import struct, sys, zlib
T = sys.argv[1]
def chunk(kind, data):
    return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
# 8x8 RGBA: white, alpha 0 in the left four columns (u < 1/2), 255 in the right four
rows = b''.join(b'\0' + b''.join(bytes((255, 255, 255, 0 if x < 4 else 255)) for x in range(8)) for _ in range(8))
with open(T + '/mask.png', 'wb') as f:
    f.write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', 8, 8, 8, 6, 0, 0, 0)) +
            chunk(b'IDAT', zlib.compress(rows)) + chunk(b'IEND', b''))
with open(T + '/black.pfm', 'wb') as f:
    f.write(b'PF\n64 32\n-1.0\n' + struct.pack('<' + 'f' * (3 * 64 * 32), *([0.0] * (3 * 64 * 32))))
PY
# the sun where the point light stands, seen from the floor's centre: elevation atan(5/4), towards -x
python3 "$MASKED_DIR/sun_sky.py" "$T/sun.pfm" 51.34 180

# scene NAME SKY LIGHTS: the floor, the masked quad over it, seen from the +x side
scene() {
    cat >"$T/$1.json" <<JSON
{"camera": {"eye": [5, -4, 3.5], "target": [0.8, 0, 0], "up": [0, 0, 1], "fovy": 45},
 "environment": {"hdr": "$T/$2.pfm"},
 "materials": {"floor": {"kd": 0.6, "ks": 0, "alpha": 10},
               "leaf": {"kd": 1, "ks": 0, "alpha": 10, "alpha_cutoff": 0.5,
                        "kd_map": {"file": "$T/mask.png", "srgb": true, "wrap": "clamp"}}},
 "objects": [{"shape": "plane", "material": "floor", "transform": {"scale": [4, 4, 1]}},
             {"shape": "plane", "material": "leaf", "transform": {"translate": [0, 0, 1]}}],
 "lights": [$3]}
JSON
}
scene point black '{"position": [-4, 0, 5], "color": "#ffffff", "intensity": 40}'
scene sun sun ''

# fates KIND AOV_DIR: each floor pixel's set from the AOV positions, as "CUT KEPT" index lists in
# $T/KIND.sets (pixel indices of the PFMs): the ray to the light (point: to (-4, 0, 5); sun: along
# each of the sun's two texel centres' directions, both required to agree) crosses z = 1 at
# |y| < 0.8 and 0.15 < |x| < 0.8
fates() {
    python3 - "$T" "$1" "$2" <<'PY'
import sys
from pfm import read_pfm
from sun_sky import sun_directions
T, kind, aov = sys.argv[1], sys.argv[2], sys.argv[3]
w, h, _, pos = read_pfm(aov + '/position.pfm')
_, _, _, nrm = read_pfm(aov + '/normal.pfm')
dirs = sun_directions(51.34, 180.0)  # the sun's two texels, as sun_sky.py lights them
def side(P, D):  # 'cut', 'kept' or None: where the ray from P along D crosses z = 1
    if D[2] <= 0:
        return None
    t = (1.0 - P[2]) / D[2]
    x, y = P[0] + t * D[0], P[1] + t * D[1]
    if abs(y) >= 0.8 or not 0.15 < abs(x) < 0.8:
        return None
    return 'cut' if x < 0 else 'kept'
cut, kept = [], []
for i in range(w * h):
    P = pos[3 * i:3 * i + 3]
    if abs(P[2]) > 1e-3 or nrm[3 * i + 2] < 0.99:  # the floor only
        continue
    if kind == 'point':
        L = (-4.0 - P[0], 0.0 - P[1], 5.0 - P[2])
        fate = {side(P, L)}
    else:
        fate = {side(P, D) for D in dirs}
    if fate == {'cut'}:
        cut.append(i)
    elif fate == {'kept'}:
        kept.append(i)
with open(T + '/' + kind + '.sets', 'w') as f:
    f.write(' '.join(map(str, cut)) + '\n' + ' '.join(map(str, kept)) + '\n')
PY
}

# judge KIND WITH.pfm WITHOUT.pfm: the sets' ratios (green): the cut-out half's >= 0.9 and the
# kept half's <= 0.1, each in >= 97% of its pixels, and each set at least 100 pixels; prints the
# shares, true when they hold
judge() {
    python3 - "$T/$1.sets" "$2" "$3" <<'PY'
import sys
from pfm import read_pfm
sets = [list(map(int, line.split())) for line in open(sys.argv[1])]
_, _, _, a = read_pfm(sys.argv[2]); _, _, _, b = read_pfm(sys.argv[3])
ratio = lambda i: a[3 * i + 1] / b[3 * i + 1] if b[3 * i + 1] > 1e-6 else 1.0
cut = sum(ratio(i) >= 0.9 for i in sets[0]) / max(len(sets[0]), 1)
kept = sum(ratio(i) <= 0.1 for i in sets[1]) / max(len(sets[1]), 1)
print("through the cut-out %d pixels, %.1f%% lit; under the kept half %d, %.1f%% shadowed"
      % (len(sets[0]), 100 * cut, len(sets[1]), 100 * kept))
sys.exit(0 if min(len(sets[0]), len(sets[1])) >= 100 and cut >= 0.97 and kept >= 0.97 else 1)
PY
}

