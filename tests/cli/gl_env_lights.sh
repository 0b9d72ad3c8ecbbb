#!/usr/bin/env bash
# gl_env_lights.sh BUILD_DIR - env lights (--env-lights K) through both shaders and the CLI.
#
# The scenes with a few very bright texels (city-sun: a sun; top-down: a lamp on a near-mirror)
# with the configuration of the accuracy measurements (--estimator mf --lod pdf --distortion,
# N = 16) and --env-lights 32: softlight renders and writes its G-buffer (--aov), softlight-gl
# lights that very G-buffer (--gbuffer), as in gl_shading.sh, so what is compared is
# lighting.frag's specular_env_lights and uEnvResidual against the C port (lighting.c) with the
# same uniforms. Tolerances are gl_shading.sh's (p99 rel <= 0.05, >8/255 on <= 0.1% of pixels),
# and, as the exact part shows in few pixels, the worst pixel within 2% of its value (below).
# Then the feature must be wired: GL's image with --env-lights must differ from GL's without
# (else uEnvLightCount or uEnvResidual never reached the shader), the C one too, and
# `softlight trace --env-lights 8` must print the env lights' part of the specular.
# CTest label: release-only
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/cli/gl_common.bash
gl_setup "$1"

SIZE=160x90
P99_TOL=0.05
OVER8_PERCENT=0.1
WORST_TOL=0.02
OPTS=(--estimator mf --lod pdf --distortion -n 16)
fail=0
for name in city-sun top-down; do
    mkdir -p "$T/$name" "$T/$name-off"
    "$SL" render "scenes/$name.json" --size "$SIZE" "${OPTS[@]}" --env-lights 32 --aov "$T/$name" \
        --pfm "$T/$name/c.pfm" -q
    "$GL" render "scenes/$name.json" "${OPTS[@]}" --env-lights 32 --gbuffer "$T/$name" --pfm "$T/$name/g.pfm" >/dev/null
    status=0
    "$SL" compare "$T/$name/c.pfm" "$T/$name/g.pfm" --metric p99rel --tolerance "$P99_TOL" >"$T/$name.txt" || status=$?
    printf '%-9s env lights 32: p99 rel %-10s mean rel %-10s >8/255 %s%%\n' "$name" \
        "$(gl_field "p99 rel error" "$T/$name.txt")" "$(gl_field "mean rel error" "$T/$name.txt")" \
        "$(gl_field "8-bit diff > 8" "$T/$name.txt")"
    if [ "$status" != 0 ]; then
        echo "FAIL $name: softlight-gl against softlight with --env-lights 32: $(grep -E '^(PASS|FAIL)' "$T/$name.txt")"
        grep '^worst' "$T/$name.txt" || true
        fail=1
    fi
    gl_check_share "$name" "$T/$name.txt" "$OVER8_PERCENT" || fail=1
    # The exact part lives in few pixels (the sun's glint, the lamp in the mirror), which p99
    # does not see: bound the worst pixel's error relative to its value. Measured: 1.4e-4
    # (city-sun, the glint at 63) and 4.5e-3 (top-down: the lamp at 81, mostly its sampled
    # remainder); the exact part off by 3% in the GLSL gives 2.6% on city-sun.
    worst=$(grep -m1 '^worst 1 ' "$T/$name.txt" || true)
    werr=$(sed -E 's/.* error ([^ ]+) .*/\1/' <<<"$worst")
    wval=$(sed -E 's/.* A \(([^)]*)\).*/\1/' <<<"$worst" | tr -d ',')
    wrel=$(awk -v e="$werr" -v a="$wval" 'BEGIN { n = split(a, v, " "); m = 1e-3
        for (i = 1; i <= n; i++) if (v[i] + 0 > m) m = v[i] + 0
        print e / m }')
    echo "          worst pixel: error $werr at value ($wval): relative $wrel"
    if ! awk -v r="$wrel" -v t="$WORST_TOL" 'BEGIN { exit !(r <= t) }'; then
        echo "FAIL $name: worst pixel off by $wrel relative (allowed $WORST_TOL): $worst"
        fail=1
    fi

    # wired: without env lights both images change (the lamp/sun is sampled, not summed)
    "$SL" render "scenes/$name.json" --size "$SIZE" "${OPTS[@]}" --pfm "$T/$name-off/c.pfm" -q
    "$GL" render "scenes/$name.json" "${OPTS[@]}" --gbuffer "$T/$name" --pfm "$T/$name-off/g.pfm" >/dev/null
    for side in c g; do
        if "$SL" compare "$T/$name/$side.pfm" "$T/$name-off/$side.pfm" --metric p99rel --tolerance 1e-3 >/dev/null; then
            echo "FAIL $name: $([ $side = c ] && echo softlight || echo softlight-gl) with --env-lights 32 equals its image without"
            fail=1
        fi
    done
done

# trace: the env lights' line, with the count. Pixel 95,43 (at 160x90) is on the mirror sphere
# where it reflects the lamp: the lamp spans more than 8 texels, and there the 8 brightest
# contribute ~0 (their lobe misses them) while 32 of them contribute 5.5 of the specular's 81
# (measured): the part must be there and substantial.
PIX=95,43
"$SL" trace scenes/top-down.json --size "$SIZE" --pixel $PIX --env-lights 8 "${OPTS[@]}" >"$T/trace.txt"
if ! grep -Eq '^ *env lights +\(.*\): the exact part from 8 env lights' "$T/trace.txt"; then
    echo "FAIL trace: no 'env lights ... from 8 env lights' line in softlight trace --env-lights 8:"
    grep -iE 'env|specular' "$T/trace.txt" || head -20 "$T/trace.txt"
    fail=1
fi
"$SL" trace scenes/top-down.json --size "$SIZE" --pixel $PIX --env-lights 32 "${OPTS[@]}" >"$T/trace32.txt"
part=$(awk '/^ *env lights +\(/ { sub(/^[^(]*\(/, ""); sub(/,.*/, ""); print $1 + 0; exit }' "$T/trace32.txt")
echo "trace $PIX: env lights' part (red) with 32 lights: ${part:-none}"
if ! awk -v p="${part:-0}" 'BEGIN { exit !(p > 0.5) }'; then
    echo "FAIL trace: the env lights' part at $PIX with --env-lights 32 is ${part:-missing}, expected > 0.5 (measured 5.5)"
    grep -E '^ *(specular|env lights)' "$T/trace32.txt" || true
    fail=1
fi
if "$SL" trace scenes/top-down.json --size "$SIZE" --pixel $PIX "${OPTS[@]}" | grep 'env lights' >/dev/null; then
    echo "FAIL trace: an 'env lights' line without --env-lights"
    fail=1
fi
# out of range: a usage error, not a render
if "$SL" render scenes/top-down.json --size 8x8 --env-lights 65 --pfm "$T/bad.pfm" -q 2>"$T/bad.txt"; then
    echo "FAIL: --env-lights 65 was accepted"
    fail=1
fi

if [ "$fail" != 0 ]; then
    echo "gl_env_lights: FAILED"
    exit 1
fi
echo "gl_env_lights: GL and C agree with --env-lights 32 (p99 rel <= $P99_TOL), the feature changes both images, trace reports it"
