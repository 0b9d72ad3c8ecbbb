#!/usr/bin/env bash
# run.sh BUILD_DIR OUT_DIR [SIZE] - the specular layouts on surfaces that reflect a pole, against the
# ground truth (docs/ibl.md "Specular layouts"). Cases: top-down.json's floor (R = +Z), grazing.json's
# floor, bench/poles/ceiling.json (R = -Z), each under its own environment and under city.hdr. For
# each: `softlight truth --part specular` once (cached in OUT_DIR), then both layouts with the spec
# estimator (the default) and the accurate one (mf, pdf rule, distortion), specular only; prints
# nRMSE, the share > 1/255 after the tone map, and the shading time (median of --repeat 5).
set -euo pipefail
cd "$(dirname "$0")/../.."
SL=${1:?usage: $0 BUILD_DIR OUT_DIR [SIZE]}/softlight
OUT=${2:?usage: $0 BUILD_DIR OUT_DIR [SIZE]}
SIZE=${3:-64x64}
mkdir -p "$OUT"
root=$(pwd)
# a scene with its environment swapped: the same JSON with an absolute path in "hdr"
variant() { # scene env name
    sed -E "s|\"hdr\": *\"[^\"]*\"|\"hdr\": \"$root/scenes/envmaps/$2\"|" "$1" >"$OUT/$3.json"
}
printf '%-20s %-8s %-9s %8s %8s %10s\n' case layout estimator nRMSE '>1/255' 'shading ms'
for spec in "scenes/top-down.json interior.hdr top-down" "scenes/top-down.json city.hdr top-down-city" \
    "scenes/grazing.json sunset.hdr grazing" "scenes/grazing.json city.hdr grazing-city" \
    "bench/poles/ceiling.json interior.hdr ceiling" "bench/poles/ceiling.json city.hdr ceiling-city"; do
    read -r scene env name <<<"$spec"
    variant "$scene" "$env" "$name"
    "$SL" truth "$OUT/$name.json" --size "$SIZE" --cache "$OUT/$name.truth" >/dev/null 2>&1
    for est in spec accurate; do
        opts=()
        [ "$est" = accurate ] && opts=(--estimator mf --lod pdf --distortion)
        for layout in latlong oct; do
            r="$OUT/$name.$est.$layout"
            "$SL" render "$OUT/$name.json" --size "$SIZE" --specular-only --env-layout "$layout" "${opts[@]}" \
                --repeat 5 --pfm "$r.pfm" >"$r.log" 2>&1
            "$SL" truth "$OUT/$name.json" --size "$SIZE" --cache "$OUT/$name.truth" --part specular \
                --compare "$r.pfm" 2>/dev/null | grep 'against the truth' >"$r.cmp"
            ms=$(grep -oE 'shading [0-9.]+ ms' "$r.log" | tail -1 | grep -oE '[0-9.]+')
            nrmse=$(grep -oE 'nrmse [0-9.]+' "$r.cmp" | grep -oE '[0-9.]+$')
            over=$(grep -oE '>1/255 [0-9.]+%' "$r.cmp" | grep -oE '[0-9.]+%')
            printf '%-20s %-8s %-9s %8s %8s %10s\n' "$name" "$layout" "$est" "$nrmse" "$over" "$ms"
        done
    done
done
