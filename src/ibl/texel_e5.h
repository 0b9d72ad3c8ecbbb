/* texel_e5.h - the compact texel of the lighting pass's lat-long fetch: RGB in 32 bits with a
 * shared exponent (GL's RGB9_E5 layout), scaled per chain so that a map's brightest texel fits.
 *
 * Why: the batched fetch is bound by gathered elements (docs/performance.md "Lighting"). With
 * 32-bit texels a REPEAT bilinear row pair (x0, x0 + 1) is one 64-bit read, so a trilinear
 * sample is 4 gathers (2 levels x 2 rows) instead of the float pair rows' 12.
 *
 * Layout of a texel t: bits 0-8 red mantissa, 9-17 green, 18-26 blue, 27-31 exponent e; the
 * value of a channel is m 2^(e + emin), emin being the chain's (sl_env.e5_emin). GL's RGB9_E5 has
 * a fixed emin = -24 and so a ceiling of 65408, which real HDR suns exceed; here emin is chosen
 * from the chain's brightest texel (texel_e5.c), so nothing is clamped, and texels below
 * 2^-30 of the brightest lose mantissa bits gradually (as RGB9_E5's low end does).
 *
 * Error bound: each channel is rounded to the nearest multiple of 2^(e + emin), where e is
 * the smallest exponent that holds the texel's largest channel M in 9 bits, so M is at least
 * 255.75 steps (256, or 511.5 of the step below when rounding moved it up) and every channel is
 * within half a step, M / 511.5, of its float value: relative per channel of the max channel,
 * at most 1.96e-3 (2^-9). Texels below 2^-30 of the chain's brightest (e clamped at 0) are
 * within 2^(emin - 1) absolute instead, about 2^-40 of the brightest. Decoding is exact in
 * float (a 9-bit integer times a power of two). */
#ifndef SL_TEXEL_E5_H
#define SL_TEXEL_E5_H

#include <stdint.h>

#include "../core/fast_math.h"

/* The exponent field's range and the mantissa's largest value. */
enum { SL_E5_EXP_MAX = 31, SL_E5_MANT_MAX = 511 };

/* The chain's emin for a brightest channel value max_value (finite, >= 0): the brightest texel
 * gets exponent 30 (one left for a mantissa that rounds up to 512), clamped so that every
 * 2^(e + emin) is a normal float. */
int sl_e5_emin(float max_value);

/* The texel for (r, g, b) (finite, >= 0) in a chain of exponent offset emin. */
uint32_t sl_e5_encode(float r, float g, float b, int emin);

/* The chain's layout in sl_env.e5 (env.c): one row stride, W + 1 texels (each row of a level
 * followed by a copy of its first texel, as the float pair rows), and level l's rows from row
 * sl_e5_row(H, l), so that the fetch computes a level's size and first row by shifts instead
 * of reading them from per-level tables (which a vectorized loop does with gathers: as many
 * gathered elements as the texels themselves). sl_env_build's level l is max(W >> l, 1) by
 * max(H >> l, 1) (floor halving, repeated, is a shift). Level l needs h_l <= H >> l rows, or 1
 * once H >> l is 0; the rows between sl_e5_row(H, l) and sl_e5_row(H, l + 1) are
 * ceil((2H >> l) / 2) + 1 >= max(H >> l, 1). The cost: about 2 (W + 1) H texels, 8 bytes per
 * level-0 texel, against 16 x 4/3 for the float pair rows. */
SL_FM_INLINE int sl_e5_size(int size0, int l)
{
    const int s = size0 >> l;
    return s > 1 ? s : 1;
}
SL_FM_INLINE int sl_e5_row(int H, int l)
{
    return 2 * H - ((2 * H) >> l) + l;
}

/* The texel's power of two 2^(e + emin), built from bits (bias = emin + 127, the float exponent
 * of 2^emin): its channels are its three mantissas times this. */
SL_FM_INLINE float sl_e5_scale(uint32_t t, int bias)
{
    return sl_fm_float((uint32_t)((int)(t >> 27) + bias) << 23);
}

/* The three 9-bit mantissas of t as floats (exact): shifts, masks and int-to-float conversions,
 * all of which vectorize. The fetch folds sl_e5_scale into its filter weights instead of
 * multiplying each channel by it (texture_lod.h sl_e5_bilinear). */
SL_FM_INLINE void sl_e5_mantissas(uint32_t t, float *r, float *g, float *b)
{
    *r = (float)(int)(t & 511u);
    *g = (float)(int)((t >> 9) & 511u);
    *b = (float)(int)((t >> 18) & 511u);
}

/* The three channels of t: the mantissas times the scale. */
SL_FM_INLINE void sl_e5_decode(uint32_t t, int bias, float *r, float *g, float *b)
{
    const float s = sl_e5_scale(t, bias);
    sl_e5_mantissas(t, r, g, b);
    *r *= s;
    *g *= s;
    *b *= s;
}

#endif
