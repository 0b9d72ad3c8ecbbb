/* brdf.h - the specification's micro-facet BRDF terms (eq. (2)), float32 as in GLSL.
 *
 *   f(L, V, N) = Kd / pi + D(H) G(L, V, H) F(L, H) / (4 (L.N)(V.N))
 *   D(H) = (alpha + 2) / (2 pi) (N.H)^alpha          Phong, alpha 0 (rough) .. inf (mirror)
 *   G / ((L.N)(V.N)) = 1 / (L.H)^2   or   = 1        the two shadowing choices
 *   F(L, H) = Ks + (1 - Ks)(1 - L.H)^5               Schlick
 *
 * and the second set, GGX, which replaces D and G only (docs/conventions.md, erratum 10):
 *   a = max(r^2, 1e-4), r the perceptual roughness in [0, 1] (glTF)
 *   D(H) = a^2 / (pi ((N.H)^2 (a^2 - 1) + 1)^2)
 *   G / ((L.N)(V.N)) = 4 Vis, Vis the height-correlated Smith visibility
 *     Vis = 0.5 / ((N.L) sqrt((N.V)^2 (1 - a^2) + a^2) + (N.V) sqrt((N.L)^2 (1 - a^2) + a^2))
 * A pixel's lobe is one float, the G-buffer's alpha (raster/gbuffer.h): >= 0 is the Phong
 * exponent, <= -1 is GGX with r = -1 - alpha. sl_lobe_D and sl_lobe_G choose by its sign; the
 * --g choice applies to the Phong set only.
 *
 * The same functions, with the same names, are in shaders/lighting.frag; both lighting paths
 * (lighting.c, lighting_batched.c) call these. Guards (docs/lighting.md, "Hard cases"): pow never sees a base <= 0 (N.H floored at
 * 1e-30, so alpha = 0 gives 1, not GLSL's undefined pow(0, 0)), 1 - L.H is clamped at 0
 * (L.H rounds above 1), and L.H is floored at 1e-3 inside 1/(L.H)^2.
 *
 * Does not: evaluate lights or the environment (lighting.c). */
#ifndef SL_BRDF_H
#define SL_BRDF_H

#include <stdbool.h>

#include <softlight/glsl.h>
#include "../core/options.h" /* sl_gterm */

#define SL_BRDF_TINY 1e-30f      /* floor of pow() and log2() arguments */
#define SL_BRDF_MIN_LDOTH 1e-3f  /* floor of L.H in 1/(L.H)^2 */

/* D(H) = (alpha + 2) / (2 pi) (N.H)^alpha. */
/* GLSL: sl_brdf_D */
static inline float sl_brdf_D(float NdotH, float alpha)
{
    return (alpha + 2.0f) / (2.0f * SL_PI) * powf(maxf(NdotH, SL_BRDF_TINY), alpha);
}

/* G(L, V, H) / ((L.N)(V.N)). */
/* GLSL: sl_brdf_G */
static inline float sl_brdf_G(float LdotH, sl_gterm gterm)
{
    if (gterm == SL_GTERM_INV_LH2) {
        float LH = maxf(LdotH, SL_BRDF_MIN_LDOTH);
        return 1.0f / (LH * LH);
    }
    return 1.0f;
}

/* Schlick's F(L, H) = Ks + (1 - Ks)(1 - L.H)^5, the fifth power by multiplication. */
/* GLSL: sl_brdf_F */
static inline vec3 sl_brdf_F(vec3 Ks, float LdotH)
{
    float m = maxf(1.0f - LdotH, 0.0f);
    float m2 = m * m;
    return add(Ks, scale(sub(vec3s(1.0f), Ks), m2 * m2 * m));
}

/* ---- GGX ---- */

#define SL_GGX_MIN_A 1e-4f /* a = max(r^2, 1e-4): r = 0 stays a finite (mirror-like) lobe */

/* The lobe parameter (G-buffer alpha) of a GGX material with roughness r. */
static inline float sl_ggx_alpha_of_roughness(float r) { return -1.0f - r; }
/* a^2 of a GGX lobe parameter alpha in [-2, -1] */
/* GLSL: sl_ggx_a2 */
static inline float sl_ggx_a2(float alpha)
{
    float r = -1.0f - alpha;
    float a = maxf(r * r, SL_GGX_MIN_A);
    return a * a;
}

/* D(H) = a^2 / (pi ((N.H)^2 (a^2 - 1) + 1)^2), the bracket as (1 - (N.H)^2) + (N.H)^2 a^2: in
 * float a^2 - 1 is -1 for a^2 < 6e-8 (r < 0.016), and the literal form then divides by 0 at
 * N.H = 1. */
/* GLSL: sl_ggx_D */
static inline float sl_ggx_D(float NdotH, float a2)
{
    float c2 = NdotH * NdotH;
    float t = maxf(1.0f - c2, 0.0f) + c2 * a2;
    return a2 / (SL_PI * t * t);
}

/* G / ((L.N)(V.N)) = 4 Vis (height-correlated Smith); N.L, N.V > 0. */
/* GLSL: sl_ggx_G */
static inline float sl_ggx_G(float NdotL, float NdotV, float a2)
{
    float gv = NdotL * sqrtf(NdotV * NdotV * (1.0f - a2) + a2);
    float gl = NdotV * sqrtf(NdotL * NdotL * (1.0f - a2) + a2);
    return 2.0f / (gv + gl);
}

/* Which set a lobe parameter (G-buffer alpha) is: GGX's are negative. */
/* GLSL: sl_lobe_is_ggx */
static inline bool sl_lobe_is_ggx(float alpha) { return alpha < 0.0f; }

/* D and G of either set, chosen by the lobe parameter's sign. */
/* GLSL: sl_lobe_D */
static inline float sl_lobe_D(float NdotH, float alpha)
{
    return sl_lobe_is_ggx(alpha) ? sl_ggx_D(NdotH, sl_ggx_a2(alpha)) : sl_brdf_D(NdotH, alpha);
}
/* GLSL: sl_lobe_G */
static inline float sl_lobe_G(float LdotH, float NdotL, float NdotV, float alpha, sl_gterm gterm)
{
    return sl_lobe_is_ggx(alpha) ? sl_ggx_G(NdotL, NdotV, sl_ggx_a2(alpha)) : sl_brdf_G(LdotH, gterm);
}

/* The phong exponent with GGX's peak value of D for comparisons: alpha_phong = 2 / a^2 - 2
 * (docs/lighting.md "Phong and GGX"). */
static inline float sl_ggx_phong_equivalent(float r)
{
    float a = maxf(r * r, SL_GGX_MIN_A);
    return 2.0f / (a * a) - 2.0f;
}

/* The split sum's lobe width of a lobe parameter (the G-buffer alpha after lobe_param): GGX's
 * r = -1 - alpha, a Phong exponent's (2 / (alpha + 2))^(1/4), the width of equal peak
 * (splitsum_lut.h indexes its table with it). */
static inline float sl_splitsum_width(float alpha)
{
    if (alpha < 0.0f)
        return -1.0f - alpha;
    return sqrtf(sqrtf(2.0f / (alpha + 2.0f)));
}

#endif
