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

/* Two integrals of the kernel mix K about dir over a grid about dir (64 rings out to 90 degrees,
 * where K ends, 64 azimuths of which the 32 on one side of the plane of N and V are summed twice;
 * N = +Z):
 *  - the share of K that no microfacet sample reaches: w = reflect(-V, H) with N.H > 0 and
 *    V.H > 0 needs N.(V + w) > 0, so the directions with N.w <= -N.V are never drawn, and the
 *    samples cannot subtract the kernel's part there;
 *  - the integral of K^2 / p over the rest, p the samples' density of w, D(H) (N.H) / (4 V.H):
 *    beta's denominator. Sampled with a Hammersley set it comes out small where it is large:
 *    near that boundary N.H and with it p go to 0 while K need not, and K / p takes values there
 *    that a thousand samples miss (the Phong set's alpha 20 at N.V 0.6: beta 0.53, and cv keeps
 *    a bias of 4% at N = 1024). */
static void cv_kernel_integrals(const sl_cv_levels *lv, const sl_prefilter_kernel *ka, const sl_prefilter_kernel *kb,
                                vec3 dir, vec3 V, float alpha, double *unreachable, double *kk)
{
    enum { RINGS = 64, AZIMUTHS = 32 }; /* over half a turn: N, V and dir lie in one plane, the
                                          integrands are symmetric about it */
    const double pi = 3.14159265358979323846;
    vec3 a = normalize(cross(vec3(0.0f, 1.0f, 0.0f), dir)), b = cross(dir, a);
    *unreachable = *kk = 0.0;
    for (int i = 0; i < RINGS; i++) {
        double theta = (i + 0.5) * (0.5 * pi / RINGS);
        float c = (float)cos(theta), sn = (float)sin(theta);
        double ring = sin(theta) * (0.5 * pi / RINGS) * (2.0 * pi / AZIMUTHS);
        float K = lv->ca * sl_prefilter_kernel_eval(ka, c) + lv->cb * sl_prefilter_kernel_eval(kb, c);
        if (K <= 0.0f)
            continue;
        for (int j = 0; j < AZIMUTHS; j++) {
            float phi = (float)((j + 0.5) * (pi / AZIMUTHS));
            vec3 w = add(add(scale(a, sn * cosf(phi)), scale(b, sn * sinf(phi))), scale(dir, c));
            vec3 h = add(V, w);
            if (h.z <= 0.0f) {
                *unreachable += (double)K * ring;
                continue;
            }
            h = normalize(h);
            double pdf = (double)sl_lobe_D(h.z, alpha) * (double)h.z / (4.0 * (double)maxf(dot(V, h), 1e-6f));
            *kk += (double)K * (double)K / fmax(pdf, 1e-30) * ring;
        }
    }
}

/* The control variate's coefficient at (N.V, r) (docs/lighting.md "Control variate"): the beta
 * that minimises the variance of (f (N.w) - beta E k(w)) L(w) / p(w) for a radiance L that varies
 * independently from one direction to the next, k the kernel mix the chain read stands for
 * (sl_cv_levels) about the lookup direction normalize(mix(N, R, t)) and E the albedo (F = 1):
 * beta = E_p[W K / p] / (E integral of K^2 / p), in [0, 1] (the first by the samples, the second
 * on a grid: cv_kernel_integrals; E is A + B of the table's `entry`, whose t gives the direction);
 * 0 where no exact level is read, and where more than SL_CV_MAX_UNREACHABLE of the kernel lies where
 * no sample reaches (that part would stay in the closed term as a bias). Checked outside the renderer (GGX r 0.4-1, N.V 0.15-0.95, 24 normals
 * each on studio.hdr, forest.hdr and interior.hdr reduced to 256x128, N = 16, the chain summed
 * exactly, RMS error over 16 rotations of the Hammersley set): with beta = 1 the rough lobes
 * seen from the side (r 0.4, N.V 0.15) carried 2-3 times the error of the samples alone; with
 * this beta at most 1.23 times it, and a hundredth of it where the kernel is the lobe (r 1,
 * N.V 0.95). */
/* beta is 0 where more of the kernel than this lies out of reach (docs/accuracy.md "The control
 * variate with mis's samples", why cvmis keeps it; a build defining another is for that
 * comparison) */
#ifndef SL_CV_MAX_UNREACHABLE
#define SL_CV_MAX_UNREACHABLE 1e-3
#endif
static float cv_beta(const sl_splitsum_lut *lut, sl_splitsum_set set, float NdotV, float r, vec3 entry,
                     const sl_hammersley *hs)
{
    const int max_lod = SL_PREFILTER_LEVELS - 1;
    sl_cv_levels lv = sl_cv_levels_at(r * (float)max_lod, max_lod, sl_prefilter_first_exact(SL_PREFILTER_LEVELS));
    if (lv.ca == 0.0f && lv.cb == 0.0f)
        return 0.0f;
    const sl_prefilter_kernel *ka = &lut->kernels[set][lv.la], *kb = &lut->kernels[set][lv.lb];
    float alpha = set_alpha(set, r);
    sl_gterm gterm = set == SL_SPLITSUM_PHONG_ONE ? SL_GTERM_ONE : SL_GTERM_INV_LH2;
    NdotV = maxf(NdotV, SHADE_MIN_NDOTV);
    vec3 V = vec3(sqrtf(maxf(1.0f - NdotV * NdotV, 0.0f)), 0.0f, NdotV);
    vec3 R = vec3(-V.x, 0.0f, NdotV);
    vec3 dir = normalize(add(scale(vec3(0.0f, 0.0f, 1.0f), 1.0f - entry.z), scale(R, entry.z)));
    double e = (double)entry.x + (double)entry.y; /* E_p[W]: albedo's A + B, over the same samples */
    double wk = 0.0;
    for (int k = 0; k < hs->n; k++) {
        vec3 H = sl_shade_microfacet_sample(hs->points[k], alpha);
        float VdotH = dot(V, H);
        vec3 w = sub(scale(H, 2.0f * VdotH), V);
        if (VdotH <= 0.0f || w.z <= 0.0f)
            continue;
        float W = sl_lobe_G(VdotH, w.z, NdotV, alpha, gterm) * w.z * VdotH / H.z;
        float pdf = sl_lobe_D(H.z, alpha) * H.z / (4.0f * VdotH);
        float c = dot(w, dir);
        float Kp = (lv.ca * sl_prefilter_kernel_eval(ka, c) + lv.cb * sl_prefilter_kernel_eval(kb, c)) / pdf;
        wk += (double)W * (double)Kp;
    }
    double unreachable, kk;
    cv_kernel_integrals(&lv, ka, kb, dir, V, alpha, &unreachable, &kk);
    if (!(e > 0.0 && kk > 0.0) || unreachable > SL_CV_MAX_UNREACHABLE)
        return 0.0f;
    double beta = (wk / hs->n) / (e * kk);
    return (float)(beta < 0.0 ? 0.0 : beta > 1.0 ? 1.0 : beta);
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
    for (int set = 0; set < SL_SPLITSUM_SETS; set++)
        for (int k = 0; k < SL_PREFILTER_LEVELS; k++)
            lut->kernels[set][k] = sl_prefilter_kernel_of(k, SL_PREFILTER_LEVELS, set == SL_SPLITSUM_GGX,
                                                          set == SL_SPLITSUM_PHONG_ONE);
    sl_hammersley hs;
    sl_error err;
    sl_hammersley_build(&hs, SL_SPLITSUM_LUT_SAMPLES, &err); /* a constant within 1 .. SL_HAMMERSLEY_MAX */
#pragma omp parallel for schedule(dynamic) num_threads(sl_threads(threads))
    for (int row = 0; row < SL_SPLITSUM_SETS * S; row++) {
        sl_splitsum_set set = (sl_splitsum_set)(row / S);
        float r = (float)(row % S) / (float)(S - 1);
        for (int i = 0; i < S; i++) {
            float NdotV = (float)i / (float)(S - 1);
            lut->texels[row * S + i] = albedo(set, NdotV, r, &hs);
            lut->beta[row * S + i] = cv_beta(lut, set, NdotV, r, lut->texels[row * S + i], &hs);
        }
    }
}
