/* ground_truth.c - the double-precision reference integrator of eq. (1) with eq. (2); the
 * conventions and the quadrature are described in ground_truth.h.
 *
 * The loop uses L.H = |L + V| / 2 and N.H = (N.L + N.V) / |L + V|, which follow from
 * H = (L + V) / |L + V| with unit L and V, so H itself is never formed. The Fresnel term is
 * split as F = Ks + (1 - Ks) p5 with p5 = (1 - L.H)^5, so one pass serves every Ks:
 * specular = Ks * S0 + (1 - Ks) * S1 with S0 = sum k L, S1 = sum k p5 L. */
#include "ground_truth.h"

#include <math.h>
#include <string.h>

#include "ibl_internal.h"

#define PI_D 3.14159265358979323846

bool sl_ground_truth_init(sl_ground_truth *gt, const sl_env *env, sl_error *err)
{
    memset(gt, 0, sizeof *gt);
    if (!env || env->level_count < 1)
        return sl_fail(err, SL_ERR_RANGE, "ground truth: the environment has no levels");
    ibl_texels t;
    if (!sl_ibl_texels_build(&t, &env->levels[0], err))
        return false;
    *gt = (sl_ground_truth){.width = t.width, .height = t.height, .count = t.count,
                            .x = t.x, .y = t.y, .z = t.z, .r = t.r, .g = t.g, .b = t.b};
    return true;
}

void sl_ground_truth_free(sl_ground_truth *gt)
{
    if (!gt)
        return;
    ibl_texels t = {.x = gt->x};
    sl_ibl_texels_free(&t); /* one block, owned through x */
    memset(gt, 0, sizeof *gt);
}

double sl_ground_truth_ggx_a2(double r)
{
    double a = r * r > 1e-4 ? r * r : 1e-4;
    return a * a;
}

double sl_ground_truth_ggx_dvis(double nh, double nl, double nv, double a2)
{
    if (!(nh > 0.0))
        return 0.0;
    double t = (1.0 - nh * nh) + nh * nh * a2; /* brdf.h's form of nh^2 (a^2 - 1) + 1 */
    double d = a2 / (PI_D * t * t);
    double den = nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2);
    return den > 0.0 ? d * 0.5 / den : 0.0;
}

static bool unit(vec3 a, double out[3])
{
    double x = (double)a.x, y = (double)a.y, z = (double)a.z;
    double len = sqrt(x * x + y * y + z * z);
    if (!(len > 0.0) || !isfinite(len))
        return false;
    out[0] = x / len;
    out[1] = y / len;
    out[2] = z / len;
    return true;
}

static bool finite3(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

bool sl_ground_truth_shade(const sl_ground_truth *gt, const sl_gt_query *q, sl_gt_result *out, sl_error *err)
{
    memset(out, 0, sizeof *out);
    double nw[3], vw[3];
    if (!unit(q->n, nw))
        return sl_fail(err, SL_ERR_RANGE, "ground truth: normal (%g, %g, %g) is zero or not finite",
                       (double)q->n.x, (double)q->n.y, (double)q->n.z);
    if (!unit(q->v, vw))
        return sl_fail(err, SL_ERR_RANGE, "ground truth: view direction (%g, %g, %g) is zero or not finite",
                       (double)q->v.x, (double)q->v.y, (double)q->v.z);
    if (q->ggx && !(q->roughness >= 0.0 && q->roughness <= 1.0))
        return sl_fail(err, SL_ERR_RANGE, "ground truth: GGX roughness %g, must be in [0, 1]", q->roughness);
    if (!q->ggx && (!(q->alpha >= 0.0) || !isfinite(q->alpha)))
        return sl_fail(err, SL_ERR_RANGE, "ground truth: alpha %g, must be finite and >= 0", q->alpha);
    if (!(q->intensity >= 0.0) || !isfinite(q->intensity) || !isfinite(q->rotation))
        return sl_fail(err, SL_ERR_RANGE, "ground truth: intensity %g / rotation %g, must be finite (intensity >= 0)",
                       q->intensity, q->rotation);
    if (q->g != SL_GT_G_INV_LH2 && q->g != SL_GT_G_ONE)
        return sl_fail(err, SL_ERR_RANGE, "ground truth: unknown G choice %d", (int)q->g);
    if (!finite3(q->kd) || !finite3(q->ks))
        return sl_fail(err, SL_ERR_RANGE, "ground truth: Kd or Ks not finite");

    /* World -> environment: d_env = Rz(-rotation) d_world. */
    double cr = cos(q->rotation), sr = sin(q->rotation);
    const double nx = cr * nw[0] + sr * nw[1], ny = -sr * nw[0] + cr * nw[1], nz = nw[2];
    const double vx = cr * vw[0] + sr * vw[1], vy = -sr * vw[0] + cr * vw[1], vz = vw[2];
    const double nv = nx * vx + ny * vy + nz * vz;
    const double alpha = q->alpha, d_norm = (alpha + 2.0) / (2.0 * PI_D);
    const bool g_one = q->g == SL_GT_G_ONE;
    const bool ggx = q->ggx;
    const double a2 = ggx ? sl_ground_truth_ggx_a2(q->roughness) : 0.0;

    const double *restrict x = gt->x, *restrict y = gt->y, *restrict z = gt->z;
    const double *restrict r = gt->r, *restrict g = gt->g, *restrict b = gt->b;
    double dr = 0, dg = 0, db = 0;    /* sum (N.L) L */
    double s0r = 0, s0g = 0, s0b = 0; /* sum k L */
    double s1r = 0, s1g = 0, s1b = 0; /* sum k p5 L */
    for (size_t t = 0; t < gt->count; t++) {
        double c = nx * x[t] + ny * y[t] + nz * z[t]; /* N.L */
        if (!(c > 0.0))
            continue;
        dr += c * r[t];
        dg += c * g[t];
        db += c * b[t];
        double len2 = 2.0 + 2.0 * (vx * x[t] + vy * y[t] + vz * z[t]); /* |L + V|^2 */
        if (!(len2 > 1e-24))
            continue; /* L = -V: H undefined, a set of measure zero */
        double len = sqrt(len2);
        double nh = (c + nv) / len;
        if (!(nh > 0.0))
            continue;
        double lh = 0.5 * len;
        double k;
        if (ggx) {
            k = sl_ground_truth_ggx_dvis(nh, c, nv, a2) * c;
        } else {
            double gterm = g_one ? 1.0 : 1.0 / (lh * lh);
            k = 0.25 * d_norm * pow(nh, alpha) * gterm * c;
        }
        double p = 1.0 - lh;
        p = p > 0.0 ? p : 0.0;
        double p5 = (p * p) * (p * p) * p;
        s0r += k * r[t];
        s0g += k * g[t];
        s0b += k * b[t];
        s1r += k * p5 * r[t];
        s1g += k * p5 * g[t];
        s1b += k * p5 * b[t];
    }
    const double kd[3] = {(double)q->kd.x, (double)q->kd.y, (double)q->kd.z};
    const double ks[3] = {(double)q->ks.x, (double)q->ks.y, (double)q->ks.z};
    const double dsum[3] = {dr, dg, db}, s0[3] = {s0r, s0g, s0b}, s1[3] = {s1r, s1g, s1b};
    for (int ch = 0; ch < 3; ch++) {
        out->diffuse[ch] = q->intensity * kd[ch] / PI_D * dsum[ch];
        out->specular[ch] = q->intensity * (ks[ch] * s0[ch] + (1.0 - ks[ch]) * s1[ch]);
    }
    return true;
}
