"""pfm.py - the PFM reader and writer the CLI tests' Python checks and the benchmarks share
(standard library only): they run with tests/cli on their path and `from pfm import read_pfm`."""
import struct


def read_pfm(path):
    """(width, height, channels, values): the values as stored, bottom row first."""
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        n = width * height * channels
        data = struct.unpack(("<" if scale < 0 else ">") + "%df" % n, f.read(n * 4))
    return width, height, channels, data


def write_pfm(path, width, height, values):
    """PATH as a little-endian colour PFM: VALUES are width * height RGB triples, flat, bottom
    row first (read_pfm's order)."""
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (width, height))
        f.write(struct.pack("<%df" % len(values), *values))


def read_pfms(directory, *names):
    """(width, height, [values per name]): DIRECTORY/NAME.pfm for each name, as read_pfm reads
    them; the width and height are the first file's."""
    images = [read_pfm("%s/%s.pfm" % (directory, name)) for name in names]
    return images[0][0], images[0][1], [values for _, _, _, values in images]
