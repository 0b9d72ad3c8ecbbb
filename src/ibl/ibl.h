/* ibl.h - the environment side of image-based lighting.
 *
 * Consumes: an equirectangular (lat-long) linear HDR image, row 0 = top = v 0.
 * Produces, once per environment: a mip chain read by textureLod, a Hammersley
 * set, irradiance for the diffuse term (SH9, a brute-force map, or a loaded
 * map), and a double-precision ground-truth integrator for tests and reports (ground_truth.h).
 * docs/ibl.md has the conventions in one table and the measured accuracy and speed.
 *
 * Conventions (docs/conventions.md "Coordinate frames", the specification's eq. (4)):
 *   direction -> uv:  u = 1/2 - atan2(d.y, d.x) / (2 pi),  v = acos(d.z) / pi
 *   uv -> direction:  (cos(2 pi (1/2 - u)) sin(pi v), sin(2 pi (1/2 - u)) sin(pi v), cos(pi v))
 *   textureLod: GL_LINEAR_MIPMAP_LINEAR, texel centres at (i + 0.5) / size,
 *   REPEAT in u, CLAMP_TO_EDGE in v, lod clamped to [0, level_count - 1].
 *
 * Does not: rotate or scale the environment (the lighting shader's uniforms do
 * that, as the GLSL does), or own the BRDF (src/shading). */
#ifndef SL_IBL_H
#define SL_IBL_H

#include <stdbool.h>
#include <stdint.h>

#include <softlight/glsl.h>

#include "../core/error.h"
#include "../core/image.h"
#include "../core/options.h" /* SL_HAMMERSLEY_MAX, sl_irradiance_method */

#define SL_ENV_MAX_LEVELS 16

/* One mip level: width * height RGB texels, row 0 = top (v = 0). */
typedef struct {
    int width, height;
    vec3 *texels;
} sl_env_level;

/* An environment map with its full mip chain down to 1x1: lat-long (env.c) or octahedral
 * (env_oct.c, layout SL_ENV_LAYOUT_OCT: S x S levels, docs/ibl.md "Specular layouts"). */
typedef struct {
    sl_env_layout layout; /* 0 or SL_ENV_LAYOUT_LATLONG: lat-long; SL_ENV_LAYOUT_OCT: octahedral */
    int level_count;
    sl_env_level levels[SL_ENV_MAX_LEVELS];
    vec3 *block; /* sl_env_build: ONE allocation holding every level, level 0 first, each level's
                    texels right after the previous level's, so a texel of any level has one
                    index from here (the lighting shader's vectorized fetch). NULL: each level
                    is its own allocation. sl_env_free handles both. */
    float *pairs; /* sl_env_build, lat-long chains of at most
                     SL_ENV_PAIRS_MAX_TEXELS texels: the chain again, level after level, each
                     row of w texels followed by a copy of its first (w + 1 texels of 3
                     floats), so the two texels a REPEAT bilinear reads in a row are always
                     6 consecutive floats (texture_lod.h sl_pair_bilinear: three 64-bit reads
                     instead of six 32-bit ones). NULL for larger chains and other layouts,
                     which the fetch reads from `block`. */
    uint32_t *e5; /* sl_env_build, lat-long chains of at most SL_ENV_PAIRS_MAX_TEXELS texels: the
                     pair rows again in the compact shared-exponent texel (texel_e5.h, 32 bits,
                     channel error at most 1.96e-3 of the texel's max channel), so a bilinear
                     row pair is one 64-bit read: the lighting pass's specular fetch
                     (texture_lod.h sl_e5_gather_lod). sl_env_prefilter too (without pair rows):
                     the split-sum fetch (lighting_splitsum.c fetch_chain). NULL where `pairs`
                     is (too large, other layouts). */
    int e5_emin;  /* the chain's exponent offset: a channel is m 2^(e + e5_emin) */
} sl_env;
/* 2^22 texels: a 2048 x 1024 map's chain (2.8 Mi texels, 34 MB more); a 4096 x 2048 one gets none. */
#define SL_ENV_PAIRS_MAX_TEXELS ((size_t)1 << 22)

/* Build the chain from a 3-channel image: level k+1 is max(1, floor(size / 2)) per axis down
 * to 1x1, each texel the exact area average of what it covers (2x2 box for even sizes; env.c).
 * Rejects images that are not 3-channel, have a side outside 1 .. 65535, or hold a NaN, Inf or
 * negative texel. On failure env is left empty. */
bool sl_env_build(sl_env *env, const sl_image *img, int threads, sl_error *err);
void sl_env_free(sl_env *env);

/* The octahedral chain of a lat-long environment (env_oct.c): size texels a side, a power of
 * two up to SL_ENV_OCT_MAX_SIZE, 0 = sl_env_oct_default_size (the smallest power of two >= the
 * lat-long width). Level 0 resampled from the lat-long chain, each level above the solid-angle-
 * weighted mean of the one below, so all hold the same power. On failure oct is left empty. */
#define SL_ENV_OCT_MAX_SIZE 4096
bool sl_env_build_oct(sl_env *oct, const sl_env *latlong, int size, int threads, sl_error *err);
int sl_env_oct_default_size(const sl_env *latlong);
/* The exact solid angle of texel (i, j) of a size x size octahedral level (size a power of two). */
double sl_env_oct_texel_solid_angle(int size, int i, int j);

/* The split-sum method's prefiltered chain (prefilter.c; --estimator splitsum): level k the
 * environment convolved with the reflection lobe of width r = k / (levels - 1) at N = V = R,
 * lat-long, with the sizes of the environment's mip chain (level 0, r = 0, is the environment's
 * level 0). Width r is GGX's perceptual roughness; a Phong exponent alpha has width
 * (2 / (alpha + 2))^(1/4) (equal peak of D, brdf.h). Zero fields are defaults. */
#define SL_PREFILTER_LEVELS 6   /* widths 0, 0.2, .. 1: the r = 1 lobe needs no more than 32x16 of a 1024x512 map */
#define SL_PREFILTER_SAMPLES 64 /* per texel of level 1, doubling per level; docs/lighting.md "Split sum" */
typedef struct {
    bool ggx;    /* the GGX lobe, else the Phong set's */
    bool g_one;  /* the Phong set's G / ((L.N)(V.N)) is 1 (--g one), else 1 / (L.H)^2 */
    int levels;  /* 1 .. SL_ENV_MAX_LEVELS; 0 = SL_PREFILTER_LEVELS */
    int samples; /* 1 .. SL_HAMMERSLEY_MAX; 0 = SL_PREFILTER_SAMPLES */
    int threads; /* 0 = all cores */
} sl_prefilter_desc;
bool sl_env_prefilter(sl_env *out, const sl_env *src, const sl_prefilter_desc *desc, sl_error *err);
/* The lobe width of level k of a chain of `levels`. */
float sl_prefilter_width(int level, int levels);

/* Levels of width at least SL_PREFILTER_EXACT_WIDTH are not sampled but summed over every texel
 * of the source (prefilter.c "Exact levels"): their texel at direction d is the self-normalised
 * quadrature of the kernel below against the environment, so a reader that knows the kernel
 * knows what the level integrates (the control variate, docs/lighting.md "Control variate").
 * The sum runs over a source level at most SL_PREFILTER_EXACT_MAX_WIDTH texels wide, to a grid
 * that the level's texel centres read with a Catmull-Rom filter. */
#define SL_PREFILTER_EXACT_WIDTH 0.4f
#define SL_PREFILTER_EXACT_MAX_WIDTH 256
/* The first exact level of a chain of `levels` (levels when none is). */
int sl_prefilter_first_exact(int levels);

/* A level's kernel: the density of w about d, k(w) = D(h) G'(w.d) (w.d) / (4 Z), h the half
 * vector of w and d, at N = V = d (the prefilter's weight times the density of its samples),
 * normalised by Z to integrate to 1 over the sphere. It depends on w only through c = w.d. */
typedef struct {
    bool ggx, g_one;
    float a2;       /* GGX: a^2 of the level's width */
    float alpha;    /* the Phong set: the exponent of equal peak */
    float inv_norm; /* 1 / Z */
} sl_prefilter_kernel;
sl_prefilter_kernel sl_prefilter_kernel_of(int level, int levels, bool ggx, bool g_one);
/* k at c = w.d: 0 for c <= 0. (nh2 = (1 + c) / 2 is (d.h)^2.) */
static inline float sl_prefilter_kernel_eval(const sl_prefilter_kernel *k, float c)
{
    if (!(c > 0.0f))
        return 0.0f;
    float nh2 = 0.5f * (1.0f + c);
    float D, G;
    if (k->ggx) {
        float t = (1.0f - nh2) + nh2 * k->a2;
        D = k->a2 / (SL_PI * t * t);
        G = 2.0f / (c + sqrtf(c * c * (1.0f - k->a2) + k->a2));
    } else {
        D = (k->alpha + 2.0f) / (2.0f * SL_PI) * powf(nh2, 0.5f * k->alpha);
        G = k->g_one ? 1.0f : 1.0f / fmaxf(nh2, 1e-6f);
    }
    return 0.25f * D * G * c * k->inv_norm;
}
/* The samples per texel of level k >= 1 for `samples` at level 1: doubled per level, at most
 * SL_HAMMERSLEY_MAX (`samples` is 1 .. SL_HAMMERSLEY_MAX). */
int sl_prefilter_samples(int level, int samples);

/* The specification's lat-long map, both ways (latlong.c). u is in [0, 1) (the seam direction
 * (-1, 0, 0) gives u = 0 for either sign of zero), z is clamped before acos: never NaN. */
vec2 sl_dir_to_uv(vec3 d);
vec3 sl_uv_to_dir(vec2 uv);

/* Rec. 709 luminance of a linear radiance: what the sky maps' cells are weighted by and the env
 * lights' clusters ranked by (src/shadow). */
static inline float sl_luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/* GLSL textureLod(sampler2D, uv, lod) for the environment (texture_lod.c). Non-finite uv reads
 * as 0, NaN lod as 0; never reads out of bounds; an empty env gives 0. */
vec3 sl_env_texture_lod(const sl_env *env, vec2 uv, float lod);
/* GLSL's textureLod as glsl.h spells it, with the environment as its other overload, chosen by
 * the first argument as glsl.h's overloads are. */
#undef textureLod
#define textureLod(s, uv, lod)                                                                              \
    _Generic((s), sl_sampler2D *: sl_texture_lod, const sl_sampler2D *: sl_texture_lod, default: sl_env_texture_lod)( \
        s, uv, lod)

/* The specification's low-discrepancy set (hammersley.c): u = radical inverse of k
 * in base 2, v = (k + 0.5) / n, for k = 0 .. n - 1. Layout matches the GLSL block. */
typedef struct {
    int n;
    vec2 points[SL_HAMMERSLEY_MAX];
} sl_hammersley;
bool sl_hammersley_build(sl_hammersley *set, int n, sl_error *err);

/* Irradiance E(n) = integral of L(w) max(0, n.w) dw, so the diffuse term is Kd/pi * E(n)
 * (irradiance.c). */
typedef struct {
    sl_irradiance_method method;
    /* SH9: coefficients pre-multiplied by the cosine lobe's A_l, so E(n) = sum sh_i Y_i(n) with,
     * for unit n = (x, y, z), in this order (l, m) = (0,0) (1,-1) (1,0) (1,1) (2,-2) (2,-1) (2,0)
     * (2,1) (2,2):  Y = 0.282095;  0.488603 y, z, x;  1.092548 xy, yz;  0.315392 (3z^2 - 1);
     * 1.092548 xz;  0.546274 (x^2 - y^2). */
    vec3 sh[9];
    sl_env map;     /* every method but SH9: the irradiance map (one level; bilinear lookup) */
    int bright_nodes, group_nodes; /* OCT and DP: what the build summed (for reports) */
} sl_irradiance;

/* Each builder overwrites *irr (sl_irradiance_free an old one first); on failure *irr is empty. */
bool sl_irradiance_sh9(sl_irradiance *irr, const sl_env *env, sl_error *err);
/* map_width x max(1, map_width / 2) texels (1 <= map_width <= 4096), integrated over the finest
 * mip level with at most SL_IRRADIANCE_BRUTE_TEXELS texels (sl_irradiance_brute_default_level);
 * _level names the level. docs/ibl.md has the measured error of each choice. */
#define SL_IRRADIANCE_BRUTE_TEXELS (256 * 128)
bool sl_irradiance_brute(sl_irradiance *irr, const sl_env *env, int map_width, int threads, sl_error *err);
bool sl_irradiance_brute_level(sl_irradiance *irr, const sl_env *env, int map_width, int level, int threads, sl_error *err);
int sl_irradiance_brute_default_level(const sl_env *env);
/* OCT and DP (irradiance_map.c): E at the map's texels from level 0, the brightest texels as
 * exact nodes and the rest grouped by the texel grid of one mip level (docs/ibl.md). Zero fields
 * are defaults. The lookup is sl_irradiance_eval (one bilinear fetch; uv below). */
#define SL_IRRADIANCE_MAP_SIZE 129       /* texels per side (DP: per half) */
#define SL_IRRADIANCE_MAP_GROUPS (32 * 16)  /* the finest level with at most this many texels groups the rest */
#define SL_IRRADIANCE_BRIGHT_MAX 4096    /* at most this many bright texels summed exactly */
#define SL_IRRADIANCE_BRIGHT_SHARE 0.25  /* bright: a texel with more power than this share of an average group */
typedef struct {
    sl_irradiance_method method; /* OCT or DP (SH9 = 0 means OCT) */
    int size;                    /* odd, 3 .. 1025: texels per side, DP per half; 0 = SL_IRRADIANCE_MAP_SIZE */
    int source_level;            /* the level whose grid groups the rest; 0 = default (see above) */
    int bright_max;              /* 0 = SL_IRRADIANCE_BRIGHT_MAX, -1 = none (groups only) */
    bool exact;                  /* every level-0 texel an exact node (slow: for measurements) */
    int threads;                 /* 0 = all cores */
} sl_irradiance_map_desc;
bool sl_irradiance_map(sl_irradiance *irr, const sl_env *env, const sl_irradiance_map_desc *desc, sl_error *err);
int sl_irradiance_map_default_source_level(const sl_env *env);
/* Texture coordinates of a unit direction in the S x S octahedral map and the 2S x S
 * dual-paraboloid map (texel centres at (i + 1/2) / size, clamped to the outer texel centres). */
vec2 sl_irradiance_oct_uv(vec3 n, int size);
vec2 sl_irradiance_dp_uv(vec3 n, int size);
bool sl_irradiance_from_image(sl_irradiance *irr, const sl_image *map, sl_error *err);
/* n unit length; the result is clamped at 0 (SH9 can ring below it; NaN also gives 0). */
vec3 sl_irradiance_eval(const sl_irradiance *irr, vec3 n);
/* The directions sl_irradiance_eval_span looks up per vector loop (its uv scratch on the stack). */
enum { SL_IRRADIANCE_SPAN = 64 };

/* sl_irradiance_eval of the directions (x[i], y[i], z[i]), i < count, into e{r,g,b}[i]: the same
 * bits for every method. SH9 and the pole-free maps (OCT, DP) run as vector loops; the lat-long
 * maps (BRUTE, MAP) a direction at a time (irradiance.c says why). Non-finite directions are
 * safe, as in sl_irradiance_eval. */
void sl_irradiance_eval_span(const sl_irradiance *irr, int count, const float *x, const float *y, const float *z,
                             float *er, float *eg, float *eb);
void sl_irradiance_free(sl_irradiance *irr);

#endif
