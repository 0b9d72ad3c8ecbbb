/* tonemap.c - the specification's exposure / gamma tone map and the sRGB curves (tonemap.h),
 * and the display image: tone map, encode and 8-bit presentation in one pass.
 *
 * Why a table and not powf: powf is a libm call that GCC does not vectorize without
 * -ffast-math, and at 1280x720 it alone took 30 ms a frame on 2 cores, against a budget of
 * 2 ms for the whole presentation. The displayed value of a channel is an 8-bit code, and the
 * code is a step function of x = eC/(eC + 1): it is k exactly when T[k] <= x < T[k+1], where
 * the 255 thresholds T[k] (the smallest float x whose exact curve value rounds to k) are found
 * once per call by bisection over the float bits with the exact curve itself. Per value the
 * loop computes x exactly as sl_tonemap_value does, guesses the code with the vectorizable
 * log2/exp2 of core/fast_math.h, and accepts it when T[code] <= x < T[code+1] (two reads from
 * a 1 KB table); a value whose guess misses (a code boundary within the guess's rounding, or a
 * denormal x) is redone by bisection over T. So each code is the exact curve's, bit for bit,
 * as long as the exact curve never decreases between two floats, which tests/unit/test_tonemap.c
 * checks around every threshold. */
#include "tonemap.h"

#include <math.h>
#include <stdint.h>

#include "../core/fast_math.h"
#include "../core/options.h"

#ifdef __clang__
/* Under -fsanitize (the fuzz build) clang cannot vectorize the `omp simd` loops below (UBSan's
 * checks on the float-to-int conversions) and reports it as an error with -Werror; they stay
 * correct scalar loops there. */
#pragma clang diagnostic ignored "-Wpass-failed"
#endif

float sl_srgb_to_linear(float c)
{
    c = c > 0.0f ? (c < 1.0f ? c : 1.0f) : 0.0f;
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

float sl_linear_to_srgb(float c)
{
    c = c > 0.0f ? (c < 1.0f ? c : 1.0f) : 0.0f;
    return c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
}

float sl_gamma_to_linear(float c)
{
    c = c > 0.0f ? (c < 1.0f ? c : 1.0f) : 0.0f;
    return powf(c, 2.2f);
}

float sl_linear_to_gamma(float c)
{
    c = c > 0.0f ? (c < 1.0f ? c : 1.0f) : 0.0f;
    return powf(c, 1.0f / 2.2f);
}

/* x = eC / (eC + 1) in [0, 1]. `!(C > 0)` catches NaN as well as C <= 0. eC/(eC + 1) would be
 * Inf/Inf = NaN for eC = +Inf and loses nothing when written as 1 - 1/(eC + 1) for eC > 1.
 * Inlined into the vector loop: it must stay the same operations in the same order. */
static inline float tonemap_x(float C, float exposure)
{
    /* both quotients, then a select: a division under a condition keeps GCC from vectorizing */
    float ec = exposure * C;
    ec = C > 0.0f ? ec : 0.0f;
    float below = ec / (ec + 1.0f), above = 1.0f - 1.0f / (ec + 1.0f);
    return ec < 1.0f ? below : above;
}

static float tonemap_curve(float x, float contrast, bool exact_srgb)
{
    if (exact_srgb)
        return sl_linear_to_srgb(powf(x, contrast));
    return powf(x, contrast / 2.2f);
}

float sl_tonemap_value(float C, float exposure, float contrast, bool exact_srgb)
{
    return tonemap_curve(tonemap_x(C, exposure), contrast, exact_srgb);
}

void sl_tonemap_thresholds(float contrast, bool exact_srgb, float t[257])
{
    /* Non-negative floats order as their bits: bisect over the bits of [0, 1]. */
    const uint32_t one = sl_fm_bits(1.0f);
    t[0] = 0.0f;
    uint32_t lo = 0;
    for (int k = 1; k <= 255; k++) {
        /* the smallest x in [lo, 1] with code(x) >= k; code(1) = 255, so one exists */
        uint32_t a = lo, b = one;
        while (a < b) {
            uint32_t mid = a + (b - a) / 2;
            if (sl_unorm8(tonemap_curve(sl_fm_float(mid), contrast, exact_srgb)) >= k)
                b = mid;
            else
                a = mid + 1;
        }
        t[k] = sl_fm_float(a);
        lo = a;
    }
    t[256] = INFINITY; /* no x reaches code 256 */
}

int sl_tonemap_code(float x, const float t[257])
{
    int a = 0, b = 255; /* the largest k with t[k] <= x; t[0] = 0 <= x */
    while (a < b) {
        int mid = (a + b + 1) / 2;
        if (t[mid] <= x)
            a = mid;
        else
            b = mid - 1;
    }
    return a;
}

/* A guess at the code of x, within one of it almost always: the curve through fast_math.h's
 * log2 and exp2 (a few 1e-7 relative). x is first raised to `xmin`, which keeps every exponent
 * within exp2's range (guess_floor); below it the code is 0 anyway. Selects on inputs and
 * outputs only: a clamp between log2 and exp2 stops GCC from vectorizing the loop. */
SL_FM_INLINE float code_of(float v)
{
    v = v * 255.0f + 0.5f; /* the code plus a fraction, truncated where it is used */
    return v > 0.0f ? (v < 255.0f ? v : 255.0f) : 0.0f;
}
SL_FM_INLINE float guess_gamma(float x, float xmin, float g)
{
    return code_of(sl_fast_exp2(sl_fast_log2(x > xmin ? x : xmin) * g));
}
SL_FM_INLINE float guess_srgb(float x, float xmin, float contrast)
{
    float l = sl_fast_log2(x > xmin ? x : xmin);
    float y = sl_fast_exp2(l * contrast);
    float s = 1.055f * sl_fast_exp2(l * (contrast / 2.4f)) - 0.055f;
    return code_of(y <= 0.0031308f ? 12.92f * y : s);
}
/* The smallest x the guesses take: 1e-30 (fast log2's range), or where x^p reaches 2^-125 for
 * the largest exponent p (exp2's range); the exact code there is 0 for any sane curve, and
 * where it is not, the guess misses and the value is redone exactly. */
static float guess_floor(float p)
{
    float l = -125.0f / p;
    return l > -99.0f ? exp2f(l) : 1e-30f;
}

/* One chunk of values: x into xs, the accepted code's level into dst, -1 where the guess
 * missed; returns the number of misses. Three loops, because GCC 12 vectorizes each but not
 * the three fused. */
static int present_chunk(const float *restrict src, float *restrict dst, float *restrict xs, float *restrict ks,
                         int count, float e, float c, bool exact, const float *restrict t,
                         const float *restrict level)
{
#pragma omp simd
    for (int i = 0; i < count; i++)
        xs[i] = tonemap_x(src[i], e);
    const float g = c / 2.2f, xmin = guess_floor(exact ? c : g);
    if (exact) {
#pragma omp simd
        for (int i = 0; i < count; i++)
            ks[i] = guess_srgb(xs[i], xmin, c);
    } else {
#pragma omp simd
        for (int i = 0; i < count; i++)
            ks[i] = guess_gamma(xs[i], xmin, g);
    }
    int missed = 0;
#pragma omp simd reduction(+ : missed)
    for (int i = 0; i < count; i++) {
        float x = xs[i];
        int k = (int)ks[i];
        float lo = t[k], hi = t[k + 1], v = level[k];
        int hit = (lo <= x) & (x < hi);
        dst[i] = hit ? v : -1.0f;
        missed += 1 - hit;
    }
    return missed;
}

/* Values per task: 16 KB of x beside 16 KB in and out, within L1 and L2. */
#define TONEMAP_CHUNK 4096

bool sl_tonemap_image(const sl_image *in, sl_image *out, const sl_tonemap_options *opt, sl_error *err)
{
    float e = opt && opt->exposure != 0.0f ? opt->exposure : (float)sl_options[SL_OPT_EXPOSURE].def[0];
    float c = opt && opt->contrast != 0.0f ? opt->contrast : (float)sl_options[SL_OPT_CONTRAST].def[0];
    bool exact = opt && opt->exact_srgb;
    if (!(isfinite(e) && e > 0.0f) || !(isfinite(c) && c > 0.0f))
        return sl_fail(err, SL_ERR_RANGE, "tone map: exposure %g and contrast %g must be finite and > 0", (double)e,
                       (double)c);
    if (!in->data || in->channels != 3)
        return sl_fail(err, SL_ERR_RANGE, "tone map: input must be a 3-channel image");
    if (out->data) {
        if (out->width != in->width || out->height != in->height || out->channels != 3)
            return sl_fail(err, SL_ERR_RANGE, "tone map: output is %dx%dx%d, expected %dx%dx3", out->width,
                           out->height, out->channels, in->width, in->height);
    } else if (!sl_image_alloc(out, in->width, in->height, 3, err)) {
        return false;
    }
    float t[257], level[256];
    sl_tonemap_thresholds(c, exact, t);
    for (int k = 0; k < 256; k++)
        level[k] = (float)k / 255.0f; /* sl_unorm8 gives k back (test_tonemap) */
    const size_t n = (size_t)in->width * (size_t)in->height * 3;
    const long chunks = (long)((n + TONEMAP_CHUNK - 1) / TONEMAP_CHUNK);
#pragma omp parallel for schedule(static)
    for (long ci = 0; ci < chunks; ci++) {
        const size_t i0 = (size_t)ci * TONEMAP_CHUNK;
        const int count = (int)(n - i0 < TONEMAP_CHUNK ? n - i0 : TONEMAP_CHUNK);
        float xs[TONEMAP_CHUNK]; /* x of each value, also for the misses (out may be in itself) */
        float ks[TONEMAP_CHUNK]; /* the guessed codes (+ a fraction) */
        float *dst = out->data + i0;
        int missed = present_chunk(in->data + i0, dst, xs, ks, count, e, c, exact, t, level);
        for (int i = 0; missed && i < count; i++)
            if (dst[i] < 0.0f) {
                dst[i] = level[sl_tonemap_code(xs[i], t)];
                missed--;
            }
    }
    return true;
}
