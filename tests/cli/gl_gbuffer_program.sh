#!/usr/bin/env bash
# gl_gbuffer_program.sh BUILD_DIR - a G-buffer program and its GLSL twin agree:
# `softlight render --gbuffer-shader examples/shaders/checker.c --aov` against
# `softlight-gl render --gbuffer-shader examples/shaders/checker.frag --aov`, channel by channel
# (tests/cli/gbuffer_diff.py), on scenes/textured.json (every material's uniforms and kd maps, a
# masked leaf the program does not discard), on scenes/pbr.json (the extra plane, which neither
# writes) and on a plane receding to the horizon (the fwidth filter from magnified cells to many
# cells a pixel); a program that discards and writes the extra channels (oExtra) against its
# GLSL twin; one that writes GGX lobes on a scene of Phong materials, through the lighting; and
# checker with the toon lighting program (--lighting), C against GLSL.
# And softlight-gl's refusals: a GLSL compile error (file:line), a missing file, a directory,
# --gbuffer-shader with --gbuffer, each one line and exit 2.
#
# Bounds, and why (measured at 320x180 on llvmpipe, the figures in docs/gbuffer-programs.md):
# - coverage identical, depth within 1e-5 (gl_raster.sh's bounds; the same vertex shader).
# - ks and alpha exact: the program writes the material's constants.
# - kd: the pattern is a function of the uv and of its fwidth, both from the interpolated
#   varyings; both sides take fine derivatives the same way (dFdx as llvmpipe: the pixel's own
#   row of the quad), so the differences are float rounding of the uv and its differences,
#   through a filter whose slope is 1 / footprint (at most 1e4 where a cell edge is magnified),
#   and the kd maps' filtering on textured.json (its sRGB mips, gl_textured.sh: up to 0.0091).
#   Measured on textured.json: objects max 0.0073, 1.4% over 1/255; floor max 0.0030, none over
#   1/255. On pbr.json's objects: max 0.0073, 2.2% over 1/255. On the plane: max 0.0005, none over 1/255. Bounds: 0.02 and 3% (textured.json's
#   objects), 0.01 and 1% (its floor, and the plane).
# - position and normal: the plain varyings; on textured.json one pixel at the sphere's depth tie
#   (gl_raster.sh) is 0.007 apart: bound 0.01, share 0.1%.
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"
export XDG_CACHE_HOME=$T/cache
fail=0

# render_both LABEL SCENE: both programs' AOVs, the differences in $T/LABEL.txt
render_both() {
    local label=$1 scene=$2
    "$SL" render "$scene" --size "$GL_TEST_SIZE" --samples 4 -q --gbuffer-shader examples/shaders/checker.c \
        --aov "$T/$label-c" --pfm "$T/$label-c.pfm"
    "$GL" render "$scene" --size "$GL_TEST_SIZE" --samples 4 --gbuffer-shader examples/shaders/checker.frag \
        --aov "$T/$label-g" --pfm "$T/$label-g.pfm" >/dev/null
    "$SL" compare "$T/$label-c/mask.pfm" "$T/$label-g/mask.pfm" --metric max --tolerance 0 >/dev/null ||
        { echo "FAIL $label: coverage differs"; fail=1; }
    python3 tests/cli/gbuffer_diff.py "$T/$label-c" "$T/$label-g" >"$T/$label.txt"
    echo "$label: channel group pixels max share>1/255"
    sed 's/^/  /' "$T/$label.txt"
}

render_both textured scenes/textured.json
for group in objects floor; do
    gl_bound "$T/textured.txt" depth "$group" 1e-5 0
    gl_bound "$T/textured.txt" ks "$group" 0 0
    gl_bound "$T/textured.txt" alpha "$group" 0 0
    gl_bound "$T/textured.txt" position "$group" 0.01 0.001
    gl_bound "$T/textured.txt" normal "$group" 0.01 0.001
done
gl_bound "$T/textured.txt" kd objects 0.02 0.03
gl_bound "$T/textured.txt" kd floor 0.01 0.01

# pbr.json: a scene with the extra plane (occlusion, emission); checker.frag has no oExtra and
# checker.c leaves *extra alone, so both leave the plane "none": exactly the same
render_both pbr scenes/pbr.json
for group in objects floor; do
    gl_bound "$T/pbr.txt" occlusion "$group" 0 0
    gl_bound "$T/pbr.txt" emissive "$group" 0 0
done
gl_bound "$T/pbr.txt" kd objects 0.02 0.03

# discard and oExtra: a program that discards stripes of world x after a derivative and writes
# the extra channels, in C and GLSL, on pbr.json: the same coverage (the stripes' edges are
# compared on the same interpolated x: measured identical), the same extra values
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
cat >"$T/cutout.frag" <<'GLSL'
#version 330 core
in vec3 vWorldPos;
in vec3 vNormal;
uniform vec3 uKd;
uniform vec3 uKs;
layout(location = 0) out vec4 oPosition;
layout(location = 1) out vec4 oNormal;
layout(location = 2) out vec4 oKd;
layout(location = 3) out vec4 oKsAlpha;
layout(location = 4) out vec4 oExtra;
void main()
{
    float w = fwidth(vWorldPos.x);
    float s = vWorldPos.x * 4.0;
    if (s - floor(s) < 0.5)
        discard;
    oPosition = vec4(vWorldPos, 1.0);
    oNormal = vec4(dot(vNormal, vNormal) > 1e-30 ? normalize(vNormal) : vec3(0.0, 0.0, 1.0), 0.0);
    oKd = vec4(uKd, 0.0);
    oKsAlpha = vec4(uKs, w > 0.0 ? 7.0 : 3.0);
    oExtra = vec4(0.5, 1.0, 0.25, 0.0);
}
GLSL
"$SL" render scenes/pbr.json --size "$GL_TEST_SIZE" --samples 4 -q --gbuffer-shader "$T/cutout.c" --aov "$T/cut-c"
"$GL" render scenes/pbr.json --size "$GL_TEST_SIZE" --samples 4 --gbuffer-shader "$T/cutout.frag" --aov "$T/cut-g" >/dev/null
"$SL" compare "$T/cut-c/mask.pfm" "$T/cut-g/mask.pfm" --metric max --tolerance 0 >/dev/null ||
    { echo "FAIL cutout: coverage differs"; fail=1; }
python3 tests/cli/gbuffer_diff.py "$T/cut-c" "$T/cut-g" >"$T/cut.txt"
echo "cutout (pbr.json): channel group pixels max share>1/255"
sed 's/^/  /' "$T/cut.txt"
for group in objects floor; do
    for channel in occlusion emissive kd ks alpha; do
        gl_bound "$T/cut.txt" "$channel" "$group" 0 0
    done
done

# lobes the materials do not have: glossy.c writes a GGX lobe on every surface of default.json,
# whose materials are all Phong. The lighting must prepare both lobe sets (the split sum's
# prefiltered chains, the GL lighting program's specialization), else GGX texels are lit with the
# Phong set's chain: the images, spec and split sum, must agree (measured: no pixel over 8/255)
cat >"$T/glossy.c" <<'C'
#include <softlight/glsl.h>
#include <softlight/gbuffer_program.h>

static void glossy(const sl_gbuffer_material *u, const sl_fragment_in *in, sl_gbuffer_texel *out,
                   sl_gbuffer_extra *extra)
{
    (void)extra;
    sl_gbuffer_varyings v = sl_gbuffer_varyings_of(in);
    out->position = v.vWorldPos;
    out->normal = dot(v.vNormal, v.vNormal) > 1e-30f ? normalize(v.vNormal) : vec3(0, 0, 1);
    out->kd = scale(u->uKd, 0.5f);
    out->ks = vec3(0.9f, 0.9f, 0.9f);
    out->alpha = -1.3f;
}

SL_GBUFFER_PROGRAM("glossy", glossy, 0);
C
cat >"$T/glossy.frag" <<'GLSL'
#version 330 core
in vec3 vWorldPos;
in vec3 vNormal;
uniform vec3 uKd;
layout(location = 0) out vec4 oPosition;
layout(location = 1) out vec4 oNormal;
layout(location = 2) out vec4 oKd;
layout(location = 3) out vec4 oKsAlpha;
void main()
{
    oPosition = vec4(vWorldPos, 1.0);
    oNormal = vec4(dot(vNormal, vNormal) > 1e-30 ? normalize(vNormal) : vec3(0.0, 0.0, 1.0), 0.0);
    oKd = vec4(uKd * 0.5, 0.0);
    oKsAlpha = vec4(vec3(0.9), -1.3);
}
GLSL
for est in spec splitsum; do
    "$SL" render scenes/default.json --size "$GL_TEST_SIZE" --samples 16 --estimator $est -q \
        --gbuffer-shader "$T/glossy.c" --pfm "$T/glossy-$est-c.pfm"
    "$GL" render scenes/default.json --size "$GL_TEST_SIZE" --samples 16 --estimator $est \
        --gbuffer-shader "$T/glossy.frag" --pfm "$T/glossy-$est-g.pfm" >/dev/null
    "$SL" compare "$T/glossy-$est-c.pfm" "$T/glossy-$est-g.pfm" >"$T/glossy-$est.txt" || true
    echo "glossy ($est): $(grep -m1 '^8-bit diff > 8' "$T/glossy-$est.txt" || true)"
    gl_check_share "glossy-$est" "$T/glossy-$est.txt" 0.5 || fail=1
done

# a G-buffer program and a lighting program together: checker and toon, C against GLSL
# (measured: 0.007% of the pixels over 8/255)
"$SL" render scenes/textured.json --size "$GL_TEST_SIZE" --samples 8 -q --lighting examples/shaders/toon.c \
    --gbuffer-shader examples/shaders/checker.c --pfm "$T/both-c.pfm"
"$GL" render scenes/textured.json --size "$GL_TEST_SIZE" --samples 8 --lighting examples/shaders/toon.frag \
    --gbuffer-shader examples/shaders/checker.frag --pfm "$T/both-g.pfm" >/dev/null
"$SL" compare "$T/both-c.pfm" "$T/both-g.pfm" >"$T/both.txt" || true
echo "checker and toon: $(grep -m1 '^8-bit diff > 8' "$T/both.txt" || true)"
gl_check_share checker-toon "$T/both.txt" 0.1 || fail=1

# the plane: magnified cells near the eye, sub-pixel cells at the horizon (uv_scale 20 on a white map)
python3 - "$T" <<'PY'
import json, struct, sys, zlib
d = sys.argv[1]
def chunk(kind, data):
    return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
rows = b''.join(b'\0' + b'\xff' * 12 for _ in range(4))
open(d + '/white.png', 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', 4, 4, 8, 2, 0, 0, 0)) +
                                   chunk(b'IDAT', zlib.compress(rows)) + chunk(b'IEND', b''))
json.dump({
    "camera": {"eye": [0, -8, 1.5], "target": [0, 6, 0], "up": [0, 0, 1], "fovy": 50, "near": 0.1, "far": 100},
    "materials": {"plane": {"kd": 1, "ks": 0.04, "alpha": 20, "kd_map": {"file": "white.png", "uv_scale": [20, 20]}}},
    "objects": [{"name": "plane", "shape": "plane", "material": "plane", "transform": {"scale": [20, 20, 1]}}],
}, open(d + '/plane.json', 'w'))
PY
render_both plane "$T/plane.json"
gl_bound "$T/plane.txt" kd floor 0.01 0.01 # the plane lies at z = 0: gbuffer_diff.py's floor
gl_bound "$T/plane.txt" depth floor 1e-5 0
gl_bound "$T/plane.txt" alpha floor 0 0

# the images after lighting: the same G-buffer through the two lighting passes
"$SL" compare "$T/plane-c.pfm" "$T/plane-g.pfm" >"$T/plane-image.txt" || true
echo "plane image: $(grep -m1 '^8-bit diff > 8' "$T/plane-image.txt" || true)"
gl_check_share plane-image "$T/plane-image.txt" 1 || fail=1

# softlight-gl's refusals: one line, exit 2, nothing written
refuse() {
    local name=$1 pattern=$2
    shift 2
    rm -f "$T/refused.png"
    local rc=0
    "$GL" render scenes/default.json --size 32x24 -o "$T/refused.png" "$@" >"$T/out" 2>"$T/err" || rc=$?
    if [ "$rc" -ne 2 ] || [ "$(wc -l <"$T/err")" -ne 1 ] || ! grep -Eq "$pattern" "$T/err" || [ -e "$T/refused.png" ]; then
        echo "FAIL $name: exit $rc, $(cat "$T/err")"; fail=1; return
    fi
    echo "ok   $name: $(cat "$T/err")"
}
printf '#version 330 core\nout vec4 oPosition;\nvoid main()\n{\n    oPosition = vec4(1.0 +);\n}\n' >"$T/bad.frag"
refuse "GLSL compile error" "bad\.frag:5\([0-9]+\): error" --gbuffer-shader "$T/bad.frag"
refuse "missing file" "missing\.frag" --gbuffer-shader "$T/missing.frag"
mkdir "$T/dir.frag"
refuse "a directory" "dir\.frag: not a regular file" --gbuffer-shader "$T/dir.frag"
refuse "with --gbuffer" "not both" --gbuffer-shader examples/shaders/checker.frag --gbuffer "$T/plane-c"

if [ "$fail" != 0 ]; then
    echo "gl_gbuffer_program: FAILED"
    exit 1
fi
echo "gl_gbuffer_program: checker.c and checker.frag agree within the bounds"
