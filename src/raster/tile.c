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
 * per-pixel tests), or partial (per-pixel edge tests, stepping by one add per edge).
 *
 * Depth: while a tile is drawn its depth values live in the thread's tile plane
 * (contiguous, hot in cache), loaded from and stored back to the target's texels. */
#include "rast_internal.h"

#include <string.h>

typedef struct {
    const rast_draw *d;
    const rast_tri *t;
    const float *planes; /* varying planes */
    float *zbuf;         /* tile-local depth */
    int px0, py0, ts;    /* tile origin and size */
    char *texels;
    long long tested, shaded, blocks_full;
} tri_ctx;

/* One covered pixel: depth (choose per draw: `depth` is a constant after inlining),
 * perspective-correct varyings (interpolate v/w and 1/w linearly, divide), shade. */
static inline __attribute__((always_inline)) void fragment(tri_ctx *c, int x, int y, const bool depth)
{
    const rast_tri *t = c->t;
    float fx = (float)x - t->ox, fy = (float)y - t->oy;
    float z = clampf(t->z[0] + t->z[1] * fx + t->z[2] * fy, 0.0f, 1.0f);
    c->tested++;
    if (depth) {
        float *zp = &c->zbuf[(y - c->py0) * c->ts + (x - c->px0)];
        if (!(z < *zp))
            return;
        *zp = z;
    }
    float iw = clampf(t->iw[0] + t->iw[1] * fx + t->iw[2] * fy, t->iw_lo, t->iw_hi);
    float w = 1.0f / iw;
    float vary[SL_MAX_VARYINGS];
    const float *p = c->planes;
    int n = c->d->nvary;
    for (int i = 0; i < n; i++)
        vary[i] = (p[3 * i] + p[3 * i + 1] * fx + p[3 * i + 2] * fy) * w;
    sl_fragment_in in = {
        .varyings = vary,
        .frag_coord = vec4((float)x + 0.5f, (float)y + 0.5f, z, iw),
        .front_facing = t->front,
        .x = x,
        .y = y,
    };
    const sl_target *tg = c->d->target;
    void *texel = c->texels + ((size_t)y * (size_t)tg->width + (size_t)x) * tg->texel_size;
    c->d->program->fragment(c->d->fs_uniforms, &in, texel);
    c->shaded++;
}

static inline __attribute__((always_inline)) void fill_rect(tri_ctx *c, int x0, int y0, int x1, int y1,
                                                            const bool depth)
{
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            fragment(c, x, y, depth);
}

/* Draw triangle t over the rectangle [x0,x1] x [y0,y1] (its bounds inside the tile). */
static inline __attribute__((always_inline)) void draw_tri(tri_ctx *c, bool full, int x0, int y0, int x1, int y1,
                                                           const bool depth)
{
    const rast_tri *t = c->t;
    if (full) {
        fill_rect(c, x0, y0, x1, y1, depth);
        return;
    }
    int bx0 = x0 & ~(RAST_BLOCK - 1), by0 = y0 & ~(RAST_BLOCK - 1);
    for (int by = by0; by <= y1; by += RAST_BLOCK) {
        int ry0 = by > y0 ? by : y0, ry1 = by + RAST_BLOCK - 1 < y1 ? by + RAST_BLOCK - 1 : y1;
        for (int bx = bx0; bx <= x1; bx += RAST_BLOCK) {
            int rx0 = bx > x0 ? bx : x0, rx1 = bx + RAST_BLOCK - 1 < x1 ? bx + RAST_BLOCK - 1 : x1;
            bool outside = false, inside = true;
            for (int k = 0; k < 3; k++) {
                int64_t emax = t->ec[k] + t->ex[k] * (t->ex[k] > 0 ? rx1 : rx0) + t->ey[k] * (t->ey[k] > 0 ? ry1 : ry0);
                int64_t emin = t->ec[k] + t->ex[k] * (t->ex[k] > 0 ? rx0 : rx1) + t->ey[k] * (t->ey[k] > 0 ? ry0 : ry1);
                outside |= emax < 0;
                inside &= emin >= 0;
            }
            if (outside)
                continue;
            if (inside) {
                c->blocks_full++;
                fill_rect(c, rx0, ry0, rx1, ry1, depth);
                continue;
            }
            for (int y = ry0; y <= ry1; y++) {
                int64_t e0 = t->ec[0] + t->ex[0] * rx0 + t->ey[0] * y;
                int64_t e1 = t->ec[1] + t->ex[1] * rx0 + t->ey[1] * y;
                int64_t e2 = t->ec[2] + t->ex[2] * rx0 + t->ey[2] * y;
                for (int x = rx0; x <= rx1; x++) {
                    if ((e0 | e1 | e2) >= 0)
                        fragment(c, x, y, depth);
                    e0 += t->ex[0];
                    e1 += t->ex[1];
                    e2 += t->ex[2];
                }
            }
        }
    }
}

static void draw_tri_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri(c, full, x0, y0, x1, y1, true);
}

static void draw_tri_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri(c, full, x0, y0, x1, y1, false);
}

void rast_tile(const rast_draw *d, const rast_chunk *chunks, int chunk_count, int tile, rast_task *task)
{
    bool any = false;
    for (int ci = 0; ci < chunk_count && !any; ci++)
        any = chunks[ci].bins[tile].count > 0;
    if (!any)
        return;

    const sl_target *tg = d->target;
    int ts = d->tile_size;
    int px0 = (tile % d->tiles_x) * ts, py0 = (tile / d->tiles_x) * ts;
    int px1 = px0 + ts - 1 < tg->width - 1 ? px0 + ts - 1 : tg->width - 1;
    int py1 = py0 + ts - 1 < tg->height - 1 ? py0 + ts - 1 : tg->height - 1;
    bool depth = tg->depth_offset >= 0;
    char *texels = tg->texels;
    if (depth)
        for (int y = py0; y <= py1; y++)
            for (int x = px0; x <= px1; x++)
                memcpy(&task->depth[(y - py0) * ts + (x - px0)],
                       texels + ((size_t)y * (size_t)tg->width + (size_t)x) * tg->texel_size + tg->depth_offset,
                       sizeof(float));

    tri_ctx c = {.d = d, .zbuf = task->depth, .px0 = px0, .py0 = py0, .ts = ts, .texels = texels};
    for (int ci = 0; ci < chunk_count; ci++) {
        const rast_chunk *ch = &chunks[ci];
        const rast_bin *bin = &ch->bins[tile];
        for (int i = 0; i < bin->count; i++) {
            uint32_t item = bin->items[i];
            const rast_tri *t = &ch->tris[item & ~RAST_BIN_FULL];
            c.t = t;
            c.planes = ch->vary + t->vary;
            int x0 = t->xmin > px0 ? t->xmin : px0, x1 = t->xmax < px1 ? t->xmax : px1;
            int y0 = t->ymin > py0 ? t->ymin : py0, y1 = t->ymax < py1 ? t->ymax : py1;
            if (depth)
                draw_tri_depth(&c, (item & RAST_BIN_FULL) != 0, x0, y0, x1, y1);
            else
                draw_tri_nodepth(&c, (item & RAST_BIN_FULL) != 0, x0, y0, x1, y1);
        }
    }
    task->stats.fragments_tested += c.tested;
    task->stats.fragments_shaded += c.shaded;
    task->stats.blocks_full += c.blocks_full;

    if (depth)
        for (int y = py0; y <= py1; y++)
            for (int x = px0; x <= px1; x++)
                memcpy(texels + ((size_t)y * (size_t)tg->width + (size_t)x) * tg->texel_size + tg->depth_offset,
                       &task->depth[(y - py0) * ts + (x - px0)], sizeof(float));
}
