/* png.c - PNG writing: softlight's own 8-bit images (1 or 3 channels) through stb_image_write,
 * into memory, then atomically to a file. The pixels written are trusted (they are ours), so a
 * small single-header encoder is enough; untrusted PNG and JPEG input is decoded by libpng and
 * libjpeg-turbo instead (png_decode.c, jpeg_decode.c).
 *
 * This file holds the one copy of stb_image_write in softlight (its IMPLEMENTATION macro is
 * defined here and nowhere else). */
#include "image.h"

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
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

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

/* [0, 1] -> 0..255 (sl_unorm8, image.h). */
static unsigned char to_byte(float v) { return (unsigned char)sl_unorm8(v); }

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
