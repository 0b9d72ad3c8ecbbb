/* png.c - 8-bit images through stb: PNG writing (stb_image_write) and PNG/JPEG texture
 * reading (stb_image) with the exact sRGB -> linear curve.
 *
 * This file holds the one copy of stb_image and stb_image_write in softlight (their
 * IMPLEMENTATION macros are defined here and nowhere else). stb_image is built for PNG
 * and JPEG only: .hdr files must never reach it (ERRATA.md: it can loop forever on a
 * truncated one); hdr.c reads those. */
#include "image.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* stb is third-party code: its own warnings are not ours to fix. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#define STBI_MAX_DIMENSIONS SL_IMAGE_MAX_SIDE
#include <stb/stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

/* ---- writing ---- */

typedef struct {
    unsigned char *data;
    size_t size, cap;
    bool failed;
} mem_sink;

/* stb_image_write hands over the finished PNG through this callback (in one or more pieces). */
static void sink_write(void *context, void *data, int size)
{
    mem_sink *s = context;
    if (s->failed || size <= 0)
        return;
    if (s->size + (size_t)size > s->cap) {
        size_t cap = s->cap ? s->cap : 4096;
        while (cap < s->size + (size_t)size)
            cap *= 2;
        unsigned char *grown = realloc(s->data, cap);
        if (!grown) {
            s->failed = true;
            return;
        }
        s->data = grown;
        s->cap = cap;
    }
    memcpy(s->data + s->size, data, (size_t)size);
    s->size += (size_t)size;
}

/* [0, 1] -> 0..255, rounding to nearest; NaN and negatives -> 0, above 1 -> 255. */
static unsigned char to_byte(float v)
{
    if (!(v > 0.0f))
        return 0;
    if (v >= 1.0f)
        return 255;
    return (unsigned char)(v * 255.0f + 0.5f);
}

bool sl_image_encode_png(const sl_image *img, unsigned char **bytes, size_t *size, sl_error *err)
{
    *bytes = NULL;
    *size = 0;
    if (!img || !img->data || img->width <= 0 || img->height <= 0)
        return sl_fail(err, SL_ERR_RANGE, "png writer: empty image");
    if (img->channels != 1 && img->channels != 3)
        return sl_fail(err, SL_ERR_RANGE, "png writer: needs 1 or 3 channels, the image has %d", img->channels);
    if (img->width > SL_IMAGE_MAX_SIDE || img->height > SL_IMAGE_MAX_SIDE)
        return sl_fail(err, SL_ERR_RANGE, "png writer: image %dx%d is over %d on a side", img->width, img->height,
                       SL_IMAGE_MAX_SIDE);
    size_t count = (size_t)img->width * (size_t)img->height * (size_t)img->channels;
    unsigned char *pixels = malloc(count);
    if (!pixels)
        return sl_fail(err, SL_ERR_MEMORY, "png writer: out of memory for %zu bytes", count);
    for (size_t i = 0; i < count; i++)
        pixels[i] = to_byte(img->data[i]);
    mem_sink sink = {0};
    int ok = stbi_write_png_to_func(sink_write, &sink, img->width, img->height, img->channels, pixels,
                                    img->width * img->channels);
    free(pixels);
    if (!ok || sink.failed) {
        free(sink.data);
        return sl_fail(err, SL_ERR_MEMORY, "png writer: encoding a %dx%d image failed (out of memory)", img->width,
                       img->height);
    }
    *bytes = sink.data;
    *size = sink.size;
    return true;
}

bool sl_image_write_png(const char *path, const sl_image *img, sl_error *err)
{
    return sl_image_write_with(path, sl_image_encode_png, img, err);
}

/* ---- reading ---- */

/* IEC 61966-2-1: c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055)^2.4, in double, then rounded once. */
float sl_srgb8_to_linear(unsigned char code)
{
    double c = code / 255.0;
    return (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
}

bool sl_image_read_texture(const char *path, sl_image *img, sl_error *err)
{
    *img = (sl_image){0};
    unsigned char *bytes;
    size_t size;
    if (!sl_read_file(path, (size_t)INT_MAX, &bytes, &size, err))
        return false;
    int w, h, n;
    if (!stbi_info_from_memory(bytes, (int)size, &w, &h, &n)) {
        free(bytes);
        return sl_fail(err, SL_ERR_FORMAT, "%s: not a PNG or JPEG image this reader accepts (stb_image: %s)", path,
                       stbi_failure_reason());
    }
    if ((long long)w * h > SL_IMAGE_MAX_PIXELS) {
        free(bytes);
        return sl_fail(err, SL_ERR_RANGE, "%s: image %dx%d has more than %lld pixels", path, w, h,
                       SL_IMAGE_MAX_PIXELS);
    }
    unsigned char *pixels = stbi_load_from_memory(bytes, (int)size, &w, &h, &n, 3);
    free(bytes);
    if (!pixels)
        return sl_fail(err, SL_ERR_FORMAT, "%s: cannot decode the image (stb_image: %s)", path,
                       stbi_failure_reason());
    if (!sl_image_alloc(img, w, h, 3, err)) {
        stbi_image_free(pixels);
        sl_error_prefix(err, "%s: ", path);
        return false;
    }
    float lut[256];
    for (int i = 0; i < 256; i++)
        lut[i] = sl_srgb8_to_linear((unsigned char)i);
    size_t count = (size_t)w * (size_t)h * 3;
    for (size_t i = 0; i < count; i++)
        img->data[i] = lut[pixels[i]];
    stbi_image_free(pixels);
    return true;
}
