#!/usr/bin/env python3
"""gbuffer_diff.py C_DIR GL_DIR - per-channel differences of two --aov G-buffers (helper of
gl_textured.sh; standard library only). For each channel: the largest absolute difference over
the pixels both cover, and the share of those more than 1/255 apart in any component. The floor
of scenes/textured.json (world z = 0) is reported apart from the other objects (see
gl_textured.sh for why). Prints one line per channel and group:
    CHANNEL GROUP PIXELS MAX SHARE_OVER_1_255"""
import os
import sys

from pfm import read_pfm


def main():
    c_dir, g_dir = sys.argv[1], sys.argv[2]
    mask_c = read_pfm(c_dir + "/mask.pfm")[3]
    mask_g = read_pfm(g_dir + "/mask.pfm")[3]
    pos = read_pfm(c_dir + "/position.pfm")[3]
    covered = [i for i in range(len(mask_c)) if mask_c[i] > 0.5 and mask_g[i] > 0.5]
    floor = {i for i in covered if abs(pos[3 * i + 2]) < 1e-6}
    # the extra plane's AOVs (occlusion, emission) when both G-buffers have them
    extra = tuple(n for n in ("occlusion", "emissive")
                  if os.path.exists(c_dir + "/" + n + ".pfm") and os.path.exists(g_dir + "/" + n + ".pfm"))
    for name in ("position", "normal", "kd", "ks", "alpha", "depth") + extra:
        _, _, ch, a = read_pfm(c_dir + "/" + name + ".pfm")
        b = read_pfm(g_dir + "/" + name + ".pfm")[3]
        for group in ("objects", "floor"):
            worst, over, count = 0.0, 0, 0
            for i in covered:
                if (i in floor) != (group == "floor"):
                    continue
                d = max(abs(a[ch * i + k] - b[ch * i + k]) for k in range(ch))
                worst = max(worst, d)
                over += d > 1.0 / 255.0
                count += 1
            print("%s %s %d %.6g %.6g" % (name, group, count, worst, over / count if count else 0.0))


main()
