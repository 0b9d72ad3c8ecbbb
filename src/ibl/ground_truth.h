/* ground_truth.h - the double-precision reference for what the lighting shader estimates:
 * eq. (1) with the BRDF of eq. (2), integrated over EVERY texel of the environment's level 0.
 *
 *   diffuse  = Kd / pi * integral L(w) (w.N)+ dw
 *   specular = integral D(H) Gterm F(w, H) / 4 * L(w) (w.N)+ dw
 *   D = (alpha + 2) / (2 pi) (N.H)^alpha,  F = Ks + (1 - Ks) (1 - L.H)^5,
 *   Gterm = G / (L.N V.N) = 1 / (L.H)^2  or  1  (the specification's two choices),
 *   or, with `ggx` set, GGX's set (src/shading/brdf.h): a = max(r^2, 1e-4),
 *   D = a^2 / (pi ((N.H)^2 (a^2 - 1) + 1)^2), Gterm = 4 Vis (height-correlated Smith), `g` unused;
 *   all times `intensity`. Light from below the horizon (w.N <= 0) contributes 0, and so do
 *   microfacets facing away from the surface (N.H <= 0, only possible when V.N < 0).
 *
 * Quadrature: the image is taken as constant over each texel; each texel is one node at its
 * centroid direction (the normalised integral of w over the texel) with weight
 * |integral of w over the texel|, so the cosine factor is integrated exactly for every texel
 * wholly above the horizon. For a constant environment L = 1 the diffuse part is Kd to 1e-12
 * when the horizon runs along texel edges (N = +-x, +-y, +-z on even sizes) and within
 * 4e-6 relative otherwise (1024x512; texels the horizon cuts). The BRDF is evaluated at the
 * node, except near the peak of a lobe narrower than a few texels (a sharp lobe, or any lobe
 * seen at a grazing angle, whose reflected directions crowd into a sliver): there a texel is
 * split into s x s cells of equal solid angle and the BRDF read at each (sl_gt_lobe). One node a
 * texel reads 56.0 where the integral is 63.4 (GGX r = 0.1 at N.V = 0.15 on a 1024x512 map), and
 * half the integral at N.V = 0.02 under a sun near the horizon.
 *
 * Rotation: the environment turned by `rotation` radians about +Z, as the lighting shader
 * applies it: d_env = Rz(-rotation) d_world. Here N and V are turned instead, which is the
 * same integral.
 *
 * Threads: none inside. sl_ground_truth_shade only reads the table, so callers may run it
 * from many threads at once (parallelise over pixels); its result does not depend on that.
 * Cost: one pass over width * height texels, a pow for each texel above the horizon: 5.6 ms
 * per pixel for 1024x512 on one core (docs/ibl.md). */
#ifndef SL_GROUND_TRUTH_H
#define SL_GROUND_TRUTH_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "ibl.h"

/* G / (L.N V.N), the specification's two choices. */
typedef enum {
    SL_GT_G_INV_LH2 = 0, /* 1 / (L.H)^2 */
    SL_GT_G_ONE,         /* 1 */
} sl_gt_geometry;

typedef struct {
    vec3 n;            /* surface normal, world space (normalised here, in double) */
    vec3 v;            /* direction towards the eye, world space (normalised here) */
    vec3 kd, ks;       /* linear RGB */
    double alpha;      /* Phong exponent of D, >= 0 (ignored with ggx) */
    bool ggx;          /* GGX's D and G in place of the Phong set's */
    double roughness;  /* GGX: perceptual roughness r in [0, 1] */
    sl_gt_geometry g;
    double rotation;   /* radians about +Z */
    double intensity;  /* multiplies the environment (explicit: 0 gives black) */
} sl_gt_query;

typedef struct {
    double diffuse[3];  /* RGB */
    double specular[3]; /* RGB */
} sl_gt_result;

/* Per-texel nodes of level 0, built once by sl_ground_truth_init; read-only afterwards.
 * Structure of arrays: (x, y, z)[t] is the unit centroid direction (environment space),
 * (r, g, b)[t] the radiance times the node weight. */
typedef struct {
    int width, height;
    size_t count;
    double *x, *y, *z;
    double *r, *g, *b;
} sl_ground_truth;

bool sl_ground_truth_init(sl_ground_truth *gt, const sl_env *env, sl_error *err);
/* False (and err) on a non-finite or zero n or v, a negative or non-finite alpha or intensity,
 * a roughness outside [0, 1] (ggx), or an unknown g. */

bool sl_ground_truth_shade(const sl_ground_truth *gt, const sl_gt_query *q, sl_gt_result *out, sl_error *err);
void sl_ground_truth_free(sl_ground_truth *gt);

/* GGX's D(H) G / (4 (L.N)(V.N)) = D Vis in double, for a^2 = a2 (the truth's and the exact pass's
 * one formula): 0 when N.H <= 0 or the visibility's denominator is not positive. */
double sl_ground_truth_ggx_dvis(double nh, double nl, double nv, double a2);
/* a^2 of a roughness r: a = max(r^2, 1e-4). */
double sl_ground_truth_ggx_a2(double r);

/* A pixel's lobe in the environment's frame: what the BRDF at a node needs, and which texels the
 * quadrature splits (those whose centroid lies within a few lobe widths of R, when the lobe's
 * narrowest width is under a few texels), into how many cells (sl_gt_lobe_init). */
typedef struct {
    double n[3], v[3], nv; /* unit N and V, and N.V */
    bool ggx;
    double alpha, d_norm;  /* Phong: the exponent and (alpha + 2) / (2 pi); 0 with ggx */
    double a2;             /* GGX: a^2 */
    double r[3];           /* R = 2 (N.V) N - V */
    int width, height;     /* the level-0 image whose texels the nodes are */
    int split;             /* a texel near the peak is split into split x split cells (1: none) */
    double cos_near;       /* near the peak: the centroid's cosine to R above this */
} sl_gt_lobe;

/* n, v: unit, environment space; alpha: the Phong exponent (ggx false) or a2: GGX's a^2. */
void sl_gt_lobe_init(sl_gt_lobe *l, const double n[3], const double v[3], bool ggx, double alpha, double a2,
                     int width, int height);

/* The BRDF times the cosine at unit direction w with c = N.w > 0, the Fresnel term split out:
 * k_inv = D G' / 4 c with G' = 1/(L.H)^2 (GGX: its own), k_one the same with G' = 1, p5 =
 * (1 - L.H)^5, so that the specular is sum (Ks k + (1 - Ks) k p5) L. False where it is 0: L = -V,
 * N.H <= 0, or a Phong power that rounds to 0 in double ((N.H)^alpha <= exp(-alpha (1 - N.H))). */
static inline bool sl_gt_kernel(const sl_gt_lobe *l, double c, double wx, double wy, double wz, double *k_inv,
                                double *k_one, double *p5)
{
    double len2 = 2.0 + 2.0 * (l->v[0] * wx + l->v[1] * wy + l->v[2] * wz); /* |L + V|^2 */
    if (!(len2 > 1e-24))
        return false; /* L = -V: H undefined, a set of measure zero */
    double len = sqrt(len2);
    double nh = (c + l->nv) / len; /* H = (L + V) / |L + V| is never formed */
    if (!(nh > 0.0) || l->alpha * (1.0 - nh) > 746.0)
        return false;
    double lh = 0.5 * len;
    if (l->ggx) {
        *k_one = *k_inv = sl_ground_truth_ggx_dvis(nh, c, l->nv, l->a2) * c;
    } else {
        double base = 0.25 * l->d_norm * pow(nh, l->alpha);
        *k_one = base * 1.0 * c;
        *k_inv = base * (1.0 / (lh * lh)) * c;
    }
    double p = 1.0 - lh;
    p = p > 0.0 ? p : 0.0;
    *p5 = (p * p) * (p * p) * p;
    return true;
}

/* The kernel of the texel whose centroid is unit w (c = N.w > 0), as factors of its radiance times
 * its node weight: k[0] = k_inv, k[1] = k_inv p5, k[2] = k_one, k[3] = k_one p5, read at the
 * centroid, or over the texel's cells where it is near a split lobe's peak. `texel` false: w is a
 * point light's direction, read there. False where the kernel is 0 (sl_gt_kernel). */
bool sl_gt_node_kernel(const sl_gt_lobe *l, double c, double wx, double wy, double wz, bool texel, double k[4]);

#endif
