#!/usr/bin/env bash
# gbuffer_program_errors.sh BUILD_DIR - what --gbuffer-shader refuses, in render and trace, each
# with exit 2, one line naming the file and nothing written: a compile error (the compiler's first
# error, file:line), a wrong ABI version, a missing entry point, an entry without a fragment
# function, a lighting program (the other kind), a file that is not regular, a missing file. And
# a scene cannot name code: a scene file that names a G-buffer program neither compiles nor loads it.
set -u
. "$(dirname "$0")/lib.bash"
cli_init gbperr "$@"
export XDG_CACHE_HOME=$T/cache

# refuse NAME FILE PATTERN: for render and trace, exit 2, one stderr line matching PATTERN, no output
refuse() {
    local name=$1 file=$2 pattern=$3 cmd
    for cmd in render trace; do
        local args=(-q -o "$T/out.png")
        [ $cmd = trace ] && args=(-p 1,1)
        rm -f "$T/out.png"
        if one_error "$pattern" "$SL" $cmd scenes/default.json --size 16x16 "${args[@]}" --gbuffer-shader "$file" &&
            [ ! -e "$T/out.png" ] && [ ! -s "$T/out" ]; then
            ok "$name ($cmd): $(cat "$T/err")"
        else
            bad "$name ($cmd): status $err_status, $err_lines lines (want 2, 1 matching /$pattern/), output $(ls "$T/out.png" 2>/dev/null):"
            sed 's/^/    /' "$T/err" | head -5
        fi
    done
}

printf '#include <softlight/gbuffer_program.h>\nstatic int broken(void)\n{\n    return 1 +;\n}\n' >"$T/bad.c"
refuse "compile error" "$T/bad.c" "bad\.c:4:[0-9]+: error"

cat >"$T/abi.c" <<'C'
#include <softlight/gbuffer_program.h>
static void frag(const sl_gbuffer_material *u, const sl_fragment_in *in, sl_gbuffer_texel *out, sl_gbuffer_extra *e)
{
    (void)u; (void)in; (void)out; (void)e;
}
SL_GBUFFER_EXPORT const int sl_gbuffer_program_abi = SL_GBUFFER_ABI + 41;
SL_GBUFFER_EXPORT const sl_gbuffer_fragment_program sl_gbuffer_program_entry = {"abi", frag, 0};
C
abi=$(sed -n 's/^#define SL_GBUFFER_ABI \([0-9]*\).*/\1/p' include/softlight/gbuffer_program.h)
refuse "wrong ABI" "$T/abi.c" "abi\.c: G-buffer program ABI $((abi + 41)), this softlight takes $abi: rebuild it"

printf '#include <softlight/gbuffer_program.h>\nSL_GBUFFER_EXPORT const int sl_gbuffer_program_abi = SL_GBUFFER_ABI;\n' >"$T/noentry.c"
refuse "missing entry point" "$T/noentry.c" "noentry\.c: no entry point: sl_gbuffer_program_entry with a fragment function"

cat >"$T/nofrag.c" <<'C'
#include <softlight/gbuffer_program.h>
SL_GBUFFER_PROGRAM("nothing", 0, 0);
C
refuse "entry without a fragment function" "$T/nofrag.c" "nofrag\.c: no entry point: sl_gbuffer_program_entry"

refuse "a lighting program" examples/shaders/toon.c \
    "toon\.c: exports no sl_gbuffer_program_abi: not a G-buffer program \(SL_GBUFFER_PROGRAM\)"
mkdir "$T/dir.c"
refuse "a directory" "$T/dir.c" "dir\.c: not a regular file"
refuse "a missing file" "$T/missing.c" "missing\.c: No such file"

# A scene that names a G-buffer program: never compiled, never loaded (its constructor would
# leave a marker), and the image is the built-in's when the scene renders at all.
cat >"$T/evil.c" <<C
#include <stdio.h>
__attribute__((constructor)) static void mark(void) { FILE *f = fopen("$T/marker", "w"); if (f) fclose(f); }
C
python3 - "$T" <<'PY'
import json, sys
s = json.load(open('scenes/default.json'))
for key in ('gbuffer_shader', 'gbuffer_program', 'fragment_shader'):
    s[key] = sys.argv[1] + '/evil.c'
json.dump(s, open(sys.argv[1] + '/scene.json', 'w'))
PY
ln -s "$PWD/scenes/envmaps" "$T/envmaps" 2>/dev/null
ln -s "$PWD/scenes/models" "$T/models" 2>/dev/null
ln -s "$PWD/scenes/meshes" "$T/meshes" 2>/dev/null
XDG_CACHE_HOME=$T/cache2 "$SL" render "$T/scene.json" --size 32x24 -q --pfm "$T/scene.pfm" >"$T/scene.log" 2>&1
"$SL" render scenes/default.json --size 32x24 -q --pfm "$T/default.pfm" >/dev/null 2>&1
if [ ! -e "$T/marker" ] && [ -z "$(ls -A "$T/cache2/softlight" 2>/dev/null)" ] &&
    { [ ! -e "$T/scene.pfm" ] || cmp -s "$T/scene.pfm" "$T/default.pfm"; }; then
    ok "a scene naming a G-buffer program: nothing compiled or loaded ($(head -1 "$T/scene.log"))"
else
    bad "a scene's G-buffer program was compiled, loaded or drawn"
fi
cli_done gbuffer_program_errors
