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

static vec2 albedo(sl_splitsum_set set, float NdotV, float r, const sl_hammersley *hs)
{
    float alpha = set_alpha(set, r);
    sl_gterm gterm = set == SL_SPLITSUM_PHONG_ONE ? SL_GTERM_ONE : SL_GTERM_INV_LH2;
    NdotV = maxf(NdotV, SHADE_MIN_NDOTV);
    vec3 V = vec3(sqrtf(maxf(1.0f - NdotV * NdotV, 0.0f)), 0.0f, NdotV);
    float a = 0.0f, b = 0.0f;
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
    }
    return vec2(a / (float)hs->n, b / (float)hs->n);
}

vec2 sl_splitsum_albedo(sl_splitsum_set set, float NdotV, float r, int samples)
{
    sl_hammersley hs;
    sl_error err;
    if (!sl_hammersley_build(&hs, samples, &err))
        return vec2(0.0f, 0.0f);
    return albedo(set, NdotV, r, &hs);
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
            vec2 ab = albedo(set, (float)i / (float)(S - 1), r, &hs);
            lut->texels[row * S + i] = vec3(ab.x, ab.y, 0.0f);
        }
    }
}
