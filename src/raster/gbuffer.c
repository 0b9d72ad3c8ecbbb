/* gbuffer.c - G-buffer storage: allocated once per size, cleared per frame, freed.
 *
 * Layout and size are in docs/gbuffer.md (56 bytes a pixel, array of structs,
 * row 0 = bottom). Clearing 116 MB at 1920x1080 is memory-bound, so it is spread
 * over the OpenMP threads by rows; every texel gets the same bits either way. */
#include "gbuffer.h"

#include <stdlib.h>
#include <string.h>

#include "raster.h"

bool sl_gbuffer_resize(sl_gbuffer *gb, int width, int height, sl_error *err)
{
    if (width < 1 || height < 1 || width > SL_RASTER_MAX_SIZE || height > SL_RASTER_MAX_SIZE)
        return sl_fail(err, SL_ERR_RANGE, "gbuffer: size %dx%d outside 1..%d", width, height, SL_RASTER_MAX_SIZE);
    if (gb->texels && gb->width == width && gb->height == height)
        return true;
    size_t n = (size_t)width * (size_t)height;
    sl_gbuffer_texel *t = malloc(n * sizeof *t);
    if (!t)
        return sl_fail(err, SL_ERR_MEMORY, "gbuffer: out of memory for %dx%d (%zu bytes)", width, height,
                       n * sizeof *t);
    free(gb->texels);
    gb->texels = t;
    gb->width = width;
    gb->height = height;
    return true;
}

void sl_gbuffer_clear(sl_gbuffer *gb)
{
    if (!gb->texels)
        return;
    const sl_gbuffer_texel empty = {.depth = 1.0f};
    int w = gb->width;
#pragma omp parallel for schedule(static)
    for (int y = 0; y < gb->height; y++) {
        sl_gbuffer_texel *row = gb->texels + (size_t)y * (size_t)w;
        for (int x = 0; x < w; x++)
            row[x] = empty;
    }
}

void sl_gbuffer_free(sl_gbuffer *gb)
{
    free(gb->texels);
    gb->texels = NULL;
    gb->width = gb->height = 0;
}
