// gbuffer_textured.frag - the textured G-buffer pass's fragment shader (GLSL twin of
// sl_gbuffer_tex_frag in src/raster/gbuffer_textured.c, line for line): gbuffer.frag with
// texture maps. Each map multiplies the material's constant: kd = uKd * kd_map.rgb,
// ks = uKs * ks_map.rgb, alpha = uAlpha * alpha_map.r (a GGX material, uRoughness >= 0: the
// lobe parameter -1 - uRoughness * alpha_map.r, src/raster/gbuffer.h); normal_map perturbs the
// normal in tangent space as glTF does (+Y up); the fragment is discarded where mask_map.r
// (else kd_map.a) < uAlphaCutoff. Each map reads vTexCoord * ST.xy + ST.zw with texture()'s
// implicit level of detail. uMaps (uniform, so the branches are uniform control flow and the
// derivatives are defined) says which samplers are bound and whether to discard.
// Every map is sampled before the discard: derivatives after a discard are undefined.
// glTF's metallic-roughness per texel (uMetallic >= 0): kd so far is the base colour, m =
// uMetallic * mr.b, kd = base (1 - m), ks = mix(0.04, base, m), roughness times mr.g. oExtra
// (occlusion 1 + strength (occlusion_map.r - 1), emission uEmissive * emissive_map.rgb) goes to the
// fifth target, attached only for a scene that uses it (src/raster/gbuffer.h: the C program writes
// the extra plane directly, tagged with its depth).
#version 330 core

in vec3 vWorldPos;
in vec3 vNormal;
in vec2 vTexCoord;
in vec4 vTangent;

uniform vec3 uKd;
uniform vec3 uKs;
uniform float uAlpha;
uniform float uRoughness;
uniform sampler2D uKdMap;
uniform sampler2D uKsMap;
uniform sampler2D uAlphaMap;
uniform sampler2D uNormalMap;
uniform sampler2D uMaskMap;
uniform sampler2D uMetallicRoughnessMap;
uniform sampler2D uOcclusionMap;
uniform sampler2D uEmissiveMap;
uniform vec4 uKdMapST;
uniform vec4 uKsMapST;
uniform vec4 uAlphaMapST;
uniform vec4 uNormalMapST;
uniform vec4 uMaskMapST;
uniform vec4 uMetallicRoughnessMapST;
uniform vec4 uOcclusionMapST;
uniform vec4 uEmissiveMapST;
uniform float uMetallic;
uniform float uOcclusionStrength;
uniform vec3 uEmissive;
uniform int uMaps;
uniform float uAlphaCutoff;

// uMaps bits: SL_GBUFFER_MAP_* (src/raster/gbuffer_textured.h), 1 << sl_map_slot (scene.h)
const int MAP_KD = 1;
const int MAP_KS = 2;
const int MAP_ALPHA = 4;
const int MAP_NORMAL = 8;
const int MAP_MASK = 16;
const int MAP_METALLIC_ROUGHNESS = 32;
const int MAP_OCCLUSION = 64;
const int MAP_EMISSIVE = 128;
const int MAP_CUTOFF = 256;

layout(location = 0) out vec4 oPosition;
layout(location = 1) out vec4 oNormal;
layout(location = 2) out vec4 oKd;
layout(location = 3) out vec4 oKsAlpha;
layout(location = 4) out vec4 oExtra;

vec2 map_uv(vec2 uv, vec4 st) { return vec2(uv.x * st.x + st.z, uv.y * st.y + st.w); }

// The facet normal, as gbuffer.frag's facet_code: the triangle's plane (dFdx and dFdy of the
// position lie in it; their cross product faces the viewer), octahedral-encoded into the normal's
// and Kd's spare .w channels, (2, 2) where the derivatives span no plane.
vec2 facet_code(vec3 dx, vec3 dy)
{
    vec3 f = cross(dx, dy);
    float l1 = abs(f.x) + abs(f.y) + abs(f.z);
    if (!(l1 > 0.0))
        return vec2(2.0);
    vec2 p = f.xy / l1;
    if (f.z < 0.0)
        p = (1.0 - abs(p.yx)) * vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
    return p;
}

void main()
{
    vec2 facet = facet_code(dFdx(vWorldPos), dFdy(vWorldPos)); // before the discard, as the maps
    vec4 kd = vec4(1.0), ks = vec4(1.0), gloss = vec4(1.0), mask = vec4(1.0);
    vec4 nt = vec4(0.5, 0.5, 1.0, 1.0);
    vec4 mr = vec4(1.0), occ = vec4(1.0), em = vec4(1.0);
    if ((uMaps & MAP_KD) != 0)
        kd = texture(uKdMap, map_uv(vTexCoord, uKdMapST));
    if ((uMaps & MAP_KS) != 0)
        ks = texture(uKsMap, map_uv(vTexCoord, uKsMapST));
    if ((uMaps & MAP_ALPHA) != 0)
        gloss = texture(uAlphaMap, map_uv(vTexCoord, uAlphaMapST));
    if ((uMaps & MAP_NORMAL) != 0)
        nt = texture(uNormalMap, map_uv(vTexCoord, uNormalMapST));
    if ((uMaps & MAP_MASK) != 0)
        mask = texture(uMaskMap, map_uv(vTexCoord, uMaskMapST));
    if ((uMaps & MAP_METALLIC_ROUGHNESS) != 0)
        mr = texture(uMetallicRoughnessMap, map_uv(vTexCoord, uMetallicRoughnessMapST));
    if ((uMaps & MAP_OCCLUSION) != 0)
        occ = texture(uOcclusionMap, map_uv(vTexCoord, uOcclusionMapST));
    if ((uMaps & MAP_EMISSIVE) != 0)
        em = texture(uEmissiveMap, map_uv(vTexCoord, uEmissiveMapST));

    if ((uMaps & MAP_CUTOFF) != 0) {
        float coverage = (uMaps & MAP_MASK) != 0 ? mask.x : kd.w;
        if (coverage < uAlphaCutoff)
            discard;
    }
    vec3 n = dot(vNormal, vNormal) > 1e-30 ? normalize(vNormal) : vec3(0.0, 0.0, 1.0);
    vec3 t = vTangent.xyz;
    if ((uMaps & MAP_NORMAL) != 0 && dot(t, t) > 1e-30) {
        t = normalize(t);
        vec3 b = cross(n, t) * vTangent.w;
        vec3 m = vec3(nt.x * 2.0 - 1.0, nt.y * 2.0 - 1.0, nt.z * 2.0 - 1.0);
        vec3 p = t * m.x + b * m.y + n * m.z;
        n = dot(p, p) > 1e-30 ? normalize(p) : n;
    }
    oPosition = vec4(vWorldPos, 1.0);
    oNormal = vec4(n, facet.x);
    oKd = vec4(uKd * kd.rgb, facet.y);
    oKsAlpha = vec4(uKs * ks.rgb, uRoughness >= 0.0 ? -1.0 - uRoughness * gloss.x : uAlpha * gloss.x);
    if (uMetallic >= 0.0) {
        vec3 base = oKd.rgb;
        float metal = uMetallic * mr.z;
        oKd = vec4(base * (1.0 - metal), facet.y);
        oKsAlpha = vec4(vec3(0.04) + (base - vec3(0.04)) * metal, -1.0 - uRoughness * gloss.x * mr.y);
    }
    oExtra = vec4(1.0 + uOcclusionStrength * (occ.x - 1.0), uEmissive * em.rgb);
}
