"""visibility_cut.py - the visibility error alone, apart from the estimator's (bench/visibility-error.sh).

    python3 bench/visibility_cut.py BLIND.pfm VIS.pfm MASK.pfm FROM.pfm TO.pfm [CORRECTED.pfm]

BLIND and VIS: the blind truth and the visibility-aware truth of one scene (`softlight truth`,
`--visibility`), MASK its covered pixels (`truth --parts DIR`: DIR/mask.pfm); FROM and TO: two
renders of the scene, the same estimator, without and with the methods that estimate visibility.
Prints three numbers over the covered pixels, the first two each an RMS over the pixels and
channels divided by the visibility truth's RMS (as `truth --compare`'s nRMSE):
  added  what visibility changes in the truth, VIS - BLIND: the error a renderer that ignores
         visibility makes, with no error of its own;
  left   how far the methods' change, TO - FROM, is from it: the visibility error they leave;
  worst  the share of left's square that its WORST pixels carry (10): near 1 when a handful of
         pixels (a glint at a silhouette) decide the figure, so that it moves with the image size.
The estimator's own error (noise, bias) is in FROM and TO alike, so it cancels in TO - FROM,
which it does not in TO against VIS: this is the figure that shows what the methods do.
CORRECTED, when given, receives BLIND + (TO - FROM), clamped at 0: the blind truth with the
methods' change, which `softlight truth --visibility --compare` scores like a render (its nRMSE is
`left` but where the clamp bites; its share of pixels more than 1/255 off is the figure that a
handful of pixels cannot carry).
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "cli"))
from pfm import read_pfm, write_pfm  # noqa: E402


WORST = 10  # the pixels whose share of what is left is reported


def rgb(path):
    w, h, channels, v = read_pfm(path)
    return w, h, (v if channels == 3 else [x for x in v for _ in range(3)])


def main():
    if len(sys.argv) not in (6, 7):
        sys.exit("usage: visibility_cut.py BLIND.pfm VIS.pfm MASK.pfm FROM.pfm TO.pfm [CORRECTED.pfm]")
    images = [rgb(p) for p in sys.argv[1:6]]
    if len({(w, h) for w, h, _ in images}) != 1:
        sys.exit("visibility_cut.py: the images differ in size")
    blind, vis, mask, before, after = (v for _, _, v in images)
    added = left = norm = 0.0
    per_pixel = []
    for i in range(0, len(vis), 3):
        if mask[i] <= 0.0:
            continue
        pixel = 0.0
        for j in range(i, i + 3):
            change = vis[j] - blind[j]
            added += change * change
            pixel += (after[j] - before[j] - change) ** 2
            norm += vis[j] * vis[j]
        left += pixel
        per_pixel.append(pixel)
    if norm <= 0.0:
        sys.exit("visibility_cut.py: the visibility truth is black over the mask")
    worst = sum(sorted(per_pixel, reverse=True)[:WORST]) / left if left > 0.0 else 0.0
    if len(sys.argv) == 7:
        corrected = [max(b + a - f, 0.0) for b, a, f in zip(blind, after, before)]
        write_pfm(sys.argv[6], images[0][0], images[0][1], corrected)
    print("%.4f %.4f %.2f" % (math.sqrt(added / norm), math.sqrt(left / norm), worst))


main()
