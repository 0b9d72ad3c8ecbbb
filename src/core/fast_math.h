/* fast_math.h - branch-free float32 floor, log2, exp2 and atan2 for vectorized inner loops
 * (the lighting shader's batched path; ibl/texture_lod.h builds its fast lat-long map on
 * atan2), written so GCC vectorizes the loops that call them (`#pragma omp simd`): no calls,
 * no data-dependent branches (selects only), no tables.
 *
 * Why: the libm calls (atan2f, acosf, powf, log2f) were 45% of the lighting pass and cannot be
 * vectorized without -ffast-math (glibc declares its vector variants only then). These are
 * the classic Cephes reductions with their minimax polynomials, in plain C, and are as good as
 * the GL driver's: measured over dense sweeps (docs/performance.md "Lighting", test_shading
 * test_fast_math), atan2 within 2.6e-7 rad, log2 within 1.2e-7 absolute on [1e-30, 1], exp2
 * within 2 ulp on [-126, 0]; llvmpipe's are 1e-6 .. 1e-5 relative (tests/cli/gl_shading.sh).
 * The same inputs give the same bits whether a loop runs vectorized or scalar (only +, -, *, /,
 * sqrt, compares; -ffp-contract=off), so the pass, sl_lighting_shade and the trace agree.
 *
 * Does not: handle NaN (callers clamp first), denormals (inputs are >= 1e-30) or exp2 outside
 * [-126, 127]. */
#ifndef SL_FAST_MATH_H
#define SL_FAST_MATH_H

#include <stdint.h>
#include <string.h>

#include <softlight/glsl.h>

/* Always inlined: a call left in a `#pragma omp simd` loop stops it from vectorizing, and GCC's
 * inlining budget for a large caller (lighting_batched.c's specular_samples) runs out before every call
 * site is inlined. */
#define SL_FM_INLINE __attribute__((always_inline)) static inline

static inline uint32_t sl_fm_bits(float x)
{
    uint32_t i;
    memcpy(&i, &x, sizeof i);
    return i;
}
static inline float sl_fm_float(uint32_t i)
{
    float x;
    memcpy(&x, &i, sizeof x);
    return x;
}

/* floor(x) for |x| < 2^31, exactly floorf's value. GCC does not vectorize floorf under the
 * default -ftrapping-math; truncation to int and one compare do the same job. */
SL_FM_INLINE float sl_fast_floor(float x)
{
    int i = (int)x;
    float t = (float)i;
    return t - (x < t ? 1.0f : 0.0f);
}

/* log2(x) for normal x > 0: x = 2^e m, m in [sqrt(1/2), sqrt(2)), ln m = 2 atanh(s) with
 * s = (m - 1)/(m + 1), |s| <= 0.172, by its series to s^9 (truncation < 1e-9). */
SL_FM_INLINE float sl_fast_log2(float x)
{
    uint32_t i = sl_fm_bits(x);
    int e = (int)(i >> 23) - 127;
    float m = sl_fm_float((i & 0x007fffffu) | 0x3f800000u);
    int big = m > 1.41421356f;
    m = big ? 0.5f * m : m;
    e = big ? e + 1 : e;
    float s = (m - 1.0f) / (m + 1.0f);
    float s2 = s * s;
    float p = s2 * (1.0f / 3.0f + s2 * (1.0f / 5.0f + s2 * (1.0f / 7.0f + s2 * (1.0f / 9.0f))));
    float ln = 2.0f * s + 2.0f * s * p;
    return (float)e + ln * 1.44269504f;
}

/* 2^x for x in [-126, 127] (the caller's to guarantee: a clamp here would be a select that GCC
 * turns into branches): 2^n 2^f, n = round(x), f in [-1/2, 1/2], Cephes exp2f polynomial. */
SL_FM_INLINE float sl_fast_exp2(float x)
{
    float n = sl_fast_floor(x + 0.5f);
    float f = x - n;
    float p = 1.535336188319500e-4f;
    p = p * f + 1.339887440266574e-3f;
    p = p * f + 9.618437357674640e-3f;
    p = p * f + 5.550332471162809e-2f;
    p = p * f + 2.402264791363012e-1f;
    p = p * f + 6.931472028550421e-1f;
    p = p * f + 1.0f;
    return p * sl_fm_float((uint32_t)((int)n + 127) << 23);
}

/* atan2(y, x) in [-pi, pi]: t = min/max in [0, 1], reduced to [0, tan(pi/8)] by
 * (t - 1)/(t + 1) + pi/4, Cephes atanf polynomial, then the octant. atan2(0, 0) = 0;
 * y = -0 gives +pi for x < 0 (the lat-long map folds u = 1 to 0 either way).
 * One division: above tan(pi/8) the reduced argument is (mn - mx)/(mn + mx), the same value as
 * (t - 1)/(t + 1) without t's rounding, so the numerator and denominator are selected and
 * divided once (the division is the costly operation of a vector loop; the lighting pass runs
 * two atan2 a sample). */
SL_FM_INLINE float sl_fast_atan2(float y, float x)
{
    float ax = fabsf(x), ay = fabsf(y);
    float mx = maxf(ax, ay), mn = minf(ax, ay);
    int big = mn > 0.41421356f * mx;
    float num = big ? mn - mx : mn, den = big ? mn + mx : mx;
    float r = mx > 0.0f ? num / den : 0.0f;
    float z = r * r;
    float p = (((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z - 3.33329491539e-1f) * z * r + r;
    p = big ? p + 0.785398163f : p;
    p = ay > ax ? 1.57079633f - p : p;
    p = x < 0.0f ? 3.14159265f - p : p;
    return y < 0.0f ? -p : p;
}

#endif
