/* raw_image.c - PNG, JPEG, BMP and TGA texture input: the signature check, the size and memory
 * limits every decode passes (sl_raw_admit), the choice of decoder by signature (png_decode.c
 * through libpng, jpeg_decode.c through libjpeg-turbo, bmp_decode.c and tga_decode.c of our own),
 * and sl_image_read_texture's linear floats (the exact sRGB -> linear curve).
 *
 * Texture files come from scenes and models, which may come from anywhere: PNG and JPEG are read
 * by the reference libraries, which are built and fuzzed for untrusted input and turn corrupt
 * data into errors; BMP and TGA, whose uncompressed and run-length layouts are a few fields,
 * by decoders that check each field against the file's size (and have a fuzz target). */
#include "raw_decode.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* IEC 61966-2-1: c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055)^2.4, in double, then rounded once. */
float sl_srgb8_to_linear(unsigned char code)
{
    double c = code / 255.0;
    return (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
}

static bool is_bmp(const unsigned char *head, size_t size) { return size >= 2 && head[0] == 'B' && head[1] == 'M'; }

static bool is_tga(const unsigned char *head, size_t size, const char *name)
{
    size_t n = strlen(name);
    return n >= 4 && strcasecmp(name + n - 4, ".tga") == 0 && sl_tga_header_plausible(head, size);
}

/* The PNG signature, a JPEG's SOI marker and the first marker after it, BMP's "BM", or a .tga
 * whose header makes sense. */
bool sl_image_magic_texture(const unsigned char *head, size_t size, const char *name, sl_error *err)
{
    static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}, jpeg[3] = {0xff, 0xd8, 0xff};
    if ((size >= sizeof png && !memcmp(head, png, sizeof png)) || (size >= sizeof jpeg && !memcmp(head, jpeg, sizeof jpeg)) ||
        is_bmp(head, size) || is_tga(head, size, name))
        return true;
    return sl_fail(err, SL_ERR_FORMAT, "%s: byte 0: not a PNG, JPEG, BMP or TGA file (expected the PNG signature, a "
                   "JPEG start-of-image marker, \"BM\", or a .tga name with a TGA header)", name);
}

bool sl_raw_admit(const char *name, size_t offset, int width, int height, int channels, int bits,
                  size_t decoder_bytes, size_t budget, sl_raw_extra_fn extra, sl_error *err)
{
    if ((long long)width * height > SL_IMAGE_MAX_PIXELS)
        return sl_fail(err, SL_ERR_RANGE, "%s: image %dx%d has more than %lld pixels", name, width, height,
                       SL_IMAGE_MAX_PIXELS);
    /* width, height <= SL_IMAGE_MAX_SIDE (the decoders check) and channels <= 4: no overflow */
    size_t images = (size_t)width * (size_t)height * 3 * (size_t)channels * (size_t)(bits / 8) + (size_t)height;
    size_t need = decoder_bytes > images ? decoder_bytes : images;
    size_t more = extra ? extra(width, height, channels, bits) : 0;
    return sl_image_check_budget(name, offset, width, height, need + more, budget, err);
}

bool sl_image_parse_raw(const unsigned char *bytes, size_t size, const char *name, size_t budget,
                        size_t (*extra)(int width, int height, int channels, int bits), sl_raw_image *out,
                        sl_error *err)
{
    *out = (sl_raw_image){0};
    if (!budget)
        budget = SL_IMAGE_BUDGET_DEFAULT;
    if (!sl_image_magic_texture(bytes, size, name, err))
        return false;
    if (bytes[0] == 0x89)
        return sl_png_decode(bytes, size, name, budget, extra, out, err);
    if (bytes[0] == 0xff)
        return sl_jpeg_decode(bytes, size, name, budget, extra, out, err);
    if (is_bmp(bytes, size))
        return sl_bmp_decode(bytes, size, name, budget, extra, out, err);
    return sl_tga_decode(bytes, size, name, budget, extra, out, err);
}

void sl_raw_image_free(sl_raw_image *img)
{
    free(img->pixels);
    *img = (sl_raw_image){0};
}

/* The float RGB image sl_image_read_texture makes, beside the decoder's buffers. */
static size_t float_rgb_bytes(int width, int height, int channels, int bits)
{
    (void)channels;
    (void)bits;
    return (size_t)width * (size_t)height * 3 * sizeof(float);
}

bool sl_image_read_texture(const char *path, size_t budget, sl_image *img, sl_error *err)
{
    *img = (sl_image){0};
    unsigned char *bytes;
    size_t size;
    if (!budget)
        budget = SL_IMAGE_BUDGET_DEFAULT;
    size_t cap = budget < (size_t)INT_MAX - SL_IMAGE_HEADER_SLACK ? budget + SL_IMAGE_HEADER_SLACK : (size_t)INT_MAX;
    char why[96];
    snprintf(why, sizeof why, " by the image memory budget (raise it with %s)", sl_options[SL_OPT_IMAGE_MEMORY].cli);
    if (!sl_read_file_checked(path, cap, why, SL_IMAGE_MAGIC_BYTES, sl_image_magic_texture, &bytes, &size, err))
        return false;
    sl_raw_image raw;
    bool ok = sl_image_parse_raw(bytes, size, path, budget, float_rgb_bytes, &raw, err);
    free(bytes);
    if (!ok)
        return false;
    if (!sl_image_alloc(img, raw.width, raw.height, 3, err)) {
        sl_raw_image_free(&raw);
        sl_error_prefix(err, "%s: ", path);
        return false;
    }
    /* grey is replicated, alpha dropped; 16-bit codes through the same curve in double */
    float lut[256];
    for (int i = 0; i < 256; i++)
        lut[i] = sl_srgb8_to_linear((unsigned char)i);
    size_t count = (size_t)raw.width * (size_t)raw.height;
    int n = raw.channels, colour = n >= 3 ? 3 : 1;
    for (size_t i = 0; i < count; i++)
        for (int c = 0; c < 3; c++) {
            size_t k = i * (size_t)n + (size_t)(colour == 3 ? c : 0);
            if (raw.bits == 8) {
                img->data[3 * i + (size_t)c] = lut[((const unsigned char *)raw.pixels)[k]];
            } else {
                double v = ((const unsigned short *)raw.pixels)[k] / 65535.0;
                img->data[3 * i + (size_t)c] = (float)(v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4));
            }
        }
    sl_raw_image_free(&raw);
    return true;
}
