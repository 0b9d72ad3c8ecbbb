/* raw_decode.h - what the PNG and JPEG decoders (png_decode.c, jpeg_decode.c) share with the
 * texture reader (raw_image.c), which tells the formats apart and owns the limits.
 *
 * A decoder reads the header, hands the declared size to sl_raw_admit before it allocates
 * anything that size, then decodes into one malloc'd buffer (sl_raw_image, freed with free).
 * Every message names the file; none is printed: both libraries' warning and error output
 * is routed into sl_error. */
#ifndef SL_RAW_DECODE_H
#define SL_RAW_DECODE_H

#include <stdbool.h>
#include <stddef.h>

#include "image.h"

typedef size_t (*sl_raw_extra_fn)(int width, int height, int channels, int bits);

/* The checks once a header has declared a width x height image of `channels` (as the header
 * gives them, before palette or transparency expansion) at `bits` 8 or 16: at most
 * SL_IMAGE_MAX_PIXELS, then the budget. The decoder's share is counted as three images of
 * that depth and a row index (its output, and room for a progressive JPEG's coefficients at two
 * bytes a sample or a PNG's rows), or `decoder_bytes` where the decoder knows it needs more;
 * `extra` adds what the caller builds from the result. `offset`: where the size was declared
 * (0 when unknown). */
bool sl_raw_admit(const char *name, size_t offset, int width, int height, int channels, int bits,
                  size_t decoder_bytes, size_t budget, sl_raw_extra_fn extra, sl_error *err);

/* Decode a whole PNG (libpng) or JPEG (libjpeg-turbo) held in memory. `bytes` starts with the
 * format's signature (raw_image.c checked it); `budget` is not 0. */
bool sl_png_decode(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_raw_extra_fn extra,
                   sl_raw_image *out, sl_error *err);
bool sl_jpeg_decode(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_raw_extra_fn extra,
                    sl_raw_image *out, sl_error *err);

/* BMP (bmp_decode.c) and TGA (tga_decode.c), decoded by softlight itself: 8 bits, grey, RGB or
 * RGBA. `bytes` starts with "BM" for a BMP; a TGA, which has no signature, is one whose name ends
 * in .tga and whose header sl_tga_header_plausible accepts. */
bool sl_bmp_decode(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_raw_extra_fn extra,
                   sl_raw_image *out, sl_error *err);
bool sl_tga_decode(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_raw_extra_fn extra,
                   sl_raw_image *out, sl_error *err);
bool sl_tga_header_plausible(const unsigned char *header, size_t size);

#endif
