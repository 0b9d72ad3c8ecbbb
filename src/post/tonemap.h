/* tonemap.h - HDR radiance to display values, and the sRGB <-> linear curves.
 *
 * The specification's global tone map, per channel, with exposure e and contrast c:
 *     x = e C / (e C + 1)                                  in [0, 1)
 *     C_out = x^(c / 2.2)                                  gamma encoding (default)
 *     C_out = srgb_encode(x^c)                             with `exact_srgb`: the piecewise
 *                                                          IEC 61966-2-1 curve replaces 1/2.2
 * Never both: with exact_srgb the exponent is c alone. e is nominally 0.1 .. 10000 (the
 * specification's range for its environments); any finite e > 0 is accepted.
 * Inputs that are negative or NaN count as 0 and +Inf as "infinitely bright" (x = 1), so the
 * output is always in [0, 1].
 *
 * The display image (sl_tonemap_image) is what is presented: each value is an 8-bit code k
 * stored as k/255, the code that rounding the exact curve above gives (sl_unorm8 of
 * sl_tonemap_value, bit for bit; tonemap.c says how it is found fast). sl_tonemap_value keeps
 * the unrounded curve for comparisons.
 *
 * Does not: adapt exposure automatically. */
#ifndef SL_TONEMAP_H
#define SL_TONEMAP_H

#include <stdbool.h>
#include <stdint.h>

#include "../core/error.h"
#include "../core/image.h"

typedef struct {
    float exposure;  /* e; 0 = 1 (the option table's default, core/options.h) */
    float contrast;  /* c; 0 = 1 */
    bool exact_srgb; /* piecewise sRGB encode instead of the 1/2.2 power */
} sl_tonemap_options;

/* The curves, for one value in [0, 1] (values outside are clamped to it). */
float sl_srgb_to_linear(float c);  /* exact piecewise: c / 12.92 below 0.04045, else ((c + 0.055) / 1.055)^2.4 */
float sl_linear_to_srgb(float c);  /* exact piecewise: 12.92 c below 0.0031308, else 1.055 c^(1/2.4) - 0.055 */
float sl_gamma_to_linear(float c); /* c^2.2 */
float sl_linear_to_gamma(float c); /* c^(1/2.2) */

/* One channel value through the tone map (options already validated). */
float sl_tonemap_value(float C, float exposure, float contrast, bool exact_srgb);

/* The 257 thresholds of the 8-bit display codes for a contrast and curve: t[k] is the smallest
 * float x = eC/(eC + 1) in [0, 1] whose code sl_unorm8(curve(x)) is k or more; t[0] = 0,
 * t[256] = +Inf. About 7700 powf calls. */
void sl_tonemap_thresholds(float contrast, bool exact_srgb, float t[257]);
/* The code of x in [0, 1] from the thresholds: the k with t[k] <= x < t[k + 1]. */
int sl_tonemap_code(float x, const float t[257]);

/* The display image's table for one exposure, contrast and curve (tonemap.c says how it is
 * built and why it is exact): the code thresholds in x and in ec = eC, and the segments of ec:
 * 128 per binade (the top 7 bits of the mantissa) over the binades where codes change. Each
 * segment holds the one threshold inside it, as the low 16 bits of its float (the segment has
 * the high 16), the code below it and the code from it on: one 32-bit read per value. A segment
 * with more than one threshold, or one the exactness check did not pass, is left to the exact
 * path (code below 255, code above 0). About 0.2 ms to build; 20 KB read per value. */
#define SL_TONEMAP_SHIFT 16 /* ec's bits >> 16: sign, exponent and 7 mantissa bits */
#define SL_TONEMAP_SEGMENTS_MAX ((40 << 7) + 2) /* 40 binades, below and above */
typedef struct {
    float exposure, contrast; /* resolved (0 -> the option table's default) */
    bool exact_srgb;
    float t[257];    /* sl_tonemap_thresholds */
    float u[257];    /* u[k]: the smallest ec whose code is k or more */
    int base, count; /* the first regular segment's key (ec's bits >> SL_TONEMAP_SHIFT), segments in all */
    uint32_t seg[SL_TONEMAP_SEGMENTS_MAX]; /* threshold's low 16 bits | code below << 16 | code from it << 24 */
} sl_tonemap_table;
/* Resolve and check the options (SL_ERR_RANGE unless exposure and contrast are finite and > 0)
 * and build the table. */
bool sl_tonemap_prepare(const sl_tonemap_options *opt, sl_tonemap_table *tab, sl_error *err);
/* sl_tonemap_image with a prepared table. */
bool sl_tonemap_apply(const sl_tonemap_table *tab, const sl_image *in, sl_image *out, int threads, sl_error *err);
/* What sl_tonemap_apply checks and allocates before it writes: in a 3-channel image with data,
 * out allocated at in's size when out->data is NULL, else of that size with 3 channels. */
bool sl_tonemap_target(const sl_image *in, sl_image *out, sl_error *err);
/* Rows [row0, row1) of sl_tonemap_apply, on the calling thread, into an `out` that
 * sl_tonemap_target accepted: the same values, for a caller that tone maps each band of rows as
 * soon as it is lit (the renderer, inside the lighting pass). */
void sl_tonemap_rows(const sl_tonemap_table *tab, const sl_image *in, sl_image *out, int row0, int row1);

/* The display image of a 3-channel linear image (tab prepared, in->data set) straight into
 * 32-bit pixels 0xffRRGGBB (SDL_PIXELFORMAT_XRGB8888: what the viewer's window takes), row y at
 * pixels + y pitch: each channel the code k whose level k/255 sl_tonemap_apply stores, so the
 * bytes equal that image's 8-bit conversion (v 255 + 0.5 rounded down gives k back). One pass
 * where a tone map and a conversion were two. OpenMP over rows. */
void sl_tonemap_apply_xrgb8888(const sl_tonemap_table *tab, const sl_image *in, uint8_t *pixels, int pitch, int threads);
/* One row of it: `width` RGB values from `row` into dst[0 .. width) (the viewer tone maps each
 * row of a moving frame right after lighting it, while the row is in cache). */
void sl_tonemap_row_xrgb8888(const sl_tonemap_table *tab, const float *row, int width, uint32_t *dst);

/* Tone map a 3-channel linear image into `out` (allocated when out->data is NULL, else it must
 * have in's size and 3 channels; out may be in itself): the display image, each value k/255 with
 * k = sl_unorm8(sl_tonemap_value(C, ...)) exactly. Row order kept.
 * SL_ERR_RANGE when exposure or contrast is not finite and > 0. OpenMP over rows. */
bool sl_tonemap_image(const sl_image *in, sl_image *out, const sl_tonemap_options *opt, int threads, sl_error *err);

#endif
