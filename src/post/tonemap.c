/* tonemap.c - the specification's exposure / gamma tone map and the sRGB curves (tonemap.h),
 * and the display image: tone map, encode and 8-bit presentation in one pass.
 *
 * Why a table and not powf: powf is a libm call that GCC does not vectorize without
 * -ffast-math, and at 1280x720 it alone takes 30 ms a frame on 2 cores, against a budget of
 * 2 ms for the whole presentation. The displayed value of a channel is an 8-bit code, and the
 * code is a step function of x = eC/(eC + 1): it is k exactly when T[k] <= x < T[k+1], where
 * the 255 thresholds T[k] (the smallest float x whose exact curve value rounds to k) are found
 * by bisection over the float bits with the exact curve itself. x is in turn a function of
 * ec = eC alone, so the code steps at thresholds U[k] of ec too (found by bisection with x's own
 * two divisions, and checked: ec_threshold says why that check makes them exact). Per value the
 * loop then needs no division and no curve: ec's top 16 bits (exponent and 7 mantissa bits)
 * pick a segment of a 22 KB table, which says the code below and above the one threshold inside
 * it; ec's low 16 bits against the threshold's pick one of the two. A segment with two or more
 * thresholds (very high contrast), or near a threshold that failed its check, goes to the exact
 * path (x, then bisection over T). So each code is the exact curve's, bit for bit, as long as
 * the exact curve never decreases between two floats, which tests/unit/test_tonemap.c checks
 * around every threshold; it also compares the table with the formula around every U[k].
 * The same lookup also writes the codes packed as 32-bit XRGB8888 pixels (sl_tonemap_row_xrgb8888),
 * so the viewer's window gets the display image without a float image in between. */
#include "../core/threads.h"
#include "tonemap.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

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
 * Both quotients, then a select: a division under a condition keeps GCC from vectorizing. */
static inline float tonemap_x_of_ec(float ec)
{
    float below = ec / (ec + 1.0f), above = 1.0f - 1.0f / (ec + 1.0f);
    return ec < 1.0f ? below : above;
}
static inline float tonemap_x(float C, float exposure)
{
    float ec = exposure * C;
    ec = C > 0.0f ? ec : 0.0f;
    return tonemap_x_of_ec(ec);
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

/* ec thresholds: u[k] is the smallest float ec >= 0 whose x reaches t[k], found by bisection over
 * the bits of [0, +Inf] (non-negative floats order as their bits). Bisection assumes x grows with
 * ec, which is exact for ec >= 1 (1 - 1/(ec + 1): each step correctly rounded and monotonic) but
 * not for ec < 1, where ec and ec + 1 round separately and x can step back by an ulp. There x is
 * within 2^-23 relative of the true ec/(ec + 1), which grows by at least 2^-26 relative per float
 * step of ec, so x(ec') > x(ec) once ec' is 17 or more steps above ec: checking that x is below
 * t[k] for the SL_TONEMAP_WINDOW floats under u[k] and at or above it for as many from u[k]
 * proves that the one step at u[k] is the whole truth. A threshold that fails the check is marked
 * bad, and the segments around it are left to the exact path. */
#define SL_TONEMAP_WINDOW 64
/* a segment left to the exact path: code below 255, code above 0 */
#define SEG_EXACT (0xffu << 16)
static bool ec_threshold(float tk, float *u)
{
    const uint32_t inf = sl_fm_bits(INFINITY);
    uint32_t a = 0, b = inf;
    while (a < b) {
        uint32_t mid = a + (b - a) / 2;
        if (tonemap_x_of_ec(sl_fm_float(mid)) >= tk)
            b = mid;
        else
            a = mid + 1;
    }
    *u = sl_fm_float(a);
    for (uint32_t j = 1; j <= SL_TONEMAP_WINDOW; j++) {
        if (a >= j && !(tonemap_x_of_ec(sl_fm_float(a - j)) < tk))
            return false;
        if (a + j - 1 <= inf && !(tonemap_x_of_ec(sl_fm_float(a + j - 1)) >= tk))
            return false;
    }
    return true;
}

/* The code of ec by the ec thresholds: the largest k with u[k] <= ec. */
static int ec_code(uint32_t ec_bits, const float u[257])
{
    int a = 0, b = 255;
    while (a < b) {
        int mid = (a + b + 1) / 2;
        if (sl_fm_bits(u[mid]) <= ec_bits)
            a = mid;
        else
            b = mid - 1;
    }
    return a;
}

bool sl_tonemap_prepare(const sl_tonemap_options *opt, sl_tonemap_table *tab, sl_error *err)
{
    float e = opt && opt->exposure != 0.0f ? opt->exposure : (float)sl_options[SL_OPT_EXPOSURE].def[0];
    float c = opt && opt->contrast != 0.0f ? opt->contrast : (float)sl_options[SL_OPT_CONTRAST].def[0];
    bool exact = opt && opt->exact_srgb;
    if (!(isfinite(e) && e > 0.0f) || !(isfinite(c) && c > 0.0f))
        return sl_fail(err, SL_ERR_RANGE, "tone map: exposure %g and contrast %g must be finite and > 0", (double)e,
                       (double)c);
    tab->exposure = e;
    tab->contrast = c;
    tab->exact_srgb = exact;
    sl_tonemap_thresholds(c, exact, tab->t);
    bool bad[257] = {false};
    tab->u[0] = 0.0f;
    tab->u[256] = INFINITY;
    for (int k = 1; k <= 255; k++)
        bad[k] = !ec_threshold(tab->t[k], &tab->u[k]);

    /* Segments: keys from the first nonzero threshold's to the last one's, at most the table's
     * size (a curve whose codes spread over more binades leaves the lowest ones to segment 0,
     * which then holds several thresholds and goes to the exact path). */
    int first = 1;
    while (first < 255 && tab->u[first] == 0.0f)
        first++;
    int top = (int)(sl_fm_bits(tab->u[255]) >> SL_TONEMAP_SHIFT);
    int base = (int)(sl_fm_bits(tab->u[first]) >> SL_TONEMAP_SHIFT);
    if (top - base + 1 > SL_TONEMAP_SEGMENTS_MAX - 2)
        base = top - (SL_TONEMAP_SEGMENTS_MAX - 2) + 1;
    tab->base = base;
    tab->count = top - base + 1 + 2;
    for (int s = 0; s < tab->count; s++) {
        /* the bits of the segment's first and last ec: segment 0 is [0, first key), the last one
         * runs to +Inf, the others are one key each */
        uint32_t lo = s == 0 ? 0u : (uint32_t)(base + s - 1) << SL_TONEMAP_SHIFT;
        uint32_t hi = s == tab->count - 1 ? sl_fm_bits(INFINITY) : ((uint32_t)(base + s) << SL_TONEMAP_SHIFT) - 1u;
        int klo = ec_code(lo, tab->u), khi = ec_code(hi, tab->u);
        bool one_step = true; /* every code between changes at one ec, and none of them is bad */
        for (int k = klo + 1; k <= khi; k++)
            one_step = one_step && tab->u[k] == tab->u[khi] && !bad[k];
        /* segment 0 spans many keys: the low bits say nothing there */
        one_step = one_step && (s > 0 || khi == klo);
        uint32_t pos = khi > klo ? sl_fm_bits(tab->u[khi]) & 0xffffu : 0u;
        tab->seg[s] = one_step ? pos | (uint32_t)klo << 16 | (uint32_t)khi << 24 : SEG_EXACT;
    }
    /* A bad threshold's window may reach the next segment: those go to the exact path too. */
    for (int k = 1; k <= 255; k++) {
        if (!bad[k])
            continue;
        uint32_t ub = sl_fm_bits(tab->u[k]);
        uint32_t lo = ub > SL_TONEMAP_WINDOW ? ub - SL_TONEMAP_WINDOW : 0u;
        uint32_t hi = ub + SL_TONEMAP_WINDOW;
        for (int s = 0; s < tab->count; s++) {
            uint32_t slo = s == 0 ? 0u : (uint32_t)(base + s - 1) << SL_TONEMAP_SHIFT;
            uint32_t shi = s == tab->count - 1 ? UINT32_MAX : ((uint32_t)(base + s) << SL_TONEMAP_SHIFT) - 1u;
            if (slo <= hi && lo <= shi)
                tab->seg[s] = SEG_EXACT;
        }
    }
    return true;
}

/* Values per task: 16 KB in and out, and the chunk's codes in L1. */
#define TONEMAP_CHUNK 1024

/* One value's code from the table: ec's top bits pick a segment, its low bits against the
 * segment's threshold pick the code below or above it; -1 where the segment is left to the exact
 * path (code_exact). A shift, a clamp, one gather, a compare: GCC vectorizes its callers' loops. */
static inline int segment_code(float C, float e, int base, int last, const uint32_t *restrict seg)
{
    float ec = e * C;
    ec = C > 0.0f ? ec : 0.0f; /* as tonemap_x: NaN and C <= 0 are 0 */
    uint32_t b = sl_fm_bits(ec);
    int s = (int)(b >> SL_TONEMAP_SHIFT) - base + 1;
    s = s < 0 ? 0 : s;
    s = s > last ? last : s;
    uint32_t g = seg[s];
    int below = (int)(g >> 16 & 0xffu), above = (int)(g >> 24);
    int code = (b & 0xffffu) >= (g & 0xffffu) ? above : below;
    int miss = above < below;
    return code | -miss; /* -1: the exact path's */
}

/* The exact path's code of one value (a segment the table leaves to it). */
static int code_exact(const sl_tonemap_table *tab, float C)
{
    float ec = tab->exposure * C;
    ec = C > 0.0f ? ec : 0.0f;
    return sl_tonemap_code(tonemap_x_of_ec(ec), tab->t);
}

/* One chunk: the display values into dst, -1 where the segment is left to the exact path;
 * returns the number of those. */
static int present_chunk(const float *restrict src, float *restrict dst, int count, const sl_tonemap_table *tab)
{
    const float e = tab->exposure;
    const int base = tab->base, last = tab->count - 1;
    const uint32_t *restrict seg = tab->seg;
    int missed = 0;
    /* No reduction clause and no select on the miss (an OR with its mask): with either, GCC 12
     * does not vectorize the loop. */
#pragma omp simd
    for (int i = 0; i < count; i++) {
        int code = segment_code(src[i], e, base, last, seg);
        dst[i] = (float)code / 255.0f; /* the level sl_unorm8 gives the code back from */
        missed += code < 0;
    }
    return missed;
}

bool sl_tonemap_target(const sl_image *in, sl_image *out, sl_error *err)
{
    if (!in->data || in->channels != 3)
        return sl_fail(err, SL_ERR_RANGE, "tone map: input must be a 3-channel image");
    if (out->data) {
        if (out->width != in->width || out->height != in->height || out->channels != 3)
            return sl_fail(err, SL_ERR_RANGE, "tone map: output is %dx%dx%d, expected %dx%dx3", out->width,
                           out->height, out->channels, in->width, in->height);
        return true;
    }
    return sl_image_alloc(out, in->width, in->height, 3, err);
}

/* Values [i0, i0 + count) of in into out (count <= TONEMAP_CHUNK). In place, the misses need
 * the source: the chunk then goes through a buffer. */
static void tonemap_chunk(const sl_tonemap_table *tab, const sl_image *in, sl_image *out, size_t i0, int count)
{
    float vals[TONEMAP_CHUNK];
    const float *src = in->data + i0;
    float *dst = in->data == out->data ? vals : out->data + i0;
    int missed = present_chunk(src, dst, count, tab);
    for (int i = 0; missed && i < count; i++)
        if (dst[i] < 0.0f) {
            dst[i] = (float)code_exact(tab, src[i]) / 255.0f;
            missed--;
        }
    if (dst == vals)
        memcpy(out->data + i0, vals, (size_t)count * sizeof(float));
}

bool sl_tonemap_apply(const sl_tonemap_table *tab, const sl_image *in, sl_image *out, int threads, sl_error *err)
{
    if (!sl_tonemap_target(in, out, err))
        return false;
    const size_t n = (size_t)in->width * (size_t)in->height * 3;
    const long chunks = (long)((n + TONEMAP_CHUNK - 1) / TONEMAP_CHUNK);
    /* Few threads for a small image: a parallel region costs more than 64 chunks of work. The
     * chunks are handed out as threads come free, not split in equal halves up front: on a
     * machine another process keeps busy, a descheduled thread's half would hold the region
     * open while the other thread waits. */
#pragma omp parallel for schedule(dynamic, 4) num_threads(sl_threads(threads)) if (chunks >= 64)
    for (long ci = 0; ci < chunks; ci++) {
        const size_t i0 = (size_t)ci * TONEMAP_CHUNK;
        tonemap_chunk(tab, in, out, i0, (int)(n - i0 < TONEMAP_CHUNK ? n - i0 : TONEMAP_CHUNK));
    }
    return true;
}

void sl_tonemap_rows(const sl_tonemap_table *tab, const sl_image *in, sl_image *out, int row0, int row1)
{
    const size_t end = (size_t)row1 * (size_t)in->width * 3;
    for (size_t i0 = (size_t)row0 * (size_t)in->width * 3; i0 < end; i0 += TONEMAP_CHUNK)
        tonemap_chunk(tab, in, out, i0, (int)(end - i0 < TONEMAP_CHUNK ? end - i0 : TONEMAP_CHUNK));
}

/* Pixels per chunk of the 32-bit path: 1020 values, whole pixels, in L1. */
#define XRGB_CHUNK_PIXELS (TONEMAP_CHUNK / 3)

/* A pixel's three codes as SDL_PIXELFORMAT_XRGB8888's 0xffRRGGBB. */
static inline uint32_t xrgb8888(int r, int g, int b)
{
    return 0xff000000u | (uint32_t)r << 16 | (uint32_t)g << 8 | (uint32_t)b;
}

void sl_tonemap_row_xrgb8888(const sl_tonemap_table *tab, const float *row, int width, uint32_t *dst)
{
    const float e = tab->exposure;
    const int base = tab->base, last = tab->count - 1;
    const uint32_t *restrict seg = tab->seg;
    for (int x0 = 0; x0 < width; x0 += XRGB_CHUNK_PIXELS) {
        const int n = width - x0 < XRGB_CHUNK_PIXELS ? width - x0 : XRGB_CHUNK_PIXELS;
        const float *restrict src = row + 3 * x0;
        uint32_t *restrict out = dst + x0;
        int missed = 0;
        /* a pixel's three codes packed (strided loads: faster than codes to a buffer and a
         * packing loop); a pixel with a code of -1 (the exact path's) is packed wrong and
         * counted, and the loop after this one packs it again */
#pragma omp simd
        for (int i = 0; i < n; i++) {
            int r = segment_code(src[3 * i], e, base, last, seg);
            int g = segment_code(src[3 * i + 1], e, base, last, seg);
            int b = segment_code(src[3 * i + 2], e, base, last, seg);
            out[i] = xrgb8888(r, g, b);
            missed += (r | g | b) < 0;
        }
        for (int i = 0; missed && i < n; i++) {
            int r = segment_code(src[3 * i], e, base, last, seg);
            int g = segment_code(src[3 * i + 1], e, base, last, seg);
            int b = segment_code(src[3 * i + 2], e, base, last, seg);
            if ((r | g | b) >= 0)
                continue;
            r = r < 0 ? code_exact(tab, src[3 * i]) : r;
            g = g < 0 ? code_exact(tab, src[3 * i + 1]) : g;
            b = b < 0 ? code_exact(tab, src[3 * i + 2]) : b;
            out[i] = xrgb8888(r, g, b);
            missed--;
        }
    }
}

void sl_tonemap_apply_xrgb8888(const sl_tonemap_table *tab, const sl_image *in, uint8_t *pixels, int pitch, int threads)
{
    const int w = in->width, h = in->height;
    /* the same threshold and hand-out as sl_tonemap_apply */
#pragma omp parallel for schedule(dynamic, 8) num_threads(sl_threads(threads)) if ((long)w * h * 3 >= 64L * TONEMAP_CHUNK)
    for (int y = 0; y < h; y++)
        sl_tonemap_row_xrgb8888(tab, sl_image_pixel(in, 0, y), w,
                                (uint32_t *)(void *)(pixels + (size_t)y * (size_t)pitch));
}

bool sl_tonemap_image(const sl_image *in, sl_image *out, const sl_tonemap_options *opt, int threads, sl_error *err)
{
    sl_tonemap_table *tab = malloc(sizeof *tab);
    if (!tab)
        return sl_fail(err, SL_ERR_MEMORY, "tone map: out of memory for its table");
    bool ok = sl_tonemap_prepare(opt, tab, err) && sl_tonemap_apply(tab, in, out, threads, err);
    free(tab);
    return ok;
}
