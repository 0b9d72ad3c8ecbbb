"""sun_sky.py PATH ELEVATION AZIMUTH [SKY [GLOW]] - a made environment for the env lights' shadow
tests (sun_shadows.sh, gl_sun_shadows.sh, masked_casters.bash): a 64x32 lat-long PFM, black (or of
radiance SKY) but for a sun of two adjacent texels at that direction (degrees), radiance 3000, so
that on a black sky the env lights hold all of its light; with GLOW, the ten texels about the
sun's two (a block of 4x3 texels, the sun in its middle row) are of radiance GLOW: a glare that
two env lights leave to the samples. Imported, sun_directions gives the two texels' centres'
directions, which the light comes from."""
import math
import sys

from pfm import write_pfm

W, H = 64, 32


def sun_texels(el_deg, az_deg):
    """The texels (column, row from the top) of the sun at that direction: (i, j) and (i + 1, j)."""
    el, az = math.radians(el_deg), math.radians(az_deg)
    d = (math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el))
    u = (0.5 - math.atan2(d[1], d[0]) / (2 * math.pi)) % 1.0   # docs/conventions.md
    v = math.acos(d[2]) / math.pi
    i, j = int(u * W), int(v * H)
    return [((i + di) % W, j) for di in (0, 1)]


def sun_directions(el_deg, az_deg):
    """The unit directions of the sun's two texels' centres (the lat-long map's inverse)."""
    out = []
    for i, j in sun_texels(el_deg, az_deg):
        phi, th = (0.5 - (i + 0.5) / W) * 2 * math.pi, (j + 0.5) / H * math.pi
        out.append((math.sin(th) * math.cos(phi), math.sin(th) * math.sin(phi), math.cos(th)))
    return out


if __name__ == "__main__":
    path = sys.argv[1]
    sky = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
    glow = float(sys.argv[5]) if len(sys.argv) > 5 else 0.0
    img = [[(sky, sky, sky)] * W for _ in range(H)]
    if glow > 0.0:
        (i0, j0), _ = sun_texels(float(sys.argv[2]), float(sys.argv[3]))
        for dj in (-1, 0, 1):
            for di in (-1, 0, 1, 2):
                img[j0 + dj][(i0 + di) % W] = (glow, glow, glow)
    for i, j in sun_texels(float(sys.argv[2]), float(sys.argv[3])):
        img[j][i] = (3000.0, 3000.0, 3000.0)
    write_pfm(path, W, H, [c for row in reversed(img) for p in row for c in p])  # bottom row first
