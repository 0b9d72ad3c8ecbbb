/* options.h - every option a user can set, one row each: its name, its spelling on the command
 * line and in a scene file, its default and its limits, and for the modes (lod rule, estimator,
 * G term, irradiance method) the name of each value. One limit per quantity: the largest image
 * side, the most samples, the most env lights, the most point lights are written here once.
 *
 * Read by: the command line (src/app/render_options.c, also softlight-gl's), the viewer (mode
 * names, cycling a mode, its key and script limits), the scene reader (the render and
 * environment keys), the stages' own defaults (sl_lighting_options_resolve, the tone map, the
 * rasterizer's tile size) and tests/unit/test_options.c, which checks that they all agree.
 * It lives in core because its lowest reader, the scene file (src/scene), sits directly above
 * core (core <- scene/ibl <- raster <- shading <- post <- render <- app): it holds words and
 * numbers only, and the stages name their structures' sizes from it (SL_HAMMERSLEY_MAX sizes the
 * GLSL's Hammersley block, SL_RASTER_MAX_SIZE is the rasterizer's fixed-point budget).
 * Like sokol's _sg_def, a default is resolved from one place; like Lua's luaL_checkoption, a
 * mode is parsed against one list of names.
 *
 * Does not: parse argv or JSON (src/app/args.c, src/scene/scene.c do, with these limits), or
 * hold options of one command only (softlight view --scale, truth --part). */
#ifndef SL_OPTIONS_H
#define SL_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>

/* Largest width or height of any image softlight renders: the rasterizer's fixed-point budget
 * (src/raster/rast_internal.h: 8192 lies inside its 16000-pixel guard band). The command line,
 * the scene file, the viewer's window and script, the G-buffer and the rasterizer share it. */
#define SL_RASTER_MAX_SIZE 8192
/* Most specular samples N: the GLSL's HammersleyBlock holds 512 vec4, two pairs each. */
#define SL_HAMMERSLEY_MAX 1024
/* Most env lights K: MAX_ENV_LIGHTS in the GLSL (whole groups of 16 for the batched path). */
#define SL_ENV_LIGHTS_MAX 64
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
} sl_estimator;

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

/* The rows, in the order `--help` lists them; rows past SL_OPT_CLI_COUNT have no command-line
 * spelling. */
typedef enum {
    SL_OPT_SIZE,
    SL_OPT_SAMPLES,
    SL_OPT_EXPOSURE,
    SL_OPT_CONTRAST,
    SL_OPT_SRGB,
    SL_OPT_LOD,
    SL_OPT_DISTORTION,
    SL_OPT_GTERM,
    SL_OPT_ESTIMATOR,
    SL_OPT_IRRADIANCE,
    SL_OPT_ENV_LAYOUT,
    SL_OPT_DIFFUSE_ONLY,
    SL_OPT_SPECULAR_ONLY,
    SL_OPT_NO_LIGHTS,
    SL_OPT_THREADS,
    SL_OPT_TILE,
    SL_OPT_ROTATE,
    SL_OPT_FRAME,
    SL_OPT_PLAIN,
    SL_OPT_ENV_LIGHTS,
    SL_OPT_IMAGE_MEMORY,
    SL_OPT_CLI_COUNT,
    SL_OPT_ENV_INTENSITY = SL_OPT_CLI_COUNT, /* scene file only */
    SL_OPT_COUNT
} sl_option_id;

typedef enum {
    SL_OPTION_FLAG,   /* off unless given */
    SL_OPTION_INT,
    SL_OPTION_FLOAT,
    SL_OPTION_SIZE,   /* width and height, each within [min, max] */
    SL_OPTION_CHOICE, /* one of an enum's values min .. max, each named by names[value] */
} sl_option_type;

typedef struct {
    const char *name;         /* "samples": what tests and reports call it */
    const char *cli, *alias;  /* "--samples", "-n"; NULL: not on the command line */
    const char *scene[2];     /* JSON paths in a scene file ("render.samples"); a size has two
                                 (width, height); NULL: not in a scene file */
    sl_option_type type;
    double def[2];            /* the default (a choice: its value; a size: width, height).
                                 Where a stage reads 0 as "default", 0 resolves to this */
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

/* The modes' names, from the rows above: "none", "spec", "spec-d4", "gems", "pdf"; "spec",
 * "consistent", "mf", "splitsum"; "inv-lh2", "one"; "sh9", "brute", "map", "oct", "dp"; "latlong", "oct". Parsers return false on an
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
