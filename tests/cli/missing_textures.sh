#!/usr/bin/env bash
# missing_textures.sh BUILD_DIR - a model whose texture files are missing, end to end: refused
# by default (status 2, one line naming model, material and file, no output), drawn with
# `--missing-textures skip` or a model object's "missing_textures": "skip" (status 0, one
# warning line per missing texture naming file and material, the image written), the command
# line's choice over the scene file's, and the key's own errors. render, info, trace and view
# take the option alike.
set -u
. "$(dirname "$0")/lib.bash"
cli_init missing_textures "$@"
cp scenes/envmaps/studio.hdr "$T/env.hdr"

# An OBJ quad with two materials: "wood" names a missing map_Kd, "stone" a missing map_Kd and
# map_Ks (two textures), and one present map would be drawn as usual.
cat >"$T/quad.obj" <<'OBJ'
mtllib quad.mtl
v -1 0 -1
v 1 0 -1
v 1 0 1
v -1 0 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
usemtl wood
f 1/1 2/2 3/3
usemtl stone
f 1/1 3/3 4/4
OBJ
printf 'newmtl wood\nKd 0.5 0.3 0.1\nmap_Kd wood.png\nnewmtl stone\nKd 0.4 0.4 0.4\nmap_Kd stone.png\nmap_Ks stone_spec.png\n' >"$T/quad.mtl"

# The default: one error line, nothing written.
rm -f "$T/a.png"
if one_error 'quad\.obj: material "(wood|stone)": texture "(wood|stone)\.png" not found' \
    "$SL" render "$T/quad.obj" -o "$T/a.png" --size 32x18 -q && [ ! -e "$T/a.png" ]; then
    ok "default fail: $(cat "$T/err")"
else
    bad "default fail: status $err_status, $err_lines lines: $(head -3 "$T/err")"
fi

# skip_ok NAME COMMAND...: status 0, exactly the three warning lines (file and material named),
# nothing else on stderr.
skip_ok() {
    local name=$1
    shift
    "$@" >"$T/out" 2>"$T/err"
    local status=$? lines
    lines=$(wc -l <"$T/err")
    if [ "$status" -eq 0 ] && [ "$lines" -eq 3 ] &&
        grep -q 'warning: .*quad\.obj: material "wood": texture "wood\.png" not found.*draws without it' "$T/err" &&
        grep -q 'material "stone": texture "stone\.png" not found' "$T/err" &&
        grep -q 'material "stone": texture "stone_spec\.png" not found' "$T/err"; then
        ok "$name"
    else
        bad "$name: status $status, $lines stderr lines (want 0, 3 warnings):"
        sed 's/^/    /' "$T/err" | head -5
    fi
}

rm -f "$T/a.png"
skip_ok "render --missing-textures skip" "$SL" render "$T/quad.obj" -o "$T/a.png" --size 32x18 -q --missing-textures skip
[ -s "$T/a.png" ] && ok "skip: the image is written" || bad "skip: no image"
skip_ok "info --missing-textures skip" "$SL" info "$T/quad.obj" --missing-textures skip
skip_ok "trace --missing-textures skip" "$SL" trace "$T/quad.obj" --missing-textures skip --pixel 0,0
# view, where Xvfb is there to run it (the view_*.sh tests require it; this one only adds the option).
if command -v xvfb-run >/dev/null && "$SL" view --help 2>&1 | grep -q -- --missing-textures; then
    export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} # X and Mesa's allocations, as view_common.bash says
    skip_ok "view --missing-textures skip" xvfb-run -a -s "-screen 0 640x480x24 -nolisten tcp" \
        timeout 120 "$SL" view "$T/quad.obj" --frames 2 --missing-textures skip
else
    echo "skip view: no xvfb-run, or softlight built without SDL2"
fi

# The scene file's key, per model; the command line's choice holds over it.
cat >"$T/skip.json" <<'JSON'
{"environment": {"hdr": "env.hdr"}, "camera": {"eye": [0, -4, 3], "target": [0, 0, 0]},
 "objects": [{"model": "quad.obj", "missing_textures": "skip"}], "render": {"width": 32, "height": 18, "samples": 4}}
JSON
skip_ok "a model object's \"missing_textures\": \"skip\"" "$SL" render "$T/skip.json" -o "$T/b.png" -q
if one_error 'objects\[0\]\.model: .*quad\.obj: material "(wood|stone)": texture' \
    "$SL" render "$T/skip.json" -o "$T/b.png" -q --missing-textures fail; then
    ok "--missing-textures fail over the scene's skip: $(cat "$T/err")"
else
    bad "--missing-textures fail over the scene's skip: status $err_status: $(head -3 "$T/err")"
fi

# The key's own errors: an unknown word, a shape with the key.
sed 's/"skip"/"ignore"/' "$T/skip.json" >"$T/word.json"
expect_error "an unknown word" 'word\.json: objects\[0\]\.missing_textures: unknown missing-textures "ignore" \(expected fail\|skip\)' \
    -- "$SL" render "$T/word.json" -o "$T/c.png" -q
sed 's/"model": "quad.obj"/"shape": "plane"/' "$T/skip.json" >"$T/shape.json"
expect_error "the key on a shape" 'shape\.json: objects\[0\]\.missing_textures: only a model has missing_textures' \
    -- "$SL" render "$T/shape.json" -o "$T/c.png" -q
expect_error "an unknown option word" 'missing-textures' \
    -- "$SL" render "$T/quad.obj" -o "$T/c.png" -q --missing-textures maybe

# softlight-gl and softlight check load the scene with the same choice.
GL=$(dirname "$SL")/softlight-gl
if [ -x "$GL" ] && "$GL" info >/dev/null 2>&1; then
    if "$GL" render "$T/quad.obj" --size 32x18 --missing-textures skip --pfm "$T/gl.pfm" 2>"$T/err"; then
        ok "softlight-gl --missing-textures skip draws the model"
    else
        bad "softlight-gl --missing-textures skip: $(head -2 "$T/err")"
    fi
    if "$SL" check "$T/quad.obj" --size 32x18 --missing-textures skip >"$T/out" 2>"$T/err"; then
        ok "softlight check --missing-textures skip: $(grep '^PASS' "$T/out")"
    else
        bad "softlight check --missing-textures skip: $(tail -2 "$T/err")"
    fi
fi

cli_done missing_textures
