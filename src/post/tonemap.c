/* tonemap.c - the specification's exposure / gamma tone map and the sRGB curves (tonemap.h).
 *
 * The per-pixel loop runs over a flat float array with no branches other than clamps, so it is
 * plain for a debugger and open to vectorization; powf itself is a libm call (glibc provides
 * vector variants only under -ffast-math, which this project does not use), so the work is
 * spread over rows with OpenMP instead. */
#include "tonemap.h"

#include <math.h>

#include "../core/options.h"

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

float sl_tonemap_value(float C, float exposure, float contrast, bool exact_srgb)
{
    /* `!(C > 0)` catches NaN as well as C <= 0. eC/(eC + 1) would be Inf/Inf = NaN for
     * eC = +Inf and loses nothing when written as 1 - 1/(eC + 1) for eC > 1. */
    float ec = C > 0.0f ? exposure * C : 0.0f;
    float x = ec < 1.0f ? ec / (ec + 1.0f) : 1.0f - 1.0f / (ec + 1.0f);
    if (exact_srgb)
        return sl_linear_to_srgb(powf(x, contrast));
    return powf(x, contrast / 2.2f);
}

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
    const int height = in->height;
    const int row_floats = in->width * 3;
#pragma omp parallel for schedule(static)
    for (int y = 0; y < height; y++) {
        const float *src = in->data + (size_t)y * (size_t)row_floats;
        float *dst = out->data + (size_t)y * (size_t)row_floats;
        for (int i = 0; i < row_floats; i++)
            dst[i] = sl_tonemap_value(src[i], e, c, exact);
    }
    return true;
}
