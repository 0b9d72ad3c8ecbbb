"""pfm.py - the PFM reader the CLI tests' Python checks share (standard library only): they run
with PYTHONPATH set to tests/cli and `from pfm import read_pfm`."""
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
