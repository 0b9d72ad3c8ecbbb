#!/usr/bin/env python3
"""make-textures.py - writes the PNG textures of scenes/textured.json into scenes/textures/.

Every texel is computed here from a formula (no photographs, no other sources), so the images
carry this repository's licence and can be regenerated bit for bit: `python3 scripts/make-textures.py`.
PNGs are written with python3's zlib alone (no PIL): 8-bit RGB or RGBA, filter 0, one IDAT.

  tiles.png     256x256 sRGB: a two-colour checker with a thin grout and a darker corner mark per
                tile, for the floor running to the horizon (minification, mip selection) and, at
                4x4 texels per tile, nothing to hide when magnified.
  ramp.png      256x16 grey ramp, code i in column i: declared sRGB on one panel and linear on the
                other, the same bytes read two ways (sRGB 128 -> 0.2159 linear, linear 128 -> 0.502).
  bumps_n.png   128x128 tangent-space normal map (+Y up, OpenGL and glTF): a 4x4 grid of round
                bumps, n = normalize(-dh/du, -dh/dv, 1) encoded as n * 0.5 + 0.5.
  leaf.png      128x128 sRGB + linear alpha: a leaf (alpha 255 inside its outline, 0 outside, a
                2-texel ramp at the edge) with a lighter midrib and veins, for alpha_cutoff.
  pixel.png     8x8 sRGB: a small picture for a magnified, bilinear-filtered face.
"""
import math
import os
import struct
import zlib


def write_png(path, width, height, channels, rows):
    """rows: a list of `height` bytes objects, top row first, width * channels bytes each."""
    colour_type = {3: 2, 4: 6}[channels]
    raw = b"".join(b"\x00" + bytes(r) for r in rows)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def clamp8(x):
    return max(0, min(255, int(round(x))))


def tiles():
    n, tile = 256, 32
    rows = []
    for y in range(n):
        row = bytearray()
        for x in range(n):
            tx, ty = x // tile, y // tile
            fx, fy = x % tile, y % tile
            if fx < 2 or fy < 2:
                c = (60, 58, 55)  # grout
            elif (tx + ty) % 2 == 0:
                c = (200, 170, 120)
            else:
                c = (70, 110, 160)
            if 4 <= fx < 10 and 4 <= fy < 10:  # a corner mark: shows orientation and mip blur
                c = tuple(v // 2 for v in c)
            row += bytes(c)
        rows.append(row)
    write_png("tiles.png", n, n, 3, rows)


def ramp():
    rows = [bytearray(b for i in range(256) for b in (i, i, i)) for _ in range(16)]
    write_png("ramp.png", 256, 16, 3, rows)


def bumps():
    n, cells = 128, 4
    cell = n / cells
    rows = []
    # Height h = cos^2(pi r / (2 R)) inside radius R of each cell centre, in texels * amp.
    R, amp = cell * 0.4, 6.0
    for y in range(n):
        row = bytearray()
        v = n - 1 - y  # PNG rows run top-down; +Y (v) is up in the texture
        for x in range(n):
            cx = (x // cell + 0.5) * cell - 0.5
            cy = ((v // cell) + 0.5) * cell - 0.5
            dx, dy = x - cx, v - cy
            r = math.hypot(dx, dy)
            gx = gy = 0.0
            if 0 < r < R:
                # dh/dr of amp cos^2(pi r / (2R)) = -amp (pi / (2R)) sin(pi r / R)
                dhdr = -amp * (math.pi / (2 * R)) * math.sin(math.pi * r / R)
                gx, gy = dhdr * dx / r, dhdr * dy / r
            nx, ny, nz = -gx, -gy, 1.0
            s = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz)
            row += bytes(clamp8((c * s * 0.5 + 0.5) * 255) for c in (nx, ny, nz))
        rows.append(row)
    write_png("bumps_n.png", n, n, 3, rows)


def leaf():
    n = 128
    rows = []
    for y in range(n):
        row = bytearray()
        for x in range(n):
            # leaf along the diagonal: u along the midrib in [-1, 1], w across it
            px, py = (x + 0.5) / n * 2 - 1, 1 - (y + 0.5) / n * 2
            u = (px + py) / math.sqrt(2) / 0.95
            w = (py - px) / math.sqrt(2)
            half = 0.42 * math.sqrt(max(0.0, 1 - u * u)) * (1 - 0.25 * u)
            edge = (half - abs(w)) * n / 2  # texels inside the outline
            a = clamp8(255 * min(1.0, max(0.0, edge / 2 + 0.5)))
            g = 0.55 + 0.2 * u
            vein = abs(w) < 0.012 or abs((abs(w) * 2.2 + u * 1.0) % 0.28 - 0.14) < 0.012 and abs(w) < half * 0.85
            c = (90 * g, 170 * g, 60 * g) if not vein else (170, 200, 120)
            row += bytes(clamp8(v) for v in c) + bytes([a])
        rows.append(row)
    write_png("leaf.png", n, n, 4, rows)


def pixel():
    art = ["..####..",
           ".#oooo#.",
           "#o#oo#o#",
           "#oooooo#",
           "#o#oo#o#",
           "#oo##oo#",
           ".#oooo#.",
           "..####.."]
    pal = {".": (40, 60, 120), "#": (20, 20, 20), "o": (250, 200, 40)}
    write_png("pixel.png", 8, 8, 3, [bytearray(b for ch in line for b in pal[ch]) for line in art])


if __name__ == "__main__":
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "textures")
    os.makedirs(out, exist_ok=True)
    os.chdir(out)
    tiles(), ramp(), bumps(), leaf(), pixel()
