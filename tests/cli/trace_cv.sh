#!/usr/bin/env bash
# trace_cv.sh BUILD_DIR - `softlight trace --estimator cv` (docs/lighting.md "Control variate"):
# the trace prints the split sum's lookup, Lbar, E_ss, the closed part, the mean correction and
# each sample's term F W (Li - Lbar); recomputed here from the printed numbers: the closed part is
# Lbar E_ss, the correction the last sample's running sum over N, and the specular term the
# closed part plus the correction (to the printed digits, 1e-4 relative of the specular term).
# Both paths (the batched default and --plain, the port), on the default scene's alpha 1, Ks 0.9
# sphere, where the correction is far from 0.
set -euo pipefail
cd "$(dirname "$0")/../.."
SL="$1/softlight"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
for path in "" --plain; do
    "$SL" trace scenes/default.json --size 192x108 --pixel 45,91 --estimator cv -n 16 --lod pdf --distortion \
        --no-lights $path >"$T/trace.txt"
    for key in "control variate: the split sum's lookup" "Lbar" "E_ss" "closed part" "correction"; do
        grep -q "^ *$key" "$T/trace.txt" || { echo "FAIL ($path): no '$key' line"; cat "$T/trace.txt"; exit 1; }
    done
    tr '(),' '   ' <"$T/trace.txt" | awk -v path="$path" '
        function bad(what, got, want) { printf "FAIL (%s): %s printed %g, recomputed %g\n", path, what, got, want; fails++ }
        function off(a, b, scale) { d = a - b; return (d < 0 ? -d : d) > 1e-4 * scale + 1e-7 }
        $1 == "Lbar" { l = $2 } $1 == "E_ss" { e = $2 } $1 == "closed" { c = $3 } $1 == "correction" { k = $2 }
        /^specular samples/ { n = $5; sub(/;/, "", n) }
        / sum / { s = $(NF - 2) }
        $1 == "specular" && NF == 4 { spec = $2 }
        END {
            if (n == "" || spec == "") { print "FAIL (" path "): no samples or no specular line"; exit 1 }
            if (off(c, l * e, spec)) bad("closed part", c, l * e)
            if (off(k, s / n, spec)) bad("correction", k, s / n)
            if (off(spec, c + k, spec)) bad("specular", spec, c + k)
            if (k == 0) { print "FAIL (" path "): the correction is 0 on a rough sphere"; fails++ }
            exit fails > 0
        }' || { cat "$T/trace.txt"; exit 1; }
done
echo "trace_cv: ok"
