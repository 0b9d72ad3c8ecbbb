/* env_lights.h - the brightest texels of an environment, taken out of it and summed exactly.
 *
 * Why: filtered importance sampling reads the environment through a blur sized for N samples.
 * That is accurate where the map is smooth and wrong where a few texels hold a sun or a lamp
 * (radiance 10^3..10^4 against a sky near 1): a near-mirror reflecting the lamp reads it blurred
 * to a fraction of its peak, a glossy floor smears the sun's glint, and those few pixels carry
 * almost all of the error against the ground truth (docs/accuracy.md). Splitting the map,
 *
 *     L = L_residual + sum over the K brightest texels t of (L_t - r_t) [w in texel t],
 *
 * lets the estimator sample a residual whose dynamic range is capped, while each extracted
 * texel becomes a light evaluated with the full BRDF at its centroid, the node the ground
 * truth uses for it (ground_truth.h), or over cells of equal solid angle where the lobe is
 * narrower than a few texels, as the truth splits such texels; so that part is exact for any
 * alpha.
 *
 * The residual keeps each extracted texel's colour at the luminance of the brightest texel
 * that was not extracted (the clamp): r_t = L_t * clamp / Y(L_t), Y the Rec. 709 luminance.
 * The decomposition is exact texel by texel on level 0; the residual's mip chain is built by
 * sl_env_build like any environment.
 *
 * Consumes: an environment (level 0). Produces: K lights (direction and radiance times the
 * texel's node weight |integral of w over the texel|, environment space) and the residual's
 * mip chain. Does not: shade (the lighting shader's specular_env_lights, src/shading). */
#ifndef SL_ENV_LIGHTS_H
#define SL_ENV_LIGHTS_H

#include "ibl.h"

/* SL_ENV_LIGHTS_MAX (core/options.h): MAX_ENV_LIGHTS in the GLSL */

typedef struct {
    int count;              /* K actually extracted: min(requested, texels with a direction) */
    float clamp;            /* the luminance extracted texels keep in the residual: that of the
                               brightest texel with a direction not taken (0 when none is left);
                               the residual's largest luminance unless a texel without a direction
                               (a 1x1 map) is brighter */
    double share;           /* the extracted part's share of the map's luminous power (report) */
    vec3 dir[SL_ENV_LIGHTS_MAX];      /* unit centroid direction, environment space */
    vec3 radiance[SL_ENV_LIGHTS_MAX]; /* (L_t - r_t) * node weight, brightest first */
    size_t texel[SL_ENV_LIGHTS_MAX];  /* index j * width + i of the texel in level 0 */
    vec3 box[SL_ENV_LIGHTS_MAX];      /* the texel's bounds for a split (z = cos(theta), phi as
                                         ibl.h's lat-long maps them): z at its top and bottom edges,
                                         phi at its first edge (its width: azimuth) */
    float spread[SL_ENV_LIGHTS_MAX];  /* its solid angle over its node weight |integral of w|: a
                                         cell of a split into n gets radiance * spread / n */
    float azimuth;          /* every level-0 texel's signed width in phi, first edge to last:
                               -2 pi / W (phi falls as u grows) */
    sl_env residual;        /* the environment less the lights, full mip chain */
} sl_env_lights;

/* Extract the `count` brightest texels of env's level 0 (1 .. SL_ENV_LIGHTS_MAX) and build the
 * residual's mip chain. Ties are broken by texel index, so the result is deterministic. On
 * failure *lights is empty. */
bool sl_env_lights_extract(sl_env_lights *lights, const sl_env *env, int count, int threads, sl_error *err);
/* The same with `most` a ceiling: only as many of the `most` brightest texels as are worth their
 * cost (SL_ENV_LIGHTS_WORTH_*, core/options.h), possibly none (count 0, no residual built: the
 * estimator reads env itself). Each light costs every pixel its evaluation, so a map whose
 * brightest texels are a plateau pays nothing, and one whose sun is four texels pays for about
 * four. */
bool sl_env_lights_extract_worth(sl_env_lights *lights, const sl_env *env, int most, int threads, sl_error *err);
void sl_env_lights_free(sl_env_lights *lights);

#endif
