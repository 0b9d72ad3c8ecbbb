#!/usr/bin/env bash
# lighting_programs.sh BUILD_DIR - lighting programs from the command line (--lighting,
# docs/lighting-programs.md): each example of examples/shaders compiles, loads and runs on a
# shipped scene and gives a sane image (every value finite, not black where the G-buffer is
# covered); a prebuilt shared object gives the same bytes as its source; the second run takes
# the cached object; a program's NaN is counted in one warning line and written as magenta; the
# trace prints the texel and the program's result.
set -u
SL=${1:?usage: $0 BUILD_DIR}/softlight
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-lprog.XXXXXX")
trap 'rm -rf "$T"' EXIT
export XDG_CACHE_HOME=$T/cache
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }
# sane IMAGE.pfm MASK.pfm: finite everywhere, and at least half the covered pixels not black
sane() {
    PYTHONPATH="$(dirname "$0")" python3 - "$1" "$2" <<'PY'
import math, struct, sys
from pfm import read_pfm as pfm
w, h, ch, img = pfm(sys.argv[1])
_, _, _, mask = pfm(sys.argv[2])
if not all(math.isfinite(v) for v in img):
    sys.exit("non-finite values")
covered = [i for i in range(w * h) if mask[i] > 0.5]
lit = [i for i in covered if max(img[3 * i:3 * i + 3]) > 0.0]
if not covered or len(lit) < len(covered) / 2:
    sys.exit("%d of %d covered pixels lit" % (len(lit), len(covered)))
PY
}
for ex in blinn_phong toon normals; do
    for scene in bunny default; do
        if ! "$SL" render "scenes/$scene.json" --size 96x64 -q --lighting "examples/shaders/$ex.c" \
            --pfm "$T/$ex-$scene.pfm" --aov "$T/aov-$ex-$scene" 2>"$T/err"; then
            fail "$ex on $scene: render failed: $(cat "$T/err")"; continue
        fi
        msg=$(sane "$T/$ex-$scene.pfm" "$T/aov-$ex-$scene/mask.pfm" 2>&1) || fail "$ex on $scene: $msg"
    done
done
[ "$fails" -eq 0 ] && echo "ok   the examples load, run and give sane images"

# the cache: the second run compiles nothing
"$SL" render scenes/bunny.json --size 32x24 -q -v --lighting examples/shaders/toon.c --pfm "$T/a.pfm" 2>"$T/v"
grep -q "cached" "$T/v" && ! grep -q " -shared " "$T/v" || fail "a second run did not take the cached object: $(cat "$T/v")"
ls "$T/cache/softlight/"*.so >/dev/null 2>&1 || fail "no object in \$XDG_CACHE_HOME/softlight"

# a prebuilt object: the same bytes
cc -std=c11 -shared -fPIC -O2 -fno-math-errno -fno-trapping-math -ffp-contract=off -Iinclude -o "$T/toon.so" examples/shaders/toon.c -lm ||
    fail "cc examples/shaders/toon.c"
"$SL" render scenes/bunny.json --size 32x24 -q --lighting "$T/toon.so" --pfm "$T/b.pfm" || fail "the prebuilt object"
cmp -s "$T/a.pfm" "$T/b.pfm" || fail "the prebuilt object's image differs from its source's"

# NaN: counted, one warning line, magenta, exit 0
cat >"$T/nan.c" <<'C'
#include <math.h>
#include <softlight/lighting.h>
static sl_vec3 shade(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *r, const sl_lighting_texel_in *in)
{
    (void)u; (void)r;
    float v = in->texel->depth < 1.0f ? NAN : 0.25f;
    return (sl_vec3){v, v, v};
}
SL_LIGHTING_PROGRAM("nan", shade, NULL);
C
if "$SL" render scenes/bunny.json --size 32x24 -q --lighting "$T/nan.c" --pfm "$T/nan.pfm" --aov "$T/aov-nan" 2>"$T/err"; then
    [ "$(grep -c 'NaN/Inf' "$T/err")" = 1 ] && grep -q "nan.c: [0-9]* pixels had NaN/Inf radiance (written as magenta)" "$T/err" ||
        fail "NaN: expected one warning line naming the file and the count, got: $(cat "$T/err")"
    python3 - "$T/nan.pfm" <<'PY' || fail "NaN: the image is not finite, or has no magenta"
import math, struct, sys
d = open(sys.argv[1], 'rb').read().split(b'\n', 3)
w, h = map(int, d[1].split())
v = struct.unpack('<' + 'f' * (3 * w * h), d[3][:12 * w * h])
assert all(math.isfinite(x) for x in v)
assert any(v[i:i + 3] == (1.0, 0.0, 1.0) for i in range(0, len(v), 3))
PY
else
    fail "NaN: render failed: $(cat "$T/err")"
fi

# trace: the texel and the result
"$SL" trace scenes/bunny.json --size 96x64 --lighting examples/shaders/blinn_phong.c -p 48,40 >"$T/trace" 2>&1 ||
    fail "trace failed: $(cat "$T/trace")"
grep -q "lighting program blinn-phong" "$T/trace" && grep -q "G-buffer texel" "$T/trace" && grep -q "returned" "$T/trace" ||
    fail "trace: no texel or result: $(cat "$T/trace")"
[ "$fails" -eq 0 ] && echo "ok   cache, prebuilt object, NaN report, trace"
exit $((fails > 0))
