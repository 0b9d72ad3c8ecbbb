#!/usr/bin/env bash
# models.sh BUILD_DIR - model files through assimp end to end:
# `softlight render FILE` and `info FILE` with no scene file (the default scene: the file's
# camera or one framing the bounds), an OBJ+MTL's material arriving, and bad files: status 2,
# one line naming the file, no output written, no hang (a FIFO or /dev/zero named as a buffer).
set -u
. "$(dirname "$0")/lib.bash"
cli_init models "$@"

# expect_error NAME PATTERN FILE: render FILE fails in 20 s with status 2 and one stderr line
# naming FILE's base name and matching PATTERN; a.png is not written.
expect_error() {
    local name=$1 pattern=$2 file=$3
    rm -f "$T/a.png"
    if ! one_error "$pattern" timeout 20 "$SL" render "$file" -o "$T/a.png" --size 32x18 -q ||
        ! grep -qF -- "$(basename "$file")" "$T/err" || [ -e "$T/a.png" ]; then
        bad "$name: status $err_status, $err_lines lines (want 2, 1 naming $(basename "$file") and matching /$pattern/): $(head -3 "$T/err")"
    else
        ok "$name: $(cat "$T/err")"
    fi
}

# An OBJ quad with an MTL material: Kd and Ns arrive as the scene material's kd and alpha.
cat >"$T/quad.obj" <<'OBJ'
mtllib quad.mtl
v -1 0 -1
v 1 0 -1
v 1 0 1
v -1 0 1
usemtl tile
f 1 2 3 4
OBJ
printf 'newmtl tile\nKd 0.5 0.25 0.125\nKs 0.04 0.04 0.04\nNs 50\n' >"$T/quad.mtl"
if "$SL" render "$T/quad.obj" -o "$T/quad.png" --size 64x36 -q 2>"$T/err" && [ -s "$T/quad.png" ]; then
    ok "render quad.obj with no scene file"
else
    bad "render quad.obj: $(cat "$T/err")"
fi
"$SL" info "$T/quad.obj" >"$T/info" 2>&1
if grep -q 'material quad/tile (kd 0.5 0.25 0.125, ks 0.04 0.04 0.04, alpha 50)' "$T/info"; then
    ok "quad.obj's MTL material arrives"
else
    bad "quad.obj's material: $(grep material "$T/info")"
fi

# A flat model standing in the file's x = 0 plane: the default camera sees its face (from the
# front it would see the plane edge-on and draw nothing); a camera turned away from everything
# draws the environment alone, with a warning.
printf 'v 0 0 0\nv 0 1 0\nv 0 1 1\nv 0 0 1\nf 1 2 3 4\n' >"$T/plaque.obj"
if "$SL" render "$T/plaque.obj" -o "$T/plaque.png" --size 64x36 -q 2>"$T/err" && [ ! -s "$T/err" ]; then
    ok "a flat model framed face-on, no warning"
else
    bad "a flat model: $(cat "$T/err")"
fi
printf '{"camera": {"eye": [0, 0, 5], "target": [0, 0, 10], "up": [0, 1, 0]},\n "objects": [{"shape": "sphere"}]}\n' >"$T/away.json"
if "$SL" render "$T/away.json" -o "$T/away.png" --size 64x36 -q 2>"$T/err" && grep -q 'warning: .*away.json: no surface is in view' "$T/err"; then
    ok "a camera seeing no triangle: warned"
else
    bad "a camera seeing no triangle: $(cat "$T/err")"
fi

# A glTF with its buffer in a data URI and a camera at (0, 0, 5) (Y-up): the default scene's eye
# is (0, -5, 0) (Z-up).
gltf() { # gltf FILE BUFFER_URI
    python3 - "$1" "$2" <<'PY'
import base64, json, struct, sys
b = struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack('<4H', 0, 1, 2, 0)
uri = sys.argv[2] if sys.argv[2] != 'data' else 'data:application/octet-stream;base64,' + base64.b64encode(b).decode()
doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
       "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 5]}],
       "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100}}],
       "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
       "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                     {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
       "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
       "buffers": [{"byteLength": len(b), "uri": uri}]}
open(sys.argv[1], 'w').write(json.dumps(doc))
PY
}
gltf "$T/tri.gltf" data
if "$SL" render "$T/tri.gltf" -o "$T/tri.png" --size 64x36 -q 2>"$T/err" && [ -s "$T/tri.png" ]; then
    ok "render tri.gltf with no scene file"
else
    bad "render tri.gltf: $(cat "$T/err")"
fi
"$SL" info "$T/tri.gltf" >"$T/info" 2>&1
if grep -qE '^  eye +\(0, -5, 0\)' "$T/info"; then ok "tri.gltf's camera"; else bad "tri.gltf's camera: $(grep eye "$T/info")"; fi

# Bad files.
gltf "$T/nobin.gltf" nobin.bin
expect_error "missing .bin" 'nobin\.bin", which cannot be read \(no such file\)' "$T/nobin.gltf"
mkfifo "$T/fifo.bin"
gltf "$T/fifo.gltf" fifo.bin
expect_error "a FIFO as the buffer" 'not a regular file' "$T/fifo.gltf"
gltf "$T/zero.gltf" /dev/zero
# (assimp joins the absolute path to the model's folder: never read either way)
expect_error "/dev/zero as the buffer" 'cannot be read' "$T/zero.gltf"
mkfifo "$T/pipe.glb"
expect_error "a FIFO as the model" 'not a regular file' "$T/pipe.glb"
head -c 100 "$T/tri.gltf" >"$T/cut.gltf"
expect_error "truncated .gltf" 'invalid JSON' "$T/cut.gltf"
printf 'glTF\002\000\000\000\377\000\000\000' >"$T/cut.glb"
head -c 20 /dev/zero >>"$T/cut.glb"
expect_error "truncated .glb" 'truncated \.glb' "$T/cut.glb"
echo hello >"$T/model.xyz"
expect_error "unknown format" 'unknown model format' "$T/model.xyz"
expect_error "no such file" 'no such file' "$T/absent.glb"
# A COLLADA file in centimetres whose camera, 5 m from a 2 m triangle, has a 37.85-degree xfov
# and clipping planes at 10 and 10000 cm: the camera sees the triangle (near and far scaled to
# metres with the eye; the field of view read as the whole angle: 25.75 degrees vertically).
cat >"$T/camtri.dae" <<'DAE'
<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Y_UP</up_axis></asset>
  <library_cameras><camera id="cam" name="cam"><optics><technique_common><perspective>
    <xfov sid="xfov">37.85</xfov><aspect_ratio>1.5</aspect_ratio><znear sid="znear">10</znear>
    <zfar sid="zfar">10000</zfar></perspective></technique_common></optics></camera></library_cameras>
  <library_geometries><geometry id="tri" name="tri"><mesh>
    <source id="tri-pos"><float_array id="tri-pos-array" count="9">-100 -100 0 100 -100 0 0 100 0</float_array>
      <technique_common><accessor source="#tri-pos-array" count="3" stride="3"><param name="X" type="float"/>
        <param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
    <vertices id="tri-vtx"><input semantic="POSITION" source="#tri-pos"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#tri-vtx" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s" name="s">
    <node id="n" name="n"><translate sid="location">0 0 500</translate><instance_camera url="#cam"/></node>
    <node id="m" name="m"><instance_geometry url="#tri"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
DAE
"$SL" info "$T/camtri.dae" >"$T/info" 2>&1
if grep -q 'fovy       25.75.* degrees, near 0.1, far 100$' "$T/info" &&
    "$SL" render "$T/camtri.dae" -o "$T/camtri.png" --size 64x36 -q 2>"$T/err" && [ ! -s "$T/err" ]; then
    ok "a COLLADA camera in centimetres sees its model"
else
    bad "a COLLADA camera: $(grep fovy "$T/info") $(cat "$T/err")"
fi

# A model given alone whose texture is not an image: one line that names the model once.
printf 'mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n' >"$T/tex.obj"
printf 'newmtl m\nKd 1 1 1\nmap_Kd junk.png\n' >"$T/t.mtl"
printf 'not an image' >"$T/junk.png"
expect_error "a texture that is no image" '^softlight render: [^ ]*tex\.obj: material "m": map_Kd: [^ ]*junk\.png: byte 0' "$T/tex.obj"

# Files without triangles: a COLLADA file of one camera (assimp builds a placeholder skeleton for
# it, which is not drawn) and an OBJ of one line.
cat >"$T/camera.dae" <<'DAE'
<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_cameras><camera id="cam"><optics><technique_common><perspective><yfov>37.85</yfov>
    <aspect_ratio>1.5</aspect_ratio><znear>0.1</znear><zfar>100</zfar></perspective></technique_common></optics></camera>
  </library_cameras>
  <library_visual_scenes><visual_scene id="s"><node id="n"><translate>0 0 5</translate>
    <instance_camera url="#cam"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
DAE
expect_error "cameras only" 'no triangle meshes \(softlight draws triangles' "$T/camera.dae"
printf 'v 0 0 0\nv 1 0 0\nl 1 2\n' >"$T/line.obj"
expect_error "lines only" 'no triangle meshes \(softlight draws triangles' "$T/line.obj"
# Counts the importer would trust: an OFF file declaring 10^8 faces is refused by softlight's
# own check of the format; a 200-byte PLY declaring 4x10^8 vertices reaches the importer, whose
# child runs out of its budget at once (4x10^8 positions are 4.8 GB). A face
# index past the vertex list, and an OBJ material no .mtl defines, are refused too.
printf 'OFF\n3 100000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$T/bomb.off"
expect_error "an OFF file declaring 10^8 faces" 'declares 3 vertices and 100000000 faces' "$T/bomb.off"
printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 9\n' >"$T/range.off"
expect_error "an OFF face past the vertices" 'face 1: vertex index 9 out of range \(4 vertices\)' "$T/range.off"
printf 'mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl nothere\nf 1 2 3\n' >"$T/nomat.obj"
printf 'newmtl other\nKd 1 0 0\n' >"$T/m.mtl"
expect_error "an undefined OBJ material" 'material "nothere" \(usemtl\) is defined by no newmtl' "$T/nomat.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Default\nf 1 2 3\n' >"$T/nolib.obj"
expect_error "usemtl with no mtllib" 'material "Default" \(usemtl\) is not defined: the file names no \.mtl library \(no mtllib line\)' "$T/nolib.obj"
rm "$T/m.mtl"
expect_error "a missing .mtl" 'its library "m.mtl" cannot be read \(no such file\)' "$T/nomat.obj"
# An importer that prints on its own: OpenGEX's parser writes a line to std::cerr for an empty
# structure before assimp fails; the import's child keeps it off the terminal, so the error is
# one line.
printf 'CameraObject {}\n' >"$T/empty_camera.ogex"
expect_error "an OpenGEX file whose parser prints" 'Validation failed' "$T/empty_camera.ogex"
# A companion file an importer only looks for is not why the import failed: an empty MD5 mesh
# is refused for its contents, not for the .md5anim beside it that does not exist.
: >"$T/empty.md5mesh"
expect_error "an empty MD5 mesh" 'empty\.md5mesh: Failed to read valid contents' "$T/empty.md5mesh"
# AddressSanitizer's builds bound the import's time only, so the memory case runs without them.
if [ -z "${SL_SANITIZED:-}" ]; then
    printf 'ply\nformat ascii 1.0\nelement vertex 400000000\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$T/bomb.ply"
    expect_error "a PLY file declaring 4x10^8 vertices" 'the import needs more than the 768 MiB' "$T/bomb.ply"
fi

echo "models: $passes passed, $fails failed"
[ "$fails" -eq 0 ]
