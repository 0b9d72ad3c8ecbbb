#!/usr/bin/env python3
"""make-model.py - writes the textured glTF model of scenes/model.json into scenes/models/.

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

Licence: the bunny's geometry is the Stanford Bunny (Stanford 3D Scanning Repository, via the npm
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


def fur_png(path, n=256):
    light, dark = (222, 196, 160), (110, 78, 52)
    rows = []
    for y in range(n):
        row = []
        for x in range(n):
            u, v = 2 * math.pi * x / n, 2 * math.pi * y / n
            patch = math.sin(3 * u + 1.3 * math.sin(2 * v)) + math.sin(2 * v + 0.7) * math.cos(u - 0.4)
            t = smoothstep(0.6, 0.9, patch)
            stripe = 0.93 + 0.07 * math.sin(48 * u + 3 * math.sin(5 * v))
            row += [int(round(stripe * (l + (d - l) * t))) for l, d in zip(light, dark)]
        rows.append(row)
    write_png(path, n, n, rows)


def brass_png(path, n=64):
    a, b = (236, 196, 110), (180, 132, 60)
    rows = [[c for x in range(n) for c in (a if ((x // 8) + (y // 8)) % 2 == 0 else b)] for y in range(n)]
    write_png(path, n, n, rows)


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


def box(lo, hi):
    """24 vertices (4 per face, outward winding), UVs one unit per 8 object units (one checker square per object unit)."""
    pos, uv, tris = [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            a, b = [(axis + 1) % 3, (axis + 2) % 3][:: sign]
            base = len(pos)
            for (s, t) in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = hi[axis] if sign > 0 else lo[axis]
                p[a] = lo[a] + s * (hi[a] - lo[a])
                p[b] = lo[b] + t * (hi[b] - lo[b])
                pos.append(tuple(p))
                uv.append((s * (hi[a] - lo[a]) / 8, t * (hi[b] - lo[b]) / 8))
            tris += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    return pos, uv, tris


def main():
    os.makedirs(OUT, exist_ok=True)
    fur_png(os.path.join(OUT, "fur.png"))
    brass_png(os.path.join(OUT, "brass.png"))
    bpos, btris = read_bunny()
    buv = bunny_uv(bpos)
    ppos, puv, ptris = box((-6.5, -1.5, -5.0), (6.5, 0.0, 5.0))

    buf, views, accessors, meshes = bytearray(), [], [], []
    def add(data, target, **acc):
        while len(buf) % 4:
            buf.append(0)
        views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(data), "target": target})
        buf.extend(data)
        accessors.append(dict(bufferView=len(views) - 1, **acc))
        return len(accessors) - 1

    for name, pos, uv, tris, material in (("bunny", bpos, buv, btris, 0), ("pedestal", ppos, puv, ptris, 1)):
        lo = [min(p[i] for p in pos) for i in range(3)]
        hi = [max(p[i] for p in pos) for i in range(3)]
        a_pos = add(b"".join(struct.pack("<3f", *p) for p in pos), 34962, componentType=5126, count=len(pos),
                    type="VEC3", min=lo, max=hi)
        a_uv = add(b"".join(struct.pack("<2f", *t) for t in uv), 34962, componentType=5126, count=len(uv),
                   type="VEC2")
        a_idx = add(b"".join(struct.pack("<3I", *t) for t in tris), 34963, componentType=5125, count=3 * len(tris),
                    type="SCALAR")
        meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": a_pos, "TEXCOORD_0": a_uv},
                                                     "indices": a_idx, "material": material}]})
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


if __name__ == "__main__":
    main()
