/* softlight/lighting.h - the contract between the deferred lighting stage and a lighting
 * program: what a program sees for one G-buffer texel (or a span of them), the frame's uniforms
 * as a plain struct, the lighting resources it reads through the toolbox below, and the ABI a
 * program loaded at run time (`softlight render SCENE --lighting my.c`) exports.
 *
 * softlight's own shading (the C port of shaders/lighting.frag, its batched and split-sum fast
 * paths) is one such program: sl_lighting_builtin(). A user's program replaces it for a frame;
 * rasterization and the G-buffer stay the same.
 *
 * The toolbox functions (sl_lighting_*) are the built-in shader's own pieces: the environment's
 * textureLod and background, the irradiance lookup, the Hammersley block, D, G and F of both BRDF
 * sets, the env lights and the point lights. A C source that wants them spelled as
 * lighting.frag spells them (irradiance(res, N), sl_lobe_D, point_light ...) defines
 * SL_GLSL_LIGHTING before including <softlight/glsl.h>. docs/lighting-programs.md describes
 * the whole contract. */
#ifndef SOFTLIGHT_LIGHTING_H
#define SOFTLIGHT_LIGHTING_H

#include <stdint.h>

#include <softlight/gbuffer.h>
#include <softlight/types.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The version of this contract. A program loaded at run time exports it as
 * sl_lighting_program_abi (SL_LIGHTING_PROGRAM below); softlight refuses any other value. */
#define SL_LIGHTING_ABI 1

#define SL_LIGHTING_MAX_POINT_LIGHTS 16 /* light_position[] and its siblings */

/* The frame's uniforms (lighting.frag's names in the comments), read-only while shading.
 * Directions named "environment space" are world directions times env_rotation. */
typedef struct sl_lighting_frame_uniforms {
    sl_vec3 eye;             /* uEye: the world-space eye */
    sl_mat4 inv_view_proj;   /* uInvViewProj: inverse(projection * view) */
    sl_vec2 viewport;        /* uViewport: the G-buffer's width and height */
    sl_mat3 env_rotation;    /* uEnvRotation: world to environment space */
    float env_intensity;     /* uEnvIntensity: multiplies every environment value */
    float env_max_lod;       /* uEnvMaxLod: the environment chain's last level */
    int samples;             /* uHammersley.N: the sample count the frame asks for */
    int rotate;              /* uRotate: 1 = rotate the Hammersley set per pixel and frame */
    uint32_t frame;          /* uFrame: the frame number hashed into that rotation */
    int diffuse, specular, point_lights; /* uDiffuse, uSpecular, uPointLights: 0 or 1 */
    int gterm;               /* uGTerm: the Phong set's G, 1 = 1/(L.H)^2, 2 = 1 */
    int light_count;         /* uLightCount: 0 .. SL_LIGHTING_MAX_POINT_LIGHTS */
    sl_vec3 light_position[SL_LIGHTING_MAX_POINT_LIGHTS]; /* uLightPosition: world space */
    sl_vec3 light_color[SL_LIGHTING_MAX_POINT_LIGHTS];    /* uLightColor: linear RGB */
    float light_intensity[SL_LIGHTING_MAX_POINT_LIGHTS];  /* uLightIntensity: radiant intensity */
    int env_light_count;     /* uEnvLightCount: the environment's brightest texels summed exactly */
} sl_lighting_frame_uniforms;

/* The lighting resources of the frame (the environment's chains, the irradiance, the Hammersley
 * block, the env lights) and the calling thread's scratch: opaque, read through the toolbox. */
typedef struct sl_lighting_resources sl_lighting_resources;

/* One texel: what the per-texel form sees. */
typedef struct sl_lighting_texel_in {
    const sl_gbuffer_texel *texel; /* depth >= 1: nothing drawn there (the background) */
    sl_gbuffer_extra extra;        /* occlusion 1 and emission 0 when the G-buffer has no extra plane */
    int x, y;                      /* the pixel, row 0 = bottom: gl_FragCoord.xy = (x + 0.5, y + 0.5) */
} sl_lighting_texel_in;

/* A span: pixels x0 .. x0 + count - 1 of G-buffer row y, what the span form sees. */
typedef struct sl_lighting_span {
    int x0, y, count;                /* row 0 = bottom; count >= 1, up to the G-buffer's width */
    const sl_gbuffer_texel *texels;  /* texels[i]: pixel x0 + i */
    const sl_gbuffer_extra *extra;   /* extra[i], or NULL when the G-buffer has no extra plane */
} sl_lighting_span;

/* Per-texel form: the linear radiance of one texel (the background's too). */
typedef sl_vec3 (*sl_lighting_texel_shader)(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *res,
                                            const sl_lighting_texel_in *in);
/* Optional span form, for vector loops: out[i] must be what the per-texel form returns for
 * pixel x0 + i, bit for bit (the pass uses this form, a trace the per-texel one). */
typedef void (*sl_lighting_span_shader)(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *res,
                                        const sl_lighting_span *span, sl_vec3 *out);

typedef struct sl_lighting_program {
    const char *name;                   /* for messages; may be NULL */
    sl_lighting_texel_shader shade;     /* required */
    sl_lighting_span_shader shade_span; /* NULL: the pass calls `shade` per texel */
} sl_lighting_program;

/* softlight's own shading as a program (the port, the batched path and the split sum, as the
 * frame's options choose). Its output is always finite. */
SL_API const sl_lighting_program *sl_lighting_builtin(void);

/* ---- the toolbox: the built-in shader's pieces, for any program ---- */

/* GLSL background(gl_FragCoord.xy): the environment behind pixel (x, y) (row 0 = bottom) at
 * level 0, times the intensity. */
SL_API sl_vec3 sl_lighting_background(const sl_lighting_resources *res, int x, int y);
/* GLSL textureLod(uEnv, uv, lod): the environment's lat-long mip chain, trilinear (uv in
 * [0,1]^2, u along the azimuth, v = 0 at +Z; sl_lighting_dir_to_uv), without the intensity. */
SL_API sl_vec3 sl_lighting_texture_lod(const sl_lighting_resources *res, sl_vec2 uv, float lod);
/* GLSL env_lod(w, lod): what the specular samples read (the environment, less its env lights
 * when the frame has some, in the frame's layout) along the environment-space direction w. */
SL_API sl_vec3 sl_lighting_env_lod(const sl_lighting_resources *res, sl_vec3 w, float lod);
/* GLSL irradiance(N): E(N) for an environment-space unit normal (0 when the frame has no diffuse). */
SL_API sl_vec3 sl_lighting_irradiance(const sl_lighting_resources *res, sl_vec3 N);
/* GLSL hammersley_point(k): pair k, 0 <= k < u->samples, of the frame's Hammersley set. */
SL_API sl_vec2 sl_lighting_hammersley_point(const sl_lighting_resources *res, int k);
/* GLSL specular_env_lights(N, V, Ks, alpha): the exact sum over the env lights (environment
 * space; 0 when the frame has none), times the intensity. */
SL_API sl_vec3 sl_lighting_env_lights(const sl_lighting_resources *res, sl_vec3 N, sl_vec3 V, sl_vec3 Ks,
                                      float alpha);
/* GLSL point_light(i, P, N, V, Kd, Ks, alpha): point light i's radiance with the BRDF of both
 * sets (world space; the frame's diffuse and specular toggles apply). */
SL_API sl_vec3 sl_lighting_point_light(const sl_lighting_resources *res, int i, sl_vec3 P, sl_vec3 N, sl_vec3 V,
                                       sl_vec3 Kd, sl_vec3 Ks, float alpha);

/* The lat-long mapping of the environment (GLSL sl_dir_to_uv, sl_uv_to_dir). */
SL_API sl_vec2 sl_lighting_dir_to_uv(sl_vec3 d);
SL_API sl_vec3 sl_lighting_uv_to_dir(sl_vec2 uv);
/* GLSL facing_normal(N, V): N normalised and bent toward V where N.V < 0.01 (V when N is 0). */
SL_API sl_vec3 sl_lighting_facing_normal(sl_vec3 N, sl_vec3 V);
/* GLSL lobe_param(a): the G-buffer alpha clamped to the ranges the BRDF takes. */
SL_API float sl_lighting_lobe_param(float alpha);

/* The BRDF (lighting.frag's sl_brdf_*, sl_ggx_*, sl_lobe_*; docs/lighting.md). alpha is the
 * lobe parameter: >= 0 a Phong exponent, <= -1 GGX with roughness -1 - alpha. G is G / ((L.N)(V.N)). */
SL_API float sl_lighting_brdf_D(float NdotH, float alpha);       /* Phong D */
SL_API float sl_lighting_brdf_G(float LdotH, int gterm);         /* Phong G: 1/(L.H)^2 (gterm 1) or 1 */
SL_API sl_vec3 sl_lighting_brdf_F(sl_vec3 Ks, float LdotH);      /* Schlick F (both sets) */
SL_API float sl_lighting_ggx_a2(float alpha);                    /* GGX a^2 of a lobe parameter */
SL_API float sl_lighting_ggx_D(float NdotH, float a2);
SL_API float sl_lighting_ggx_G(float NdotL, float NdotV, float a2); /* 4 Vis, height-correlated Smith */
SL_API float sl_lighting_lobe_D(float NdotH, float alpha);       /* either set, by alpha's sign */
SL_API float sl_lighting_lobe_G(float LdotH, float NdotL, float NdotV, float alpha, int gterm);

/* ---- a program loaded at run time ----
 * The shared object exports two symbols: `int sl_lighting_program_abi` (= SL_LIGHTING_ABI) and
 * `sl_lighting_program sl_lighting_program_entry`. In a C source, one line writes both:
 *     SL_LIGHTING_PROGRAM("toon", toon_shade, NULL);                                          */
#if defined(__GNUC__)
#define SL_LIGHTING_EXPORT __attribute__((visibility("default")))
#else
#define SL_LIGHTING_EXPORT
#endif
#define SL_LIGHTING_PROGRAM(name, shade, shade_span)                                                                   \
    SL_LIGHTING_EXPORT extern const int sl_lighting_program_abi;                                                      \
    SL_LIGHTING_EXPORT extern const sl_lighting_program sl_lighting_program_entry;                                    \
    const int sl_lighting_program_abi = SL_LIGHTING_ABI;                                                              \
    const sl_lighting_program sl_lighting_program_entry = {name, shade, shade_span}

#ifdef __cplusplus
}
#endif

#endif
