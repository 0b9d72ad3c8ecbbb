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
 * node, so narrow lobes (alpha of thousands, a few texels wide) carry quadrature error too.
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

#endif
