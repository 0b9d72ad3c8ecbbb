/* compare.h - how far apart two renderings of the same frame are.
 *
 * Consumes: two sl_images of the same size and channel count (linear values:
 * radiance, depth, positions...), optionally a mask image. Produces: error
 * figures in linear units, figures after the specification's tone map (what a
 * viewer sees), the worst pixels, and a false-colour difference image. This is
 * what `softlight compare` prints and what the GL-comparison tests assert on.
 *
 * Definitions (per channel value v = |a - b|, over the pixels inside the mask):
 *   max_abs   max v              mean_abs  mean v            rmse  sqrt(mean v^2)
 *   pixel relative error  rel(p) = max over channels of |a - b| / max(|a|, |b|, rel_floor)
 *   mean_rel  mean of rel(p)     p99_rel   99th percentile of rel(p) (nearest rank)
 *   tone map  T(x) = (e x / (e x + 1))^(c / 2.2)   (specification, "Tone Mapping"; src/post/tonemap.h)
 *   psnr      10 log10(1 / mean (T(a) - T(b))^2), +inf when the tone-mapped images agree
 *   over1/8   share of pixels whose largest 8-bit difference |round(255 T(a)) - round(255 T(b))|
 *             exceeds 1 (resp. 8) levels, i.e. is more than 1/255 (8/255) apart
 * A pixel with a NaN or Inf channel in either image is counted and left out of
 * every other figure; sl_compare_within then fails whatever the tolerance.
 *
 * Does not: read files (the command does; its loaders repair non-finite texels
 * and report them separately), align images of different sizes, or weight channels. */
#ifndef SL_COMPARE_H
#define SL_COMPARE_H

#include <stdbool.h>
#include <stdio.h>

#include "../core/error.h"
#include "../core/image.h"

#define SL_COMPARE_WORST 5

typedef enum { SL_METRIC_RMSE, SL_METRIC_MAX, SL_METRIC_P99REL } sl_compare_metric;

/* Zero means default: exposure 1, contrast 1, rel_floor 1e-3, no mask. */
typedef struct {
    float exposure;
    float contrast;
    float rel_floor;      /* denominators below this count as this (keeps black pixels from dominating) */
    const sl_image *mask; /* 1 or 3 channels, same size; a pixel is compared when channel 0 > 0.5 */
} sl_compare_desc;

typedef struct {
    int x, y;        /* row 0 = top, as in the files */
    double error;    /* largest channel |a - b| */
    float a[3], b[3]; /* the values (first min(channels, 3) channels) */
} sl_compare_pixel;

typedef struct {
    int width, height, channels;
    long pixels;                 /* inside the mask and finite in both images */
    long masked_out;             /* outside the mask */
    long nan_a, inf_a, nan_b, inf_b; /* pixels with a NaN / an Inf channel (inside the mask) */
    double max_abs, mean_abs, rmse;
    double nrmse;                /* rmse / the RMS of b over the same values: the error on the scale
                                    of the reference (b), 0 when b is all zero */
    double mean_rel, p99_rel;
    double psnr;                 /* dB, INFINITY when identical after the tone map */
    double share_over_1, share_over_8; /* in [0, 1] */
    int worst_count;             /* min(pixels, SL_COMPARE_WORST) */
    sl_compare_pixel worst[SL_COMPARE_WORST]; /* largest error first */
} sl_compare_stats;

/* The tone map used for psnr and the 8-bit figures: sl_tonemap_value with the 1/2.2 gamma. */
float sl_compare_tonemap(float x, float exposure, float contrast);

/* Compare a with b. False (and err) when sizes or channel counts differ, or the mask does not fit. */
bool sl_compare_images(const sl_image *a, const sl_image *b, const sl_compare_desc *desc, sl_compare_stats *stats,
                       sl_error *err);

/* The figure the metric names, and whether it is <= tolerance with no NaN/Inf. */
double sl_compare_metric_value(const sl_compare_stats *stats, sl_compare_metric metric);
bool sl_compare_within(const sl_compare_stats *stats, sl_compare_metric metric, double tolerance);

/* Where a difference in shading is meaningful when two rasterizers drew the frame: 1 where, for
 * every pixel within `band` pixels (a (2 band + 1)^2 square, clipped at the border), both depth
 * images (1 channel, depth >= 1 = empty, as softlight's depth.pfm) agree on coverage, the coverage
 * does not change (no silhouette against the background), and covered depths differ by at most
 * `depth_tol`; 0 elsewhere. Silhouette pixels are left out because there the two rasterizers'
 * attribute planes (snapped vs unsnapped vertices) legitimately differ the most. `mask` is
 * allocated here (1 channel); *kept (may be NULL) counts its ones. */
bool sl_compare_edge_mask(const sl_image *depth_a, const sl_image *depth_b, int band, float depth_tol, sl_image *mask,
                          long *kept, sl_error *err);

/* The figures and the worst pixels, one per line ("max abs error   0.0049"), as `softlight
 * compare` and `softlight check` print them; name_a, name_b label the two images. */
void sl_compare_print(FILE *out, const sl_compare_stats *s, float exposure, const char *name_a, const char *name_b);

/* False-colour difference (3 channels, display values in [0,1], row 0 = top): black where the
 * tone-mapped images agree, then blue, green, yellow, red, white on a log scale that reaches
 * white at 255 levels; 1 level is dark blue. Masked-out pixels are dark grey, NaN/Inf magenta.
 * `out` is allocated here; free with sl_image_free. */
bool sl_compare_diff_image(const sl_image *a, const sl_image *b, const sl_compare_desc *desc, sl_image *out,
                           sl_error *err);

#endif
