#!/usr/bin/env bash
# view_keys.sh BUILD_DIR - the viewer's text and its exits: the key table docs/viewer.md shows is
# the one the help overlay draws (`softlight view --keys` prints it from the same table,
# src/app/view_keys.c), every key it names is a name the script language accepts, and a
# DISPLAY with no X server behind it exits 2 with one line, within 5 s, instead of running
# invisibly on SDL's offscreen driver.
set -euo pipefail
source "$(dirname "$0")/view_common.bash"
view_setup "$@"
SCENE=scenes/default.json

# ---- the doc's key table is the program's
"$SL" view --keys >"$T/keys.md"
awk '/^\| input \| action \| script \|$/ { on = 1 } on && !/^\|/ { exit } on' docs/viewer.md >"$T/doc-keys.md"
[ -s "$T/doc-keys.md" ] || fail "docs/viewer.md has no '| input | action | script |' table"
diff "$T/doc-keys.md" "$T/keys.md" || fail "docs/viewer.md's key table differs from softlight view --keys (the help overlay's)"
echo "ok: docs/viewer.md's key table is the overlay's ($(($(wc -l <"$T/keys.md") - 2)) rows)"

# ---- every `key NAME` of the table is accepted by the script language, and runs
grep -o '`key [^`]*`' "$T/keys.md" | tr -d '`' | grep -v -e 'key Escape' -e 'key p$' -e 'key F12' >"$T/keys.txt"
[ "$(wc -l <"$T/keys.txt")" -ge 30 ] || fail "expected at least 30 key names in the table"
{ cat "$T/keys.txt"; echo "key Escape"; echo "key Escape"; echo "quit"; } >"$T/all-keys.txt"
view_run "$SCENE" --size 160x90 -n 4 --script "$T/all-keys.txt"
view_expect_exit0 "every key of the table"
echo "ok: the script accepts and runs every key the table names ($(wc -l <"$T/keys.txt"))"

# ---- DISPLAY pointing at no server: exit 2, one line, within 5 s
d=90
while [ -e "/tmp/.X11-unix/X$d" ] || [ -e "/tmp/.X$d-lock" ]; do d=$((d + 1)); done
set +e
start=$(date +%s.%N)
env -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER DISPLAY=":$d" timeout 10 "$SL" view "$SCENE" >"$T/out.txt" 2>"$T/err.txt"
rc=$?
set -e
secs=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
cat "$T/err.txt"
[ "$rc" -eq 2 ] || fail "DISPLAY=:$d (no server): exit $rc after ${secs}s, expected 2"
awk -v s="$secs" 'BEGIN { exit !(s < 5) }' || fail "DISPLAY=:$d (no server) took ${secs}s"
[ "$(wc -l <"$T/err.txt")" -eq 1 ] || fail "DISPLAY=:$d (no server): expected one line on stderr"
grep -q "^softlight view: no display (DISPLAY=:$d" "$T/err.txt" || fail "the line does not say no display"
echo "ok: a DISPLAY with no server exits 2 with one line in ${secs}s"
echo "PASS view_keys"
