/* gbuffer.c - G-buffer storage: allocated once per size, cleared per frame, freed.
 *
 * Layout and size are in docs/gbuffer.md (56 bytes a pixel, array of structs,
 * row 0 = bottom). Clearing 116 MB at 1920x1080 is memory-bound, so it is spread
 * over the OpenMP threads by rows; every texel gets the same bits either way. The extra plane
 * (occlusion, emission; gbuffer.h) is allocated, cleared and resolved here, only when asked for.
 *
 * Both planes start on a cache line: a tile's rows (64 texels of 56 or 20 bytes) are then whole
 * lines at any width that is a multiple of 8 (1280, 1920), so two threads drawing neighbouring tiles
 * never write one line. At malloc's alignment (16 bytes past a line) every row at a tile edge would
 * share a line with the neighbour's, and those lines would move back and forth between the cores
 * while both tiles are cleared and shaded (docs/performance.md "Rasterizer"). */
#include "gbuffer.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "../core/threads.h"
#include "raster.h"

#define GBUFFER_ALIGN 64 /* a cache line */

/* `bytes` starting on a cache line (aligned_alloc wants a multiple of the alignment); free() frees it. */
static void *plane_alloc(size_t bytes)
{
    return aligned_alloc(GBUFFER_ALIGN, (bytes + GBUFFER_ALIGN - 1) / GBUFFER_ALIGN * GBUFFER_ALIGN);
}

bool sl_gbuffer_resize(sl_gbuffer *gb, int width, int height, sl_error *err)
{
    if (width < 1 || height < 1 || width > SL_RASTER_MAX_SIZE || height > SL_RASTER_MAX_SIZE)
        return sl_fail(err, SL_ERR_RANGE, "gbuffer: size %dx%d outside 1..%d", width, height, SL_RASTER_MAX_SIZE);
    if (gb->texels && gb->width == width && gb->height == height)
        return true;
    size_t n = (size_t)width * (size_t)height;
    sl_gbuffer_texel *t = plane_alloc(n * sizeof *t);
    if (!t)
        return sl_fail(err, SL_ERR_MEMORY, "gbuffer: out of memory for %dx%d (%zu bytes)", width, height,
                       n * sizeof *t);
    free(gb->texels);
    gb->texels = t;
    gb->width = width;
    gb->height = height;
    bool extra = gb->extra != NULL, facet = gb->facet != NULL;
    free(gb->facet); /* the old size's */
    gb->facet = NULL;
    if (facet && !sl_gbuffer_use_facet(gb, true, err))
        return false;
    free(gb->cone); /* the old size's: the occlusion passes allocate them again */
    gb->cone = NULL;
    free(gb->reflection);
    gb->reflection = NULL;
    free(gb->extra); /* the old size's */
    gb->extra = NULL;
    return sl_gbuffer_use_extra(gb, extra, 0, err);
}

/* Allocate (on) or free one optional plane of texel_bytes a texel (`what` names it in the error);
 * *fresh says whether it was allocated now, its contents undefined until the caller clears it. */
static bool use_plane(const sl_gbuffer *gb, void **plane, bool on, size_t texel_bytes, const char *what, bool *fresh,
                      sl_error *err)
{
    *fresh = false;
    if (!on || !gb->texels) {
        free(*plane);
        *plane = NULL;
        return true;
    }
    if (*plane)
        return true;
    size_t bytes = (size_t)gb->width * (size_t)gb->height * texel_bytes;
    if (!(*plane = plane_alloc(bytes)))
        return sl_fail(err, SL_ERR_MEMORY, "gbuffer: out of memory for the %s of %dx%d (%zu bytes)", what, gb->width,
                       gb->height, bytes);
    *fresh = true;
    return true;
}

bool sl_gbuffer_use_facet(sl_gbuffer *gb, bool on, sl_error *err)
{
    void *plane = gb->facet;
    bool fresh;
    bool ok = use_plane(gb, &plane, on, sizeof *gb->facet, "facet plane", &fresh, err);
    gb->facet = plane;
    if (fresh)
        memset(gb->facet, 0, (size_t)gb->width * (size_t)gb->height * sizeof *gb->facet);
    return ok;
}

bool sl_gbuffer_use_extra(sl_gbuffer *gb, bool on, int threads, sl_error *err)
{
    void *plane = gb->extra;
    bool fresh;
    bool ok = use_plane(gb, &plane, on, sizeof *gb->extra, "extra channels", &fresh, err);
    gb->extra = plane;
    if (fresh)
        sl_gbuffer_extra_clear(gb, threads);
    return ok;
}

/* "Nothing drawn here": no occlusion, no emission, a depth no fragment has. */
static const sl_gbuffer_extra extra_none = {.occlusion = 1.0f, .depth = -1.0f};

void sl_gbuffer_extra_clear(sl_gbuffer *gb, int threads)
{
    if (!gb->extra)
        return;
    long n = (long)gb->width * gb->height;
    /* handed out in blocks as threads come free (a descheduled thread holds up no fixed half) */
#pragma omp parallel for schedule(dynamic, 16384) num_threads(sl_threads(threads))
    for (long i = 0; i < n; i++)
        gb->extra[i] = extra_none;
}

void sl_gbuffer_extra_resolve(sl_gbuffer *gb)
{
    sl_gbuffer_extra_resolve_rect(gb, 0, 0, gb->width - 1, gb->height - 1, NULL, 0);
}

void sl_gbuffer_extra_clear_rect(sl_gbuffer *gb, int x0, int y0, int x1, int y1)
{
    if (!gb->extra)
        return;
    /* the first row element by element, then the others copied from it: a tile row is a
     * contiguous run, and one memcpy writes it faster than 20-byte stores do */
    sl_gbuffer_extra *first = gb->extra + (size_t)y0 * (size_t)gb->width + (size_t)x0;
    for (int x = x0; x <= x1; x++)
        first[x - x0] = extra_none;
    for (int y = y0 + 1; y <= y1; y++)
        memcpy(gb->extra + (size_t)y * (size_t)gb->width + (size_t)x0, first, (size_t)(x1 - x0 + 1) * sizeof *first);
}

/* sl_gbuffer_extra_resolve's test, over a tile with its depths at hand (tile.c keeps them in a
 * plane of their own): the texels' depths, 56 bytes apart, are not read at all. An extra texel
 * already "none" (tag -1, never a depth) is left as it is rather than written again. */
void sl_gbuffer_extra_resolve_rect(sl_gbuffer *gb, int x0, int y0, int x1, int y1, const float *depth, int stride)
{
    if (!gb->extra)
        return;
    for (int y = y0; y <= y1; y++) {
        sl_gbuffer_extra *row = gb->extra + (size_t)y * (size_t)gb->width;
        const sl_gbuffer_texel *texels = gb->texels + (size_t)y * (size_t)gb->width;
        for (int x = x0; x <= x1; x++) {
            float tag = row[x].depth;
            float d = depth ? depth[(y - y0) * stride + (x - x0)] : texels[x].depth;
            if (tag != extra_none.depth && tag != d)
                row[x] = extra_none;
        }
    }
}

static void tile_clear(void *ctx, int x0, int y0, int x1, int y1) { sl_gbuffer_extra_clear_rect(ctx, x0, y0, x1, y1); }

static void tile_drawn(void *ctx, int x0, int y0, int x1, int y1, const float *depth, int stride)
{
    sl_gbuffer_extra_resolve_rect(ctx, x0, y0, x1, y1, depth, stride);
}

sl_target sl_gbuffer_target(sl_gbuffer *gb)
{
    return (sl_target){
        .width = gb->width,
        .height = gb->height,
        .texel_size = sizeof(sl_gbuffer_texel),
        .texels = gb->texels,
        .depth_offset = (long)offsetof(sl_gbuffer_texel, depth),
        .tile_clear = gb->extra ? tile_clear : NULL,
        .tile_drawn = gb->extra ? tile_drawn : NULL,
        .tile_ctx = gb,
        .facets = gb->facet,
    };
}

void sl_gbuffer_clear(sl_gbuffer *gb, int threads)
{
    if (!gb->texels)
        return;
    sl_gbuffer_extra_clear(gb, threads);
    if (gb->facet)
        memset(gb->facet, 0, (size_t)gb->width * (size_t)gb->height * sizeof *gb->facet);
    const sl_gbuffer_texel empty = {.depth = 1.0f};
    int w = gb->width;
#pragma omp parallel for schedule(dynamic, 16) num_threads(sl_threads(threads))
    for (int y = 0; y < gb->height; y++) {
        sl_gbuffer_texel *row = gb->texels + (size_t)y * (size_t)w;
        for (int x = 0; x < w; x++)
            row[x] = empty;
    }
}

void sl_gbuffer_free(sl_gbuffer *gb)
{
    free(gb->texels);
    free(gb->extra);
    free(gb->cone);
    free(gb->reflection);
    free(gb->facet);
    gb->facet = NULL;
    gb->texels = NULL;
    gb->extra = NULL;
    gb->cone = NULL;
    gb->reflection = NULL;
    gb->width = gb->height = 0;
}
