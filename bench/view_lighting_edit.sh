#!/usr/bin/env bash
# view_lighting_edit.sh BUILD_DIR [SIZE] - editing a lighting program to seeing its result in
# `softlight view --lighting`: five saves of examples/shaders/toon.c (each a new source, so each
# is compiled, not taken from the cache), under Xvfb; the viewer prints, per save, the time from
# the file's mtime to the present of the first frame lit in full by the new program. Prints
# the five and their median (docs/lighting-programs.md "Live editing in the viewer").
set -euo pipefail
BUILD=${1:?usage: $0 BUILD_DIR [WxH]}
SIZE=${2:-640x360}
SL=$BUILD/softlight
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-edit.XXXXXX")
trap 'rm -rf "$T"' EXIT
export XDG_CACHE_HOME=$T/cache
cp examples/shaders/toon.c "$T/toon.c"
printf 'wait 19000\nquit\n' >"$T/script.txt"
(
    sleep 3
    for i in 1 2 3 4 5; do
        sed "s/light > 0\.6f/light > 0.6${i}f/" examples/shaders/toon.c >"$T/next.c"
        mv "$T/next.c" "$T/toon.c"
        sleep "$(awk -v r=$RANDOM 'BEGIN { print 2 + r / 32768 }')" # a random phase against the 0.25 s poll
    done
) &
xvfb-run -a -s "-screen 0 1024x768x24 -nolisten tcp" \
    "$SL" view scenes/default.json --size "$SIZE" --lighting "$T/toon.c" --script "$T/script.txt" 2>"$T/err.txt"
wait
grep -o 'on screen [0-9]* ms after it was saved (compile [0-9]* ms)' "$T/err.txt" || true
grep -o 'on screen [0-9]* ms' "$T/err.txt" | awk '{print $3}' | sort -n |
    awk '{v[NR] = $1} END { if (NR != 5) { print "expected 5 saves, saw " NR; exit 1 } print "median " v[3] " ms" }'
