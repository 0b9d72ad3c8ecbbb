/* tile.c - the tile stage: coverage, early depth test and the fragment shader, for one tile.
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
#include "rast_internal.h"

#include <stdint.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#define RAST_PREFETCH 8       /* bin items ahead whose triangle is loaded early */

typedef struct {
    const rast_draw *d;
    const rast_call *call; /* the current triangle's draw */
    const rast_tri *t;
    /* the triangle's varying planes by coefficient (setup.c stores f0, fdx, fdy per varying;
     * copied per triangle: three short loops), so that the per-fragment and per-quad loops over
     * the varyings read each array contiguously and vectorize; the values and the expression are
     * the planes', so the bits are too */
    _Alignas(RAST_CACHE_LINE) float p0[SL_MAX_VARYINGS];
    float pdx[SL_MAX_VARYINGS], pdy[SL_MAX_VARYINGS];
    float *zbuf;         /* tile-local depth */
    int px0, py0, ts;    /* tile origin and size */
    char *texels;
    rast_span *span;     /* span path scratch */
    sl_fragment_span sp; /* span path: what the span shader gets (arrays point into span) */
    sl_quad *quad;       /* quads and discards: the task's */
    rast_quads *batch;   /* multi-quad shaders: the quads gathered so far (span path) */
    char *scratch;       /* 4 texels: what quad lanes and discarding fragments write first */
    long long tested, shaded, blocks_full;
    long long discarded, late_z, quads, rounds, helpers;
} tri_ctx;

/* ---- the plain path ---- */

/* Window depth, clamped to [0, 1], at pixel offset (fx, fy) from the triangle's origin. */
static inline __attribute__((always_inline)) float depth_at(const rast_tri *t, float fx, float fy)
{
    return clampf(t->z[0] + t->z[1] * fx + t->z[2] * fy, 0.0f, 1.0f);
}

/* Perspective-correct varyings at (fx, fy): v/w and 1/w interpolated linearly, divided.
 * Returns 1/w (gl_FragCoord.w). Used wherever a fragment's inputs are made, so every
 * path gets the same bits. */
static inline __attribute__((always_inline)) float varyings_at(const tri_ctx *c, float fx, float fy, float *vary)
{
    const rast_tri *t = c->t;
    float iw = clampf(t->iw[0] + t->iw[1] * fx + t->iw[2] * fy, t->iw_lo, t->iw_hi);
    float w = 1.0f / iw;
    int n = c->call->nvary;
    for (int i = 0; i < n; i++)
        vary[i] = (c->p0[i] + c->pdx[i] * fx + c->pdy[i] * fy) * w;
    return iw;
}

/* One covered pixel: depth (choose per draw: `depth` is a constant after inlining),
 * varyings, shade. `late` (a program that may discard, also a constant): the depth test
 * comes first but depth and texel are written after the shader, only if it did not
 * discard; the shader writes a scratch copy of the texel meanwhile. */
static inline __attribute__((always_inline)) void fragment(tri_ctx *c, int x, int y, const bool depth,
                                                           const bool late)
{
    const rast_tri *t = c->t;
    float fx = (float)x - (float)t->xmin, fy = (float)y - (float)t->ymin;
    float z = depth_at(t, fx, fy);
    c->tested++;
    float *zp = NULL;
    if (depth) {
        zp = &c->zbuf[(y - c->py0) * c->ts + (x - c->px0)];
        if (!(z < *zp))
            return;
        if (!late)
            *zp = z;
    }
    float vary[SL_MAX_VARYINGS];
    float iw = varyings_at(c, fx, fy, vary);
    sl_fragment_in in = {
        .varyings = vary,
        .frag_coord = vec4((float)x + 0.5f, (float)y + 0.5f, z, iw),
        .front_facing = t->front,
        .x = x,
        .y = y,
    };
    const sl_target *tg = c->d->target;
    void *texel = c->texels + ((size_t)y * (size_t)tg->width + (size_t)x) * tg->texel_size;
    c->shaded++;
    if (!late) {
        c->call->program->fragment(c->call->fs_uniforms, &in, texel);
        return;
    }
    in.quad = c->quad;
    in.lane = (x & 1) + 2 * (y & 1);
    sl_rast_quad_begin(c->quad, false, false);
    memcpy(c->scratch, texel, tg->texel_size);
    c->call->program->fragment(c->call->fs_uniforms, &in, c->scratch);
    if (c->quad->discarded[in.lane]) {
        c->discarded++;
        return;
    }
    memcpy(texel, c->scratch, tg->texel_size);
    if (depth) {
        *zp = z;
        c->late_z++;
    }
}

static inline __attribute__((always_inline)) void fill_rect(tri_ctx *c, int x0, int y0, int x1, int y1,
                                                            const bool depth, const bool late)
{
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            fragment(c, x, y, depth, late);
}

/* Block classification: 1 outside, 2 inside (no per-pixel test needed), 0 partial. */
enum { BLOCK_PARTIAL, BLOCK_OUTSIDE, BLOCK_INSIDE };
static inline int classify(const rast_tri *t, int rx0, int ry0, int rx1, int ry1)
{
    bool outside = false, inside = true;
    for (int k = 0; k < 3; k++) {
        int64_t emax = t->ec[k] + t->ex[k] * (t->ex[k] > 0 ? rx1 : rx0) + t->ey[k] * (t->ey[k] > 0 ? ry1 : ry0);
        int64_t emin = t->ec[k] + t->ex[k] * (t->ex[k] > 0 ? rx0 : rx1) + t->ey[k] * (t->ey[k] > 0 ? ry0 : ry1);
        outside |= emax < 0;
        inside &= emin >= 0;
    }
    return outside ? BLOCK_OUTSIDE : inside ? BLOCK_INSIDE : BLOCK_PARTIAL;
}

/* Draw triangle t over the rectangle [x0,x1] x [y0,y1] (its bounds inside the tile). */
static inline __attribute__((always_inline)) void draw_tri(tri_ctx *c, bool full, int x0, int y0, int x1, int y1,
                                                           const bool depth, const bool late)
{
    const rast_tri *t = c->t;
    if (full) {
        fill_rect(c, x0, y0, x1, y1, depth, late);
        return;
    }
    int bx0 = x0 & ~(RAST_BLOCK - 1), by0 = y0 & ~(RAST_BLOCK - 1);
    for (int by = by0; by <= y1; by += RAST_BLOCK) {
        int ry0 = by > y0 ? by : y0, ry1 = by + RAST_BLOCK - 1 < y1 ? by + RAST_BLOCK - 1 : y1;
        for (int bx = bx0; bx <= x1; bx += RAST_BLOCK) {
            int rx0 = bx > x0 ? bx : x0, rx1 = bx + RAST_BLOCK - 1 < x1 ? bx + RAST_BLOCK - 1 : x1;
            int cls = classify(t, rx0, ry0, rx1, ry1);
            if (cls == BLOCK_OUTSIDE)
                continue;
            if (cls == BLOCK_INSIDE) {
                c->blocks_full++;
                fill_rect(c, rx0, ry0, rx1, ry1, depth, late);
                continue;
            }
            for (int y = ry0; y <= ry1; y++) {
                int64_t e0 = t->ec[0] + t->ex[0] * rx0 + t->ey[0] * y;
                int64_t e1 = t->ec[1] + t->ex[1] * rx0 + t->ey[1] * y;
                int64_t e2 = t->ec[2] + t->ex[2] * rx0 + t->ey[2] * y;
                for (int x = rx0; x <= rx1; x++) {
                    if ((e0 | e1 | e2) >= 0)
                        fragment(c, x, y, depth, late);
                    e0 += t->ex[0];
                    e1 += t->ex[1];
                    e2 += t->ex[2];
                }
            }
        }
    }
}

/* ---- the span path ---- */

/* Row y from column x0 of the current triangle, `count` columns (a multiple of 8, or a
 * constant: one vector loop with no scalar remainder), of which the first n are the span:
 * coverage (per pixel when `edges`; the others count as covered) and the depth test (when
 * `depth`: the tile plane's row updated, lanes that fail storing back what they loaded, so the
 * plane is padded past a row's end: raster.c), into flags[j]: bit 0 covered, bit 1 passed.
 * Columns past n are neither. Every value is fragment()'s expression, term for term. */
static inline __attribute__((always_inline)) void cover_and_test(const tri_ctx *c, int y, int x0, int n, int count,
                                                                 const bool edges, const bool depth, int32_t *flags)
{
    const rast_tri *t = c->t;
    const float fy = (float)y - (float)t->ymin, ox = (float)t->xmin;
    const float z0 = t->z[0], z1 = t->z[1], z2fy = t->z[2] * fy;
    const int64_t a0 = t->ex[0], a1 = t->ex[1], a2 = t->ex[2];
    const int64_t r0 = t->ec[0] + t->ey[0] * y, r1 = t->ec[1] + t->ey[1] * y, r2 = t->ec[2] + t->ey[2] * y;
    float *zrow = c->zbuf + (y - c->py0) * c->ts + (x0 - c->px0);
#pragma omp simd
    for (int j = 0; j < count; j++) {
        int64_t x = x0 + j;
        int64_t e0 = r0 + a0 * x, e1 = r1 + a1 * x, e2 = r2 + a2 * x;
        int32_t cov = (!edges | ((e0 | e1 | e2) >= 0)) & (j < n);
        int32_t pass = cov;
        if (depth) {
            float fx = (float)(x0 + j) - ox;
            float z = clampf(z0 + z1 * fx + z2fy, 0.0f, 1.0f);
            float old = zrow[j];
            pass = cov & (z < old);
            zrow[j] = pass ? z : old;
        }
        flags[j] = cov | pass << 1;
    }
}

/* Row y, columns [x0, x1] of the current triangle: coverage (per pixel when `edges`),
 * the depth test (when `depth`), then one shader call for the passing fragments.
 * Every value is the plain path's expression, term for term: fragment() above. */
static inline __attribute__((always_inline)) void span_row(tri_ctx *c, int y, int x0, int x1, const bool edges,
                                                           const bool depth)
{
    const rast_tri *t = c->t;
    rast_span *s = c->span;
    int n = x1 - x0 + 1;
    float fy = (float)y - (float)t->ymin, ox = (float)t->xmin;
    float z0 = t->z[0], z1 = t->z[1], z2fy = t->z[2] * fy;
    int32_t *flags = s->flags;
    /* The vector loops run to a multiple of 8 (n8, m8 below), the extra lanes uncovered or
     * unread, so that no column goes through a scalar remainder: as in small_tri_spans. */
    cover_and_test(c, y, x0, n, (n + 7) & ~7, edges, depth, flags);

    /* pack the passing columns */
    int m = 0, tested = 0;
    for (int j = 0; j < n; j++) {
        s->x[m] = x0 + j;
        m += flags[j] >> 1;
        tested += flags[j] & 1;
    }
    c->tested += tested;
    if (m == 0)
        return;

    const int m8 = (m + 7) & ~7;
    float iw0 = t->iw[0], iw1 = t->iw[1], iw2fy = t->iw[2] * fy, lo = t->iw_lo, hi = t->iw_hi;
#pragma omp simd
    for (int j = 0; j < m8; j++) {
        float fx = (float)s->x[j] - ox;
        float iw = clampf(iw0 + iw1 * fx + iw2fy, lo, hi);
        s->z[j] = clampf(z0 + z1 * fx + z2fy, 0.0f, 1.0f);
        s->iw[j] = iw;
        s->w[j] = 1.0f / iw;
    }
    int nvary = c->call->nvary;
    for (int i = 0; i < nvary; i++) {
        float p0 = c->p0[i], p1 = c->pdx[i], p2fy = c->pdy[i] * fy;
        float *out = s->vary[i];
#pragma omp simd
        for (int j = 0; j < m8; j++) {
            float fx = (float)s->x[j] - ox;
            out[j] = (p0 + p1 * fx + p2fy) * s->w[j];
        }
    }

    const sl_program *prog = c->call->program;
    const sl_target *tg = c->d->target;
    char *row = c->texels + (size_t)y * (size_t)tg->width * tg->texel_size;
    if (prog->fragment_span) {
        c->sp.n = m;
        c->sp.y = y;
        c->sp.front_facing = t->front;
        c->sp.row = row;
        prog->fragment_span(c->call->fs_uniforms, &c->sp);
    } else {
        for (int j = 0; j < m; j++) {
            float vary[SL_MAX_VARYINGS];
            for (int i = 0; i < nvary; i++)
                vary[i] = s->vary[i][j];
            int x = s->x[j];
            sl_fragment_in in = {
                .varyings = vary,
                .frag_coord = vec4((float)x + 0.5f, (float)y + 0.5f, s->z[j], s->iw[j]),
                .front_facing = t->front,
                .x = x,
                .y = y,
            };
            prog->fragment(c->call->fs_uniforms, &in, row + (size_t)x * tg->texel_size);
        }
    }
    c->shaded += m;
}

/* A block row of a triangle's bounds: its pixel rows [y0, y1] and the run of blocks in it that
 * are not outside, columns [lo, hi] (the triangle is convex, so they form one run); inside when
 * every block of the run is. */
typedef struct {
    int y0, y1, lo, hi;
    bool inside;
} block_run;

/* The block row starting at `by` of the bounds [x0, x1] x [y0, y1]; false when it has no block
 * that is not outside. */
static inline bool block_row_run(tri_ctx *c, int by, int x0, int y0, int x1, int y1, block_run *run)
{
    run->y0 = by > y0 ? by : y0;
    run->y1 = by + RAST_BLOCK - 1 < y1 ? by + RAST_BLOCK - 1 : y1;
    run->lo = x1 + 1;
    run->hi = x0 - 1;
    run->inside = true;
    for (int bx = x0 & ~(RAST_BLOCK - 1); bx <= x1; bx += RAST_BLOCK) {
        int rx0 = bx > x0 ? bx : x0, rx1 = bx + RAST_BLOCK - 1 < x1 ? bx + RAST_BLOCK - 1 : x1;
        int cls = classify(c->t, rx0, run->y0, rx1, run->y1);
        if (cls == BLOCK_OUTSIDE)
            continue;
        c->blocks_full += cls == BLOCK_INSIDE;
        run->inside &= cls == BLOCK_INSIDE;
        run->lo = rx0 < run->lo ? rx0 : run->lo;
        run->hi = rx1 > run->hi ? rx1 : run->hi;
    }
    return run->lo <= run->hi;
}

/* The span path's draw_tri: the same blocks, drawn a block row at a time. In each
 * block row the blocks that are not outside form one run (the triangle is convex);
 * each pixel row of the run is one span, tested per pixel unless every block of the
 * run is inside. */
static inline __attribute__((always_inline)) void draw_tri_spans(tri_ctx *c, bool full, int x0, int y0, int x1,
                                                                 int y1, const bool depth)
{
    if (full) {
        for (int y = y0; y <= y1; y++)
            span_row(c, y, x0, x1, false, depth);
        return;
    }
    for (int by = y0 & ~(RAST_BLOCK - 1); by <= y1; by += RAST_BLOCK) {
        block_run run;
        if (!block_row_run(c, by, x0, y0, x1, y1, &run))
            continue;
        for (int y = run.y0; y <= run.y1; y++) {
            if (run.inside) /* a constant at each call: span_row without its edge tests */
                span_row(c, y, run.lo, run.hi, false, depth);
            else
                span_row(c, y, run.lo, run.hi, true, depth);
        }
    }
}

static void draw_tri_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri(c, full, x0, y0, x1, y1, true, false);
}

static void draw_tri_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri(c, full, x0, y0, x1, y1, false, false);
}

/* A program that may discard and takes no derivative: pixel by pixel on both paths
 * (a span shader has no way to say which fragments it discarded). */
static void draw_tri_late_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri(c, full, x0, y0, x1, y1, true, true);
}

static void draw_tri_late_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri(c, full, x0, y0, x1, y1, false, true);
}

/* Small triangles (few pixels a row): a span per row does not pay back its fixed cost
 * (three vector loops, the packing, a call) with a handful of pixels. */
static inline bool small_tri(int x0, int y0, int x1, int y1)
{
    return x1 - x0 < RAST_SPAN_MIN_WIDTH && y1 - y0 < RAST_BLOCK;
}
_Static_assert(RAST_SPAN_MIN_WIDTH * RAST_BLOCK <= SL_SPAN_MAX, "a small triangle's pixels fit one rast_span");

/* A small triangle of a program with a span form, over its whole bounds [x0,x1] x [y0,y1]
 * at once: coverage and depth row by row (span_row's first loop, no block classification:
 * the bounds are at most 8x8), the passing pixels of every row packed into one set, z, 1/w
 * and the varyings interpolated for the whole set in one loop each, then one span call per
 * row that has any. The pixel-by-pixel path it replaces took a branch per pixel (coverage,
 * depth) and an indirect call per fragment. Every value is fragment()'s expression, term for
 * term (fy per pixel instead of per row: the same product). */
static inline __attribute__((always_inline)) void small_tri_spans(tri_ctx *c, bool full, int x0, int y0, int x1,
                                                                  int y1, const bool depth)
{
    const rast_tri *t = c->t;
    rast_span *s = c->span;
    const int n = x1 - x0 + 1;
    const float ox = (float)t->xmin, z0 = t->z[0], z1 = t->z[1], z2 = t->z[2];
    int32_t *flags = s->flags; /* bit 0: covered, bit 1: passed the depth test */
    int row_end[RAST_BLOCK];   /* packed fragments after each row */
    int m = 0, tested = 0;
    for (int y = y0; y <= y1; y++) {
        const float fy = (float)y - (float)t->ymin;
        /* Always RAST_SPAN_MIN_WIDTH columns, those past n uncovered: a loop of a fixed count
         * is one vector step, where n columns (often 2-6) went through the scalar remainder. */
        cover_and_test(c, y, x0, n, RAST_SPAN_MIN_WIDTH, !full, depth, flags);
        for (int j = 0; j < n; j++) {
            s->x[m] = x0 + j;
            s->fy[m] = fy;
            m += flags[j] >> 1;
            tested += flags[j] & 1;
        }
        row_end[y - y0] = m;
    }
    c->tested += tested;
    if (m == 0)
        return;

    /* The loops run to m rounded up to 8 (m is often under 8: without the rounding those
     * fragments would all go through the loops' scalar remainder). The lanes past m read
     * x and fy left by earlier sets (finite: the span is zeroed when allocated, raster.c)
     * and write results no span call reads. */
    const int m8 = (m + 7) & ~7;
    const float iw0 = t->iw[0], iw1 = t->iw[1], iw2 = t->iw[2], lo = t->iw_lo, hi = t->iw_hi;
#pragma omp simd
    for (int j = 0; j < m8; j++) {
        float fx = (float)s->x[j] - ox, fy = s->fy[j];
        float iw = clampf(iw0 + iw1 * fx + iw2 * fy, lo, hi);
        s->z[j] = clampf(z0 + z1 * fx + z2 * fy, 0.0f, 1.0f);
        s->iw[j] = iw;
        s->w[j] = 1.0f / iw;
    }
    const int nvary = c->call->nvary;
    for (int i = 0; i < nvary; i++) {
        const float p0 = c->p0[i], p1 = c->pdx[i], p2 = c->pdy[i];
        float *out = s->vary[i];
#pragma omp simd
        for (int j = 0; j < m8; j++) {
            float fx = (float)s->x[j] - ox;
            out[j] = (p0 + p1 * fx + p2 * s->fy[j]) * s->w[j];
        }
    }

    /* one span a row: the arrays from the row's first packed fragment */
    const sl_program *prog = c->call->program;
    const sl_target *tg = c->d->target;
    sl_fragment_span sp = c->sp;
    sp.front_facing = t->front;
    for (int y = y0, start = 0; y <= y1; y++) {
        int end = row_end[y - y0];
        if (end == start)
            continue;
        sp.n = end - start;
        sp.y = y;
        sp.x = s->x + start;
        for (int i = 0; i < nvary; i++)
            sp.varyings[i] = s->vary[i] + start;
        sp.frag_z = s->z + start;
        sp.frag_w = s->iw + start;
        sp.row = c->texels + (size_t)y * (size_t)tg->width * tg->texel_size;
        prog->fragment_span(c->call->fs_uniforms, &sp);
        start = end;
    }
    c->shaded += m;
}

/* The span path: small triangles of a program with a span form as one set
 * (small_tri_spans), of one without pixel by pixel (draw_tri), the others a span a row.
 * All give the same bits, so the choice is free. */
static void draw_tri_spans_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    if (!small_tri(x0, y0, x1, y1))
        draw_tri_spans(c, full, x0, y0, x1, y1, true);
    else if (c->call->program->fragment_span)
        small_tri_spans(c, full, x0, y0, x1, y1, true);
    else
        draw_tri(c, full, x0, y0, x1, y1, true, false);
}

static void draw_tri_spans_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    if (!small_tri(x0, y0, x1, y1))
        draw_tri_spans(c, full, x0, y0, x1, y1, false);
    else if (c->call->program->fragment_span)
        small_tri_spans(c, full, x0, y0, x1, y1, false);
    else
        draw_tri(c, full, x0, y0, x1, y1, false, false);
}

/* ---- the quad path (programs that take derivatives) ---- */

/* The quad at (qx, qy) (both even) whose lanes `cov` (bit l: pixel (qx + (l & 1),
 * qy + (l >> 1))) the triangle covers. The depth test picks the live lanes (early write
 * unless the program may discard); a quad with none is not shaded. Every lane's inputs
 * are made at its pixel centre (the uncovered ones extrapolated from the same planes),
 * the lanes run through the shader in rounds into scratch texels (quad.c), or once
 * through the program's quad form on the span path; then each live lane that did not
 * discard is written. Helpers write nothing.
 *
 * A quad form that writes its whole texel (sl_program.quad_writes_texel) reads nothing
 * of it, so its texels are not copied in: a live lane of a program that cannot discard
 * writes the target's texel in place (no copy out either), the others write scratch. */
static inline __attribute__((always_inline)) void quad(tri_ctx *c, int qx, int qy, unsigned cov, const bool depth)
{
    const rast_tri *t = c->t;
    const sl_program *prog = c->call->program;
    const bool late = prog->discards;
    const sl_target *tg = c->d->target;
    const size_t tsz = tg->texel_size;
    /* the lanes' offsets from the triangle's origin: lane l (pixel (qx + (l & 1), qy + (l >> 1)))
     * is at (fx[l], fy[l]) */
    const float fx0 = (float)qx - (float)t->xmin, fx1 = (float)(qx + 1) - (float)t->xmin;
    const float fy0 = (float)qy - (float)t->ymin, fy1 = (float)(qy + 1) - (float)t->ymin;
    const float fx[4] = {fx0, fx1, fx0, fx1}, fy[4] = {fy0, fy0, fy1, fy1};
    float z[4];
    for (int l = 0; l < 4; l++)
        z[l] = depth_at(t, fx[l], fy[l]);
    unsigned live = 0;
    for (int l = 0; l < 4; l++) {
        int x = qx + (l & 1), y = qy + (l >> 1);
        if (!(cov >> l & 1))
            continue;
        c->tested++;
        if (depth) {
            float *zp = &c->zbuf[(y - c->py0) * c->ts + (x - c->px0)];
            if (!(z[l] < *zp))
                continue;
            if (!late)
                *zp = z[l];
        }
        live |= 1u << l;
    }
    if (!live)
        return;

    /* The lanes' inputs, varyings_at's expressions: 1/w for the four lanes at once, then each
     * lane's varyings in one loop over the coefficient arrays (both loops vectorize). A helper's
     * 1/w is the plane extrapolated, unclamped, as llvmpipe makes it: a helper lies outside the
     * triangle, where clamping to the vertices' range bent its varyings and so the quad's
     * derivatives (lambda up to 1.4 off llvmpipe's on textured.json's sphere seam; unclamped,
     * within 0.001 on every quad: docs/shader-api.md "Level of detail"). Live lanes keep the
     * clamp, which only holds their rounding inside the triangle. */
    float iw[4], w[4];
    for (int l = 0; l < 4; l++) {
        float plane = t->iw[0] + t->iw[1] * fx[l] + t->iw[2] * fy[l];
        iw[l] = live >> l & 1 ? clampf(plane, t->iw_lo, t->iw_hi) : plane;
        w[l] = 1.0f / iw[l];
    }
    float vary[4][SL_MAX_VARYINGS];
    const int n = c->call->nvary;
    for (int l = 0; l < 4; l++) {
        const float lx = fx[l], ly = fy[l], lw = w[l];
#pragma omp simd
        for (int i = 0; i < n; i++)
            vary[l][i] = (c->p0[i] + c->pdx[i] * lx + c->pdy[i] * ly) * lw;
    }
    sl_fragment_in in[4];
    char *target[4]; /* the lane's texel, NULL outside the target (odd sizes) */
    void *out[4];    /* what the shader writes: scratch, or the target's texel in place */
    bool quad_form = prog->fragment_quad && c->d->spans;
    bool fresh = quad_form && prog->quad_writes_texel; /* no copy in */
    for (int l = 0; l < 4; l++) {
        int x = qx + (l & 1), y = qy + (l >> 1);
        in[l] = (sl_fragment_in){
            .varyings = vary[l],
            .frag_coord = vec4((float)x + 0.5f, (float)y + 0.5f, z[l], iw[l]),
            .front_facing = t->front,
            .x = x,
            .y = y,
            .quad = c->quad,
            .lane = l,
            .helper = !(live >> l & 1),
        };
        target[l] = x < tg->width && y < tg->height
                        ? c->texels + ((size_t)y * (size_t)tg->width + (size_t)x) * tsz
                        : NULL;
        out[l] = fresh && !late && (live >> l & 1) ? target[l] : c->scratch + (size_t)l * tsz;
    }
    int rounds = 0;
    sl_rast_quad_begin(c->quad, !quad_form, prog->stores);
    do {
        /* every round starts from the target's texels, so rounds do not see each other */
        sl_rast_quad_round(c->quad);
        if (!fresh)
            for (int l = 0; l < 4; l++) {
                if (target[l])
                    memcpy(out[l], target[l], tsz);
                else
                    memset(out[l], 0, tsz);
            }
        if (quad_form) {
            prog->fragment_quad(c->call->fs_uniforms, in, out);
        } else {
            for (int l = 0; l < 4; l++)
                prog->fragment(c->call->fs_uniforms, &in[l], out[l]);
        }
        rounds++;
    } while (!quad_form && !sl_rast_quad_done(c->quad, rounds));

    c->quads++;
    c->rounds += rounds;
    for (int l = 0; l < 4; l++) {
        if (!(live >> l & 1)) {
            c->helpers++;
            continue;
        }
        c->shaded++;
        if (c->quad->discarded[l]) {
            c->discarded++;
            continue;
        }
        if (out[l] != target[l])
            memcpy(target[l], out[l], tsz);
        if (depth && late) {
            int x = qx + (l & 1), y = qy + (l >> 1);
            c->zbuf[(y - c->py0) * c->ts + (x - c->px0)] = z[l];
            c->late_z++;
        }
    }
}

/* ---- the multi-quad path (sl_program.fragment_quads, span path) ----
 * quad() split in two: quad_row_gather runs the depth test of a row of quads and keeps each
 * quad's lane offsets; quads_flush makes the inputs of every gathered lane at once (quad()'s
 * expressions, in loops over up to 64 lanes), calls the shader once, then writes what quad()
 * writes. The quads of
 * one triangle cover disjoint pixels, so testing a later quad's depth before an earlier one
 * is shaded changes nothing; the batch is flushed when full and at the end of the triangle. */
static void quads_flush(tri_ctx *c, const bool depth)
{
    rast_quads *b = c->batch;
    const int n = b->n, lanes = 4 * n;
    if (n == 0)
        return;
    const rast_tri *t = c->t;
    const sl_program *prog = c->call->program;
    const bool late = prog->discards, fresh = prog->quad_writes_texel;
    const sl_target *tg = c->d->target;
    const size_t tsz = tg->texel_size;
    const float iw0 = t->iw[0], iw1 = t->iw[1], iw2 = t->iw[2], lo = t->iw_lo, hi = t->iw_hi;
#pragma omp simd
    for (int j = 0; j < lanes; j++) {
        float plane = iw0 + iw1 * b->fx[j] + iw2 * b->fy[j];
        float iw = b->helper[j] ? plane : clampf(plane, lo, hi);
        b->iw[j] = iw;
        b->w[j] = 1.0f / iw;
    }
    const int nv = c->call->nvary;
    for (int i = 0; i < nv; i++) {
        const float p0 = c->p0[i], p1 = c->pdx[i], p2 = c->pdy[i];
        float *out = b->vary[i];
#pragma omp simd
        for (int j = 0; j < lanes; j++)
            out[j] = (p0 + p1 * b->fx[j] + p2 * b->fy[j]) * b->w[j];
    }
    const size_t row = (size_t)tg->width * tsz;
    for (int k = 0; k < n; k++) {
        int qx = b->qx[k], qy = b->qy[k];
        char *lane0 = c->texels + (size_t)qy * row + (size_t)qx * tsz;
        bool right = qx + 1 < tg->width, top = qy + 1 < tg->height; /* false only at odd sizes */
        char *target[4] = {lane0, right ? lane0 + tsz : NULL, top ? lane0 + row : NULL,
                           right && top ? lane0 + row + tsz : NULL};
        for (int l = 0; l < 4; l++) {
            int j = 4 * k + l;
            b->target[j] = target[l];
            b->texel[j] = fresh && !late && !b->helper[j] ? target[l] : c->scratch + (size_t)j * tsz;
        }
    }
    for (int j = 0; j < lanes; j++)
        b->discarded[j] = 0;
    if (!fresh)
        for (int j = 0; j < lanes; j++) {
            if (b->target[j])
                memcpy(b->texel[j], b->target[j], tsz);
            else
                memset(b->texel[j], 0, tsz);
        }
    b->in.n = n;
    b->in.front_facing = t->front;
    prog->fragment_quads(c->call->fs_uniforms, &b->in);

    c->quads += n;
    c->rounds += n;
    int helpers = 0, discarded = 0;
    for (int j = 0; j < lanes; j++) {
        helpers += b->helper[j];
        discarded += b->discarded[j] & !b->helper[j];
    }
    c->helpers += helpers;
    c->shaded += lanes - helpers;
    c->discarded += discarded;
    if (fresh && !late && discarded == 0) { /* every live lane wrote its texel in place */
        b->n = 0;
        return;
    }
    for (int j = 0; j < lanes; j++) {
        if (b->helper[j] || b->discarded[j])
            continue;
        if (b->texel[j] != b->target[j])
            memcpy(b->target[j], b->texel[j], tsz);
        if (depth && late) {
            int x = b->qx[j >> 2] + (j & 1), y = b->qy[j >> 2] + ((j >> 1) & 1);
            c->zbuf[(y - c->py0) * c->ts + (x - c->px0)] = b->z[j];
            c->late_z++;
        }
    }
    b->n = 0;
}

/* The multi-quad path's coverage and depth test, a row of quads at a time: the quads at
 * (xa + 2k, qy) (xa even) up to column hi, of the triangle over the rectangle [lo, hi] x [y0, y1]
 * (lanes outside it uncovered), edge tests per lane when `edges`. One vector loop over both pixel
 * rows makes each lane's depth (depth_at's expression), coverage (draw_tri_quads's) and depth
 * test (quad()'s: the plane updated unless the program may discard, lanes that fail storing
 * back what they loaded, as cover_and_test; its lanes past hi are uncovered); then each quad with
 * a live lane joins the batch with its lanes' offsets, depths and helper flags. The per-lane
 * branches and 64-bit edge products of draw_tri_quads's lane loop were 40% of sl_rast_tile on
 * pbr.json. */
static inline __attribute__((always_inline)) void quad_row_gather(tri_ctx *c, int qy, int xa, int lo, int hi, int y0,
                                                                  int y1, const bool edges, const bool depth)
{
    const rast_tri *t = c->t;
    const bool late = c->call->program->discards;
    const int count = (hi - xa + 1 + 7) & ~7; /* a multiple of 8, past the last quad's right lane */
    const float ox = (float)t->xmin, z0 = t->z[0], z1 = t->z[1];
    const float fy0 = (float)qy - (float)t->ymin, fy1 = (float)(qy + 1) - (float)t->ymin;
    const float z2fy0 = t->z[2] * fy0, z2fy1 = t->z[2] * fy1;
    const int64_t a0 = t->ex[0], a1 = t->ex[1], a2 = t->ex[2];
    const int64_t r00 = t->ec[0] + t->ey[0] * qy, r01 = t->ec[1] + t->ey[1] * qy, r02 = t->ec[2] + t->ey[2] * qy;
    const int64_t r10 = r00 + t->ey[0], r11 = r01 + t->ey[1], r12 = r02 + t->ey[2];
    const int32_t row0 = qy >= y0 && qy <= y1, row1 = qy + 1 >= y0 && qy + 1 <= y1;
    float *zr0 = c->zbuf + (qy - c->py0) * c->ts + (xa - c->px0), *zr1 = zr0 + c->ts;
    _Alignas(RAST_CACHE_LINE) float zv0[SL_SPAN_MAX], zv1[SL_SPAN_MAX];
    _Alignas(RAST_CACHE_LINE) int32_t live0[SL_SPAN_MAX], live1[SL_SPAN_MAX]; /* covered and passed */
    int tested = 0;
#pragma omp simd reduction(+ : tested)
    for (int j = 0; j < count; j++) {
        const int64_t x = xa + j;
        const int32_t col = x >= lo && x <= hi;
        int32_t cov0 = col & row0, cov1 = col & row1;
        if (edges) {
            cov0 &= ((r00 + a0 * x) | (r01 + a1 * x) | (r02 + a2 * x)) >= 0;
            cov1 &= ((r10 + a0 * x) | (r11 + a1 * x) | (r12 + a2 * x)) >= 0;
        }
        const float fx = (float)(xa + j) - ox;
        const float za = clampf(z0 + z1 * fx + z2fy0, 0.0f, 1.0f), zb = clampf(z0 + z1 * fx + z2fy1, 0.0f, 1.0f);
        int32_t pass0 = cov0, pass1 = cov1;
        if (depth) {
            const float olda = zr0[j], oldb = zr1[j];
            pass0 = cov0 & (za < olda);
            pass1 = cov1 & (zb < oldb);
            if (!late) {
                zr0[j] = pass0 ? za : olda;
                zr1[j] = pass1 ? zb : oldb;
            }
        }
        zv0[j] = za;
        zv1[j] = zb;
        live0[j] = pass0;
        live1[j] = pass1;
        tested += cov0 + cov1;
    }
    c->tested += tested;
    rast_quads *b = c->batch;
    for (int j = 0; xa + j <= hi; j += 2) {
        const unsigned live = (unsigned)live0[j] | (unsigned)live0[j + 1] << 1 | (unsigned)live1[j] << 2 |
                              (unsigned)live1[j + 1] << 3;
        if (!live)
            continue;
        const int qx = xa + j, k = b->n++;
        const float fx0 = (float)qx - ox, fx1 = (float)(qx + 1) - ox;
        b->qx[k] = qx;
        b->qy[k] = qy;
        b->fx[4 * k] = fx0;
        b->fx[4 * k + 1] = fx1;
        b->fx[4 * k + 2] = fx0;
        b->fx[4 * k + 3] = fx1;
        b->fy[4 * k] = fy0;
        b->fy[4 * k + 1] = fy0;
        b->fy[4 * k + 2] = fy1;
        b->fy[4 * k + 3] = fy1;
        b->z[4 * k] = zv0[j];
        b->z[4 * k + 1] = zv0[j + 1];
        b->z[4 * k + 2] = zv1[j];
        b->z[4 * k + 3] = zv1[j + 1];
        for (int l = 0; l < 4; l++)
            b->helper[4 * k + l] = !(live >> l & 1);
        if (b->n == SL_QUADS_MAX)
            quads_flush(c, depth);
    }
}

/* The multi-quad path's draw_tri_quads: the same quads (a triangle's quads cover disjoint pixels
 * and each lane's values depend on its quad alone, so the batches' make-up changes no bit),
 * gathered a row of quads at a time (quad_row_gather) over each block row's run of blocks that
 * are not outside, as draw_tri_spans walks them; edge tests only where a block of the run is
 * partial. */
static inline __attribute__((always_inline)) void draw_tri_multi(tri_ctx *c, bool full, int x0, int y0, int x1, int y1,
                                                                 const bool depth)
{
    if (full) {
        for (int qy = y0 & ~1; qy <= y1; qy += 2)
            quad_row_gather(c, qy, x0 & ~1, x0, x1, y0, y1, false, depth);
        quads_flush(c, depth);
        return;
    }
    for (int by = y0 & ~(RAST_BLOCK - 1); by <= y1; by += RAST_BLOCK) {
        block_run run;
        if (!block_row_run(c, by, x0, y0, x1, y1, &run))
            continue;
        for (int qy = run.y0 & ~1; qy <= run.y1; qy += 2) {
            if (run.inside) /* a constant at each call: the loop without its edge tests */
                quad_row_gather(c, qy, run.lo & ~1, run.lo, run.hi, run.y0, run.y1, false, depth);
            else
                quad_row_gather(c, qy, run.lo & ~1, run.lo, run.hi, run.y0, run.y1, true, depth);
        }
    }
    quads_flush(c, depth);
}

/* The quads of the triangle over [x0,x1] x [y0,y1], block by block as draw_tri: tiles
 * and blocks have even sizes and origins, so a quad never straddles two, and lanes
 * outside the rectangle are outside the triangle's bounds (uncovered). */
static inline __attribute__((always_inline)) void draw_tri_quads(tri_ctx *c, bool full, int x0, int y0, int x1,
                                                                 int y1, const bool depth)
{
    const rast_tri *t = c->t;
    int bx0 = x0 & ~(RAST_BLOCK - 1), by0 = y0 & ~(RAST_BLOCK - 1);
    int bstep = full ? 1 << 30 : RAST_BLOCK; /* full: the whole rectangle is one inside block */
    for (int by = full ? y0 : by0; by <= y1; by += bstep) {
        int ry0 = by > y0 ? by : y0, ry1 = full || by + RAST_BLOCK - 1 > y1 ? y1 : by + RAST_BLOCK - 1;
        for (int bx = full ? x0 : bx0; bx <= x1; bx += bstep) {
            int rx0 = bx > x0 ? bx : x0, rx1 = full || bx + RAST_BLOCK - 1 > x1 ? x1 : bx + RAST_BLOCK - 1;
            int cls = full ? BLOCK_INSIDE : classify(t, rx0, ry0, rx1, ry1);
            if (cls == BLOCK_OUTSIDE)
                continue;
            c->blocks_full += !full && cls == BLOCK_INSIDE;
            for (int qy = ry0 & ~1; qy <= ry1; qy += 2)
                for (int qx = rx0 & ~1; qx <= rx1; qx += 2) {
                    unsigned cov = 0;
                    for (int l = 0; l < 4; l++) {
                        int x = qx + (l & 1), y = qy + (l >> 1);
                        if (x < rx0 || x > rx1 || y < ry0 || y > ry1)
                            continue;
                        bool in = cls == BLOCK_INSIDE;
                        if (!in) {
                            int64_t e0 = t->ec[0] + t->ex[0] * x + t->ey[0] * y;
                            int64_t e1 = t->ec[1] + t->ex[1] * x + t->ey[1] * y;
                            int64_t e2 = t->ec[2] + t->ex[2] * x + t->ey[2] * y;
                            in = (e0 | e1 | e2) >= 0;
                        }
                        cov |= (unsigned)in << l;
                    }
                    if (cov)
                        quad(c, qx, qy, cov, depth);
                }
        }
    }
}

static void draw_tri_quads_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri_quads(c, full, x0, y0, x1, y1, true);
}

static void draw_tri_quads_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri_quads(c, full, x0, y0, x1, y1, false);
}

static void draw_tri_multi_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri_multi(c, full, x0, y0, x1, y1, true);
}

static void draw_tri_multi_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri_multi(c, full, x0, y0, x1, y1, false);
}

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

    tri_ctx c = {.d = d, .zbuf = task->depth, .px0 = px0, .py0 = py0, .ts = ts, .texels = texels, .span = task->span,
                 .quad = task->quad, .scratch = task->scratch};
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
                __builtin_prefetch(ch->vary + next->vary);
            }
            c.t = t;
            c.call = &d->calls[t->call];
            const float *planes = ch->vary + t->vary;
            for (int k = 0, n = c.call->nvary; k < n; k++) {
                c.p0[k] = planes[3 * k];
                c.pdx[k] = planes[3 * k + 1];
                c.pdy[k] = planes[3 * k + 2];
            }
            int x0 = t->xmin > px0 ? t->xmin : px0, x1 = t->xmax < px1 ? t->xmax : px1;
            int y0 = t->ymin > py0 ? t->ymin : py0, y1 = t->ymax < py1 ? t->ymax : py1;
            bool full = (item & RAST_BIN_FULL) != 0;
            /* one test per triangle: programs without the flags take the paths they always took */
            const sl_program *prog = c.call->program;
            if (prog->derivatives || prog->discards) {
                bool multi = prog->derivatives && prog->fragment_quads && c.batch;
                if (multi && depth)
                    draw_tri_multi_depth(&c, full, x0, y0, x1, y1);
                else if (multi)
                    draw_tri_multi_nodepth(&c, full, x0, y0, x1, y1);
                else if (prog->derivatives && depth)
                    draw_tri_quads_depth(&c, full, x0, y0, x1, y1);
                else if (prog->derivatives)
                    draw_tri_quads_nodepth(&c, full, x0, y0, x1, y1);
                else if (depth)
                    draw_tri_late_depth(&c, full, x0, y0, x1, y1);
                else
                    draw_tri_late_nodepth(&c, full, x0, y0, x1, y1);
            } else if (spans && depth)
                draw_tri_spans_depth(&c, full, x0, y0, x1, y1);
            else if (spans)
                draw_tri_spans_nodepth(&c, full, x0, y0, x1, y1);
            else if (depth)
                draw_tri_depth(&c, full, x0, y0, x1, y1);
            else
                draw_tri_nodepth(&c, full, x0, y0, x1, y1);
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
