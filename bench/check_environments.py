"""check_environments.py - environments that are not in the repository, and the shipped scenes under them.

    python3 bench/check_environments.py DIR

Writes into DIR three 1024x512 PFM environments, each with a bright source small enough to stress
the specular estimators (bench/mis-front.sh's front, bench/adaptive-samples.sh):
  sun.pfm      a sun of 5e4, 0.25 degrees in radius, in a dark blue sky
  night.pfm    four lamps of 0.18 degrees in radius (2e3 .. 1e4) in a faint sky
  horizon.pfm  a sun of 1e5 two degrees above the horizon in a warm sky
and, for each, ggx-NAME.json, default-NAME.json and grazing-NAME.json: those shipped scenes with
the environment replaced (intensity 1, no rotation; each scene names its environment by its file
name, so DIR can move).
"""
import json, math, os, struct, sys
W, H = 1024, 512
if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
    print("usage: check_environments.py DIR", file=sys.stderr)
    sys.exit(2)
out = sys.argv[1]
scenes = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes")
os.makedirs(out, exist_ok=True)
def direction(i, j):
    phi, th = 2 * math.pi * (0.5 - (i + 0.5) / W), math.pi * (j + 0.5) / H
    return (math.cos(phi) * math.sin(th), math.sin(phi) * math.sin(th), math.cos(th))
def unit(a):
    n = math.sqrt(sum(x * x for x in a))
    return tuple(x / n for x in a)
def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
def write(name, f):  # PFM, bottom row first
    with open(os.path.join(out, name + ".pfm"), "wb") as fh:
        fh.write(b"PF\n%d %d\n-1.0\n" % (W, H))
        for j in range(H - 1, -1, -1):
            row = []
            for i in range(W):
                row.extend(f(direction(i, j)))
            fh.write(struct.pack("<%df" % (3 * W), *row))
sun = unit((0.4, -0.3, 0.8))
def sunny(d):  # a sun of 5e4, 0.25 degrees in radius, in a dark blue sky
    if dot(d, sun) > math.cos(math.radians(0.25)):
        return (5e4, 4.7e4, 4.2e4)
    return (0.02 + 0.05 * d[2], 0.04 + 0.08 * d[2], 0.12 + 0.2 * d[2]) if d[2] > 0 else (0.03, 0.025, 0.02)
lamps = [(unit((1, 0.2, 0.15)), 1e4), (unit((-0.5, 0.8, 0.3)), 5e3), (unit((-0.3, -0.9, 0.05)), 2e3),
         (unit((0.1, 0.1, 0.95)), 8e3)]
def night(d):  # four lamps of 0.18 degrees in radius, a faint sky
    for c, e in lamps:
        if dot(d, c) > math.cos(math.radians(0.18)):
            return (e, 0.8 * e, 0.5 * e)
    return (0.002, 0.003, 0.008) if d[2] > 0 else (0.004, 0.004, 0.004)
c2 = math.cos(math.radians(2))
low = unit((0.6 * c2, 0.8 * c2, math.sin(math.radians(2))))
def horizon(d):  # a sun of 1e5 two degrees above the horizon, a warm sky
    if dot(d, low) > math.cos(math.radians(0.3)):
        return (1e5, 8e4, 5e4)
    if d[2] > 0:
        g = math.exp(-6 * d[2])
        return (0.3 + 1.5 * g, 0.25 + 0.8 * g, 0.3 + 0.3 * g)
    return (0.08, 0.06, 0.05)
for name, f in (("sun", sunny), ("night", night), ("horizon", horizon)):
    write(name, f)
    for base in ("ggx", "default", "grazing"):
        s = json.load(open(os.path.join(scenes, base + ".json")))
        s["environment"] = {"hdr": name + ".pfm", "intensity": 1, "rotation": 0}
        json.dump(s, open(os.path.join(out, "%s-%s.json" % (base, name)), "w"))
