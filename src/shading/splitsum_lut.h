/* splitsum_lut.h - the second half of the split-sum approximation (--estimator splitsum): the
 * BRDF's directional albedo split around Schlick's F0 = Ks, as a 2-D table over (N.V, lobe width).
 *
 *     integral of f_spec (N.w) dw = Ks A(N.V, r) + B(N.V, r)
 *     A = E[(1 - Fc) W],  B = E[Fc W],  Fc = (1 - V.H)^5,  W = G' (N.w) (V.H) / (N.H)
 *
 * W is the microfacet estimator's weight (lighting.c, specular_microfacet: H drawn from
 * D(H) (N.H), w = reflect(-V, H), G' = G / ((N.w)(N.V)) of brdf.h), so the table holds the
 * specification's D, G and F exactly as the shader evaluates them. The shading is then
 *     specular = P(normalize(mix(N, R, t)), r) (Ks A + B)
 * with P the prefiltered chain (src/ibl/prefilter.c) and t the table's third value: it points
 * the lookup towards the lobe's centroid (the W-weighted mean direction). The chain holds the
 * lobe at N = V, round about R; away from normal view the true lobe leans towards N (more for
 * wide lobes, the off-specular shift), so reading along R alone leaves a ring too dark or too
 * bright across a rough sphere. The shift from R is the centroid's times r (splitsum_lut.c:
 * narrower lobes keep their peak near R). The lobe width r is GGX's roughness, or
 * (2 / (alpha + 2))^(1/4) for a Phong exponent (the same peak of D; brdf.h).
 *
 * Layout: one texture of SL_SPLITSUM_LUT_SIZE columns (N.V = i / (SIZE - 1)) and
 * SL_SPLITSUM_SETS * SIZE rows (set s, width r = j / (SIZE - 1) in row s SIZE + j); a texel's
 * .x = A, .y = B, .z = t (RGB: the same bilinear filter as the environment, texture_lod.h), and
 * the control variate's beta over the same grid beside them (--estimator cv; softlight-gl
 * uploads the four as one GL_RGBA32F texture). Read at texel centres, so the lookup never leaves
 * its set's rows. N.V = 0 is evaluated at 0.01, the shader's smallest N.V (facing_normal). */
#ifndef SL_SPLITSUM_LUT_H
#define SL_SPLITSUM_LUT_H

#include <softlight/glsl.h>
#include "../core/options.h"
#include "../ibl/ibl.h"
#include "brdf.h"

#define SL_SPLITSUM_LUT_SIZE 32      /* per axis: A and B are smooth; 32 is Karis' and Filament's order */
#define SL_SPLITSUM_LUT_SAMPLES 256 /* per entry (Hammersley); test_splitsum's tolerances say what it gives */

/* The sets: the Phong set with each G term, and GGX (the values index rows; the GLSL has them). */
typedef enum {
    SL_SPLITSUM_PHONG_INV_LH2 = 0,
    SL_SPLITSUM_PHONG_ONE = 1,
    SL_SPLITSUM_GGX = 2,
    SL_SPLITSUM_SETS = 3
} sl_splitsum_set;

typedef struct {
    vec3 texels[SL_SPLITSUM_SETS * SL_SPLITSUM_LUT_SIZE * SL_SPLITSUM_LUT_SIZE];
    /* the control variate's coefficient beta over the same (set, N.V, r) grid (--estimator cv,
     * docs/lighting.md "Control variate"); softlight-gl uploads it as the table's .w */
    float beta[SL_SPLITSUM_SETS * SL_SPLITSUM_LUT_SIZE * SL_SPLITSUM_LUT_SIZE];
    /* each level's kernel in each set's chain of SL_PREFILTER_LEVELS (ibl.h sl_prefilter_kernel) */
    sl_prefilter_kernel kernels[SL_SPLITSUM_SETS][SL_PREFILTER_LEVELS];
} sl_splitsum_lut;

/* The control variate's levels for a chain read at lod (the split sum's lod = r (levels - 1)):
 * textureLod mixes level la with weight 1 - f and lb = la + 1 with f; ca and cb are those
 * weights where the level is exact (ibl.h sl_prefilter_first_exact) and 0 where it is not (level
 * 0, the environment itself, and the sampled levels), so ca C_a + cb C_b is the integral of the
 * environment against ca k_a + cb k_b. */
typedef struct {
    int la, lb;
    float ca, cb;
} sl_cv_levels;
/* GLSL: cv_levels */
static inline sl_cv_levels sl_cv_levels_at(float lod, int max_lod, int first_exact)
{
    lod = lod < 0.0f ? 0.0f : lod > (float)max_lod ? (float)max_lod : lod;
    int la = (int)lod;
    la = la < max_lod ? la : max_lod;
    int lb = la < max_lod ? la + 1 : max_lod;
    float f = lb > la ? lod - (float)la : 0.0f;
    sl_cv_levels l = {la, lb, la >= first_exact ? 1.0f - f : 0.0f, lb > la && lb >= first_exact ? f : 0.0f};
    return l;
}

/* Fill the table (about 0.8 M BRDF evaluations, in parallel; deterministic). */
void sl_splitsum_lut_build(sl_splitsum_lut *lut, int threads);
/* One entry computed directly (the table's (i, j) is this at N.V = max(i / (SIZE - 1), 0.01),
 * r = j / (SIZE - 1)): A in .x, B in .y. For tests. */
vec2 sl_splitsum_albedo(sl_splitsum_set set, float NdotV, float r, int samples);
/* The entry with its direction factor t in .z (the table's texel before filtering). */
vec3 sl_splitsum_entry(sl_splitsum_set set, float NdotV, float r, int samples);
/* sl_splitsum_width, the lobe width of a lobe parameter, is the BRDF's (brdf.h). */

#endif
