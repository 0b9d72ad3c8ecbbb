/* setup.c - triangle setup and binning: one slice of a batch, into one rast_chunk.
 *
 * Called by raster.c in parallel, one chunk per slice, so each thread writes only
 * its own chunk. A slice may span several draws of the list. For every index
 * triple: reject or clip (clip.c), snap to 1/256 pixel, compute the signed area
 * (int64, exact), drop degenerate triangles, cull or flip clockwise ones, build the
 * three edge functions with the top-left bias,
 * the attribute planes, and append the triangle to the bins of every tile it
 * touches (tiles it covers entirely are flagged, the tile stage fills them blind).
 *
 * Fill rule: the top-left rule as D3D states it for a y-down raster, applied to the
 * target's rows in memory order (row 0 first), which is what Mesa's llvmpipe does for
 * a GL framebuffer object: in GL window coordinates (y up) the inclusive horizontal
 * edge is the one with the interior ABOVE it. For a counter-clockwise triangle the
 * interior lies to the left of each directed edge a -> b, so a pixel centre exactly on
 * an edge belongs to the triangle when the edge is a left edge (going down: dy < 0; the
 * interior is to its right) or that horizontal edge (going right: dy == 0, dx > 0).
 * Measured against llvmpipe: identical coverage on grid-aligned edges (docs/gl.md).
 * The other edges get a bias of -1 in the integer edge value, turning E >= 0 into E > 0. */
#include "rast_internal.h"

#include <stdlib.h>
#include <string.h>

static int64_t floor_div256(int64_t n) { return n >= 0 ? n / 256 : -((-n + 255) / 256); }

static bool grow(void **p, size_t elem, size_t need, size_t *cap)
{
    if (need <= *cap)
        return true;
    size_t ncap = *cap ? *cap : 64;
    while (ncap < need)
        ncap *= 2;
    void *q = realloc(*p, ncap * elem);
    if (!q)
        return false;
    *p = q;
    *cap = ncap;
    return true;
}

static bool bin_push(rast_chunk *ch, int tile, uint32_t item)
{
    rast_bin *b = &ch->bins[tile];
    if (b->count == b->cap) {
        size_t cap = (size_t)b->cap;
        if (!grow((void **)&b->items, sizeof *b->items, cap + 1, &cap)) {
            ch->oom = true;
            return false;
        }
        b->cap = (int)cap;
    }
    b->items[b->count++] = item;
    return true;
}

/* Plane through three values at vertex-0-relative positions (x1,y1), (x2,y2) in pixels. */
static void plane(float f0, float f1, float f2, float x1, float y1, float x2, float y2, float inv_det, float out[3])
{
    float d1 = f1 - f0, d2 = f2 - f0;
    out[0] = f0;
    out[1] = (d1 * y2 - d2 * y1) * inv_det;
    out[2] = (d2 * x1 - d1 * x2) * inv_det;
}

/* Set up one triangle of draw `call` in window coordinates and bin it. */
static void setup_triangle(const rast_draw *d, const rast_call *call, uint16_t call_index, rast_chunk *ch,
                           rast_wvert v0, rast_wvert v1, rast_wvert v2)
{
    int64_t area = (int64_t)(v1.X - v0.X) * (v2.Y - v0.Y) - (int64_t)(v2.X - v0.X) * (v1.Y - v0.Y);
    if (area == 0) {
        ch->stats.triangles_dropped++;
        return;
    }
    bool front = area > 0;
    if (!front) {
        if (call->cull == SL_CULL_BACK) {
            ch->stats.triangles_culled++;
            return;
        }
        rast_wvert t = v1;
        v1 = v2;
        v2 = t;
        area = -area;
    }
    const rast_wvert *v[3] = {&v0, &v1, &v2};

    /* Pixels whose centre (256x + 128) can lie inside the bounds, clipped to the target. */
    int32_t minX = v0.X, maxX = v0.X, minY = v0.Y, maxY = v0.Y;
    for (int k = 1; k < 3; k++) {
        minX = v[k]->X < minX ? v[k]->X : minX;
        maxX = v[k]->X > maxX ? v[k]->X : maxX;
        minY = v[k]->Y < minY ? v[k]->Y : minY;
        maxY = v[k]->Y > maxY ? v[k]->Y : maxY;
    }
    int64_t xlo = floor_div256((int64_t)minX - 128 + 255), xhi = floor_div256((int64_t)maxX - 128);
    int64_t ylo = floor_div256((int64_t)minY - 128 + 255), yhi = floor_div256((int64_t)maxY - 128);
    if (xlo < 0) xlo = 0;
    if (ylo < 0) ylo = 0;
    if (xhi > d->target->width - 1) xhi = d->target->width - 1;
    if (yhi > d->target->height - 1) yhi = d->target->height - 1;
    if (xlo > xhi || ylo > yhi) {
        ch->stats.triangles_dropped++;
        return;
    }

    if (ch->tri_count == ch->tri_cap) {
        size_t cap = (size_t)ch->tri_cap;
        if (!grow((void **)&ch->tris, sizeof *ch->tris, cap + 1, &cap)) {
            ch->oom = true;
            return;
        }
        ch->tri_cap = (int)cap;
    }
    size_t nv = (size_t)call->nvary * 3;
    if (!grow((void **)&ch->vary, sizeof *ch->vary, ch->vary_count + nv, &ch->vary_cap)) {
        ch->oom = true;
        return;
    }
    rast_tri *t = &ch->tris[ch->tri_count];
    t->xmin = (int32_t)xlo;
    t->xmax = (int32_t)xhi;
    t->ymin = (int32_t)ylo;
    t->ymax = (int32_t)yhi;
    t->front = front;
    t->call = call_index;

    /* Edge k runs from vertex k+1 to vertex k+2 and is positive towards vertex k. */
    for (int k = 0; k < 3; k++) {
        const rast_wvert *a = v[(k + 1) % 3], *b = v[(k + 2) % 3];
        int64_t dx = (int64_t)b->X - a->X, dy = (int64_t)b->Y - a->Y;
        bool top_left = dy < 0 || (dy == 0 && dx > 0);
        int64_t ea = -dy, eb = dx, ec = dy * a->X - dx * a->Y - (top_left ? 0 : 1);
        /* at the centre of pixel (x, y): X = 256 x + 128, Y = 256 y + 128 */
        t->ex[k] = ea * RAST_SUBPIXEL_ONE;
        t->ey[k] = eb * RAST_SUBPIXEL_ONE;
        t->ec[k] = ec + (ea + eb) * (RAST_SUBPIXEL_ONE / 2);
    }

    const float sub = 1.0f / (float)RAST_SUBPIXEL_ONE;
    float x1 = (float)(v1.X - v0.X) * sub, y1 = (float)(v1.Y - v0.Y) * sub;
    float x2 = (float)(v2.X - v0.X) * sub, y2 = (float)(v2.Y - v0.Y) * sub;
    float inv_det = (float)(RAST_SUBPIXEL_ONE * RAST_SUBPIXEL_ONE) / (float)area;
    t->ox = (float)v0.X * sub - 0.5f;
    t->oy = (float)v0.Y * sub - 0.5f;
    plane(v0.z, v1.z, v2.z, x1, y1, x2, y2, inv_det, t->z);
    plane(v0.iw, v1.iw, v2.iw, x1, y1, x2, y2, inv_det, t->iw);
    t->iw_lo = minf(v0.iw, minf(v1.iw, v2.iw));
    t->iw_hi = maxf(v0.iw, maxf(v1.iw, v2.iw));
    t->vary = (uint32_t)ch->vary_count;
    float *pv = ch->vary + ch->vary_count;
    for (int i = 0; i < call->nvary; i++)
        plane(v0.v[i] * v0.iw, v1.v[i] * v1.iw, v2.v[i] * v2.iw, x1, y1, x2, y2, inv_det, pv + 3 * i);

    /* Bin: every tile the bounds touch, unless an edge excludes the whole tile. */
    uint32_t index = (uint32_t)ch->tri_count;
    int sh = d->tile_shift, ts = d->tile_size;
    int tx0 = (int)xlo >> sh, tx1 = (int)xhi >> sh, ty0 = (int)ylo >> sh, ty1 = (int)yhi >> sh;
    int binned = 0;
    for (int ty = ty0; ty <= ty1; ty++) {
        for (int tx = tx0; tx <= tx1; tx++) {
            int px0 = tx * ts, py0 = ty * ts;
            int px1 = px0 + ts - 1 < d->target->width - 1 ? px0 + ts - 1 : d->target->width - 1;
            int py1 = py0 + ts - 1 < d->target->height - 1 ? py0 + ts - 1 : d->target->height - 1;
            bool outside = false, full = true;
            for (int k = 0; k < 3; k++) {
                int64_t emax = t->ec[k] + t->ex[k] * (t->ex[k] > 0 ? px1 : px0) + t->ey[k] * (t->ey[k] > 0 ? py1 : py0);
                int64_t emin = t->ec[k] + t->ex[k] * (t->ex[k] > 0 ? px0 : px1) + t->ey[k] * (t->ey[k] > 0 ? py0 : py1);
                outside |= emax < 0;
                full &= emin >= 0;
            }
            if (outside)
                continue;
            if (!bin_push(ch, ty * d->tiles_x + tx, index | (full ? RAST_BIN_FULL : 0u)))
                return;
            binned++;
            ch->stats.tiles_full += full;
        }
    }
    if (!binned) {
        ch->stats.triangles_dropped++;
        return;
    }
    ch->tri_count++;
    ch->vary_count += nv;
    ch->stats.triangles_binned++;
    ch->stats.bin_entries += binned;
}

void rast_setup_range(const rast_draw *d, rast_chunk *chunk, long long first, long long last)
{
    /* Work on a copy (counters, counts) on this thread's stack; written back once. */
    rast_chunk local = *chunk, *ch = &local;
    int ci = 0;
    while (ci + 1 < d->call_count && d->calls[ci + 1].first_tri <= first)
        ci++;
    for (long long g = first; g < last && !ch->oom; g++) {
        while (g >= d->calls[ci].first_tri + d->calls[ci].mesh->triangle_count)
            ci++; /* draws without triangles are skipped here */
        const rast_call *call = &d->calls[ci];
        long long tri = g - call->first_tri;
        const uint32_t *idx = call->mesh->indices;
        const rast_vpos *vpos = call->vpos;
        const float *vvary = call->vvary;
        int nvary = call->nvary;
        uint32_t i0 = idx[3 * tri], i1 = idx[3 * tri + 1], i2 = idx[3 * tri + 2];
        const rast_vpos *p0 = &vpos[i0], *p1 = &vpos[i1], *p2 = &vpos[i2];
        ch->stats.triangles_in++;
        unsigned all = p0->outcode | p1->outcode | p2->outcode;
        if (all == 0) {
            rast_wvert w0 = {p0->X, p0->Y, p0->z, p0->iw, vvary + (size_t)i0 * (size_t)nvary};
            rast_wvert w1 = {p1->X, p1->Y, p1->z, p1->iw, vvary + (size_t)i1 * (size_t)nvary};
            rast_wvert w2 = {p2->X, p2->Y, p2->z, p2->iw, vvary + (size_t)i2 * (size_t)nvary};
            setup_triangle(d, call, (uint16_t)ci, ch, w0, w1, w2);
            continue;
        }
        /* A non-finite vertex, or every vertex outside the same plane: nothing to draw. */
        if ((all & RAST_BAD) || (p0->outcode & p1->outcode & p2->outcode)) {
            ch->stats.triangles_dropped++;
            continue;
        }
        ch->stats.triangles_clipped++;
        rast_cvert in[3];
        const uint32_t ids[3] = {i0, i1, i2};
        for (int k = 0; k < 3; k++) {
            in[k].clip = vpos[ids[k]].clip;
            if (nvary > 0)
                memcpy(in[k].v, vvary + (size_t)ids[k] * (size_t)nvary, (size_t)nvary * sizeof(float));
        }
        rast_cvert poly[RAST_CLIP_MAX];
        int n = rast_clip_triangle(in, all, nvary, d->gx, d->gy, poly);
        if (n < 3) {
            ch->stats.triangles_dropped++;
            continue;
        }
        rast_wvert w[RAST_CLIP_MAX];
        bool finite = true;
        for (int k = 0; k < n; k++) {
            rast_to_window(d->target, poly[k].clip, &w[k].X, &w[k].Y, &w[k].z, &w[k].iw);
            w[k].v = poly[k].v;
            finite &= poly[k].clip.w > 0.0f && isfinite(w[k].iw) && isfinite(w[k].z);
        }
        if (!finite) { /* rounding put a cut vertex at w <= 0: drop rather than divide by it */
            ch->stats.triangles_dropped++;
            continue;
        }
        for (int k = 1; k + 1 < n; k++)
            setup_triangle(d, call, (uint16_t)ci, ch, w[0], w[k], w[k + 1]);
    }
    *chunk = local;
}
