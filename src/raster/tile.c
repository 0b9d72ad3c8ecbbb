/* tile.c - the tile stage: coverage, early depth test and the fragment shader, for one tile.
 * This file draws a tile (its clear, its triangles through the paths, its depth plane); the
 * paths are in tile_plain.c, tile_span.c, tile_quad.c and tile_quads.c (tile_internal.h).
 *
 * Called from raster.c inside `omp parallel for` over tiles: a call touches only
 * the texels of its own tile and the calling thread's rast_task, so there are no
 * locks. Triangles are drawn in bin order (chunk 0 first, each chunk in submission
 * order), which is submission order: the result does not depend on the thread
 * count. Nothing here depends on the tile size either: coverage is exact integer
 * arithmetic and attributes are evaluated from absolute pixel indices.
 *
 * Coverage descends tile -> 8x8 block -> pixel. A bin item flagged full (setup.c)
 * covers the tile: no edge tests at all. Otherwise each block of the triangle's
 * bounds is classified from its corners (edge functions are linear, so their
 * extremes over a block are at corners): outside (skipped), inside (filled without
 * per-pixel tests), or partial (per-pixel edge tests).
 *
 * Two paths, chosen per draw (the specialised path, and the plain one beside it to compare
 * against):
 *   span   (the default) one row of the triangle's blocks at a time: a vectorized loop
 *          tests coverage and depth for the whole row, the passing columns are packed,
 *          a second loop interpolates z, 1/w and the varyings for them in structure-of-
 *          arrays form, and the fragment shader is called once for the row
 *          (sl_program.fragment_span), or per fragment from those arrays when the
 *          program has no span form. A small triangle (bounds at most 8 x 8 in the tile)
 *          of a program with a span form is one set: all its rows tested, packed and
 *          interpolated together, then a span call per row (small_tri_spans); without
 *          a span form, pixel by pixel. The vector loops run to a multiple of 8 lanes,
 *          the extra ones uncovered: no pixel goes through a scalar remainder.
 *   plain  (sl_raster_desc.plain) pixel by pixel, one fragment shader call each.
 * Both evaluate every value with the same expression, in the same order (no FMA
 * contraction: -std=c11 implies -ffp-contract=off), so they give the same bits;
 * tests/unit/test_raster_span.c compares them.
 * Programs with flags (chosen per triangle, so programs without them pay one test):
 *   quads  (sl_program.derivatives) aligned 2x2 quads over the same blocks, helpers for
 *          uncovered and occluded lanes, the lanes run in rounds (quad.c) or through the
 *          program's quad form (span path only), on both paths; a program with a multi-quad
 *          form (span path only) has up to 16 quads gathered and shaded in one call
 *          (quad_row_gather, a row of quads at a time; quads_flush).
 *   late   (sl_program.discards, no derivatives) pixel by pixel on both paths; the
 *          shader writes a scratch texel, copied with its depth unless it discarded.
 *
 * Depth: while a tile is drawn its depth values live in the thread's tile plane
 * (contiguous, hot in cache), loaded from and stored back to the target's texels.
 *
 * Clear (sl_draw.clear, first batch of a draw): the tile's texels are set to the clear
 * value just before the tile is drawn, and its depth plane starts at the clear depth
 * instead of being loaded (a tile nothing is drawn into stops after the clear: its
 * texels hold the clear depth already, so its depth plane is not written back). The
 * clear is then done by the thread that owns the tile, in parallel, and the fragment
 * shader's writes find the lines in cache (a 64x64 tile of 56-byte texels is 224 KB,
 * inside L2): the target goes through memory once per frame instead of twice (a
 * separate clear pass, then the draw). Clearing only the texels no fragment wrote,
 * after the tile, measured no faster, and would break shaders that read their texel
 * (blending, counting). Drawing the tile in a per-thread buffer and writing it out
 * with streaming stores (no read of the target's lines) measured no faster either:
 * what the clear costs is the G-buffer's write to memory (docs/performance.md
 * "Rasterizer"). The rows of a tile that no binned triangle
 * reaches (every row of an empty tile) are the exception: no fragment will write them, so
 * they are cleared with streaming stores, which skip the read of each line.
 * The target's tile hooks (sl_target.tile_clear, tile_drawn) run here too: after the tile's clear,
 * and after its triangles with the tile's depth plane, for data beside the texels (the G-buffer's
 * extra plane is cleared and resolved that way, in cache, instead of in two passes over memory). */
#include "tile_internal.h"

#include <stdint.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#define RAST_PREFETCH 8       /* bin items ahead whose triangle is loaded early */

/* ---- the tile ---- */

/* Copy `bytes` of the clear row to dst with streaming (non-temporal) stores: for texels no
 * fragment of this pass will write, which need not come through the cache. A store that fills
 * a whole cache line needs no read of it first: the write of an empty region costs about half
 * a cached copy's time (1.1 against 2.7 ms for a whole 1280x720 G-buffer in a throwaway
 * benchmark, 2 cores). The ends, outside whole lines, are copied as usual; without SSE2 all of it. */
static void clear_streaming(char *dst, const char *src, size_t bytes)
{
#if defined(__SSE2__)
    size_t head = (size_t)(-(uintptr_t)dst & (RAST_CACHE_LINE - 1)), k;
    head = head < bytes ? head : bytes;
    memcpy(dst, src, head);
    for (k = head; k + RAST_CACHE_LINE <= bytes; k += RAST_CACHE_LINE)
        for (int q = 0; q < RAST_CACHE_LINE; q += 16)
            _mm_stream_si128((__m128i *)(void *)(dst + k + q), _mm_loadu_si128((const __m128i *)(const void *)(src + k + q)));
    memcpy(dst + k, src + k, bytes - k);
#else
    memcpy(dst, src, bytes);
#endif
}

/* Streaming stores are not ordered with the others: fence them before the tile is done
 * (the pass's closing barrier then publishes them like any store). */
static void clear_streaming_done(void)
{
#if defined(__SSE2__)
    _mm_sfence();
#endif
}

void sl_rast_tile(const rast_draw *d, const rast_chunk *chunks, int chunk_count, int tile, rast_task *task)
{
    const char *clear = d->clear_row;
    bool any = false;
    for (int ci = 0; ci < chunk_count && !any; ci++)
        any = chunks[ci].bins[tile].count > 0;
    if (!any && !clear)
        return;

    const sl_target *tg = d->target;
    int ts = d->tile_size;
    int px0 = (tile % d->tiles_x) * ts, py0 = (tile / d->tiles_x) * ts;
    int px1 = px0 + ts - 1 < tg->width - 1 ? px0 + ts - 1 : tg->width - 1;
    int py1 = py0 + ts - 1 < tg->height - 1 ? py0 + ts - 1 : tg->height - 1;
    bool depth = tg->depth_offset >= 0;
    char *texels = tg->texels;
    size_t tsz = tg->texel_size;
    if (clear) {
        /* The rows no triangle of the tile reaches (all of them when nothing is binned) are
         * cleared with streaming stores; the others through the cache, where the fragments
         * will find them. */
        int uy0 = py1 + 1, uy1 = py0 - 1;
        for (int ci = 0; ci < chunk_count; ci++) {
            const rast_chunk *ch = &chunks[ci];
            for (int i = 0; i < ch->bins[tile].count; i++) {
                const rast_tri *t = &ch->tris[ch->bins[tile].items[i] & ~RAST_BIN_FULL];
                uy0 = t->ymin < uy0 ? t->ymin : uy0;
                uy1 = t->ymax > uy1 ? t->ymax : uy1;
            }
        }
        size_t bytes = (size_t)(px1 - px0 + 1) * tsz;
        for (int y = py0; y <= py1; y++) {
            char *row = texels + ((size_t)y * (size_t)tg->width + (size_t)px0) * tsz;
            if (y < uy0 || y > uy1)
                clear_streaming(row, clear, bytes);
            else
                memcpy(row, clear, bytes);
        }
        clear_streaming_done();
        if (tg->facets)
            for (int y = py0; y <= py1; y++)
                memset(tg->facets + (size_t)y * (size_t)tg->width + (size_t)px0, 0,
                       (size_t)(px1 - px0 + 1) * sizeof *tg->facets);
        if (tg->tile_clear)
            tg->tile_clear(tg->tile_ctx, px0, py0, px1, py1);
    }
    if (!any) /* cleared, nothing drawn: the clear texel holds the clear depth already */
        return;
    if (depth && clear) {
        for (int y = py0; y <= py1; y++)
            for (int x = px0; x <= px1; x++)
                task->depth[(y - py0) * ts + (x - px0)] = d->clear_depth;
    } else if (depth) {
        for (int y = py0; y <= py1; y++)
            for (int x = px0; x <= px1; x++)
                memcpy(&task->depth[(y - py0) * ts + (x - px0)],
                       texels + ((size_t)y * (size_t)tg->width + (size_t)x) * tsz + tg->depth_offset, sizeof(float));
    }

    tri_ctx c = {.d = d, .facets = tg->facets, .zbuf = task->depth, .px0 = px0, .py0 = py0, .ts = ts,
                 .texels = texels, .span = task->span, .quad = task->quad, .scratch = task->scratch};
    bool spans = d->spans && task->span;
    if (spans) {
        for (int i = 0; i < SL_MAX_VARYINGS; i++)
            c.sp.varyings[i] = task->span->vary[i];
        c.sp.x = task->span->x;
        c.sp.frag_z = task->span->z;
        c.sp.frag_w = task->span->iw;
        c.sp.texel_size = tsz;
    }
    if (spans && task->quads) {
        rast_quads *b = task->quads;
        c.batch = b;
        b->n = 0;
        for (int i = 0; i < SL_MAX_VARYINGS; i++)
            b->in.varyings[i] = b->vary[i];
        b->in.qx = b->qx;
        b->in.qy = b->qy;
        b->in.frag_z = b->z;
        b->in.frag_w = b->iw;
        b->in.helper = b->helper;
        b->in.texel = b->texel;
        b->in.discarded = b->discarded;
    }
    for (int ci = 0; ci < chunk_count; ci++) {
        const rast_chunk *ch = &chunks[ci];
        const rast_bin *bin = &ch->bins[tile];
        for (int i = 0; i < bin->count; i++) {
            uint32_t item = bin->items[i];
            const rast_tri *t = &ch->tris[item & ~RAST_BIN_FULL];
            /* The set-up triangles of a batch (a 128-byte rast_tri and 12 bytes of planes a
             * varying: 26 to 35 MB for RAST_BATCH = 131072 of the G-buffer programs' 6 or 12
             * varyings) are out of the caches by the time the tiles read them: start loading the
             * next ones' (their 2 lines and their planes) while this one is drawn. A hint: no
             * value depends on it. */
            if (i + RAST_PREFETCH < bin->count) {
                const rast_tri *next = &ch->tris[bin->items[i + RAST_PREFETCH] & ~RAST_BIN_FULL];
                __builtin_prefetch(next);
                __builtin_prefetch((const char *)next + RAST_CACHE_LINE);
                if (ch->vary)
                    __builtin_prefetch(ch->vary + next->vary);
            }
            c.t = t;
            c.call = &d->calls[t->call];
            /* a batch of programs without varyings has no varying store (NULL + 0 is undefined) */
            const float *planes = ch->vary ? ch->vary + t->vary : NULL;
            for (int k = 0, n = c.call->nvary; k < n; k++) {
                c.p0[k] = planes[3 * k];
                c.pdx[k] = planes[3 * k + 1];
                c.pdy[k] = planes[3 * k + 2];
            }
            if (c.facets) /* after the varyings' planes (setup.c) */
                c.facet = vec3(planes[3 * c.call->nvary], planes[3 * c.call->nvary + 1], planes[3 * c.call->nvary + 2]);
            int x0 = t->xmin > px0 ? t->xmin : px0, x1 = t->xmax < px1 ? t->xmax : px1;
            int y0 = t->ymin > py0 ? t->ymin : py0, y1 = t->ymax < py1 ? t->ymax : py1;
            bool full = (item & RAST_BIN_FULL) != 0;
            /* one test per triangle: programs without the flags take the paths they always took */
            const sl_program *prog = c.call->program;
            if (prog->derivatives || prog->discards) {
                bool multi = prog->derivatives && prog->fragment_quads && c.batch;
                if (multi && depth)
                    sl_rast_tri_multi_depth(&c, full, x0, y0, x1, y1);
                else if (multi)
                    sl_rast_tri_multi_nodepth(&c, full, x0, y0, x1, y1);
                else if (prog->derivatives && depth)
                    sl_rast_tri_quads_depth(&c, full, x0, y0, x1, y1);
                else if (prog->derivatives)
                    sl_rast_tri_quads_nodepth(&c, full, x0, y0, x1, y1);
                else if (depth)
                    sl_rast_tri_late_depth(&c, full, x0, y0, x1, y1);
                else
                    sl_rast_tri_late_nodepth(&c, full, x0, y0, x1, y1);
            } else if (spans && depth)
                sl_rast_tri_spans_depth(&c, full, x0, y0, x1, y1);
            else if (spans)
                sl_rast_tri_spans_nodepth(&c, full, x0, y0, x1, y1);
            else if (depth)
                sl_rast_tri_plain_depth(&c, full, x0, y0, x1, y1);
            else
                sl_rast_tri_plain_nodepth(&c, full, x0, y0, x1, y1);
        }
    }
    task->stats.fragments_tested += c.tested;
    task->stats.fragments_shaded += c.shaded;
    task->stats.blocks_full += c.blocks_full;
    task->stats.fragments_discarded += c.discarded;
    task->stats.fragments_late_z += c.late_z;
    task->stats.quads += c.quads;
    task->stats.quad_rounds += c.rounds;
    task->stats.helper_invocations += c.helpers;

    /* the tile's depths back into its texels, unless every program wrote each fragment's depth
     * there itself (sl_program.writes_depth): a fragment that passes sets the plane and its texel to
     * the same z, and one that fails or discards changes neither */
    if (depth && !d->depth_written)
        for (int y = py0; y <= py1; y++)
            for (int x = px0; x <= px1; x++)
                memcpy(texels + ((size_t)y * (size_t)tg->width + (size_t)x) * tsz + tg->depth_offset,
                       &task->depth[(y - py0) * ts + (x - px0)], sizeof(float));
    if (tg->tile_drawn)
        tg->tile_drawn(tg->tile_ctx, px0, py0, px1, py1, depth ? task->depth : NULL, ts);
}
