/* image.c - the sl_image buffer: allocation with size checks, row flipping, and the
 * NaN / Inf / negative repair every loader runs (docs/conventions.md "NaN and Inf":
 * no NaN or Inf leaves a stage). */
#include "image.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

bool sl_image_alloc(sl_image *img, int width, int height, int channels, sl_error *err)
{
    *img = (sl_image){0};
    if (width <= 0 || height <= 0)
        return sl_fail(err, SL_ERR_RANGE, "image size %dx%d: width and height must be positive", width, height);
    if (channels != 1 && channels != 3 && channels != 4)
        return sl_fail(err, SL_ERR_RANGE, "image with %d channels: only 1, 3 or 4 are supported", channels);
    /* width, height <= INT_MAX and channels <= 4, so the product of the first two fits in
     * 62 bits; only the multiplication by sizeof(float) * channels needs care. */
    uint64_t pixels = (uint64_t)width * (uint64_t)height;
    if (pixels > SL_IMAGE_MAX_BYTES / (sizeof(float) * (uint64_t)channels))
        return sl_fail(err, SL_ERR_MEMORY, "image %dx%dx%d needs more than the %zu bytes allowed", width,
                       height, channels, SL_IMAGE_MAX_BYTES);
    size_t count = (size_t)pixels * (size_t)channels;
    float *data = calloc(count, sizeof(float));
    if (!data)
        return sl_fail(err, SL_ERR_MEMORY, "image %dx%dx%d: out of memory (%zu bytes)", width, height,
                       channels, count * sizeof(float));
    *img = (sl_image){.width = width, .height = height, .channels = channels, .data = data};
    return true;
}

void sl_image_free(sl_image *img)
{
    if (!img)
        return;
    free(img->data);
    *img = (sl_image){0};
}

void sl_image_flip_rows(sl_image *img)
{
    if (!img || !img->data)
        return;
    size_t row = (size_t)img->width * (size_t)img->channels;
    for (int top = 0, bottom = img->height - 1; top < bottom; top++, bottom--) {
        float *a = img->data + (size_t)top * row;
        float *b = img->data + (size_t)bottom * row;
        for (size_t i = 0; i < row; i++) {
            float t = a[i];
            a[i] = b[i];
            b[i] = t;
        }
    }
}

long sl_image_repair(sl_image *img, sl_image_repairs *repairs)
{
    sl_image_repairs r = {0};
    if (img && img->data) {
        size_t n = (size_t)img->width * (size_t)img->height * (size_t)img->channels;
        for (size_t i = 0; i < n; i++) {
            float v = img->data[i];
            if (v >= 0.0f && v <= FLT_MAX) /* the common case: finite, non-negative */
                continue;
            if (isnan(v))
                r.nan_count++;
            else if (isinf(v))
                r.inf_count++;
            else
                r.negative_count++;
            img->data[i] = 0.0f;
        }
    }
    if (repairs)
        *repairs = r;
    return r.nan_count + r.inf_count + r.negative_count;
}

bool sl_image_check_budget(const char *name, size_t offset, int width, int height, size_t need, size_t budget,
                           sl_error *err)
{
    size_t b = budget ? budget : SL_IMAGE_BUDGET_DEFAULT;
    if (need <= b)
        return true;
    size_t mib = ((size_t)1 << 20), need_mib = need / mib + (need % mib != 0);
    if (need_mib > SL_IMAGE_MEMORY_MAX_MIB)
        return sl_fail(err, SL_ERR_RANGE,
                       "%s: byte %zu: image %dx%d needs %zu MiB in memory, more than the largest image memory "
                       "budget (%s %d)",
                       name, offset, width, height, need_mib, sl_options[SL_OPT_IMAGE_MEMORY].cli,
                       SL_IMAGE_MEMORY_MAX_MIB);
    return sl_fail(err, SL_ERR_RANGE,
                   "%s: byte %zu: image %dx%d needs %zu MiB in memory, more than the image memory budget of %zu MiB "
                   "(raise it with %s %zu)",
                   name, offset, width, height, need_mib, b / mib, sl_options[SL_OPT_IMAGE_MEMORY].cli, need_mib);
}
