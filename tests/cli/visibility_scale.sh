#!/usr/bin/env bash
# visibility_scale.sh BUILD_DIR - the visibility methods and the visibility truth do not depend on
# the unit a scene is modelled in. One scene (the bunny, a GGX ball and box on a glossy floor under
# sunset.hdr, a point light) written three times: in its own units, 1000 times larger and 1000
# times smaller (every position, size, near and far plane; the light's intensity times the scale
# squared), each rendered with the whole visibility set at its scale (--shadows, --ao-radius 1 and
# --reflection-occlusion 7 times the scale, --sky-maps 32, --env-lights 32):
#   - each scaled render agrees with the unscaled one: p99 relative error <= 0.01 and no more than
#     0.1% of the pixels more than 1/255 apart (measured p99 0.0011 and 0.0004, no pixel);
#   - the set changes the image (the unscaled render without it: p99 0.93), so the agreement is
#     the set's and not the absence of it;
#   - `softlight truth --visibility --lights` agrees the same way, p99 <= 0.001 (measured 5e-6);
#     a ray offset with an absolute floor (1e-4 world units) put 5.6% of the smaller scene's
#     pixels more than 1/255 off (p99 0.13).
# CTest label: release-only
set -euo pipefail
. "$(dirname "$0")/lib.bash"
cli_init visibility_scale "$1"
R=$PWD/scenes

# scene SCALE: the scene with every length times SCALE
scene() {
    python3 - "$1" "$R" <<'PY'
import json, sys
s, root = float(sys.argv[1]), sys.argv[2]
print(json.dumps({
    "camera": {"eye": [-4.0 * s, 5.5 * s, 1.8 * s], "target": [0.3 * s, 0, 0.7 * s], "up": [0, 0, 1],
               "fovy": 40, "near": 0.1 * s, "far": 60 * s},
    "environment": {"hdr": root + "/envmaps/sunset.hdr", "rotation": 70},
    "materials": {"fur": {"kd": 0.5, "ks": 0.04, "alpha": 30},
                  "chrome": {"brdf": "ggx", "kd": 0.02, "ks": 0.9, "roughness": 0.15},
                  "floor": {"brdf": "ggx", "kd": 0.3, "ks": 0.04, "roughness": 0.2}},
    "objects": [
        {"name": "bunny", "mesh": root + "/meshes/bunny.obj", "material": "fur",
         "transform": {"rotate": [1, 0, 0, 90], "scale": 0.2 * s}},
        {"name": "ball", "shape": "sphere", "material": "chrome",
         "transform": {"translate": [1.6 * s, 1.0 * s, 0.6 * s], "scale": 0.6 * s}},
        {"name": "box", "shape": "box", "material": "chrome",
         "transform": {"translate": [-1.2 * s, -1.5 * s, 0.5 * s], "scale": 0.5 * s}},
        {"name": "floor", "shape": "plane", "material": "floor", "transform": {"scale": [6 * s, 6 * s, 1]}}],
    "lights": [{"position": [-3 * s, 3 * s, 4 * s], "color": "#ffe8c8", "intensity": 60 * s * s}],
    "render": {"width": 160, "height": 90, "samples": 40, "exposure": 1.2}}))
PY
}

# agree NAME A B P99: A and B within P99 (p99 relative error) and at most 0.1% of the pixels
# more than 1/255 apart
agree() {
    local status=0 over
    "$SL" compare "$2" "$3" --metric p99rel --tolerance "$4" >"$T/cmp.txt" || status=$?
    over=$(sed -n 's/^8-bit diff > 1 *\([0-9.]*\)%.*/\1/p' "$T/cmp.txt")
    if [ "$status" = 0 ] && awk -v o="$over" 'BEGIN { exit !(o != "" && o <= 0.1) }'; then
        ok "$1: $(grep 'p99 rel' "$T/cmp.txt"), ${over}% of pixels more than 1/255 apart"
    else
        bad "$1: $(grep 'p99 rel' "$T/cmp.txt"), ${over:-?}% of pixels more than 1/255 apart"
    fi
}

for s in 1 1000 0.001; do
    scene "$s" >"$T/scene-$s.json"
    "$SL" render "$T/scene-$s.json" --env-lights 32 --shadows --sky-maps 32 \
        --ao-radius "$(awk -v s="$s" 'BEGIN { print s }')" \
        --reflection-occlusion "$(awk -v s="$s" 'BEGIN { print 7 * s }')" --pfm "$T/set-$s.pfm" -o "$T/set-$s.png" -q
done
"$SL" render "$T/scene-1.json" --env-lights 32 --pfm "$T/blind.pfm" -o "$T/blind.png" -q
agree "the set, 1000 times larger" "$T/set-1.pfm" "$T/set-1000.pfm" 0.01
agree "the set, 1000 times smaller" "$T/set-1.pfm" "$T/set-0.001.pfm" 0.01
if "$SL" compare "$T/set-1.pfm" "$T/blind.pfm" --metric p99rel --tolerance 0.1 >"$T/cmp.txt"; then
    bad "the set leaves the image within 0.1 of the render without it: the test sees no visibility"
else
    ok "the set changes the image: $(grep 'p99 rel' "$T/cmp.txt")"
fi

if "$SL" truth "$T/scene-1.json" --size 2x2 --visibility --pfm "$T/x.pfm" 2>&1 | grep -q "needs Embree"; then
    ok "the truth's part skipped: a build without Embree"
else
    for s in 1 1000 0.001; do
        "$SL" truth "$T/scene-$s.json" --size 64x36 --visibility --lights --pfm "$T/truth-$s.pfm" >/dev/null \
            2>"$T/truth.err" || { cat "$T/truth.err"; exit 1; }
    done
    agree "the visibility truth, 1000 times larger" "$T/truth-1.pfm" "$T/truth-1000.pfm" 0.001
    agree "the visibility truth, 1000 times smaller" "$T/truth-1.pfm" "$T/truth-0.001.pfm" 0.001
fi
cli_done visibility_scale
