#!/usr/bin/env bash
# occlusion.sh BUILD_DIR - ambient occlusion from the command line (--ao-radius, docs/lighting.md
# "Ambient occlusion"): off by default and at 0 (the same bytes as without the option, no cone
# files); on, it darkens the contact under pbr.json's sphere and nowhere brightens; the specular
# there is darkened by its own factor, the specular occlusion, far below the diffuse's AO; trace
# reads the same occlusion, AO, bent normal and specular occlusion the render used; bad radii are
# one line, exit 2; `softlight check` agrees with GL lighting softlight's occluded G-buffer (the
# GL twin of the pass itself: gl_occlusion.sh).
set -u
. "$(dirname "$0")/lib.bash"
cli_init occlusion "$1"
GL=${1}/softlight-gl
S=160x90

"$SL" render scenes/pbr.json --size $S -q --pfm "$T/off.pfm" --aov "$T/off"
"$SL" render scenes/pbr.json --size $S -q --ao-radius 0 --pfm "$T/zero.pfm"
cmp -s "$T/off.pfm" "$T/zero.pfm" && ok "--ao-radius 0: the same bytes as without it" || bad "--ao-radius 0 changed the image"
"$SL" render scenes/pbr.json --size $S -q --ao-radius 0.5 --pfm "$T/on.pfm" --aov "$T/on"
PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY' && ok "AO darkens the contact under the sphere and brightens nothing" || bad "AO's occlusion or radiance is wrong"
import struct, sys
from pfm import read_pfm as pfm
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
[ ! -e "$T/off/bent.pfm" ] && [ ! -e "$T/off/ao.pfm" ] && [ -e "$T/on/bent.pfm" ] && [ -e "$T/on/ao.pfm" ] &&
    ok "the cone's AOVs (bent.pfm, ao.pfm) only with AO on" || bad "the cone's AOVs with AO off, or none with it on"

# The specular alone, without and with AO: darkened at the contact far more than the AO there (the
# lobe's share in the visibility cone, not the cosine-weighted share), never brightened; trace's
# factors at a partly occluded floor pixel are the render's.
"$SL" render scenes/pbr.json --size $S -q --specular-only --no-lights --pfm "$T/soff.pfm"
"$SL" render scenes/pbr.json --size $S -q --specular-only --no-lights --ao-radius 0.5 --pfm "$T/son.pfm"
"$SL" trace scenes/pbr.json --size $S --ao-radius 0.5 --pixel 36,81 >"$T/trace.txt"
PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY' && ok "the contact's specular darkened by its own factor; trace's cone is the render's" || bad "specular occlusion"
import re, struct, sys
from pfm import read_pfm as pfm
T = sys.argv[1]
w, h, _, off = pfm(T + '/soff.pfm')
_, _, _, on = pfm(T + '/son.pfm')
_, _, _, occ = pfm(T + '/on/occlusion.pfm')
_, _, _, ao = pfm(T + '/on/ao.pfm')
_, _, _, bent = pfm(T + '/on/bent.pfm')
_, _, _, mask = pfm(T + '/on/mask.pfm')
assert all(on[k] <= off[k] + 1e-6 for k in range(3 * w * h) if mask[k // 3] > 0.5), "specular occlusion brightened"
contact = [(y, x) for y in range(10, 20) for x in range(40, 60)]
ratio = sum(on[3 * (y * w + x)] for y, x in contact) / sum(off[3 * (y * w + x)] for y, x in contact)
mean_occ = sum(occ[y * w + x] for y, x in contact) / len(contact)
print("contact: specular kept %.3f, AO %.3f" % (ratio, mean_occ))
assert ratio < 0.5 * mean_occ, "the contact's specular not darker than its AO"
t = open(T + '/trace.txt').read()
num = lambda name: float(re.search(r'^  %s +([-0-9.e]+)' % name, t, re.M).group(1))
i = (h - 1 - 81) * w + 36
so = num('spec occl')
got = on[3 * i] / off[3 * i]
print("pixel 36,81: trace AO %.5f spec occl %.5f; render AO %.5f specular kept %.5f" % (num('ao'), so, ao[i], got))
assert abs(num('ao') - ao[i]) < 1e-5 and 0.1 < so < 0.9 and abs(so - got) < 1e-4 * max(1.0, got)
b = [float(v) for v in re.search(r'^  bent normal +\(([^)]*)\)', t, re.M).group(1).split(',')]
assert all(abs(b[c] - bent[3 * i + c]) < 1e-4 for c in range(3)), "trace's bent normal"
PY
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
