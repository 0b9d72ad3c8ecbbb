#!/usr/bin/env bash
# truth.sh BUILD_DIR - `softlight truth`: the ground-truth image, its cache, and that it agrees
# with what the renderer computes where the renderer is nearly exact.
#
# The diffuse term with the brute-force irradiance map is within a few percent of the exact
# integral everywhere (docs/ibl.md, docs/accuracy.md: p99 relative error about 0.03 on the
# shipped scenes), so the truth's diffuse part must match `render --diffuse-only --irradiance
# brute` to p99 < 0.1 over the covered pixels; a flipped row order, a wrong rotation or a
# wrong eye would be far outside that. A tiny size keeps the brute-force integral under a
# second (about 5.6 ms per covered pixel).
set -euo pipefail
cd "$(dirname "$0")/../.."
SL="$1/softlight"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
SIZE=32x18
scene=scenes/default.json

"$SL" truth "$scene" --size $SIZE --cache "$T/t.gt" --pfm "$T/t.pfm" --parts "$T/p" >"$T/1.txt"
grep -q "integrated" "$T/1.txt" || { echo "FAIL: first run did not integrate"; cat "$T/1.txt"; exit 1; }
"$SL" truth "$scene" --size $SIZE --cache "$T/t.gt" --pfm "$T/t2.pfm" >"$T/2.txt"
grep -q "read from the cache" "$T/2.txt" || { echo "FAIL: second run did not use the cache"; cat "$T/2.txt"; exit 1; }
cmp -s "$T/t.pfm" "$T/t2.pfm" || { echo "FAIL: the cached truth differs from the computed one"; exit 1; }
head -c 200 "$T/t.gt" | grep "^size 32 18" >/dev/null || { echo "FAIL: cache header"; head -c 300 "$T/t.gt"; exit 1; }

# another size is another G-buffer: recomputed, not read
"$SL" truth "$scene" --size 16x9 --cache "$T/t.gt" >"$T/3.txt"
grep -q "integrated" "$T/3.txt" || { echo "FAIL: a stale cache was used"; cat "$T/3.txt"; exit 1; }

# the diffuse part against the renderer's near-exact diffuse
"$SL" render "$scene" --size $SIZE --diffuse-only --irradiance brute --pfm "$T/d.pfm" -q
"$SL" compare "$T/d.pfm" "$T/p/diffuse.pfm" --mask "$T/p/mask.pfm" --metric p99rel --tolerance 0.1 >"$T/c.txt" || {
    echo "FAIL: diffuse truth against render --diffuse-only --irradiance brute"; cat "$T/c.txt"; exit 1; }

# --compare prints the figures for a whole frame (image-based light only)
"$SL" render "$scene" --size $SIZE --no-lights --pfm "$T/r.pfm" -q
"$SL" truth "$scene" --size $SIZE --cache "$T/t.gt" --compare "$T/r.pfm" >"$T/4.txt"
grep -q "against the truth" "$T/4.txt" || { echo "FAIL: --compare printed nothing"; cat "$T/4.txt"; exit 1; }

# --part: one part instead of the sum, the same bits as --parts writes; --compare on it gives an
# nrmse, and with env lights on a small sun-less map the specular error must not grow (the
# extraction only moves texels from the sampled map to the exact sum)
"$SL" truth "$scene" --size $SIZE --cache "$T/t.gt" --part specular --pfm "$T/s.pfm" >/dev/null
cmp -s "$T/s.pfm" "$T/p/specular.pfm" || { echo "FAIL: --part specular differs from --parts' specular.pfm"; exit 1; }
"$SL" render "$scene" --size $SIZE --specular-only --estimator mf --lod pdf --distortion -n 32 --pfm "$T/s0.pfm" -q
"$SL" render "$scene" --size $SIZE --specular-only --estimator mf --lod pdf --distortion -n 32 --env-lights 32 \
    --pfm "$T/s1.pfm" -q
n0=$("$SL" truth "$scene" --size $SIZE --cache "$T/t.gt" --part specular --compare "$T/s0.pfm" | grep -o 'nrmse [0-9.]*' | cut -d' ' -f2)
n1=$("$SL" truth "$scene" --size $SIZE --cache "$T/t.gt" --part specular --compare "$T/s1.pfm" | grep -o 'nrmse [0-9.]*' | cut -d' ' -f2)
[ -n "$n0" ] && [ -n "$n1" ] || { echo "FAIL: --compare printed no nrmse"; exit 1; }
awk -v a="$n0" -v b="$n1" 'BEGIN { exit !(a > 0 && a < 0.5 && b <= a * 1.05) }' || {
    echo "FAIL: specular nrmse without env lights $n0, with $n1 (expected below 0.5 and no worse with them)"; exit 1; }

# errors: one line, status 2
status=0
"$SL" truth scenes/no-such-scene.json 2>"$T/e.txt" || status=$?
[ "$status" = 2 ] && [ "$(wc -l <"$T/e.txt")" = 1 ] || { echo "FAIL: missing scene gave status $status"; cat "$T/e.txt"; exit 1; }
echo "truth: PASS ($(grep -o '[0-9.]* ms per covered pixel' "$T/1.txt" || echo cached))"
