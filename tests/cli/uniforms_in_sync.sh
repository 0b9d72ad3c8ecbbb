#!/usr/bin/env bash
# uniforms_in_sync.sh BUILD_DIR - the lighting shader's uniform list is written in three places
# that must agree (docs/architecture.md "Adding a uniform"): shaders/lighting.frag declares it,
# sl_lighting_uniforms in src/shading/lighting.h holds it for the C port, and src/gl/lighting_pass.c
# uploads it for softlight-gl. This fails, naming the uniform, when one of them misses a name
# another has, and when the GLSL's array sizes and option values differ from the C constants.
set -u
cd "$(dirname "$0")/../.." || exit 2
frag=shaders/lighting.frag hdr=src/shading/lighting.h gl=src/gl/lighting_pass.c
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }

# GLSL: `uniform TYPE uName[...];` and the block's instance name (`} uHammersley;`)
glsl=$( { sed -n 's/^uniform [A-Za-z0-9_]* \(u[A-Z][A-Za-z0-9]*\).*/\1/p' "$frag"
          sed -n 's/^} *\(u[A-Z][A-Za-z0-9]*\);/\1/p' "$frag"; } | sort -u)
# C: the u-prefixed fields of sl_lighting_uniforms. The G-buffer samplers are the sl_gbuffer the
# pass takes, and the irradiance map is inside uIrradiance (sl_irradiance holds SH9 or the map).
c=$(awk '/^typedef struct \{/{ body = "" } { body = body "\n" $0 } /^\} sl_lighting_uniforms;/{ print body }' "$hdr" |
    grep -o '\bu[A-Z][A-Za-z0-9]*\b' | sed 's/^uIrradiance$/uIrradianceMap/' | sort -u)
# GL host: every "uName" string it looks up, and the block by its block name
host=$( { grep -o '"u[A-Z][A-Za-z0-9]*' "$gl" | tr -d '"'
          grep -q '"HammersleyBlock"' "$gl" && echo uHammersley; } | sort -u)
gbuffer="uPosition uNormal uKd uKsAlpha uDepth"

for u in $glsl; do
    case " $gbuffer " in *" $u "*) ;; *) grep -qx "$u" <<<"$c" || fail "$u: in $frag, not a field of sl_lighting_uniforms ($hdr)";; esac
    grep -qx "$u" <<<"$host" || fail "$u: in $frag, never set by $gl"
done
for u in $c; do grep -qx "$u" <<<"$glsl" || fail "$u: a field of sl_lighting_uniforms, not a uniform of $frag"; done
for u in $host; do grep -qx "$u" <<<"$glsl" || fail "$u: set by $gl, not a uniform of $frag"; done

# Sizes and option values: GLSL `const int NAME = V;` against the C definitions.
glsl_const() { sed -n "s/^const int $1 = \([0-9]*\);.*/\1/p" "$frag"; }
c_value() { grep -rhoE "$1 *=? *\(?[0-9]+" src/core/options.h src/shading/lighting.h src/shading/brdf.h src/ibl/env_lights.h src/ibl/ibl.h | head -1 | grep -oE '[0-9]+$'; }
check() { # check GLSL_NAME C_NAME
    local g v; g=$(glsl_const "$1"); v=$(c_value "$2")
    [ -n "$g" ] && [ "$g" = "$v" ] || fail "$1 = '${g}' in $frag, $2 = '${v}' in C"
}
check MAX_LIGHTS SL_LIGHTING_MAX_LIGHTS
check MAX_ENV_LIGHTS SL_ENV_LIGHTS_MAX
for x in NONE SPEC SPEC_D4 GEMS PDF; do check "LOD_$x" "SL_LOD_$x"; done
check GTERM_INV_LH2 SL_GTERM_INV_LH2
check ESTIMATOR_CONSISTENT SL_ESTIMATOR_CONSISTENT
check ESTIMATOR_MICROFACET SL_ESTIMATOR_MICROFACET
for x in SH9 OCT DP; do check "IRRADIANCE_$x" "SL_IRRADIANCE_$x"; done
check ENV_LAYOUT_OCT SL_ENV_LAYOUT_OCT
pairs=$(sed -n 's/^ *vec4 hammersley\[\([0-9]*\)\];/\1/p' "$frag")
max=$(c_value SL_HAMMERSLEY_MAX)
[ -n "$pairs" ] && [ $((pairs * 2)) = "$max" ] || fail "hammersley[$pairs] in $frag holds $((pairs * 2)) pairs, SL_HAMMERSLEY_MAX = $max"

n=$(wc -w <<<"$glsl")
[ "$fails" -eq 0 ] && echo "uniforms in sync: $n uniforms of $frag in sl_lighting_uniforms and $gl; constants agree"
[ "$fails" -eq 0 ]
