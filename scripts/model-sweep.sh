#!/usr/bin/env bash
# model-sweep.sh BUILD_DIR [MODELS_DIR] [OUT_DIR] - every model file of a collection through
# `softlight render`, to hold the promise about bad input to account: one error line and status 2,
# never a crash, a hang, a half-written output, a sanitizer report or an unannounced empty
# picture; no file under 10 MB over 10 s or 1 GiB.
#
# MODELS_DIR defaults to assimp's test models (Debian's assimp-testmodels,
# /usr/share/assimp/models: valid and deliberately broken files in some 45 formats). Each model
# file (images, text, shaders and glTF buffers are skipped) is rendered at 160x90 under `timeout`
# and /usr/bin/time -v, two at a time (SWEEP_JOBS), with its G-buffer mask written to count the
# pixels a surface covers; SWEEP_ARGS adds options to every render (SWEEP_ARGS="--missing-textures
# skip"). OUT_DIR (default: a new temporary directory) receives N.png, N.err and
# sweep.tsv, one row per file:
#   n file status err_lines wall_s rss_mib covered png_left warned sanitizer first_err_line
# status: the exit status, 124/137 for a timeout; covered: pixels of the mask a surface covers
# (-1: no mask); png_left: an image (or the AOV folder) was left by a run that failed; warned: the run said
# "no surface is in view"; sanitizer: an AddressSanitizer or UBSan report in stderr.
# The summary follows on stdout; the exit status is 1 when any class but "rendered" and
# "refused in one line" is not empty.
set -uo pipefail
build=${1:?usage: model-sweep.sh BUILD_DIR [MODELS_DIR] [OUT_DIR]}
models=${2:-/usr/share/assimp/models}
out=${3:-$(mktemp -d "${TMPDIR:-/tmp}/model-sweep.XXXXXX")}
jobs=${SWEEP_JOBS:-2}
kill_after=${SWEEP_TIMEOUT:-60} # seconds before a run is killed (a run over 10 s is reported anyway)
extra=${SWEEP_ARGS:-}
sl=$(cd "$build" && pwd)/softlight
[ -x "$sl" ] || { echo "model-sweep.sh: $sl: not built" >&2; exit 2; }
[ -d "$models" ] || { echo "model-sweep.sh: $models: no such directory" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "model-sweep.sh: /usr/bin/time is missing (Debian package time)" >&2; exit 2; }
mkdir -p "$out"
out=$(cd "$out" && pwd)

# The list: every file whose name does not say image, text, shader, buffer or archive.
skip='\.(png|jpe?g|bmp|tga|dds|gif|tiff?|hdr|exr|txt|md|mtl|material|glsl|vert|frag|bin|uc|zip|py|sh|json)$|/(LICENSE|README|readme)[^/]*$|/ReferenceImages/|/ParsingFiles/'
find "$models" -type f | LC_ALL=C sort | grep -viE "$skip" | awk '{ print NR "\t" $0 }' >"$out/files.tsv"

# one N FILE: renders FILE into $out/N.*, then prints its row.
one() {
    local n=$1 file=$2 d=$out
    rm -f "$d/$n.png"
    rm -rf "$d/$n.aov"
    local start end
    start=$(date +%s.%N)
    timeout -k 5 "$kill_after" /usr/bin/time -v -o "$d/$n.time" \
        "$sl" render "$file" --size 160x90 -j 1 -o "$d/$n.png" --aov "$d/$n.aov" $extra >"$d/$n.out" 2>"$d/$n.err"
    local status=$?
    end=$(date +%s.%N)
    local wall rss lines covered=-1 png_left=0 warned=0 sanitizer=0 first
    wall=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }')
    rss=$(awk -F': ' '/Maximum resident set size/ { printf "%.0f", $2 / 1024 }' "$d/$n.time" 2>/dev/null)
    lines=$(wc -l <"$d/$n.err")
    first=$(head -n 1 "$d/$n.err" | tr '\t' ' ' | cut -c1-300)
    if [ -f "$d/$n.aov/mask.pfm" ]; then # 160x90 floats after the three header lines
        covered=$(tail -c $((160 * 90 * 4)) "$d/$n.aov/mask.pfm" | od -An -v -tx4 | tr -s ' ' '\n' |
                  grep -c '^[0-9a-f]*[1-9a-f][0-9a-f]*$')
    fi
    [ "$status" -ne 0 ] && { [ -e "$d/$n.png" ] || [ -e "$d/$n.aov" ]; } && png_left=1
    grep -q 'no surface is in view' "$d/$n.err" && warned=1
    grep -qE 'ERROR: AddressSanitizer|ERROR: LeakSanitizer|runtime error:' "$d/$n.err" && sanitizer=1
    rm -rf "$d/$n.aov" "$d/$n.time" "$d/$n.out"
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$n" "$file" "$status" "$lines" "$wall" "${rss:--1}" \
        "$covered" "$png_left" "$warned" "$sanitizer" "$first"
}
export -f one
export out sl kill_after extra

total=$(wc -l <"$out/files.tsv")
echo "model-sweep.sh: $total files from $models, $jobs at a time${extra:+, with $extra}, into $out" >&2
tr '\t' '\n' <"$out/files.tsv" | tr '\n' '\0' | xargs -0 -n 2 -P "$jobs" bash -c 'one "$@"' one >"$out/rows.tsv"
{
    printf 'n\tfile\tstatus\terr_lines\twall_s\trss_mib\tcovered\tpng_left\twarned\tsanitizer\tfirst_err_line\n'
    sort -n "$out/rows.tsv"
} >"$out/sweep.tsv"
rm -f "$out/rows.tsv"

# The summary: each class with its count, and the files of every class that breaks the promise.
awk -F'\t' -v out="$out/sweep.tsv" -v build="$build" -v extra="$extra" '
NR == 1 { next }
{
    files++
    st = $3; lines = $4; wall = $5 + 0; rss = $6 + 0; cov = $7 + 0
    if (st == 0) { rendered++; if (cov == 0 && !$9) add("empty", $2); if (cov == 0 && $9) emptyw++ }
    else if (st == 2 && lines == 1) refused++
    else if (st == 2) add("multi", $2 " (" lines " lines)")
    else if (st == 124 || st == 137) add("hang", $2)
    else add("crash", $2 " (status " st ")")
    if (wall > 10) add("slow", $2 " (" wall " s)")
    if (wall > maxwall) { maxwall = wall; maxwall_f = $2 }
    if (rss > maxrss) { maxrss = rss; maxrss_f = $2 }
    if (rss > 1024) add("big", $2 " (" rss " MiB)")
    if ($8) add("halfout", $2)
    if ($10) add("san", $2)
}
function add(k, f) { n[k]++; list[k] = list[k] "    " f "\n" }
function show(k, label) { printf "%-46s %5d\n", label, n[k]; if (n[k]) printf "%s", list[k] }
END {
    printf "model sweep of %d files with %s%s (rows: %s)\n", files, build, extra != "" ? " " extra : "", out
    printf "%-46s %5d\n", "rendered (exit 0)", rendered
    printf "%-46s %5d\n", "  of them empty, with the warning", emptyw
    printf "%-46s %5d\n", "refused in one line (exit 2, 1 line)", refused
    show("crash", "crashed (signal, or exit other than 0 and 2)")
    show("hang", "killed by the sweep'"'"'s timeout")
    show("multi", "multi-line errors (exit 2)")
    show("empty", "exit 0, empty image, no warning")
    show("halfout", "failed run that left an image")
    show("slow", "over 10 s")
    show("big", "over 1 GiB peak RSS")
    show("san", "ASan/UBSan reports")
    printf "longest run: %.2f s (%s); largest peak RSS: %d MiB (%s)\n", maxwall, maxwall_f, maxrss, maxrss_f
    bad = n["crash"] + n["hang"] + n["multi"] + n["empty"] + n["halfout"] + n["slow"] + n["big"] + n["san"]
    exit bad > 0
}' "$out/sweep.tsv"
