#!/usr/bin/env bash
# uniforms_in_sync.sh BUILD_DIR - the lighting shader's uniform list is written in three places
# that must agree (docs/architecture.md "Adding a uniform"): shaders/lighting.frag declares it,
# sl_lighting_uniforms in src/shading/lighting.h holds it for the C port, and src/gl/lighting_pass.c
# uploads it for softlight-gl. This fails, naming the uniform, when one of them misses a name
# another has, and when the GLSL's array sizes, option values, shadow-map, reflection occlusion and
# lobe-map constants differ from the C constants.
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
gbuffer="uPosition uNormal uKd uKsAlpha uDepth uExtra uHasExtra uCone uHasCone uHasFacet"
# The shadow maps' samplers, layer tables and frames: the C struct holds the maps themselves
# (shadowMaps, envShadowMaps: src/shadow), softlight-gl draws its own (src/gl/shadow_pass.c) and
# binds them.
gbuffer="$gbuffer uShadowCubes uShadowCubeLayer uShadowSuns uShadowSunCount uShadowSunAxis uShadowSunRight"
gbuffer="$gbuffer uShadowSunUp uShadowSunBox uShadowSunDepth uEnvLightSun"
# The sky visibility maps likewise: the C struct holds them (skyMaps: src/shadow/sky.h).
gbuffer="$gbuffer uSkyMaps uSkyMapCount uSkyMapAxis uSkyMapRight uSkyMapUp uSkyMapBox uSkyMapDepth uSkyMapWeight"
gbuffer="$gbuffer uSkyCellSite uSkyCellSkySites uSkyCellAngle"
# The chains' kernel normalisations: the C struct's table holds them (uSplitSumLut's kernels).
gbuffer="$gbuffer uSplitSumKernelNorm"

for u in $glsl; do
    case " $gbuffer " in *" $u "*) ;; *) grep -qx "$u" <<<"$c" || fail "$u: in $frag, not a field of sl_lighting_uniforms ($hdr)";; esac
    grep -qx "$u" <<<"$host" || fail "$u: in $frag, never set by $gl"
done
for u in $c; do grep -qx "$u" <<<"$glsl" || fail "$u: a field of sl_lighting_uniforms, not a uniform of $frag"; done
for u in $host; do grep -qx "$u" <<<"$glsl" || fail "$u: set by $gl, not a uniform of $frag"; done

# Sizes and option values: GLSL `const int NAME = V;` against the C definitions.
glsl_const() { sed -n "s/^const int $1 = \([0-9]*\);.*/\1/p" "$frag"; }
c_value() { grep -rhoE "$1 *=? *\(?[0-9]+" src/core/options.h src/shading/lighting.h src/shading/brdf.h src/shading/splitsum_lut.h src/ibl/env_lights.h src/ibl/ibl.h src/shadow/shadow.h src/shadow/sky.h | head -1 | grep -oE '[0-9]+$'; }
check() { # check GLSL_NAME C_NAME
    local g v; g=$(glsl_const "$1"); v=$(c_value "$2")
    [ -n "$g" ] && [ "$g" = "$v" ] || fail "$1 = '${g}' in $frag, $2 = '${v}' in C"
}
check MAX_LIGHTS SL_LIGHTING_MAX_LIGHTS
check MAX_ENV_LIGHTS SL_ENV_LIGHTS_MAX
check TEXEL_SPLIT_CELLS_PER_WIDTH SL_TEXEL_SPLIT_CELLS_PER_WIDTH
check TEXEL_SPLIT_MAX SL_TEXEL_SPLIT_MAX
check ENV_LIGHT_NEAR_WIDTHS SL_ENV_LIGHT_NEAR_WIDTHS
g=$(sed -n 's/^const float TEXEL_SPLIT_MIN_NV = \([-+0-9.eE]*\);.*/\1/p' "$frag")
v=$(sed -n 's/^#define SL_TEXEL_SPLIT_MIN_NV \([-+0-9.eE]*\)$/\1/p' src/core/options.h)
[ -n "$g" ] && [ -n "$v" ] && awk -v a="$g" -v b="$v" 'BEGIN { exit !(a + 0 == b + 0) }' ||
    fail "TEXEL_SPLIT_MIN_NV = '${g}' in $frag, SL_TEXEL_SPLIT_MIN_NV = '${v}' in src/core/options.h"
for x in NONE SPEC SPEC_D4 GEMS PDF; do check "LOD_$x" "SL_LOD_$x"; done
check GTERM_INV_LH2 SL_GTERM_INV_LH2
check ESTIMATOR_CONSISTENT SL_ESTIMATOR_CONSISTENT
check ESTIMATOR_MICROFACET SL_ESTIMATOR_MICROFACET
check ESTIMATOR_SPLITSUM SL_ESTIMATOR_SPLITSUM
check ESTIMATOR_CV SL_ESTIMATOR_CV
check ESTIMATOR_CV_MIS SL_ESTIMATOR_CV_MIS
check SPLITSUM_LUT_SIZE SL_SPLITSUM_LUT_SIZE
check SPLITSUM_SETS SL_SPLITSUM_SETS
check SPLITSUM_LEVELS SL_PREFILTER_LEVELS
for x in PHONG_INV_LH2 PHONG_ONE GGX; do check "SPLITSUM_$x" "SL_SPLITSUM_$x"; done
for x in SH9 OCT DP; do check "IRRADIANCE_$x" "SL_IRRADIANCE_$x"; done
check ENV_LAYOUT_OCT SL_ENV_LAYOUT_OCT
check SHADOW_CUBE_SIZE SL_SHADOW_CUBE_SIZE
check SHADOW_GUARD SL_SHADOW_GUARD
check SHADOW_SUN_SIZE SL_SHADOW_SUN_SIZE
check SHADOW_SUN_MAX SL_SHADOW_SUN_MAX
check SKY_MAPS_MAX SL_SKY_MAPS_MAX
# The shadow lookup's float constants: GLSL `const float NAME = V;` against shadow.c's
# `#define NAME Vf`, compared as numbers.
for x in SHADOW_BIAS_CONST SHADOW_DEPTH_REL SHADOW_NORMAL_OFFSET; do
    g=$(sed -n "s/^const float $x = \([-+0-9.eE]*\);.*/\1/p" "$frag")
    v=$(sed -n "s/^#define $x \([-+0-9.eE]*\)f.*/\1/p" src/shadow/shadow.c)
    [ -n "$g" ] && [ -n "$v" ] && awk -v a="$g" -v b="$v" 'BEGIN { exit !(a + 0 == b + 0) }' ||
        fail "$x = '${g}' in $frag, '${v}' in src/shadow/shadow.c"
done
# The sky maps' lookup constants: GLSL against sky.c's `#define NAME Vf`.
for x in SKY_NORMAL_OFFSET SKY_BIAS_CONST; do
    g=$(sed -n "s/^const float $x = \([-+0-9.eE]*\);.*/\1/p" "$frag")
    v=$(sed -n "s/^#define $x \([-+0-9.eE]*\)f.*/\1/p" src/shadow/sky.c)
    [ -n "$g" ] && [ -n "$v" ] && awk -v a="$g" -v b="$v" 'BEGIN { exit !(a + 0 == b + 0) }' ||
        fail "$x = '${g}' in $frag, '${v}' in src/shadow/sky.c"
done
# The reflection occlusion's constants: GLSL `const int|float REFLECTION_X = V;` against
# src/occlusion/reflection.h's `#define SL_REFLECTION_X V[f]`.
for x in RAYS BLOCK STEPS RING THICKNESS OFFSET PLANE_EPS SAME_DEPTH SAME_NORMAL LONE; do
    g=$(sed -n "s/^const [a-z]* REFLECTION_$x = \([-+0-9.eE]*\);.*/\1/p" "$frag")
    v=$(sed -n "s/^#define SL_REFLECTION_$x \([-+0-9.eE]*\).*/\1/p" src/occlusion/reflection.h)
    [ -n "$g" ] && [ -n "$v" ] && awk -v a="$g" -v b="$v" 'BEGIN { exit !(a + 0 == b + 0) }' ||
        fail "REFLECTION_$x = '${g}' in $frag, SL_REFLECTION_$x = '${v}' in src/occlusion/reflection.h"
done
# A wide lobe's map: GLSL LOBE_MAP_SHARE against src/shading/lighting_internal.h's default.
g=$(sed -n 's/^const float LOBE_MAP_SHARE = \([0-9.]*\);.*/\1/p' "$frag")
v=$(sed -n 's/^#define SL_LOBE_MAP_SHARE \([0-9.]*\)f$/\1/p' src/shading/lighting_internal.h)
[ -n "$g" ] && [ -n "$v" ] && awk -v a="$g" -v b="$v" 'BEGIN { exit !(a + 0 == b + 0) }' ||
    fail "LOBE_MAP_SHARE = '${g}' in $frag, SL_LOBE_MAP_SHARE = '${v}' in src/shading/lighting_internal.h"
pairs=$(sed -n 's/^ *vec4 hammersley\[\([0-9]*\)\];/\1/p' "$frag")
max=$(c_value SL_HAMMERSLEY_MAX)
[ -n "$pairs" ] && [ $((pairs * 2)) = "$max" ] || fail "hammersley[$pairs] in $frag holds $((pairs * 2)) pairs, SL_HAMMERSLEY_MAX = $max"

# The textured G-buffer program: shaders/gbuffer_textured.vert + .frag, sl_gbuffer_tex_uniforms
# (src/raster/gbuffer_textured.h) and src/gl/gbuffer_pass.c (which also sets gbuffer.vert/.frag's,
# a subset of these names). trace/trace_ctx are C-only (softlight trace), not u-prefixed.
tvert=shaders/gbuffer_textured.vert tfrag=shaders/gbuffer_textured.frag thdr=src/raster/gbuffer_textured.h
tgl=src/gl/gbuffer_pass.c
tglsl=$(sed -n 's/^uniform [A-Za-z0-9_]* \(u[A-Z][A-Za-z0-9]*\).*/\1/p' "$tvert" "$tfrag" | sort -u)
tc=$(awk '/^typedef struct \{/{ body = "" } { body = body "\n" $0 } /^\} sl_gbuffer_tex_uniforms;/{ print body }' "$thdr" |
     sed 's,/\*.*\*/,,' | grep -o '\bu[A-Z][A-Za-z0-9]*\b' | sort -u)
thost=$(grep -o '"u[A-Z][A-Za-z0-9]*' "$tgl" | tr -d '"' | sort -u)
for u in $tglsl; do
    grep -qx "$u" <<<"$tc" || fail "$u: in $tvert/$tfrag, not a field of sl_gbuffer_tex_uniforms ($thdr)"
    grep -qx "$u" <<<"$thost" || fail "$u: in $tvert/$tfrag, never set by $tgl"
done
for u in $tc; do grep -qx "$u" <<<"$tglsl" || fail "$u: a field of sl_gbuffer_tex_uniforms, not a uniform of $tvert/$tfrag"; done
for u in $thost; do grep -qx "$u" <<<"$tglsl" || fail "$u: set by $tgl, not a uniform of $tvert/$tfrag"; done
# uMaps bits: GLSL's MAP_* = 1 << SL_MAP_* (scene.h's slot order), MAP_CUTOFF = 1 << SL_MAP_COUNT
slot=0
for x in KD KS ALPHA NORMAL MASK METALLIC_ROUGHNESS OCCLUSION EMISSIVE CUTOFF; do
    g=$(sed -n "s/^const int MAP_$x = \([0-9]*\);.*/\1/p" "$tfrag")
    [ "$g" = $((1 << slot)) ] || fail "MAP_$x = '$g' in $tfrag, expected $((1 << slot)) (SL_GBUFFER_MAP_$x)"
    slot=$((slot + 1))
done
tr -d ' \n' <src/scene/scene.h | grep -q 'SL_MAP_KD,SL_MAP_KS,SL_MAP_ALPHA,SL_MAP_NORMAL,SL_MAP_MASK,SL_MAP_METALLIC_ROUGHNESS,SL_MAP_OCCLUSION,SL_MAP_EMISSIVE,SL_MAP_COUNT' ||
    fail "sl_map_slot's order in src/scene/scene.h is not the one $tfrag's MAP_* bits assume"

n=$(wc -w <<<"$glsl")
nt=$(wc -w <<<"$tglsl")
[ "$fails" -eq 0 ] && echo "uniforms in sync: $n uniforms of $frag in sl_lighting_uniforms and $gl; constants agree;" \
    "$nt uniforms of $tvert/$tfrag in sl_gbuffer_tex_uniforms and $tgl"
[ "$fails" -eq 0 ]
