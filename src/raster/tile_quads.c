/* tile_quads.c - programs with a multi-quad form (sl_program.fragment_quads, span path): the
 * quads of a triangle gathered a row at a time, up to 16 shaded in one call
 * (tile_internal.h maps the tile stage's files). */
#include "tile_internal.h"

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
    if (fresh && !late && discarded == 0 && !c->facets) { /* every live lane wrote its texel in place */
        b->n = 0;
        return;
    }
    for (int j = 0; j < lanes; j++) {
        if (b->helper[j] || b->discarded[j])
            continue;
        if (b->texel[j] != b->target[j])
            memcpy(b->target[j], b->texel[j], tsz);
        write_facet(c, b->qx[j >> 2] + (j & 1), b->qy[j >> 2] + ((j >> 1) & 1));
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

void sl_rast_tri_multi_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri_multi(c, full, x0, y0, x1, y1, true);
}

void sl_rast_tri_multi_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri_multi(c, full, x0, y0, x1, y1, false);
}
