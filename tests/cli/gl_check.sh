#!/usr/bin/env bash
# gl_check.sh BUILD_DIR - `softlight check`: a C lighting program against its GLSL twin on one
# G-buffer (docs/lighting-programs.md, "Checking a port").
#
# - The built-in port against shaders/lighting.frag agrees within gl_shading.sh's bounds (p99
#   relative error <= 0.05, no pixel more than 8/255 apart after the tone map), and the printed
#   trace line runs.
# - Each example of examples/shaders agrees with its .frag twin within its stated bound:
#     normals      p99 rel <= 1e-4 (no transcendental in it: float rounding only)
#     blinn_phong  p99 rel <= 0.05, share > 8/255 = 0 (pow, and the background's bilinear taps)
#     toon         share > 8/255 <= 0.5% (a texel within rounding of a band threshold flips band)
# - Twins that are not twins fail (exit 1): the check can tell.
# - Nothing is left in TMPDIR (the G-buffer's files and softlight-gl's image are removed).
# - Errors are one line, exit 2, nothing written: a GLSL compile error names the .frag and its
#   line, a C compile error the .c, and a missing softlight-gl says so.
set -u
. "$(dirname "$0")/lib.bash"
source "$(dirname "$0")/gl_common.bash"
gl_setup "$1"
cli_init check "$1"
export XDG_CACHE_HOME=$T/cache
EX=examples/shaders

mkdir -p "$T/tmp"
TMPDIR=$T/tmp "$SL" check scenes/default.json --size "$GL_TEST_SIZE" --diff "$T/d.png" >"$T/builtin.txt" 2>"$T/err"
status=$?
if [ -z "$(ls -A "$T/tmp")" ]; then
    ok "check leaves its temporary directory removed"
else
    bad "check left files in TMPDIR: $(ls -A "$T/tmp" | head -3 | tr '\n' ' ')"
fi
p99=$(gl_field "p99 rel error" "$T/builtin.txt")
if [ "$status" = 0 ] && gl_check_share builtin "$T/builtin.txt" 0 && [ -s "$T/d.png" ]; then
    ok "built-in vs lighting.frag: p99 rel $p99, diff image written"
else
    bad "built-in vs lighting.frag: status $status, p99 rel $p99"; cat "$T/err"
fi
line=$(sed -n 's/^trace the worst: //p' "$T/builtin.txt")
if [ -n "$line" ] && eval "${line/#softlight/\"\$SL\"}" >"$T/trace.txt" 2>&1 && grep '^result' "$T/trace.txt" >/dev/null; then
    ok "the trace line runs: $line"
else
    bad "the trace line '$line' does not run"; head -3 "$T/trace.txt"
fi

# twin NAME P99_MAX OVER8_MAX_PERCENT
twin() {
    local status=0
    "$SL" check scenes/bunny.json --size "$GL_TEST_SIZE" --lighting "$EX/$1.c" --glsl "$EX/$1.frag" \
        --tolerance "$2" >"$T/$1.txt" 2>"$T/err" || status=$?
    if [ "$status" = 0 ] && gl_check_share "$1" "$T/$1.txt" "$3"; then
        ok "$1.c vs $1.frag: p99 rel $(gl_field "p99 rel error" "$T/$1.txt") (<= $2), >8/255 $(gl_field "8-bit diff > 8" "$T/$1.txt")% (<= $3%)"
    else
        bad "$1.c vs $1.frag: status $status"; grep -E '^(p99|8-bit|PASS|FAIL)' "$T/$1.txt"; cat "$T/err"
    fi
}
twin normals 1e-4 0
twin blinn_phong 0.05 0
twin toon 1 0.5

status=0
"$SL" check scenes/bunny.json --size 96x54 --lighting "$EX/blinn_phong.c" --glsl "$EX/normals.frag" \
    >"$T/wrong.txt" 2>"$T/err" || status=$?
if [ "$status" = 1 ] && grep '^FAIL p99rel' "$T/wrong.txt" >/dev/null; then
    ok "blinn_phong.c against normals.frag fails: $(grep '^FAIL' "$T/wrong.txt")"
else
    bad "blinn_phong.c against normals.frag: status $status (want 1)"
fi

printf '#version 330 core\nvoid main()\n{\n    fragColor = vec4(nothing, 1.0);\n}\n' >"$T/bad.frag"
expect_error "GLSL compile error" "bad\.frag:4\([0-9]+\): error" -- \
    "$SL" check scenes/bunny.json --size 96x54 --glsl "$T/bad.frag" --diff "$T/none.png"
[ ! -e "$T/none.png" ] && ok "nothing written on error" || bad "the diff image was written on error"
printf 'void main() {}\n' >"$T/noversion.frag"
expect_error "no #version" "noversion\.frag: the first line must be #version 330 core" -- \
    "$SL" check scenes/bunny.json --size 96x54 --glsl "$T/noversion.frag"
printf '#version 330 core\nfloat f() { return 1.0; }\n' >"$T/nomain.frag"
expect_error "no main" "nomain\.frag: does not link" -- \
    "$SL" check scenes/bunny.json --size 96x54 --glsl "$T/nomain.frag"
expect_error "a directory" "softlight check: .*: not a regular file" -- \
    "$SL" check scenes/bunny.json --size 96x54 --glsl "$T"
printf '#define SL_GLSL_LIGHTING\n#include <softlight/glsl.h>\nstatic vec3 f(void) { return nothing; }\n' >"$T/bad.c"
expect_error "C compile error" "bad\.c:3:[0-9]+: error" -- \
    "$SL" check scenes/bunny.json --size 96x54 --lighting "$T/bad.c" --glsl "$EX/normals.frag"
expect_error "no softlight-gl" "cannot run $T/nowhere/softlight-gl" -- \
    env SOFTLIGHT_GL="$T/nowhere/softlight-gl" "$SL" check scenes/bunny.json --size 96x54

# A GLSL NaN is counted by softlight-gl and shown as magenta on the GL side, as in the C pass.
printf '#version 330 core\nvoid main() { fragColor = vec4(vec3(0.0) / vec3(uEye.x - uEye.x), 1.0); }\n' >"$T/nan.frag"
status=0
"$SL" check scenes/bunny.json --size 96x54 --lighting "$EX/normals.c" --glsl "$T/nan.frag" >"$T/nan.txt" 2>"$T/err" || status=$?
if [ "$status" = 1 ] && grep 'nan.frag: 5184 pixels had NaN/Inf radiance (written as magenta)' "$T/err" >/dev/null; then
    ok "GLSL NaN counted: $(cat "$T/err")"
else
    bad "GLSL NaN: status $status (want 1)"; cat "$T/err"
fi
cli_done check
