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

/* The capacity an array of capacity cap grows to for need elements: doubled from 64. */
static size_t grown_cap(size_t cap, size_t need)
{
    size_t ncap = cap ? cap : 64;
    while (ncap < need)
        ncap *= 2;
    return ncap;
}

static bool grow(void **p, size_t elem, size_t need, size_t *cap)
{
    if (need <= *cap)
        return true;
    size_t ncap = grown_cap(*cap, need);
    void *q = realloc(*p, ncap * elem);
    if (!q)
        return false;
    *p = q;
    *cap = ncap;
    return true;
}

/* grow() for the set-up triangles: the array starts on a cache line, so that each 128-byte
 * triangle is two lines, not three (realloc keeps no alignment, so this copies). */
static bool grow_tris(rast_chunk *ch, size_t need)
{
    if (need <= (size_t)ch->tri_cap)
        return true;
    size_t ncap = grown_cap((size_t)ch->tri_cap, need);
    rast_tri *q = aligned_alloc(RAST_CACHE_LINE, ncap * sizeof *q); /* a multiple of the alignment */
    if (!q)
        return false;
    if (ch->tri_count > 0)
        memcpy(q, ch->tris, (size_t)ch->tri_count * sizeof *q);
    free(ch->tris);
    ch->tris = q;
    ch->tri_cap = (int)ncap;
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

/* Where a triangle's attribute planes are built: its vertices' exact window positions
 * relative to vertex 0, and the anchor (the centre of the plane origin's pixel) relative to
 * vertex 0. All in double: a clipped triangle's vertices lie up to the guard band away
 * (16000 pixels), and a vertex cut at the near plane has 1/w = 1/near while the pixels on the
 * horizon have 1/w = 1/far; a float plane anchored there loses the far pixels' value to
 * cancellation (measured on a floor crossing the near plane: world positions off by 4e-3 of
 * their distance; in double, 1e-6 as llvmpipe's; docs/gl.md "Clipped triangles"). */
typedef struct {
    double x1, y1, x2, y2, inv_det; /* vertices 1 and 2, 1 / twice the area */
    double ax, ay;                  /* the anchor */
} plane_frame;

/* Plane through values f0, f1, f2 at the frame's vertices: its value at the anchor and its
 * gradient per pixel, rounded to float once. */
static void plane(const plane_frame *fr, double f0, double f1, double f2, float out[3])
{
    double d1 = f1 - f0, d2 = f2 - f0;
    double gx = (d1 * fr->y2 - d2 * fr->y1) * fr->inv_det;
    double gy = (d2 * fr->x1 - d1 * fr->x2) * fr->inv_det;
    out[0] = (float)(f0 + gx * fr->ax + gy * fr->ay);
    out[1] = (float)gx;
    out[2] = (float)gy;
}

/* The unit normal of the plane through three clip positions, in the space that view_proj
 * carries to clip space, on the viewer's side (sl_target.facets); 0 when they span no plane. The
 * plane through homogeneous points a, b, c is the vector pi with pi . a = pi . b = pi . c = 0 (the
 * cofactors of [a; b; c]); a point X of that space lies on view_proj's transpose times pi. The
 * viewer is the clip-space point at infinity (0, 0, -1, 0) for a perspective projection (the eye)
 * and an orthographic one (the direction it looks from) alike, so the viewer's side is pi.z < 0.
 * In double: the cofactors cancel. */
static void facet_normal(const sl_mat4 *view_proj, vec4 a, vec4 b, vec4 c, float out[3])
{
    const double A[4] = {(double)a.x, (double)a.y, (double)a.z, (double)a.w};
    const double B[4] = {(double)b.x, (double)b.y, (double)b.z, (double)b.w};
    const double C[4] = {(double)c.x, (double)c.y, (double)c.z, (double)c.w};
    double pi[4];
    for (int k = 0; k < 4; k++) {
        /* the 3x3 minor without column k, signed as the cofactor of row 0 of [X; a; b; c] */
        int i = k == 0 ? 1 : 0, j = k <= 1 ? 2 : 1, l = k <= 2 ? 3 : 2;
        double minor = A[i] * (B[j] * C[l] - B[l] * C[j]) - A[j] * (B[i] * C[l] - B[l] * C[i]) +
                       A[l] * (B[i] * C[j] - B[j] * C[i]);
        pi[k] = (k & 1) ? -minor : minor;
    }
    double sign = pi[2] > 0.0 ? -1.0 : 1.0;
    double n[3];
    for (int j = 0; j < 3; j++) {
        const sl_vec4 col = view_proj->c[j];
        n[j] = sign * (pi[0] * (double)col.x + pi[1] * (double)col.y + pi[2] * (double)col.z + pi[3] * (double)col.w);
    }
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    bool plane = len > 0.0 && isfinite(len);
    for (int j = 0; j < 3; j++)
        out[j] = plane ? (float)(n[j] / len) : 0.0f;
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

    if (ch->tri_count == ch->tri_cap && !grow_tris(ch, (size_t)ch->tri_cap + 1)) {
        ch->oom = true;
        return;
    }
    const bool facets = d->target->facets != NULL;
    size_t nv = (size_t)call->nvary * 3 + (facets ? 3 : 0);
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

    /* Attribute planes on the exact positions (rast_window_exact), anchored at the centre of
     * the first pixel of the bounds. A sliver whose exact area is not close to its snapped one
     * (the snap moved a vertex by a share of its size) takes the snapped positions, whose area
     * is exact and non-zero: its gradients stay bounded. */
    const rast_exact e[3] = {v0.win, v1.win, v2.win};
    const double sub = 1.0 / (double)RAST_SUBPIXEL_ONE;
    double snapped_area = (double)area * sub * sub;
    double px[3], py[3];
    for (int k = 0; k < 3; k++) {
        px[k] = e[k].x;
        py[k] = e[k].y;
    }
    double exact_area = (px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]);
    if (!(exact_area > 0.5 * snapped_area && exact_area < 2.0 * snapped_area)) {
        for (int k = 0; k < 3; k++) {
            px[k] = (double)v[k]->X * sub;
            py[k] = (double)v[k]->Y * sub;
        }
        exact_area = snapped_area;
    }
    plane_frame fr = {
        .x1 = px[1] - px[0], .y1 = py[1] - py[0], .x2 = px[2] - px[0], .y2 = py[2] - py[0],
        .inv_det = 1.0 / exact_area,
        .ax = (double)xlo + 0.5 - px[0], .ay = (double)ylo + 0.5 - py[0],
    };
    plane(&fr, e[0].z, e[1].z, e[2].z, t->z);
    plane(&fr, e[0].iw, e[1].iw, e[2].iw, t->iw);
    float iw0 = (float)e[0].iw, iw1 = (float)e[1].iw, iw2 = (float)e[2].iw;
    t->iw_lo = minf(iw0, minf(iw1, iw2));
    t->iw_hi = maxf(iw0, maxf(iw1, iw2));
    t->vary = (uint32_t)ch->vary_count;
    /* A program without varyings (depth only) has no varying store: ch->vary is NULL, and even
     * NULL + 0 is undefined, so the address is formed only inside the loop. */
    for (int i = 0; i < call->nvary; i++)
        plane(&fr, (double)v0.v[i] * e[0].iw, (double)v1.v[i] * e[1].iw, (double)v2.v[i] * e[2].iw,
              ch->vary + ch->vary_count + 3 * i);
    if (facets)
        facet_normal(&d->target->facet_view_proj, v0.clip, v1.clip, v2.clip,
                     ch->vary + ch->vary_count + 3 * (size_t)call->nvary);

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

void sl_rast_setup_range(const rast_draw *d, rast_chunk *chunk, long long first, long long last)
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
            rast_wvert w0 = {p0->X, p0->Y, p0->win, vvary + (size_t)i0 * (size_t)nvary, p0->clip};
            rast_wvert w1 = {p1->X, p1->Y, p1->win, vvary + (size_t)i1 * (size_t)nvary, p1->clip};
            rast_wvert w2 = {p2->X, p2->Y, p2->win, vvary + (size_t)i2 * (size_t)nvary, p2->clip};
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
        int n = sl_rast_clip_triangle(in, all, nvary, d->gx, d->gy, poly);
        if (n < 3) {
            ch->stats.triangles_dropped++;
            continue;
        }
        rast_wvert w[RAST_CLIP_MAX];
        bool finite = true;
        for (int k = 0; k < n; k++) {
            vec4 c = poly[k].clip;
            rast_to_window(d->target, c, &w[k].X, &w[k].Y);
            w[k].win = rast_window_exact(d->target, c);
            w[k].v = poly[k].v;
            w[k].clip = c;
            finite &= c.w > 0.0f && isfinite(1.0f / c.w) && isfinite(c.z / c.w);
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
