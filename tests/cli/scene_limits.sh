#!/usr/bin/env bash
# scene_limits.sh BUILD_DIR - limits of a scene file found where the scene is read: `info` fails as `render` would, with one line naming the file and the JSON
# path, and `render` writes nothing; a scene at the limit renders. docs/scene-format.md
# "Limits" lists them.
set -u
. "$(dirname "$0")/lib.bash"
cli_init limits "$@"

# expect_error NAME PATTERN -- COMMAND...: status 2, one stderr line matching PATTERN, no
# byte outside printable ASCII on it, no output file.
expect_error() {
    local name=$1 pattern=$2; shift 3
    rm -f "$T/a.png"
    if ! one_error "$pattern" "$@"; then
        bad "$name: status $err_status, $err_lines stderr lines (want 2, 1 matching /$pattern/):"
        sed 's/^/    /' "$T/err" | head -5
    elif LC_ALL=C grep -q '[^[:print:]]' "$T/err"; then
        bad "$name: a byte that is not printable ASCII reached the message: $(cat -v "$T/err")"
    elif [ -e "$T/a.png" ]; then
        bad "$name: a.png was written"
    else
        ok "$name: $(cat "$T/err")"
    fi
}

# lights.json with N point lights around a sphere under the studio environment.
lights() { # lights FILE N
    local list="" i
    for ((i = 0; i < $2; i++)); do list="$list${list:+, }{\"position\": [$i, -3, 3], \"intensity\": 0.5}"; done
    cat >"$1" <<JSON
{"environment": "$PWD/scenes/envmaps/studio.hdr", "objects": [{"shape": "sphere"}],
 "lights": [$list], "render": {"width": 32, "height": 18, "samples": 4}}
JSON
}
lights "$T/l16.json" 16
lights "$T/l17.json" 17

# A 17th light fails where the scene is read, with the file and the JSON path: in `info`, in
# `render`, and with --no-lights too.
pat='l17\.json: lights\[16\]: at most 16 point lights \(MAX_LIGHTS of shaders/lighting\.frag\)'
expect_error lights-info "$pat" -- "$SL" info "$T/l17.json"
expect_error lights-render "$pat" -- "$SL" render "$T/l17.json" -o "$T/a.png" -q
expect_error lights-no-lights "$pat" -- "$SL" render "$T/l17.json" --no-lights -o "$T/a.png" -q
if "$SL" render "$T/l16.json" -o "$T/l16.png" -q && [ -s "$T/l16.png" ]; then
    echo "ok   16 point lights render"; passes=$((passes + 1))
else
    echo "FAIL 16 point lights did not render"; fails=$((fails + 1))
fi

# Nesting past the JSON parser's limit is named as such; \u0000 in a key is refused, not cut
# short; bytes of the file are masked in the message, not echoed raw.
{ printf '{"camera": {"eye": '; printf '[%.0s' $(seq 999); printf ']%.0s' $(seq 999); printf '}}'; } >"$T/deep.json"
printf '{"objects": [{"shape": "box", "na\\u0000me": "x"}]}' >"$T/nul.json"
printf '{"objects": [{"shape": "box", "\033[2J\033[31m": 1}]}' >"$T/esc.json"
expect_error json-depth 'deep\.json:1:1018: camera\.eye\[0\]\[0\].*nested deeper than 1000 levels' -- "$SL" info "$T/deep.json"
expect_error json-nul-key 'nul\.json:1:34: objects\[0\]: the key "na\\u0000me" holds \\u0000' -- "$SL" info "$T/nul.json"
expect_error json-raw-bytes 'esc\.json: objects\[0\]: unknown key "\?\[2J\?\[31m"' -- "$SL" render "$T/esc.json" -o "$T/a.png" -q

echo "$passes passed, $fails failed"
[ "$fails" -eq 0 ]
