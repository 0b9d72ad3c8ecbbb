#!/usr/bin/env bash
# lobe-sets.sh - scenes of both lobe sets (GGX objects beside the specification's Phong ones):
# what their default, each set sampled its own way (docs/accuracy.md "Defaults": the GGX objects
# by the microfacet estimator with the pdf rule and the distortion, the Phong ones by the
# recipe), costs and leaves against the truth, beside every pixel sampled by the recipe and
# every pixel by the microfacet estimator; and scenes of GGX objects alone that set no N, as a
# model opened by itself is (`model-alone`, model.json without its floor; `pbr-alone`, pbr.json):
# their default (mf, pdf, distortion, the env lights worth their cost) at the N they take
# (SL_GGX_DEFAULT_SAMPLES) and at N 40, beside the recipe at N 40.
#
#   bench/lobe-sets.sh [BUILD_DIR] [SIZE]
#
# Scenes: scenes/model.json (a glTF model, GGX, on a Phong floor) and `spheres-floor`, written
# here: scenes/ggx.json's ten GGX spheres over a Phong floor (Phong 50, Ks 0.04); each under its
# own environment and under the three of bench/check_environments.py that are not in the
# repository (a small sun, small lamps at night, a sun on the horizon). Per scene: the ground
# truth (`softlight truth`, cached by content in out/ground-truth/lobe-sets/), bench_mis_front's
# lighting CPU time (1 thread, median of 7 interleaved frames, point lights off) and `softlight
# truth --compare` of each variant: nRMSE and the shares of pixels more than 1/255 and 8/255 off
# after the scene's tone map. The Phong pixels are the same bits under the default and under the
# recipe, so the two rows differ by the GGX pixels alone. Writes docs/accuracy/lobe-sets.md.
# About 25 minutes on the 2-core machine with a cold cache (most of it the ground truth).
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/cpu_frame.bash # vector_isa
source bench/front_rows.bash
build=${1:-build}
size=${2:-192x108}
SL=$build/softlight
BENCH=$build/bench_mis_front
[ -x "$BENCH" ] || { echo "lobe-sets: $BENCH not found: build first" >&2; exit 2; }
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-lobe-sets.XXXXXX")
trap 'rm -rf "$T"' EXIT
cache=out/ground-truth/lobe-sets
mkdir -p "$cache" docs/accuracy
python3 bench/check_environments.py "$T" >/dev/null
# the scenes, their paths made absolute so that they load from $T
python3 - "$T" <<'PY'
import json, os, sys
out = sys.argv[1]
root = os.path.abspath("scenes")
def absolute(s):
    s["environment"]["hdr"] = os.path.join(root, s["environment"]["hdr"])
    for o in s["objects"]:
        if "model" in o:
            o["model"] = os.path.join(root, o["model"])
    return s
model = absolute(json.load(open("scenes/model.json")))
spheres = absolute(json.load(open("scenes/ggx.json")))
spheres["materials"]["floor"] = {"kd": 0.3, "ks": 0.04, "alpha": 50}
spheres["objects"].append({"shape": "plane", "material": "floor",
                           "transform": {"translate": [0, 0, -2.1], "scale": [12, 12, 1]}})
# GGX alone, as a model opened by itself is: the model without its floor and pbr.json, neither
# setting N
alone = json.loads(json.dumps(model))
alone["objects"] = [o for o in alone["objects"] if "model" in o]
alone["render"].pop("samples", None)
pbr = absolute(json.load(open("scenes/pbr.json")))
pbr["render"].pop("samples", None)
for name, s in (("model", model), ("spheres-floor", spheres), ("model-alone", alone), ("pbr-alone", pbr)):
    json.dump(s, open(os.path.join(out, name + ".json"), "w"))
    for env in ("sun", "night", "horizon"):
        s["environment"] = {"hdr": os.path.join(out, env + ".pfm"), "intensity": 1, "rotation": 0}
        json.dump(s, open(os.path.join(out, "%s-%s.json" % (name, env)), "w"))
PY
V=("recipe-N40|spec|spec-d4|0|40" "default-N40|default|-|0|40|auto" "mf-pdf+dist-N40|mf|pdf|1|40")
md=docs/accuracy/lobe-sets.md
front_table_head bench/lobe-sets.sh "$md"
for name in model model-sun model-night model-horizon spheres-floor spheres-floor-sun spheres-floor-night \
    spheres-floor-horizon; do
    front_rows "$SL" "$BENCH" "$name" "$T/$name.json" "$size" "$cache/$name-$size.gt" "$T/$name" "$md" "${V[@]}"
done
# GGX alone: the recipe at N 40, the default at the N it takes when the scene sets none (N 0:
# the scene's own) and at N 40
A=("recipe-N40|spec|spec-d4|0|40" "default|default|-|0|0|auto" "default-N40|default|-|0|40|auto")
for name in model-alone model-alone-sun model-alone-night model-alone-horizon pbr-alone pbr-alone-sun \
    pbr-alone-night pbr-alone-horizon; do
    front_rows "$SL" "$BENCH" "$name" "$T/$name.json" "$size" "$cache/$name-$size.gt" "$T/$name" "$md" "${A[@]}"
done
echo "lobe-sets: table in $md" >&2
