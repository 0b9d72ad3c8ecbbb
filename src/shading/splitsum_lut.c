/* splitsum_lut.c - the split-sum table of the BRDF's scale and bias (splitsum_lut.h), computed
 * once per renderer with the lighting shader's own BRDF terms (brdf.h) and sample generator
 * (lighting.c's microfacet_sample), so the table and the per-pixel estimators integrate the
 * same function. */
#include "../core/threads.h"
#include <math.h>

#include "../ibl/ibl.h"
#include "brdf.h"
#include "lighting_internal.h"
#include "splitsum_lut.h"

/* The lobe parameter of width r in a set: -1 - r (GGX), or the Phong exponent of equal peak. */
static float set_alpha(sl_splitsum_set set, float r)
{
    if (set == SL_SPLITSUM_GGX)
        return sl_ggx_alpha_of_roughness(r);
    return minf(sl_ggx_phong_equivalent(r), SHADE_MAX_ALPHA);
}

/* The table's entry: A, B (splitsum_lut.h) and the lookup direction's factor t. t comes from the
 * W-weighted mean of the sampled directions (the lobe's centroid, in the plane of N and R): the
 * direction normalize(mix(N, R, t)) points at it. Its angle from N, theta_d, against R's,
 * theta_R: tan theta_d = t sin theta_R / (1 - t + t cos theta_R), solved for t; then the shift
 * from R is scaled by r (below). */
static vec3 albedo(sl_splitsum_set set, float NdotV, float r, const sl_hammersley *hs)
{
    float alpha = set_alpha(set, r);
    sl_gterm gterm = set == SL_SPLITSUM_PHONG_ONE ? SL_GTERM_ONE : SL_GTERM_INV_LH2;
    NdotV = maxf(NdotV, SHADE_MIN_NDOTV);
    vec3 V = vec3(sqrtf(maxf(1.0f - NdotV * NdotV, 0.0f)), 0.0f, NdotV);
    float a = 0.0f, b = 0.0f, cx = 0.0f, cz = 0.0f;
    for (int k = 0; k < hs->n; k++) {
        vec3 H = sl_shade_microfacet_sample(hs->points[k], alpha); /* about +Z = N */
        float VdotH = dot(V, H);
        vec3 w = sub(scale(H, 2.0f * VdotH), V);
        float wN = w.z;
        if (VdotH <= 0.0f || wN <= 0.0f)
            continue;
        float W = sl_lobe_G(VdotH, wN, NdotV, alpha, gterm) * wN * VdotH / H.z;
        float m = maxf(1.0f - VdotH, 0.0f);
        float Fc = m * m * m * m * m;
        a += (1.0f - Fc) * W;
        b += Fc * W;
        cx -= W * w.x; /* R is at -x: V = (sin, 0, N.V) */
        cz += W * w.z;
    }
    float t = 1.0f;
    float sinR = V.x, cosR = NdotV;
    if (sinR > 1e-4f && cz > 0.0f) {
        float tan_d = maxf(cx, 0.0f) / cz;
        t = clamp(tan_d / (sinR + tan_d * (1.0f - cosR)), 0.0f, 1.0f);
    }
    /* the shift towards the centroid scaled by r: the whole of it for the widest lobe, where the
     * lobe's mean is what the eye sees, less for the narrower, whose peak stays near R while the
     * tail of the stretched lobe pulls the centroid away. Measured against the ground truth at
     * 480x270 (docs/lighting.md "Split sum"), relative RMS error of ggx.json's r = 0.5 metal and
     * dielectric spheres: 0.47 and 1.77 with the whole shift, 0.38 and 1.58 with r times it, 0.34
     * and 1.46 with r^2 times it; but r^2 lets the default scene's alpha 1 sphere go from 0.14 to
     * 0.15 and test_splitsum's rough lobes from a mean error of 10.8% to 14.4% (6.5% with the
     * whole shift), and leaves ggx.json's nRMSE higher (0.2924 against 0.2900). */
    t = 1.0f - (1.0f - t) * r;
    return vec3(a / (float)hs->n, b / (float)hs->n, t);
}

vec3 sl_splitsum_entry(sl_splitsum_set set, float NdotV, float r, int samples)
{
    sl_hammersley hs;
    sl_error err;
    if (!sl_hammersley_build(&hs, samples, &err))
        return vec3s(0.0f);
    return albedo(set, NdotV, r, &hs);
}

vec2 sl_splitsum_albedo(sl_splitsum_set set, float NdotV, float r, int samples)
{
    vec3 e = sl_splitsum_entry(set, NdotV, r, samples);
    return vec2(e.x, e.y);
}

void sl_splitsum_lut_build(sl_splitsum_lut *lut, int threads)
{
    enum { S = SL_SPLITSUM_LUT_SIZE };
    sl_hammersley hs;
    sl_error err;
    sl_hammersley_build(&hs, SL_SPLITSUM_LUT_SAMPLES, &err); /* a constant within 1 .. SL_HAMMERSLEY_MAX */
#pragma omp parallel for schedule(dynamic) num_threads(sl_threads(threads))
    for (int row = 0; row < SL_SPLITSUM_SETS * S; row++) {
        sl_splitsum_set set = (sl_splitsum_set)(row / S);
        float r = (float)(row % S) / (float)(S - 1);
        for (int i = 0; i < S; i++) {
            lut->texels[row * S + i] = albedo(set, (float)i / (float)(S - 1), r, &hs);
        }
    }
}
