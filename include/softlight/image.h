/* softlight/image.h - float images in memory, and reading and writing them as files.
 *
 * An sl_image is `channels` interleaved float32 values per pixel (1 = a plane, 3 = linear RGB),
 * width * height pixels, ROW 0 IS THE TOP ROW, as in the files. Render targets follow OpenGL
 * instead (row 0 at the bottom); sl_image_flip_rows turns one into the other.
 *
 * Readers check what they load: NaN, Inf and negative texels are replaced by 0 and counted in
 * `repairs` (may be NULL). `budget` is the most bytes one decoded image may take (0 = the
 * default, 1 GiB); a header that declares more is refused before anything is allocated.
 * Writers are atomic (a temporary file beside the target, then rename). */
#ifndef SOFTLIGHT_IMAGE_H
#define SOFTLIGHT_IMAGE_H

#include <stdbool.h>
#include <stddef.h>

#include <softlight/types.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sl_image {
    int width, height, channels;
    float *data; /* width * height * channels floats, row 0 = top */
} sl_image;

/* What loading repaired: texels that were NaN, +-Inf or negative (set to 0). */
typedef struct sl_image_repairs {
    long nan_count, inf_count, negative_count;
} sl_image_repairs;

/* Allocate a zeroed image: channels 1, 3 or 4. */
SL_API bool sl_image_alloc(sl_image *img, int width, int height, int channels, sl_error *err);
SL_API void sl_image_free(sl_image *img);
/* Reverse the row order in place (top-first <-> bottom-first). */
SL_API void sl_image_flip_rows(sl_image *img);

/* Radiance .hdr, PFM, OpenEXR (R, G, B of the first part; always 3 channels); any of the three
 * told apart by its first bytes (sl_image_read_radiance); PNG or JPEG decoded from sRGB to
 * linear RGB (sl_image_read_texture). On failure img is left empty. */
SL_API bool sl_image_read_hdr(const char *path, size_t budget, sl_image *img, sl_image_repairs *repairs,
                              sl_error *err);
SL_API bool sl_image_read_pfm(const char *path, size_t budget, sl_image *img, sl_image_repairs *repairs,
                              sl_error *err);
SL_API bool sl_image_read_exr(const char *path, size_t budget, sl_image *img, sl_image_repairs *repairs,
                              sl_error *err);
SL_API bool sl_image_read_radiance(const char *path, size_t budget, sl_image *img, sl_image_repairs *repairs,
                                   sl_error *err);
SL_API bool sl_image_read_texture(const char *path, size_t budget, sl_image *img, sl_error *err);

/* hdr needs 3 channels; pfm 1 or 3; png takes 1 or 3 channels of display values in [0,1]
 * (8 bits, rounded to nearest). */
SL_API bool sl_image_write_hdr(const char *path, const sl_image *img, sl_error *err);
SL_API bool sl_image_write_pfm(const char *path, const sl_image *img, sl_error *err);
SL_API bool sl_image_write_png(const char *path, const sl_image *img, sl_error *err);

#ifdef __cplusplus
}
#endif

#endif
