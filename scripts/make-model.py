#!/usr/bin/env python3
"""make-model.py - writes the glTF models of scenes/model.json and scenes/pbr.json into scenes/models/.

`python3 scripts/make-model.py` (python3's json, struct and zlib only) regenerates, bit for bit:

  bunny.gltf    glTF 2.0: two meshes under one root node (scale 0.2, glTF's Y-up like the OBJ):
                the Stanford bunny of scenes/meshes/bunny.obj (its positions and triangles, no
                normals: the importer makes smooth ones) with texture coordinates projected on
                its side (u along the body, nose to tail; v down from the ears), and a pedestal
                box under it with per-face coordinates (one checker square per object unit).
                Materials: "fur", a rough dielectric (metallic 0, roughness 0.55) with fur.png as
                baseColorTexture; "brass", a metal (metallic 1, roughness 0.3) with brass.png,
                which the importer draws as Ks too (a full metal's Ks is its base colour).
  bunny.bin     the buffer: positions, texture coordinates, indices (uint32), per mesh.
  fur.png       256x256 sRGB: a warm coat with darker patches (a sum of sines thresholded with
                a smooth step) and fine stripes along u, for a texture that shows its orientation.
  brass.png     64x64 sRGB: a two-tone brass checker, 8x8 texels per square.

  pbr.gltf      glTF 2.0, scenes/pbr.json's model: one material ("panel") with all five glTF
                textures, on a UV sphere (its own NORMALs; u around, v pole to pole) and on a
                thin upright panel (a box whose front face carries the whole texture square),
                each placed by a node (translation; the panel also a rotation, tilted back 12
                degrees). The texture square is an 8x8 grid of bevelled tiles: the left half
                (u < 0.5) metal, the right half dielectric, roughness rising down the square.
  pbr.bin       the buffer: positions, normals (both meshes: flat ones on the panel), texture
                coordinates, indices (uint16).
  pbr_base.png  256x256 sRGB baseColorTexture: per tile column a metal (gold, copper, silver,
                iron) on the left half and a paint (red, green, blue, white) on the right, darker
                grooves between the tiles.
  pbr_orm.png   256x256 linear, glTF's packed layout, read by two textures: R occlusion
                (occlusionTexture: 1 on the tiles, 0.3 deep in the grooves), G roughness
                (metallicRoughnessTexture: 0.1 at the top row of tiles to 1 at the bottom, one
                value per tile row),
                B metallic (255 on the left half, 0 on the right; grooves dielectric).
  pbr_normal.png 256x256 linear normalTexture (tangent space, +Y up toward the image's top row as
                glTF's): the tiles' bevels and a round rivet at each tile's centre, from a height
                field h, n = normalize(-dh/dx, dh/dy, 1) with y down the image.
  pbr_emit.png  128x128 sRGB emissiveTexture (emissiveFactor 1): the grooves of the fourth tile
                row glow cyan, the rivets of the seventh row orange; black elsewhere.

Licence: pbr.* is computed here entirely (this repository's licence). The bunny's geometry is the Stanford Bunny (Stanford 3D Scanning Repository, via the npm
package "bunny", as scenes/meshes/bunny.obj); everything else (coordinates, pedestal, textures,
materials) is computed here and under this repository's licence.
"""
import json
import math
import os
import struct
import zlib

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
OUT = os.path.join(ROOT, "scenes", "models")


def write_png(path, width, height, rows):
    """8-bit RGB, filter 0, one IDAT; rows top first (glTF's v = 0)."""
    raw = b"".join(b"\x00" + bytes(r) for r in rows)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def smoothstep(a, b, x):
    t = min(max((x - a) / (b - a), 0.0), 1.0)
    return t * t * (3 - 2 * t)


def field_png(path, n, texel):
    """An n x n RGB PNG of texel(x, y) -> (r, g, b) codes, y down the image (rows top first)."""
    write_png(path, n, n, [[c for x in range(n) for c in texel(x, y)] for y in range(n)])


class GltfBuffer:
    """One .bin with its bufferViews and accessors: add() appends 4-byte aligned data."""

    def __init__(self):
        self.buf, self.views, self.accessors = bytearray(), [], []

    def add(self, data, target, **acc):
        while len(self.buf) % 4:
            self.buf.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.buf), "byteLength": len(data), "target": target})
        self.buf.extend(data)
        self.accessors.append(dict(bufferView=len(self.views) - 1, **acc))
        return len(self.accessors) - 1

    def positions(self, pos):
        lo = [min(p[i] for p in pos) for i in range(3)]
        hi = [max(p[i] for p in pos) for i in range(3)]
        return self.add(b"".join(struct.pack("<3f", *p) for p in pos), 34962, componentType=5126, count=len(pos),
                        type="VEC3", min=lo, max=hi)

    def uvs(self, uv):
        return self.add(b"".join(struct.pack("<2f", *t) for t in uv), 34962, componentType=5126, count=len(uv),
                        type="VEC2")


def fur_png(path, n=256):
    light, dark = (222, 196, 160), (110, 78, 52)

    def texel(x, y):
        u, v = 2 * math.pi * x / n, 2 * math.pi * y / n
        patch = math.sin(3 * u + 1.3 * math.sin(2 * v)) + math.sin(2 * v + 0.7) * math.cos(u - 0.4)
        t = smoothstep(0.6, 0.9, patch)
        stripe = 0.93 + 0.07 * math.sin(48 * u + 3 * math.sin(5 * v))
        return [int(round(stripe * (l + (d - l) * t))) for l, d in zip(light, dark)]
    field_png(path, n, texel)


def brass_png(path, n=64):
    a, b = (236, 196, 110), (180, 132, 60)
    field_png(path, n, lambda x, y: a if ((x // 8) + (y // 8)) % 2 == 0 else b)


def read_bunny():
    pos, tris = [], []
    with open(os.path.join(ROOT, "scenes", "meshes", "bunny.obj")) as f:
        for line in f:
            p = line.split()
            if p and p[0] == "v":
                pos.append(tuple(float(c) for c in p[1:4]))
            elif p and p[0] == "f":
                tris.append(tuple(int(c.split("/")[0]) - 1 for c in p[1:4]))
    return pos, tris


def bunny_uv(pos):
    """Projected on the side (the XY plane of the Y-up OBJ): u from x (nose at -X), v from y
    downwards, two repeats along the body; repeat wrap, no seam."""
    xs, ys = [p[0] for p in pos], [p[1] for p in pos]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    return [(2 * (p[0] - x0) / (x1 - x0), 2 * (y1 - p[1]) / (y1 - y0)) for p in pos]


def box_faces(lo, hi):
    """The six faces of the box lo..hi, each as (axis, sign, a, b, corners): the face lies at
    hi[axis] (sign +1) or lo[axis] (-1), a and b are the other two axes in the order that winds it
    outward, corners its four (s, t, position) with s along a and t along b, in winding order."""
    for axis in range(3):
        for sign in (-1, 1):
            a, b = [(axis + 1) % 3, (axis + 2) % 3][:: sign]
            corners = []
            for (s, t) in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = hi[axis] if sign > 0 else lo[axis]
                p[a] = lo[a] + s * (hi[a] - lo[a])
                p[b] = lo[b] + t * (hi[b] - lo[b])
                corners.append((s, t, tuple(p)))
            yield axis, sign, a, b, corners


def box(lo, hi):
    """24 vertices (4 per face, outward winding), UVs one unit per 8 object units (one checker square per object unit)."""
    pos, uv, tris = [], [], []
    for axis, sign, a, b, corners in box_faces(lo, hi):
        base = len(pos)
        for s, t, p in corners:
            pos.append(p)
            uv.append((s * (hi[a] - lo[a]) / 8, t * (hi[b] - lo[b]) / 8))
        tris += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    return pos, uv, tris


# --- scenes/pbr.json's model: every glTF texture on one material -------------------------------

TILES = 8  # tiles per side of the texture square


def tile_field(x, y, n):
    """At texel centre (x, y) of an n x n image: (column, row, distance to the tile's edge in
    texels, distance to the tile's centre in texels), n / TILES texels per tile."""
    size = n / TILES
    fx, fy = (x + 0.5) / size, (y + 0.5) / size
    col, row = int(fx), int(fy)
    ex, ey = (fx - col) * size, (fy - row) * size
    edge = min(ex, size - ex, ey, size - ey)
    centre = math.hypot(ex - size / 2, ey - size / 2)
    return col, row, edge, centre


def pbr_height(x, y, n):
    """Height in texels: the groove at 0, a bevel rising over 6 texels (texels 1 .. 7 from the
    edge) to the tile at 2.5, a rivet at the centre rising 2 more (a cos^2 dome of radius 7).
    Gentle slopes (at most about 0.6) keep the normals smooth across mip levels, so the filtering
    differences between softlight and GL (gl_pipeline.sh) stay small on the mirror-like tiles."""
    _, _, edge, centre = tile_field(x % n, y % n, n)
    h = 2.5 * smoothstep(1.0, 7.0, edge)
    if centre < 7.0:
        h += 2.0 * math.cos(0.5 * math.pi * centre / 7.0) ** 2
    return h


PBR_METALS = ((255, 227, 156), (250, 209, 194), (252, 250, 245), (198, 198, 201))  # gold copper silver iron
PBR_PAINTS = ((180, 40, 35), (50, 140, 60), (40, 70, 170), (230, 230, 225))


def pbr_base_png(path, n=256):
    def texel(x, y):
        col, _, edge, _ = tile_field(x, y, n)
        c = PBR_METALS[col % 4] if col < TILES // 2 else PBR_PAINTS[col % 4]
        t = smoothstep(1.0, 3.0, edge)  # 0 in the groove
        return [int(round(60 + (v - 60) * t)) for v in c]
    field_png(path, n, texel)


def pbr_orm_png(path, n=256):
    def texel(x, y):
        col, trow, edge, _ = tile_field(x, y, n)
        occlusion = 0.3 + 0.7 * smoothstep(0.5, 5.0, edge)
        roughness = 0.1 + 0.9 * trow / (TILES - 1)
        metal = col < TILES // 2 and edge > 1.0
        return [int(round(255 * occlusion)), int(round(255 * roughness)), 255 if metal else 0]
    field_png(path, n, texel)


def pbr_normal_png(path, n=256):
    def texel(x, y):
        dx = (pbr_height(x + 1, y, n) - pbr_height(x - 1, y, n)) / 2
        dy = (pbr_height(x, y + 1, n) - pbr_height(x, y - 1, n)) / 2
        # +Y is up the image (y runs down it): the normal leans against the slope
        nx, ny, nz = -dx, dy, 1.0
        k = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz)
        return [int(round(255 * (0.5 + 0.5 * c * k))) for c in (nx, ny, nz)]
    field_png(path, n, texel)


def pbr_emit_png(path, n=128):
    def texel(x, y):
        _, trow, edge, centre = tile_field(x, y, n)
        if trow == 3 and edge < 1.0:
            return (0, 200, 255)
        if trow == 6 and centre < 2.5 * n / 256 * 2:
            return (255, 140, 30)
        return (0, 0, 0)
    field_png(path, n, texel)


def uv_sphere(radius, centre_y, segments=64, rings=32):
    """u around (u = 0.5 faces glTF's +Z, the camera; u grows toward +X), v from the top pole."""
    pos, nrm, uv, tris = [], [], [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments - math.pi
            d = (math.sin(theta) * math.sin(phi), math.cos(theta), math.sin(theta) * math.cos(phi))
            pos.append((radius * d[0], centre_y + radius * d[1], radius * d[2]))
            nrm.append(d)
            uv.append((j / segments, i / rings))
    w = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b, c, d = i * w + j, (i + 1) * w + j, (i + 1) * w + j + 1, i * w + j + 1
            if i > 0:
                tris.append((a, b, d))  # counter-clockwise seen from outside
            if i < rings - 1:
                tris.append((b, c, d))
    return pos, nrm, uv, tris


def panel(half_w, height, half_t):
    """A box standing on y = 0: the front face (+Z) carries the whole texture square (u with +X,
    v down), the other faces the square scaled to their size; flat normals, 4 vertices a face."""
    pos, nrm, uv, tris = [], [], [], []
    lo, hi = (-half_w, 0.0, -half_t), (half_w, height, half_t)
    for axis, sign, a, b, corners in box_faces(lo, hi):
        base = len(pos)
        for s, t, p in corners:
            pos.append(p)
            q = [0.0, 0.0, 0.0]
            q[axis] = float(sign)
            nrm.append(tuple(q))
            if axis == 2:  # front and back: the whole square, v down the panel
                uv.append(((p[0] - lo[0]) / (hi[0] - lo[0]), (hi[1] - p[1]) / (hi[1] - lo[1])))
            else:
                uv.append((s * (hi[a] - lo[a]) / (2 * half_w), t * (hi[b] - lo[b]) / (2 * half_w)))
        tris += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    return pos, nrm, uv, tris


def pbr_model():
    pbr_base_png(os.path.join(OUT, "pbr_base.png"))
    pbr_orm_png(os.path.join(OUT, "pbr_orm.png"))
    pbr_normal_png(os.path.join(OUT, "pbr_normal.png"))
    pbr_emit_png(os.path.join(OUT, "pbr_emit.png"))
    gb, meshes = GltfBuffer(), []
    for name, (pos, nrm, uv, tris) in (("sphere", uv_sphere(0.9, 0.9)), ("panel", panel(0.9, 1.8, 0.06))):
        a_pos = gb.positions(pos)
        a_nrm = gb.add(b"".join(struct.pack("<3f", *p) for p in nrm), 34962, componentType=5126, count=len(nrm),
                       type="VEC3")
        a_uv = gb.uvs(uv)
        a_idx = gb.add(b"".join(struct.pack("<3H", *t) for t in tris), 34963, componentType=5123,
                       count=3 * len(tris), type="SCALAR")
        meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": a_pos, "NORMAL": a_nrm,
                                                                    "TEXCOORD_0": a_uv},
                                                     "indices": a_idx, "material": 0}]})
    buf, views, accessors = gb.buf, gb.views, gb.accessors
    with open(os.path.join(OUT, "pbr.bin"), "wb") as f:
        f.write(buf)
    tilt = math.radians(-12.0)  # about +X: the panel's top leans away from the camera (-Z)
    doc = {
        "asset": {"version": "2.0", "generator": "softlight scripts/make-model.py",
                  "copyright": "softlight's licence (computed by scripts/make-model.py)"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "sphere", "mesh": 0, "translation": [-1.05, 0.0, 0.0]},
                  {"name": "panel", "mesh": 1, "translation": [1.05, 0.0, -0.2],
                   "rotation": [math.sin(tilt / 2), 0.0, 0.0, math.cos(tilt / 2)]}],
        "meshes": meshes,
        "materials": [
            {"name": "panel",
             "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1},
                                      "metallicFactor": 1.0, "roughnessFactor": 1.0},
             "normalTexture": {"index": 2}, "occlusionTexture": {"index": 1, "strength": 1.0},
             "emissiveTexture": {"index": 3}, "emissiveFactor": [1.0, 1.0, 1.0]},
        ],
        "textures": [{"source": i, "sampler": 0} for i in range(4)],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"uri": "pbr_base.png"}, {"uri": "pbr_orm.png"}, {"uri": "pbr_normal.png"},
                   {"uri": "pbr_emit.png"}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"uri": "pbr.bin", "byteLength": len(buf)}],
    }
    with open(os.path.join(OUT, "pbr.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def main():
    os.makedirs(OUT, exist_ok=True)
    fur_png(os.path.join(OUT, "fur.png"))
    brass_png(os.path.join(OUT, "brass.png"))
    bpos, btris = read_bunny()
    buv = bunny_uv(bpos)
    ppos, puv, ptris = box((-6.5, -1.5, -5.0), (6.5, 0.0, 5.0))

    gb, meshes = GltfBuffer(), []
    for name, pos, uv, tris, material in (("bunny", bpos, buv, btris, 0), ("pedestal", ppos, puv, ptris, 1)):
        a_pos, a_uv = gb.positions(pos), gb.uvs(uv)
        a_idx = gb.add(b"".join(struct.pack("<3I", *t) for t in tris), 34963, componentType=5125,
                       count=3 * len(tris), type="SCALAR")
        meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": a_pos, "TEXCOORD_0": a_uv},
                                                     "indices": a_idx, "material": material}]})
    buf, views, accessors = gb.buf, gb.views, gb.accessors
    with open(os.path.join(OUT, "bunny.bin"), "wb") as f:
        f.write(buf)
    doc = {
        "asset": {"version": "2.0", "generator": "softlight scripts/make-model.py",
                  "copyright": "bunny geometry: Stanford 3D Scanning Repository; the rest: softlight's licence"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "root", "scale": [0.2, 0.2, 0.2], "children": [1, 2]},
                  {"name": "bunny", "mesh": 0},
                  {"name": "pedestal", "mesh": 1}],
        "meshes": meshes,
        "materials": [
            {"name": "fur", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0,
                                                     "roughnessFactor": 0.55}},
            {"name": "brass", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}, "metallicFactor": 1.0,
                                                       "roughnessFactor": 0.3}},
        ],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"uri": "fur.png"}, {"uri": "brass.png"}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"uri": "bunny.bin", "byteLength": len(buf)}],
    }
    with open(os.path.join(OUT, "bunny.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    pbr_model()


if __name__ == "__main__":
    main()
