/* texture_lod.h - the inline core of textureLod (texture_lod.c) and of the lat-long map, for
 * the lighting shader's inner loop, where a function call per sample and the guards of the
 * public entry point cost more than the filtering itself; and the same filter over the chain's
 * single block (sl_env_gather), which a vectorized loop turns into gathers.
 *
 * The caller guarantees what textureLod otherwise checks: env has at least one level, u is
 * finite and in [0, 1] (REPEAT already applied: 1.0 wraps to column 0 like 0.0), v finite,
 * lod finite and in [0, level_count - 1]. Under those conditions sl_texture_lod_clamped
 * returns exactly the bits textureLod returns: the same operations in the same order, and
 * when fract(lod) is 0 the second level is skipped (mix(a, b, 0) = a + (b - a) * 0 = a for
 * finite, non-negative texels, which sl_env_build guarantees). */
#ifndef SL_TEXTURE_LOD_H
#define SL_TEXTURE_LOD_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "../core/fast_math.h"
#include "ibl.h"
#include "octahedral.h"
#include "texel_e5.h"

/* Where GL_LINEAR reads a lat-long level of w x h texels at (u, v): REPEAT in u, CLAMP_TO_EDGE in
 * v, texel centres at (i + 1/2) / size. Columns x0 and x0 + 1 (wrapped: x0 = w - 1 reads column 0
 * second), rows y0 and y1, weights fx and fy of the second of each. The three fetches below (float
 * texels, pair rows, compact rows) read the same taps from this. u in [0, 1], so x in
 * [-1/2, w - 1/2] and the floor in [-1, w - 1]. Clamping the coordinate (not the index) gives
 * CLAMP_TO_EDGE: at the clamp both rows are the same or the fraction is 0. */
typedef struct {
    int x0, y0, y1;
    float fx, fy;
} sl_latlong_taps;
__attribute__((always_inline)) static inline sl_latlong_taps sl_latlong_taps_at(int w, int h, float u, float v)
{
    sl_latlong_taps t;
    float x = u * (float)w - 0.5f;
    float xf = sl_fast_floor(x);
    t.fx = x - xf;
    int x0 = (int)xf;
    t.x0 = x0 < 0 ? x0 + w : x0;
    float y = minf(maxf(v * (float)h - 0.5f, 0.0f), (float)(h - 1));
    t.y0 = (int)y;
    t.fy = y - (float)t.y0;
    t.y1 = t.y0 + 1 < h ? t.y0 + 1 : h - 1;
    return t;
}

/* GL_LINEAR within one level of w x h texels starting at T[o]: REPEAT in u, CLAMP_TO_EDGE in v,
 * texel centres at (i + 1/2) / size. The one bilinear filter of the environment: sl_env_bilinear
 * (one level) and sl_env_gather_bilinear (a level of the block) are this. Indices are int: a
 * level has at most SL_IMAGE_MAX_PIXELS texels and a gathered block fewer than 2^31 / 3, so the
 * vectorized fetch gathers with 32-bit indices; sl_fast_floor is floorf for |x| < 2^31. Texels
 * are read component by component, as floats (a struct copy stops GCC's vectorizer). */
__attribute__((always_inline)) static inline vec3 sl_texels_bilinear(const vec3 *T, int w, int h, int o, float u,
                                                                     float v)
{
    const sl_latlong_taps t = sl_latlong_taps_at(w, h, u, v);
    const int x0 = t.x0, x1 = t.x0 + 1 < w ? t.x0 + 1 : 0, y0 = t.y0, y1 = t.y1;
    const float fx = t.fx, fy = t.fy;
    /* Float offsets (3 per texel) in int: a vectorized loop then gathers with 32-bit indices
     * and scale 4; through T[i].x GCC 12 widened the index to 64 bits and emulated every gather
     * with scalar loads and inserts (the split-sum fetch's profile). Same values, same bits. */
    const float *F = &T[0].x;
    int a = 3 * (o + y0 * w + x0), b = 3 * (o + y0 * w + x1);
    int c = 3 * (o + y1 * w + x0), d = 3 * (o + y1 * w + x1);
    vec3 top = vec3(mixf(F[a], F[b], fx), mixf(F[a + 1], F[b + 1], fx), mixf(F[a + 2], F[b + 2], fx));
    vec3 bottom = vec3(mixf(F[c], F[d], fx), mixf(F[c + 1], F[d + 1], fx), mixf(F[c + 2], F[d + 2], fx));
    return mix3(top, bottom, fy);
}

/* GL_LINEAR within one level. */
static inline vec3 sl_env_bilinear(const sl_env_level *lv, float u, float v)
{
    return sl_texels_bilinear(lv->texels, lv->width, lv->height, 0, u, v);
}

/* Catmull-Rom (cubic convolution with a = -1/2) within one level, 4 x 4 texels, texel centres at
 * (i + 1/2) / size, REPEAT in u as the bilinear filter; in v a row past a pole is the row beside
 * it half a turn away in u (the sphere's own neighbour; CLAMP_TO_EDGE would repeat the first row
 * across the pole, which on the coarse levels is 11 degrees of a 16-row level). It passes
 * through the texel centres with an error of third order in the texel's size where the bilinear
 * filter's is of second: the control variate reads the chain's exact levels with it (lighting.c
 * cv_closed), whose texels are exact at their centres and whose coarse levels are a few texels a
 * lobe (32 x 16 at r = 1 on a 1024 x 512 map, where bilinear reads are 0.5-1.3% RMS off the
 * quadrature and these 0.3-0.8%). GLSL: lighting.frag's chain_catmull_rom, with texelFetch. */
static inline void sl_catmull_rom_weights(float t, float w[4])
{
    w[0] = ((-0.5f * t + 1.0f) * t - 0.5f) * t;
    w[1] = (1.5f * t - 2.5f) * t * t + 1.0f;
    w[2] = ((-1.5f * t + 2.0f) * t + 0.5f) * t;
    w[3] = (0.5f * t - 0.5f) * t * t;
}
static inline vec3 sl_env_catmull_rom(const sl_env_level *lv, float u, float v)
{
    const int w = lv->width, h = lv->height;
    float x = u * (float)w - 0.5f, y = v * (float)h - 0.5f;
    if (!(x > -2.0f && x < (float)w + 1.0f && y > -2.0f && y < (float)h + 1.0f)) /* NaN or off the map */
        return vec3s(0.0f);
    int i = (int)floorf(x), j = (int)floorf(y);
    float wx[4], wy[4];
    sl_catmull_rom_weights(x - (float)i, wx);
    sl_catmull_rom_weights(y - (float)j, wy);
    /* the columns, wrapped (i is in [-2, w]: a step of w each way, more on a level 1 or 2 texels
     * wide), and half a turn on */
    int cols[4], turned[4];
    for (int a = 0; a < 4; a++) {
        int col = i - 1 + a;
        while (col < 0)
            col += w;
        while (col >= w)
            col -= w;
        cols[a] = col;
        int t = col + w / 2;
        turned[a] = t >= w ? t - w : t;
    }
    vec3 sum = vec3s(0.0f);
    for (int b = 0; b < 4; b++) {
        int row = j - 1 + b;
        const int *c = cols;
        if (row < 0 || row > h - 1) { /* a row past a pole is the row beside it, half a turn away */
            row = row < 0 ? -row - 1 : 2 * h - row - 1;
            row = row < 0 ? 0 : row > h - 1 ? h - 1 : row;
            c = turned;
        }
        vec3 r = vec3s(0.0f);
        for (int a = 0; a < 4; a++) {
            int col = c[a];
            r = add(r, scale(lv->texels[(size_t)row * (size_t)w + (size_t)col], wx[a]));
        }
        sum = add(sum, scale(r, wy[b]));
    }
    return sum;
}

/* GL_LINEAR_MIPMAP_LINEAR between levels floor(lod) and floor(lod) + 1 (the last one twice). */
static inline vec3 sl_texture_lod_clamped(const sl_env *env, float u, float v, float lod)
{
    int last = env->level_count - 1;
    int l0 = (int)lod;
    float f = lod - (float)l0;
    vec3 a = sl_env_bilinear(&env->levels[l0], u, v);
    if (f == 0.0f)
        return a;
    int l1 = l0 < last ? l0 + 1 : last;
    vec3 b = sl_env_bilinear(&env->levels[l1], u, v);
    return mix3(a, b, f);
}

/* The specification's lat-long map (latlong.c sl_dir_to_uv) for a unit direction:
 * u = 1/2 - atan2(y, x) / (2 pi), folded into [0, 1); v = theta / pi with theta =
 * atan2(sqrt(x^2 + y^2), z), which equals acos(z) for unit d and stays accurate at the poles,
 * where acos(z) loses half its digits. */
SL_FM_INLINE void sl_fast_dir_to_uv(float x, float y, float z, float *u, float *v)
{
    float uu = 0.5f - sl_fast_atan2(y, x) * (1.0f / (2.0f * SL_PI));
    uu = uu < 1.0f ? uu : uu - 1.0f;
    *u = uu >= 0.0f ? uu : 0.0f; /* NaN -> 0 */
    float vv = sl_fast_atan2(sqrtf(x * x + y * y), z) * (1.0f / SL_PI);
    *v = vv >= 0.0f ? vv : 0.0f; /* NaN -> 0: a texel row is always in range */
}

/* The chain as one block of texels (sl_env.block), for a vectorized fetch: level l starts at
 * texel offset[l]. gather = 0 when the chain has no block or too many texels for 32-bit vec3
 * indices; every level is then described as level 0, so a vectorized loop still reads valid
 * texels (of the wrong level) and the caller redoes the fetch with sl_texture_lod_clamped. */
typedef struct {
    int gather;
    const vec3 *texels; /* the block, or level 0's texels */
    int last;           /* level_count - 1 */
    int offset[SL_ENV_MAX_LEVELS], width[SL_ENV_MAX_LEVELS], height[SL_ENV_MAX_LEVELS];
    const float *pairs; /* sl_env.pairs (NULL: none), level l's texel (x, y) at 3 (pair_offset[l] +
                           y (width + 1) + x) */
    int pair_offset[SL_ENV_MAX_LEVELS];
    const uint32_t *e5; /* sl_env.e5 (NULL: none), level l's texel (x, y) at (sl_e5_row(e5_h, l) + y)
                           (e5_w + 1) + x (texel_e5.h) */
    int e5_w, e5_h;     /* level 0's size */
    int e5_bias;        /* sl_env.e5_emin + 127: the float exponent field of 2^emin */
} sl_env_gather;

/* Describe env's chain (texture_lod.c); env must have at least one level. */
void sl_env_gather_init(sl_env_gather *g, const sl_env *env);

/* sl_env_bilinear for level l of a gather description; inlined into a simd loop it becomes
 * gathers. */
__attribute__((always_inline)) static inline vec3 sl_env_gather_bilinear(const sl_env_gather *g, int l, float u,
                                                                       float v)
{
    return sl_texels_bilinear(g->texels, g->width[l], g->height[l], g->offset[l], u, v);
}

/* sl_texture_lod_clamped over a gather description, with lod in [0, last] (no fract(lod) = 0
 * shortcut: a branch would stop the vectorizer; blending with weight 0 gives the same bits). */
__attribute__((always_inline)) static inline vec3 sl_env_gather_lod(const sl_env_gather *g, float u, float v, float lod)
{
    int l0 = (int)lod;
    float f = lod - (float)l0;
    int l1 = l0 < g->last ? l0 + 1 : g->last;
    return mix3(sl_env_gather_bilinear(g, l0, u, v), sl_env_gather_bilinear(g, l1, u, v), f);
}

/* Two floats from one 64-bit read: in a vectorized loop, one 64-bit gather instead of two
 * 32-bit ones (the fetch is bound by gathered elements, not bytes). The bits of p[0] and p[1]. */
__attribute__((always_inline)) static inline void sl_load_float2(const float *p, float *a, float *b)
{
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    uint64_t q;
    memcpy(&q, p, sizeof q);
    *a = sl_fm_float((uint32_t)q);
    *b = sl_fm_float((uint32_t)(q >> 32));
#else
    *a = p[0];
    *b = p[1];
#endif
}

/* sl_env_gather_bilinear of level l read from the pair rows (sl_env.pairs): the same texels,
 * the same operations, so the same bits; x0 wraps to w - 1 and x1 = x0 + 1 is then the copy
 * of column 0 at the row's end, so each row's two texels are the 6 floats from 3 (row + x0). */
__attribute__((always_inline)) static inline vec3 sl_pair_bilinear(const sl_env_gather *g, int l, float u, float v)
{
    const int w = g->width[l], h = g->height[l];
    const sl_latlong_taps t = sl_latlong_taps_at(w, h, u, v);
    const int x0 = t.x0, y0 = t.y0, y1 = t.y1;
    const float fx = t.fx, fy = t.fy;
    /* float indices, added to the block's base as ints: the form GCC turns into gathers
     * (a pointer moved by a constant first is not) */
    const int k0 = 3 * (g->pair_offset[l] + y0 * (w + 1) + x0), k1 = 3 * (g->pair_offset[l] + y1 * (w + 1) + x0);
    const float *P = g->pairs;
    float a0, a1, a2, a3, a4, a5, b0, b1, b2, b3, b4, b5; /* texel x0 RGB, texel x1 RGB */
    sl_load_float2(P + k0, &a0, &a1);
    sl_load_float2(P + (k0 + 2), &a2, &a3);
    sl_load_float2(P + (k0 + 4), &a4, &a5);
    sl_load_float2(P + k1, &b0, &b1);
    sl_load_float2(P + (k1 + 2), &b2, &b3);
    sl_load_float2(P + (k1 + 4), &b4, &b5);
    vec3 top = vec3(mixf(a0, a3, fx), mixf(a1, a4, fx), mixf(a2, a5, fx));
    vec3 bottom = vec3(mixf(b0, b3, fx), mixf(b1, b4, fx), mixf(b2, b5, fx));
    return mix3(top, bottom, fy);
}

/* sl_env_gather_lod from the pair rows (g->pairs must be set): the same bits. */
__attribute__((always_inline)) static inline vec3 sl_pair_gather_lod(const sl_env_gather *g, float u, float v,
                                                                    float lod)
{
    int l0 = (int)lod;
    float f = lod - (float)l0;
    int l1 = l0 < g->last ? l0 + 1 : g->last;
    return mix3(sl_pair_bilinear(g, l0, u, v), sl_pair_bilinear(g, l1, u, v), f);
}

/* sl_pair_bilinear from the compact rows (sl_env.e5, texel_e5.h), times a weight wl (the
 * trilinear filter's weight of level l): the same texel positions and filter, on texels within
 * 1.96e-3 of the max channel of the float ones; each row's two texels are one 64-bit read.
 * Written as one weight per texel, wl times its bilinear weight times its power of two
 * (sl_e5_scale), applied to its mantissas: the decode's multiply by the scale and the filter's
 * mixes become one multiply and add a channel (the mixes' a + (b - a) f, as
 * (1 - f) a + f b; the same value to float rounding). */
__attribute__((always_inline)) static inline vec3 sl_e5_bilinear(const sl_env_gather *g, int l, float u, float v,
                                                               float wl)
{
    const int w = sl_e5_size(g->e5_w, l), h = sl_e5_size(g->e5_h, l); /* shifts, not table reads */
    const sl_latlong_taps t = sl_latlong_taps_at(w, h, u, v);
    const int x0 = t.x0, y0 = t.y0, y1 = t.y1;
    const float fx = t.fx, fy = t.fy;
    const int row = sl_e5_row(g->e5_h, l), stride = g->e5_w + 1;
    const int k0 = (row + y0) * stride + x0, k1 = (row + y1) * stride + x0;
    uint64_t q0, q1;
    memcpy(&q0, g->e5 + k0, sizeof q0);
    memcpy(&q1, g->e5 + k1, sizeof q1);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    const uint32_t t00 = (uint32_t)q0, t10 = (uint32_t)(q0 >> 32), t01 = (uint32_t)q1, t11 = (uint32_t)(q1 >> 32);
#else
    const uint32_t t00 = (uint32_t)(q0 >> 32), t10 = (uint32_t)q0, t01 = (uint32_t)(q1 >> 32), t11 = (uint32_t)q1;
#endif
    const int bias = g->e5_bias;
    const float top = wl * (1.0f - fy), bottom = wl * fy;
    const float w00 = top * (1.0f - fx) * sl_e5_scale(t00, bias), w10 = top * fx * sl_e5_scale(t10, bias);
    const float w01 = bottom * (1.0f - fx) * sl_e5_scale(t01, bias), w11 = bottom * fx * sl_e5_scale(t11, bias);
    float a0, a1, a2, a3, a4, a5, b0, b1, b2, b3, b4, b5; /* mantissas: texel x0 RGB, texel x1 RGB */
    sl_e5_mantissas(t00, &a0, &a1, &a2);
    sl_e5_mantissas(t10, &a3, &a4, &a5);
    sl_e5_mantissas(t01, &b0, &b1, &b2);
    sl_e5_mantissas(t11, &b3, &b4, &b5);
    return vec3((w00 * a0 + w10 * a3) + (w01 * b0 + w11 * b3), (w00 * a1 + w10 * a4) + (w01 * b1 + w11 * b4),
                (w00 * a2 + w10 * a5) + (w01 * b2 + w11 * b5));
}

/* sl_pair_gather_lod from the compact rows (g->e5 must be set): 4 64-bit reads a sample; the
 * levels weighted 1 - f and f (mix's value to float rounding; f = 0 gives level l0's exactly,
 * as level l1's finite texels then add +0). */
__attribute__((always_inline)) static inline vec3 sl_e5_gather_lod(const sl_env_gather *g, float u, float v, float lod)
{
    int l0 = (int)lod;
    float f = lod - (float)l0;
    int l1 = l0 < g->last ? l0 + 1 : g->last;
    return add(sl_e5_bilinear(g, l0, u, v, 1.0f - f), sl_e5_bilinear(g, l1, u, v, f));
}

/* ---- The octahedral layout (env_oct.c): the same trilinear filter over S x S levels whose
 * outer edge folds onto itself ---- */

/* Octahedral coordinates of direction d (need not be unit; the lighting shader's
 * env_oct_uv): p = d.xy / |d|_1, folded below the equator to ((1 - |p.y|) sgn p.x,
 * (1 - |p.x|) sgn p.y) with sgn 0 = +1; (u, v) = (p + 1) / 2, clamped to [0, 1] (a zero or NaN
 * d gives 0). Divisions and selects only: the port and the batched path get the same bits. */
SL_FM_INLINE void sl_oct_dir_to_uv(float x, float y, float z, float *u, float *v)
{
    float px, py;
    sl_oct_fold(x, y, z, &px, &py);
    float uu = px * 0.5f + 0.5f, vv = py * 0.5f + 0.5f;
    *u = uu >= 0.0f ? minf(uu, 1.0f) : 0.0f; /* NaN -> 0 */
    *v = vv >= 0.0f ? minf(vv, 1.0f) : 0.0f;
}

/* The unit direction at octahedral (u, v) in [0, 1]^2: the inverse of sl_oct_dir_to_uv. */
static inline vec3 sl_oct_uv_to_dir(float u, float v)
{
    float px = 2.0f * u - 1.0f, py = 2.0f * v - 1.0f;
    float z = 1.0f - fabsf(px) - fabsf(py);
    float x = z < 0.0f ? (1.0f - fabsf(py)) * (px >= 0.0f ? 1.0f : -1.0f) : px;
    float y = z < 0.0f ? (1.0f - fabsf(px)) * (py >= 0.0f ? 1.0f : -1.0f) : py;
    return normalize(vec3(x, y, z));
}

/* Texel index (y s + x) of tap (x, y), x and y in [-1, s]: a tap past the outer edge reads the
 * texel mirrored across it ((-1, y) is (0, s - 1 - y); (x, -1) is (s - 1 - x, 0)), the
 * direction on the other side of the fold; past a corner both, which lands on the opposite
 * corner (all four are -Z). */
__attribute__((always_inline)) static inline int sl_oct_tap(int s, int x, int y)
{
    int xo = x < 0 || x >= s;
    x = x < 0 ? 0 : (x >= s ? s - 1 : x);
    y = xo ? s - 1 - y : y;
    int yo = y < 0 || y >= s;
    y = y < 0 ? 0 : (y >= s ? s - 1 : y);
    x = yo ? s - 1 - x : x;
    return y * s + x;
}

/* GL_LINEAR within one s x s octahedral level starting at T[o], u and v in [0, 1], texel
 * centres at (i + 1/2) / s, the four taps through sl_oct_tap; blended as sl_texels_bilinear. */
__attribute__((always_inline)) static inline vec3 sl_oct_texels_bilinear(const vec3 *T, int s, int o, float u, float v)
{
    float x = u * (float)s - 0.5f, y = v * (float)s - 0.5f;
    float xf = sl_fast_floor(x), yf = sl_fast_floor(y);
    float fx = x - xf, fy = y - yf;
    int x0 = (int)xf, y0 = (int)yf;
    int t00 = o + sl_oct_tap(s, x0, y0), t10 = o + sl_oct_tap(s, x0 + 1, y0);
    int t01 = o + sl_oct_tap(s, x0, y0 + 1), t11 = o + sl_oct_tap(s, x0 + 1, y0 + 1);
    vec3 top = vec3(mixf(T[t00].x, T[t10].x, fx), mixf(T[t00].y, T[t10].y, fx), mixf(T[t00].z, T[t10].z, fx));
    vec3 bottom = vec3(mixf(T[t01].x, T[t11].x, fx), mixf(T[t01].y, T[t11].y, fx), mixf(T[t01].z, T[t11].z, fx));
    return mix3(top, bottom, fy);
}

/* sl_texture_lod_clamped for an octahedral chain: u, v in [0, 1], lod in [0, level_count - 1]. */
static inline vec3 sl_oct_lod_clamped(const sl_env *env, float u, float v, float lod)
{
    int last = env->level_count - 1;
    int l0 = (int)lod;
    float f = lod - (float)l0;
    const sl_env_level *a = &env->levels[l0];
    vec3 c = sl_oct_texels_bilinear(a->texels, a->width, 0, u, v);
    if (f == 0.0f)
        return c;
    const sl_env_level *b = &env->levels[l0 < last ? l0 + 1 : last];
    return mix3(c, sl_oct_texels_bilinear(b->texels, b->width, 0, u, v), f);
}

/* sl_env_gather_lod for an octahedral chain's block (the same bits as sl_oct_lod_clamped). */
__attribute__((always_inline)) static inline vec3 sl_oct_gather_lod(const sl_env_gather *g, float u, float v, float lod)
{
    int l0 = (int)lod;
    float f = lod - (float)l0;
    int l1 = l0 < g->last ? l0 + 1 : g->last;
    return mix3(sl_oct_texels_bilinear(g->texels, g->width[l0], g->offset[l0], u, v),
                sl_oct_texels_bilinear(g->texels, g->width[l1], g->offset[l1], u, v), f);
}

/* The guarded entry point for an octahedral chain, as textureLod is for lat-long
 * (texture_lod.c): direction d, NaN lod as 0; an empty env gives 0. */
vec3 sl_oct_texture_lod(const sl_env *env, vec3 d, float lod);

#endif
