/* lighting.h - the deferred lighting stage: G-buffer in, linear HDR radiance out.
 *
 * Consumes: a G-buffer (src/raster/gbuffer.h, row 0 = bottom), an environment mip chain and
 * its irradiance (src/ibl/ibl.h), point lights (src/scene/scene.h) and the camera.
 * Produces: a 3-channel sl_image of linear radiance, ROW 0 = TOP (flipped here, once).
 *
 * The shading is a line-by-line C port of shaders/lighting.frag (lighting.c): IBL diffuse
 * Kd/pi E(N), IBL specular by the specification's importance-sampled estimator (eq. (3)) or one
 * of three consistent ones (options.estimator; mis draws from the environment too), optionally plus the exact sum over the environment's
 * brightest texels while the samples read the rest (options.env_lights, docs/lighting.md "Env
 * lights"), point lights with the BRDF of eq. (2), and the environment behind empty pixels.
 * The uniforms struct below is the GLSL uniform list with the same names, so the GL host
 * code can copy from it field by field (docs/lighting.md).
 *
 * Use:
 *     sl_lighting_uniforms *u = malloc(sizeof *u);            (about 9 KB)
 *     sl_lighting_uniforms_init(u, &(sl_lighting_desc){.env = &env, .irradiance = &irr,
 *         .eye = eye, .inv_view_proj = inverse(proj * view), .width = w, .height = h}, &err);
 *     sl_lighting_pass(u, &stats, &gbuffer, &image, threads, &err);
 *
 * The pass runs a batched, vectorized version of the same shader by default and the line-by-line
 * port when options.plain is set (docs/lighting.md "Two paths"); options.rotate turns on the
 * per-pixel rotation of the sample set, and sl_lighting_accumulate averages frames rendered
 * with frame = 0, 1, 2, ... (docs/lighting.md "Per-pixel rotation").
 *
 * The stage's files: lighting.c (the port), lighting_batched.c (the fast path),
 * lighting_uniforms.c (options and uniforms), lighting_task.c (per-thread tables and counters),
 * lighting_pass.c (dispatch, the pass, accumulation), lighting_trace.c/.h (one pixel's trace);
 * lighting_internal.h says which calls which.
 *
 * Does not: tone map (src/post/tonemap.h), build the environment or irradiance (ibl), rasterize. */
#ifndef SL_LIGHTING_H
#define SL_LIGHTING_H

#include <stdbool.h>
#include <stdint.h>

#include "../core/error.h"
#include <softlight/glsl.h>
#include <softlight/lighting.h>
#include "../core/image.h"
#include "../core/options.h"
#include "../ibl/env_dist.h"
#include "../ibl/env_lights.h"
#include "../ibl/ibl.h"
#include "../ibl/texture_lod.h"
#include "../occlusion/gtao.h"
#include "../raster/gbuffer.h"
#include "../scene/scene.h"
#include "../shadow/shadow.h"
#include "../shadow/sky.h"
#include "env_light_groups.h"
#include "brdf.h"
#include "splitsum_lut.h"

/* SL_LIGHTING_MAX_LIGHTS (core/options.h): MAX_LIGHTS in the GLSL */

/* The modes sl_lod_rule, sl_estimator and sl_gterm, their names, defaults and limits: the option
 * table, core/options.h. Enum values are the GLSL uniform values; 0 is "default". */

/* How a lobe set's pixels sample the environment: the estimator and its mip level's rule and
 * distortion (sl_lighting_options.ggx). */
typedef struct {
    sl_estimator estimator; /* 0 = the frame's options, all three */
    sl_lod_rule lod_rule;   /* 0 = SL_LOD_SPEC_D4 */
    bool distortion;
} sl_lobe_sampling;

/* Options, zero meaning "default" (resolved by sl_lighting_options_resolve). */
typedef struct {
    int samples;                   /* N, 1 .. SL_HAMMERSLEY_MAX; 0 = 40 */
    int lod_samples;               /* the N of uLodBase = 1/2 log2(W H / N), 1 .. SL_HAMMERSLEY_MAX;
                                      0 = samples. The viewer's accumulation frames draw few
                                      samples yet filter as the full N does (docs/viewer.md) */
    sl_lod_rule lod_rule;          /* 0 = SL_LOD_SPEC_D4 */
    bool distortion;               /* lat-long distortion d(theta) in the lod (default off) */
    sl_gterm gterm;                /* 0 = SL_GTERM_INV_LH2 */
    sl_estimator estimator;        /* 0 = SL_ESTIMATOR_SPEC */
    sl_env_layout env_layout;      /* the specular samples' chain; 0 = SL_ENV_LAYOUT_LATLONG */
    sl_irradiance_method irradiance; /* must equal the irradiance's method (SH9 = 0, BRUTE, MAP, OCT, DP) */
    bool no_diffuse, no_specular, no_point_lights; /* toggles (default: all on) */
    float env_intensity;           /* multiplies the environment; 0 = 1 */
    float env_rotation_deg;        /* environment rotated about +Z, degrees */
    bool rotate;                   /* Cranley-Patterson rotation of the Hammersley set per pixel
                                      and frame (uRotate; default off: every pixel the same set) */
    uint32_t frame;                /* frame number hashed into the rotation (uFrame) */
    bool plain;                    /* C only: run the line-by-line port of the GLSL instead of the
                                      batched fast path (docs/lighting.md "Two paths") */
    int env_lights;                /* K: the environment's K brightest texels are summed exactly
                                      and the estimator samples the rest (src/ibl/env_lights.h);
                                      0 = off, else 1 .. SL_ENV_LIGHTS_MAX */
    bool env_lights_worth;         /* env_lights is a ceiling: only as many as are worth their
                                      cost, possibly none (sl_env_lights_extract_worth; the GGX
                                      default). The renderer extracts them; the lighting stage
                                      reads what it is given */
    sl_lobe_sampling ggx;          /* the GGX set's own estimator, lod rule and distortion, where
                                      they differ from the fields above, which the Phong set
                                      keeps (a scene of both sets: the GGX objects get the
                                      accurate default, the specification's objects the recipe;
                                      sl_render_desc_resolve). ggx.estimator 0 = every pixel the
                                      fields above */
    bool env_lights_ggx_only;      /* the env lights are the GGX set's alone: a Phong pixel's
                                      samples read the whole environment and sum no light, as the
                                      recipe does (a scene of both sets' default); not with the
                                      env lights' shadow maps nor the octahedral layout */
} sl_lighting_options;

/* Fill every zero field with its default (the option table's, core/options.h). */
sl_lighting_options sl_lighting_options_resolve(const sl_lighting_options *opt);

/* Whether resolved options sample the GGX set otherwise than the Phong set. */
static inline bool sl_lighting_sets_differ(const sl_lighting_options *o)
{
    return o->ggx.estimator != o->estimator || o->ggx.lod_rule != o->lod_rule || o->ggx.distortion != o->distortion;
}

/* The GLSL block HammersleyBlock under std140, byte for byte: float N at 0, vec4 array at 16,
 * pair k in hammersley[k / 2].xy (k even) or .zw (k odd). */
typedef struct {
    float N;
    float pad_[3];
    vec4 hammersley[SL_HAMMERSLEY_MAX / 2];
} sl_hammersley_block;
void sl_hammersley_pack_std140(const sl_hammersley *set, sl_hammersley_block *block);

/* What a frame is lit with. */
typedef struct {
    sl_lighting_options options;
    const sl_env *env;               /* required */
    const sl_irradiance *irradiance; /* required unless options.no_diffuse */
    vec3 eye;                        /* world-space eye */
    mat4 inv_view_proj;              /* inverse(projection * view), for background pixels */
    int width, height;               /* the G-buffer's size (uViewport) */
    const sl_point_light *lights;    /* may be NULL when light_count is 0 */
    int light_count;                 /* 0 .. SL_LIGHTING_MAX_LIGHTS */
    const sl_env_lights *env_lights; /* required when options.env_lights > 0: extracted from env
                                        with that count; ignored otherwise */
    const sl_env *env_oct;           /* required when options.env_layout is OCT: sl_env_build_oct of
                                        what the samples read (env, or env_lights' residual) */
    const sl_env *splitsum_phong, *splitsum_ggx; /* required when options.estimator is SPLITSUM:
                                        sl_env_prefilter of what the samples read, each lobe set */
    const sl_splitsum_lut *splitsum_lut;         /* ... and the BRDF's table (splitsum_lut.h) */
    const sl_env_dist *env_dist;                 /* required when options.estimator is MIS:
                                                    sl_env_dist_build of what the samples read */
    const sl_lighting_program *program;          /* the shading (softlight/lighting.h); NULL = the
                                                    built-in, sl_lighting_builtin() */
    const sl_shadow_maps *shadows;               /* the point lights' shadow maps (src/shadow), each
                                                    light's term times its visibility; NULL = none */
    const sl_shadow_suns *env_shadows;           /* the env lights' maps (src/shadow), each env light
                                                    times its map's visibility in the specular and
                                                    the diffuse; NULL = none (ignored without env
                                                    lights) */
    const sl_shadow_sky *sky;                    /* the sky visibility maps (src/shadow/sky.h): the
                                                    diffuse irradiance (the residual's part) times
                                                    their visibility V; NULL = none */
    float reflection_distance;                   /* the reflection occlusion's ray length, 0 = off
                                                    (src/occlusion/reflection.h): softlight-gl
                                                    traces in the shader with it and `view`; the
                                                    C port reads the G-buffer's plane */
    sl_gtao_view view;                           /* the camera's frame (sl_gtao_view_of) */
} sl_lighting_desc;

/* The uniforms of shaders/lighting.frag with their GLSL names (the G-buffer samplers are the
 * sl_gbuffer passed to the pass), plus the resolved options. Read-only while shading. */
typedef struct {
    const sl_env *uEnv;                  /* the environment (background) */
    const sl_env *uEnvResidual;          /* what the specular samples read: uEnv, or uEnv less its
                                            env lights when there are any; in the octahedral
                                            layout, the octahedral chain of that */
    int uEnvLayout;                      /* the layout of uEnvResidual (sl_env_layout) */
    float uEnvMaxLod;
    float uLodBase;
    float uSinThetaMin;
    mat3 uEnvRotation;
    float uEnvIntensity;
    int uIrradianceMethod;
    vec3 uSH[9];                         /* GL upload; the C port evaluates uIrradiance */
    const sl_irradiance *uIrradiance;    /* uSH / uIrradianceMap (NULL when diffuse is off) */
    sl_hammersley_block uHammersley;
    vec3 uEye;
    mat4 uInvViewProj;
    vec2 uViewport;
    float uReflectionDistance;           /* GL upload with the frame below: the C port reads the
                                            G-buffer's reflection plane */
    vec3 uViewForward, uViewRight, uViewUp;
    float uPixelsPerUnit;
    int uLightCount;
    vec3 uLightPosition[SL_LIGHTING_MAX_LIGHTS];
    vec3 uLightColor[SL_LIGHTING_MAX_LIGHTS];
    float uLightIntensity[SL_LIGHTING_MAX_LIGHTS];
    int uEnvLightCount;                  /* 0 .. SL_ENV_LIGHTS_MAX */
    vec4 uEnvLightDir[SL_ENV_LIGHTS_MAX];      /* .xyz: unit direction, environment space */
    vec4 uEnvLightRadiance[SL_ENV_LIGHTS_MAX]; /* .rgb: radiance times the texel's node weight,
                                                  .a: its solid angle over that weight */
    vec4 uEnvLightTexel[SL_ENV_LIGHTS_MAX];    /* .xyz: the texel's bounds (sl_env_lights.box) */
    float uEnvLightSide;                 /* the level-0 texel's longest side, max(pi / H, 2 pi / W) */
    float uEnvLightMeridian;             /* every level-0 texel's side along its meridian, pi / H */
    float uEnvLightAzimuth;              /* every level-0 texel's signed width in phi, -2 pi / W
                                            (sl_env_lights.azimuth; 0 without env lights) */
    int uEnvGlowCount;                   /* with the env lights' maps, their count; else 0 */
    vec4 uEnvGlow[SL_SHADOW_SUN_MAX];    /* map k's glow (lighting_internal.h shade_glow): .xyz its
                                            direction (environment space), .w the cosine of the
                                            cap about it that its samples lie in */
    /* the split-sum method (estimator SPLITSUM; NULL otherwise): the prefiltered chains of the
     * two lobe sets, the BRDF's table, and the lod of lobe width 1 (levels - 1) */
    const sl_env *uSplitSumPhong, *uSplitSumGGX;
    const sl_splitsum_lut *uSplitSumLut;
    float uSplitSumMaxLod;
    int uSplitSumExactLevel; /* the chains' first exact level (ibl.h sl_prefilter_first_exact) */
    /* the MIS estimator (NULL otherwise): the environment distribution (uEnvDist, uEnvDistMarginal)
     * and log2 of uEnvResidual's level-0 width over its width */
    const sl_env_dist *uEnvDist;
    int uEnvDistShift;
    int uLodRule, uDistortion, uGTerm, uEstimator, uDiffuse, uSpecular, uPointLights;
    int uLodRuleGGX, uDistortionGGX, uEstimatorGGX; /* the GGX set's (options.ggx), else the three above */
    int uEnvLightsGGXOnly;               /* 1: the env lights are the GGX set's alone (options.env_lights_ggx_only) */
    int uRotate;                         /* 1 = per-pixel rotation of the Hammersley set */
    uint32_t uFrame;                     /* GLSL uint */
    sl_lighting_options options;         /* resolved */
    /* C only: each lobe set's sampling, [0] the Phong set's (uEstimator, uLodRule, uDistortion),
     * [1] the GGX set's (uEstimatorGGX ...), with whether its samples are drawn about N (mf,
     * cv): read through the lobe's sign (lighting_internal.h shade_estimator_of) */
    struct {
        int estimator, lod_rule, distortion;
        bool about_n;
        bool env_lights;                 /* it sums the env lights */
        bool whole_map;                  /* its samples read uEnv (envGather), not uEnvResidual
                                            (residualGather): a Phong lobe's where the env lights
                                            are the GGX set's alone */
    } setSampling[2];
    /* C only, for the batched path's vectorized fetch: uEnv and uEnvResidual as single blocks
     * (ibl/texture_lod.h); without a block it fetches texel by texel (same bits). */
    sl_env_gather envGather, residualGather;
    /* C only, for the split-sum fast path (lighting_splitsum.c): the two prefiltered chains
     * as blocks (zeroed when the estimator is not SPLITSUM) */
    sl_env_gather splitSumPhongGather, splitSumGGXGather;
    /* C only: the env lights as structure of arrays, for the batched path's vector loads */
    float envLightX[SL_ENV_LIGHTS_MAX], envLightY[SL_ENV_LIGHTS_MAX], envLightZ[SL_ENV_LIGHTS_MAX];
    float envLightR[SL_ENV_LIGHTS_MAX], envLightG[SL_ENV_LIGHTS_MAX], envLightB[SL_ENV_LIGHTS_MAX];
    /* the point lights' shadow maps (NULL: no light casts), read by point_light's callers
     * through sl_shade_light_visibility; softlight-gl draws its own (src/gl/shadow_pass.c, bound
     * as uShadowCubes) for the lights these cast for */
    const sl_shadow_maps *shadowMaps;
    /* the env lights' shadows (envLightShadows = 1: envShadowMaps is set and there are env
     * lights): each env light's specular term, and its part of the irradiance, times its map's
     * visibility (docs/lighting.md "Shadow maps"). softlight-gl draws its own from the same
     * clusters and frames (sl_shadow_suns_frames), bound as uShadowSuns */
    int envLightShadows;
    const sl_shadow_suns *envShadowMaps;
    /* C only, with envLightShadows: the env lights grouped by the map that shadows them, for the
     * batched path's irradiance sums (lighting_batched.c: env_shadow_diffuse), and each one's
     * visibility slot */
    sl_env_light_groups envLightGroups;
    /* each light's visibility slot: its map (0 .. count - 1), SL_SHADOW_SUN_MAX for none (1),
     * SL_SHADOW_SUN_MAX + 1 past the count (0): sl_shade_env_light_visibility_of */
    unsigned char envLightVisSlot[SL_ENV_LIGHTS_MAX];
    /* the sky visibility maps (NULL: none), the diffuse irradiance times their V
     * (sl_shadow_sky_visibility) and the specular's part across the horizon times one map's
     * (lighting_internal.h: shade_horizon); softlight-gl draws its own from the same directions,
     * weights and frames (sl_shadow_sky_frames), bound as uSkyMaps */
    const sl_shadow_sky *skyMaps;
    /* the lighting program (NULL = the built-in) and the frame's uniforms as it sees them */
    const sl_lighting_program *program;
    sl_lighting_frame_uniforms frame;
} sl_lighting_uniforms;

/* Resolve options, build the Hammersley set and derive every uniform. False with SL_ERR_RANGE
 * on: no env, samples out of 1..SL_HAMMERSLEY_MAX, light_count out of range, a missing or
 * mismatched irradiance, non-finite intensity/rotation, width or height < 1. */
bool sl_lighting_uniforms_init(sl_lighting_uniforms *u, const sl_lighting_desc *desc, sl_error *err);

/* Per-frame counters (summed over threads; integers, so the sums do not depend on threads). */
typedef struct {
    int64_t pixels;            /* pixels written */
    int64_t background;        /* pixels with no geometry */
    int64_t samples;           /* specular samples drawn */
    int64_t below_horizon;     /* ... of which w.N <= 0 (contributed 0) */
    int64_t bent_normals;      /* normals bent toward the eye (N.V < 0.01) */
    int64_t pole_frames;       /* the sample frame's axis (R; N for the microfacet estimator)
                                  within 1e-3 of +-Z: the X x axis frame was used */
    int64_t nonfinite;         /* pixels whose NaN/Inf was replaced: by 0 in the built-in program
                                  (should stay 0), by magenta (SL_LIGHTING_NONFINITE) in another */
} sl_lighting_stats;

/* Per-thread scratch: the batched path's per-alpha sample cache (docs/lighting.md "Two paths")
 * and counters (lighting_task.c).
 * Entries are valid for one uniforms struct: call sl_lighting_task_reset after re-initialising
 * the uniforms it was used with. */
typedef struct sl_lighting_task sl_lighting_task;

/* What a traced pixel computed (lighting_trace.h). */
typedef struct sl_lighting_trace sl_lighting_trace;
sl_lighting_task *sl_lighting_task_create(sl_error *err);
void sl_lighting_task_reset(sl_lighting_task *task);
void sl_lighting_task_stats(const sl_lighting_task *task, sl_lighting_stats *stats); /* adds */
void sl_lighting_task_destroy(sl_lighting_task *task);

/* What the built-in's batched paths read from a whole G-buffer, filled before any of its rows is
 * shaded: the sky maps' V per texel (with u->skyMaps and the diffuse term: sky_plane.c, fewer
 * lookups than one a pixel). sl_lighting_pass keeps its own; a caller that schedules rows itself
 * (the viewer) prepares one after the uniforms and before the rows, and hands it to each task
 * (without it a task's pixels look V up themselves: the port's values, slower). */
typedef struct {
    float *sky;      /* width x height in the G-buffer's order, or NULL: not needed */
    size_t capacity; /* floats allocated */
} sl_lighting_planes;
bool sl_lighting_planes_prepare(sl_lighting_planes *planes, const sl_lighting_uniforms *u, const sl_gbuffer *gb,
                                int threads, sl_error *err);
void sl_lighting_planes_free(sl_lighting_planes *planes);
/* The task's rows read `planes` (NULL: none) until the next call (sl_lighting_task_reset, which
 * drops the sample tables, keeps it). */
void sl_lighting_task_use_planes(sl_lighting_task *task, const sl_lighting_planes *planes);

/* What a lighting program's NaN or Inf becomes (the built-in repairs its own to 0): magenta,
 * loud in any tone map. */
#define SL_LIGHTING_NONFINITE vec3(1.0f, 0.0f, 1.0f)

/* The frame's lighting program: radiance of G-buffer texel (x, y) (the built-in: the C port of
 * main()), row 0 = bottom, i.e. gl_FragCoord = (x + 0.5, y + 0.5). `task` may be NULL (no cache, no counters; same bits);
 * `trace` may be NULL (the fast path tests it once per sample). Never returns NaN/Inf. */
vec3 sl_lighting_shade(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y,
                       sl_lighting_task *task, sl_lighting_trace *trace);

/* Pixels x0 .. x0 + count - 1 of G-buffer row y (row 0 = bottom) into out[0 .. count): the
 * pass's unit of work, for callers that schedule rows themselves (the viewer). The batched path
 * vectorizes over the row's pixels, so this is faster than count calls of sl_lighting_shade,
 * with the same bits. The pixels must lie inside gb. */
void sl_lighting_shade_row(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                           sl_lighting_task *task, vec3 *out);
/* So `out` may be a row of an sl_image of 3 channels, shaded in place (the pass, the viewer). */
_Static_assert(sizeof(vec3) == 3 * sizeof(float), "an image row of 3 floats a pixel is a row of vec3");

/* The lighting pass: every texel of gb into `out` (allocated when out->data is NULL, else it
 * must be gb's size with 3 channels), row 0 = top. OpenMP over bands of whole rows, dynamic schedule;
 * bitwise identical for any thread count. threads <= 0: OpenMP's default. stats may be NULL. */
bool sl_lighting_pass(const sl_lighting_uniforms *u, sl_lighting_stats *stats, const sl_gbuffer *gb,
                      sl_image *out, int threads, sl_error *err);
/* Work run inside the pass on each band as soon as it is lit, by the thread that lit it: image
 * rows [row0, row1) of `out` are final (row 0 = top); `thread` is the OpenMP thread number, below
 * the pass's thread count. A stage fused this way (the renderer's tone map) reads the rows while
 * they are in cache and needs no parallel region of its own: a region ends when its last thread
 * does, and on a machine another process keeps busy that is often a descheduled one. */
typedef struct sl_lighting_band_hook {
    void (*run)(void *ctx, int thread, int row0, int row1);
    void *ctx;
} sl_lighting_band_hook;
/* sl_lighting_pass with `hook` run after each band (NULL: none). */
bool sl_lighting_pass_hooked(const sl_lighting_uniforms *u, sl_lighting_stats *stats, const sl_gbuffer *gb,
                             sl_image *out, int threads, const sl_lighting_band_hook *hook, sl_error *err);

/* The per-sample mip level of lighting.frag's mip_level() (exposed for tests and reports):
 * D = D(H), pdf = p(w), w the environment-space sample direction. Always in [0, uEnvMaxLod]. */
float sl_lighting_mip_level(const sl_lighting_uniforms *u, float D, float pdf, vec3 w);

/* Cranley-Patterson rotation (lighting.frag hash_u32, pixel_rotation): a per-pixel, per-frame
 * offset in [0, 1)^2 added to every Hammersley pair mod 1 when uRotate is on. Integer hash
 * (Wellons' lowbias32) of x, y (G-buffer pixel, row 0 = bottom, as gl_FragCoord) and frame;
 * both components have 24 bits, exact in float, so C and GLSL agree bit for bit. */
uint32_t sl_lighting_hash(uint32_t x);
vec2 sl_lighting_pixel_rotation(int x, int y, uint32_t frame);

/* Progressive refinement: fold frame number `index` (0, 1, 2, ...) of a sequence rendered with
 * rotation on and frame = 0, 1, 2, ... into the running mean: mean += (frame - mean) / (index + 1)
 * (index 0 copies; mean is allocated then when mean->data is NULL). Same size and channels
 * required (SL_ERR_RANGE otherwise). Deterministic: per pixel, in index order. */
bool sl_lighting_accumulate(sl_image *mean, const sl_image *frame, int index, sl_error *err);

#endif
