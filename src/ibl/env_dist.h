/* env_dist.h - the environment as a probability distribution over directions: what the MIS
 * estimator (--estimator mis, src/shading) draws its environment samples from.
 *
 * Why: a sun or a lamp covers a few texels of the map and carries most of its power; a BRDF
 * sample finds it only by luck, so filtered importance sampling reads it blurred (docs/accuracy.md).
 * Drawing directions in proportion to the environment's own radiance puts samples on it, and the
 * power heuristic (lighting.frag specular_mis) weighs them against the BRDF's own.
 *
 * The distribution is piecewise constant in solid angle over a W x H lat-long grid (a level of
 * the environment's chain, the first no wider than SL_ENV_DIST_MAX_WIDTH): texel (i, j) has
 * probability proportional to Y(i, j) * Omega(j), Y the Rec. 709 luminance of the level's texel
 * and Omega(j) = (2 pi / W)(cos(pi j / H) - cos(pi (j + 1) / H)) its exact solid angle, and is
 * sampled uniformly in solid angle inside (uniform in cos(theta) and phi), so its density is
 * Y(i, j) / sum(Y Omega), constant over the texel: the pole rows' tiny texels get their own
 * (finite) density, with no sin(theta) to divide by. The stored density is that of the float
 * CDFs as drawn (their steps over Omega), so what the weights count on is what is drawn. A map whose luminance is 0 everywhere
 * becomes the uniform sphere (density 1 / (4 pi)).
 *
 * Sampling is by inversion (lighting.frag env_dist_sample): a row from the marginal CDF, a
 * column from the row's conditional CDF, both binary searches, O(log W + log H). The GLSL reads
 * the same arrays as two textures (src/gl/lighting_pass.c).
 *
 * Built once per environment (and env-lights count: it is the distribution of what the samples
 * read) by the renderer, like the irradiance and the env lights; the shading only reads it. */
#ifndef SL_ENV_DIST_H
#define SL_ENV_DIST_H

#include "ibl.h"

/* The widest grid the distribution is built on: the first level of the chain no wider than this.
 * The shipped maps (1024 x 512) are used at full resolution: a sun of a few texels keeps its
 * own density. */
#define SL_ENV_DIST_MAX_WIDTH 1024

typedef struct {
    int width, height;   /* the grid W x H */
    int level;           /* the level of the chain it was built from (0 = full resolution) */
    int src_width, src_height; /* that chain's level 0, which the estimator reads radiance from */
    float *cdf;          /* W x H, row j: the conditional CDF of the columns, cdf[j W + W - 1] = 1
                            (rows of zero luminance: uniform) */
    float *density;      /* W x H: the density in solid angle of directions in texel (i, j), per sr */
    float *marginal;     /* H: the CDF of the rows, marginal[H - 1] = 1 */
    double total;        /* sum of Y Omega over the grid (the normaliser; 0: the uniform sphere) */
    float *texel_pdf;    /* the batched path's one read per direction: level-0 texel k's radiance
                            and the density of its grid texel, (r, g, b, density) at 4 k; for
                            chains of at most SL_ENV_PAIRS_MAX_TEXELS texels at level 0, else NULL */
} sl_env_dist;

/* Build the distribution of `env` (a lat-long chain). On failure *dist is empty. */
bool sl_env_dist_build(sl_env_dist *dist, const sl_env *env, sl_error *err);
void sl_env_dist_free(sl_env_dist *dist);

#endif
