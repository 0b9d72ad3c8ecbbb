/* png_decode.c - PNG decoding through libpng, for textures: the pixels as stored, 8 or 16 bits,
 * 1 to 4 channels (grey, grey + alpha, RGB, RGBA), row 0 = top.
 *
 * libpng is the reference decoder and is maintained for untrusted input; this file only feeds
 * it from memory and shapes its output. Expansions: a palette becomes RGB (RGBA with a tRNS
 * chunk), grey of 1, 2 or 4 bits becomes 8-bit grey (bits replicated), a tRNS colour key adds an
 * alpha channel (0 where a pixel equals the key, full elsewhere), 16-bit samples are returned
 * in the machine's byte order. No gamma or colour management is applied: gAMA, cHRM, sRGB and
 * iCCP are ignored, as the texture's own sRGB flag says how its codes are read.
 *
 * libpng reports errors by calling back and longjmp'ing out of the decode; the callbacks keep
 * the message and print nothing. Warnings (a damaged ancillary chunk, trailing compressed data)
 * leave the pixels defined and are ignored. Limits: each side at most SL_IMAGE_MAX_SIDE (also
 * given to libpng as its user limits), ancillary chunks at most 1 MiB each, and the decoded
 * size checked against the budget (sl_raw_admit) before the image buffer is allocated. libpng
 * inflates only as many bytes as the rows need, so compressed data that inflates past the image
 * costs no memory. The end of the file after the image data (chunks after the last IDAT, IEND)
 * is not read. */
#include "raw_decode.h"

#include <png.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PNG_CHUNK_MAX ((png_alloc_size_t)1 << 20)

typedef struct {
    const unsigned char *bytes;
    size_t size, pos; /* the reader's position: where a failure is reported */
    bool truncated;
    char msg[200];        /* libpng's error */
    unsigned char *pixels; /* what is allocated while libpng may longjmp, freed on failure */
    png_bytep *rows;
} png_source;

static void on_error(png_structp png, png_const_charp msg)
{
    png_source *s = png_get_error_ptr(png);
    snprintf(s->msg, sizeof s->msg, "%s", msg);
    png_longjmp(png, 1);
}

static void on_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

static void read_bytes(png_structp png, png_bytep out, size_t n)
{
    png_source *s = png_get_io_ptr(png);
    if (n > s->size - s->pos) {
        s->pos = s->size;
        s->truncated = true;
        png_error(png, "truncated");
    }
    memcpy(out, s->bytes + s->pos, n);
    s->pos += n;
}

static uint32_t be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* Everything between png_create_read_struct and its destruction: libpng's errors come back
 * here through setjmp (the state that must survive the jump lives in *s, outside this frame). */
static bool decode(png_structp png, png_infop info, png_source *s, const char *name, size_t budget,
                   sl_raw_extra_fn extra, sl_raw_image *out, sl_error *err)
{
    if (setjmp(png_jmpbuf(png))) {
        if (s->truncated)
            return sl_fail(err, SL_ERR_FORMAT, "%s: byte %zu: truncated PNG", name, s->pos);
        return sl_fail(err, SL_ERR_FORMAT, "%s: byte %zu: corrupt PNG: %s", name, s->pos, s->msg);
    }
    png_set_read_fn(png, s, read_bytes);
    png_set_user_limits(png, SL_IMAGE_MAX_SIDE, SL_IMAGE_MAX_SIDE);
    png_set_chunk_malloc_max(png, PNG_CHUNK_MAX);
    /* The size before libpng's own IHDR checks, so that an image over the limit says so (libpng
     * would report "Invalid IHDR data"). IHDR must come first: libpng refuses anything else. */
    if (s->size >= 24 && !memcmp(s->bytes + 12, "IHDR", 4)) {
        uint32_t w = be32(s->bytes + 16), h = be32(s->bytes + 20);
        if (w > SL_IMAGE_MAX_SIDE || h > SL_IMAGE_MAX_SIDE)
            return sl_fail(err, SL_ERR_RANGE, "%s: byte 16: PNG: image too large: %lux%lu is over %d on a side", name,
                           (unsigned long)w, (unsigned long)h, SL_IMAGE_MAX_SIDE);
    }
    png_read_info(png, info);
    png_uint_32 w, h;
    int depth, colour, interlace;
    png_get_IHDR(png, info, &w, &h, &depth, &colour, &interlace, NULL, NULL);
    bool key = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
    int declared = colour == PNG_COLOR_TYPE_PALETTE ? (key ? 4 : 3) : png_get_channels(png, info);
    int bits = depth == 16 ? 16 : 8;
    if (!sl_raw_admit(name, 16, (int)w, (int)h, declared, bits, 0, budget, extra, err))
        return false;

    if (colour == PNG_COLOR_TYPE_PALETTE)
        png_set_palette_to_rgb(png);
    if (colour == PNG_COLOR_TYPE_GRAY && depth < 8)
        png_set_expand_gray_1_2_4_to_8(png);
    if (key)
        png_set_tRNS_to_alpha(png);
    const uint16_t one = 1;
    if (depth == 16 && *(const unsigned char *)&one == 1)
        png_set_swap(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    int channels = png_get_channels(png, info);
    size_t row_bytes = png_get_rowbytes(png, info);
    if (png_get_bit_depth(png, info) != bits || channels < 1 || channels > 4 ||
        row_bytes != (size_t)w * (size_t)channels * (size_t)(bits / 8))
        return sl_fail(err, SL_ERR_FORMAT, "%s: PNG: unexpected layout after expansion (%d channels of %d bits)", name,
                       channels, png_get_bit_depth(png, info));

    s->pixels = malloc(row_bytes * h);
    s->rows = malloc(sizeof *s->rows * h);
    if (!s->pixels || !s->rows)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for a %lux%lu image", name, (unsigned long)w,
                       (unsigned long)h);
    for (png_uint_32 y = 0; y < h; y++)
        s->rows[y] = s->pixels + (size_t)y * row_bytes;
    png_read_image(png, s->rows);
    *out = (sl_raw_image){(int)w, (int)h, channels, bits, s->pixels};
    s->pixels = NULL;
    return true;
}

bool sl_png_decode(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_raw_extra_fn extra,
                   sl_raw_image *out, sl_error *err)
{
    *out = (sl_raw_image){0};
    png_source s = {.bytes = bytes, .size = size};
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &s, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info) {
        png_destroy_read_struct(&png, NULL, NULL);
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for the PNG decoder", name);
    }
    bool ok = decode(png, info, &s, name, budget, extra, out, err);
    png_destroy_read_struct(&png, &info, NULL);
    free(s.pixels);
    free(s.rows);
    return ok;
}
