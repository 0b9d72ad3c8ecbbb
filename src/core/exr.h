/* exr.h - OpenEXR files through OpenEXRCore (Debian's libopenexr-dev, its C API openexr.h).
 *
 * Reading an environment is in image.h with the other formats (sl_image_read_exr); this header
 * has the multi-layer writer `softlight render --exr` uses: several sl_images of one size, each
 * a layer of named channels following the EXR convention "layer.channel" (normal.X, kd.R), a
 * layer without a name giving the plain channels R, G, B that every viewer shows, and a one-
 * channel layer with no suffix giving one channel named after the layer ("depth").
 *
 * Written: one scanline part (or tiled, for tests of the reader), rows top first as EXR
 * expects (the sl_image's row 0 is y = 0, the top), data and display window (0,0)-(w-1,h-1),
 * 32-bit float or half channels, any of the lossless compressions. No OpenEXR type appears
 * here, so a caller needs no OpenEXR include path. */
#ifndef SL_EXR_H
#define SL_EXR_H

#include <stdbool.h>
#include <stddef.h>

#include "error.h"
#include "image.h"

/* The most channels one file written here may hold (the G-buffer has 20 with the radiance). */
#define SL_EXR_MAX_CHANNELS 64

typedef struct {
    const char *name;     /* "" = the default layer (channels R, G, B) */
    const char *suffixes; /* one letter per image channel ("XYZ", "RGB"); "" for a one-channel layer */
    const sl_image *img;  /* channels == strlen(suffixes) (1 when ""), row 0 = top */
} sl_exr_layer;

/* The compressions, numbered as OpenEXR numbers them (the lossy ones, DWAA/DWAB, left out). */
typedef enum {
    SL_EXR_NONE = 0,
    SL_EXR_RLE = 1,
    SL_EXR_ZIPS = 2,
    SL_EXR_ZIP = 3,
    SL_EXR_PIZ = 4,
    SL_EXR_PXR24 = 5, /* lossy for float (24-bit), lossless for half */
    SL_EXR_B44 = 6,   /* lossy for half */
    SL_EXR_B44A = 7,
} sl_exr_compression;

typedef struct {
    bool half;                      /* 16-bit half channels instead of 32-bit float */
    sl_exr_compression compression; /* SL_EXR_NONE is the zero value; --exr uses ZIP */
    int tile;                       /* > 0: tiled, tile x tile pixels, one level; 0: scanlines */
} sl_exr_options;

/* Encode the layers into one .exr in memory; the caller frees *bytes with free(). False (err
 * names the layer) when the layers differ in size, a channel count does not match its
 * suffixes, two channels share a name, or the library fails. */
bool sl_exr_encode(const sl_exr_layer *layers, int count, const sl_exr_options *options, unsigned char **bytes,
                   size_t *size, sl_error *err);

/* Read one layer back (what sl_exr_encode wrote as `layer` with `suffixes`): an image of
 * strlen(suffixes) channels (1 for ""), signed values kept, NaN or Inf an error, the budget as
 * sl_image_read_exr's. `suffixes` NULL: whichever of layer.R/G/B, layer.X/Y/Z or a channel named
 * `layer` the file has. For tests and `softlight compare FILE.exr:LAYER`. */
bool sl_exr_read_layer(const char *path, const char *layer, const char *suffixes, size_t budget, sl_image *img,
                       sl_error *err);
bool sl_exr_parse_layer(const unsigned char *bytes, size_t size, const char *layer, const char *suffixes,
                        size_t budget, sl_image *img, sl_error *err);

#endif
