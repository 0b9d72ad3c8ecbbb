#!/usr/bin/env python3
"""mis_glance.py - the MIS section's table at a glance (docs/accuracy/mis.md), from bench/mis-front.sh's
table (docs/accuracy/mis-front.md): per scene the recipe's lighting CPU ms, nRMSE and share of pixels
more than 1/255 off, and for six variants their time as a multiple of the recipe's on the same
scene with their nRMSE and share. It rewrites the lines between the section's markers
<!-- mis-glance:begin --> and <!-- mis-glance:end -->; mis-front.sh runs it after its default run.

    python3 bench/mis_glance.py docs/accuracy/mis-front.md docs/accuracy/mis.md
"""
import sys

RECIPE = "spec-N40"
COLUMNS = [("mf-pdf+dist-N32", "mf pdf+dist N32"), ("mf-pdf+dist+envauto-N16", "GGX default at N16: mf pdf+dist + env lights worth their cost"),
           ("mis-N16", "mis N16"), ("mis+env32-N16", "mis N16 + 32 env lights"), ("mis-N40", "mis N40"),
           ("mis-N256", "mis N256")]
BEGIN, END = "<!-- mis-glance:begin -->", "<!-- mis-glance:end -->"


def read_front(path):
    """{scene: {variant: (ms, nrmse, share)}} and the scenes in the table's order"""
    rows, order = {}, []
    with open(path) as f:
        for line in f:
            if not line.startswith("| ") or line.startswith("| scene"):
                continue
            scene, _size, variant, ms, nrmse, over1, _over8 = [x.strip() for x in line.strip().strip("|").split("|")]
            if scene not in rows:
                rows[scene] = {}
                order.append(scene)
            rows[scene][variant] = (float(ms), nrmse, over1)
    return rows, order


def glance(rows, order):
    head = ["scene", "recipe N40: CPU ms, nRMSE, >1/255"] + [name for _, name in COLUMNS]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for scene in order:
        r = rows[scene]
        if RECIPE not in r or any(v not in r for v, _ in COLUMNS):
            continue  # a run with MIS_FRONT_ONLY: not every column
        base = r[RECIPE]
        cells = ["%.2f, %s, %s" % base]
        cells += ["%.2fx, %s, %s" % (r[v][0] / base[0], r[v][1], r[v][2]) for v, _ in COLUMNS]
        out.append("| %s | %s |" % (scene, " | ".join(cells)))
    return out


def main():
    front, doc = sys.argv[1], sys.argv[2]
    rows, order = read_front(front)
    with open(doc) as f:
        lines = f.read().split("\n")
    if BEGIN not in lines or END not in lines:
        sys.exit("mis_glance: %s has no %s ... %s block" % (doc, BEGIN, END))
    a, b = lines.index(BEGIN), lines.index(END)
    lines[a + 1:b] = glance(rows, order)
    with open(doc, "w") as f:
        f.write("\n".join(lines))


if __name__ == "__main__":
    main()
