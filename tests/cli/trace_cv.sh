#!/usr/bin/env bash
# trace_cv.sh BUILD_DIR - `softlight trace --estimator cv` (docs/lighting.md "Control variate"):
# the trace prints the chain's exact part (its levels and shares), beta, the albedo E, the closed
# part, the mean correction, and each sample's term (F W - beta E K/p) Li with its K/p; recomputed
# here from the printed numbers: the closed part is beta E times the prefiltered read (intensity 1),
# each sample's contribution F Li G (w.N)(V.H)/(N.H) less beta E K/p Li, the correction the last
# sample's running sum over N, and the specular term the closed part plus the correction (to the
# printed digits: 1e-4 relative of the specular term; 5e-3 of a contribution's two terms, whose
# factors are printed to four digits). Both paths
# (the batched default and --plain, the port), on the default scene's alpha 1, Ks 0.9 sphere,
# where beta is near 1 and the kernel's terms are far from 0. Then --estimator cvmis (the same
# kernel with mis's pairs), on the alpha 1, Ks 0.5 sphere, where the kernel reaches some of the
# samples below the horizon: the same lines, K/p for both strategies' samples, a sample below the
# horizon adding only -beta E K/p weight Li (at least one with K/p > 0, so the check bites), the
# correction the last running sum over the pair count, and the specular term the closed part
# plus the correction.
set -euo pipefail
cd "$(dirname "$0")/../.."
SL="$1/softlight"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
# trace LABEL PIXEL PATH OPTIONS... -- KEY...: trace PIXEL of the default scene with OPTIONS and
# PATH ("" or --plain) into $T/trace.txt; every KEY must begin a line of it
trace() {
    local label=$1 pixel=$2 path=$3
    shift 3
    local options=()
    while [ "$1" != "--" ]; do options+=("$1"); shift; done
    shift
    "$SL" trace scenes/default.json --size 192x108 --pixel "$pixel" --no-lights "${options[@]}" $path >"$T/trace.txt"
    for key in "$@"; do
        grep -q "^ *$key" "$T/trace.txt" || { echo "FAIL $label($path): no '$key' line"; cat "$T/trace.txt"; exit 1; }
    done
}
# check LABEL PATH AWK: $T/trace.txt through awk with AWK after the parts both estimators share:
# bad and off, the printed factors of the closed part (p, beta, e, c), the correction k and the
# specular term spec, and sums(), which recomputes the closed part, the correction (s / n, s and
# n set by AWK) and the specular term
check() {
    tr '(),' '   ' <"$T/trace.txt" | awk -v label="$1" -v path="$2" '
        function bad(what, got, want) { printf "FAIL %s(%s): %s printed %g, recomputed %g\n", label, path, what, got, want; fails++ }
        function off(a, b, tol) { d = a - b; return (d < 0 ? -d : d) > tol }
        function sums() {
            if (off(c, beta * e * p, 1e-4 * spec + 1e-7)) bad("closed part", c, beta * e * p)
            if (off(k, s / n, 1e-4 * spec + 1e-7)) bad("correction", k, s / n)
            if (off(spec, c + k, 1e-4 * spec + 1e-7)) bad("specular", spec, c + k)
        }
        $1 == "prefiltered" { p = $2 } $1 == "beta" { beta = $2 } $1 == "E" { e = $2 }
        $1 == "closed" { c = $3 } $1 == "correction" { k = $2 }
        $1 == "specular" && NF == 4 { spec = $2 }
        '"$3" || { cat "$T/trace.txt"; exit 1; }
}
for path in "" --plain; do
    trace "" 45,91 "$path" --estimator cv -n 16 --lod pdf --distortion -- "control variate: the split sum's lookup" \
        "prefiltered" "exact part" "beta" "E" "closed part" "correction" "K/p"
    check "" "$path" '
        /^specular samples/ { n = $5; sub(/;/, "", n) }
        / sum / && NF >= 30 { s = $(NF - 2); cx = $25; pred = $18 * $22 * $17 * $11 * $15 / $6; li = $22; have = 1 }
        / sum / && NF < 30 { s = $(NF - 2); have = 0 }
        $1 == "K/p" && have { kernel++; if ($2 > 0) used++
            sub_term = beta * e * $2 * li; want = pred - sub_term
            if (off(cx, want, 5e-3 * ((pred < 0 ? -pred : pred) + sub_term) + 1e-6)) bad("a contribution", cx, want) }
        END {
            if (n == "" || spec == "" || kernel == 0) { print "FAIL (" path "): no samples or no specular line"; exit 1 }
            if (beta < 0.5 || used == 0) { print "FAIL (" path "): beta " beta " and no kernel term on a rough sphere"; fails++ }
            sums()
            exit fails > 0
        }'
done
for path in "" --plain; do
    trace "cvmis " 45,75 "$path" --estimator cvmis -n 16 -- "control variate: the split sum's lookup" "beta" \
        "closed part" "correction" "K/p" "specular samples (MIS"
    check "cvmis " "$path" '
        /^specular samples/ { n = $4 }
        / sum / { s = $(NF - 2); alone = 0 }
        /kernel.s term alone/ { for (i = 1; i <= NF; i++) if ($i == "Li") { li = $(i + 1); cx = $(i + 4) }
            w = $11; alone = 1 }
        $1 == "K/p" { kernel++; if ($2 > 0) used++
            if (alone) { below++; if ($2 > 0) reached++; want = -beta * e * $2 * w * li
                if (off(cx, want, 5e-3 * (want < 0 ? -want : want) + 1e-7)) bad("a kernel term below the horizon", cx, want) } }
        END {
            if (n == "" || spec == "" || kernel == 0) { print "FAIL cvmis (" path "): no samples or no specular line"; exit 1 }
            if (used == 0) { print "FAIL cvmis (" path "): no kernel term"; fails++ }
            if (reached == 0) { print "FAIL cvmis (" path "): no sample below the horizon that the kernel reaches"; fails++ }
            sums()
            printf "cvmis (%s): %d samples with a kernel term, %d of them below the horizon, %d the kernel reaches\n", path, kernel, below, reached
            exit fails > 0
        }'
done
echo "trace_cv: ok"
