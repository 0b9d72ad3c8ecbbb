#!/usr/bin/env bash
# gbuffer_programs.sh BUILD_DIR - G-buffer fragment programs from the command line
# (--gbuffer-shader, docs/gbuffer-programs.md), on softlight alone (no GL):
# - examples/shaders/checker.c on a receding plane: where a checker cell is at least 4 pixels
#   wide, a pixel away from a cell's edge has exactly one of the two tones, the one its cell's
#   parity picks (the cell computed from the position AOV); where the pixel's footprint covers a
#   whole period of the pattern (the far plane), kd is the two tones' mean, not either tone (the
#   fwidth filter: an unfiltered checker would alias there); and the built-in program's kd is the
#   material's (1, 1, 1) everywhere, so the program is what made the pattern. The plane's kd map
#   (white, uv_scale 20) reaches the program: it scales the pattern's coordinate.
# - a program that discards (after a derivative) and writes the extra channels, on pbr.json.
# - a program that writes GGX lobes on Phong materials is lit with the GGX set (the split sum).
# - the per-pixel reference path (--plain) draws the G-buffer the tiled path draws.
# - the second run takes the cached object; a prebuilt shared object gives the same bytes; -v
#   shows the compiler command, with -g -O0 under --debug-shader; trace names the program and
#   prints its texel; gdb stops in the program's function (skipped without gdb).
set -u
. "$(dirname "$0")/lib.bash"
cli_init gbprog "$@"
export XDG_CACHE_HOME=$T/cache

# the scene: a 40 x 40 plane seen from 1.5 above, receding to the horizon; a white 4x4 kd map
python3 - "$T" <<'PY'
import json, struct, sys, zlib
d = sys.argv[1]
def chunk(kind, data):
    return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
rows = b''.join(b'\0' + b'\xff' * 12 for _ in range(4))
png = (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', 4, 4, 8, 2, 0, 0, 0)) +
       chunk(b'IDAT', zlib.compress(rows)) + chunk(b'IEND', b''))
open(d + '/white.png', 'wb').write(png)
scene = {
    "camera": {"eye": [0, -8, 1.5], "target": [0, 6, 0], "up": [0, 0, 1], "fovy": 50, "near": 0.1, "far": 100},
    "materials": {"plane": {"kd": 1, "ks": 0.04, "alpha": 20,
                            "kd_map": {"file": "white.png", "uv_scale": [20, 20]}}},
    "objects": [{"name": "plane", "shape": "plane", "material": "plane", "transform": {"scale": [20, 20, 1]}}],
    "render": {"width": 320, "height": 180, "samples": 4, "exposure": 1, "contrast": 1},
}
json.dump(scene, open(d + '/plane.json', 'w'))
PY

if "$SL" render "$T/plane.json" -q --gbuffer-shader examples/shaders/checker.c --aov "$T/checker" \
    --pfm "$T/checker.pfm" 2>"$T/err" && "$SL" render "$T/plane.json" -q --aov "$T/builtin" 2>>"$T/err"; then
    if PYTHONPATH="$(dirname "$0")" python3 - "$T" >"$T/check" 2>&1 <<'PY'; then
import math, struct, sys
d = sys.argv[1]
from pfm import read_pfm as pfm
w, h, _, pos = pfm(d + '/checker/position.pfm')
_, _, _, kd = pfm(d + '/checker/kd.pfm')
_, _, _, mask = pfm(d + '/checker/mask.pfm')
_, _, _, kd0 = pfm(d + '/builtin/kd.pfm')
A, B = (0.85, 0.80, 0.70), (0.10, 0.12, 0.16)
mean = tuple(0.5 * (a + b) for a, b in zip(A, B))
# the pattern's coordinate: object x = X / 20, u = (x + 1) / 2, times uv_scale 20, times 8 cells
def p(i):
    return ((pos[3 * i] / 20 + 1) / 2 * 160, (pos[3 * i + 1] / 20 + 1) / 2 * 160)
sharp = sharp_ok = flat = flat_ok = 0
worst_sharp = worst_flat = 0.0
for y in range(h - 1):
    for x in range(w - 1):
        i, ix, iy = y * w + x, y * w + x + 1, (y + 1) * w + x
        if not (mask[i] > 0.5 and mask[ix] > 0.5 and mask[iy] > 0.5):
            continue
        (px, py), (qx, qy), (rx, ry) = p(i), p(ix), p(iy)
        fw = (abs(qx - px) + abs(rx - px), abs(qy - py) + abs(ry - py))  # fwidth of the coordinate
        k = kd[3 * i:3 * i + 3]
        if max(fw) < 0.25:
            edge = min(abs(px - round(px)), abs(py - round(py)))
            if edge > 2 * max(fw):
                want = A if (math.floor(px) + math.floor(py)) % 2 == 0 else B
                e = max(abs(a - b) for a, b in zip(k, want))
                worst_sharp = max(worst_sharp, e)
                sharp += 1
                sharp_ok += e < 0.01
        elif min(fw) > 2.5:
            e = max(abs(a - b) for a, b in zip(k, mean))
            worst_flat = max(worst_flat, e)
            flat += 1
            flat_ok += e < 0.02
print("sharp pixels %d (%d of the parity's tone, worst %.4g); whole-period pixels %d (%d at the mean, worst %.4g)"
      % (sharp, sharp_ok, worst_sharp, flat, flat_ok, worst_flat))
assert sharp > 1000 and sharp_ok == sharp, "the checker's cells"
assert flat > 200 and flat_ok == flat, "the filtered far plane"
builtin = [i for i in range(w * h) if mask[i] > 0.5 and kd0[3 * i:3 * i + 3] != (1.0, 1.0, 1.0)]
assert not builtin, "%d built-in texels with kd other than (1, 1, 1)" % len(builtin)
PY
        ok "checker.c: $(head -1 "$T/check")"
    else
        bad "checker.c: $(cat "$T/check")"
    fi
else
    bad "render failed: $(cat "$T/err")"
fi

# discard and the extra channels: cutout.c discards the stripes where fract(4 x) < 0.5 (after a
# derivative, as the quad rounds must handle) and writes occlusion 0.5 and emission (1, 0.25, 0);
# on scenes/pbr.json (the extra plane) every covered pixel must be a kept stripe with those extra
# values, the built-in covers more, and alpha says the derivative was seen (7 where fwidth > 0)
cat >"$T/cutout.c" <<'C'
#include <softlight/glsl.h>
#include <softlight/gbuffer_program.h>

static void cutout(const sl_gbuffer_material *u, const sl_fragment_in *in, sl_gbuffer_texel *out,
                   sl_gbuffer_extra *extra)
{
    sl_gbuffer_varyings v = sl_gbuffer_varyings_of(in);
    float w = fwidth(in, v.vWorldPos.x);
    float s = v.vWorldPos.x * 4.0f;
    if (s - floorf(s) < 0.5f) {
        discard(in);
        return;
    }
    out->position = v.vWorldPos;
    out->normal = dot(v.vNormal, v.vNormal) > 1e-30f ? normalize(v.vNormal) : vec3(0, 0, 1);
    out->kd = u->uKd;
    out->ks = u->uKs;
    out->alpha = w > 0.0f ? 7.0f : 3.0f;
    extra->occlusion = 0.5f;
    extra->emissive = vec3(1.0f, 0.25f, 0.0f);
}

SL_GBUFFER_PROGRAM("cutout", cutout, SL_GBUFFER_DERIVATIVES | SL_GBUFFER_DISCARDS);
C
if "$SL" render scenes/pbr.json --size 160x90 -q --gbuffer-shader "$T/cutout.c" --aov "$T/cut" 2>"$T/err" &&
    "$SL" render scenes/pbr.json --size 160x90 -q --aov "$T/cut0" 2>>"$T/err"; then
    if python3 - "$T" >"$T/check" 2>&1 <<'PY'; then
import math, struct, sys
d = sys.argv[1]
def pfm(path):
    data = open(path, 'rb').read()
    parts = data.split(b'\n', 3)
    ch = 3 if parts[0] == b'PF' else 1
    w, h = map(int, parts[1].split())
    return struct.unpack(('<' if float(parts[2]) < 0 else '>') + 'f' * (w * h * ch), parts[3][:4 * w * h * ch])
pos, mask, occ, em, alpha = (pfm(d + '/cut/' + n + '.pfm') for n in ('position', 'mask', 'occlusion', 'emissive', 'alpha'))
mask0 = pfm(d + '/cut0/mask.pfm')
covered = [i for i in range(len(mask)) if mask[i] > 0.5]
cut = [i for i in covered if (4 * pos[3 * i]) - math.floor(4 * pos[3 * i]) < 0.5]
extra = [i for i in covered if occ[i] != 0.5 or em[3 * i:3 * i + 3] != (1.0, 0.25, 0.0)]
seen = sum(alpha[i] == 7.0 for i in covered)
print("%d covered (built-in %d), %d in a discarded stripe, %d with other extra values, %d saw fwidth > 0"
      % (len(covered), sum(m > 0.5 for m in mask0), len(cut), len(extra), seen))
assert covered and not cut and not extra and sum(m > 0.5 for m in mask0) > len(covered) + 1000
assert seen > 0.95 * len(covered)
PY
        ok "cutout.c: $(cat "$T/check")"
    else
        bad "cutout.c: $(cat "$T/check")"
    fi
else
    bad "cutout.c: render failed: $(cat "$T/err")"
fi

# lobes the materials do not have: asggx.c writes GGX of roughness 0.3 on default.json, whose
# materials are all Phong; default.json with every material GGX 0.3 under the built-in program is
# the same G-buffer, so the split sum (which prefilters a chain per lobe set) must light it to the
# same image, bit for bit: the program's frame must prepare the GGX chain too
cat >"$T/asggx.c" <<'C'
#include <softlight/glsl.h>
#include <softlight/gbuffer_program.h>

static void asggx(const sl_gbuffer_material *u, const sl_fragment_in *in, sl_gbuffer_texel *out,
                  sl_gbuffer_extra *extra)
{
    (void)extra;
    sl_gbuffer_varyings v = sl_gbuffer_varyings_of(in);
    out->position = v.vWorldPos;
    out->normal = dot(v.vNormal, v.vNormal) > 1e-30f ? normalize(v.vNormal) : vec3(0, 0, 1);
    out->kd = u->uKd;
    out->ks = u->uKs;
    out->alpha = -1.0f - 0.3f;
}

SL_GBUFFER_PROGRAM("asggx", asggx, 0);
C
python3 - "$T" <<'PY'
import json, os, sys
s = json.load(open('scenes/default.json'))
for m in s['materials'].values():
    m.pop('alpha', None)
    m.update({'brdf': 'ggx', 'roughness': 0.3})
s['environment']['hdr'] = os.path.abspath(os.path.join('scenes', s['environment']['hdr']))
json.dump(s, open(sys.argv[1] + '/ggx.json', 'w'))
PY
"$SL" render scenes/default.json --size 96x64 -q --estimator splitsum --gbuffer-shader "$T/asggx.c" \
    --pfm "$T/asggx.pfm" --aov "$T/asggx"
"$SL" render "$T/ggx.json" --size 96x64 -q --estimator splitsum --pfm "$T/ggx.pfm" --aov "$T/ggx"
if cmp -s "$T/asggx/alpha.pfm" "$T/ggx/alpha.pfm" && cmp -s "$T/asggx/kd.pfm" "$T/ggx/kd.pfm" &&
    cmp -s "$T/asggx.pfm" "$T/ggx.pfm"; then
    ok "GGX lobes on Phong materials: the split sum's image is the GGX materials' one, bit for bit"
else
    bad "GGX lobes on Phong materials: $("$SL" compare "$T/asggx.pfm" "$T/ggx.pfm" | grep -m1 '^max abs')"
fi

# the rasterizer's per-pixel reference path (--plain) and the tiled one draw the same G-buffer
"$SL" render scenes/textured.json --size 160x90 -q --gbuffer-shader examples/shaders/checker.c --aov "$T/tiled"
"$SL" render scenes/textured.json --size 160x90 -q --plain --gbuffer-shader examples/shaders/checker.c --aov "$T/plain"
same=0
for f in position normal kd ks alpha depth; do cmp -s "$T/tiled/$f.pfm" "$T/plain/$f.pfm" && same=$((same + 1)); done
if [ "$same" -eq 6 ]; then ok "--plain and the tiled path: the same G-buffer, bit for bit"; else bad "--plain: $((6 - same)) channels differ"; fi

# the cache: the second run compiles nothing; -v names the object
"$SL" render "$T/plane.json" -q -v --size 64x36 --gbuffer-shader examples/shaders/checker.c --pfm "$T/a.pfm" 2>"$T/v"
if grep -q "cached" "$T/v" && ! grep -q " -shared " "$T/v"; then
    ok "a second run takes the cached object"
else
    bad "a second run compiled again: $(cat "$T/v")"
fi
# --debug-shader -v: the command, with -g -O0
"$SL" render "$T/plane.json" -q -v --debug-shader --size 64x36 --gbuffer-shader examples/shaders/checker.c \
    --pfm "$T/d.pfm" 2>"$T/v"
if grep -q " -shared .* -g -O0 .*checker\.c" "$T/v"; then
    ok "--debug-shader -v prints the compiler command with -g -O0"
else
    bad "--debug-shader -v: $(cat "$T/v")"
fi

# a prebuilt object: the same bytes as its source
if cc -std=c11 -shared -fPIC -O2 -fno-math-errno -fno-trapping-math -ffp-contract=off -Iinclude -o "$T/checker.so" \
    examples/shaders/checker.c -lm && "$SL" render "$T/plane.json" -q --size 64x36 --gbuffer-shader "$T/checker.so" \
    --pfm "$T/b.pfm" && cmp -s "$T/a.pfm" "$T/b.pfm"; then
    ok "a prebuilt shared object gives its source's image"
else
    bad "the prebuilt object's image differs from its source's (or it did not build or load)"
fi

# trace: the program is named, and the texel is its (the far plane: the two tones' mean)
"$SL" trace "$T/plane.json" -p 160,80 --gbuffer-shader examples/shaders/checker.c >"$T/trace" 2>&1
if grep -q "G-buffer program: checker (examples/shaders/checker.c)" "$T/trace" &&
    grep -q "^  kd  *(0.475, 0.46, 0.43)" "$T/trace"; then
    ok "trace names the program and prints its texel: $(grep -m1 '^  kd' "$T/trace" | tr -s ' ')"
else
    bad "trace: $(head -5 "$T/trace"; tail -1 "$T/trace")"
fi
# gdb: the documented command stops in the user's own function, at the pixel asked for
if command -v gdb >/dev/null; then
    gdb -batch -nx -ex "set breakpoint pending on" -ex "break checker if in->x == 32 && in->y == 5" -ex run \
        -ex "print in->x" --args "$SL" trace scenes/textured.json --size 64x36 \
        --gbuffer-shader examples/shaders/checker.c --debug-shader -p 32,30 >"$T/gdb.log" 2>&1
    if grep -Eq "Breakpoint 1, checker \(.*\) at examples/shaders/checker\.c:[0-9]+" "$T/gdb.log" &&
        grep -q "^\$1 = 32" "$T/gdb.log"; then
        ok "gdb stopped in checker (examples/shaders/checker.c) at x 32"
    else
        bad "gdb did not stop in checker: $(grep -m3 -E 'Breakpoint|^\$1|rror' "$T/gdb.log")"
    fi
else
    echo "skip gdb: not installed"
fi
cli_done gbuffer_programs
