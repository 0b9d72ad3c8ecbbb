#!/usr/bin/env bash
# reflection_occlusion.sh BUILD_DIR - reflection occlusion (--reflection-occlusion D,
# src/occlusion/reflection.h) from the command line, on a mirror-like floor beside a wall 1 tall
# under a constant white environment, the image-based specular alone:
#   - the floor's mirror rays that hit the wall well within D (found here from the AOV positions
#     and the box's geometry) go dark: at least 90% of those pixels under 0.1 of the image
#     without the option; the rays that pass over the wall, miss its ends or reach it far beyond
#     D leave at least 99% of their pixels unchanged (ratio 1 within 1e-6);
#   - --reflection-occlusion 0 gives the same bytes as no option, and the scene key
#     render.reflection_occlusion the same bytes as the flag;
#   - render prints its line; trace prints the reflection line: 0 in the wall's reflection, 1
#     far from it; and the facet line, the floor's +Z;
#   - bad values (negative, nan, over 1e6, the key as a string) are one line, status 2.
set -euo pipefail
. "$(dirname "$0")/lib.bash"
cli_init reflection_occlusion "$1"

python3 - "$T/white.pfm" <<'PY'
import struct, sys
w, h = 64, 32
with open(sys.argv[1], 'wb') as f:
    f.write(b'PF\n%d %d\n-1.0\n' % (w, h))
    f.write(struct.pack('<' + 'f' * (3 * w * h), *([1.0] * (3 * w * h))))
PY
# scene WALL_MATERIAL_AND_RENDER_EXTRA: the floor (a mirror) and the wall, x in [-0.1, 0.1],
# y in [-3, 3], z in [0, 1]; the camera on the +x side, looking down at the floor before it
scene() {
    cat <<JSON
{"camera": {"eye": [5, -1.5, 2.5], "target": [0.8, 0, 0.2], "up": [0, 0, 1], "fovy": 50},
 "environment": {"hdr": "$T/white.pfm"},
 "materials": {"wall": {"kd": 1, "ks": 0, "alpha": 10}, "floor": {"kd": 0, "ks": 0.9, "alpha": 10000}},
 "objects": [{"shape": "plane", "material": "floor", "transform": {"scale": [3, 3, 1]}},
             {"shape": "box", "material": "wall", "transform": {"translate": [0, 0, 0.5], "scale": [0.1, 3, 0.5]}}],
 "render": {"samples": 1$1}}
JSON
}
scene "" >"$T/mirror.json"
scene ', "reflection_occlusion": 4' >"$T/keyed.json"
scene ', "reflection_occlusion": "4"' >"$T/string.json"
W=160 H=90
R="--size ${W}x$H --specular-only --no-lights --estimator mf --lod pdf --distortion -n 16"

"$SL" render "$T/mirror.json" $R -q --pfm "$T/off.pfm" --aov "$T/aov" || bad "render without the option"
"$SL" render "$T/mirror.json" $R --reflection-occlusion 4 --pfm "$T/on.pfm" >"$T/on.txt" || bad "render with it"
grep -q "^reflection occlusion: rays 4 world units long, .* ms a frame (5 rays x 16 steps; [0-9]* texels, at edges and where the normal turns fast, traced their own 5)$" "$T/on.txt" &&
    ok "render prints: $(grep "^reflection occlusion" "$T/on.txt")" || bad "render's line: $(cat "$T/on.txt")"
"$SL" render "$T/mirror.json" $R -q --reflection-occlusion 0 --pfm "$T/zero.pfm" || bad "render at 0"
cmp -s "$T/off.pfm" "$T/zero.pfm" && ok "--reflection-occlusion 0: the same bytes as without it" ||
    bad "--reflection-occlusion 0 changed the image"
"$SL" render "$T/keyed.json" $R -q --pfm "$T/keyed.pfm" || bad "render with the scene key"
cmp -s "$T/on.pfm" "$T/keyed.pfm" && ok "render.reflection_occlusion 4: the same bytes as the flag" ||
    bad "render.reflection_occlusion 4 differs from the flag"

# The floor pixels' fates from the AOV positions: the mirror ray R = reflect(P - E) about +z from
# floor point P; BLOCKED when it hits the wall's face x = 0.1 within 0.7 D, 0.15 inside its edges
# and in the image; OPEN when it moves away from the wall, passes 0.15 over it or beyond its
# ends, or hits it beyond 1.5 D. Writes the ratios' shares, and a pixel of each set for trace
# (X,Y with Y from the top) in $T/pixels.
PYTHONPATH="$(dirname "$0")" python3 - "$T" $W $H <<'PY' && ok "$(cat "$T/shares.txt")" || bad "$(cat "$T/shares.txt")"
import math, sys
from pfm import read_pfm
T, W, H = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
D, E, target, fovy = 4.0, (5.0, -1.5, 2.5), (0.8, 0.0, 0.2), 50.0
_, _, _, off = read_pfm(T + '/off.pfm')
_, _, _, on = read_pfm(T + '/on.pfm')
_, _, _, pos = read_pfm(T + '/aov/position.pfm')
_, _, _, nrm = read_pfm(T + '/aov/normal.pfm')
sub = lambda a, b: tuple(x - y for x, y in zip(a, b))
dot = lambda a, b: sum(x * y for x, y in zip(a, b))
unit = lambda a: tuple(x / math.sqrt(dot(a, a)) for x in a)
cross = lambda a, b: (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
fwd = unit(sub(target, E))
right = unit(cross(fwd, (0.0, 0.0, 1.0)))
up = cross(right, fwd)
tan_y = math.tan(math.radians(fovy) / 2)

def in_image(p):
    d = sub(p, E)
    z = dot(d, fwd)
    return z > 0 and abs(dot(d, right) / z) < tan_y * W / H and abs(dot(d, up) / z) < tan_y

def fate(P):
    d = unit(sub(P, E))
    Rx, Ry, Rz = d[0], d[1], -d[2]
    if Rx >= 0:
        return 'open'
    t = (0.1 - P[0]) / Rx
    y, z = P[1] + Ry * t, Rz * t
    if z > 1.15 or abs(y) > 3.15 or t > 1.5 * D:
        return 'open'
    if z < 0.85 and abs(y) < 2.85 and t < 0.7 * D and in_image((0.1, y, z)):
        return 'blocked'
    return None

sets = {'blocked': [], 'open': []}
for row in range(H):
    for x in range(W):
        i = 3 * (row * W + x)
        P = pos[i:i + 3]
        if nrm[i + 2] < 0.9 or abs(P[2]) > 1e-3 or P[0] < 0.1 or off[i + 1] <= 0:
            continue
        f = fate(P)
        if f:
            sets[f].append((on[i + 1] / off[i + 1], x, H - 1 - row))
dark = sum(r < 0.1 for r, _, _ in sets['blocked'])
same = sum(abs(r - 1) <= 1e-6 for r, _, _ in sets['open'])
nb, no = len(sets['blocked']), len(sets['open'])
text = "ratio with/without: %d of %d floor pixels reflecting the wall under 0.1, %d of %d others unchanged" % (
    dark, nb, same, no)
open(T + '/shares.txt', 'w').write(text)
# for trace: the blocked pixel nearest the set's middle, an open one far from the wall
mid = sorted(sets['blocked'], key=lambda s: s[1])[nb // 2] if nb else (0, 0, 0)
far = max(sets['open'], key=lambda s: pos[3 * ((H - 1 - s[2]) * W + s[1])]) if no else (0, 0, 0)
open(T + '/pixels', 'w').write("%d,%d %d,%d\n" % (mid[1], mid[2], far[1], far[2]))
sys.exit(not (nb > 300 and no > 300 and dark >= 0.9 * nb and same >= 0.99 * no))
PY

# trace: the reflection line, 0 in the wall's reflection (below 0.2), 1 far from it
read -r blocked open_px <"$T/pixels"
reflection_of() {
    "$SL" trace "$T/mirror.json" $R --reflection-occlusion 4 --pixel "$1" >"$T/trace.txt" || true
    sed -n 's/^  reflection   \([0-9.e+-]*\).*/\1/p' "$T/trace.txt"
}
v=$(reflection_of "$blocked")
python3 -c "import sys; sys.exit(not (0 <= float('${v:-nan}') < 0.2))" &&
    ok "trace at $blocked (the wall's reflection): reflection $v" || bad "trace at $blocked: reflection '$v' (want < 0.2)"
v=$(reflection_of "$open_px")
[ "$v" = "1" ] && ok "trace at $open_px (far from it): reflection $v" || bad "trace at $open_px: reflection '$v' (want 1)"
# and the floor's facet (the drawn triangle's normal), +Z within 1e-5
facet=$(sed -n 's/^  facet        (\([^)]*\)).*/\1/p' "$T/trace.txt")
python3 -c "import sys; v = [float(c) for c in '${facet:-nan, nan, nan}'.split(',')]; sys.exit(not (abs(v[0]) < 1e-5 and abs(v[1]) < 1e-5 and abs(v[2] - 1) < 1e-5))" &&
    ok "trace at $open_px: the floor's facet ($facet)" || bad "trace at $open_px: facet '$facet' (want 0, 0, 1)"

expect_error "negative" "reflection-occlusion" -- "$SL" render "$T/mirror.json" --size 16x9 --reflection-occlusion -1 -o "$T/x.png"
expect_error "nan" "reflection-occlusion" -- "$SL" render "$T/mirror.json" --size 16x9 --reflection-occlusion nan -o "$T/x.png"
expect_error "over 1e6" "reflection-occlusion" -- "$SL" render "$T/mirror.json" --size 16x9 --reflection-occlusion 1e7 -o "$T/x.png"
expect_error "the key as a string" "reflection_occlusion" -- "$SL" render "$T/string.json" --size 16x9 -o "$T/x.png"
cli_done reflection_occlusion
