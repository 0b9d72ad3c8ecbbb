/* compare.c - image comparison metrics (compare.h): what `softlight compare` prints and the
 * GL-comparison tests assert on. Sums are in double so that a 4-megapixel image's mean is not
 * limited by float accumulation; the values compared are whatever the images hold. */
#include "compare.h"

#include <softlight/glsl.h>
#include "tonemap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The viewer's tone map (src/post/tonemap.h, the specification's "Tone Mapping"), so that the
 * 8-bit figures are about the pixels a user would actually see. */
float sl_compare_tonemap(float x, float exposure, float contrast)
{
    return sl_tonemap_value(x, exposure, contrast, false);
}

typedef struct {
    float exposure, contrast, rel_floor;
    const sl_image *mask;
} resolved_desc;

static resolved_desc resolve(const sl_compare_desc *desc)
{
    resolved_desc r = {1.0f, 1.0f, 1e-3f, NULL};
    if (desc) {
        if (desc->exposure > 0.0f)
            r.exposure = desc->exposure;
        if (desc->contrast > 0.0f)
            r.contrast = desc->contrast;
        if (desc->rel_floor > 0.0f)
            r.rel_floor = desc->rel_floor;
        r.mask = desc->mask;
    }
    return r;
}

static bool check_inputs(const sl_image *a, const sl_image *b, const resolved_desc *d, sl_error *err)
{
    if (!a->data || !b->data || a->width <= 0 || a->height <= 0 || a->channels <= 0)
        return sl_fail(err, SL_ERR_RANGE, "compare: empty image");
    if (a->width != b->width || a->height != b->height)
        return sl_fail(err, SL_ERR_RANGE, "compare: sizes differ (%dx%d and %dx%d)", a->width, a->height, b->width,
                       b->height);
    if (a->channels != b->channels)
        return sl_fail(err, SL_ERR_RANGE, "compare: channel counts differ (%d and %d)", a->channels, b->channels);
    if (d->mask && (!d->mask->data || d->mask->width != a->width || d->mask->height != a->height))
        return sl_fail(err, SL_ERR_RANGE, "compare: the mask is %dx%d, the images %dx%d", d->mask->width,
                       d->mask->height, a->width, a->height);
    return true;
}

static bool inside_mask(const resolved_desc *d, int x, int y)
{
    return !d->mask || sl_image_pixel(d->mask, x, y)[0] > 0.5f;
}

/* 0 = finite, 1 = has a NaN, 2 = has an Inf (NaN wins when both). */
static int classify(const float *p, int channels)
{
    int kind = 0;
    for (int c = 0; c < channels; c++) {
        if (isnan(p[c]))
            return 1;
        if (isinf(p[c]))
            kind = 2;
    }
    return kind;
}

static int to_8bit(float t) { return (int)lrintf(255.0f * t); }

/* Keep the SL_COMPARE_WORST largest errors, largest first; ties keep scan order. */
static void note_worst(sl_compare_stats *s, int x, int y, double error, const float *pa, const float *pb,
                       int channels)
{
    int n = s->worst_count;
    if (n == SL_COMPARE_WORST && !(error > s->worst[n - 1].error))
        return;
    int at = n < SL_COMPARE_WORST ? n : n - 1;
    while (at > 0 && error > s->worst[at - 1].error) {
        s->worst[at] = s->worst[at - 1];
        at--;
    }
    sl_compare_pixel *w = &s->worst[at];
    memset(w, 0, sizeof *w);
    w->x = x;
    w->y = y;
    w->error = error;
    for (int c = 0; c < channels && c < 3; c++) {
        w->a[c] = pa[c];
        w->b[c] = pb[c];
    }
    if (n < SL_COMPARE_WORST)
        s->worst_count = n + 1;
}

static int cmp_float(const void *pa, const void *pb)
{
    float a = *(const float *)pa, b = *(const float *)pb;
    return (a > b) - (a < b);
}

bool sl_compare_images(const sl_image *a, const sl_image *b, const sl_compare_desc *desc, sl_compare_stats *stats,
                       sl_error *err)
{
    memset(stats, 0, sizeof *stats);
    resolved_desc d = resolve(desc);
    if (!check_inputs(a, b, &d, err))
        return false;
    size_t count = (size_t)a->width * (size_t)a->height;
    float *rel = malloc(count * sizeof *rel);
    if (!rel)
        return sl_fail(err, SL_ERR_MEMORY, "compare: no memory for %zu pixels", count);

    int ch = a->channels;
    stats->width = a->width;
    stats->height = a->height;
    stats->channels = ch;
    double sum_abs = 0.0, sum_sq = 0.0, sum_b_sq = 0.0, sum_rel = 0.0, sum_tm_sq = 0.0;
    long over1 = 0, over8 = 0;
    for (int y = 0; y < a->height; y++) {
        for (int x = 0; x < a->width; x++) {
            if (!inside_mask(&d, x, y)) {
                stats->masked_out++;
                continue;
            }
            const float *pa = sl_image_pixel(a, x, y), *pb = sl_image_pixel(b, x, y);
            int ka = classify(pa, ch), kb = classify(pb, ch);
            stats->nan_a += ka == 1;
            stats->inf_a += ka == 2;
            stats->nan_b += kb == 1;
            stats->inf_b += kb == 2;
            if (ka || kb)
                continue;
            double pixel_max = 0.0, pixel_rel = 0.0;
            int levels = 0;
            for (int c = 0; c < ch; c++) {
                double v = fabs((double)pa[c] - (double)pb[c]);
                double denom = fmax(fmax(fabs((double)pa[c]), fabs((double)pb[c])), (double)d.rel_floor);
                sum_abs += v;
                sum_sq += v * v;
                sum_b_sq += (double)pb[c] * (double)pb[c];
                pixel_max = fmax(pixel_max, v);
                pixel_rel = fmax(pixel_rel, v / denom);
                float ta = sl_compare_tonemap(pa[c], d.exposure, d.contrast);
                float tb = sl_compare_tonemap(pb[c], d.exposure, d.contrast);
                double tv = (double)ta - (double)tb;
                sum_tm_sq += tv * tv;
                int l = abs(to_8bit(ta) - to_8bit(tb));
                levels = l > levels ? l : levels;
            }
            over1 += levels > 1;
            over8 += levels > 8;
            stats->max_abs = fmax(stats->max_abs, pixel_max);
            sum_rel += pixel_rel;
            rel[stats->pixels++] = (float)pixel_rel;
            note_worst(stats, x, y, pixel_max, pa, pb, ch);
        }
    }
    if (stats->pixels > 0) {
        double n = (double)stats->pixels, values = n * ch;
        stats->mean_abs = sum_abs / values;
        stats->rmse = sqrt(sum_sq / values);
        stats->nrmse = sum_b_sq > 0.0 ? sqrt(sum_sq / sum_b_sq) : 0.0;
        stats->mean_rel = sum_rel / n;
        double mse_tm = sum_tm_sq / values;
        stats->psnr = mse_tm > 0.0 ? 10.0 * log10(1.0 / mse_tm) : (double)INFINITY;
        stats->share_over_1 = (double)over1 / n;
        stats->share_over_8 = (double)over8 / n;
        qsort(rel, (size_t)stats->pixels, sizeof *rel, cmp_float);
        /* nearest rank ceil(0.99 n), in integers so that 0.99 * 200 cannot round up to 199 */
        long rank = (99 * stats->pixels + 99) / 100;
        stats->p99_rel = (double)rel[rank - 1];
    } else {
        stats->psnr = (double)INFINITY;
    }
    free(rel);
    return true;
}

double sl_compare_metric_value(const sl_compare_stats *stats, sl_compare_metric metric)
{
    switch (metric) {
    case SL_METRIC_RMSE:
        return stats->rmse;
    case SL_METRIC_MAX:
        return stats->max_abs;
    case SL_METRIC_P99REL:
        return stats->p99_rel;
    }
    return (double)INFINITY;
}

bool sl_compare_within(const sl_compare_stats *stats, sl_compare_metric metric, double tolerance)
{
    if (stats->nan_a || stats->inf_a || stats->nan_b || stats->inf_b)
        return false;
    return sl_compare_metric_value(stats, metric) <= tolerance;
}

static bool covered(const sl_image *depth, int x, int y) { return sl_image_pixel(depth, x, y)[0] < 1.0f; }

bool sl_compare_edge_mask(const sl_image *depth_a, const sl_image *depth_b, int band, float depth_tol, sl_image *mask,
                          long *kept, sl_error *err)
{
    memset(mask, 0, sizeof *mask);
    resolved_desc d = resolve(NULL);
    if (!check_inputs(depth_a, depth_b, &d, err))
        return false;
    if (depth_a->channels != 1)
        return sl_fail(err, SL_ERR_RANGE, "compare: depth images have 1 channel, not %d", depth_a->channels);
    if (band < 0)
        return sl_fail(err, SL_ERR_RANGE, "compare: edge band %d < 0", band);
    int w = depth_a->width, h = depth_a->height;
    /* First the pixels that are bad in themselves, then grow them by `band`. */
    unsigned char *bad = calloc((size_t)w * (size_t)h, 1);
    if (!bad)
        return sl_fail(err, SL_ERR_MEMORY, "compare: no memory for a %dx%d mask", w, h);
    if (!sl_image_alloc(mask, w, h, 1, err)) {
        free(bad);
        return false;
    }
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            float za = sl_image_pixel(depth_a, x, y)[0], zb = sl_image_pixel(depth_b, x, y)[0];
            bool ca = za < 1.0f, cb = zb < 1.0f;
            /* a silhouette against the background: a 4-neighbour with the other coverage */
            bool edge = (x > 0 && covered(depth_a, x - 1, y) != ca) || (x + 1 < w && covered(depth_a, x + 1, y) != ca) ||
                        (y > 0 && covered(depth_a, x, y - 1) != ca) || (y + 1 < h && covered(depth_a, x, y + 1) != ca);
            bool differ = ca != cb || (ca && !(fabsf(za - zb) <= depth_tol));
            bad[(size_t)y * (size_t)w + (size_t)x] = edge || differ;
        }
    }
    long ones = 0;
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            bool keep = true;
            for (int v = y - band; keep && v <= y + band; v++)
                for (int u = x - band; keep && u <= x + band; u++)
                    if (u >= 0 && v >= 0 && u < w && v < h && bad[(size_t)v * (size_t)w + (size_t)u])
                        keep = false;
            sl_image_pixel(mask, x, y)[0] = keep ? 1.0f : 0.0f;
            ones += keep;
        }
    }
    free(bad);
    if (kept)
        *kept = ones;
    return true;
}

/* Six evenly spaced stops: black, blue, green, yellow, red, white. */
static void false_colour(float t, float *rgb)
{
    static const float stops[6][3] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {1, 1, 1}};
    t = clampf(t, 0.0f, 1.0f) * 5.0f;
    int i = (int)t;
    if (i >= 5) {
        memcpy(rgb, stops[5], 3 * sizeof *rgb);
        return;
    }
    float f = t - (float)i;
    for (int c = 0; c < 3; c++)
        rgb[c] = stops[i][c] + (stops[i + 1][c] - stops[i][c]) * f;
}

bool sl_compare_diff_image(const sl_image *a, const sl_image *b, const sl_compare_desc *desc, sl_image *out,
                           sl_error *err)
{
    memset(out, 0, sizeof *out);
    resolved_desc d = resolve(desc);
    if (!check_inputs(a, b, &d, err))
        return false;
    if (!sl_image_alloc(out, a->width, a->height, 3, err))
        return false;
    int ch = a->channels;
    for (int y = 0; y < a->height; y++) {
        for (int x = 0; x < a->width; x++) {
            float *o = sl_image_pixel(out, x, y);
            const float *pa = sl_image_pixel(a, x, y), *pb = sl_image_pixel(b, x, y);
            if (!inside_mask(&d, x, y)) {
                o[0] = o[1] = o[2] = 0.15f;
                continue;
            }
            if (classify(pa, ch) || classify(pb, ch)) {
                o[0] = 1.0f, o[1] = 0.0f, o[2] = 1.0f;
                continue;
            }
            float levels = 0.0f;
            for (int c = 0; c < ch; c++) {
                float ta = sl_compare_tonemap(pa[c], d.exposure, d.contrast);
                float tb = sl_compare_tonemap(pb[c], d.exposure, d.contrast);
                levels = maxf(levels, 255.0f * fabsf(ta - tb));
            }
            /* log scale: 1 level -> 1/8 (dark blue), 8 -> ~0.4 (green), 255 -> 1 (white) */
            false_colour(log2f(1.0f + levels) / 8.0f, o);
        }
    }
    return true;
}

void sl_compare_print(FILE *out, const sl_compare_stats *s, float exposure, const char *name_a, const char *name_b)
{
    fprintf(out, "size            %dx%d, %d channel%s\n", s->width, s->height, s->channels, s->channels == 1 ? "" : "s");
    fprintf(out, "pixels compared %ld (%ld outside the mask)\n", s->pixels, s->masked_out);
    fprintf(out, "non-finite      %s: %ld NaN, %ld Inf   %s: %ld NaN, %ld Inf (pixels)\n", name_a, s->nan_a, s->inf_a,
            name_b, s->nan_b, s->inf_b);
    fprintf(out, "max abs error   %.6g\n", s->max_abs);
    fprintf(out, "mean abs error  %.6g\n", s->mean_abs);
    fprintf(out, "rmse            %.6g\n", s->rmse);
    fprintf(out, "mean rel error  %.6g\n", s->mean_rel);
    fprintf(out, "p99 rel error   %.6g\n", s->p99_rel);
    if (isinf(s->psnr))
        fprintf(out, "psnr            inf (identical after the tone map, exposure %g)\n", (double)exposure);
    else
        fprintf(out, "psnr            %.2f dB (after the tone map, exposure %g)\n", s->psnr, (double)exposure);
    fprintf(out, "8-bit diff > 1  %.4f%% of pixels\n", 100.0 * s->share_over_1);
    fprintf(out, "8-bit diff > 8  %.4f%% of pixels\n", 100.0 * s->share_over_8);
    for (int i = 0; i < s->worst_count; i++) {
        const sl_compare_pixel *w = &s->worst[i];
        int shown = s->channels < 3 ? s->channels : 3;
        fprintf(out, "worst %d         (%d, %d) error %.6g  %s (", i + 1, w->x, w->y, w->error, name_a);
        for (int c = 0; c < shown; c++)
            fprintf(out, "%s%.6g", c ? ", " : "", (double)w->a[c]);
        fprintf(out, ")  %s (", name_b);
        for (int c = 0; c < shown; c++)
            fprintf(out, "%s%.6g", c ? ", " : "", (double)w->b[c]);
        fprintf(out, ")\n");
    }
}
