/* tile_internal.h - what the tile stage's files share: the triangle being drawn in a tile
 * (tri_ctx), the pixel-by-pixel primitives every path falls back on or reuses (a fragment's
 * depth and varyings, one fragment, a rectangle, block classification, draw_tri), a block row's
 * run of blocks, and the paths' entry points.
 *
 * tile.c draws a tile: the clear, then each binned triangle through one of the paths:
 *   tile_plain.c  the plain path and late (discarding) programs: pixel by pixel (draw_tri)
 *   tile_span.c   the span path: a row of blocks a span, small triangles as one set
 *   tile_quad.c   programs that take derivatives: 2x2 quads one at a time
 *   tile_quads.c  programs with a multi-quad form: up to 16 quads gathered a call
 * Each path comes in twins, with and without a depth plane: the helpers here are always
 * inlined with `depth` (and `late`, `edges`) constant, so each twin is its own loop. */
#ifndef SL_TILE_INTERNAL_H
#define SL_TILE_INTERNAL_H

#include "rast_internal.h"

#include <stdint.h>
#include <string.h>

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
    sl_vec3 *facets;     /* the target's facet normals, or NULL (sl_target.facets) */
    vec3 facet;          /* the current triangle's, when facets */
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

/* The current triangle's facet normal at pixel (x, y), where its fragment wrote the texel: each
 * path calls it beside the texel's write (sl_target.facets). */
static inline __attribute__((always_inline)) void write_facet(const tri_ctx *c, int x, int y)
{
    if (c->facets)
        c->facets[(size_t)y * (size_t)c->d->target->width + (size_t)x] = c->facet;
}

/* ---- pixel by pixel (the plain path, and every path's fallback) ---- */

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
        write_facet(c, x, y);
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
    write_facet(c, x, y);
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

/* ---- a block row's run (the span and multi-quad paths) ---- */

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

/* The paths' entry points: triangle c->t over [x0,x1] x [y0,y1] (its bounds inside the tile;
 * full: the bin item covers the tile), with and without the tile's depth plane. */
/* tile_plain.c */
void sl_rast_tri_plain_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1);
void sl_rast_tri_plain_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1);
/* tile_plain.c: programs that may discard, no derivatives */
void sl_rast_tri_late_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1);
void sl_rast_tri_late_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1);
/* tile_span.c */
void sl_rast_tri_spans_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1);
void sl_rast_tri_spans_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1);
/* tile_quad.c */
void sl_rast_tri_quads_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1);
void sl_rast_tri_quads_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1);
/* tile_quads.c */
void sl_rast_tri_multi_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1);
void sl_rast_tri_multi_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1);

#endif
