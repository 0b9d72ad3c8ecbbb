/* specular_occlusion.h - how much of the image-based specular lobe the occluders around a point
 * hide, from the ambient occlusion pass's visibility cone (src/occlusion/gtao.h: the bent normal
 * and the AO) and the lobe (R = reflect(-V, N) and the lobe parameter). One function for the C
 * port, the batched path and trace; shaders/lighting.frag has its GLSL twin (specular_occlusion).
 *
 * The method, cone against cone (Jimenez et al. 2016, "Practical Realtime Strategies for Accurate
 * Indirect Occlusion", after Oat and Sander's ambient aperture lighting): the visible directions
 * are taken as a cone about the bent normal B whose cosine-weighted share of the hemisphere is the
 * AO, so cos(theta_v) = sqrt(1 - AO); the lobe as a cone about R holding most of its energy; the
 * occlusion is the share of the lobe's cone inside the visibility cone, the caps' intersection
 * (its solid angle from the smaller cap and a smoothstep in the angle between the axes) over the
 * lobe's cap. It is divided by the same share for the open hemisphere (B = N, AO = 1), so a
 * point nothing hides keeps its lobe whole: the part of a wide lobe below the horizon is the
 * blind integral's business, not an occluder's; and it fades to 1 as the AO nears 1 (below). docs/lighting.md "Specular occlusion" says why
 * this form and not Lagarde's (AO, N.V and roughness alone), with the measurements. */
#ifndef SL_SPECULAR_OCCLUSION_H
#define SL_SPECULAR_OCCLUSION_H

#include <math.h>

#include <softlight/glsl.h>

/* The share of a lobe's energy its cone holds: the cone of a Phong lobe cos^n about R holding the
 * share f of it has cos = (1 - f)^(1/(n + 1)); 1 - f = 0.244 (Jimenez et al.'s choice). */
#define SL_SO_LOBE_OUTSIDE 0.244f
/* The AO from which the cone's factor fades to 1 (sl_specular_occlusion; chosen by
 * bench/specular-occlusion.sh: 0.5 .. 0.95 measured, 0.8 the lowest error summed over the scenes). */
#define SL_SO_FADE 0.8f

/* The Phong exponent of the lobe parameter (lighting.frag lobe_param): Phong's own, or GGX's
 * roughness r as the exponent of the same width, 2 / a^2 - 2 with a = max(r^2, 1e-4). */
/* GLSL: so_phong_exponent */
static inline float sl_so_phong_exponent(float alpha)
{
    if (alpha >= 0.0f)
        return alpha;
    float r = -1.0f - alpha;
    float a = fmaxf(r * r, 1e-4f);
    return fmaxf(2.0f / (a * a) - 2.0f, 0.0f);
}

/* acos(x) for x in [-1, 1] as a polynomial, vectorizable (no library call): Abramowitz and
 * Stegun 4.4.46, sqrt(1 - x) times a degree-7 polynomial on [0, 1], |error| <= 2e-8 rad in exact
 * arithmetic (a few float ulps as evaluated, far below the factor's bounds); acos(-x) = pi -
 * acos(x) below 0. The GLSL twin evaluates the same polynomial, so the two sides agree. */
/* GLSL: so_acos */
static inline float sl_so_acos(float x)
{
    float a = minf(fabsf(x), 1.0f);
    float p = -0.0012624911f;
    p = p * a + 0.0066700901f;
    p = p * a - 0.0170881256f;
    p = p * a + 0.0308918810f;
    p = p * a - 0.0501743046f;
    p = p * a + 0.0889789874f;
    p = p * a - 0.2145988016f;
    p = p * a + 1.5707963050f;
    float r = p * sqrtf(1.0f - a), mirrored = SL_PI - r; /* both formed, one kept: a vector select */
    return x < 0.0f ? mirrored : r;
}

/* The lobe's cone, which depends on the lobe parameter alone (a caller shading many pixels of
 * one material computes it once): its cosine cos_s (GLSL so_lobe_cos) and its angle ts. */
typedef struct {
    float cos_s, ts;
} sl_so_lobe;

/* GLSL: so_lobe_cos */
static inline sl_so_lobe sl_so_lobe_cone(float alpha)
{
    float cos_s = powf(SL_SO_LOBE_OUTSIDE, 1.0f / (sl_so_phong_exponent(alpha) + 1.0f));
    return (sl_so_lobe){cos_s, sl_so_acos(cos_s)};
}

/* The share of the lobe's cap (cosine cos_s, angle ts) inside a cap of cosine cos_v (angle tv)
 * whose axis is at cosine cos_d from the lobe's: caps' intersection over the lobe's cap, in
 * [0, 1]. The smaller cap over 2 pi is 1 - cos(min(tv, ts)) = 1 - max(cos_v, cos_s). */
/* GLSL: so_cap_share */
static inline float sl_so_cap_share(float cos_v, float tv, sl_so_lobe lobe, float cos_d)
{
    float d = sl_so_acos(cos_d);
    float lo = fabsf(tv - lobe.ts), hi = tv + lobe.ts;
    float inside = 1.0f - clampf((d - lo) / maxf(hi - lo, 1e-6f), 0.0f, 1.0f);
    float cap = 1.0f - maxf(cos_v, lobe.cos_s);
    return clampf(cap * smoothstep(0.0f, 1.0f, inside) / maxf(1.0f - lobe.cos_s, 1e-12f), 0.0f, 1.0f);
}

/* sl_specular_occlusion with the lobe's cone given: no branch and no library call but sqrtf
 * (minf and maxf, not fminf and fmaxf, which GCC does not vectorize), so the batched path runs
 * it for a whole span in one vector loop (the same bits as one call). */
static inline float sl_specular_occlusion_lobe(float ao, float b_dot_r, float n_dot_v, sl_so_lobe lobe)
{
    float cos_v = sqrtf(maxf(1.0f - ao, 0.0f));
    float open = sl_so_cap_share(0.0f, 0.5f * SL_PI, lobe, n_dot_v);
    float seen = sl_so_cap_share(cos_v, sl_so_acos(cos_v), lobe, b_dot_r);
    /* each value formed, then one kept: GCC will not move a division out from under a branch
     * (it might trap), and a branch keeps the loop from vectorizing */
    float ratio = clampf(seen / open, 0.0f, 1.0f);
    float so = open > 0.0f ? ratio : ao;
    /* Near ao = 1 the cone misleads: a few hidden directions become a ring all along the horizon,
     * which swallows a grazing lobe whole, and there the AO is mostly the pass's own error on open
     * ground (up to 0.025 at grazing views, tests/unit/test_gtao.c). The factor fades to 1 over
     * SL_SO_FADE < ao < 1, and is exactly 1 from ao = 1 on (nothing hidden). */
    float faded = so + (1.0f - so) * smoothstep(SL_SO_FADE, 1.0f, ao);
    faded = ao >= 1.0f ? 1.0f : faded;
    return ao > 0.0f ? faded : 0.0f;
}

/* The specular occlusion, in [0, 1]: `ao` the AO, `b_dot_r` the cosine between the bent normal and
 * R, `n_dot_v` N.V (= N.R), `alpha` the lobe parameter. 1 where ao is 1; 0 where ao is 0; never
 * rising as the lobe widens about the cone's axis or as R leaves the cone, never falling as the
 * cone opens (ao grows). */
/* GLSL: specular_occlusion */
static inline float sl_specular_occlusion(float ao, float b_dot_r, float n_dot_v, float alpha)
{
    if (!(ao > 0.0f))
        return 0.0f;
    if (ao >= 1.0f) /* the fade's weight is 1: nothing hidden, exactly */
        return 1.0f;
    return sl_specular_occlusion_lobe(ao, b_dot_r, n_dot_v, sl_so_lobe_cone(alpha));
}

#endif
