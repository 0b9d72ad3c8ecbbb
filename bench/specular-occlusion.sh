#!/usr/bin/env bash
# specular-occlusion.sh - which specular occlusion to take from the ambient occlusion: the forms
# the literature offers, each measured against the visibility-aware ground truth
# (`softlight truth --visibility`) on the shipped scenes with something to occlude. Writes the
# table of docs/accuracy/specular-occlusion.md (--no-doc: prints it only).
#
#   bash bench/specular-occlusion.sh [BUILD_DIR] [--size 80x45] [--scenes bunny,pbr,...] [--radius 1]
#                                    [--no-doc]
#
# One render with --ao-radius (`--estimator mf --lod pdf --distortion -n 256 --no-lights`, as
# bench/visibility-error.sh) gives the G-buffer's files (normal, view, alpha, occlusion, and the
# cone: bent, ao) and its diffuse term (--diffuse-only); one without it gives the specular term
# with the material's occlusion alone (--specular-only). The image of each form is then the
# diffuse plus the specular times that form's factor, computed here per pixel from the files:
#   ao        the AO itself (the specular scaled as the diffuse is)
#   none      1 (no specular occlusion: the AO on the diffuse only)
#   lagarde   Lagarde and de Rousiers 2014: clamp((N.V + AO)^(2^(-16 a - 1)) - 1 + AO, 0, 1), a the
#             GGX width of the lobe (for Phong, sqrt(2 / (n + 2)))
#   cone-sharp  the visibility cone against the lobe's cone, without the fade to 1 near AO 1
#   cone      the same with the fade (src/occlusion/specular_occlusion.h, SL_SO_FADE), the
#             renderer's; its column is also the renderer's own image to within float rounding
# FADE=F in the environment moves the fade's start (default 0.8, SL_SO_FADE) for the cone column.
# and each is compared with the truth by `softlight truth --compare` (nRMSE over the covered
# pixels). Truths are cached in out/specular-occlusion/ (the visibility truths at 80x45: about a
# minute each on the loaded 2-core machine; a rerun takes seconds).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=build
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then BUILD=$1; shift; fi
SIZE=80x45
SCENES=bunny,pbr,model,city-sun,top-down
RADIUS=1
DOC=1
while [ $# -gt 0 ]; do
    case $1 in
    --size) SIZE=$2; shift 2 ;;
    --scenes) SCENES=$2; shift 2 ;;
    --radius) RADIUS=$2; shift 2 ;;
    --no-doc) DOC=0; shift ;;
    *) echo "specular-occlusion.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
SL=$BUILD/softlight
OUT=out/specular-occlusion
mkdir -p "$OUT"
BEST="--estimator mf --lod pdf --distortion -n 256 --no-lights"
FORMS="ao none lagarde cone-sharp cone"

table=$OUT/table.md
{
    echo "| scene | no occlusion | ao | none | lagarde | cone-sharp | cone |"
    echo "|---|---:|---:|---:|---:|---:|---:|"
} >"$table"
IFS=, read -r -a scenes <<<"$SCENES"
for s in "${scenes[@]}"; do
    scene=scenes/$s.json
    d=$OUT/$s
    mkdir -p "$d"
    echo "specular-occlusion: $s" >&2
    # shellcheck disable=SC2086
    "$SL" render "$scene" --size "$SIZE" $BEST --pfm "$d/plain.pfm" -q
    # shellcheck disable=SC2086
    "$SL" render "$scene" --size "$SIZE" $BEST --ao-radius "$RADIUS" --diffuse-only --aov "$d/aov" --pfm "$d/diffuse.pfm" -q
    # shellcheck disable=SC2086
    "$SL" render "$scene" --size "$SIZE" $BEST --specular-only --pfm "$d/specular.pfm" -q
    python3 - "$d" $FORMS <<'PY'
import math, os, struct, sys
def read(path):
    data = open(path, 'rb').read()
    parts = data.split(b'\n', 3)
    kind, (w, h), scale = parts[0], map(int, parts[1].split()), float(parts[2])
    ch = 3 if kind == b'PF' else 1
    return w, h, ch, list(struct.unpack(('<' if scale < 0 else '>') + 'f' * (w * h * ch), parts[3][:4 * w * h * ch]))
def write(path, w, h, px):
    with open(path, 'wb') as f:
        f.write(b'PF\n%d %d\n-1.0\n' % (w, h))
        f.write(struct.pack('<' + 'f' * len(px), *px))
def phong_exponent(alpha):
    if alpha >= 0:
        return alpha
    r = -1 - alpha
    a = max(r * r, 1e-4)
    return max(2 / (a * a) - 2, 0)
def cap_share(cos_v, cos_s, cos_d):
    cl = lambda x: min(max(x, -1.0), 1.0)
    tv, ts, dd = math.acos(cl(cos_v)), math.acos(cl(cos_s)), math.acos(cl(cos_d))
    lo, hi = abs(tv - ts), tv + ts
    t = min(max(1 - min(max((dd - lo) / max(hi - lo, 1e-6), 0), 1), 0), 1)
    return min(max((1 - math.cos(min(tv, ts))) * t * t * (3 - 2 * t) / max(1 - cos_s, 1e-12), 0), 1)
def cone(ao, bdr, nv, alpha):
    if not ao > 0:
        return 0.0
    cos_s = 0.244 ** (1 / (phong_exponent(alpha) + 1))
    open_ = cap_share(0, cos_s, nv)
    so = min(max(cap_share(math.sqrt(max(0, 1 - ao)), cos_s, bdr) / open_, 0), 1) if open_ > 0 else ao
    t = min(max((ao - FADE) / (1 - FADE), 0), 1)
    return so + (1 - so) * t * t * (3 - 2 * t)
def cone_sharp(ao, bdr, nv, alpha):
    global FADE
    keep, FADE = FADE, 1.0 - 1e-9
    try:
        return cone(ao, bdr, nv, alpha)
    finally:
        FADE = keep
FADE = float(os.environ.get('FADE', '0.8'))  # SL_SO_FADE
def lagarde(ao, nv, alpha):
    a = math.sqrt(2 / (phong_exponent(alpha) + 2))
    return min(max((nv + ao) ** (2 ** (-16 * a - 1)) - 1 + ao, 0), 1)
d, forms = sys.argv[1], sys.argv[2:]
w, h, _, diffuse = read(d + '/diffuse.pfm')
_, _, _, spec = read(d + '/specular.pfm')
_, _, _, normal = read(d + '/aov/normal.pfm')
_, _, _, view = read(d + '/aov/view.pfm')
_, _, _, alpha = read(d + '/aov/alpha.pfm')
_, _, _, bent = read(d + '/aov/bent.pfm')
_, _, _, ao = read(d + '/aov/ao.pfm')
_, _, _, mask = read(d + '/aov/mask.pfm')
for form in forms:
    out = list(diffuse)
    for i in range(w * h):
        if mask[i] < 0.5:
            continue
        N, V, B = normal[3 * i:3 * i + 3], view[3 * i:3 * i + 3], bent[3 * i:3 * i + 3]
        nv = sum(N[c] * V[c] for c in range(3))
        if nv < 0.01:  # lighting.frag's facing_normal
            N = [N[c] + (0.01 - nv) * V[c] for c in range(3)]
            l = math.sqrt(sum(x * x for x in N))
            N = [x / l for x in N]
            nv = sum(N[c] * V[c] for c in range(3))
        R = [2 * nv * N[c] - V[c] for c in range(3)]
        a = alpha[i] if alpha[i] <= -1 else min(max(alpha[i], 0), 1e7)
        a = max(a, -2.0)
        bdr = sum(B[c] * R[c] for c in range(3))
        f = {'ao': ao[i], 'none': 1.0, 'lagarde': lagarde(ao[i], nv, a),
             'cone-sharp': cone_sharp(ao[i], bdr, nv, a), 'cone': cone(ao[i], bdr, nv, a)}[form]
        for c in range(3):
            out[3 * i + c] += spec[3 * i + c] * f
    write(d + '/' + form + '.pfm', w, h, out)
PY
    row="| $s"
    for f in plain $FORMS; do
        n=$("$SL" truth "$scene" --size "$SIZE" --cache "$OUT/$s-vis.gt" --visibility --compare "$d/$f.pfm" 2>/dev/null |
            sed -n 's/.*nrmse \([0-9.]*\),.*/\1/p')
        row="$row | $n"
    done
    echo "$row |" >>"$table"
done
cat "$table"
[ "$DOC" = 1 ] || exit 0
doc=docs/accuracy/specular-occlusion.md
{
    echo "# Specular occlusion: which form"
    echo
    echo "Generated by \`bash bench/specular-occlusion.sh $BUILD --size $SIZE --scenes $SCENES --radius $RADIUS\` on $(date -u +%Y-%m-%d)"
    echo "($(nproc) cores). nRMSE against the visibility-aware truth (\`softlight truth --visibility\`),"
    echo "over the covered pixels, image-based light only, of \`--estimator mf --lod pdf --distortion -n 256\`"
    echo "renders: without occlusion, and with \`--ao-radius $RADIUS\` on the diffuse and each form of"
    echo "specular occlusion on the specular (the script's header defines them; docs/lighting.md"
    echo "\"Specular occlusion\" says which the renderer takes and why). Lower is better."
    echo
    cat "$table"
} >"$doc"
echo "wrote $doc" >&2
