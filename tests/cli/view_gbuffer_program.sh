#!/usr/bin/env bash
# view_gbuffer_program.sh BUILD_DIR - `softlight view --gbuffer-shader my.c` fills the G-buffer
# with the user's program, recompiles it when it is saved and swaps it in (the G-buffer drawn
# again), and keeps the last good one on a compile error.
#
# Under Xvfb the viewer opens scenes/textured.json with a copy of examples/shaders/checker.c. A
# screenshot must equal `softlight render --gbuffer-shader` of the same source (linear .hdr); then
# the source is replaced (renamed over, as editors save) by a program that writes one grey for
# every surface, and the next screenshot must equal render's of that program; then by a source
# with a syntax error: stderr must name the file and line, the viewer keeps running with the grey
# program, exit 0; the trace of a pixel (T) names the program and prints its texel.
# CTest label: release-only
set -euo pipefail
source "$(dirname "$0")/view_common.bash"
view_setup "$@"
SCENE=scenes/textured.json
export XDG_CACHE_HOME=$T/cache

cp examples/shaders/checker.c "$T/live.c"
cat >"$T/grey.c" <<'SHADER'
#include <softlight/gbuffer_program.h>

static void grey(const sl_gbuffer_material *u, const sl_fragment_in *in, sl_gbuffer_texel *out,
                 sl_gbuffer_extra *extra)
{
    (void)extra;
    sl_gbuffer_varyings v = sl_gbuffer_varyings_of(in);
    out->position = v.vWorldPos;
    out->normal = (sl_vec3){0.0f, 0.0f, 1.0f};
    out->kd = (sl_vec3){0.5f, 0.5f, 0.5f};
    out->ks = u->uKs;
    out->alpha = u->uAlpha;
}

SL_GBUFFER_PROGRAM("grey", grey, 0);
SHADER
cat >"$T/bad.c" <<'SHADER'
#include <softlight/gbuffer_program.h>

static void bad(const sl_gbuffer_material *u, const sl_fragment_in *in, sl_gbuffer_texel *out,
                sl_gbuffer_extra *extra)
{
    out->alpha = 1.0f +;
}

SL_GBUFFER_PROGRAM("bad", bad, 0);
SHADER

"$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --gbuffer-shader "$T/live.c" --hdr "$T/ref-checker.hdr" -q
"$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --gbuffer-shader "$T/grey.c" --hdr "$T/ref-grey.hdr" -q

cat >"$T/script.txt" <<SCRIPT
settle
screenshot $T/checker
wait 4000
settle
screenshot $T/grey
wait 3000
settle
screenshot $T/still-grey
move 160 150
key t
wait 200
quit
SCRIPT

# The editor: each save waits for the screenshot before it (up to 60 s: a sanitized build draws
# textured.json's first frames slowly), and lands as a rename.
(
    for step in grey bad; do
        shot=$T/checker.hdr
        [ "$step" = bad ] && shot=$T/grey.hdr
        for _ in $(seq 1 1200); do
            [ -s "$shot" ] && break
            sleep 0.05
        done
        sleep 0.2
        cp "$T/$step.c" "$T/live.c.tmp"
        mv "$T/live.c.tmp" "$T/live.c"
    done
) &
editor=$!

view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --gbuffer-shader "$T/live.c" --script "$T/script.txt"
wait "$editor"
view_expect_exit0 "view --gbuffer-shader"

view_same "$T/checker.hdr" "$T/ref-checker.hdr" "the viewer's frame is render's with the same G-buffer program"
view_same "$T/grey.hdr" "$T/ref-grey.hdr" "a saved program is swapped in and the G-buffer drawn again: render's frame"
view_differ "$T/checker.hdr" "$T/grey.hdr" "the frame changed with the program"
grep -Eq "live\.c:6:[0-9]+: error" "$T/err.txt" || fail "the compile error does not name live.c:6 on stderr"
echo "ok: the compile error names the file and line"
grep -q "the last good program keeps running" "$T/err.txt" || fail "no word that the last good program runs"
view_same "$T/still-grey.hdr" "$T/ref-grey.hdr" "after the error the last good program still runs"
grep -q "G-buffer program: grey; its texture fetches are not traced" "$T/out.txt" ||
    fail "the viewer's trace (T) does not name the G-buffer program"
grep -Eq "^  kd +\(0.5, 0.5, 0.5\)" "$T/out.txt" || fail "the viewer's trace does not print the program's kd"
echo "ok: the viewer's trace names the G-buffer program and prints its texel"
echo "PASS view_gbuffer_program"
