#!/usr/bin/env bash
# shadows.sh BUILD_DIR - point lights' cube shadow maps (--shadows, a light's "shadow" key;
# docs/lighting.md "Shadow maps") on small scenes lit by one point light alone (no environment):
# off, nothing changes; a light inside a closed box lights nothing outside it; a plane facing the
# light, and one it grazes, stay fully lit (no acne); the shadows of a slab and of a wall 0.02
# thick fall where the visibility-aware truth (`softlight truth --visibility --lights`, Embree)
# puts them, in the default path, the port (--plain) and the split sum; `softlight trace` prints
# each light's visibility; bad keys are one line and exit 2. Without Embree the truth
# comparisons are left out. softlight-gl's maps against these: tests/cli/gl_shadows.sh.
set -u
. "$(dirname "$0")/lib.bash"
cli_init shadows "$1"
S=160x90

. "$(dirname "$0")/shadow_scene.bash" # shadow_scene NAME LIGHT_Z OBJECTS...
same() { # same NAME A.pfm B.pfm WHAT
    cmp -s "$2" "$3" && ok "$1: $4" || bad "$1: not $4"
}

# off: a scene with no point light draws no map and changes nothing
"$SL" render scenes/default.json --size $S -q --pfm "$T/d0.pfm"
"$SL" render scenes/default.json --size $S -q --shadows --pfm "$T/d1.pfm"
same "no point light" "$T/d0.pfm" "$T/d1.pfm" "--shadows gives the same bytes"

# a light inside a closed box floating over the floor: nothing outside it is lit
shadow_scene box 1.0 '{"shape": "box", "material": "m", "transform": {"translate": [0, -0.3, 1], "scale": 0.4}}'
"$SL" render "$T/box.json" --size $S -q --shadows --pfm "$T/box-s.pfm"
"$SL" render "$T/box.json" --size $S -q --no-lights --pfm "$T/box-n.pfm"
"$SL" render "$T/box.json" --size $S -q --pfm "$T/box-b.pfm"
same "light in a box" "$T/box-s.pfm" "$T/box-n.pfm" "the image is the one without lights"
cmp -s "$T/box-b.pfm" "$T/box-n.pfm" && bad "light in a box: without shadows the light shines through (test is void)"
# the same with the light's own key instead of the flag
sed 's/"intensity": 4}/"intensity": 4, "shadow": true}/' "$T/box.json" >"$T/box-key.json"
"$SL" render "$T/box-key.json" --size $S -q --pfm "$T/box-k.pfm"
same "light in a box, \"shadow\": true" "$T/box-k.pfm" "$T/box-n.pfm" "the image is the one without lights"

# no acne: a plane under the light, lit head-on and at grazing angles, stays fully lit
for z in 2 0.02; do
    shadow_scene "plane$z" "$z"
    "$SL" render "$T/plane$z.json" --size $S -q --shadows --pfm "$T/p-s.pfm"
    "$SL" render "$T/plane$z.json" --size $S -q --pfm "$T/p-b.pfm"
    same "plane, light at height $z" "$T/p-s.pfm" "$T/p-b.pfm" "fully lit: the same bytes as without shadows"
done

# bad input: one line, exit 2
sed 's/"intensity": 4}/"intensity": 4, "shadow": 1}/' "$T/box.json" >"$T/bad.json"
expect_error "shadow not a boolean" "lights\[0\]\.shadow: expected true or false" -- "$SL" render "$T/bad.json" --size $S -o "$T/x.png"

# trace: each light's visibility, 0 in the slab's shadow and 1 in the open (no line without maps)
shadow_scene occ 2 '{"shape": "box", "material": "m", "transform": {"translate": [0.2, 0.1, 0.8], "scale": [0.3, 0.3, 0.05]}}' \
    '{"shape": "box", "material": "m", "transform": {"translate": [-0.8, 0.6, 0.4], "scale": [0.5, 0.01, 0.4]}}'
for pair in "78,39 0" "80,60 1"; do
    read -r px want <<<"$pair"
    line=$("$SL" trace "$T/occ.json" --size $S --shadows --pixel "$px" | grep "light 0 ")
    [ "${line##*visibility }" = "$want" ] && ok "trace at $px: $line" || bad "trace at $px: '$line', want visibility $want"
done
"$SL" trace "$T/occ.json" --size $S --pixel 80,60 | grep -q "visibility" && bad "trace without --shadows prints a visibility"

# against the visibility-aware truth: a slab over the floor and a wall 0.02 thick
if ! "$SL" truth "$T/box.json" --size 2x2 --visibility --lights --pfm "$T/probe.pfm" >/dev/null 2>&1; then
    cli_done "shadows (a build without Embree: no truth comparisons)"
    exit
fi
"$SL" truth "$T/occ.json" --size $S --visibility --lights --pfm "$T/t.pfm" >/dev/null 2>&1
"$SL" render "$T/occ.json" --size $S -q --pfm "$T/b.pfm"
for mode in "" "--plain" "--estimator splitsum"; do
    # shellcheck disable=SC2086
    "$SL" render "$T/occ.json" --size $S -q --shadows $mode --pfm "$T/s.pfm"
    python3 - "$T/t.pfm" "$T/s.pfm" "$T/b.pfm" >"$T/cmp.txt" <<'PY' && ok "${mode:-default path}: $(cat "$T/cmp.txt")" || bad "${mode:-default path}: $(cat "$T/cmp.txt")"
import struct, sys
def pfm(path):
    with open(path, 'rb') as f:
        kind = f.readline().strip(); w, h = map(int, f.readline().split()); scale = float(f.readline())
        n = w * h * (3 if kind == b'PF' else 1)
        return w, h, struct.unpack(('<' if scale < 0 else '>') + 'f' * n, f.read(4 * n))[1::3]  # green
w, h, t = pfm(sys.argv[1]); _, _, s = pfm(sys.argv[2]); _, _, b = pfm(sys.argv[3])
lit = [i for i in range(w * h) if b[i] > 1e-4]
shadowed = lambda img, i: img[i] < 0.5 * b[i]
in_truth = sum(shadowed(t, i) for i in lit)
disagree = sum(shadowed(t, i) != shadowed(s, i) for i in lit)
l1 = sum(abs(t[i] - s[i]) for i in lit) / sum(t[i] for i in lit)
l1_blind = sum(abs(t[i] - b[i]) for i in lit) / sum(t[i] for i in lit)
msg = (f"{in_truth} of {len(lit)} pixels in the truth's shadows, {disagree} classified otherwise; "
       f"relative L1 {l1:.4f} (without shadows {l1_blind:.4f})")
print(msg)
# the shadows are there (slab and wall), they fall where the truth's do up to their one-texel
# edges, and they remove nearly all of the error of ignoring them
sys.exit(0 if in_truth > 200 and disagree <= 0.02 * in_truth and l1 < 0.05 * l1_blind else 1)
PY
done
cli_done shadows
