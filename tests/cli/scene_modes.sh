#!/usr/bin/env bash
# scene_modes.sh BUILD_DIR - the lighting's modes named in a scene file's "render" section
# ("estimator", "lod", "gterm", "env_layout", "irradiance", and the flags "distortion" and
# "rotate"; docs/scene-format.md) give the render the same
# command-line options give, bit for bit, in softlight and in softlight-gl; a mode given on the
# command line wins over the scene's; `softlight info` reports the modes a render would use;
# an unknown name is one error line naming the file and the key, exit 2, nothing written.
set -u
BUILD=${1:?usage: $0 BUILD_DIR}
SL=$BUILD/softlight
GL=$BUILD/softlight-gl
cd "$(dirname "$0")/../.."
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-modes.XXXXXX")
trap 'rm -rf "$T"' EXIT
fails=0

# scene OUT 'JSON fragment': scenes/ggx.json (GGX and a point light: every mode matters) with
# its environment made absolute and the render section's keys replaced by the fragment's.
scene() {
    python3 - "$1" "$2" <<'PY'
import json, os, sys
s = json.load(open("scenes/ggx.json"))
s["environment"]["hdr"] = os.path.abspath("scenes/" + s["environment"]["hdr"])
s["render"] = dict(s.get("render", {}), **json.loads(sys.argv[2]))
json.dump(s, open(sys.argv[1], "w"))
PY
}

# same NAME A B: files A and B are byte-identical
same() {
    if cmp -s "$2" "$3"; then echo "ok   $1"; else echo "FAIL $1: $2 and $3 differ"; fails=$((fails + 1)); fi
}

SIZE=(--size 96x54)
scene "$T/plain.json" '{}'
scene "$T/modes.json" '{"estimator": "mf", "lod": "pdf", "gterm": "one", "env_layout": "oct", "irradiance": "sh9",
                        "distortion": true, "rotate": true}'
scene "$T/splitsum.json" '{"estimator": "splitsum"}'
scene "$T/default.json" '{"estimator": "default", "lod": "default"}'
scene "$T/bad.json" '{"estimator": "fastest"}'

MODES=(--estimator mf --lod pdf --g one --env-layout oct --irradiance sh9 --distortion --rotate)
"$SL" render "$T/plain.json" "${SIZE[@]}" "${MODES[@]}" --pfm "$T/cli.pfm" >/dev/null &&
    "$SL" render "$T/modes.json" "${SIZE[@]}" --pfm "$T/file.pfm" >/dev/null || { echo "FAIL: render"; exit 1; }
same "softlight: the scene's modes = the same options on the command line" "$T/cli.pfm" "$T/file.pfm"
"$SL" render "$T/plain.json" "${SIZE[@]}" --estimator splitsum --pfm "$T/cli_ss.pfm" >/dev/null &&
    "$SL" render "$T/splitsum.json" "${SIZE[@]}" --pfm "$T/file_ss.pfm" >/dev/null || { echo "FAIL: render"; exit 1; }
same "softlight: \"estimator\": \"splitsum\" = --estimator splitsum" "$T/cli_ss.pfm" "$T/file_ss.pfm"
"$SL" render "$T/plain.json" "${SIZE[@]}" --pfm "$T/plain.pfm" >/dev/null &&
    "$SL" render "$T/plain.json" "${SIZE[@]}" --estimator spec --pfm "$T/plain_spec.pfm" >/dev/null &&
    "$SL" render "$T/plain.json" "${SIZE[@]}" --estimator mf --lod pdf --distortion \
        --pfm "$T/plain_ggx.pfm" >/dev/null &&
    "$SL" render "$T/splitsum.json" "${SIZE[@]}" --estimator spec --pfm "$T/override.pfm" >/dev/null &&
    "$SL" render "$T/default.json" "${SIZE[@]}" --pfm "$T/default.pfm" >/dev/null || { echo "FAIL: render"; exit 1; }
same "softlight: --estimator spec wins over the scene's splitsum" "$T/plain_spec.pfm" "$T/override.pfm"
same "softlight: \"default\" is the default" "$T/plain.pfm" "$T/default.pfm"
# a scene of GGX materials only (this one) is shaded by the microfacet estimator with the pdf
# rule, the distortion and those of the 64 brightest texels worth their cost as env lights unless
# it asks for another estimator: under the studio map, whose brightest texels are a plateau, none
same "softlight: an all-GGX scene's default is mf pdf+dist, under the studio map without env lights" \
    "$T/plain.pfm" "$T/plain_ggx.pfm"
if "$SL" render "$T/plain.json" "${SIZE[@]}" -o "$T/plain.png" | grep -q "^env lights: none (the brightest 64 texels"; then
    echo "ok   softlight: the render says the default took no env lights"
else echo "FAIL softlight: no 'env lights: none' line"; fails=$((fails + 1)); fi
# under a sky with a sun of three texels (a 64x32 PFM), the default takes those three and no more
python3 - "$T/sun.pfm" <<'PY'
import struct, sys
w, h = 64, 32
px = [(0.5, 0.6, 0.8)] * (w * h)
for i, j, v in ((10, 5, 9e3), (11, 5, 6e3), (10, 6, 3e3)):
    px[(h - 1 - j) * w + i] = (v, v, v) # PFM rows run bottom to top
with open(sys.argv[1], "wb") as f:
    f.write(b"PF\n%d %d\n-1.0\n" % (w, h) + b"".join(struct.pack("<3f", *p) for p in px))
PY
"$SL" render "$T/plain.json" "${SIZE[@]}" --env "$T/sun.pfm" --pfm "$T/sun_default.pfm" >"$T/sun_out" &&
    "$SL" render "$T/plain.json" "${SIZE[@]}" --env "$T/sun.pfm" --estimator mf --lod pdf --distortion \
        --env-lights 3 --pfm "$T/sun_3.pfm" >/dev/null || { echo "FAIL: render"; exit 1; }
same "softlight: an all-GGX scene's default under a sun of three texels is --env-lights 3" \
    "$T/sun_default.pfm" "$T/sun_3.pfm"
if grep -q "^env lights: 3 texels summed exactly, those worth their cost of the brightest 64" "$T/sun_out"; then
    echo "ok   softlight: the render says the default took the sun's 3 texels"
else echo "FAIL softlight: no 'env lights: 3 texels' line:"; grep "env lights" "$T/sun_out"; fails=$((fails + 1)); fi
if cmp -s "$T/plain.pfm" "$T/file.pfm"; then
    echo "FAIL: the modes changed nothing (the test would pass without reading them)"; fails=$((fails + 1))
fi

want="lighting   estimator mf, lod pdf, g one, env layout oct, irradiance sh9, distortion, rotate"
if "$SL" info "$T/modes.json" | grep -qF "$want"; then echo "ok   info reports the scene's modes"
else echo "FAIL info: no line '$want'"; "$SL" info "$T/modes.json" | grep lighting; fails=$((fails + 1)); fi

"$SL" render "$T/bad.json" "${SIZE[@]}" -o "$T/bad.png" >"$T/out" 2>"$T/err"
status=$?
if [ $status -eq 2 ] && [ "$(wc -l <"$T/err")" -eq 1 ] && [ ! -e "$T/bad.png" ] &&
    grep -qF 'bad.json: render.estimator: unknown estimator "fastest" (expected spec|consistent|mf|splitsum|mis|cv|cvmis)' "$T/err"; then
    echo "ok   an unknown mode: one line, exit 2, nothing written"
else
    echo "FAIL an unknown mode: status $status, stderr:"; sed 's/^/    /' "$T/err"; fails=$((fails + 1))
fi

# softlight-gl reads the same section (sl_renderer_init): its render of the scene's modes is
# its render of the same options, bit for bit (skipped where it has no GL context)
if [ -x "$GL" ] && "$GL" render "$T/plain.json" "${SIZE[@]}" --pfm "$T/gl_cli.pfm" "${MODES[@]}" \
    >/dev/null 2>"$T/glerr"; then
    "$GL" render "$T/modes.json" "${SIZE[@]}" --pfm "$T/gl_file.pfm" >/dev/null || { echo "FAIL: gl render"; exit 1; }
    same "softlight-gl: the scene's modes = the same options on the command line" "$T/gl_cli.pfm" "$T/gl_file.pfm"
    "$GL" render "$T/plain.json" "${SIZE[@]}" --pfm "$T/gl_plain.pfm" >/dev/null || { echo "FAIL: gl render"; exit 1; }
    if cmp -s "$T/gl_plain.pfm" "$T/gl_file.pfm"; then
        echo "FAIL: softlight-gl: the modes changed nothing"; fails=$((fails + 1))
    fi
else
    echo "SKIP softlight-gl: $(head -1 "$T/glerr" 2>/dev/null)"
fi

[ $fails -eq 0 ] && echo "scene_modes: all passed" || { echo "scene_modes: $fails failed"; exit 1; }
