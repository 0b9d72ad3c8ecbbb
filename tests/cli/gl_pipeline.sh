#!/usr/bin/env bash
# gl_pipeline.sh BUILD_DIR - the whole frame: `softlight render` against `softlight-gl render`.
#
# Both rasterize and shade on their own. Where their G-buffers describe different surfaces the
# shading is not comparable, so the comparison leaves out (softlight compare --edges) every pixel
# within 1 pixel of: a coverage difference, a depth difference above 1e-6, or a silhouette against
# the background (where the two rasterizers' attribute planes differ most; gl_raster.sh measures
# those). On the rest the tolerances of gl_shading.sh apply, since what remains is shading plus
# the last-bit differences in interpolated positions and normals.
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"

P99_TOL=0.05
OVER8_PERCENT=0.1
# scenes/pbr.json (a normal-mapped glTF model with mirror-like metal) needed a looser bound while
# the textured G-buffer's lambda drifted from llvmpipe's per quad (p99 rel 0.069, 0.21% > 8/255);
# with the same lambda it is within the common one (measured: p99 0.036, 0.038% > 8/255).
fail=0
for scene in scenes/*.json; do
    name=$(basename "$scene" .json)
    p99_tol=$P99_TOL over8=$OVER8_PERCENT
    mkdir -p "$T/$name/c" "$T/$name/g"
    "$SL" render "$scene" --size "$GL_TEST_SIZE" --aov "$T/$name/c" --pfm "$T/$name/c.pfm" >/dev/null
    "$GL" render "$scene" --size "$GL_TEST_SIZE" --aov "$T/$name/g" --pfm "$T/$name/g.pfm" >/dev/null
    status=0
    "$SL" compare "$T/$name/c.pfm" "$T/$name/g.pfm" --edges "$T/$name/c/depth.pfm,$T/$name/g/depth.pfm" \
        --metric p99rel --tolerance "$p99_tol" >"$T/$name.txt" || status=$?
    printf '%-10s compared %-6s of %-6s  p99 rel %-10s mean rel %-10s >1/255 %s%%  >8/255 %s%%\n' "$name" \
        "$(gl_field "pixels compared" "$T/$name.txt")" \
        "$(awk '/^size/ { split($2, s, "x"); print s[1] * s[2]; exit }' "$T/$name.txt")" \
        "$(gl_field "p99 rel error" "$T/$name.txt")" "$(gl_field "mean rel error" "$T/$name.txt")" \
        "$(gl_field "8-bit diff > 1" "$T/$name.txt")" "$(gl_field "8-bit diff > 8" "$T/$name.txt")"
    if [ "$status" != 0 ]; then
        echo "FAIL $name: $(grep -E '^(PASS|FAIL)' "$T/$name.txt")"
        grep '^worst' "$T/$name.txt" || true
        fail=1
    fi
    gl_check_share "$name" "$T/$name.txt" "$over8" || fail=1
done
if [ "$fail" != 0 ]; then
    echo "gl_pipeline: FAILED"
    exit 1
fi
echo "gl_pipeline: whole frames agree within p99 rel $P99_TOL away from edges, >8/255 on <= $OVER8_PERCENT% of pixels"
