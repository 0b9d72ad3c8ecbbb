"""sun_sky.py PATH ELEVATION AZIMUTH [SKY] - a made environment for the env lights' shadow tests
(sun_shadows.sh, gl_sun_shadows.sh): a 64x32 lat-long PFM, black (or of radiance SKY) but for a
sun of two adjacent texels at that direction (degrees), radiance 3000, so that on a black sky
the env lights hold all of its light."""
import math
import struct
import sys

path, el, az = sys.argv[1], math.radians(float(sys.argv[2])), math.radians(float(sys.argv[3]))
W, H = 64, 32
d = (math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el))
u = (0.5 - math.atan2(d[1], d[0]) / (2 * math.pi)) % 1.0   # docs/conventions.md
v = math.acos(d[2]) / math.pi
i, j = int(u * W), int(v * H)                               # row j from the top
sky = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
img = [[(sky, sky, sky)] * W for _ in range(H)]
for di in (0, 1):
    img[j][(i + di) % W] = (3000.0, 3000.0, 3000.0)
with open(path, "wb") as f:
    f.write(b"PF\n%d %d\n-1.0\n" % (W, H))
    for row in reversed(img):                               # PFM: bottom row first
        for p in row:
            f.write(struct.pack("<3f", *p))
