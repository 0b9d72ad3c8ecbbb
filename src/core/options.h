/* options.h - every option a user can set, declared once (SL_OPTION_LIST): its field, its name,
 * its spelling on the command line and in a scene file, its help line, its default and its
 * limits, and for the modes (lod rule, estimator, G term, irradiance method, layout) the name of
 * each value; and the one record of values (sl_option_values) that carries them from the command
 * line or the scene file to the renderer. One limit per quantity: the largest image
 * side, the most samples, the most env lights, the most point lights are written here once.
 *
 * Read by: the command line (src/app/render_options.c, also softlight-gl's), the viewer (mode
 * names, cycling a mode, its key and script limits), the scene reader (src/scene/scene_options.c:
 * the render and environment keys), the renderer's one resolution (sl_render_desc_resolve), the
 * stages' own defaults (sl_lighting_options_resolve, the tone map) and
 * tests/unit/test_options.c, which checks that they, --help, README.md's option table and
 * docs/scene-format.md's key tables all agree.
 * It lives in core because its lowest reader, the scene file (src/scene), sits directly above
 * core (core <- scene/ibl <- raster <- shading <- post <- render <- app): it holds words and
 * numbers only, and the stages name their structures' sizes from it (SL_HAMMERSLEY_MAX sizes the
 * GLSL's Hammersley block, SL_RASTER_MAX_SIZE is the rasterizer's fixed-point budget).
 * Like sokol's _sg_def, a default is resolved from one place; like Lua's luaL_checkoption, a
 * mode is parsed against one list of names.
 *
 * Does not: parse argv or JSON (src/app/args.c, src/scene/scene_json.c do, with these limits), or
 * hold options of one command only (softlight view --scale, truth --part). */
#ifndef SL_OPTIONS_H
#define SL_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>

#include "error.h"

/* Largest width or height of any image softlight renders: the rasterizer's fixed-point budget
 * (src/raster/rast_internal.h: 8192 lies inside its 16000-pixel guard band). The command line,
 * the scene file, the viewer's window and script, the G-buffer and the rasterizer share it. */
#define SL_RASTER_MAX_SIZE 8192
/* Most specular samples N: the GLSL's HammersleyBlock holds 512 vec4, two pairs each. */
#define SL_HAMMERSLEY_MAX 1024
/* Most env lights K: MAX_ENV_LIGHTS in the GLSL (whole groups of 16 for the batched path). */
#define SL_ENV_LIGHTS_MAX 64
/* Which of the brightest texels are worth their cost as lights, where the count is a ceiling (the
 * GGX default: src/ibl/env_lights.h sl_env_lights_extract_worth). None when the part the ceiling's
 * lights would take out of their texels is under WORTH_PEAK of those texels' power: the brightest
 * texels are a plateau (a softbox, an overcast sky), not peaks, and filtered samples read a
 * plateau well. Else the fewest lights that take all but WORTH_REST of what the ceiling's take. */
#define SL_ENV_LIGHTS_WORTH_PEAK 0.25
#define SL_ENV_LIGHTS_WORTH_REST 0.02
/* N for a scene whose objects are all GGX where neither it nor the command line sets one (a model
 * opened alone): its default mode (mf, pdf, distortion, the env lights worth their cost) at N 16
 * costs 0.87-0.97 times the recipe at the option table's N 40 (docs/accuracy.md "Defaults"). */
#define SL_GGX_DEFAULT_SAMPLES 16
#define SL_SKY_MAPS_MAX 64 /* the most sky visibility maps (--sky-maps; src/shadow/sky.h) */
/* A texel under a lobe narrower than a few texels is integrated over cells of equal solid angle,
 * by the ground truth (src/ibl/ground_truth.h) and by the env lights (lighting.frag
 * env_light_split, TEXEL_SPLIT_* there): where the lobe's narrowest width 2 a max(N.V, MIN_NV)
 * spans fewer than CELLS_PER_WIDTH cells of the texel's side, that many cells a side, at most MAX.
 * The truth splits the texels whose centroid lies within NEAR_WIDTHS widths 2 a of R plus two
 * texels, s x s cells each. The env lights split those within ENV_LIGHT_NEAR_WIDTHS of the lobe's
 * widths along each of its axes, as many cells along each side of the texel as the lobe's width
 * across it asks (lighting.c env_light_split). At the truth's 6 widths, the GGX default mode's
 * nRMSE on the eleven scenes of bench/mis-front.sh is the same to four digits as at 3, for 1.7x the
 * lighting time on grazing.json (17.6 against 10.2 ms) and 1.4x on ggx.json. */
#define SL_TEXEL_SPLIT_CELLS_PER_WIDTH 8
#define SL_TEXEL_SPLIT_MAX 16
#define SL_TEXEL_SPLIT_NEAR_WIDTHS 6
#define SL_TEXEL_SPLIT_MIN_NV 0.02
#define SL_ENV_LIGHT_NEAR_WIDTHS 3
/* Most point lights of a scene: MAX_LIGHTS in the GLSL, the size of its uLight* arrays (and of
 * sl_lighting_uniforms'). Here, not in shading/lighting.h, because the scene reader checks it
 * where the lights are read (`lights[16]: at most 16 point lights`). */
#define SL_LIGHTING_MAX_LIGHTS 16
/* Raster tile side, a power of two; the default was chosen from bench_raster's sweep
 * (docs/performance.md); SL_SPAN_MAX (raster.h) equals the largest. */
#define SL_TILE_DEFAULT 64
#define SL_TILE_MIN 16
#define SL_TILE_MAX 256
/* The image memory budget, in MiB: the most one image read from a file (an environment, an
 * irradiance map, a PFM or PNG) may take decoded, checked against the size its header declares
 * before anything that size is allocated. The default reads an 8192x8192 RGB render (768 MiB)
 * and an 8k environment (384 MiB) and refuses a 16384x8192 one (1536 MiB), which needs about
 * 6.5 GiB at its peak (softlight info). The largest is image.h's SL_IMAGE_MAX_BYTES. */
#define SL_IMAGE_MEMORY_DEFAULT_MIB 1024
#define SL_IMAGE_MEMORY_MAX_MIB 4096

/* The mip-level rule of the specular samples. Enum values of the modes are the GLSL uniform
 * values; 0 is "default" and never reaches the shader. */
typedef enum {
    SL_LOD_DEFAULT = 0,
    SL_LOD_NONE = 1,    /* lod 0: every sample reads the full-resolution map */
    SL_LOD_SPEC = 2,    /* 1/2 log2(W H / N) - 1/2 log2(D(H))            (specification) */
    SL_LOD_SPEC_D4 = 3, /* 1/2 log2(W H / N) - 1/2 log2(D(H) / 4)        (its note; default) */
    SL_LOD_GEMS = 4,    /* max(1/2 log2(Omega_s / Omega_p) + 1, 0), Omega_s = 1/(N p(w)),
                           Omega_p = 4 pi / (W H)                         (GPU Gems 3, ch. 20.4) */
    SL_LOD_PDF = 5,     /* max(1/2 log2(Omega_s / Omega_p), 0): gems without its +1 over-blur,
                           the footprint of the drawn direction's own density ("pdf") */
} sl_lod_rule;

/* The specular estimator (uEstimator). */
typedef enum {
    SL_ESTIMATOR_DEFAULT = 0,
    SL_ESTIMATOR_SPEC = 1,       /* eq. (3), divides by D(H): the GLSL's; biased (conventions.md, erratum 7) */
    SL_ESTIMATOR_CONSISTENT = 2, /* divides by the density of the drawn w, p(w) */
    SL_ESTIMATOR_MICROFACET = 3, /* H drawn from D(H) (N.H), w = reflect(-V, H), divides by
                                    p(w) = D (N.H) / (4 V.H): bounded weights ("mf") */
    SL_ESTIMATOR_SPLITSUM = 4,   /* no samples: the environment prefiltered per lobe width
                                    (src/ibl/prefilter.c) at R times a table of the BRDF's
                                    scale and bias (src/shading/splitsum_lut.h); N = V assumed */
    SL_ESTIMATOR_MIS = 5,        /* N/2 directions drawn from the BRDF (as mf) and N/2 from the
                                    environment's own radiance (src/ibl/env_dist.h), each weighed
                                    by the power heuristic, lod 0: consistent, and the sun drawn
                                    where it is ("mis") */
    SL_ESTIMATOR_CV = 6,         /* the split sum as a control variate: its chain's exact part
                                    times beta E plus the mf samples less the chain's kernel,
                                    (F W - beta E K / p) L ("cv") */
    SL_ESTIMATOR_CV_MIS = 7,     /* the same control variate with mis's pairs of samples: each
                                    BRDF and environment sample's (f (N.w) - beta E K) L / p
                                    times its power-heuristic weight ("cvmis") */
} sl_estimator;

/* What an estimator reads besides the environment: the split sum's chains and table (splitsum,
 * cv, cvmis), the environment's own distribution (mis, cvmis). */
static inline bool sl_estimator_reads_splitsum(sl_estimator e)
{
    return e == SL_ESTIMATOR_SPLITSUM || e == SL_ESTIMATOR_CV || e == SL_ESTIMATOR_CV_MIS;
}
static inline bool sl_estimator_reads_env_dist(sl_estimator e)
{
    return e == SL_ESTIMATOR_MIS || e == SL_ESTIMATOR_CV_MIS;
}

/* The G term (uGTerm). */
typedef enum {
    SL_GTERM_DEFAULT = 0,
    SL_GTERM_INV_LH2 = 1, /* G / (L.N V.N) = 1 / (L.H)^2 (default) */
    SL_GTERM_ONE = 2,     /* G / (L.N V.N) = 1 */
} sl_gterm;

/* How the diffuse irradiance E(n) is obtained (src/ibl/ibl.h); the values are uIrradianceMethod's. */
typedef enum {
    SL_IRRADIANCE_SH9 = 0,   /* 9 SH coefficients projected with exact texel solid angles */
    SL_IRRADIANCE_BRUTE = 1, /* a small lat-long map integrated by quadrature */
    SL_IRRADIANCE_MAP = 2,   /* a precomputed lat-long .hdr given in the scene, read as it is */
    SL_IRRADIANCE_OCT = 3,   /* an octahedral map (irradiance_map.c): no pole, no seam; the default */
    SL_IRRADIANCE_DP = 4,    /* a dual-paraboloid map (irradiance_map.c), both halves in one texture */
} sl_irradiance_method;

/* The layout of the environment's mip chain that the specular samples read (uEnvLayout). The
 * background always reads the lat-long level 0. docs/ibl.md "Specular layouts" has the measured
 * comparison. */
typedef enum {
    SL_ENV_LAYOUT_DEFAULT = 0,
    SL_ENV_LAYOUT_LATLONG = 1, /* the specification's lat-long chain, GL's glGenerateMipmap: the GL-matching recipe */
    SL_ENV_LAYOUT_OCT = 2,     /* an octahedral S x S chain (env_oct.c): no pole, no seam */
} sl_env_layout;

/* What a model's texture that names no file does (--missing-textures, a model object's
 * missing_textures): refuse the model, or draw its material without the texture. */
typedef enum {
    SL_MISSING_TEXTURES_FAIL = 0, /* one error line naming model, material and file (the default) */
    SL_MISSING_TEXTURES_SKIP = 1, /* one warning line each; the material draws with its factors alone */
} sl_missing_textures;

/* ---- the declaration: every option, once ----
 *
 * X(ID, field, TYPE, ctype, name, cli, alias, metavar, help, (row))
 *   ID       SL_OPT_ID, the row's index in sl_options[] and its bit in sl_option_values.set
 *   field    its field in sl_option_values: the same word as the flag and the scene key
 *            (--diffuse-only, render.diffuse_only, diffuse_only)
 *   TYPE     FLAG, INT, FLOAT, SIZE (two ints, width and height) or CHOICE; ctype its C type
 *   name     what messages and tests call it
 *   cli, alias, metavar: the command line's spelling (NULL: not on the command line)
 *   help     --help's line; README.md's table and docs/scene-format.md's are checked against
 *            these rows by tests/unit/test_options.c
 *   row      the rest of its sl_option: scene keys, default, limits, choice names
 *
 * In --help's order; the rows without a command-line spelling come last. A scene file's keys are
 * read in the "render" object (the environment's intensity in "environment"). Not in a scene
 * file: threads, tile, plain and image-memory, which belong to the machine that renders, not to
 * the scene (a file must not raise the memory budget that guards against it). missing-textures is
 * read by the scene loader, not the renderer: a scene file gives it per model (an object's
 * "missing_textures"), and the command line's, when given, holds for every model. */
#define SL_OPTION_LIST(X)                                                                                            \
    X(SIZE, size, SIZE, int, "size", "--size", NULL, "WxH", "render size (default: the scene's)",                    \
      (.scene = {"render.width", "render.height"}, .def = {1280, 720}, .min = 1, .max = SL_RASTER_MAX_SIZE))          \
    /* N: the specification suggests 20 to 40 */                                                                     \
    X(SAMPLES, samples, INT, int, "samples", "--samples", "-n", "N", "specular samples N per pixel (1..1024)",      \
      (.scene = {"render.samples"}, .def = {40}, .min = 1, .max = SL_HAMMERSLEY_MAX))                                \
    /* e of the tone map: a scene file keeps to the specification's range for its environments, the command line    \
     * and the viewer's keys go beyond it (src/post/tonemap.h) */                                                    \
    X(EXPOSURE, exposure, FLOAT, float, "exposure", "--exposure", "-e", "E", "tone-map exposure e",                 \
      (.scene = {"render.exposure"}, .def = {1}, .min = 0.001, .max = 1e6, .file_min = 0.1, .file_max = 10000.0))    \
    /* c of the tone map's exponent c/2.2 */                                                                         \
    X(CONTRAST, contrast, FLOAT, float, "contrast", "--contrast", "-c", "C", "tone-map contrast c (exponent c/2.2)", \
      (.scene = {"render.contrast"}, .def = {1}, .min = 0.01, .max = 100, .file_min = 0.0, .file_max = 10.0,         \
       .file_min_open = true))                                                                                       \
    X(SRGB, srgb, FLAG, bool, "srgb", "--srgb", NULL, NULL,                                                          \
      "encode with the exact sRGB curve instead of the 1/2.2 power", (.scene = {"render.srgb"}))                     \
    X(LOD, lod, CHOICE, sl_lod_rule, "lod", "--lod", NULL, NULL,                                                     \
      "mip-level rule for specular samples (default spec-d4; pdf: gems without its +1)",                             \
      (.scene = {"render.lod"}, .def = {SL_LOD_SPEC_D4}, .min = SL_LOD_NONE, .max = SL_LOD_PDF, .names = lod_names)) \
    X(DISTORTION, distortion, FLAG, bool, "distortion", "--distortion", NULL, NULL,                                  \
      "include the lat-long distortion in the mip level", (.scene = {"render.distortion"}))                          \
    X(GTERM, gterm, CHOICE, sl_gterm, "gterm", "--g", NULL, NULL, "G/(L.N V.N): 1/(L.H)^2 (default) or 1",           \
      (.scene = {"render.gterm"}, .def = {SL_GTERM_INV_LH2}, .min = SL_GTERM_INV_LH2, .max = SL_GTERM_ONE,           \
       .names = gterm_names))                                                                                        \
    X(ESTIMATOR, estimator, CHOICE, sl_estimator, "estimator", "--estimator", NULL, NULL,                            \
      "specular estimator: the specification's eq. (3) (default), consistent, microfacet sampling, the "             \
      "split-sum lookup (prefiltered environment, no samples), mis (BRDF and environment sampling), or cv "          \
      "(the split sum plus microfacet samples of its error) or cvmis (the split sum plus mis samples of its error)", \
      (.scene = {"render.estimator"}, .def = {SL_ESTIMATOR_SPEC}, .min = SL_ESTIMATOR_SPEC,                          \
       .max = SL_ESTIMATOR_CV_MIS, .names = estimator_names))                                                  \
    /* default: the scene's map if it names one (the scene reader chooses "map" then), else this, the pole-free      \
     * octahedral map (docs/ibl.md says why) */                                                                      \
    X(IRRADIANCE, irradiance, CHOICE, sl_irradiance_method, "irradiance", "--irradiance", NULL, NULL,                \
      "diffuse irradiance (default: the scene's map if any, else oct, the pole-free octahedral map)",                \
      (.scene = {"render.irradiance"}, .def = {SL_IRRADIANCE_OCT}, .min = SL_IRRADIANCE_SH9,                         \
       .max = SL_IRRADIANCE_DP, .names = irradiance_names))                                                          \
    /* the specular samples' mip chain; docs/ibl.md "Specular layouts" says why the default */                       \
    X(ENV_LAYOUT, env_layout, CHOICE, sl_env_layout, "env-layout", "--env-layout", NULL, NULL,                       \
      "the specular samples' mip chain: latlong (default; the specification's, as GL builds it) or oct, an "         \
      "octahedral chain without pole or seam",                                                                       \
      (.scene = {"render.env_layout"}, .def = {SL_ENV_LAYOUT_LATLONG}, .min = SL_ENV_LAYOUT_LATLONG,                 \
       .max = SL_ENV_LAYOUT_OCT, .names = env_layout_names))                                                         \
    X(DIFFUSE_ONLY, diffuse_only, FLAG, bool, "diffuse-only", "--diffuse-only", NULL, NULL,                          \
      "image-based diffuse term only", (.scene = {"render.diffuse_only"}))                                           \
    X(SPECULAR_ONLY, specular_only, FLAG, bool, "specular-only", "--specular-only", NULL, NULL,                      \
      "image-based specular term only", (.scene = {"render.specular_only"}))                                         \
    X(NO_LIGHTS, no_lights, FLAG, bool, "no-lights", "--no-lights", NULL, NULL, "ignore the scene's point lights",   \
      (.scene = {"render.no_lights"}))                                                                               \
    /* default 0: all cores */                                                                                       \
    X(THREADS, threads, INT, int, "threads", "--threads", "-j", "N", "worker threads (default: all cores)",         \
      (.min = 1, .max = 256))                                                                                        \
    /* a power of two (sl_options_check) */                                                                          \
    X(TILE, tile, INT, int, "tile", "--tile", NULL, "S", "raster tile size in pixels (power of two)",                \
      (.def = {SL_TILE_DEFAULT}, .min = SL_TILE_MIN, .max = SL_TILE_MAX))                                            \
    X(ROTATE, rotate, FLAG, bool, "rotate", "--rotate", NULL, NULL,                                                  \
      "rotate the specular sample set per pixel (Cranley-Patterson): noise instead of banding",                      \
      (.scene = {"render.rotate"}))                                                                                  \
    X(FRAME, frame, INT, int, "frame", "--frame", NULL, "N",                                                         \
      "frame number of the rotation (--rotate): average frames 0..K-1 to converge",                                  \
      (.scene = {"render.frame"}, .min = 0, .max = 1e9))                                                             \
    X(PLAIN, plain, FLAG, bool, "plain", "--plain", NULL, NULL,                                                      \
      "run the plain reference paths (per-pixel raster, the line-by-line port of lighting.frag) to compare with "    \
      "the fast ones or to step through in a debugger",                                                              \
      ())                                                                                                            \
    X(ENV_LIGHTS, env_lights, INT, int, "env-lights", "--env-lights", NULL, "K",                                     \
      "sum the environment's K brightest texels exactly, sample the rest (0..64; default 0: off)",                   \
      (.scene = {"render.env_lights"}, .min = 0, .max = SL_ENV_LIGHTS_MAX))                                          \
    /* 0: off, and the frame pays nothing for it (src/occlusion/gtao.h) */                                         \
    X(AO_RADIUS, ao_radius, FLOAT, float, "ao-radius", "--ao-radius", NULL, "R",                                     \
      "ambient occlusion of the environment (GTAO on the G-buffer) within R world units (default 0: off)",          \
      (.scene = {"render.ao_radius"}, .min = 0, .max = 1e6))                                                         \
    /* 0: off, and the frame pays nothing for it (src/occlusion/reflection.h) */                                   \
    X(REFLECTION_OCCLUSION, reflection_occlusion, FLOAT, float, "reflection-occlusion", "--reflection-occlusion",    \
      NULL, "D",                                                                                                     \
      "occlude the environment's specular where the lobe's rays, traced D world units against the G-buffer, hit "  \
      "a surface (default 0: off)",                                                                                  \
      (.scene = {"render.reflection_occlusion"}, .min = 0, .max = 1e6))                                              \
    /* 0: off, no maps drawn, the frame pays nothing for them (src/shadow/sky.h) */                                 \
    X(SKY_MAPS, sky_maps, INT, int, "sky-maps", "--sky-maps", NULL, "K",                                             \
      "occlude the environment's diffuse, and the specular across the horizon, with K orthographic depth maps of "  \
      "the scene from directions over the sphere (sky visibility maps; 0..64; default 0: off)",                      \
      (.scene = {"render.sky_maps"}, .min = 0, .max = SL_SKY_MAPS_MAX))                                              \
    /* off: no maps drawn, the frame pays nothing for them (src/shadow/shadow.h) */                                 \
    X(SHADOWS, shadows, FLAG, bool, "shadows", "--shadows", NULL, NULL,                                             \
      "every point light and env light casts shadows (shadow maps; a light's \"shadow\": true casts alone)",       \
      (.scene = {"render.shadows"}))                                                                                 \
    X(IMAGE_MEMORY, image_memory, INT, int, "image-memory", "--image-memory", NULL, "MIB",                           \
      "the most memory one image read from a file may take decoded, in MiB (1..4096; default 1024); an "             \
      "environment needs 2.4 (maps over 2048x1024) to 4.4 times that at its peak (softlight info)",                  \
      (.def = {SL_IMAGE_MEMORY_DEFAULT_MIB}, .min = 1, .max = SL_IMAGE_MEMORY_MAX_MIB))                              \
    /* fail by default: outputs are all or nothing, and a picture drawn without its base colour would pass for the \
     * model (docs/scene-format.md "Models") */                                                                      \
    X(MISSING_TEXTURES, missing_textures, CHOICE, sl_missing_textures, "missing-textures", "--missing-textures",      \
      NULL, NULL,                                                                                                    \
      "a model's texture file that is missing: fail (default: refuse the model) or skip (draw its material "         \
      "without it, one warning line each)",                                                                          \
      (.def = {SL_MISSING_TEXTURES_FAIL}, .min = SL_MISSING_TEXTURES_FAIL, .max = SL_MISSING_TEXTURES_SKIP,          \
       .names = missing_textures_names))                                                                             \
    X(ENV_INTENSITY, env_intensity, FLOAT, float, "env-intensity", NULL, NULL, NULL,                                 \
      "multiplies the environment's radiance",                                                                       \
      (.scene = {"environment.intensity"}, .def = {1}, .min = 0, .max = 1e6))

#define SL_OPT_ID_(ID, ...) SL_OPT_##ID,
typedef enum { SL_OPTION_LIST(SL_OPT_ID_) SL_OPT_COUNT } sl_option_id;
#undef SL_OPT_ID_
_Static_assert(SL_OPT_COUNT <= 32, "sl_option_values.set has a bit per option");

/* One record of option values: what the command line gave, what a scene file gave, or what a
 * render uses once both are resolved. `set` has bit (1u << SL_OPT_ID) for each option its source
 * gave; a field whose bit is clear holds the option's default (sl_option_values_default). That
 * is the one "unset" convention: no 0, -1 or separate bool stands for "not given". */
#define SL_OPT_FIELD_FLAG(ctype, field) ctype field;
#define SL_OPT_FIELD_INT(ctype, field) ctype field;
#define SL_OPT_FIELD_FLOAT(ctype, field) ctype field;
#define SL_OPT_FIELD_CHOICE(ctype, field) ctype field;
#define SL_OPT_FIELD_SIZE(ctype, field) ctype field[2];
#define SL_OPT_FIELD_(ID, field, TYPE, ctype, ...) SL_OPT_FIELD_##TYPE(ctype, field)
typedef struct {
    unsigned set;
    SL_OPTION_LIST(SL_OPT_FIELD_)
} sl_option_values;
#undef SL_OPT_FIELD_

#define SL_OPT_BIT(ID) (1u << (unsigned)(ID))
static inline bool sl_option_is_set(const sl_option_values *v, sl_option_id id) { return (v->set & SL_OPT_BIT(id)) != 0; }

/* sl_option_set_FIELD(v, value) (a size: width, height): the value, marked as given. */
#define SL_OPT_SETTER_FLAG(ID, ctype, field) SL_OPT_SETTER_ONE_(ID, ctype, field)
#define SL_OPT_SETTER_INT(ID, ctype, field) SL_OPT_SETTER_ONE_(ID, ctype, field)
#define SL_OPT_SETTER_FLOAT(ID, ctype, field) SL_OPT_SETTER_ONE_(ID, ctype, field)
#define SL_OPT_SETTER_CHOICE(ID, ctype, field) SL_OPT_SETTER_ONE_(ID, ctype, field)
#define SL_OPT_SETTER_ONE_(ID, ctype, field)                                                                         \
    static inline void sl_option_set_##field(sl_option_values *v, ctype x)                                          \
    {                                                                                                                \
        v->field = x;                                                                                                \
        v->set |= SL_OPT_BIT(SL_OPT_##ID);                                                                           \
    }
#define SL_OPT_SETTER_SIZE(ID, ctype, field)                                                                         \
    static inline void sl_option_set_##field(sl_option_values *v, ctype w, ctype h)                                 \
    {                                                                                                                \
        v->field[0] = w;                                                                                             \
        v->field[1] = h;                                                                                             \
        v->set |= SL_OPT_BIT(SL_OPT_##ID);                                                                           \
    }
#define SL_OPT_SETTER_(ID, field, TYPE, ctype, ...) SL_OPT_SETTER_##TYPE(ID, ctype, field)
SL_OPTION_LIST(SL_OPT_SETTER_)
#undef SL_OPT_SETTER_

typedef enum {
    SL_OPTION_FLAG,   /* off unless given */
    SL_OPTION_INT,
    SL_OPTION_FLOAT,
    SL_OPTION_SIZE,   /* width and height, each within [min, max] */
    SL_OPTION_CHOICE, /* one of an enum's values min .. max, each named by names[value] */
} sl_option_type;

/* A row of the declaration, as code reads it. */
typedef struct {
    const char *name;         /* "samples": what messages, tests and reports call it */
    const char *cli, *alias;  /* "--samples", "-n"; NULL: not on the command line */
    const char *metavar;      /* "N"; NULL for a flag or a choice (its names stand there) */
    const char *help;         /* --help's line */
    const char *scene[2];     /* JSON paths in a scene file ("render.samples"); a size has two
                                 (width, height); NULL: not in a scene file */
    sl_option_type type;
    size_t offset;            /* of its field in sl_option_values */
    double def[2];            /* the default (a choice: its value; a size: width, height; 0 for
                                 threads: the stage decides, all cores) */
    double min, max;          /* what any input may give (a choice: its first and last value) */
    double file_min, file_max; /* where a scene file is held to a narrower range (the
                                  specification's, for exposure and contrast); else both 0 */
    bool file_min_open;       /* the scene file's minimum itself is excluded (contrast > 0) */
    const char *const *names; /* choice: names[v] for v in 0 .. max ("default" at 0 where 0
                                 means the default) */
} sl_option;

extern const sl_option sl_options[SL_OPT_COUNT];

/* A choice's name for `value` ("?" outside 0 .. max), and the value of `name` (false when it
 * names none; "default" parses where 0 means the default). */
const char *sl_option_name(const sl_option *opt, int value);
bool sl_option_parse(const sl_option *opt, const char *name, int *value);
/* The value after `value`, back to the first after the last (the viewer's mode keys). */
int sl_option_next(const sl_option *opt, int value);
/* A choice's values min .. max as the command line spells them, "none|spec|spec-d4|gems|pdf";
 * false when `size` is too small. */
bool sl_option_choices(const sl_option *opt, char *out, size_t size);
/* The range a scene file is held to: file_min/file_max where the row has them, else min/max. */
double sl_option_file_min(const sl_option *opt);
double sl_option_file_max(const sl_option *opt);

/* The record with every option at its default and nothing marked as given. */
void sl_option_values_default(sl_option_values *v);
/* Each option `over` gives (its bit set) copied into `v`, and marked as given there: resolving is
 * defaults, then the scene file's record, then the command line's. */
void sl_option_values_merge(sl_option_values *v, const sl_option_values *over);
/* The options that must agree with each other: diffuse-only and specular-only exclude each
 * other, a tile is a power of two. `scene` NULL: the command line's record, the message spells
 * the flags; else the name of the scene file the record was read from, and the message spells its
 * keys. */
bool sl_option_values_check(const sl_option_values *v, const char *scene, sl_error *err);
/* The field of row `id` in `v`. */
void *sl_option_field(sl_option_values *v, sl_option_id id);

/* The modes' names, from the rows above: "none", "spec", "spec-d4", "gems", "pdf"; "spec",
 * "consistent", "mf", "splitsum", "mis"; "inv-lh2", "one"; "sh9", "brute", "map", "oct", "dp"; "latlong", "oct". Parsers return false on an
 * unknown name. */
const char *sl_lod_rule_name(sl_lod_rule rule);
const char *sl_estimator_name(sl_estimator estimator);
const char *sl_gterm_name(sl_gterm gterm);
const char *sl_irradiance_name(sl_irradiance_method method);
const char *sl_env_layout_name(sl_env_layout layout);
/* The irradiance a frame gets when the scene names no map: the row's default. */
sl_irradiance_method sl_irradiance_default(void);
bool sl_lod_rule_parse(const char *name, sl_lod_rule *rule);
bool sl_estimator_parse(const char *name, sl_estimator *estimator);
bool sl_gterm_parse(const char *name, sl_gterm *gterm);

#endif
