"""adaptive_samples.py - what spending a frame's samples per pixel could buy (bench/adaptive-samples.sh).

    python3 bench/adaptive_samples.py EXPOSURE CONTRAST TRUTH.pfm MASK.pfm PILOT.pfm N1=R1.pfm N2=R2.pfm ... \
        rot=F1.pfm rot=F2.pfm ...

TRUTH and MASK: a scene's ground truth and its covered pixels (`softlight truth --parts`); Rk: the
scene rendered with one estimator at Nk samples a pixel, for a ladder of N (one of them 16: the
budget); PILOT: a cheap first look at the image (the split sum); Fj: the same estimator at a few
samples with its sample set rotated per pixel, one frame each (`--rotate --frame j`), whose spread
is each pixel's estimator's own noise. A pixel is "off" when a channel's 8-bit code after the
scene's tone map differs from the truth's by more than 1, as `softlight truth --compare` counts
it. Prints one markdown row: the share off at each N of the ladder, then at a mean of 16 samples a
pixel
  oracle  each pixel given the fewest samples of the ladder that bring it within a step, cheapest
          first until the budget is spent: a bound no rule that must guess can pass;
  steady  the same, each pixel given the fewest samples from which it stays within a step at
          every larger N of the ladder: a pixel that lands within a step at one N by chance
          (its error's sign turns between two N) is not counted there;
  pilot   the pixels ranked by how far the pilot's display code is from the 4-sample render's,
          the top quarter given 32 samples, the next quarter 8, the rest 4: mean 12, plus the 4
          of the look at them (the pilot's own cost left out, in the rule's favour); the best of
          the splits tried is printed;
  spread  each pixel given N in proportion to the spread s (the largest channel's standard
          deviation of the display code over the rotated frames) or to s^2 (the N that would
          bring a noise of spread s within a step), scaled until the ladder's N (rounded up)
          average 16; the frames' own cost left out; the better of the two is printed.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "cli"))
from pfm import read_pfm  # noqa: E402

BUDGET = 16
# (share of the pixels, samples) from the most needy down; each split's mean is 12 (4 go to the look)
SPLITS = ([(0.25, 32), (0.25, 8), (0.5, 4)], [(0.5, 16), (0.5, 8)], [(0.1, 64), (0.2, 16), (0.7, 4)])


def rgb(path):
    w, h, channels, v = read_pfm(path)
    return (v if channels == 3 else [x for x in v for _ in range(3)]), w * h


def main():
    if len(sys.argv) < 8:
        sys.exit("usage: adaptive_samples.py EXPOSURE CONTRAST TRUTH.pfm MASK.pfm PILOT.pfm N1=R1.pfm ...")
    exposure, contrast = float(sys.argv[1]), float(sys.argv[2])

    def code(c):  # src/post/tonemap.c's curve without exact sRGB, then compare.c's rounding
        ec = exposure * c if c > 0 else 0.0
        return round(255.0 * (ec / (ec + 1.0)) ** (contrast / 2.2))

    truth, n = rgb(sys.argv[3])
    mask, _ = rgb(sys.argv[4])
    pilot, _ = rgb(sys.argv[5])
    renders, frames = {}, []
    for arg in sys.argv[6:]:
        k, path = arg.split("=", 1)
        if k == "rot":
            frames.append(rgb(path)[0])
        else:
            renders[int(k)] = rgb(path)[0]
    if len(frames) < 2:
        sys.exit("adaptive_samples.py: the spread needs two rotated frames or more (rot=F.pfm)")
    ladder = sorted(renders)
    needed = sorted({4, BUDGET} | {k for split in SPLITS for _, k in split})  # the look's, the budget's, the splits'
    if any(k not in renders for k in needed):
        sys.exit("adaptive_samples.py: the ladder needs N = " + ", ".join(str(k) for k in needed))
    pixels = [i for i in range(n) if mask[3 * i] > 0]
    codes = {k: [[code(v[3 * i + c]) for c in range(3)] for i in pixels] for k, v in renders.items()}
    tcodes = [[code(truth[3 * i + c]) for c in range(3)] for i in pixels]

    def steps(a, j):
        return max(abs(a[j][c] - tcodes[j][c]) for c in range(3))

    off = {k: [steps(codes[k], j) > 1 for j in range(len(pixels))] for k in ladder}
    row = ["%.1f%%" % (100.0 * sum(off[k]) / len(pixels)) for k in ladder]

    def allocated(need):  # the share left off when the cheapest needs are met first
        spent, fine = ladder[0] * len(pixels), 0
        for k in sorted(need):
            if k < (1 << 30) and spent + k - ladder[0] <= BUDGET * len(pixels):
                spent += k - ladder[0]
                fine += 1
        return 100.0 * (1.0 - fine / len(pixels))

    oracle = allocated([next((k for k in ladder if not off[k][j]), 1 << 30) for j in range(len(pixels))])
    steady = allocated([next((k for a, k in enumerate(ladder) if not any(off[b][j] for b in ladder[a:])), 1 << 30)
                        for j in range(len(pixels))])

    pcodes = [[code(pilot[3 * i + c]) for c in range(3)] for i in pixels]
    look = [max(abs(pcodes[j][c] - codes[4][j][c]) for c in range(3)) for j in range(len(pixels))]
    order = sorted(range(len(pixels)), key=lambda j: -look[j])
    best = None
    for split in SPLITS:
        given, at = [0] * len(pixels), 0
        for share, k in split:
            for j in order[at:at + int(round(share * len(pixels)))]:
                given[j] = k
            at += int(round(share * len(pixels)))
        for j in order[at:]:
            given[j] = split[-1][1]
        share_off = 100.0 * sum(off[given[j]][j] for j in range(len(pixels))) / len(pixels)
        best = share_off if best is None else min(best, share_off)
    fcodes = [[[code(f[3 * i + c]) for c in range(3)] for i in pixels] for f in frames]

    def deviation(j, c):
        xs = [fc[j][c] for fc in fcodes]
        mean = sum(xs) / len(xs)
        return (sum((x - mean) ** 2 for x in xs) / len(xs)) ** 0.5

    spread = [max(deviation(j, c) for c in range(3)) for j in range(len(pixels))]

    def rung(n):  # the ladder's smallest N at least n (its largest past the end)
        return next((k for k in ladder if k >= n), ladder[-1])

    spread_best = None
    for power in (1, 2):
        weight = [s ** power for s in spread]
        lo, hi = 1e-9, 1e9
        for _ in range(200):  # the largest scale whose rounded-up N average at most the budget
            k = (lo * hi) ** 0.5
            if sum(rung(k * w) for w in weight) > BUDGET * len(pixels):
                hi = k
            else:
                lo = k
        given = [rung(lo * w) for w in weight]
        share_off = 100.0 * sum(off[given[j]][j] for j in range(len(pixels))) / len(pixels)
        spread_best = share_off if spread_best is None else min(spread_best, share_off)
    print("| " + " | ".join(row) + " | %.1f%% | %.1f%% | %.1f%% | %.1f%% |" % (oracle, steady, best, spread_best))


if __name__ == "__main__":
    main()
