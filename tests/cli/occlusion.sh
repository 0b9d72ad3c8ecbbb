#!/usr/bin/env bash
# occlusion.sh BUILD_DIR - ambient occlusion from the command line (--ao-radius, docs/lighting.md
# "Ambient occlusion"): off by default and at 0 (the same bytes as without the option); on, it
# darkens the contact under pbr.json's sphere and nowhere brightens; trace reads the same
# occlusion the render wrote; bad radii are one line, exit 2; `softlight check` agrees with GL
# lighting softlight's occluded G-buffer (the GL twin of the pass itself: gl_occlusion.sh).
set -u
. "$(dirname "$0")/lib.bash"
cli_init occlusion "$1"
GL=${1}/softlight-gl
S=160x90

"$SL" render scenes/pbr.json --size $S -q --pfm "$T/off.pfm" --aov "$T/off"
"$SL" render scenes/pbr.json --size $S -q --ao-radius 0 --pfm "$T/zero.pfm"
cmp -s "$T/off.pfm" "$T/zero.pfm" && ok "--ao-radius 0: the same bytes as without it" || bad "--ao-radius 0 changed the image"
"$SL" render scenes/pbr.json --size $S -q --ao-radius 0.5 --pfm "$T/on.pfm" --aov "$T/on"
python3 - "$T" <<'PY' && ok "AO darkens the contact under the sphere and brightens nothing" || bad "AO's occlusion or radiance is wrong"
import struct, sys
def pfm(path):
    data = open(path, 'rb').read()
    parts = data.split(b'\n', 3)
    kind, (w, h), scale = parts[0], map(int, parts[1].split()), float(parts[2])
    ch = 3 if kind == b'PF' else 1
    return w, h, ch, struct.unpack(('<' if scale < 0 else '>') + 'f' * (w * h * ch), parts[3][:4 * w * h * ch])
T = sys.argv[1]
w, h, _, off = pfm(T + '/off/occlusion.pfm')
_, _, _, on = pfm(T + '/on/occlusion.pfm')
_, _, _, mask = pfm(T + '/on/mask.pfm')
_, _, _, ra = pfm(T + '/off.pfm')
_, _, _, rb = pfm(T + '/on.pfm')
covered = [i for i in range(w * h) if mask[i] > 0.5]
# AO multiplies: never above the map's occlusion; the floor under the sphere (image rows 70..80
# from the top are PFM rows 10..20 from the bottom, columns 40..60) is clearly darker
assert all(on[i] <= off[i] + 1e-6 for i in covered), "AO raised an occlusion"
contact = min(on[y * w + x] for y in range(10, 20) for x in range(40, 60))
assert contact < 0.6, "contact occlusion %.3f" % contact
assert all(rb[3 * i + c] <= ra[3 * i + c] + 1e-6 for i in covered for c in range(3)), "AO brightened a pixel"
print("contact occlusion %.3f; mean occlusion %.3f -> %.3f" % (contact, sum(off[i] for i in covered) / len(covered),
                                                            sum(on[i] for i in covered) / len(covered)))
PY
line=$("$SL" trace scenes/pbr.json --size $S --ao-radius 0.5 --pixel 50,75 | sed -n 's/^  occlusion *\([0-9.]*\).*/\1/p')
want=$(python3 -c "
import struct
d = open('$T/on/occlusion.pfm', 'rb').read().split(b'\n', 3); w, h = map(int, d[1].split())
v = struct.unpack(('<' if float(d[2]) < 0 else '>') + 'f' * (w * h), d[3][:4 * w * h])
print('%g' % v[(h - 1 - 75) * w + 50])")
python3 -c "import sys; sys.exit(abs(float('$line') - float('$want')) > 1e-5)" 2>/dev/null &&
    ok "trace's occlusion at 50,75 is the render's: $line" || bad "trace's occlusion '$line', the render's '$want'"
expect_error "negative radius" "--ao-radius" -- "$SL" render scenes/pbr.json --size $S --ao-radius -1 -o "$T/x.png"
expect_error "not a number" "--ao-radius" -- "$SL" render scenes/pbr.json --size $S --ao-radius abc -o "$T/x.png"
if [ -x "$GL" ] && "$GL" info >/dev/null 2>&1; then
    if "$SL" check scenes/pbr.json --size $S --ao-radius 0.5 >"$T/check.txt" 2>&1; then
        ok "softlight check with AO: $(grep '^PASS' "$T/check.txt")"
    else
        bad "softlight check with AO"; tail -3 "$T/check.txt"
    fi
else
    echo "skip the GL half: softlight-gl has no OpenGL here"
fi
cli_done occlusion
