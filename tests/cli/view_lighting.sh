#!/usr/bin/env bash
# view_lighting.sh BUILD_DIR - `softlight view --lighting my.c` runs the user's lighting program,
# recompiles it when it is saved and swaps it in, and keeps the last good one on a compile error.
#
# Under Xvfb the viewer opens scenes/default.json with a copy of examples/shaders/toon.c. A
# screenshot must equal `softlight render --lighting` of the same source (linear .hdr); then the
# source is replaced (renamed over, as editors save) by a constant-colour program, and the next
# screenshot must equal render's of that program; then by a source with a syntax error: stderr
# must name the file and line, the viewer keeps running with the constant program, exit 0.
# CTest label: release-only
set -euo pipefail
source "$(dirname "$0")/view_common.bash"
view_setup "$@"
SCENE=scenes/default.json
export XDG_CACHE_HOME=$T/cache

cp examples/shaders/toon.c "$T/live.c"
cat >"$T/flat.c" <<'SHADER'
#include <softlight/lighting.h>

static sl_vec3 flat_shade(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *res,
                          const sl_lighting_texel_in *in)
{
    (void)u;
    (void)res;
    sl_vec3 c = {0.25f, 0.5f, 0.75f};
    if (in->texel->depth >= 1.0f)
        c.x = 0.0f;
    return c;
}

SL_LIGHTING_PROGRAM("flat", flat_shade, NULL);
SHADER
cat >"$T/bad.c" <<'SHADER'
#include <softlight/lighting.h>

static sl_vec3 bad_shade(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *res,
                         const sl_lighting_texel_in *in)
{
    return (sl_vec3){0.0f, 1.0f, 0.0f} +;
}

SL_LIGHTING_PROGRAM("bad", bad_shade, NULL);
SHADER

"$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --lighting "$T/live.c" --hdr "$T/ref-toon.hdr" -q
"$SL" render "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --lighting "$T/flat.c" --hdr "$T/ref-flat.hdr" -q

cat >"$T/script.txt" <<SCRIPT
settle
screenshot $T/toon
wait 4000
settle
screenshot $T/flat
wait 3000
settle
screenshot $T/still-flat
quit
SCRIPT

# The editor: each save waits for the screenshot before it, and lands as a rename.
(
    for step in flat bad; do
        shot=$T/toon.hdr
        [ "$step" = bad ] && shot=$T/flat.hdr
        for _ in $(seq 1 300); do
            [ -s "$shot" ] && break
            sleep 0.05
        done
        sleep 0.2
        cp "$T/$step.c" "$T/live.c.tmp"
        mv "$T/live.c.tmp" "$T/live.c"
    done
) &
editor=$!

view_run "$SCENE" --size "$VIEW_TEST_SIZE" -n 8 --lighting "$T/live.c" --script "$T/script.txt"
wait "$editor"
view_expect_exit0 "view --lighting"

view_same "$T/toon.hdr" "$T/ref-toon.hdr" "the viewer's frame is render's with the same program"
view_same "$T/flat.hdr" "$T/ref-flat.hdr" "a saved program is swapped in: render's frame of it"
view_differ "$T/toon.hdr" "$T/flat.hdr" "the frame changed with the program"
grep -Eq "live\.c:6:[0-9]+: error" "$T/err.txt" || fail "the compile error does not name live.c:6 on stderr"
echo "ok: the compile error names the file and line"
grep -q "the last good program keeps running" "$T/err.txt" || fail "no word that the last good program runs"
view_same "$T/still-flat.hdr" "$T/ref-flat.hdr" "after the error the last good program still runs"
echo "PASS view_lighting"
