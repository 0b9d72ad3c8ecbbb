#!/usr/bin/env bash
# texture_errors.sh BUILD_DIR - bad texture maps end to end: a missing file, a
# truncated PNG, a corrupt PNG, a JPEG cut short, an absurd size, maps on an OBJ without vt.
# Each must exit with status 2, print one line on stderr naming the scene, the material's map (or
# the object and material) and the file, and leave the existing output file untouched.
set -u
. "$(dirname "$0")/lib.bash"
cli_init texerr "$@"
cp scenes/envmaps/studio.hdr "$T/env.hdr"
good=scenes/textures/tiles.png

# scene NAME MAPFILE [OBJ]: a plane (or the OBJ) whose material "brick" has kd_map MAPFILE.
scene() {
    local obj=${3:-}
    local what='"shape": "plane"'
    [ -n "$obj" ] && what="\"mesh\": \"$obj\""
    cat >"$T/$1.json" <<JSON
{"camera": {"eye": [0, -3, 2], "target": [0, 0, 0]}, "environment": {"hdr": "env.hdr"},
 "materials": {"brick": {"kd_map": "$2"}},
 "objects": [{$what, "material": "brick"}], "render": {"width": 32, "height": 18, "samples": 4}}
JSON
}

expect_error() { # expect_error NAME PATTERN
    echo "keep" >"$T/out.png"
    if ! one_error "$2" "$SL" render "$T/$1.json" -o "$T/out.png" -q || [ "$(cat "$T/out.png")" != keep ]; then
        bad "$1: status $err_status, $err_lines stderr lines (want 2, 1 matching /$2/), output kept: $(head -c 4 "$T/out.png")"
        sed 's/^/    /' "$T/err" | head -5
    else
        ok "$1: $(cat "$T/err")"
    fi
}

scene missing nowhere.png
expect_error missing "missing.json: materials.brick.kd_map: .*nowhere.png"

head -c 300 "$good" >"$T/trunc.png"
scene truncated trunc.png
expect_error truncated "truncated.json: materials.brick.kd_map: .*trunc.png"

cp "$good" "$T/corrupt.png"
printf 'XXXXXXXXXXXXXXXX' | dd of="$T/corrupt.png" bs=1 seek=60 conv=notrunc 2>/dev/null
scene corrupt corrupt.png
expect_error corrupt "corrupt.json: materials.brick.kd_map: .*corrupt.png"

# A JPEG: start of image, then nothing.
printf '\xff\xd8\xff\xe0\x00\x10JFIF\x00' >"$T/cut.jpg"
scene jpeg cut.jpg
expect_error jpeg "jpeg.json: materials.brick.kd_map: .*cut.jpg"

# A PNG header claiming 100000 x 100000 texels (30 GB decoded): refused before decoding.
python3 - "$T/huge.png" <<'PY'
import struct, sys, zlib
def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
open(sys.argv[1], "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 100000, 100000, 8, 2, 0, 0, 0))
                              + chunk(b"IDAT", zlib.compress(b"\0" * 64)) + chunk(b"IEND", b""))
PY
scene huge huge.png
expect_error huge "huge.json: materials.brick.kd_map: .*huge.png"

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$T/no_uv.obj"
scene no_uv "$(pwd)/$good" no_uv.obj
expect_error no_uv 'no_uv.json: objects\[0\]: material "brick" has a kd_map .*tiles.png.*/no_uv.obj has no texture coordinates'

echo "$passes passed, $fails failed"
[ "$fails" -eq 0 ]
