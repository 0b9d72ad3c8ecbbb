/* clip.c - homogeneous clipping of triangles in clip space (Sutherland-Hodgman).
 *
 * Called from setup.c for the few triangles whose vertices are not all inside:
 * near and far planes (so w <= 0 never reaches the divide), a w >= eps plane for
 * projections that are not perspective, and the guard-band planes that keep window
 * coordinates inside the fixed-point budget (rast_internal.h). Only the planes some
 * vertex violates are clipped against; everything else passes through untouched.
 *
 * Watertightness: an edge shared by two triangles is cut at the same point in both,
 * because the intersection is always interpolated from the edge's inside vertex
 * towards its outside vertex, whatever direction the polygon walks the edge.
 *
 * Precision: the cut is computed in double and rounded to float once. At the near plane w
 * is small (the camera's near distance) while the edge's ends have w of the scene's size,
 * so a float lerp cancels: w came out 1e-4 off relative, and with it the cut vertex's 1/w,
 * against the varyings lerped with the same t (docs/gl.md "Clipped triangles"). */
#include "rast_internal.h"

#include <string.h>

/* Signed distance to plane `p`, >= 0 inside. In double, where each product of two floats is
 * exact: the sign (the outcode) is the exact one, and the cut (lerp_vertex) does not cancel. */
static double plane_dist(unsigned p, vec4 c, float gx, float gy)
{
    double x = (double)c.x, y = (double)c.y, z = (double)c.z, w = (double)c.w;
    switch (p) {
    case RAST_PLANE_NEAR: return z + w;
    case RAST_PLANE_FAR: return w - z;
    case RAST_PLANE_W: return w - (double)RAST_W_EPSILON;
    case RAST_PLANE_LEFT: return x + (double)gx * w;
    case RAST_PLANE_RIGHT: return (double)gx * w - x;
    case RAST_PLANE_BOTTOM: return y + (double)gy * w;
    default: return (double)gy * w - y; /* RAST_PLANE_TOP */
    }
}

unsigned sl_rast_outcode(vec4 c, float gx, float gy)
{
    if (!isfinite(c.x) || !isfinite(c.y) || !isfinite(c.z) || !isfinite(c.w))
        return RAST_BAD;
    unsigned code = 0;
    for (int i = 0; i < RAST_PLANE_COUNT; i++) {
        unsigned p = 1u << i;
        if (plane_dist(p, c, gx, gy) < 0.0)
            code |= p;
    }
    return code;
}

static float lerp_d(float a, float b, double t) { return (float)((double)a + ((double)b - (double)a) * t); }

/* out = a + t (b - a), a being the inside vertex; rounded to float once. */
static void lerp_vertex(const rast_cvert *a, const rast_cvert *b, double t, int nvary, rast_cvert *out)
{
    vec4 ca = a->clip, cb = b->clip;
    out->clip = vec4(lerp_d(ca.x, cb.x, t), lerp_d(ca.y, cb.y, t), lerp_d(ca.z, cb.z, t), lerp_d(ca.w, cb.w, t));
    for (int i = 0; i < nvary; i++)
        out->v[i] = lerp_d(a->v[i], b->v[i], t);
}

int sl_rast_clip_triangle(const rast_cvert in[3], unsigned planes, int nvary, float gx, float gy,
                       rast_cvert out[RAST_CLIP_MAX])
{
    rast_cvert buf[2][RAST_CLIP_MAX];
    int n = 3;
    memcpy(buf[0], in, 3 * sizeof in[0]);
    int cur = 0;
    for (int i = 0; i < RAST_PLANE_COUNT && n > 0; i++) {
        unsigned p = 1u << i;
        if (!(planes & p))
            continue;
        const rast_cvert *src = buf[cur];
        rast_cvert *dst = buf[cur ^ 1];
        int m = 0;
        for (int k = 0; k < n; k++) {
            const rast_cvert *a = &src[k], *b = &src[(k + 1) % n];
            double da = plane_dist(p, a->clip, gx, gy), db = plane_dist(p, b->clip, gx, gy);
            bool ina = da >= 0.0, inb = db >= 0.0;
            if (ina && m < RAST_CLIP_MAX)
                dst[m++] = *a;
            if (ina != inb && m < RAST_CLIP_MAX) {
                if (ina)
                    lerp_vertex(a, b, da / (da - db), nvary, &dst[m++]);
                else
                    lerp_vertex(b, a, db / (db - da), nvary, &dst[m++]);
            }
        }
        n = m;
        cur ^= 1;
    }
    if (n < 3)
        return 0;
    memcpy(out, buf[cur], (size_t)n * sizeof out[0]);
    return n;
}
