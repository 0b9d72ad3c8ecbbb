/* tile_span.c - the span path (the default): coverage and depth a row of blocks at a time in
 * vector loops, then one span call a row; small triangles as one set (small_tri_spans)
 * (tile_internal.h maps the tile stage's files). */
#include "tile_internal.h"

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
    if (c->facets)
        for (int j = 0; j < m; j++)
            write_facet(c, s->x[j], y);
    c->shaded += m;
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
        if (c->facets)
            for (int j = start; j < end; j++)
                write_facet(c, s->x[j], y);
        start = end;
    }
    c->shaded += m;
}

/* The span path: small triangles of a program with a span form as one set
 * (small_tri_spans), of one without pixel by pixel (draw_tri), the others a span a row.
 * All give the same bits, so the choice is free. */
void sl_rast_tri_spans_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    if (!small_tri(x0, y0, x1, y1))
        draw_tri_spans(c, full, x0, y0, x1, y1, true);
    else if (c->call->program->fragment_span)
        small_tri_spans(c, full, x0, y0, x1, y1, true);
    else
        draw_tri(c, full, x0, y0, x1, y1, true, false);
}

void sl_rast_tri_spans_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    if (!small_tri(x0, y0, x1, y1))
        draw_tri_spans(c, full, x0, y0, x1, y1, false);
    else if (c->call->program->fragment_span)
        small_tri_spans(c, full, x0, y0, x1, y1, false);
    else
        draw_tri(c, full, x0, y0, x1, y1, false, false);
}
