#!/usr/bin/env bash
# lighting_program_errors.sh BUILD_DIR - what --lighting refuses, each with exit 2, one line
# naming the file and nothing written: a compile error (the compiler's first error, file:line),
# a wrong ABI version, a missing entry point, a file that is not regular, a missing file. And a
# scene cannot name code: a scene file that names a lighting program neither compiles nor loads it.
set -u
SL=${1:?usage: $0 BUILD_DIR}/softlight
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-lperr.XXXXXX")
trap 'rm -rf "$T"' EXIT
export XDG_CACHE_HOME=$T/cache
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }
# refuse NAME FILE PATTERN: exit 2, one stderr line matching PATTERN, no output file
refuse() {
    local name=$1 file=$2 pattern=$3
    for cmd in render trace; do
        local args=(-q -o "$T/out.png")
        [ $cmd = trace ] && args=(-p 1,1)
        "$SL" $cmd scenes/default.json --size 16x16 "${args[@]}" --lighting "$file" >"$T/out" 2>"$T/err"
        local rc=$?
        [ $cmd = trace ] && sed -i '/^$/d' "$T/err"
        if [ $rc -ne 2 ]; then fail "$name ($cmd): exit $rc, expected 2"; continue; fi
        [ "$(wc -l <"$T/err")" -eq 1 ] || fail "$name ($cmd): expected one line, got: $(cat "$T/err")"
        grep -Eq "$pattern" "$T/err" || fail "$name ($cmd): '$(cat "$T/err")' does not match '$pattern'"
        [ ! -e "$T/out.png" ] || fail "$name ($cmd): an output was written"
    done
}
printf '#include <softlight/lighting.h>\nstatic int broken(void)\n{\n    return 1 +;\n}\n' >"$T/bad.c"
refuse "compile error" "$T/bad.c" "bad\.c:4:[0-9]+: error"
cat >"$T/abi.c" <<'C'
#include <softlight/lighting.h>
static sl_vec3 shade(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *r, const sl_lighting_texel_in *in)
{
    (void)u; (void)r; (void)in;
    return (sl_vec3){0, 0, 0};
}
SL_LIGHTING_EXPORT const int sl_lighting_program_abi = SL_LIGHTING_ABI + 41;
SL_LIGHTING_EXPORT const sl_lighting_program sl_lighting_program_entry = {"abi", shade, NULL};
C
refuse "wrong ABI" "$T/abi.c" "abi\.c: lighting program ABI $(( $(sed -n 's/^#define SL_LIGHTING_ABI \([0-9]*\).*/\1/p' include/softlight/lighting.h) + 41 )), this softlight takes"
printf '#include <softlight/lighting.h>\nSL_LIGHTING_EXPORT const int sl_lighting_program_abi = SL_LIGHTING_ABI;\n' >"$T/noentry.c"
refuse "missing entry point" "$T/noentry.c" "noentry\.c: no entry point"
printf 'int unrelated(void) { return 0; }\n' >"$T/plain.c"
refuse "not a program" "$T/plain.c" "plain\.c: exports no sl_lighting_program_abi"
mkdir "$T/dir.c"
refuse "a directory" "$T/dir.c" "dir\.c: not a regular file"
refuse "a missing file" "$T/missing.c" "missing\.c: No such file"

# A scene that names a lighting program: never compiled, never loaded (its constructor would
# leave a marker), and the image is the built-in's.
cat >"$T/evil.c" <<C
#include <stdio.h>
__attribute__((constructor)) static void mark(void) { FILE *f = fopen("$T/marker", "w"); if (f) fclose(f); }
C
python3 - "$T" <<'PY'
import json, sys
s = json.load(open('scenes/default.json'))
for key in ('lighting', 'lighting_program', 'shader'):
    s[key] = sys.argv[1] + '/evil.c'
s.setdefault('settings', {})
json.dump(s, open(sys.argv[1] + '/scene.json', 'w'))
PY
# relative paths of the scene resolve against its directory: link the scene's neighbours
ln -s "$PWD/scenes/envmaps" "$T/envmaps" 2>/dev/null
ln -s "$PWD/scenes/models" "$T/models" 2>/dev/null
XDG_CACHE_HOME=$T/cache2 "$SL" render "$T/scene.json" --size 32x24 -q --pfm "$T/scene.pfm" >"$T/scene.log" 2>&1
"$SL" render scenes/default.json --size 32x24 -q --pfm "$T/default.pfm" >/dev/null 2>&1
[ ! -e "$T/marker" ] || fail "a scene's program was loaded"
[ -z "$(ls -A "$T/cache2/softlight" 2>/dev/null)" ] || fail "a scene's program was compiled"
if [ -e "$T/scene.pfm" ] && ! cmp -s "$T/scene.pfm" "$T/default.pfm"; then
    fail "a scene naming a program did not render with the built-in shading"
fi
[ "$fails" -eq 0 ] && echo "ok   compile error, ABI, entry point, not regular, missing, scene cannot name code"
exit $((fails > 0))
