#!/usr/bin/env python3
"""png_compare.py A.png B.png SHARE - compare two 8-bit PNG images (grey, RGB or RGBA; what
sl_image_write_png writes) pixel by pixel, with the standard library only.

Prints the largest difference of a channel (in codes of 255), the mean absolute difference and
the share of pixels with a channel more than 2 codes apart. Exit status 0 when the sizes agree
and that share is at most SHARE percent, 1 otherwise, 2 on an unreadable file."""
import struct
import sys
import zlib


def read_png(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG file")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(colour)
    if depth != 8 or channels is None or interlace:
        raise ValueError(f"{path}: only 8-bit, non-interlaced grey or RGB(A) PNGs")
    raw, stride = zlib.decompress(idat), width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return width, height, channels, rows


def main():
    if len(sys.argv) != 4:
        print(__doc__.strip().splitlines()[0], file=sys.stderr)
        return 2
    try:
        wa, ha, ca, a = read_png(sys.argv[1])
        wb, hb, cb, b = read_png(sys.argv[2])
    except (OSError, ValueError, TypeError, zlib.error, struct.error) as e:
        print(f"png_compare: {e}", file=sys.stderr)
        return 2
    if (wa, ha, ca) != (wb, hb, cb):
        print(f"sizes differ: {wa}x{ha}x{ca} and {wb}x{hb}x{cb}")
        return 1
    worst, total, over = 0, 0, 0
    for ra, rb in zip(a, b):
        for x in range(wa):
            d = max(abs(ra[x * ca + k] - rb[x * ca + k]) for k in range(ca))
            worst, total, over = max(worst, d), total + sum(abs(ra[x * ca + k] - rb[x * ca + k]) for k in range(ca)), over + (d > 2)
    share = 100.0 * over / (wa * ha)
    print(f"max {worst}/255, mean {total / (wa * ha * ca):.4f}/255, {share:.2f}% of pixels more than 2/255 apart")
    return 0 if share <= float(sys.argv[3]) else 1


if __name__ == "__main__":
    sys.exit(main())
