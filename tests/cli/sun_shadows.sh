#!/usr/bin/env bash
# sun_shadows.sh BUILD_DIR - the env lights' orthographic shadow maps (--shadows with
# --env-lights; docs/lighting.md "Shadow maps") under a made environment: a black sky and a sun
# of two texels, so that the env lights hold all of its light. Without env lights --shadows
# changes nothing, nor does a sun with under 1% of the environment's light; a floor alone under a high sun and a grazing one (3 degrees) stays fully lit
# (no acne); the shadows of a floating slab and of a box standing on the floor (no gap at its
# foot: no peter-panning) fall where the visibility-aware truth (`softlight truth --visibility`,
# Embree) puts them, with the environment turned, in the default path, the port (--plain) and
# the microfacet estimator; the default path's vector sum agrees with the port's, with
# --ao-radius too; `softlight trace` prints each env light's visibility (softlight-gl's maps:
# gl_sun_shadows.sh). A sun's glow: under a sun of two texels in a glare of ten that two env
# lights leave to the samples, a glossy floor's reflection of the glare in a box's shadow is as
# dark as the truth's (each sample in a map's glow is times its visibility), in the batched path
# and the port, with the microfacet and the MIS estimators, and the trace marks the samples in
# a glow. Without Embree the truth comparisons are left out.
set -u
. "$(dirname "$0")/lib.bash"
cli_init sun_shadows "$1"
S=160x90
export PYTHONPATH="$(dirname "$0")"

# sky NAME ELEVATION AZIMUTH: the black sky with a sun of two texels at that direction
# (degrees), $T/NAME.pfm (sun_sky.py)
sky() { python3 "$(dirname "$0")/sun_sky.py" "$T/$1.pfm" "$2" "$3"; }

# scene NAME SKY ROTATION OBJECTS...: a 4x4 floor seen from above at an angle under sky SKY
scene() {
    local name=$1 sky=$2 rot=$3; shift 3
    local objects=""
    for o in "$@"; do objects="$objects, $o"; done
    cat >"$T/$name.json" <<JSON
{"camera": {"eye": [0, -3.5, 3.5], "target": [0, 0, 0], "up": [0, 0, 1], "fovy": 45},
 "environment": {"hdr": "$T/$sky.pfm", "rotation": $rot},
 "materials": {"m": {"kd": 0.6, "ks": 0.04, "alpha": 10}},
 "objects": [{"shape": "plane", "material": "m", "transform": {"scale": [2, 2, 1]}}$objects]}
JSON
}

# off: --shadows without env lights changes nothing
sky high 60 40
scene plane-high high 0
"$SL" render "$T/plane-high.json" --size $S -q --pfm "$T/o0.pfm"
"$SL" render "$T/plane-high.json" --size $S -q --shadows --pfm "$T/o1.pfm"
cmp -s "$T/o0.pfm" "$T/o1.pfm" && ok "no env lights: --shadows gives the same bytes" || bad "no env lights: --shadows changed the image"

# a sun under 1% of the environment's light (a sky of 1000 around it) gets no map: the same
# bytes as without --shadows; on a sky of 10 it carries about 30% and gets one
python3 "$(dirname "$0")/sun_sky.py" "$T/bright.pfm" 60 40 1000
scene plane-bright bright 0 '{"shape": "box", "material": "m", "transform": {"translate": [0.3, 0.1, 0.7], "scale": [0.3, 0.3, 0.05]}}'
"$SL" render "$T/plane-bright.json" --size $S -q --env-lights 4 --pfm "$T/w0.pfm"
"$SL" render "$T/plane-bright.json" --size $S --env-lights 4 --shadows --pfm "$T/w1.pfm" >"$T/w1.txt"
cmp -s "$T/w0.pfm" "$T/w1.pfm" && grep -q '^env-light shadow maps: none' "$T/w1.txt" &&
    ok "a sun with under 1% of the light: no map, the same bytes" ||
    bad "a sun with under 1% of the light: $(grep '^env-light' "$T/w1.txt")"
python3 "$(dirname "$0")/sun_sky.py" "$T/dim.pfm" 60 40 10
scene plane-dim dim 0 '{"shape": "box", "material": "m", "transform": {"translate": [0.3, 0.1, 0.7], "scale": [0.3, 0.3, 0.05]}}'
"$SL" render "$T/plane-dim.json" --size $S --env-lights 4 --shadows -o "$T/w2.png" >"$T/w2.txt"
grep -q '^env-light shadow maps: 1 orthographic map' "$T/w2.txt" && ok "a sun with about 30% of the light: one map" ||
    bad "a sun with about 30% of the light: $(grep '^env-light' "$T/w2.txt")"

# ratio A.pfm B.pfm: the smallest and largest ratio A/B (green) over pixels B lights
ratio() {
    python3 - "$1" "$2" <<'PY'
import sys
from pfm import read_pfm
_, _, _, a = read_pfm(sys.argv[1]); _, _, _, b = read_pfm(sys.argv[2])
r = [a[i] / b[i] for i in range(1, len(b), 3) if b[i] > 1e-3]
print(f"{min(r):.4f} {max(r):.4f} {len(r)}")
PY
}

# no acne: the floor, under a high sun and a grazing one, stays lit as without maps; a box hidden
# under it deepens the scene's bounds, so the map's texels are coarse against the floor's slope
sky graze 3 40
scene plane-graze graze 0 '{"shape": "box", "material": "m", "transform": {"translate": [0, 0, -2], "scale": 0.5}}'
for s in high graze; do
    "$SL" render "$T/plane-$s.json" --size $S -q --env-lights 4 --pfm "$T/p-b.pfm"
    "$SL" render "$T/plane-$s.json" --size $S -q --env-lights 4 --shadows --pfm "$T/p-s.pfm"
    read -r lo hi n <<<"$(ratio "$T/p-s.pfm" "$T/p-b.pfm")"
    python3 -c "import sys; sys.exit(0 if $n > 5000 and $lo > 0.99 and $hi < 1.01 else 1)" &&
        ok "floor, sun $s: fully lit ($n pixels, shadowed / unshadowed in [$lo, $hi])" ||
        bad "floor, sun $s: shadowed / unshadowed in [$lo, $hi] over $n pixels, want [0.99, 1.01]"
done

# a slab floating over the floor and a box standing on it, the sky turned by 30 degrees
sky mid 40 30
scene occ mid 30 '{"shape": "box", "material": "m", "transform": {"translate": [0.3, 0.1, 0.7], "scale": [0.3, 0.3, 0.05]}}' \
    '{"shape": "box", "material": "m", "transform": {"translate": [-0.7, -0.5, 0.25], "scale": 0.25}}'
# the batched path's vector sum against the port's per-pixel sum, with the maps and with the
# ambient occlusion's cone under pbr.json's sky as well: the tolerance of test_lighting_fast
# (mean relative 3e-4)
for run in "$T/occ.json --env-lights 4" "scenes/pbr.json --env-lights 32 --ao-radius 1" "scenes/ggx.json --ao-radius 1"; do
    # shellcheck disable=SC2086
    "$SL" render $run --size $S -q --shadows --pfm "$T/fast.pfm"
    # shellcheck disable=SC2086
    "$SL" render $run --size $S -q --shadows --plain --pfm "$T/port.pfm"
    name="$(basename "${run%% *}") ${run#* }"
    python3 - "$T/fast.pfm" "$T/port.pfm" >"$T/fp.txt" <<'PY' && ok "batched vs port, $name: $(cat "$T/fp.txt")" || bad "batched vs port, $name: $(cat "$T/fp.txt")"
import sys
from pfm import read_pfm
_, _, _, f = read_pfm(sys.argv[1]); _, _, _, p = read_pfm(sys.argv[2])
rel = [abs(a - b) / b for a, b in zip(f, p) if b > 1e-3]
mean = sum(rel) / len(rel)
print(f"mean relative {mean:.2e}, max {max(rel):.2e} over {len(rel)} channels")
sys.exit(0 if mean < 3e-4 else 1)
PY
done

if ! "$SL" truth "$T/occ.json" --size 2x2 --visibility --pfm "$T/probe.pfm" >/dev/null 2>&1; then
    cli_done "sun_shadows (a build without Embree: no truth comparisons)"
    exit
fi
"$SL" truth "$T/occ.json" --size $S --visibility --vis-level 0 --pfm "$T/t.pfm" >/dev/null 2>&1
"$SL" render "$T/occ.json" --size $S -q --env-lights 4 --pfm "$T/b.pfm"
for mode in "" "--plain" "--estimator mf"; do
    # shellcheck disable=SC2086
    "$SL" render "$T/occ.json" --size $S -q --env-lights 4 --shadows $mode --pfm "$T/s.pfm"
    python3 - "$T/t.pfm" "$T/s.pfm" "$T/b.pfm" >"$T/cmp.txt" <<'PY' && ok "${mode:-default path}: $(head -1 "$T/cmp.txt")" || bad "${mode:-default path}: $(head -1 "$T/cmp.txt")"
import sys
from pfm import read_pfm
w, h, _, t = read_pfm(sys.argv[1]); _, _, _, s = read_pfm(sys.argv[2]); _, _, _, b = read_pfm(sys.argv[3])
t, s, b = t[1::3], s[1::3], b[1::3]  # green
lit = [i for i in range(w * h) if b[i] > 1e-3]
shadowed = lambda img, i: img[i] < 0.5 * b[i]
in_truth = [i for i in lit if shadowed(t, i)]
# the sun's two texels, 4 degrees apart, share one map (one shadow along their mean direction)
# where the truth casts two: along each edge it has half the light where the map has all or
# none, so a disagreement is a difference of more than half the light
disagree = sum(abs(t[i] - s[i]) > 0.55 * b[i] for i in lit)
l1 = sum(abs(t[i] - s[i]) for i in lit) / sum(t[i] for i in lit)
l1_blind = sum(abs(t[i] - b[i]) for i in lit) / sum(t[i] for i in lit)
print(f"{len(in_truth)} of {len(lit)} pixels in the truth's shadows, {disagree} off by more than half; "
      f"relative L1 {l1:.4f} (without shadows {l1_blind:.4f})")
# a pixel deep in the shadows and one in the open, image rows from the top, for the trace
deep = min(in_truth, key=lambda i: t[i] / b[i])
open_ = max((i for i in lit if not shadowed(t, i)), key=lambda i: t[i] / b[i])
for i in (deep, open_):
    print(f"{i % w},{h - 1 - i // w}")
sys.exit(0 if len(in_truth) > 300 and disagree <= 0.03 * len(in_truth) and l1 < 0.15 * l1_blind else 1)
PY
done

# a sun's glow: a glossy floor (GGX, r 0.3) facing a sun 25 degrees up in a glare of ten texels
# of 300 (glare_scene.bash), a box between; two env lights take the sun, the samples read the glare.
# The light without shadows, which picks the pixels and scales their error, is the recipe's on
# every pixel (`--estimator spec`).
# Over the floor pixels in the truth's shadow (under half the light without shadows), the
# render's distance from the truth over its light without shadows: 0.10 with the glow and
# 0.36 to 0.39 without it (a build with SL_SHADOW_GLOW_DEG 0), at 96x54; over the whole floor
# the relative L1 0.048 to 0.057 with it, 0.12 to 0.13 without
source "$(dirname "$0")/glare_scene.bash"
glare_scene "$T"
G=96x54
"$SL" truth "$T/glare.json" --size $G --visibility --vis-level 0 --pfm "$T/gt.pfm" >/dev/null 2>&1
"$SL" render "$T/glare.json" --size $G -q --env-lights 2 --estimator spec --pfm "$T/gb.pfm"
for mode in "--estimator mf --lod pdf --distortion -n 256" "--estimator mf --lod pdf --distortion -n 256 --plain" \
    "--estimator mis -n 40" "--estimator mis -n 40 --plain"; do
    # shellcheck disable=SC2086
    "$SL" render "$T/glare.json" --size $G -q --env-lights 2 --shadows $mode --pfm "$T/gs.pfm"
    python3 - "$T/gt.pfm" "$T/gs.pfm" "$T/gb.pfm" >"$T/glare.txt" <<'PY' && ok "glare, $mode: $(head -1 "$T/glare.txt")" || bad "glare, $mode: $(head -1 "$T/glare.txt")"
import sys
from pfm import read_pfm
w, h, _, t = read_pfm(sys.argv[1]); _, _, _, s = read_pfm(sys.argv[2]); _, _, _, b = read_pfm(sys.argv[3])
t, s, b = t[1::3], s[1::3], b[1::3]  # green
lit = [i for i in range(w * h) if b[i] > 1e-3]
shade = [i for i in lit if t[i] < 0.5 * b[i]]
off = sum(abs(t[i] - s[i]) for i in shade) / sum(b[i] for i in shade)
l1 = sum(abs(t[i] - s[i]) for i in lit) / sum(t[i] for i in lit)
print(f"{len(shade)} pixels in the truth's shadow, off by {off:.4f} of their light; relative L1 {l1:.4f}")
deep = min(shade, key=lambda i: t[i] / b[i])  # for the trace: x, y from the top
print(f"{deep % w},{h - 1 - deep // w}")
sys.exit(0 if len(shade) > 300 and off < 0.15 and l1 < 0.08 else 1)
PY
done
"$SL" trace "$T/glare.json" --size $G --env-lights 2 --shadows --estimator mis -n 8 --pixel "$(sed -n 2p "$T/glare.txt")" |
    grep -q "in map [0-9]'s glow" && ok "trace marks the samples in a glow ($(sed -n 2p "$T/glare.txt"))" ||
    bad "trace marks no sample in a glow at $(sed -n 2p "$T/glare.txt")"

# trace: each env light's visibility, 0 in the shadow and 1 in the open (no line without maps)
for pair in "$(sed -n 2p "$T/cmp.txt") 0" "$(sed -n 3p "$T/cmp.txt") 1"; do
    read -r px want <<<"$pair"
    lines=$("$SL" trace "$T/occ.json" --size $S --env-lights 4 --shadows --pixel "$px" | grep "^  env light [0-9]")
    vis=$(echo "$lines" | grep -c "visibility $want\$")
    [ "$vis" -ge 2 ] && ok "trace at $px: $vis env lights with visibility $want" ||
        bad "trace at $px: want visibility $want:"$'\n'"$lines"
done
"$SL" trace "$T/occ.json" --size $S --env-lights 4 --pixel 80,60 | grep -q "^  env light [0-9]" &&
    bad "trace without --shadows prints env lights' visibility"

cli_done sun_shadows
