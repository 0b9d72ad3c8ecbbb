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

/* The share of the lobe's cap (cosine cos_s) inside a cap of cosine cos_v whose axis is at cosine
 * cos_d from the lobe's: caps' intersection over the lobe's cap, in [0, 1]. */
/* GLSL: so_cap_share */
static inline float sl_so_cap_share(float cos_v, float cos_s, float cos_d)
{
    float tv = acosf(clampf(cos_v, -1.0f, 1.0f)), ts = acosf(clampf(cos_s, -1.0f, 1.0f));
    float d = acosf(clampf(cos_d, -1.0f, 1.0f));
    float lo = fabsf(tv - ts), hi = tv + ts;
    float inside = 1.0f - clampf((d - lo) / fmaxf(hi - lo, 1e-6f), 0.0f, 1.0f);
    float cap = 1.0f - cosf(fminf(tv, ts)); /* the smaller cap, over 2 pi */
    return clampf(cap * smoothstep(0.0f, 1.0f, inside) / fmaxf(1.0f - cos_s, 1e-12f), 0.0f, 1.0f);
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
    float cos_s = powf(SL_SO_LOBE_OUTSIDE, 1.0f / (sl_so_phong_exponent(alpha) + 1.0f));
    float open = sl_so_cap_share(0.0f, cos_s, n_dot_v);
    float seen = sl_so_cap_share(sqrtf(fmaxf(0.0f, 1.0f - ao)), cos_s, b_dot_r);
    float so = open > 0.0f ? clampf(seen / open, 0.0f, 1.0f) : ao;
    /* Near ao = 1 the cone misleads: a few hidden directions become a ring all along the horizon,
     * which swallows a grazing lobe whole, and there the AO is mostly the pass's own error on open
     * ground (up to 0.025 at grazing views, tests/unit/test_gtao.c). The factor fades to 1 over
     * SL_SO_FADE < ao < 1. */
    return so + (1.0f - so) * smoothstep(SL_SO_FADE, 1.0f, ao);
}

#endif
