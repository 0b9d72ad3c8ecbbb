#!/usr/bin/env bash
# visibility-error.sh - the error that ignoring visibility adds to softlight's renders: each
# scene's render (the default estimator, the most accurate sampling mode, and that mode with the
# renderer's screen-space ambient occlusion, --ao-radius 1) compared with the
# blind ground truth (`softlight truth`, every surface sees the whole environment, as the
# renderer assumes) and with the visibility-aware one (`softlight truth --visibility`, occluders
# traced with Embree); for scenes with point lights also the render with its lights, without and
# with their shadow maps (--shadows), against `truth --lights` and `truth --lights --visibility`
# (shadow rays). Then the visibility
# quadrature's own error: the first scene's truth at --vis-level 3 (the default) and 2 against
# --vis-level 1; per scene the factor by which the occlusion cuts the visibility error; and that
# error alone, apart from the estimator's (bench/visibility_cut.py): the change visibility makes
# to the truth against the change the methods make to the render, with the share of what the
# methods leave that the 10 worst pixels carry. Then the same error alone at a second size, twice
# the first by default (--check-size, on --check-scenes; --no-check skips it), since a figure that
# a handful of pixels decide moves with the image size. Writes the section "Visibility" of docs/accuracy.md (its text and tables, also
# kept in docs/accuracy/visibility.md, which bench/speed-vs-error.sh appends to the report it
# rewrites) and prints the tables; --no-doc leaves docs/ alone (tables in out/visibility-error/SIZE/).
#
#   bash bench/visibility-error.sh [BUILD_DIR] [--size WxH] [--scenes bunny,pbr,...] [--threads N]
#                                  [--no-levels] [--no-doc] [--no-point-lights]
#                                  [--check-size WxH] [--check-scenes bunny,...] [--no-check]
#
# Truths are cached in out/visibility-error/SIZE/ (a rerun with unchanged inputs integrates nothing).
# Figures per comparison from `softlight truth --compare`: nRMSE (RMSE over the covered pixels
# divided by the truth's RMS, linear radiance) and the share of pixels more than 1/255 off after
# the scene's tone map. About an hour for the default set at 160x90 on 2 loaded cores, nearly all
# of it the truths (2-6 minutes each; a visibility truth costs about 1.1x a blind one in CPU time),
# and as long again for the check at 320x180 on its four scenes (4 times the pixels).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=build
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then BUILD=$1; shift; fi
SIZE=160x90
SCENES=bunny,pbr,model,textured,top-down,grazing,city-sun,lamp
THREADS=2
LEVELS=1
DOC=1
LIGHTS=1
CHECK_SIZE=
CHECK_SCENES=bunny,model,textured,grazing
CHECK=1
while [ $# -gt 0 ]; do
    case $1 in
    --size) SIZE=$2; shift 2 ;;
    --scenes) SCENES=$2; shift 2 ;;
    --threads) THREADS=$2; shift 2 ;;
    --no-levels) LEVELS=0; shift ;;
    --no-doc) DOC=0; shift ;;
    --no-point-lights) LIGHTS=0; shift ;;
    --check-size) CHECK_SIZE=$2; shift 2 ;;
    --check-scenes) CHECK_SCENES=$2; shift 2 ;;
    --no-check) CHECK=0; shift ;;
    *) echo "visibility-error.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
# the check's size: twice the first's, each side
[ -n "$CHECK_SIZE" ] || CHECK_SIZE=$(awk -F x -v s="$SIZE" 'BEGIN { split(s, d, "x"); printf "%dx%d", 2 * d[1], 2 * d[2] }')
SL=$BUILD/softlight
OUT=out/visibility-error/$SIZE
mkdir -p "$OUT"
source bench/visibility_set.bash # BEST, AO, SUN, SKY, REFL

# truth NAME SCENE OPTIONS...: the truth of SCENE at SIZE with OPTIONS, cached as NAME
truth() {
    local name=$1 scene=$2; shift 2
    "$SL" truth "$scene" --size "$SIZE" --threads "$THREADS" --cache "$OUT/$name.gt" --pfm "$OUT/$name.pfm" "$@" \
        >"$OUT/$name.txt" 2>/dev/null
}
# seconds NAME: how long the cached truth NAME took to integrate (its cache header's line)
seconds() { head -c 3000 "$OUT/$1.gt" | sed -n 's/^seconds //p' | head -1; }
# rays NAME: rays per covered pixel of the cached truth NAME (its header: rays and covered pixels)
rays() {
    head -c 3000 "$OUT/$1.gt" | awk '/^covered /{c=$2} /^visibility /{for(i=1;i<NF;i++) if($i=="rays") r=$(i+1)}
        END{if(c>0 && r>0) printf "%.0f", r/c}'
}
# ratio A B: A / B to one decimal ("-" when B is 0 or missing)
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b + 0 > 0) printf "%.1fx", a / b; else printf "-" }'; }
# figures SCENE RENDER.pfm TRUTH_NAME TRUTH_OPTIONS...: "nrmse|share over 1/255|share over 8/255" of
# RENDER against it
figures() {
    local scene=$1 render=$2 name=$3; shift 3
    "$SL" truth "$scene" --size "$SIZE" --threads "$THREADS" --cache "$OUT/$name.gt" --compare "$render" "$@" 2>/dev/null |
        sed -n 's/.*nrmse \([0-9.]*\),.*>1\/255 \([0-9.]*%\), >8\/255 \([0-9.]*%\).*/\1|\2|\3/p'
}

table=$OUT/table.md
{
    echo "| scene | render | nRMSE vs blind truth | >1/255 vs blind | nRMSE vs visibility truth | >1/255 vs visibility | nRMSE ratio | blind truth s | visibility truth s |"
    echo "|---|---|---:|---:|---:|---:|---:|---:|---:|"
} >"$table"
{
    echo "| scene | nRMSE vs visibility truth, mf pdf+dist N256 | with --ao-radius 1 | cut | with --ao-radius 1 $SUN | cut | with $SKY --ao-radius 1 $SUN | cut | with $REFL $SKY --ao-radius 1 $SUN | cut |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
} >"$OUT/cut.md"
{
    echo "| scene | visibility's change to the truth | left with --ao-radius 1 | cut | left with --ao-radius 1 $SUN | cut | left with $SKY --ao-radius 1 $SUN | cut | left with $REFL $SKY --ao-radius 1 $SUN | cut | the last's share in its 10 worst pixels | pixels >1/255 off, >8/255: ignoring visibility | left with the last |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
} >"$OUT/alone.md"
IFS=, read -r -a scenes <<<"$SCENES"
for s in "${scenes[@]}"; do
    scene=scenes/$s.json
    echo "visibility-error: $s" >&2
    truth "$s-blind" "$scene"
    truth "$s-vis" "$scene" --visibility
    tb=$(seconds "$s-blind"); tv=$(seconds "$s-vis")
    "$SL" render "$scene" --size "$SIZE" --threads "$THREADS" --no-lights --pfm "$OUT/$s-default.pfm" -q
    # shellcheck disable=SC2086
    "$SL" render "$scene" --size "$SIZE" --threads "$THREADS" --no-lights $BEST --pfm "$OUT/$s-best.pfm" -q
    # shellcheck disable=SC2086
    "$SL" render "$scene" --size "$SIZE" --threads "$THREADS" --no-lights $BEST $AO --pfm "$OUT/$s-best-ao.pfm" -q
    # shellcheck disable=SC2086
    "$SL" render "$scene" --size "$SIZE" --threads "$THREADS" --no-lights $BEST $AO $SUN --pfm "$OUT/$s-best-ao-sun.pfm" -q
    # shellcheck disable=SC2086
    "$SL" render "$scene" --size "$SIZE" --threads "$THREADS" --no-lights $BEST $SKY $AO $SUN --pfm "$OUT/$s-best-sky-ao-sun.pfm" -q
    # shellcheck disable=SC2086
    "$SL" render "$scene" --size "$SIZE" --threads "$THREADS" --no-lights $BEST $REFL $SKY $AO $SUN \
        --pfm "$OUT/$s-best-refl-sky-ao-sun.pfm" -q
    # the env lights without their maps: what the renders with $SUN change from (the table of the
    # error alone)
    # shellcheck disable=SC2086
    "$SL" render "$scene" --size "$SIZE" --threads "$THREADS" --no-lights $BEST --env-lights 32 --pfm "$OUT/$s-best-el.pfm" -q
    for variant in default best best-ao best-ao-sun best-sky-ao-sun best-refl-sky-ao-sun; do
        case $variant in
        default) label="default" ;;
        best) label="mf pdf+dist N256" ;;
        best-ao) label="mf pdf+dist N256, --ao-radius 1" ;;
        best-ao-sun) label="mf pdf+dist N256, --ao-radius 1 $SUN" ;;
        best-sky-ao-sun) label="mf pdf+dist N256, $SKY --ao-radius 1 $SUN" ;;
        *) label="mf pdf+dist N256, $REFL $SKY --ao-radius 1 $SUN" ;;
        esac
        IFS='|' read -r bn bs _ <<<"$(figures "$scene" "$OUT/$s-$variant.pfm" "$s-blind")"
        IFS='|' read -r vn vs _ <<<"$(figures "$scene" "$OUT/$s-$variant.pfm" "$s-vis" --visibility)"
        echo "| $s | $label | $bn | $bs | $vn | $vs | $(ratio "$vn" "$bn") | ${tb:--} | ${tv:--} |" >>"$table"
    done
    # the cut: the visibility error of the mf render without and with the occlusion
    best_vis=$(grep "^| $s | mf pdf+dist N256 |" "$table" | cut -d'|' -f6 | tr -d ' ')
    ao_vis=$(grep "^| $s | mf pdf+dist N256, --ao-radius 1 |" "$table" | cut -d'|' -f6 | tr -d ' ')
    sun_vis=$(grep "^| $s | mf pdf+dist N256, --ao-radius 1 $SUN |" "$table" | cut -d'|' -f6 | tr -d ' ')
    sky_vis=$(grep "^| $s | mf pdf+dist N256, $SKY --ao-radius 1 $SUN |" "$table" | cut -d'|' -f6 | tr -d ' ')
    refl_vis=$(grep "^| $s | mf pdf+dist N256, $REFL $SKY --ao-radius 1 $SUN |" "$table" | cut -d'|' -f6 | tr -d ' ')
    echo "| $s | $best_vis | $ao_vis | $(ratio "$best_vis" "$ao_vis") | $sun_vis | $(ratio "$best_vis" "$sun_vis") | $sky_vis | $(ratio "$best_vis" "$sky_vis") | $refl_vis | $(ratio "$best_vis" "$refl_vis") |" >>"$OUT/cut.md"
    # the error alone: each method set's change to the render (from the render without it, the
    # same estimator and env lights) against visibility's change to the truth
    "$SL" truth "$scene" --size "$SIZE" --threads "$THREADS" --cache "$OUT/$s-vis.gt" --visibility --parts "$OUT/$s-parts" \
        >/dev/null 2>&1
    cut_of() { python3 bench/visibility_cut.py "$OUT/$s-blind.pfm" "$OUT/$s-vis.pfm" "$OUT/$s-parts/mask.pfm" "$@"; }
    added=$(cut_of "$OUT/$s-best.pfm" "$OUT/$s-best.pfm" | cut -d' ' -f1)
    row="| $s | $added"
    for pair in "best best-ao" "best-el best-ao-sun" "best-el best-sky-ao-sun" "best-el best-refl-sky-ao-sun"; do
        read -r from to <<<"$pair"
        read -r _ left worst <<<"$(cut_of "$OUT/$s-$from.pfm" "$OUT/$s-$to.pfm" "$OUT/$s-corrected.pfm")"
        row="$row | $left | $(ratio "$added" "$left")"
    done
    # the pixels visibly off, after the tone map: the blind truth, and the blind truth with the
    # full set's change (the last pair's; visibility_cut.py), each against the visibility truth
    IFS='|' read -r _ i1 i8 <<<"$(figures "$scene" "$OUT/$s-blind.pfm" "$s-vis" --visibility)"
    IFS='|' read -r _ l1 l8 <<<"$(figures "$scene" "$OUT/$s-corrected.pfm" "$s-vis" --visibility)"
    echo "$row | $worst | $i1, $i8 | $l1, $l8 |" >>"$OUT/alone.md"
    if [ "$LIGHTS" = 1 ] && python3 -c 'import json, sys; sys.exit(not json.load(open(sys.argv[1])).get("lights"))' "$scene"; then
        # with the scene's point lights: shadow rays to them
        truth "$s-blind-lights" "$scene" --lights
        truth "$s-vis-lights" "$scene" --lights --visibility
        "$SL" render "$scene" --size "$SIZE" --threads "$THREADS" --pfm "$OUT/$s-lights.pfm" -q
        IFS='|' read -r bn bs _ <<<"$(figures "$scene" "$OUT/$s-lights.pfm" "$s-blind-lights" --lights)"
        IFS='|' read -r vn vs _ <<<"$(figures "$scene" "$OUT/$s-lights.pfm" "$s-vis-lights" --lights --visibility)"
        echo "| $s | default, point lights on | $bn | $bs | $vn | $vs | $(ratio "$vn" "$bn") | $(seconds "$s-blind-lights") | $(seconds "$s-vis-lights") |" >>"$table"
        # the same with the lights' shadow maps (--shadows, docs/lighting.md "Shadow maps")
        "$SL" render "$scene" --size "$SIZE" --threads "$THREADS" --shadows --pfm "$OUT/$s-shadows.pfm" -q
        IFS='|' read -r bn bs _ <<<"$(figures "$scene" "$OUT/$s-shadows.pfm" "$s-blind-lights" --lights)"
        IFS='|' read -r vn vs _ <<<"$(figures "$scene" "$OUT/$s-shadows.pfm" "$s-vis-lights" --lights --visibility)"
        echo "| $s | default, point lights on, --shadows | $bn | $bs | $vn | $vs | $(ratio "$vn" "$bn") | $(seconds "$s-blind-lights") | $(seconds "$s-vis-lights") |" >>"$table"
    fi
done

if [ "$LEVELS" = 1 ]; then # the quadrature's own error, on the first scene
    s=${scenes[0]}
    scene=scenes/$s.json
    {
        echo
        echo "| scene | --vis-level | rays per covered pixel | seconds | nRMSE vs --vis-level 1 | >1/255 vs --vis-level 1 |"
        echo "|---|---:|---:|---:|---:|---:|"
    } >>"$table"
    for level in 1 2; do truth "$s-vis-L$level" "$scene" --visibility --vis-level $level; done
    for level in 3 2; do
        name=$s-vis-L$level
        [ $level = 3 ] && name=$s-vis
        rays=$(rays "$name")
        secs=$(seconds "$name")
        IFS='|' read -r n o _ <<<"$(figures "$scene" "$OUT/$name.pfm" "$s-vis-L1" --visibility --vis-level 1)"
        echo "| $s | $level | ${rays:--} | ${secs:--} | $n | $o |" >>"$table"
    done
    rays=$(rays "$s-vis-L1")
    secs=$(seconds "$s-vis-L1")
    echo "| $s | 1 | ${rays:--} | ${secs:--} | 0 | 0% |" >>"$table"
fi
cat "$table"
echo
cat "$OUT/cut.md"
echo
cat "$OUT/alone.md"

# the check: the error alone at the second size, and the full set's cut at both
check=$OUT/check.md
if [ "$CHECK" = 1 ]; then
    bash "$0" "$BUILD" --size "$CHECK_SIZE" --scenes "$CHECK_SCENES" --threads "$THREADS" --no-levels --no-doc \
        --no-point-lights --no-check >/dev/null
    {
        echo "| scene | cut at $SIZE | its 10 worst pixels' share | pixels >1/255 off, >8/255: ignoring, left | cut at $CHECK_SIZE | its 10 worst pixels' share | pixels >1/255 off, >8/255: ignoring, left |"
        echo "|---|---:|---:|---:|---:|---:|---:|"
        IFS=, read -r -a checked <<<"$CHECK_SCENES"
        for s in "${checked[@]}"; do
            # the last four columns of a scene's row: the full set's cut, its worst pixels' share
            # and the pixels off without and with it
            # shellcheck disable=SC2016 # an awk program: its $ are awk's
            pick='$2 == s { print $(NF - 4) "|" $(NF - 3) "| " $(NF - 2) "->" $(NF - 1) }'
            a=$(awk -F'|' -v s=" $s " "$pick" "$OUT/alone.md")
            b=$(awk -F'|' -v s=" $s " "$pick" "out/visibility-error/$CHECK_SIZE/alone.md")
            echo "| $s |${a:- - | - | - }|${b:- - | - | - }|"
        done
    } >"$check"
    echo
    cat "$check"
fi
[ "$DOC" = 1 ] || exit 0

# the section of docs/accuracy.md: text, the command, the tables
section=docs/accuracy/visibility.md
mkdir -p docs/accuracy
{
    echo "<!-- visibility:begin (bench/visibility-error.sh writes this section; do not edit by hand) -->"
    echo "## Visibility: the error of ignoring it"
    echo
    echo "Generated by \`bash bench/visibility-error.sh $BUILD --size $SIZE --scenes $SCENES\` on $(date -u +%Y-%m-%d)"
    echo "($(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end)."
    echo
    cat <<'TEXT'
The renderer lets every surface see the whole environment; the blind truth (every figure above)
does the same, so the sweep measures the estimator alone. `softlight truth --visibility` traces the
scene's triangles (docs/ibl.md "Visibility"): each render below is compared with both, over the
covered pixels at the size above, image-based light only (`render --no-lights`) except the
"point lights on" rows (`render` with the scene's lights against `truth --lights`, shadow rays to
the lights with `--visibility`; `--shadows`: the render with the lights' cube shadow maps,
docs/lighting.md "Shadow maps"). `default` is `softlight render` with the scene's settings (the
specification's estimator, N = 40 in these scenes); `mf pdf+dist N256` is `--estimator mf --lod pdf --distortion
-n 256`, whose error against the blind truth is nearly all bias-free noise; `--ao-radius 1` adds
the renderer's screen-space ambient occlusion within 1 world unit (docs/lighting.md "Ambient
occlusion"), the estimate of visibility it has; `--sky-maps 32` adds the sky visibility maps
(docs/lighting.md "Sky visibility maps"), which replace the ambient occlusion on the diffuse and
occlude the specular's part across the horizon; `--reflection-occlusion 7` traces the specular
lobe's rays 7 units against the G-buffer (docs/lighting.md "Reflection occlusion").
nRMSE: RMSE over the
covered pixels in linear radiance divided by the truth's RMS; `>1/255`: the share of covered
pixels more than 1/255 off after the scene's tone map (`softlight truth --compare`). The
difference between the two columns of one row is the error that ignoring visibility adds (the
ratio: nRMSE against the visibility truth over nRMSE against the blind one); the plain `mf` rows show
it nearly alone, since their error against the blind truth is small. Truth seconds: wall time
of the integration on the loaded machine (cache header), not CPU time. In `textured` the
alpha-masked leaf casts where its mask keeps it, in the truth and in the maps alike (docs/ibl.md
"Visibility", docs/lighting.md "Shadow maps").

TEXT
    sed -n '1,/^$/p' "$table" | sed '/^$/d'
    echo
    echo "What the occlusion (GTAO on the diffuse, read along the bent normal, its visibility cone's"
    echo "specular occlusion on the specular: docs/lighting.md \"Ambient occlusion\", \"Specular"
    echo "occlusion\"), the env lights' shadow maps (docs/lighting.md \"Shadow maps\") and the sky"
    echo "visibility maps (docs/lighting.md \"Sky visibility maps\") remove of the"
    echo "error of ignoring visibility: nRMSE against the visibility truth of the \`mf pdf+dist N256\`"
    echo "render without them, with \`--ao-radius 1\`, with \`--ao-radius 1 $SUN\` and with"
    echo "\`$SKY --ao-radius 1 $SUN\` (and \`$REFL\`, docs/lighting.md \"Reflection occlusion\"), and the"
    echo "factor by which each cuts the first:"
    echo
    cat "$OUT/cut.md"
    echo
    echo "Each figure above holds the estimator's own error too (the plain \`mf\` row against the blind"
    echo "truth), and \`$SUN\` changes the estimator (the env lights are summed exactly, with less"
    echo "noise): a cut there can come from less noise rather than from seeing occluders. The"
    echo "visibility error alone (bench/visibility_cut.py): what visibility changes in the truth, the"
    echo "visibility truth less the blind one, as an nRMSE of the visibility truth (the error of a"
    echo "renderer that ignores visibility and has no error of its own), against what each method set"
    echo "changes in the render, the render with it less the render without it with the same estimator"
    echo "(\`mf pdf+dist N256\`, with \`--env-lights 32\` for the sets with \`$SUN\`), whose noise"
    echo "cancels in the difference; \"left\": the nRMSE of that difference of differences, the"
    echo "visibility error the methods leave; \"cut\": the first column over it. The last columns count"
    echo "pixels instead, after the scene's tone map: the blind truth against the visibility truth"
    echo "(ignoring visibility), and the blind truth plus the full set's change (the last pair's) against"
    echo "it (what the set leaves), more than 1/255 and more than 8/255 off:"
    echo
    cat "$OUT/alone.md"
    if [ "$CHECK" = 1 ]; then
        echo
        echo "The same at $CHECK_SIZE (\`--size $CHECK_SIZE\`, image-based light only), against the first size:"
        echo "the full set's cut, the share of what it leaves in the 10 worst pixels, and the pixels visibly"
        echo "off before and after it. Where the worst pixels' share is large, a handful of pixels decide the"
        echo "nRMSE (the glint of a sharp lobe at a silhouette or an edge, whose factor the methods take to 0"
        echo "or leave at 1), and the cut moves with the image size; the pixels off do not depend on a few:"
        echo
        cat "$check"
    fi
    if [ "$LEVELS" = 1 ]; then
        echo
        echo "The visibility quadrature's own error: the visibility truth of ${scenes[0]} at the default"
        echo "\`--vis-level 3\` (8x8 texels per ray) and at 2 against \`--vis-level 1\` (2x2 texels per ray),"
        echo "the same figures (the renders' error against the truth is far above it):"
        echo
        sed -n '/--vis-level/,$p' "$table"
    fi
    echo "<!-- visibility:end -->"
} >"$section"
# replace the section in docs/accuracy.md (or append it)
python3 - docs/accuracy.md "$section" <<'PY'
import re, sys
doc, sec = sys.argv[1], open(sys.argv[2]).read()
text = open(doc).read()
pat = re.compile(r'<!-- visibility:begin.*?<!-- visibility:end -->\n', re.S)
text = pat.sub(lambda m: sec, text) if pat.search(text) else text.rstrip('\n') + '\n\n' + sec
open(doc, 'w').write(text)
PY
echo "wrote $section and its section in docs/accuracy.md" >&2
