#!/usr/bin/env bash
# errors.sh BUILD_DIR - bad input end to end: every case must exit with status 2, print exactly
# one line on stderr naming the problem, and leave no output file (or leave an existing one
# untouched). Covers a truncated and a corrupt .hdr, a malformed OBJ, malformed scene files,
# absurd parameters and unwritable outputs.
set -u
. "$(dirname "$0")/lib.bash"
cli_init errors "$@"

# A scene around a given environment and mesh, written into $T.
scene() { # scene FILE HDR [OBJ]
    local obj=${3:-}
    local objects='{"shape": "sphere"}'
    [ -n "$obj" ] && objects="{\"mesh\": \"$obj\"}"
    cat >"$1" <<JSON
{"environment": {"hdr": "$2"}, "objects": [$objects], "render": {"width": 64, "height": 36, "samples": 4}}
JSON
}

cp scenes/envmaps/studio.hdr "$T/good.hdr"
head -c 40000 scenes/envmaps/studio.hdr >"$T/truncated.hdr"
{ head -c 200 scenes/envmaps/studio.hdr; head -c 5000 /dev/urandom; } >"$T/corrupt.hdr"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n' >"$T/bad.obj"
scene "$T/truncated.json" truncated.hdr
scene "$T/corrupt.json" corrupt.hdr
scene "$T/badobj.json" good.hdr bad.obj
scene "$T/good.json" good.hdr
printf '{"objects": [{"shape": "sphere", "material": "gold"}]}' >"$T/nomat.json"
printf '{"camera": {"eye": [0, 0]}}' >"$T/eye.json"
printf '{"render": {"samples": 5000}}' >"$T/samples.json"
printf '{"objects": [' >"$T/syntax.json"

expect_error truncated-hdr 'truncated\.hdr.*byte' -- "$SL" render "$T/truncated.json" -o "$T/a.png"
expect_error corrupt-hdr 'corrupt\.hdr' -- "$SL" render "$T/corrupt.json" -o "$T/a.png"
expect_error bad-obj 'bad\.obj:4:.*out of range' -- "$SL" render "$T/badobj.json" -o "$T/a.png"
expect_error no-material 'objects\[0\]\.material.*gold' -- "$SL" render "$T/nomat.json" -o "$T/a.png"
expect_error camera-eye 'camera\.eye' -- "$SL" render "$T/eye.json" -o "$T/a.png"
expect_error scene-samples 'render\.samples' -- "$SL" render "$T/samples.json" -o "$T/a.png"
expect_error json-syntax 'syntax\.json' -- "$SL" render "$T/syntax.json" -o "$T/a.png"
expect_error missing-scene 'nothere\.json' -- "$SL" render "$T/nothere.json" -o "$T/a.png"
expect_error samples-range '--samples.*5000' -- "$SL" render "$T/good.json" --samples 5000 -o "$T/a.png"
expect_error size-zero '--size' -- "$SL" render "$T/good.json" --size 0x10 -o "$T/a.png"
expect_error exposure-nan '--exposure' -- "$SL" render "$T/good.json" --exposure nan -o "$T/a.png"
expect_error unknown-option "unknown option '--bogus'" -- "$SL" render "$T/good.json" --bogus
expect_error missing-value '--samples needs a value' -- "$SL" render "$T/good.json" --samples
expect_error bad-choice '--lod' -- "$SL" render "$T/good.json" --lod sideways
expect_error both-only 'exclude' -- "$SL" render "$T/good.json" --diffuse-only --specular-only
expect_error unknown-command "unknown command 'paint'" -- "$SL" paint
expect_error pixel-outside 'outside' -- "$SL" trace "$T/good.json" --pixel 64,0
expect_error no-dir 'nodir' -- "$SL" render "$T/good.json" -o "$T/nodir/a.png"

# No half-written output anywhere: nothing but our inputs in $T, no temporaries.
if ls -A "$T" | grep -qE '^a\.png|tmp'; then
    echo "FAIL leftovers: $(ls -A "$T" | grep -E '^a\.png|tmp' | tr '\n' ' ')"; fails=$((fails + 1))
else
    echo "ok   no output or temporary file was left behind"; passes=$((passes + 1))
fi
# A failing render leaves an existing output untouched.
echo "previous" >"$T/keep.png"
"$SL" render "$T/truncated.json" -o "$T/keep.png" 2>/dev/null
if [ "$(cat "$T/keep.png")" = previous ]; then
    echo "ok   existing output kept after a failed render"; passes=$((passes + 1))
else
    echo "FAIL existing output was overwritten by a failed render"; fails=$((fails + 1))
fi
# And the good scene renders.
if "$SL" render "$T/good.json" -o "$T/good.png" -q && [ -s "$T/good.png" ]; then
    echo "ok   the control scene renders"; passes=$((passes + 1))
else
    echo "FAIL the control scene did not render"; fails=$((fails + 1))
fi
echo "$passes passed, $fails failed"
[ "$fails" -eq 0 ]
