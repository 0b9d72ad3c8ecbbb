/* softlight/gbuffer_program.h - the contract between the G-buffer pass and a user's G-buffer
 * fragment program loaded at run time (`softlight render SCENE --gbuffer-shader my.c`): what the
 * program sees of each object's material (its constants and texture maps, under the uniform names
 * of shaders/gbuffer_textured.frag), the varyings of the vertex shader it runs behind, what it
 * writes (the G-buffer texel and the extra channels), and the ABI the shared object exports.
 *
 * The program replaces the G-buffer fragment program of every object of the scene; the vertex
 * shader stays softlight's textured one (shaders/gbuffer_textured.vert), and everything after the
 * G-buffer (lighting, tone map, outputs) stays as it is. A GLSL fragment shader with the same
 * names runs in softlight-gl (`softlight-gl render SCENE --gbuffer-shader my.frag`).
 * docs/gbuffer-programs.md describes the whole contract. */
#ifndef SOFTLIGHT_GBUFFER_PROGRAM_H
#define SOFTLIGHT_GBUFFER_PROGRAM_H

#include <softlight/gbuffer.h>
#include <softlight/program.h>
#include <softlight/texture.h>
#include <softlight/types.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The version of this contract. A program loaded at run time exports it as
 * sl_gbuffer_program_abi (SL_GBUFFER_PROGRAM below); softlight refuses any other value. */
#define SL_GBUFFER_ABI 1

/* uMaps bits: which map samplers are bound, and whether the material has an alpha cutoff. */
#define SL_GBUFFER_MAP_KD 1
#define SL_GBUFFER_MAP_KS 2
#define SL_GBUFFER_MAP_ALPHA 4
#define SL_GBUFFER_MAP_NORMAL 8
#define SL_GBUFFER_MAP_MASK 16
#define SL_GBUFFER_MAP_METALLIC_ROUGHNESS 32
#define SL_GBUFFER_MAP_OCCLUSION 64
#define SL_GBUFFER_MAP_EMISSIVE 128
#define SL_GBUFFER_MAP_CUTOFF 256

/* One object's material, read-only while drawing. The fields carry gbuffer_textured.frag's
 * uniform names, so a C program and its GLSL twin read the same words. An unbound sampler (its
 * uMaps bit clear) has no texture: sampling it returns (0, 0, 0, 1), as an incomplete GL
 * sampler does; the built-in program reads 1 in its place instead of sampling. */
typedef struct sl_gbuffer_material {
    sl_mat4 uModel;           /* object to world */
    sl_mat4 uViewProj;        /* world to clip */
    sl_mat3 uNormalMatrix;    /* transpose(inverse(mat3(uModel))) */
    sl_mat3 uModel3;          /* mat3(uModel) */
    sl_vec3 uKd, uKs;         /* the diffuse and specular colours (linear RGB) */
    float uAlpha;             /* the Phong exponent */
    float uRoughness;         /* a GGX material's roughness; -1 for a Phong material */
    float uMetallic;          /* >= 0: glTF metallic-roughness (uKd is the base colour); -1 otherwise */
    float uOcclusionStrength; /* occlusion = 1 + strength (occlusion_map.r - 1) */
    sl_vec3 uEmissive;        /* emission = uEmissive * emissive_map.rgb */
    sl_sampler2D uKdMap, uKsMap, uAlphaMap, uNormalMap, uMaskMap, uMetallicRoughnessMap, uOcclusionMap,
        uEmissiveMap;
    sl_vec4 uKdMapST, uKsMapST, uAlphaMapST, uNormalMapST, uMaskMapST, uMetallicRoughnessMapST, uOcclusionMapST,
        uEmissiveMapST;       /* a map reads uv * ST.xy + ST.zw */
    int uMaps;                /* SL_GBUFFER_MAP_* bits */
    float uAlphaCutoff;       /* with SL_GBUFFER_MAP_CUTOFF: the built-in discards coverage below it */
} sl_gbuffer_material;

/* The vertex shader's varyings (gbuffer_textured.vert), perspective-correct, in
 * sl_fragment_in.varyings in this order: 12 floats. */
typedef struct sl_gbuffer_varyings {
    sl_vec3 vWorldPos; /* world position */
    sl_vec3 vNormal;   /* world normal, interpolated (not unit length) */
    sl_vec2 vTexCoord; /* the mesh's texture coordinate; (0, 0) without one */
    sl_vec4 vTangent;  /* world tangent xyz and handedness w; (0, 0, 0, 0) without one */
} sl_gbuffer_varyings;
#define SL_GBUFFER_VARYING_COUNT 12

/* The fragment's varyings by name (exported by the library and by the softlight executable). */
SL_API sl_gbuffer_varyings sl_gbuffer_varyings_of(const sl_fragment_in *in);

/* The fragment program: reads the material and the fragment (its varyings, gl_FragCoord, the
 * derivative and discard built-ins through `in`), writes the texel's position, normal (unit),
 * kd, ks and alpha (the lobe: >= 0 Phong, <= -1 GGX, softlight/gbuffer.h) into *out, whose
 * fields start at 0 (depth is gl_FragCoord.z, set after it returns), and the extra channels into
 * *extra, which start as "none" (occlusion 1, emission 0) and reach the G-buffer only when the
 * scene has the extra plane. Called from every thread at once: it keeps no mutable state. */
typedef void (*sl_gbuffer_fragment_shader)(const sl_gbuffer_material *u, const sl_fragment_in *in,
                                           sl_gbuffer_texel *out, sl_gbuffer_extra *extra);

/* sl_gbuffer_fragment_program.flags */
#define SL_GBUFFER_DERIVATIVES 1u /* takes dFdx/dFdy/fwidth or calls texture(): runs in 2x2 quads */
#define SL_GBUFFER_DISCARDS 2u    /* may discard: its depth test runs after it */

typedef struct sl_gbuffer_fragment_program {
    const char *name;
    sl_gbuffer_fragment_shader fragment; /* required */
    unsigned flags;                      /* SL_GBUFFER_DERIVATIVES | SL_GBUFFER_DISCARDS, or 0 */
} sl_gbuffer_fragment_program;

/* ---- a program loaded at run time ----
 * The shared object exports two symbols: `int sl_gbuffer_program_abi` (= SL_GBUFFER_ABI) and
 * `sl_gbuffer_fragment_program sl_gbuffer_program_entry`. In a C source, one line writes both:
 *     SL_GBUFFER_PROGRAM("checker", checker_fragment, SL_GBUFFER_DERIVATIVES);                   */
#if defined(__GNUC__)
#define SL_GBUFFER_EXPORT __attribute__((visibility("default")))
#else
#define SL_GBUFFER_EXPORT
#endif
#define SL_GBUFFER_PROGRAM(name, fragment, flags)                                                                      \
    SL_GBUFFER_EXPORT extern const int sl_gbuffer_program_abi;                                                        \
    SL_GBUFFER_EXPORT extern const sl_gbuffer_fragment_program sl_gbuffer_program_entry;                              \
    const int sl_gbuffer_program_abi = SL_GBUFFER_ABI;                                                                \
    const sl_gbuffer_fragment_program sl_gbuffer_program_entry = {name, fragment, flags}

#ifdef __cplusplus
}
#endif

#endif
