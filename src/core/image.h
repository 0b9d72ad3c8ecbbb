/* image.h - float images in memory and the file formats softlight reads and writes.
 *
 * An sl_image is `channels` interleaved float32 values per pixel (1 = a plane,
 * 3 = linear RGB), `width * height` pixels, ROW 0 IS THE TOP ROW, as in .hdr
 * and .png files and as the environment's v = 0 (docs/conventions.md "Coordinate frames"). Render targets
 * inside the pipeline follow OpenGL instead (row 0 at the bottom); they turn
 * into sl_images once, with sl_image_flip_rows, when written out.
 *
 * Formats (hdr.c, pfm.c, exr.c; png.c writes PNG; raw_image.c reads PNG / JPEG through png_decode.c
 * and jpeg_decode.c; image.c owns the buffer, file.c the I/O, radiance.c picks the format):
 *   .hdr  Radiance RGBE, read (flat and new-style RLE scanlines, "-Y h +X w" only) and
 *         write (RLE for widths 8..32767, flat otherwise). A texel (m_r, m_g, m_b, e) decodes
 *         as m * 2^(e - 136) (e = 0 is black), the convention of Greg Ward's rgbe.c that the
 *         specification ships; the writer rounds to nearest, so a written value comes back
 *         within half a mantissa step (at most max(r, g, b) / 255.5).
 *   .pfm  Portable float map, 1 ("Pf") or 3 ("PF") channels, either byte order,
 *         rows bottom-to-top in the file as the format says; written little endian
 *   .exr  OpenEXR through OpenEXRCore (libopenexr-dev): read R, G, B (or a grey Y) of the first
 *         part, half/float/uint, scanline or tiled, any compression the library decodes, by
 *         offsets from a regular file (never read whole); write float or half layers (exr.h)
 *   .png  write 8-bit (from values in [0,1]); read PNG/JPEG as sRGB -> linear floats, or as
 *         stored (8/16-bit, 1-4 channels) for textures (sl_image_parse_raw)
 * Every write goes to a temporary name beside the target and is renamed into
 * place, so a failed write never leaves a half file; the files of one command go
 * through one output set (output_set.h), all replaced or none. Loaded images are checked:
 * NaN, Inf and negative texels are counted, replaced by 0, and reported once
 * through the `repairs` out-parameter. */
#ifndef SL_IMAGE_H
#define SL_IMAGE_H

#include <stdbool.h>
#include <stddef.h>

#include <softlight/image.h>

#include "error.h"
#include "options.h"
#include "softlight/version.h"

/* Limits for files read from disk: no side over 32768, no more than 2^28 pixels, and no
 * buffer over 4 GiB (2^28 RGB float pixels are 3 GiB). */
#define SL_IMAGE_MAX_SIDE 32768
#define SL_IMAGE_MAX_PIXELS ((long long)1 << 28)
#define SL_IMAGE_MAX_BYTES ((size_t)1 << 32)
/* Whole-file size cap the readers pass to sl_read_file. */
#define SL_IMAGE_MAX_FILE_BYTES ((size_t)1 << 31)
/* The image memory budget (options.h, --image-memory): the bytes one image read from a file may
 * take decoded. Every reader takes a budget in bytes (0 = this default) and checks the size a
 * header declares against it before allocating anything of that size; a file larger than the
 * budget (plus SL_IMAGE_HEADER_SLACK for headers) is refused before it is read, since no valid
 * .hdr, .pfm or PNG is larger than its decoded floats. */
#define SL_IMAGE_BUDGET_DEFAULT ((size_t)SL_IMAGE_MEMORY_DEFAULT_MIB << 20)
#define SL_IMAGE_HEADER_SLACK ((size_t)1 << 20)

/* sl_image and sl_image_repairs are public (softlight/image.h), with sl_image_alloc (false and
 * err on absurd sizes or no memory: width or height <= 0 or channels not 1, 3 or 4 ->
 * SL_ERR_RANGE, a byte count that overflows or exceeds SL_IMAGE_MAX_BYTES, or a failed
 * allocation -> SL_ERR_MEMORY), sl_image_free, sl_image_flip_rows, the file readers and
 * writers. */
static inline float *sl_image_pixel(const sl_image *img, int x, int y)
{
    return img->data + ((size_t)y * (size_t)img->width + (size_t)x) * (size_t)img->channels;
}
/* Count and replace non-finite and negative values; returns the total repaired. */
long sl_image_repair(sl_image *img, sl_image_repairs *repairs);

/* Readers (softlight/image.h: hdr, pfm, exr, radiance, texture): on failure `img` is left empty
 * and err says file, byte offset and what was expected. `budget`: the image memory budget in
 * bytes (0 = SL_IMAGE_BUDGET_DEFAULT). The file's first bytes are checked for the format's magic
 * before the rest is read (a device or a FIFO that is not an image fails after a few bytes).
 * `repairs` may be NULL.
 * - OpenEXR (exr.c, through OpenEXRCore): R, G, B of the first part (or a grey Y, replicated),
 *   half, float or uint, scanline or tiled, any compression the library decodes; always 3
 *   channels. Read by offsets, never whole: a regular file only. The budget counts the float
 *   image and one chunk's decoding buffers.
 * - sl_image_read_radiance: any radiance image by its first bytes: OpenEXR, Radiance .hdr or PFM
 *   (a file whose magic is none of them, or that is not a regular file, by its extension; .hdr's
 *   reader when that says nothing either). What environments and irradiance maps are read with.
 * - sl_image_read_texture: PNG (libpng) / JPEG (libjpeg-turbo), 8- or 16-bit sRGB decoded to
 *   linear RGB (3 channels) with the exact piecewise curve; alpha is dropped, grey is replicated.
 *   The budget counts the decoder's share (three images of the file's channels and depth) with
 *   the float image. */
/* A PFM of signed data (positions, normals: the G-buffer's AOVs): negative values are kept,
 * NaN or Inf is an error; nothing is repaired. */
bool sl_image_read_pfm_signed(const char *path, size_t budget, sl_image *img, sl_error *err);
/* A PNG or JPEG decoded as stored, for textures (raster/texture.c): `channels` 1..4 (grey,
 * grey + alpha, RGB, RGBA; a palette is expanded to RGB or RGBA, a colour key to an alpha
 * channel) of `bits` 8 or 16 (PNG only; JPEG is 8) per channel, interleaved, row 0 = top; free
 * with sl_raw_image_free. Corrupt or truncated data is an error naming the file, never a
 * partial image. The budget counts the decoder's share plus `extra` bytes the caller will
 * allocate for the result (a texture and its mips), so one check refuses what the whole load
 * would need. */
typedef struct {
    int width, height, channels, bits;
    void *pixels;
} sl_raw_image;
bool sl_image_parse_raw(const unsigned char *bytes, size_t size, const char *name, size_t budget,
                        size_t (*extra)(int width, int height, int channels, int bits), sl_raw_image *out,
                        sl_error *err);
void sl_raw_image_free(sl_raw_image *img);
/* The PNG signature or a JPEG start-of-image marker (what sl_image_read_with is given). */
bool sl_image_magic_texture(const unsigned char *head, size_t size, const char *name, sl_error *err);
/* Parse from memory (what the readers and the fuzz targets call); `name` is used in messages. */
bool sl_image_parse_hdr(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_image *img,
                        sl_image_repairs *repairs, sl_error *err);
bool sl_image_parse_exr(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_image *img,
                        sl_image_repairs *repairs, sl_error *err);
bool sl_image_parse_pfm(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_image *img,
                        sl_image_repairs *repairs, sl_error *err);
bool sl_image_parse_pfm_signed(const unsigned char *bytes, size_t size, const char *name, size_t budget,
                               sl_image *img, sl_image_repairs *repairs, sl_error *err);
/* The budget check every reader makes once a header has declared a size: `need` bytes (the
 * decoded image and the reader's own buffers) against `budget` (0 = the default). The error
 * names the file, the byte offset of the declaration, the size, and the option that raises
 * the budget. */
bool sl_image_check_budget(const char *name, size_t offset, int width, int height, size_t need, size_t budget,
                           sl_error *err);
/* The exact sRGB -> linear curve (IEC 61966-2-1) of one 8-bit code, as the texture reader uses. */
float sl_srgb8_to_linear(unsigned char code);

/* A display value in [0, 1] to its 8-bit code, rounding to nearest; NaN and negatives -> 0,
 * 1 and above -> 255. What the PNG writer stores and the tone map's display codes are. */
static inline int sl_unorm8(float v)
{
    if (!(v > 0.0f))
        return 0;
    if (v >= 1.0f)
        return 255;
    return (int)(v * 255.0f + 0.5f);
}

/* Writers (softlight/image.h): atomic (temporary file + rename). hdr needs 3 channels; pfm 1
 * or 3; png takes 1 or 3 channels of already display-encoded values in [0,1].
 * The same encodings into memory (what the writers and the fuzz round trips call);
 * the caller frees *bytes with free(). */
bool sl_image_encode_hdr(const sl_image *img, unsigned char **bytes, size_t *size, sl_error *err);
bool sl_image_encode_pfm(const sl_image *img, unsigned char **bytes, size_t *size, sl_error *err);
bool sl_image_encode_png(const sl_image *img, unsigned char **bytes, size_t *size, sl_error *err);
/* One image as an .exr: 3 channels as R, G, B, 1 as Y; 32-bit float, ZIP (core/exr.h writes layers). */
bool sl_image_encode_exr(const sl_image *img, unsigned char **bytes, size_t *size, sl_error *err);

/* A parse-from-memory function (sl_image_parse_hdr, sl_image_parse_pfm); a check of a file's
 * first bytes (at most `size`, fewer only where the file ends) for the format's magic, failing
 * with the parser's own message; and the reader every file format shares: the magic first, then
 * the whole file (at most the budget plus SL_IMAGE_HEADER_SLACK) through `parse`. */
typedef bool (*sl_image_parser)(const unsigned char *bytes, size_t size, const char *name, size_t budget,
                                sl_image *img, sl_image_repairs *repairs, sl_error *err);
typedef bool (*sl_magic_check)(const unsigned char *head, size_t size, const char *name, sl_error *err);
bool sl_image_read_with(const char *path, size_t budget, sl_magic_check magic, sl_image_parser parse,
                        sl_image *img, sl_image_repairs *repairs, sl_error *err);
/* The magic checks of the formats (what sl_image_read_with is given), and how many bytes each needs. */
#define SL_IMAGE_MAGIC_BYTES 18 /* a TGA header; every other format needs fewer */
bool sl_image_magic_hdr(const unsigned char *head, size_t size, const char *name, sl_error *err);
bool sl_image_magic_pfm(const unsigned char *head, size_t size, const char *name, sl_error *err);
bool sl_image_magic_exr(const unsigned char *head, size_t size, const char *name, sl_error *err);

/* An encode-to-memory function (sl_image_encode_hdr/pfm/png), and the writer every format
 * shares: encode, then sl_write_file_atomic. */
typedef bool (*sl_image_encoder)(const sl_image *img, unsigned char **bytes, size_t *size, sl_error *err);
bool sl_image_write_with(const char *path, sl_image_encoder encode, const sl_image *img, sl_error *err);

/* Read a whole file into memory (caps at `max_bytes`); caller frees *bytes. */
bool sl_read_file(const char *path, size_t max_bytes, unsigned char **bytes, size_t *size, sl_error *err);
/* The same, checking the first `head` bytes with `magic` (NULL: none) before reading further;
 * `cap_name`, if not NULL, says in the too-large message what sets `max_bytes` (" (the image
 * memory budget, --image-memory)"). */
bool sl_read_file_checked(const char *path, size_t max_bytes, const char *cap_name, size_t head,
                          sl_magic_check magic, unsigned char **bytes, size_t *size, sl_error *err);
/* Write bytes atomically: a temporary beside the target, then rename; an output set of one
 * (core/output_set.h: symbolic links written through, non-regular targets refused). To write
 * several files all or none, add them to one sl_output_set instead. */
bool sl_write_file_atomic(const char *path, const void *bytes, size_t size, sl_error *err);

#endif
