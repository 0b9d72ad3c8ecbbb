/* brdf.h - the specification's micro-facet BRDF terms (eq. (2)), float32 as in GLSL.
 *
 *   f(L, V, N) = Kd / pi + D(H) G(L, V, H) F(L, H) / (4 (L.N)(V.N))
 *   D(H) = (alpha + 2) / (2 pi) (N.H)^alpha          Phong, alpha 0 (rough) .. inf (mirror)
 *   G / ((L.N)(V.N)) = 1 / (L.H)^2   or   = 1        the two shadowing choices
 *   F(L, H) = Ks + (1 - Ks)(1 - L.H)^5               Schlick
 *
 * The same functions, with the same names, are in shaders/lighting.frag; both lighting paths
 * (lighting.c, lighting_batched.c) call these. Guards (docs/lighting.md, "Hard cases"): pow never sees a base <= 0 (N.H floored at
 * 1e-30, so alpha = 0 gives 1, not GLSL's undefined pow(0, 0)), 1 - L.H is clamped at 0
 * (L.H rounds above 1), and L.H is floored at 1e-3 inside 1/(L.H)^2.
 *
 * Does not: evaluate lights or the environment (lighting.c). */
#ifndef SL_BRDF_H
#define SL_BRDF_H

#include "../core/glsl.h"
#include "../core/options.h" /* sl_gterm */

#define SL_BRDF_TINY 1e-30f      /* floor of pow() and log2() arguments */
#define SL_BRDF_MIN_LDOTH 1e-3f  /* floor of L.H in 1/(L.H)^2 */

/* D(H) = (alpha + 2) / (2 pi) (N.H)^alpha. */
static inline float sl_brdf_D(float NdotH, float alpha)
{
    return (alpha + 2.0f) / (2.0f * SL_PI) * powf(maxf(NdotH, SL_BRDF_TINY), alpha);
}

/* G(L, V, H) / ((L.N)(V.N)). */
static inline float sl_brdf_G(float LdotH, sl_gterm gterm)
{
    if (gterm == SL_GTERM_INV_LH2) {
        float LH = maxf(LdotH, SL_BRDF_MIN_LDOTH);
        return 1.0f / (LH * LH);
    }
    return 1.0f;
}

/* Schlick's F(L, H) = Ks + (1 - Ks)(1 - L.H)^5, the fifth power by multiplication. */
static inline vec3 sl_brdf_F(vec3 Ks, float LdotH)
{
    float m = maxf(1.0f - LdotH, 0.0f);
    float m2 = m * m;
    return add(Ks, scale(sub(vec3s(1.0f), Ks), m2 * m2 * m));
}

#endif
