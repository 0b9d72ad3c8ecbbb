/* image.h - float images in memory and the file formats softlight reads and writes.
 *
 * An sl_image is `channels` interleaved float32 values per pixel (1 = a plane,
 * 3 = linear RGB), `width * height` pixels, ROW 0 IS THE TOP ROW, as in .hdr
 * and .png files and as the environment's v = 0 (DESIGN.md). Render targets
 * inside the pipeline follow OpenGL instead (row 0 at the bottom); they turn
 * into sl_images once, with sl_image_flip_rows, when written out.
 *
 * Formats (image_io.c):
 *   .hdr  Radiance RGBE, read (flat and RLE scanlines, "-Y h +X w" only) and write (RLE)
 *   .pfm  Portable float map, 1 ("Pf") or 3 ("PF") channels, either byte order,
 *         rows bottom-to-top in the file as the format says
 *   .png  write 8-bit (from values in [0,1]); read PNG/JPEG textures as sRGB -> linear
 * Every write goes to a temporary name beside the target and is renamed into
 * place, so a failed write never leaves a half file. Loaded images are checked:
 * NaN, Inf and negative texels are counted, replaced by 0, and reported once
 * through `sl_image_load_report`. */
#ifndef SL_IMAGE_H
#define SL_IMAGE_H

#include <stdbool.h>
#include <stddef.h>

#include "error.h"

typedef struct {
    int width, height, channels;
    float *data; /* width * height * channels floats, row 0 = top */
} sl_image;

/* Allocate a zeroed image; false (and err) on absurd sizes or no memory. */
bool sl_image_alloc(sl_image *img, int width, int height, int channels, sl_error *err);
void sl_image_free(sl_image *img);
static inline float *sl_image_pixel(const sl_image *img, int x, int y)
{
    return img->data + ((size_t)y * (size_t)img->width + (size_t)x) * (size_t)img->channels;
}
/* Reverse the row order in place (top-first <-> bottom-first). */
void sl_image_flip_rows(sl_image *img);

/* What loading repaired: texels that were NaN, +-Inf or negative (set to 0). */
typedef struct {
    long nan_count, inf_count, negative_count;
} sl_image_repairs;
/* Count and replace non-finite and negative values; returns the total repaired. */
long sl_image_repair(sl_image *img, sl_image_repairs *repairs);

/* Readers: on failure `img` is left empty and err says file, byte offset and what was expected.
 * `repairs` may be NULL. */
bool sl_image_read_hdr(const char *path, sl_image *img, sl_image_repairs *repairs, sl_error *err);
bool sl_image_read_pfm(const char *path, sl_image *img, sl_image_repairs *repairs, sl_error *err);
/* PNG / JPEG (stb_image), 8-bit sRGB decoded to linear RGB with the exact piecewise curve. */
bool sl_image_read_texture(const char *path, sl_image *img, sl_error *err);
/* Parse from memory (what the readers and the fuzz targets call); `name` is used in messages. */
bool sl_image_parse_hdr(const unsigned char *bytes, size_t size, const char *name, sl_image *img,
                        sl_image_repairs *repairs, sl_error *err);
bool sl_image_parse_pfm(const unsigned char *bytes, size_t size, const char *name, sl_image *img,
                        sl_image_repairs *repairs, sl_error *err);

/* Writers: atomic (temporary file + rename). hdr needs 3 channels; pfm 1 or 3;
 * png takes 1 or 3 channels of already display-encoded values in [0,1]. */
bool sl_image_write_hdr(const char *path, const sl_image *img, sl_error *err);
bool sl_image_write_pfm(const char *path, const sl_image *img, sl_error *err);
bool sl_image_write_png(const char *path, const sl_image *img, sl_error *err);

/* Read a whole file into memory (caps at `max_bytes`); caller frees *bytes. */
bool sl_read_file(const char *path, size_t max_bytes, unsigned char **bytes, size_t *size, sl_error *err);
/* Write bytes atomically: `path.tmpXXXXXX` then rename. */
bool sl_write_file_atomic(const char *path, const void *bytes, size_t size, sl_error *err);

#endif
