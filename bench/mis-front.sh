#!/usr/bin/env bash
# mis-front.sh - the MIS estimator's speed against error front (docs/accuracy.md "MIS"): the
# recipe (spec N40), the best microfacet settings at its cost (mf pdf+dist N32, and N16 with 64
# env lights, which GGX scenes get by default, also at the scenes' own N 40) and --estimator mis over N, alone and with 32 env lights, on shipped scenes and on environments that are not in the repository, written here into
# a temporary directory: a sun of 5e4 on a few texels in a dark sky, four small lamps (2e3..1e4) at
# night, a sun of 1e5 two degrees above the horizon (1024x512 PFM each).
#
#   bench/mis-front.sh [BUILD_DIR] [SCENE:SIZE ...]
#   MIS_FRONT_ONLY='^(spec|mf|cv|splitsum)' MIS_FRONT_MD=docs/accuracy/cv-front.md bench/mis-front.sh build ...
#
# The split sum and --estimator cv (its control variate, docs/lighting.md "Control variate") are
# on the front too, cv at the microfacet settings above and with lod none (the samples unfiltered,
# beside mf with lod none).
#
# Per scene: the ground truth (`softlight truth`, cached by content in out/ground-truth/mis/),
# then bench_mis_front's lighting CPU time (1 thread, median of 7 interleaved frames) and
# `softlight truth --compare` of each variant: nRMSE and the shares of pixels more than 1/255
# and 8/255 off after the scene's tone map (total radiance, point lights off). Writes the table
# to docs/accuracy/mis-front.md (bench/speed-vs-error.sh appends docs/accuracy/mis.md, the section
# that reads it, and the table to docs/accuracy.md). The default list takes about an hour on the 2-core machine,
# most of it the ground truth; later runs reuse the cache.
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/cpu_frame.bash # vector_isa
build=${1:-build}
[ $# -gt 0 ] && shift
SL=$build/softlight
BENCH=$build/bench_mis_front
[ -x "$BENCH" ] || { echo "mis-front: $BENCH not found: build first" >&2; exit 2; }
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-mis-front.XXXXXX")
trap 'rm -rf "$T"' EXIT
cache=out/ground-truth/mis
mkdir -p "$cache" docs/accuracy

python3 - "$T" <<'PY'
import json, math, os, struct, sys
W, H = 1024, 512
out = sys.argv[1]
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
        s = json.load(open("scenes/%s.json" % base))
        s["environment"] = {"hdr": os.path.join(out, name + ".pfm"), "intensity": 1, "rotation": 0}
        json.dump(s, open(os.path.join(out, "%s-%s.json" % (base, name)), "w"))
PY

scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(ggx:320x180 default:320x180 ggx-sun:320x180 ggx-night:320x180 ggx-horizon:320x180
    default-sun:192x108 default-night:192x108 grazing-horizon:192x108 city-sun:192x108 default-horizon:192x108
    grazing:192x108)
V=("spec-N40|spec|spec-d4|0|40" "mf-pdf+dist-N32|mf|pdf|1|32" "mf-pdf+dist+env64-N16|mf|pdf|1|16|64"
   "mis-N8|mis|none|0|8" "mis-N16|mis|none|0|16" "mis+env32-N16|mis|none|0|16|32" "mis-N24|mis|none|0|24"
   "mis-N40|mis|none|0|40" "mis+env32-N40|mis|none|0|40|32" "mis-N64|mis|none|0|64" "mis-N256|mis|none|0|256"
   "mis-N1024|mis|none|0|1024" "splitsum|splitsum|none|0|1" "mf-pdf+dist-N16|mf|pdf|1|16" "cv-pdf+dist-N16|cv|pdf|1|16"
   "cv-pdf+dist-N32|cv|pdf|1|32" "cv-pdf+dist+env8-N8|cv|pdf|1|8|8" "cv-pdf+dist+env8-N16|cv|pdf|1|16|8" "mf-pdf+dist+env64-N32|mf|pdf|1|32|64" "mf-pdf+dist+env64-N40|mf|pdf|1|40|64" "cv-pdf+dist+env64-N16|cv|pdf|1|16|64"
   "cv-pdf+dist+env64-N32|cv|pdf|1|32|64" "cv-none-N64|cv|none|0|64" "mf-none-N64|mf|none|0|64"
   "cvmis-N12|cvmis|none|0|12" "cvmis-N16|cvmis|none|0|16" "cvmis-N24|cvmis|none|0|24" "cvmis-N32|cvmis|none|0|32"
   "cvmis+env64-N16|cvmis|none|0|16|64")
# MIS_FRONT_ONLY=REGEX: only the variants whose name matches (a partial run); MIS_FRONT_MD=FILE:
# the table's file (a partial run writes its own, not the whole front's)
if [ -n "${MIS_FRONT_ONLY:-}" ]; then
    keep=()
    for v in "${V[@]}"; do [[ ${v%%|*} =~ $MIS_FRONT_ONLY ]] && keep+=("$v"); done
    V=("${keep[@]}")
fi
md=${MIS_FRONT_MD:-docs/accuracy/mis-front.md}
{
    echo "Generated by \`bench/mis-front.sh\` on $(date -u +%F) ($(nproc) cores, $(vector_isa), load average at the start: $(cut -d' ' -f1 /proc/loadavg))."
    echo
    echo "| scene | size | variant | lighting CPU ms | nRMSE | >1/255 | >8/255 |"
    echo "|---|---|---|---:|---:|---:|---:|"
} >"$md"
for entry in "${scenes[@]}"; do
    name=${entry%%:*} size=${entry#*:}
    scene=scenes/$name.json
    [ -f "$scene" ] || scene=$T/$name.json
    gt=$cache/$name-$size.gt
    echo "mis-front: $name at $size: ground truth" >&2
    "$SL" truth "$scene" --size "$size" --cache "$gt" >/dev/null 2>&1
    mkdir -p "$T/$name"
    OMP_WAIT_POLICY=passive "$BENCH" "$scene" "$size" "$T/$name" 1 "${V[@]}" >"$T/$name/times"
    while read -r variant ms; do
        line=$("$SL" truth "$scene" --size "$size" --cache "$gt" --compare "$T/$name/$variant.pfm" 2>&1 |
            grep "against the truth")
        nr=$(sed -n 's/.*nrmse \([0-9.e-]*\).*/\1/p' <<<"$line")
        o1=$(sed -n 's/.*>1\/255 \([0-9.]*%\).*/\1/p' <<<"$line")
        o8=$(sed -n 's/.*>8\/255 \([0-9.]*%\).*/\1/p' <<<"$line")
        echo "| $name | $size | $variant | $ms | $nr | $o1 | $o8 |" | tee -a "$md"
    done <"$T/$name/times"
done
echo "mis-front: table in $md" >&2
