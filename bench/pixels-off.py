#!/usr/bin/env python3
"""pixels-off.py - where a render's pixels more than a display step off the ground truth lie: by
material (the lobe set and its parameter, metal-like where Ks > 0.5) and by how the surface faces
the eye (N.V under 0.4: the rim; 0.4 to 0.8; 0.8 and over: the face), so that an estimator's
error can be traced to the lobes and views that carry it (docs/accuracy.md quotes it).

    python3 bench/pixels-off.py BUILD_DIR SCENE.json WxH [RENDER OPTION ...]

Renders SCENE at WxH with --no-lights and the options given (PNG and the G-buffer's AOVs),
tone maps the ground truth (`softlight truth`, cached in out/ground-truth/pixels-off/) and counts,
per bin, the covered pixels and those with a channel more than one code of 255 apart (the
truth's --compare ">1/255" counts in float; the two agree to a pixel or two). Prints a markdown
table, the bins in order of the pixels off. Standard library only."""
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "cli"))
from pfm import read_pfm  # noqa: E402
from png_compare import read_png  # noqa: E402


def band(n_dot_v):
    if n_dot_v < 0.4:
        return "rim (N.V < 0.4)"
    return "N.V 0.4 to 0.8" if n_dot_v < 0.8 else "face (N.V >= 0.8)"


def material(alpha, ks):
    kind = "metal-like" if ks > 0.5 else "dielectric"
    lobe = "GGX r %.2f" % (-1.0 - alpha) if alpha <= -1.0 else "Phong %g" % alpha
    return "%s, %s" % (lobe, kind)


def main():
    if len(sys.argv) < 4:
        sys.stderr.write(__doc__)
        return 2
    build, scene, size, options = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    sl = os.path.join(build, "softlight")
    name = os.path.splitext(os.path.basename(scene))[0]
    cache = os.path.join("out", "ground-truth", "pixels-off")
    os.makedirs(cache, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        render, truth, aov = os.path.join(tmp, "render.png"), os.path.join(tmp, "truth.png"), os.path.join(tmp, "aov")
        subprocess.run([sl, "render", scene, "--size", size, "--no-lights", *options, "-o", render, "--aov", aov, "-q"],
                       check=True)
        subprocess.run([sl, "truth", scene, "--size", size, "--cache", os.path.join(cache, "%s-%s.gt" % (name, size)),
                        "-o", truth], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        w, h, ch, got = read_png(render)
        tw, th, tch, want = read_png(truth)
        if (w, h, ch) != (tw, th, tch):
            sys.stderr.write("pixels-off: the render and the truth differ in size\n")
            return 1
        planes = {k: read_pfm(os.path.join(aov, k + ".pfm")) for k in ("mask", "alpha", "ks", "normal", "view")}
    bins = {}
    for y in range(h):
        for x in range(w):
            i = (h - 1 - y) * w + x  # the AOVs are stored bottom row first
            if planes["mask"][3][i * planes["mask"][2]] <= 0.0:
                continue
            n = planes["normal"][3][3 * i:3 * i + 3]
            v = planes["view"][3][3 * i:3 * i + 3]
            key = (material(planes["alpha"][3][i * planes["alpha"][2]], planes["ks"][3][3 * i]),
                   band(sum(a * b for a, b in zip(n, v))))
            p = x * ch  # read_png's rows, top row first
            off = max(abs(got[y][p + c] - want[y][p + c]) for c in range(min(ch, 3))) > 1
            counts = bins.setdefault(key, [0, 0])
            counts[0] += 1
            counts[1] += off
    total = sum(c[0] for c in bins.values())
    total_off = sum(c[1] for c in bins.values())
    print("| material | where | covered pixels | more than 1/255 off | share of the bin | share of all off |")
    print("|---|---|---:|---:|---:|---:|")
    for (mat, where), (n, off) in sorted(bins.items(), key=lambda kv: (-kv[1][1], kv[0])):
        print("| %s | %s | %d | %d | %.0f%% | %.0f%% |" % (mat, where, n, off, 100.0 * off / n,
                                                          100.0 * off / max(total_off, 1)))
    print("| all | | %d | %d | %.1f%% | |" % (total, total_off, 100.0 * total_off / max(total, 1)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
