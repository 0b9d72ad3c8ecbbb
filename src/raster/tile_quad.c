/* tile_quad.c - programs that take derivatives: aligned 2x2 quads over the same blocks, one quad
 * at a time, helpers for uncovered and occluded lanes (the lanes run in rounds, quad.c, or
 * through the program's quad form)
 * (tile_internal.h maps the tile stage's files). */
#include "tile_internal.h"

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
        write_facet(c, qx + (l & 1), qy + (l >> 1));
        if (depth && late) {
            int x = qx + (l & 1), y = qy + (l >> 1);
            c->zbuf[(y - c->py0) * c->ts + (x - c->px0)] = z[l];
            c->late_z++;
        }
    }
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

void sl_rast_tri_quads_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri_quads(c, full, x0, y0, x1, y1, true);
}

void sl_rast_tri_quads_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri_quads(c, full, x0, y0, x1, y1, false);
}
