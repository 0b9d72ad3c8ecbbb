/* lighting_batched.c - the lighting shader's fast path, the pass's default: main() of
 * shaders/lighting.frag (as ported in lighting.c) reorganised into loops over arrays that GCC
 * vectorizes (`#pragma omp simd`). The port is the reference; this file computes the same
 * formulas in another order and with lighting's fast transcendentals, so its results differ
 * from the port's by float rounding (test_lighting_fast bounds it); it is deterministic, and a
 * trace follows it (docs/lighting.md "Two paths").
 *
 * Per span of a tile row (sl_shade_span): every pixel's V, N and sample frame (pixel_stage; not
 * for a span of background alone), the background of empty pixels (sl_shade_background_span);
 * then per pixel the samples in stages (specular_samples): (0) the skewed samples, from the
 * task's per-alpha table (lighting_task.c) or rotated per pixel; (1) directions w, H, the dot
 * products, G, the Fresnel factor and the lat-long uv; (2) the mip levels; (3) the texture
 * fetches (gathers from the environment's single block, ibl/texture_lod.h) and contributions;
 * (4) the sum. The diffuse term's irradiance for the whole span (ibl sl_irradiance_eval_span,
 * the port's lookup's bits). Then main()'s sum of the terms and its NaN guard, over the span in
 * vector loops in the port's order (sum_stage; the point lights per pixel by the port's own
 * function), or per pixel by the port's own code (sl_shade_surface_color, sl_shade_finish) with
 * a trace.
 *
 * core/fast_math.h's log2, exp2 and atan2 replace libm's powf/log2f/atan2f/acosf: the lod needs
 * only log2(N.H), since log2 D = log2((alpha+2)/2pi) + alpha log2(N.H), and the spec estimator
 * never needs D itself. The microfacet estimator (H about N, w = reflect(-V, H)) has a stage
 * (1) and a spec-rule lod loop of its own, since its samples and weights differ, while the
 * fetch and the sum are the same.
 *
 * GCC vectorizes a loop only if no floating-point operation sits under a branch (its default
 * -ftrapping-math); hence selects between constants multiplied in, and a loop per option
 * where the port has an `if`. */
#include <stdlib.h>
#include <string.h>

/* clang honours `omp simd` too but cannot vectorize every one of these loops (gathers through a
 * computed level); that is a missed optimisation, not an error in a -Werror build. */
#ifdef __clang__
#pragma clang diagnostic ignored "-Wpass-failed"
#endif

#include "../core/fast_math.h"
#include "../ibl/texture_lod.h"
#include "lighting_internal.h"

/* ======================== constants and the sample block ======================== */

/* GLSL constants, as lighting.c has them */
static const int LOD_SPEC = SL_LOD_SPEC;
static const int LOD_SPEC_D4 = SL_LOD_SPEC_D4;
static const int LOD_GEMS = SL_LOD_GEMS;
static const int LOD_PDF = SL_LOD_PDF;
static const int ESTIMATOR_CONSISTENT = SL_ESTIMATOR_CONSISTENT;
static const int ESTIMATOR_SPLITSUM = SL_ESTIMATOR_SPLITSUM;
static const int ESTIMATOR_MIS = SL_ESTIMATOR_MIS;
static const int ESTIMATOR_CV = SL_ESTIMATOR_CV;
static const int ESTIMATOR_CV_MIS = SL_ESTIMATOR_CV_MIS;
static const int ENV_LAYOUT_OCT = SL_ENV_LAYOUT_OCT;
static const float POLE_EPS = SHADE_POLE_EPS;
static const float TINY = SL_BRDF_TINY;
#define PI SL_PI

/* Samples are processed in blocks of BLOCK, so the per-sample arrays live on the stack (5 KB)
 * whatever N is; N = 40 is one block. */
enum { BLOCK = 64 };
_Static_assert(BLOCK % SL_SAMPLE_LANES == 0, "a block's padding stays in the block");

/* One block of samples, structure of arrays: stage (1) writes them, (2) and (3) read them. */
typedef struct {
    float xi1[BLOCK], xi2[BLOCK], Lx[BLOCK], Ly[BLOCK], Lz[BLOCK], pdf[BLOCK]; /* when not from a table */
    float wx[BLOCK], wy[BLOCK], wz[BLOCK], wN[BLOCK];
    float hx[BLOCK], hy[BLOCK], hz[BLOCK], NdotH[BLOCK], LdotH[BLOCK];
    float m5[BLOCK], lod[BLOCK], u[BLOCK], v[BLOCK];
    float weight[BLOCK], cr[BLOCK], cg[BLOCK], cb[BLOCK];
    float vh[BLOCK], pw[BLOCK]; /* microfacet only: V.H and p(w) */
    float lr[BLOCK], lg[BLOCK], lb[BLOCK], kp[BLOCK]; /* cv only: Li, and K(w) / p(w) */
} sample_block;

/* log2(TINY): the floor of every log2 in mip_level */
static const float LOG2_TINY = -99.6578428f;

/* ======================== stage (0): rotated samples ======================== */

/* Stage (0), rotation on: the pixel's pairs fract(xi + rotation) skewed to the lobe, i.e.
 * skewed_sample and sample_pdf of the rotated pair (plus = 1), or microfacet_sample and
 * microfacet_D (plus = 2: the exponents 1/(alpha+2), alpha/(alpha+2), the constant
 * (alpha+2)/(2 pi)). Shifting xi1 shifts the azimuth by -2 pi rotation.x for every sample: one
 * rotation (cr, sr) of each (cos phi, sin phi); the polar part cos(theta) = xi2^(1/(alpha+plus))
 * and the pdf's (or D's) xi2^(alpha/(alpha+plus)) go through log2/exp2, and sin(theta) =
 * sqrt(1 - cos^2). A rotated xi2 of exactly 0 gives cos(theta) = 0 and pdf = 0, as pow(0, e)
 * does. */
static void rotated_lobe(const azimuth_table *az, int k0, int m, float alpha, float plus, vec2 rotation,
                         sample_block *b)
{
    float rho = 2.0f * PI * rotation.x;
    float cr = cosf(rho), sr = sinf(rho);
    float e_cos = 1.0f / (alpha + plus), e_pdf = alpha / (alpha + plus);
    float norm = (alpha + plus) / (2.0f * PI);
    const float *xi1 = az->xi1 + k0, *xi2 = az->xi2 + k0, *cphi = az->cphi + k0, *sphi = az->sphi + k0;
#pragma omp simd
    for (int i = 0; i < m; i++) {
        float s1 = xi1[i] + rotation.x, s2 = xi2[i] + rotation.y;
        float x1 = s1 - sl_fast_floor(s1); /* fract, as the port computes it */
        float x2 = s2 - sl_fast_floor(s2);
        float lx = sl_fast_log2(maxf(x2, TINY)); /* in [log2 TINY, 0]: exp2's range below */
        float zero = x2 > 0.0f ? 1.0f : 0.0f; /* a product, not a select: GCC vectorizes it */
        float ct = sl_fast_exp2(lx * e_cos) * zero;
        float st = sqrtf(maxf(1.0f - ct * ct, 0.0f));
        float cp = cphi[i] * cr + sphi[i] * sr;
        float sp = sphi[i] * cr - cphi[i] * sr;
        b->xi1[i] = x1;
        b->xi2[i] = x2;
        b->Lx[i] = cp * st;
        b->Ly[i] = sp * st;
        b->Lz[i] = ct;
        b->pdf[i] = norm * sl_fast_exp2(lx * e_pdf) * (alpha > 0.0f ? zero : 1.0f); /* pow(0, 0) = 1 */
    }
}

/* Stage (0) for a GGX lobe (alpha < 0), rotation on: rotated_lobe's azimuth, and the polar part
 * of ggx_cos_theta, cos(theta) = sqrt((1 - xi2) / (1 + (a^2 - 1) xi2)); the table value is
 * ggx_D_of_xi (microfacet: D(H)) or that times cos(theta) (sample_pdf: D(w.R) (w.R)). */
static void rotated_lobe_ggx(const azimuth_table *az, int k0, int m, float a2, bool microfacet, vec2 rotation,
                             sample_block *b)
{
    float rho = 2.0f * PI * rotation.x;
    float cr = cosf(rho), sr = sinf(rho);
    const float *xi1 = az->xi1 + k0, *xi2 = az->xi2 + k0, *cphi = az->cphi + k0, *sphi = az->sphi + k0;
    const float pdf_cos = microfacet ? 0.0f : 1.0f; /* a select of a factor, so the loop vectorizes */
#pragma omp simd
    for (int i = 0; i < m; i++) {
        float s1 = xi1[i] + rotation.x, s2 = xi2[i] + rotation.y;
        float x1 = s1 - sl_fast_floor(s1);
        float x2 = s2 - sl_fast_floor(s2);
        float t = (1.0f - x2) + a2 * x2;
        float ct = sqrtf((1.0f - x2) / t);
        float st = sqrtf(maxf(1.0f - ct * ct, 0.0f)); /* as sl_uv_to_dir's sin(acos(c)) rounds */
        float cp = cphi[i] * cr + sphi[i] * sr;
        float sp = sphi[i] * cr - cphi[i] * sr;
        b->xi1[i] = x1;
        b->xi2[i] = x2;
        b->Lx[i] = cp * st;
        b->Ly[i] = sp * st;
        b->Lz[i] = ct;
        b->pdf[i] = t * t / (PI * a2) * (pdf_cos * ct + (1.0f - pdf_cos));
    }
}

/* ======================== per-sample helpers and the trace ======================== */

/* clamp(lod, 0, max_lod) with NaN -> 0 (the fetch indexes with it) */
static inline float clamp_lod(float lod, float max_lod)
{
    lod = lod > 0.0f ? lod : 0.0f;
    return lod < max_lod ? lod : max_lod;
}

/* Stage (3)'s contribution of sample i, c = F Li weight, from its fetched radiance t (Li = t
 * times the intensity): one expression for every fetch (inlined in each loop, which still
 * vectorizes). */
static inline void store_contribution(sample_block *b, int i, vec3 t, vec3 Ks, vec3 F1, float intensity, bool keep_li)
{
    float m5 = b->m5[i], weight = b->weight[i];
    b->cr[i] = (Ks.x + F1.x * m5) * (t.x * intensity) * weight;
    b->cg[i] = (Ks.y + F1.y * m5) * (t.y * intensity) * weight;
    b->cb[i] = (Ks.z + F1.z * m5) * (t.z * intensity) * weight;
    if (keep_li) { /* cv: Li for its subtraction */
        b->lr[i] = t.x * intensity;
        b->lg[i] = t.y * intensity;
        b->lb[i] = t.z * intensity;
    }
}

/* One sample's radiance through texture_lod.h's scalar filter of the samples' layout (the trace,
 * and the fetch when the chain has no block), from the lobe set's chain: the same bits as the
 * gathers. */
static vec3 fetch_clamped(const sl_lighting_uniforms *u, const sl_env *chain, float tu, float tv, float lod)
{
    if (u->uEnvLayout == ENV_LAYOUT_OCT)
        return sl_oct_lod_clamped(chain, tu, tv, lod);
    return sl_texture_lod_clamped(chain, tu, tv, lod);
}

/* Where a block's per-sample values come from: a lobe table, or the block itself. */
typedef struct {
    const float *xi1, *xi2, *Lx, *Ly, *Lz, *pdf;
} lobe_view;

/* The trace of samples k0 .. k0 + m - 1 of a block, as the port records them; the running sum
 * is in sample order (the pass sums in four partial sums) and leaves out the samples across the
 * horizon (h). */
static void trace_block(const sl_lighting_uniforms *u, sl_lighting_trace *t, const sample_block *b, const lobe_view *s,
                        int k0, int m, vec3 Ks, float alpha, vec3 V, float NdotV, bool cv, const shade_horizon *h,
                        vec3 *sum)
{
    const bool mf = shade_microfacet_samples(u, alpha);
    const vec3 F1 = sub(vec3s(1.0f), Ks);
    for (int i = 0; i < m; i++) {
        sl_lighting_trace_sample *ts = &t->samples[k0 + i];
        memset(ts, 0, sizeof *ts);
        ts->xi = vec2(s->xi1[i], s->xi2[i]);
        ts->L = vec3(s->Lx[i], s->Ly[i], s->Lz[i]);
        ts->pdf = s->pdf[i];
        ts->w = vec3(b->wx[i], b->wy[i], b->wz[i]);
        ts->wN = b->wN[i];
        ts->sum = *sum;
        if (mf) { /* as specular_microfacet records them: H, N.H, V.H, D before the test */
            ts->H = vec3(b->hx[i], b->hy[i], b->hz[i]);
            ts->NdotH = b->NdotH[i];
            ts->LdotH = b->LdotH[i];
            ts->D = s->pdf[i];
            ts->pdf = 0.0f;
        }
        ts->hidden = shade_facet_hides(h, ts->w);
        if (((b->wN[i] <= 0.0f || ts->hidden) && !cv) || (mf && b->vh[i] <= 0.0f))
            continue;
        vec3 c = vec3(b->cr[i], b->cg[i], b->cb[i]);
        ts->across = shade_horizon_across(h, ts->w);
        ts->glow = shade_glow_map(h, ts->w) + 1;
        if (!ts->across)
            *sum = add(*sum, c);
        /* the spec path does not form H (stage (1)): normalize(w + V), as the port has it */
        ts->H = mf ? vec3(b->hx[i], b->hy[i], b->hz[i]) : normalize(add(ts->w, V));
        ts->NdotH = b->NdotH[i];
        ts->LdotH = b->LdotH[i];
        ts->pdf = mf ? b->pw[i] : s->pdf[i];
        ts->D = mf ? s->pdf[i] : sl_lobe_D(b->NdotH[i], alpha);
        ts->F = add(Ks, scale(F1, b->m5[i]));
        ts->G = sl_lobe_G(b->LdotH[i], b->wN[i], NdotV, alpha, (sl_gterm)u->uGTerm);
        ts->lod = b->lod[i];
        /* Li is not kept by the pass: fetched again through texture_lod.h (same bits) */
        ts->Li = scale(fetch_clamped(u, shade_samples_chain(u, alpha), b->u[i], b->v[i], b->lod[i]),
                       u->uEnvIntensity);
        ts->c = c;
        ts->cv_kp = cv ? b->kp[i] : 0.0f;
        ts->sum = *sum;
    }
}

/* Stage (0) of the microfacet estimator for a GGX lobe: H drawn from the visible normals
 * (ggx_visible_normal's operations, vectorized) for the stretched view Vh (the pixel's, in the
 * frame A, B, N) and a = sqrt(a^2), with the table's azimuths (cos, sin of 2 pi (0.5 - xi1): the
 * port's own values) rotated as rotated_lobe rotates them when rotation is on (rotate: the pair
 * shifted by `rotation`; off, the shift is 0 and the rotation (1, 0): the same bits). The
 * block's pdf holds D(H), as the table's does. */
static void visible_lobe_ggx(const azimuth_table *az, int k0, int m, float a2, float a, vec3 Vh, bool rotate,
                             vec2 rotation, sample_block *b)
{
    const float shift_x = rotate ? rotation.x : 0.0f, shift_y = rotate ? rotation.y : 0.0f;
    const float rho = 2.0f * PI * shift_x;
    const float cr = rotate ? cosf(rho) : 1.0f, sr = rotate ? sinf(rho) : 0.0f;
    const float vx = Vh.x, vy = Vh.y, vz = Vh.z; /* scalars: a struct read in the loop stops GCC's vectorizer */
    const float *xi1 = az->xi1 + k0, *xi2 = az->xi2 + k0, *cphi = az->cphi + k0, *sphi = az->sphi + k0;
#pragma omp simd
    for (int i = 0; i < m; i++) {
        float s1 = xi1[i] + shift_x, s2 = xi2[i] + shift_y;
        float x1 = s1 - sl_fast_floor(s1); /* fract, as the port computes it */
        float x2 = s2 - sl_fast_floor(s2);
        float cp = cphi[i] * cr + sphi[i] * sr;
        float sp = sphi[i] * cr - cphi[i] * sr;
        float z = (1.0f - x2) * (1.0f + vz) - vz;
        float st = sqrtf(maxf(1.0f - z * z, 0.0f)); /* the port's clamp to [0, 1]: 1 - z^2 <= 1 */
        float hx = a * (st * cp + vx), hy = a * (st * sp + vy), hz = z + vz;
        float ih = 1.0f / maxf(sqrtf((hx * hx + hy * hy) + hz * hz), TINY);
        float Hz = hz * ih;
        b->xi1[i] = x1;
        b->xi2[i] = x2;
        b->Lx[i] = hx * ih;
        b->Ly[i] = hy * ih;
        b->Lz[i] = Hz;
        b->pdf[i] = sl_ggx_D(Hz, a2); /* D(H) */
    }
}

/* ======================== stage (1): directions and weights ======================== */

/* GGX's G' = 4 Vis(w.N, N.V) = 2 / (w.N kv + N.V sqrt((w.N)^2 (1 - a^2) + a^2)), kv the N.V half
 * (ggx_kv, once a pixel; brdf.h's sl_ggx_G over 2 (w.N)(N.V)); for w.N <= 0 a value stage (4)
 * drops. */
__attribute__((always_inline)) static inline float ggx_kv(float NdotV, float a2)
{
    return sqrtf(NdotV * NdotV * (1.0f - a2) + a2);
}
__attribute__((always_inline)) static inline float ggx_g(float wN, float NdotV, float kv, float a2)
{
    return 2.0f / (wN * kv + NdotV * sqrtf(maxf(wN * wN * (1.0f - a2) + a2, TINY)));
}

/* Stage (1) of the spec estimators (specular_ibl's operations, vectorized over the samples):
 * w in the frame A, B, R, the dot products, the Fresnel factor and the weight G (w.N)/4, with
 * the Phong set's G (1 or 1/(L.H)^2) or GGX's G' (ggx: a constant at each call, so the loop is
 * chosen per pixel and a GGX lobe never computes the Phong G nor a Phong one the Smith term).
 *
 * H = (w + V)/|w + V| is never formed: with q = |w + V|^2 and rs = 1/sqrt(q), for unit w and V
 * L.H = |w + V|/2 = q rs/2, N.H = N.(w + V) rs and 1/(L.H)^2 = 4/q = 4 rs^2: one square root and
 * one division a sample where normalising w and H and dividing by (L.H)^2 took two and three
 * (divisions and roots were the loop's costliest operations). q is summed from the components
 * of w + V as normalize(w + V) does: 1 + w.V would cancel at grazing angles (1.2e-5 relative at
 * N.V = 0.05, which alpha = 5000 raises to 3%), and N.H is N's dot product with w + V as the
 * port's is with H (w.N + N.V, the same value, moved the consistent estimator's worst pixel at
 * alpha 5000 from 0.28% to 0.48% of the port's). w is not normalised: the frame A, B, R and the
 * sample L are unit to float rounding, so |w| = 1 within a few ulp (the port normalises; the
 * difference is rounding, inside test_batched_vs_plain's bounds). The trace forms H itself. */
__attribute__((always_inline)) static inline void spec_directions(sample_block *b, int m, const float *Lx,
                                                                  const float *Ly, const float *Lz, vec3 N, vec3 V,
                                                                  vec3 R, vec3 A, vec3 B, bool inv_lh2, bool ggx,
                                                                  float a2)
{
    const float g_min = 1.0f / (SL_BRDF_MIN_LDOTH * SL_BRDF_MIN_LDOTH); /* 1/(L.H)^2 at the clamp */
    const float NdotV = dot(N, V);
    const float kv = ggx ? ggx_kv(NdotV, a2) : 0.0f;
#pragma omp simd
    for (int i = 0; i < m; i++) {
        float wx = (A.x * Lx[i] + B.x * Ly[i]) + R.x * Lz[i];
        float wy = (A.y * Lx[i] + B.y * Ly[i]) + R.y * Lz[i];
        float wz = (A.z * Lx[i] + B.z * Ly[i]) + R.z * Lz[i];
        float hx = wx + V.x, hy = wy + V.y, hz = wz + V.z;
        float q = (hx * hx + hy * hy) + hz * hz;
        float rs = 1.0f / sqrtf(q);
        float wN = (wx * N.x + wy * N.y) + wz * N.z;
        float LdotH = 0.5f * (q * rs);
        float mm = maxf(1.0f - LdotH, 0.0f);
        float m2 = mm * mm;
        b->wx[i] = wx;
        b->wy[i] = wy;
        b->wz[i] = wz;
        b->wN[i] = wN;
        b->NdotH[i] = ((N.x * hx + N.y * hy) + N.z * hz) * rs;
        b->LdotH[i] = LdotH;
        b->m5[i] = m2 * m2 * mm;
        if (ggx) {
            b->weight[i] = ggx_g(wN, NdotV, kv, a2) * wN / 4.0f; /* G' w.N / 4 */
        } else {
            float g = LdotH >= SL_BRDF_MIN_LDOTH ? 4.0f * (rs * rs) : g_min; /* 1/max(L.H, min)^2 */
            b->weight[i] = (inv_lh2 ? g : 1.0f) * wN / 4.0f;                /* G w.N / 4 */
        }
    }
}

/* Stage (1) of specular_microfacet: (L, pdf) are (H about +Z, D(H)) and A, B span the frame
 * about N; w = reflect(-V, H), p(w) = D (N.H) / (4 V.H), and the weight G (w.N)(V.H)/(N.H) with
 * the Phong set's G or GGX's G' (ggx constant at each call, as spec_directions). visible (GGX
 * only, a constant too): H drawn from the visible normals (visible_lobe_ggx), p(w) = D / norm
 * and the weight G' (w.N) norm / 4, norm = 2 (N.V + kv) (ggx_visible_norm). */
__attribute__((always_inline)) static inline void microfacet_directions(sample_block *b, int m, const float *Lx,
                                                                        const float *Ly, const float *Lz,
                                                                        const float *pdf, vec3 N, vec3 V, vec3 A,
                                                                        vec3 B, bool inv_lh2, bool ggx, bool visible,
                                                                        float a2)
{
    const float NdotV = dot(N, V);
    const float kv = ggx ? ggx_kv(NdotV, a2) : 0.0f;
    const float norm = 2.0f * (NdotV + kv);
#pragma omp simd
    for (int i = 0; i < m; i++) {
        float hx = (A.x * Lx[i] + B.x * Ly[i]) + N.x * Lz[i];
        float hy = (A.y * Lx[i] + B.y * Ly[i]) + N.y * Lz[i];
        float hz = (A.z * Lx[i] + B.z * Ly[i]) + N.z * Lz[i];
        float ih = 1.0f / sqrtf((hx * hx + hy * hy) + hz * hz);
        hx *= ih;
        hy *= ih;
        hz *= ih;
        float VdotH = (V.x * hx + V.y * hy) + V.z * hz;
        float wx = hx * (2.0f * VdotH) - V.x;
        float wy = hy * (2.0f * VdotH) - V.y;
        float wz = hz * (2.0f * VdotH) - V.z;
        float iw = 1.0f / sqrtf((wx * wx + wy * wy) + wz * wz);
        wx *= iw;
        wy *= iw;
        wz *= iw;
        float wN = (wx * N.x + wy * N.y) + wz * N.z;
        float NdotH = Lz[i];
        float mm = maxf(1.0f - VdotH, 0.0f);
        float m2 = mm * mm;
        b->wx[i] = wx;
        b->wy[i] = wy;
        b->wz[i] = wz;
        b->wN[i] = wN;
        b->hx[i] = hx;
        b->hy[i] = hy;
        b->hz[i] = hz;
        b->NdotH[i] = NdotH;
        b->LdotH[i] = VdotH;
        b->vh[i] = VdotH;
        b->pw[i] = visible ? pdf[i] / norm : pdf[i] * NdotH / (4.0f * VdotH); /* p(w) */
        b->m5[i] = m2 * m2 * mm;
        if (ggx && visible) {
            b->weight[i] = ggx_g(wN, NdotV, kv, a2) * wN * norm / 4.0f; /* G' (w.N) norm / 4 */
        } else if (ggx) {
            b->weight[i] = ggx_g(wN, NdotV, kv, a2) * wN * VdotH / NdotH; /* G' (w.N)(V.H)/(N.H) */
        } else {
            float LH = maxf(VdotH, SL_BRDF_MIN_LDOTH);
            b->weight[i] = (inv_lh2 ? 1.0f / (LH * LH) : 1.0f) * wN * VdotH / NdotH; /* G (w.N)(V.H)/(N.H) */
        }
    }
}

/* shade_glow over m samples (directions w, contributions c), in place: each lane keeps the
 * nearest map so far (its cosine, cap and visibility, a later map only where strictly nearer, as
 * shade_glow_map), then c times its visibility where w lies in its glow, else times 1 (x * 1 is
 * x: the port's c as it is, bit for bit). Out of line, as horizon_split. */
__attribute__((noinline)) static void glow_scale(const shade_horizon *h, const float *wx, const float *wy,
                                                 const float *wz, float *cr, float *cg, float *cb, int m)
{
    enum { MAPS = SL_SHADOW_SUN_MAX };
    _Static_assert(MAPS == 4, "the unroll below counts the maps");
    /* the maps' glows in locals, those past the count zero and never nearer: the loop over them
     * has a constant count, so that it unrolls inside the vector loop over the samples and the
     * nearest so far stays in registers (in arrays beside a loop over the maps, GCC stores it
     * by masked stores, which some cores issue slowly) */
    float gx[MAPS], gy[MAPS], gz[MAPS], gcap[MAPS], gvis[MAPS];
    int live[MAPS];
    for (int k = 0; k < MAPS; k++) {
        live[k] = k < h->glows;
        gx[k] = live[k] ? h->glow[k].x : 0.0f;
        gy[k] = live[k] ? h->glow[k].y : 0.0f;
        gz[k] = live[k] ? h->glow[k].z : 0.0f;
        gcap[k] = live[k] ? h->glow[k].w : 2.0f;
        gvis[k] = live[k] ? h->glow_vis[k] : 1.0f;
    }
#pragma omp simd
    for (int i = 0; i < m; i++) {
        float nearest = -2.0f, cap = 2.0f, vis = 1.0f;
#pragma GCC unroll 4 /* MAPS: a constant the pragma cannot name */
        for (int k = 0; k < MAPS; k++) {
            const float d = wx[i] * gx[k] + wy[i] * gy[k] + wz[i] * gz[k];
            const bool nearer = live[k] & (d > nearest);
            nearest = nearer ? d : nearest;
            cap = nearer ? gcap[k] : cap;
            vis = nearer ? gvis[k] : vis;
        }
        const float f = nearest >= cap ? vis : 1.0f;
        cr[i] *= f;
        cg[i] *= f;
        cb[i] *= f;
    }
}

/* The samples among m (directions w, contributions c) that lie across the horizon from h's R
 * (shade_horizon_across) to h, and +0 in their place, which leaves every partial sum's bits as
 * they are. Those that add something are counted first in one vector loop, so that a lobe on one
 * side of the horizon (most) skips the rest, and so does a floor's, whose samples across are
 * those below its own horizon, 0 already: moved, they would add 0 to the part and to its
 * direction, which leaves their bits as they are. Out of line, so that the estimators' loops keep
 * their size. */
__attribute__((noinline)) static void horizon_split(shade_horizon *h, const float *wx, const float *wy,
                                                    const float *wz, float *cr, float *cg, float *cb, int m)
{
    const int sky = h->sky;
    int across = 0;
#pragma omp simd reduction(+ : across)
    for (int i = 0; i < m; i++)
        across += ((wz[i] >= 0.0f) != sky) & ((cr[i] != 0.0f) | (cg[i] != 0.0f) | (cb[i] != 0.0f));
    if (across == 0)
        return;
    /* shade_horizon_add's sums, vectorized (its order is the port's, sample by sample; these
     * differ by float rounding) */
    float sr = 0.0f, sg = 0.0f, sb = 0.0f, dx = 0.0f, dy = 0.0f, dz = 0.0f;
#pragma omp simd reduction(+ : sr, sg, sb, dx, dy, dz)
    for (int i = 0; i < m; i++) {
        bool a = (wz[i] >= 0.0f) != sky;
        float r = a ? cr[i] : 0.0f, g = a ? cg[i] : 0.0f, b = a ? cb[i] : 0.0f;
        float l = fabsf(sl_luminance(vec3(r, g, b)));
        sr += r;
        sg += g;
        sb += b;
        dx += wx[i] * l;
        dy += wy[i] * l;
        dz += wz[i] * l;
        cr[i] = a ? 0.0f : cr[i];
        cg[i] = a ? 0.0f : cg[i];
        cb[i] = a ? 0.0f : cb[i];
    }
    h->sum = add(h->sum, vec3(sr, sg, sb));
    h->dir = add(h->dir, vec3(dx, dy, dz));
}

/* ======================== specular_samples and its stages ======================== */

/* What every stage of specular_samples reads for one pixel: the options as flags, the lobe,
 * the lod's constants and the Fresnel terms. Built once a pixel (lobe_consts_for) and passed by
 * pointer into the always-inlined stages, where its fields stay in registers. */
typedef struct {
    bool mf, ggx, inv_lh2, consistent, distortion, oct;
    int rule;
    float alpha, a2;
    float base, max_lod, sin_min, intensity;
    float log2_c_lod; /* log2 of D's constant (alpha + 2)/(2 pi), or a^2/pi; spec-d4 takes D/4 */
    float log2_d4;    /* microfacet: log2 D - log2 4 under spec-d4 */
    vec3 Ks, F1;      /* F = Ks + F1 (1 - L.H)^5 */
    float a;          /* GGX: sqrt(a^2) */
    vec3 Vh;          /* microfacet, GGX: the stretched view in the frame A, B, N (visible_lobe_ggx) */
    const sl_cv_kernel *cvk; /* the control variate's kernel, whose scale K(w) / p(w) Li every
                                contribution loses (NULL: none) */
    const sl_prefilter_kernel *ka, *kb; /* ... its levels' kernels */
    vec3 facet;                         /* the pixel's facet (shade_facet_hides), 0: none */
    const sl_env *chain;                /* what the samples read (the lobe set's: setSampling) */
    const sl_env_gather *gather;        /* ... as a block */
} lobe_consts;

__attribute__((always_inline)) static inline lobe_consts lobe_consts_for(const sl_lighting_uniforms *u, vec3 Ks,
                                                                         float alpha)
{
    lobe_consts c;
    c.mf = shade_microfacet_samples(u, alpha);
    c.ggx = sl_lobe_is_ggx(alpha);
    c.inv_lh2 = u->uGTerm == SL_GTERM_INV_LH2;
    c.consistent = shade_estimator_of(u, alpha) == ESTIMATOR_CONSISTENT;
    c.distortion = shade_distortion_of(u, alpha) != 0;
    c.oct = u->uEnvLayout == ENV_LAYOUT_OCT;
    c.rule = shade_lod_rule_of(u, alpha);
    c.chain = shade_samples_chain(u, alpha);
    c.gather = shade_samples_gather(u, alpha);
    c.alpha = alpha;
    c.a2 = c.ggx ? sl_ggx_a2(alpha) : 0.0f;
    c.base = u->uLodBase;
    c.max_lod = u->uEnvMaxLod;
    c.sin_min = u->uSinThetaMin;
    c.intensity = u->uEnvIntensity;
    c.log2_c_lod = c.ggx ? sl_fast_log2(c.a2 / PI) - (c.rule == LOD_SPEC_D4 ? 2.0f : 0.0f)
                         : sl_fast_log2((alpha + 2.0f) / (2.0f * PI)) - (c.rule == LOD_SPEC_D4 ? 2.0f : 0.0f);
    c.log2_d4 = c.rule == LOD_SPEC_D4 ? 2.0f : 0.0f;
    c.Ks = Ks;
    c.F1 = sub(vec3s(1.0f), Ks);
    c.a = c.ggx ? sqrtf(c.a2) : 0.0f;
    c.Vh = vec3s(0.0f); /* the caller's, with the frame */
    c.cvk = NULL;
    c.ka = c.kb = NULL;
    c.facet = vec3s(0.0f); /* the caller's, with the pixel */
    return c;
}

/* Stage (0): the block's skewed samples, from the task's table, recomputed (no task), or
 * rotated per pixel; a GGX lobe's microfacet samples from the visible normals, per pixel: m
 * samples and their padding to mv (sl_samples_padded), from the tables' padded tails or copied.
 * Returns where they are (the table's arrays or the block's). */
__attribute__((always_inline)) static inline lobe_view stage_samples(const sl_lighting_uniforms *u,
                                                                     const lobe_consts *c, const lobe_table *lobe,
                                                                     const azimuth_table *az, bool rotate,
                                                                     vec2 rotation, int k0, int m, int mv,
                                                                     sample_block *b)
{
    if (c->mf && c->ggx) /* the visible normals: the pixel's own, from V */
        visible_lobe_ggx(az, k0, mv, c->a2, c->a, c->Vh, rotate, rotation, b);
    else if (lobe)
        return (lobe_view){lobe->xi1 + k0, lobe->xi2 + k0, lobe->Lx + k0, lobe->Ly + k0, lobe->Lz + k0,
                           lobe->pdf + k0};
    else if (rotate && c->ggx)
        rotated_lobe_ggx(az, k0, mv, c->a2, c->mf, rotation, b);
    else if (rotate)
        rotated_lobe(az, k0, mv, c->alpha, c->mf ? 2.0f : 1.0f, rotation, b);
    else {
        sl_shade_lobe_fill(u, c->alpha, c->mf, k0, m, b->xi1, b->xi2, b->Lx, b->Ly, b->Lz, b->pdf);
        float *columns[] = {b->xi1, b->xi2, b->Lx, b->Ly, b->Lz, b->pdf};
        sl_shade_pad_samples(columns, 6, m, mv);
    }
    return (lobe_view){b->xi1, b->xi2, b->Lx, b->Ly, b->Lz, b->pdf};
}

/* Stage (1): directions, dot products, G (or GGX's G'), the Fresnel factor, then the texture
 * coordinates of w in the samples' layout: lat-long (the fast atan2s) or octahedral (the port's
 * own divisions and selects: the same bits). One loop per estimator and lobe set, chosen per
 * pixel. A sample with N.H = 0 (a rotated xi2 of 0) divides by 0 here; it has w.N < 0, so
 * stage (4) drops it. */
__attribute__((always_inline)) static inline void stage_directions(const lobe_consts *c, const lobe_view *s, int m,
                                                                   vec3 N, vec3 V, vec3 R, vec3 A, vec3 B,
                                                                   sample_block *b)
{
    if (c->mf && c->ggx)
        microfacet_directions(b, m, s->Lx, s->Ly, s->Lz, s->pdf, N, V, A, B, c->inv_lh2, true, true, c->a2);
    else if (c->mf)
        microfacet_directions(b, m, s->Lx, s->Ly, s->Lz, s->pdf, N, V, A, B, c->inv_lh2, false, false, c->a2);
    else if (c->ggx)
        spec_directions(b, m, s->Lx, s->Ly, s->Lz, N, V, R, A, B, c->inv_lh2, true, c->a2);
    else
        spec_directions(b, m, s->Lx, s->Ly, s->Lz, N, V, R, A, B, c->inv_lh2, false, c->a2);
    if (c->oct) {
#pragma omp simd
        for (int i = 0; i < m; i++)
            sl_oct_dir_to_uv(b->wx[i], b->wy[i], b->wz[i], &b->u[i], &b->v[i]);
    } else {
#pragma omp simd
        for (int i = 0; i < m; i++)
            sl_fast_dir_to_uv(b->wx[i], b->wy[i], b->wz[i], &b->u[i], &b->v[i]);
    }
}

/* Stage (2): mip levels, mip_level in the log domain: log2(max(D d, TINY)) = max(log2 c +
 * alpha log2(max(N.H, TINY)) + log2 d, log2 TINY); one loop per rule. Then the consistent
 * estimator's weight D / pdf, with the port's D (a pow per sample). */
__attribute__((always_inline)) static inline void stage_lod(const lobe_consts *c, const float *pdf, int m,
                                                            sample_block *b)
{
    const int rule = c->rule;
    const float base = c->base, max_lod = c->max_lod, alpha = c->alpha, a2 = c->a2;
    if (c->distortion && c->oct) { /* the octahedral texel's |w|_1^3 / pi */
#pragma omp simd
        for (int i = 0; i < m; i++) {
            float l1 = (fabsf(b->wx[i]) + fabsf(b->wy[i])) + fabsf(b->wz[i]);
            b->lod[i] = sl_fast_log2(l1 * l1 * l1 / PI);
        }
    } else if (c->distortion) {
        const float sin_min = c->sin_min;
#pragma omp simd
        for (int i = 0; i < m; i++)
            b->lod[i] = sl_fast_log2(0.5f * PI * maxf(sqrtf(maxf(1.0f - b->wz[i] * b->wz[i], 0.0f)), sin_min));
    } else {
        memset(b->lod, 0, sizeof(float) * (size_t)m); /* log2 d = 0 */
    }
    if (c->mf && (rule == LOD_SPEC || rule == LOD_SPEC_D4)) { /* D(H) is at hand: log2 of it */
        const float log2_d4 = c->log2_d4;
#pragma omp simd
        for (int i = 0; i < m; i++) {
            float lg = sl_fast_log2(maxf(pdf[i], TINY)) - log2_d4 + b->lod[i];
            b->lod[i] = clamp_lod(base - 0.5f * maxf(lg, LOG2_TINY), max_lod);
        }
    } else if (c->ggx && (rule == LOD_SPEC || rule == LOD_SPEC_D4)) {
        /* log2 D = log2(a^2 / pi) - 2 log2((N.H)^2 (a^2 - 1) + 1) */
        const float log2_c_lod = c->log2_c_lod;
#pragma omp simd
        for (int i = 0; i < m; i++) {
            float nh = b->NdotH[i];
            float c2 = nh * nh;
            float lg = log2_c_lod - 2.0f * sl_fast_log2(maxf(maxf(1.0f - c2, 0.0f) + c2 * a2, TINY)) + b->lod[i];
            b->lod[i] = clamp_lod(base - 0.5f * maxf(lg, LOG2_TINY), max_lod);
        }
    } else if (rule == LOD_SPEC || rule == LOD_SPEC_D4) {
        const float log2_c_lod = c->log2_c_lod;
#pragma omp simd
        for (int i = 0; i < m; i++) {
            float lg = log2_c_lod + alpha * sl_fast_log2(maxf(b->NdotH[i], TINY)) + b->lod[i];
            b->lod[i] = clamp_lod(base - 0.5f * maxf(lg, LOG2_TINY), max_lod);
        }
    } else if (rule == LOD_GEMS || rule == LOD_PDF) {
        const float *pw = c->mf ? b->pw : pdf; /* the density of w */
        const float bias = rule == LOD_GEMS ? 1.0f : 0.0f; /* Gems' +1; pdf has none */
#pragma omp simd
        for (int i = 0; i < m; i++) {
            float lg = sl_fast_log2(maxf(4.0f * PI * pw[i], TINY)) + b->lod[i];
            b->lod[i] = clamp_lod(base - 0.5f * maxf(lg, LOG2_TINY) + bias, max_lod);
        }
    } else {
        memset(b->lod, 0, sizeof(float) * (size_t)m);
    }
    if (c->consistent)
        for (int i = 0; i < m; i++)
            b->weight[i] = b->weight[i] * sl_lobe_D(b->NdotH[i], alpha) / pdf[i];
}

/* The pixel's two levels' kernels for cv_kernel_over_pdf. A level of share 0 takes the other's
 * kernel: it adds 0 (its share multiplies it), and the narrow levels' (not exact) would put 0
 * times an overflow into the one-division form. */
static inline void cv_kernels(const sl_lighting_uniforms *u, const sl_cv_kernel *cv, const sl_prefilter_kernel **ka,
                              const sl_prefilter_kernel **kb)
{
    *ka = &u->uSplitSumLut->kernels[cv->set][cv->levels.ca > 0.0f ? cv->levels.la : cv->levels.lb];
    *kb = &u->uSplitSumLut->kernels[cv->set][cv->levels.cb > 0.0f ? cv->levels.lb : cv->levels.la];
}

/* cv's K(w) / p(w) into kp for the m directions (wx, wy, wz) of densities p, K = ca k_a + cb k_b
 * (ibl.h sl_prefilter_kernel_eval), vectorized, both levels in one loop over one division: GGX's
 * k = d 2c / (t^2 (c + s)), s = sqrt(c^2 (1 - a^2) + a^2), over the common denominator; the Phong
 * set's powers through core/fast_math.h's log2 (one, shared) and exp2, as the lod's. A level of
 * share 0 adds 0 (its share multiplies it). */
__attribute__((always_inline)) static inline void cv_kernel_over_pdf(const float *restrict wx, const float *restrict wy,
                                                                     const float *restrict wz, const float *restrict p,
                                                                     float *restrict kp_out, int m, vec3 dir,
                                                                     const sl_prefilter_kernel *ka,
                                                                     const sl_prefilter_kernel *kb, float ca, float cb)
{
    if (ka->ggx) {
        const float a2a = ka->a2, a2b = kb->a2;
        const float da = 0.5f * ka->inv_norm * ca * a2a / PI, db = 0.5f * kb->inv_norm * cb * a2b / PI;
#pragma omp simd
        for (int i = 0; i < m; i++) {
            float c = wx[i] * dir.x + wy[i] * dir.y + wz[i] * dir.z;
            float cc = maxf(c, 0.0f), nh2 = 0.5f * (1.0f + cc);
            float ta = (1.0f - nh2) + nh2 * a2a, tb = (1.0f - nh2) + nh2 * a2b;
            float ea = ta * ta * (cc + sqrtf(cc * cc * (1.0f - a2a) + a2a));
            float eb = tb * tb * (cc + sqrtf(cc * cc * (1.0f - a2b) + a2b));
            float kp = cc * (da * eb + db * ea) / (ea * eb * p[i]);
            kp_out[i] = c > 0.0f ? kp : 0.0f;
        }
    } else {
        const float ha = 0.5f * ka->alpha, hb = 0.5f * kb->alpha;
        const float da = 0.25f * ka->inv_norm * ca * (ka->alpha + 2.0f) / (2.0f * PI);
        const float db = 0.25f * kb->inv_norm * cb * (kb->alpha + 2.0f) / (2.0f * PI);
        const float inv = ka->g_one ? 0.0f : 1.0f; /* G = 1 / (d.h)^2, or 1 */
#pragma omp simd
        for (int i = 0; i < m; i++) {
            float c = wx[i] * dir.x + wy[i] * dir.y + wz[i] * dir.z;
            float nh2 = maxf(0.5f * (1.0f + c), 0.5f); /* c <= 0 gives 0 below: keep exp2's argument in range */
            float lg = sl_fast_log2(nh2);
            float D = da * sl_fast_exp2(ha * lg) + db * sl_fast_exp2(hb * lg);
            float kp = D * c / ((1.0f + inv * (nh2 - 1.0f)) * p[i]);
            kp_out[i] = c > 0.0f ? kp : 0.0f;
        }
    }
}

/* w.F of sample i, the port's dot(w, h->facet) (shade_facet_hides) in its order */
__attribute__((always_inline)) static inline float facet_dot(const sample_block *b, int i, vec3 F)
{
    return (b->wx[i] * F.x + b->wy[i] * F.y) + b->wz[i] * F.z;
}

/* Stage (3): radiance and contribution: textureLod from the block (texture_lod.h's operations
 * on the block's layout: gathers), c = F Li weight; without a block, the same filter through
 * texture_lod.h, texel by texel. */
__attribute__((always_inline)) static inline void stage_fetch(const sl_lighting_uniforms *u, const lobe_consts *c,
                                                              int m, sample_block *b)
{
    const sl_env_gather *env = c->gather;
    const vec3 Ks = c->Ks, F1 = c->F1;
    const float intensity = c->intensity;
    const bool keep_li = c->cvk != NULL;
    if (c->oct) {
#pragma omp simd
        for (int i = 0; i < m; i++) {
            vec3 t = sl_oct_gather_lod(env, b->u[i], b->v[i], b->lod[i]);
            store_contribution(b, i, t, Ks, F1, intensity, keep_li);
        }
    } else if (env->e5) { /* the compact rows: 4 64-bit reads a sample */
#pragma omp simd
        for (int i = 0; i < m; i++) {
            vec3 t = sl_e5_gather_lod(env, b->u[i], b->v[i], b->lod[i]);
            store_contribution(b, i, t, Ks, F1, intensity, keep_li);
        }
    } else if (env->pairs) { /* the pair rows: 12 64-bit reads a sample instead of 24 32-bit */
#pragma omp simd
        for (int i = 0; i < m; i++) {
            vec3 t = sl_pair_gather_lod(env, b->u[i], b->v[i], b->lod[i]);
            store_contribution(b, i, t, Ks, F1, intensity, keep_li);
        }
    } else {
#pragma omp simd
        for (int i = 0; i < m; i++) {
            vec3 t = sl_env_gather_lod(env, b->u[i], b->v[i], b->lod[i]);
            store_contribution(b, i, t, Ks, F1, intensity, keep_li);
        }
    }
    if (!env->gather) {
        for (int i = 0; i < m; i++) {
            vec3 t = fetch_clamped(u, c->chain, b->u[i], b->v[i], b->lod[i]);
            store_contribution(b, i, t, Ks, F1, intensity, keep_li);
        }
    }
    if (c->cvk) { /* F Li weight - scale K(w) / p(w) Li, the port's form: a loop of its own, so mf's
                    loops above stay as they are */
        const sl_cv_kernel *cv = c->cvk;
        const vec3 dir = cv->dir, sc = cv->scale, F = c->facet;
        cv_kernel_over_pdf(b->wx, b->wy, b->wz, b->pw, b->kp, m, dir, c->ka, c->kb, cv->levels.ca, cv->levels.cb);
#pragma omp simd
        for (int i = 0; i < m; i++) { /* below the horizon (or under the facet) only the kernel's term */
            float kp = b->kp[i];
            bool above = b->wN[i] > 0.0f && !(facet_dot(b, i, F) < 0.0f);
            b->cr[i] = (above ? b->cr[i] : 0.0f) - sc.x * b->lr[i] * kp;
            b->cg[i] = (above ? b->cg[i] : 0.0f) - sc.y * b->lg[i] * kp;
            b->cb[i] = (above ? b->cb[i] : 0.0f) - sc.z * b->lb[i] * kp;
        }
    }
}

/* Stage (4), its first half: the horizon test over the mv samples of the block, m of them
 * real. Samples below the horizon or under the facet (microfacet: or with V.H <= 0) add
 * nothing: their contributions become +0, and so do the padding's (m .. mv, a multiple of 4),
 * which leaves every partial sum's bits as they are (a sum starts at +0 and is never -0).
 * Returns how many of the m were below. */
__attribute__((always_inline)) static inline int stage_horizon(const lobe_consts *c, int m, int mv, sample_block *b)
{
    int below_block = 0;
    const float *drop = c->mf ? b->vh : b->wN;
    const int keep_below = c->cvk != NULL; /* cv's samples below the horizon keep the kernel's term */
    const vec3 F = c->facet;
#pragma omp simd
    for (int i = 0; i < mv; i++) {
        int real = i < m;
        int above = !(b->wN[i] <= 0.0f) & !(drop[i] <= 0.0f) & !(facet_dot(b, i, F) < 0.0f);
        int keep = real & (above | (keep_below & !(drop[i] <= 0.0f)));
        below_block += real & (1 - above);
        b->cr[i] = keep ? b->cr[i] : 0.0f; /* the trace reads only the samples kept */
        b->cg[i] = keep ? b->cg[i] : 0.0f;
        b->cb[i] = keep ? b->cb[i] : 0.0f;
    }
    return below_block;
}

/* specular_ibl (or specular_microfacet, uEstimator = 3, with cv's kernel subtracted from every
 * sample's contribution when cv is not NULL), batched, for one pixel whose frame (N,
 * V, R and A, B: about R, or about N for the microfacet estimator; environment space) the pixel
 * stage computed: the stages above per block of samples, then stage (4)'s sum. Same samples,
 * same sum order. */
__attribute__((noinline)) /* a call per pixel; inlined, it keeps sl_shade_span from vectorizing */
static vec3 specular_samples(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 R, vec3 A, vec3 B, bool pole,
                             vec3 Ks, float alpha, vec2 rotation, const sl_cv_kernel *cv, shade_horizon *h,
                             sl_lighting_task *task, sl_lighting_trace *trace)
{
    int n = (int)u->uHammersley.N;
    const bool rotate = u->uRotate != 0;
    lobe_consts c = lobe_consts_for(u, Ks, alpha);
    c.facet = h->facet;
    if (cv) {
        c.cvk = cv;
        cv_kernels(u, cv, &c.ka, &c.kb);
    }
    const float NdotV = dot(N, V);
    const bool visible = c.mf && c.ggx; /* drawn per pixel from the azimuths (visible_lobe_ggx) */
    if (visible)
        c.Vh = sl_shade_ggx_stretched_view(vec3(dot(V, A), dot(V, B), NdotV), c.a);
    const lobe_table *lobe = task && !rotate && !visible ? sl_shade_lobe_for(u, task, alpha, c.mf) : NULL;
    azimuth_table local_az; /* 16 KB, filled only without a task (tests, traces) */
    const azimuth_table *az = rotate || visible ? sl_shade_azimuth_for(u, task, &local_az) : NULL;
    sample_block blk;
    sample_block *b = &blk;
    /* stage (4)'s four partial sums per channel, as scalars: as arrays GCC kept them on the
     * stack and reloaded them every four samples (a store-to-load chain, 5-8% of this function) */
    float sx0 = 0.0f, sx1 = 0.0f, sx2 = 0.0f, sx3 = 0.0f, sy0 = 0.0f, sy1 = 0.0f, sy2 = 0.0f, sy3 = 0.0f;
    float sz0 = 0.0f, sz1 = 0.0f, sz2 = 0.0f, sz3 = 0.0f;
    vec3 trace_sum = vec3s(0.0f);
    int below = 0;
    for (int k0 = 0; k0 < n; k0 += BLOCK) {
        const int m = n - k0 < BLOCK ? n - k0 : BLOCK, mv = sl_samples_padded(m);
        const lobe_view s = stage_samples(u, &c, lobe, az, rotate, rotation, k0, m, mv, b);
        stage_directions(&c, &s, mv, N, V, R, A, B, b);
        stage_lod(&c, s.pdf, mv, b);
        stage_fetch(u, &c, mv, b);
        below += stage_horizon(&c, m, mv, b);
        if (h->glows > 0)
            glow_scale(h, b->wx, b->wy, b->wz, b->cr, b->cg, b->cb, m);
        if (trace)
            trace_block(u, trace, b, &s, k0, m, Ks, alpha, V, NdotV, c.cvk != NULL, h, &trace_sum);
        if (h->on)
            horizon_split(h, b->wx, b->wy, b->wz, b->cr, b->cg, b->cb, m);
        /* (4) the sum: sample k goes into partial sum k mod 4 and the four are added at the end,
         * (0 + 1) + (2 + 3): four short dependency chains instead of one long one (the port adds
         * in sample order; the difference is float rounding). The same order whatever the
         * vectorization, so the pass, sl_lighting_shade and the trace agree bit for bit. Four
         * samples at a time into the four sums (BLOCK is a multiple of 4, so sample k0 + i goes
         * into sum i mod 4). */
        for (int i = 0; i < m; i += 4) {
            sx0 += b->cr[i];
            sx1 += b->cr[i + 1];
            sx2 += b->cr[i + 2];
            sx3 += b->cr[i + 3];
            sy0 += b->cg[i];
            sy1 += b->cg[i + 1];
            sy2 += b->cg[i + 2];
            sy3 += b->cg[i + 3];
            sz0 += b->cb[i];
            sz1 += b->cb[i + 1];
            sz2 += b->cb[i + 2];
            sz3 += b->cb[i + 3];
        }
    }
    vec3 sum = vec3((sx0 + sx1) + (sx2 + sx3), (sy0 + sy1) + (sy2 + sy3), (sz0 + sz1) + (sz2 + sz3));
    count_samples(task, n, below, pole);
    h->sum = scale(h->sum, 1.0f / (float)(n > 1 ? n : 1));
    return scale(sum, 1.0f / (float)(n > 1 ? n : 1));
}

/* ======================== MIS ======================== */

/* The trace of one MIS pair's samples, as specular_mis records them (the values the loops
 * computed; G recomputed by brdf.h for the record only). */
static void trace_mis_pair(sl_lighting_trace *t, int k, const sample_block *b, int i, const float *D, const float *pe,
                           const float *mis_b, const float *Lr, const float *Lg, const float *Lb, vec3 cb,
                           const env_sample_table *e, int ke, vec3 ce, float De, float pbe, float mis_e, vec3 Ks,
                           float alpha, sl_gterm gterm, vec3 N, vec3 V, const shade_horizon *h, vec3 *sum)
{
    const float NdotV = dot(N, V);
    vec3 w = vec3(b->wx[i], b->wy[i], b->wz[i]), H = vec3(b->hx[i], b->hy[i], b->hz[i]);
    vec2 xi = vec2(b->xi1[i], b->xi2[i]);
    const bool hidden = shade_facet_hides(h, w);
    if (b->vh[i] > 0.0f && b->wN[i] > 0.0f && !hidden) {
        bool across = shade_horizon_across(h, w);
        if (!across)
            *sum = add(*sum, cb);
        trace_sample(t, k, &(sl_lighting_trace_sample){
            .xi = xi, .L = vec3(b->Lx[i], b->Ly[i], b->Lz[i]), .pdf = b->pw[i], .pdf_other = pe[i], .mis = mis_b[i],
            .w = w, .wN = b->wN[i], .H = H, .NdotH = b->NdotH[i], .LdotH = b->vh[i], .D = D[i],
            .F = sl_brdf_F(Ks, b->vh[i]), .G = sl_lobe_G(b->vh[i], b->wN[i], NdotV, alpha, gterm),
            .Li = vec3(Lr[i], Lg[i], Lb[i]), .c = cb, .across = across, .glow = shade_glow_map(h, w) + 1,
            .sum = *sum});
    } else {
        trace_sample(t, k, &(sl_lighting_trace_sample){.xi = xi, .L = vec3(b->Lx[i], b->Ly[i], b->Lz[i]), .w = w,
                                                          .wN = b->wN[i], .H = H, .NdotH = b->NdotH[i],
                                                          .LdotH = b->vh[i], .D = D[i], .hidden = hidden,
                                                          .sum = *sum});
    }
    vec3 we = vec3(e->wx[ke], e->wy[ke], e->wz[ke]);
    vec3 He = normalize(add(we, V));
    float weN = dot(we, N), NdotHe = dot(N, He), LdotHe = dot(we, He);
    sl_lighting_trace_sample s = {.xi = vec2(e->xe1[ke], e->xe2[ke]), .pdf = e->pe[ke], .w = we, .wN = weN, .H = He,
                                  .NdotH = NdotHe, .LdotH = LdotHe, .hidden = shade_facet_hides(h, we)};
    if (weN > 0.0f && NdotHe > 0.0f && LdotHe > 0.0f && !s.hidden) {
        s.across = shade_horizon_across(h, we);
        s.glow = shade_glow_map(h, we) + 1;
        if (!s.across)
            *sum = add(*sum, ce);
        s.pdf_other = pbe;
        s.mis = mis_e;
        s.D = De;
        s.F = sl_brdf_F(Ks, LdotHe);
        s.G = sl_lobe_G(LdotHe, weN, NdotV, alpha, gterm);
        s.Li = vec3(e->lr[ke], e->lg[ke], e->lb[ke]);
        s.c = ce;
    }
    s.sum = *sum;
    trace_env_sample(t, k, &s);
}

/* A light direction w = (x, y, z) in the pixel's frame: w.N, and N.H and w.H of the half vector
 * H = normalize(w + V) (its length floored at TINY: w = -V gives H = 0, not a NaN), as the env
 * lights and mis's environment samples evaluate the BRDF at a given direction. */
__attribute__((always_inline)) static inline void toward_light(float x, float y, float z, vec3 N, vec3 V, float *wN,
                                                              float *NdotH, float *LdotH)
{
    *wN = (x * N.x + y * N.y) + z * N.z;
    float hx = x + V.x, hy = y + V.y, hz = z + V.z;
    float ih = 1.0f / sqrtf(maxf((hx * hx + hy * hy) + hz * hz, TINY));
    hx *= ih;
    hy *= ih;
    hz *= ih;
    *NdotH = (N.x * hx + N.y * hy) + N.z * hz;
    *LdotH = (x * hx + y * hy) + z * hz;
}

/* A Phong lobe's D at a given direction, D = (alpha + 2)/(2 pi) (N.H)^alpha, through the fast
 * log2/exp2 (the env lights and mis's environment samples): sl_fast_exp2 needs its argument in
 * [-126, 127], and log2_c + alpha log2(N.H) >= -120 when N.H >= 2^((-120 - log2_c)/alpha).
 * Clamping N.H at that floor, not the sum, keeps the loops vectorizable (GCC gives up on a max of
 * the exp2's argument); below the floor D < 2^-120 anyway. */
typedef struct {
    float log2_c, alpha, nh_floor;
} phong_fast_D;

static inline phong_fast_D phong_fast_D_for(float alpha)
{
    phong_fast_D p = {sl_fast_log2((alpha + 2.0f) / (2.0f * PI)), alpha, TINY};
    if (alpha > 0.0f)
        p.nh_floor = maxf(sl_fast_exp2(maxf((-120.0f - p.log2_c) / alpha, -126.0f)), TINY);
    return p;
}

__attribute__((always_inline)) static inline float phong_fast_D_at(const phong_fast_D *p, float NdotH)
{
    return sl_fast_exp2(p->log2_c + p->alpha * sl_fast_log2(maxf(NdotH, p->nh_floor)));
}

/* The lobe of a pixel as env_pair_terms reads it (mis_samples' constants). */
typedef struct {
    vec3 N, V, Ks, F1;
    vec3 facet; /* shade_facet_hides' (0: none) */
    float NdotV, a2, kv;
    phong_fast_D phong; /* the Phong set's D (unread for GGX) */
    bool inv_lh2;
} env_pair_lobe;

/* The environment's samples of a block of pairs (specular_mis's second half, vectorized over the
 * pairs): the BRDF at each direction (D, G, F), the BRDF's density there, the power heuristic's
 * weight and the contribution. Inlined with `ggx` a constant, once per lobe set, so that a pixel
 * computes its own set's D and G only, not both sets' (Phong's D is a log2 and an exp2 a sample)
 * and a select. */
__attribute__((always_inline)) static inline void env_pair_terms(const env_pair_lobe *l, const bool ggx,
                                                                 const float *X, const float *Y, const float *Z,
                                                                 const float *P, const float *ER, const float *EG,
                                                                 const float *EB, int mp, float *lit_e, float *De,
                                                                 float *pbe, float *mis_e, float *cr, float *cg,
                                                                 float *cb)
{
    const vec3 N = l->N, V = l->V, Ks = l->Ks, F1 = l->F1, Fc = l->facet;
    const float NdotV = l->NdotV, a2 = l->a2, kv = l->kv;
#pragma omp simd
    for (int i = 0; i < mp; i++) {
        float wN, NdotH, LdotH;
        toward_light(X[i], Y[i], Z[i], N, V, &wN, &NdotH, &LdotH);
        float shown = (X[i] * Fc.x + Y[i] * Fc.y) + Z[i] * Fc.z < 0.0f ? 0.0f : 1.0f; /* not under the facet */
        float Dv, G;
        if (ggx) {
            Dv = sl_ggx_D(NdotH, a2);
            G = ggx_g(maxf(wN, 0.0f), NdotV, kv, a2);
        } else {
            Dv = phong_fast_D_at(&l->phong, NdotH);
            float LH = maxf(LdotH, SL_BRDF_MIN_LDOTH);
            G = l->inv_lh2 ? 1.0f / (LH * LH) : 1.0f;
        }
        float mm = maxf(1.0f - LdotH, 0.0f);
        float m2 = mm * mm;
        float m5 = m2 * m2 * mm;
        /* products of selects, not &&, and every factor finite when it is 0: vectorizes */
        float reached = (NdotH > 0.0f ? 1.0f : 0.0f) * (LdotH > 0.0f ? 1.0f : 0.0f); /* by the BRDF's draws */
        float lit = (wN > 0.0f ? 1.0f : 0.0f) * reached * shown;
        float pb = Dv * NdotH / (4.0f * maxf(LdotH, TINY)) * reached;
        float r = pb / maxf(P[i], TINY);
        float mis = 1.0f / (1.0f + r * r);
        float k = Dv * G * wN / (4.0f * P[i]) * mis * lit;
        lit_e[i] = lit;
        De[i] = Dv;
        pbe[i] = pb;
        mis_e[i] = mis;
        cr[i] = (Ks.x + F1.x * m5) * ER[i] * k;
        cg[i] = (Ks.y + F1.y * m5) * EG[i] * k;
        cb[i] = (Ks.z + F1.z * m5) * EB[i] * k;
    }
}

/* specular_mis, batched, for one pixel (rotation off; with rotation on every pixel draws its own
 * pairs, and the port's loop runs). Per block of pairs: the BRDF's samples from the per-alpha
 * microfacet table through microfacet_directions (the microfacet estimator's stage (1)); their
 * level-0 texel through the fast lat-long map (vectorized), then the environment's radiance and
 * density there, one packed read a sample, prefetched and read after the environment's samples
 * are computed; their weights and contributions vectorized. The environment's samples come from
 * the task's table (the same directions in every pixel): their BRDF, the BRDF's density and the
 * weights vectorized (env_pair_terms), as env_lights_samples evaluates a light (D through the
 * fast log2/exp2 for Phong). Both halves run with the lobe set a constant, a loop per set. The
 * sum: per block, the BRDF's samples then the environment's, in sample order (the port
 * alternates; the difference is float rounding). cv (cvmis_samples; NULL for mis): each sample's
 * kernel term, scale K(w) Li / p(w) times its weight, subtracted in a loop of its own
 * (cv_kernel_over_pdf for both strategies' directions), the BRDF's samples below the horizon read
 * for it (cvmis_samples runs the port's specular_cv, with mis, where this one would run the
 * port's loop, and for a traced pixel, whose trace then has the kernel's terms: cv is never given
 * without a task). */
static vec3 mis_samples(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation,
                        const sl_cv_kernel *cv, shade_horizon *h, sl_lighting_task *task, sl_lighting_trace *trace)
{
    if (u->uRotate != 0)
        return sl_shade_specular_mis(u, N, V, Ks, alpha, rotation, h, task, trace);
    const int n = (int)u->uHammersley.N;
    const float NdotV = dot(N, V);
    vec3 axis = (N.x * N.x + N.y * N.y < POLE_EPS) ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 0.0f, 1.0f);
    vec3 A = normalize(cross(axis, N));
    vec3 B = normalize(cross(N, A));
    trace_sample_frame(trace, N, V, A, B, axis.x == 1.0f, n, true);
    trace_mis(trace);
    const lobe_table *lobe = task ? sl_shade_lobe_for(u, task, alpha, true) : NULL;
    env_sample_table *local = NULL;
    if (!task) { /* tests and traces: the table on the heap, 36 KB */
        local = malloc(sizeof *local);
        if (!local)
            return sl_shade_specular_mis(u, N, V, Ks, alpha, rotation, h, task, trace);
    }
    const env_sample_table *e = sl_shade_env_samples_for(u, task, local);
    const bool ggx = sl_lobe_is_ggx(alpha);
    const bool inv_lh2 = u->uGTerm == SL_GTERM_INV_LH2;
    const float a2 = ggx ? sl_ggx_a2(alpha) : 0.0f;
    const float kv = ggx ? ggx_kv(NdotV, a2) : 0.0f;
    const float I = u->uEnvIntensity;
    const vec3 F1 = sub(vec3s(1.0f), Ks);
    const env_pair_lobe pair = {N,  V,  Ks, F1, h->facet, NdotV, a2, kv,
                                ggx ? (phong_fast_D){0.0f, 0.0f, TINY} : phong_fast_D_for(alpha), inv_lh2};
    const vec3 F = h->facet;
    const float *packed = u->uEnvDist->texel_pdf;
    const int w0 = u->uEnvResidual->levels[0].width, h0 = u->uEnvResidual->levels[0].height;
    const sl_prefilter_kernel *ka = NULL, *kb = NULL;
    if (cv)
        cv_kernels(u, cv, &ka, &kb);
    sample_block blk;
    sample_block *b = &blk;
    float pe[BLOCK], mis_b[BLOCK], Lr[BLOCK], Lg[BLOCK], Lb[BLOCK];
    float cr[2 * BLOCK], cg[2 * BLOCK], cb[2 * BLOCK], De[BLOCK], pbe[BLOCK], mis_e[BLOCK];
    float sr = 0.0f, sg = 0.0f, sb = 0.0f;
    vec3 trace_sum = vec3s(0.0f);
    int below = 0;
    for (int k0 = 0; k0 < n; k0 += BLOCK) {
        const int m = n - k0 < BLOCK ? n - k0 : BLOCK;
        /* the loops run over whole vectors of 16: the pairs past m are H = N with D = 1, made
         * invalid below (V.H = 0), and the table's environment samples past n add 0 (their
         * radiance is 0); so a small N is not left to the scalar remainder loops */
        const int mp = (m + 15) & ~15;
        if (lobe) {
            for (int i = 0; i < m; i++) {
                b->xi1[i] = lobe->xi1[k0 + i];
                b->xi2[i] = lobe->xi2[k0 + i];
                b->Lx[i] = lobe->Lx[k0 + i];
                b->Ly[i] = lobe->Ly[k0 + i];
                b->Lz[i] = lobe->Lz[k0 + i];
                b->pdf[i] = lobe->pdf[k0 + i];
            }
        } else {
            sl_shade_lobe_fill(u, alpha, true, k0, m, b->xi1, b->xi2, b->Lx, b->Ly, b->Lz, b->pdf);
        }
        for (int i = m; i < mp; i++) {
            b->Lx[i] = b->Ly[i] = 0.0f;
            b->Lz[i] = b->pdf[i] = 1.0f;
        }
        const float *D = b->pdf;
        if (ggx) /* ggx a constant at each call, as stage_directions has it */
            microfacet_directions(b, mp, b->Lx, b->Ly, b->Lz, D, N, V, A, B, inv_lh2, true, false, a2);
        else
            microfacet_directions(b, mp, b->Lx, b->Ly, b->Lz, D, N, V, A, B, inv_lh2, false, false, a2);
        for (int i = m; i < mp; i++)
            b->vh[i] = 0.0f;
        /* the BRDF's samples: texel, density and radiance, one at a time (one read of the
         * distribution's packed texels where it has them) */
        /* env_texel through the fast lat-long map (vectorized); a direction within rounding of a
         * texel's edge may read its neighbour, where the port reads it */
        int tx[BLOCK], ty[BLOCK];
#pragma omp simd
        for (int i = 0; i < mp; i++) {
            float tu, tv;
            sl_fast_dir_to_uv(b->wx[i], b->wy[i], b->wz[i], &tu, &tv);
            int x = (int)(tu * (float)w0), y = (int)(tv * (float)h0);
            tx[i] = x < w0 - 1 ? x : w0 - 1;
            ty[i] = y < h0 - 1 ? y : h0 - 1;
        }
        /* the BRDF's texels asked for now and read after the environment's samples, whose
         * arithmetic runs while they come in from memory (a random read of the 8 MB array is
         * the BRDF sample's largest cost; the sums below keep their order) */
        if (packed)
            for (int i = 0; i < mp; i++)
                __builtin_prefetch(packed + 4 * ((size_t)ty[i] * (size_t)w0 + (size_t)tx[i]));
        /* the environment's samples of the same pairs */
        const float *X = e->wx + k0, *Y = e->wy + k0, *Z = e->wz + k0, *P = e->pe + k0;
        const float *ER = e->lr + k0, *EG = e->lg + k0, *EB = e->lb + k0;
        float lit_e[BLOCK];
        if (ggx) /* a loop per lobe set: each computes its own D and G only */
            env_pair_terms(&pair, true, X, Y, Z, P, ER, EG, EB, mp, lit_e, De, pbe, mis_e, cr + BLOCK, cg + BLOCK,
                           cb + BLOCK);
        else
            env_pair_terms(&pair, false, X, Y, Z, P, ER, EG, EB, mp, lit_e, De, pbe, mis_e, cr + BLOCK, cg + BLOCK,
                           cb + BLOCK);
        if (cv) {
            const vec3 sc = cv->scale;
            float kpe[BLOCK];
            cv_kernel_over_pdf(X, Y, Z, P, kpe, mp, cv->dir, ka, kb, cv->levels.ca, cv->levels.cb);
#pragma omp simd
            for (int i = 0; i < mp; i++) {
                float kw = P[i] > 0.0f ? kpe[i] * mis_e[i] : 0.0f; /* past n: no sample */
                cr[BLOCK + i] -= sc.x * ER[i] * kw;
                cg[BLOCK + i] -= sc.y * EG[i] * kw;
                cb[BLOCK + i] -= sc.z * EB[i] * kw;
            }
        }
        /* the reads apart from the index arithmetic, so that their cache misses overlap */
        for (int i = 0; i < mp; i++) {
            bool valid = b->vh[i] > 0.0f && b->wN[i] > 0.0f && !(facet_dot(b, i, F) < 0.0f);
            below += !valid && i < m;
            ivec2 t = ivec2(tx[i], ty[i]);
            pe[i] = 0.0f;
            Lr[i] = Lg[i] = Lb[i] = 0.0f;
            if (!valid && !(cv && b->vh[i] > 0.0f)) /* cv: below the horizon too, for the kernel */
                continue;
            vec3 L;
            if (packed) {
                const float *p = packed + 4 * ((size_t)t.y * (size_t)w0 + (size_t)t.x);
                L = vec3(p[0], p[1], p[2]);
                pe[i] = p[3];
            } else {
                L = sl_shade_env_texel_fetch(u, t);
                pe[i] = sl_shade_env_dist_pdf(u, t);
            }
            Lr[i] = L.x * I;
            Lg[i] = L.y * I;
            Lb[i] = L.z * I;
        }
#pragma omp simd
        for (int i = 0; i < mp; i++) {
            float r = pe[i] / maxf(b->pw[i], TINY);
            float mis = 1.0f / (1.0f + r * r);
            bool valid = b->vh[i] > 0.0f && b->wN[i] > 0.0f && !(facet_dot(b, i, F) < 0.0f);
            float k = valid ? b->weight[i] * mis : 0.0f;
            mis_b[i] = mis;
            cr[i] = (Ks.x + F1.x * b->m5[i]) * Lr[i] * k;
            cg[i] = (Ks.y + F1.y * b->m5[i]) * Lg[i] * k;
            cb[i] = (Ks.z + F1.z * b->m5[i]) * Lb[i] * k;
        }
        if (cv) {
            const vec3 sc = cv->scale;
            cv_kernel_over_pdf(b->wx, b->wy, b->wz, b->pw, b->kp, mp, cv->dir, ka, kb, cv->levels.ca, cv->levels.cb);
#pragma omp simd
            for (int i = 0; i < mp; i++) {
                float kw = b->vh[i] > 0.0f ? b->kp[i] * mis_b[i] : 0.0f; /* V.H <= 0: not drawn */
                cr[i] -= sc.x * Lr[i] * kw;
                cg[i] -= sc.y * Lg[i] * kw;
                cb[i] -= sc.z * Lb[i] * kw;
            }
        }
        for (int i = 0; i < m; i++)
            below += lit_e[i] == 0.0f;
        if (h->glows > 0) { /* the BRDF's samples, then the environment's */
            glow_scale(h, b->wx, b->wy, b->wz, cr, cg, cb, m);
            glow_scale(h, X, Y, Z, cr + BLOCK, cg + BLOCK, cb + BLOCK, m);
        }
        if (trace)
            for (int i = 0; i < m; i++)
                trace_mis_pair(trace, k0 + i, b, i, D, pe, mis_b, Lr, Lg, Lb, vec3(cr[i], cg[i], cb[i]), e, k0 + i,
                               vec3(cr[BLOCK + i], cg[BLOCK + i], cb[BLOCK + i]), De[i], pbe[i], mis_e[i], Ks, alpha,
                               (sl_gterm)u->uGTerm, N, V, h, &trace_sum);
        if (h->on) { /* the BRDF's samples, then the environment's: the sum's order */
            horizon_split(h, b->wx, b->wy, b->wz, cr, cg, cb, m);
            horizon_split(h, X, Y, Z, cr + BLOCK, cg + BLOCK, cb + BLOCK, m);
        }
        for (int i = 0; i < m; i++) {
            sr += cr[i];
            sg += cg[i];
            sb += cb[i];
        }
        for (int i = 0; i < m; i++) {
            sr += cr[BLOCK + i];
            sg += cg[BLOCK + i];
            sb += cb[BLOCK + i];
        }
    }
    free(local);
    count_samples(task, 2 * n, below, axis.x == 1.0f);
    h->sum = scale(h->sum, 1.0f / (float)(n > 1 ? n : 1));
    return scale(vec3(sr, sg, sb), 1.0f / (float)(n > 1 ? n : 1));
}

/* ======================== env lights ======================== */

/* A pixel's lobe constants as specular_env_lights' kernel reads them, formed once per pixel (N and
 * V travel beside them). */
typedef struct {
    bool ggx, inv_lh2;
    float a2, NdotV, kv; /* GGX */
    phong_fast_D phong;  /* Phong */
} env_lobe;

static env_lobe env_lobe_for(const sl_lighting_uniforms *u, vec3 N, vec3 V, float alpha)
{
    env_lobe l = {.ggx = sl_lobe_is_ggx(alpha), .inv_lh2 = u->uGTerm == SL_GTERM_INV_LH2};
    if (l.ggx) {
        l.a2 = sl_ggx_a2(alpha);
        l.NdotV = dot(N, V);
        l.kv = sqrtf(l.NdotV * l.NdotV * (1.0f - l.a2) + l.a2);
    } else {
        l.phong = phong_fast_D_for(alpha);
    }
    return l;
}

/* specular_env_lights' kernel at unit directions (X, Y, Z)[0 .. n), vectorized: k = D G' / 4
 * (w.N), 0 below the horizon and for facets facing away, and m5 = (1 - L.H)^5, so that a
 * direction's term is (Ks + (1 - Ks) m5) k times its radiance. GGX: brdf.h's D and G' = 4 Vis;
 * Phong: D through the fast log2/exp2 as the lod does. The lights and the split lights' cells
 * (env_lights_split) share it. */
static void env_kernel(const env_lobe *l, vec3 N, vec3 V, const float *X, const float *Y, const float *Z, int n,
                       float *k, float *m5)
{
    if (l->ggx) {
        const float a2 = l->a2, NdotV = l->NdotV, kv = l->kv;
#pragma omp simd
        for (int j = 0; j < n; j++) {
            float wN, NdotH, LdotH;
            toward_light(X[j], Y[j], Z[j], N, V, &wN, &NdotH, &LdotH);
            float D = sl_ggx_D(NdotH, a2);
            float wl = maxf(wN, 0.0f);
            float G = 2.0f / maxf(wl * kv + NdotV * sqrtf(wl * wl * (1.0f - a2) + a2), TINY);
            float mm = maxf(1.0f - LdotH, 0.0f);
            float m2 = mm * mm;
            m5[j] = m2 * m2 * mm;
            float lit = (wN > 0.0f ? 1.0f : 0.0f) * (NdotH > 0.0f ? 1.0f : 0.0f);
            k[j] = D * G / 4.0f * wN * lit;
        }
        return;
    }
    const float g_on = l->inv_lh2 ? 1.0f : 0.0f; /* a float: a bool read from *l stops GCC vectorizing */
    const phong_fast_D phong = l->phong;
#pragma omp simd
    for (int j = 0; j < n; j++) {
        float wN, NdotH, LdotH;
        toward_light(X[j], Y[j], Z[j], N, V, &wN, &NdotH, &LdotH);
        float D = phong_fast_D_at(&phong, NdotH);
        float LH = maxf(LdotH, SL_BRDF_MIN_LDOTH);
        float mm = maxf(1.0f - LdotH, 0.0f);
        float m2 = mm * mm;
        m5[j] = m2 * m2 * mm;
        float lit = (wN > 0.0f ? 1.0f : 0.0f) * (NdotH > 0.0f ? 1.0f : 0.0f); /* products, not &&: vectorizes */
        float g = 1.0f / (LH * LH); /* computed, then selected: a division under a branch stops GCC */
        k[j] = D * (g_on != 0.0f ? g : 1.0f) / 4.0f * wN * lit;
    }
}

/* The split lights' cells of one pixel, gathered so that one kernel pass covers them all: a
 * light's texel is split into at most SL_TEXEL_SPLIT_MAX^2 cells, and a batch holds four such. */
#define CELL_BATCH (4 * SL_TEXEL_SPLIT_MAX * SL_TEXEL_SPLIT_MAX)

typedef struct {
    float X[CELL_BATCH], Y[CELL_BATCH], Z[CELL_BATCH], k[CELL_BATCH], m5[CELL_BATCH];
    int count, cells;                                        /* lights, cells held */
    int light[SL_ENV_LIGHTS_MAX], first[SL_ENV_LIGHTS_MAX + 1]; /* each one's index, first cell */
} cell_batch;

/* env_light_cells' directions for light j, rows x cols, appended: formed row by row, each
 * column's azimuth once. */
static void cells_add(cell_batch *c, const sl_lighting_uniforms *u, int j, int rows, int cols)
{
    const vec4 box = u->uEnvLightTexel[j];
    float cos_phi[SL_TEXEL_SPLIT_MAX], sin_phi[SL_TEXEL_SPLIT_MAX];
    for (int a = 0; a < cols; a++) {
        float phi = box.z + u->uEnvLightAzimuth * ((float)a + 0.5f) / (float)cols;
        cos_phi[a] = cosf(phi);
        sin_phi[a] = sinf(phi);
    }
    float *X = c->X + c->cells, *Y = c->Y + c->cells, *Z = c->Z + c->cells;
    for (int b = 0; b < rows; b++) {
        float z = mixf(box.x, box.y, ((float)b + 0.5f) / (float)rows);
        float sz = sqrtf(maxf(1.0f - z * z, 0.0f));
        for (int a = 0; a < cols; a++) {
            X[b * cols + a] = cos_phi[a] * sz;
            Y[b * cols + a] = sin_phi[a] * sz;
            Z[b * cols + a] = z;
        }
    }
    c->light[c->count++] = j;
    c->cells += rows * cols;
    c->first[c->count] = c->cells;
}

/* The kernel over the batch's cells, then each light's term, its cells' mean (Fresnel's two parts
 * summed apart, Ks sum k + (1 - Ks) sum k m5) times its solid angle over its node weight, in
 * place of its centroid's. */
static void cells_flush(cell_batch *c, const sl_lighting_uniforms *u, const env_lobe *l, vec3 N, vec3 V, vec3 Ks,
                        const float *vis, float *cr, float *cg, float *cb)
{
    env_kernel(l, N, V, c->X, c->Y, c->Z, c->cells, c->k, c->m5);
    for (int i = 0; i < c->count; i++) {
        const int j = c->light[i], c0 = c->first[i], c1 = c->first[i + 1];
        float s0 = 0.0f, s1 = 0.0f;
#pragma omp simd reduction(+ : s0, s1)
        for (int q = c0; q < c1; q++) {
            s0 += c->k[q];
            s1 += c->k[q] * c->m5[q];
        }
        vec3 f = scale(add(scale(Ks, s0), scale(sub(vec3s(1.0f), Ks), s1)), u->uEnvLightRadiance[j].w / (float)(c1 - c0));
        vec3 t = scale(mul(f, xyz(u->uEnvLightRadiance[j])), vis[j]);
        cr[j] = t.x;
        cg[j] = t.y;
        cb[j] = t.z;
    }
    c->count = c->cells = 0;
}

/* The lights env_light_near picks (near R, when the lobe is narrower than a few texels), each
 * one's centroid term replaced by the sum over its texel's cells: the test vectorized over the
 * lights (env_light_near's, in its order), the cells of those it passes gathered into batches. */
static void env_lights_split(const sl_lighting_uniforms *u, const shade_env_light_split *split, const env_lobe *l,
                             vec3 N, vec3 V, vec3 F, vec3 Ks, const float *vis, float *cr, float *cg, float *cb)
{
    const int n = shade_env_light_lanes(u);
    const float *X = u->envLightX, *Y = u->envLightY, *Z = u->envLightZ;
    const vec3 R = split->R, T = split->T, B = split->B;
    const float edge = 2.0f * split->side, cos_near = split->cos_near;
    const float across = split->across, reach = split->reach;
    const float near2 = (float)(SL_ENV_LIGHT_NEAR_WIDTHS * SL_ENV_LIGHT_NEAR_WIDTHS);
    int near[SL_ENV_LIGHTS_MAX];
#pragma omp simd
    for (int j = 0; j < n; j++) {
        float wN = (X[j] * N.x + Y[j] * N.y) + Z[j] * N.z; /* 0 past the count: not near */
        float wF = (X[j] * F.x + Y[j] * F.y) + Z[j] * F.z; /* under the facet: its term stays 0 */
        float rl = (R.x * X[j] + R.y * Y[j]) + R.z * Z[j];
        float qx = X[j] - R.x, qy = Y[j] - R.y, qz = Z[j] - R.z;
        float t = maxf(fabsf((qx * T.x + qy * T.y) + qz * T.z) - edge, 0.0f) / across;
        float b = maxf(fabsf((qx * B.x + qy * B.y) + qz * B.z) - edge, 0.0f) / reach;
        near[j] = (wN > 0.0f) & !(wF < 0.0f) & (rl > cos_near) & (t * t + b * b < near2);
    }
    cell_batch c;
    c.count = c.cells = 0;
    c.first[0] = 0;
    for (int j = 0; j < u->uEnvLightCount; j++) {
        if (!near[j])
            continue;
        int rows, cols;
        sl_shade_env_light_grid(u, j, split, &rows, &cols);
        if (rows * cols == 1)
            continue; /* its centroid's term stands */
        if (c.cells + rows * cols > CELL_BATCH)
            cells_flush(&c, u, l, N, V, Ks, vis, cr, cg, cb);
        cells_add(&c, u, j, rows, cols);
    }
    if (c.count > 0)
        cells_flush(&c, u, l, N, V, Ks, vis, cr, cg, cb);
}

/* specular_env_lights, batched: the lights vectorized (structure of arrays in the uniforms), then
 * the few that env_light_split reads over their texel's cells (those near R, when the lobe is
 * narrower than a few texels) replaced by their cells' sum, and the sum in light order. A light
 * under the facet F (shade_facet_hides; 0: none) adds 0. */
__attribute__((noinline)) static vec3 env_lights_samples(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 F,
                                                         vec3 Ks, float alpha, const float *vis)
{
    const int n = shade_env_light_lanes(u); /* zero lights add exactly 0 (below) */
    const float *LR = u->envLightR, *LG = u->envLightG, *LB = u->envLightB;
    const vec3 F1 = sub(vec3s(1.0f), Ks);
    const env_lobe lobe = env_lobe_for(u, N, V, alpha);
    float k[SL_ENV_LIGHTS_MAX], m5[SL_ENV_LIGHTS_MAX];
    env_kernel(&lobe, N, V, u->envLightX, u->envLightY, u->envLightZ, n, k, m5);
    float cr[SL_ENV_LIGHTS_MAX], cg[SL_ENV_LIGHTS_MAX], cb[SL_ENV_LIGHTS_MAX];
    const float *X = u->envLightX, *Y = u->envLightY, *Z = u->envLightZ;
#pragma omp simd
    for (int j = 0; j < n; j++) {
        float wF = (X[j] * F.x + Y[j] * F.y) + Z[j] * F.z;
        float kv = wF < 0.0f ? 0.0f : k[j] * vis[j]; /* x 1 without maps: the same bits */
        cr[j] = (Ks.x + F1.x * m5[j]) * kv * LR[j];
        cg[j] = (Ks.y + F1.y * m5[j]) * kv * LG[j];
        cb[j] = (Ks.z + F1.z * m5[j]) * kv * LB[j];
    }
    const shade_env_light_split split = sl_shade_env_light_split(u, N, V, alpha);
    if (split.cells > 1)
        env_lights_split(u, &split, &lobe, N, V, F, Ks, vis, cr, cg, cb);
    vec3 sum = vec3s(0.0f);
    for (int j = 0; j < n; j++)
        sum = add(sum, vec3(cr[j], cg[j], cb[j]));
    return scale(sum, u->uEnvIntensity);
}

/* ======================== the pixel stage ======================== */

/* One row span of pixels (at most a tile row), structure of arrays: what main() computes
 * per pixel before the samples, for every pixel of the span at once, so the normalisations
 * (a chain of divisions and square roots per pixel) run as vector throughput, not latency. */
typedef struct {
    float Vx[SPAN], Vy[SPAN], Vz[SPAN], Nx[SPAN], Ny[SPAN], Nz[SPAN];            /* world */
    float NEx[SPAN], NEy[SPAN], NEz[SPAN], VEx[SPAN], VEy[SPAN], VEz[SPAN];      /* environment */
    float Rx[SPAN], Ry[SPAN], Rz[SPAN], Ax[SPAN], Ay[SPAN], Az[SPAN], Bx[SPAN], By[SPAN], Bz[SPAN];
    float NdotV[SPAN];
    float Px[SPAN], Py[SPAN], Pz[SPAN], nx[SPAN], ny[SPAN], nz[SPAN]; /* the texels' position, normal */
    int bent[SPAN], pole[SPAN];
    float Er[SPAN], Eg[SPAN], Eb[SPAN];       /* irradiance(NE), with the diffuse term on */
    vec3 B[SPAN];                             /* Bx, By, Bz as vectors (sl_shade_span says why) */
    float bg_r[SPAN], bg_g[SPAN], bg_b[SPAN]; /* background(), for the empty pixels */
} pixel_block;

/* The span's pixels that a shadow or sky map is read for, packed (a lanes lookup costs the same
 * for a pixel that needs nothing): each one's position and normal as pixel_block holds them, and
 * which pixel it is. */
typedef struct {
    float px[SPAN], py[SPAN], pz[SPAN], nx[SPAN], ny[SPAN], nz[SPAN];
    int pixel[SPAN];
    int n;
} shadow_points;
_Static_assert(SPAN <= SL_SHADOW_LANES, "a span's points fit one lanes lookup");

static void shadow_points_add(shadow_points *s, const pixel_block *p, int i)
{
    const int k = s->n++;
    s->px[k] = p->Px[i], s->py[k] = p->Py[i], s->pz[k] = p->Pz[i];
    s->nx[k] = p->Nx[i], s->ny[k] = p->Ny[i], s->nz[k] = p->Nz[i];
    s->pixel[k] = i;
}

static inline float select_f(bool c, float a, float b) { return c ? a : b; }

/* main() up to the samples (V, facing_normal, the environment frame) and specular_ibl's frame
 * (R, A, B; A, B about N for specular_microfacet), for pixels x0 .. x0 + count - 1 of G-buffer row y; empty pixels compute garbage
 * that nothing reads. The view frame is shade_view_frame_at (lighting_internal.h). */
static void pixel_stage(const sl_lighting_uniforms *u, const sl_gbuffer_texel *t, int count, pixel_block *p)
{
    const vec3 eye = u->uEye;
    const vec3 r[3] = {u->uEnvRotation.c[0], u->uEnvRotation.c[1], u->uEnvRotation.c[2]};
    /* the frame is about N (microfacet samples), not R, per lobe set (a GGX lobe may sample
     * otherwise than a Phong one: shade_estimator_of). The loop below reads the choice as a
     * float per pixel: with shade_microfacet_samples' flags (compares) in it, GCC 12 does not
     * vectorize the loop, and the lighting pass takes 7% longer. */
    const float about_n_phong = u->setSampling[0].about_n ? 1.0f : 0.0f;
    const float about_n_ggx = u->setSampling[1].about_n ? 1.0f : 0.0f;
    float about_n[SPAN];
    for (int i = 0; i < count; i++) { /* to structure of arrays: the G-buffer texel is 56 bytes */
        about_n[i] = select_f(sl_lobe_is_ggx(t[i].alpha), about_n_ggx, about_n_phong);
        p->Px[i] = t[i].position.x;
        p->Py[i] = t[i].position.y;
        p->Pz[i] = t[i].position.z;
        p->nx[i] = t[i].normal.x;
        p->ny[i] = t[i].normal.y;
        p->nz[i] = t[i].normal.z;
    }
#pragma omp simd
    for (int i = 0; i < count; i++) {
        shade_view_frame f =
            shade_view_frame_at(eye, vec3(p->Px[i], p->Py[i], p->Pz[i]), vec3(p->nx[i], p->ny[i], p->nz[i]), r);
        const vec3 V = f.V, N = f.N, NE = f.NE, VE = f.VE, R = f.R;
        const float NdotV = f.NdotV;
        /* specular_ibl's frame about R, or specular_microfacet's about N */
        const bool mf = about_n[i] != 0.0f;
        vec3 Z = vec3(select_f(mf, NE.x, R.x), select_f(mf, NE.y, R.y), select_f(mf, NE.z, R.z));
        bool pole = Z.x * Z.x + Z.y * Z.y < POLE_EPS;
        vec3 axis = vec3(select_f(pole, 1.0f, 0.0f), 0.0f, select_f(pole, 0.0f, 1.0f));
        vec3 A = normalize(cross(axis, Z));
        vec3 B = normalize(cross(Z, A));
        p->Vx[i] = V.x;
        p->Vy[i] = V.y;
        p->Vz[i] = V.z;
        p->Nx[i] = N.x;
        p->Ny[i] = N.y;
        p->Nz[i] = N.z;
        p->NEx[i] = NE.x;
        p->NEy[i] = NE.y;
        p->NEz[i] = NE.z;
        p->VEx[i] = VE.x;
        p->VEy[i] = VE.y;
        p->VEz[i] = VE.z;
        p->NdotV[i] = NdotV;
        p->Rx[i] = R.x;
        p->Ry[i] = R.y;
        p->Rz[i] = R.z;
        p->Ax[i] = A.x;
        p->Ay[i] = A.y;
        p->Az[i] = A.z;
        p->Bx[i] = B.x;
        p->By[i] = B.y;
        p->Bz[i] = B.z;
        p->pole[i] = pole;
        p->bent[i] = f.bent;
    }
}

/* ======================== the background ======================== */

/* How the background reads level 0: the environment's pair rows (texture_lod.h sl_pair_bilinear:
 * 6 64-bit gathers where the block takes 12 32-bit ones), its single block (gathers), or the
 * port's filter. The same texels and operations in all three, so the same bits. */
enum { BACKGROUND_PAIRS, BACKGROUND_GATHER, BACKGROUND_SCALAR };

/* The background's loop, its fetch a constant at each call (each call its own vector loop). */
__attribute__((always_inline)) static inline void background_loop(const sl_lighting_uniforms *u, int x0, int y,
                                                                  int count, int fetch, float *bg_r, float *bg_g,
                                                                  float *bg_b)
{
    const float I = u->uEnvIntensity;
    const sl_env_level *l0 = &u->uEnv->levels[0];
    const sl_env_gather *env = &u->envGather;
    const vec4 m[4] = {u->uInvViewProj.c[0], u->uInvViewProj.c[1], u->uInvViewProj.c[2], u->uInvViewProj.c[3]};
    const vec3 r[3] = {u->uEnvRotation.c[0], u->uEnvRotation.c[1], u->uEnvRotation.c[2]};
    const vec2 viewport = u->uViewport;
#pragma omp simd
    for (int i = 0; i < count; i++) {
        vec3 d = shade_background_dir(m, r, viewport, vec2((float)(x0 + i) + 0.5f, (float)y + 0.5f));
        float bu, bv;
        sl_fast_dir_to_uv(d.x, d.y, d.z, &bu, &bv);
        vec3 c = fetch == BACKGROUND_PAIRS    ? sl_pair_bilinear(env, 0, bu, bv)
                 : fetch == BACKGROUND_GATHER ? sl_env_gather_bilinear(env, 0, bu, bv)
                                              : sl_env_bilinear(l0, bu, bv);
        bg_r[i] = c.x * I;
        bg_g[i] = c.y * I;
        bg_b[i] = c.z * I;
    }
}

void sl_shade_background_span(const sl_lighting_uniforms *u, int x0, int y, int count, float *bg_r, float *bg_g,
                           float *bg_b)
{
    if (u->envGather.gather && u->envGather.pairs)
        background_loop(u, x0, y, count, BACKGROUND_PAIRS, bg_r, bg_g, bg_b);
    else if (u->envGather.gather)
        background_loop(u, x0, y, count, BACKGROUND_GATHER, bg_r, bg_g, bg_b);
    else
        background_loop(u, x0, y, count, BACKGROUND_SCALAR, bg_r, bg_g, bg_b);
}

/* ======================== main(): the sum and the span ======================== */

/* The control variate's kernel for the pixel (*cv) and its closed part, the port's cv_closed with
 * the samples' fast lat-long map. *subtract: whether the samples subtract the kernel; where beta
 * is 0 or no level is exact they do not, and run the plain estimator's loops and bits (the port's
 * closed part is 0 there too). */
static vec3 cv_closed_part(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, sl_cv_kernel *cv,
                           bool *subtract, sl_lighting_trace *trace)
{
    *cv = sl_shade_cv_setup(u, N, V, Ks, alpha);
    *subtract = cv->beta > 0.0f && (cv->levels.ca > 0.0f || cv->levels.cb > 0.0f);
    vec3 C = vec3s(0.0f);
    if (*subtract) {
        float tu, tv;
        sl_fast_dir_to_uv(cv->dir.x, cv->dir.y, cv->dir.z, &tu, &tv);
        const sl_env *chain = cv->set == SL_SPLITSUM_GGX ? u->uSplitSumGGX : u->uSplitSumPhong;
        if (cv->levels.ca > 0.0f)
            C = add(C, scale(sl_env_catmull_rom(&chain->levels[cv->levels.la], tu, tv), cv->levels.ca));
        if (cv->levels.cb > 0.0f)
            C = add(C, scale(sl_env_catmull_rom(&chain->levels[cv->levels.lb], tu, tv), cv->levels.cb));
    }
    int traced = trace ? trace->sample_count : 0; /* the lookup's trace records no samples: cv has them */
    trace_splitsum(trace, N, V, cv->R, cv->r, cv->lod, cv->dir, C, cv->ab);
    if (trace)
        trace->sample_count = traced;
    return scale(mul(cv->scale, C), u->uEnvIntensity);
}

/* lighting.c specular_cv's operations: the split sum's closed value and the microfacet samples'
 * correction. Out of line, so that the pixel loop that inlines pixel_specular stays the size it
 * is for the other estimators. */
__attribute__((noinline)) static vec3 cv_samples(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 R, vec3 A, vec3 B,
                                                 bool pole, vec3 Ks, float alpha, vec2 rotation, shade_horizon *h,
                                                 sl_lighting_task *task, sl_lighting_trace *trace)
{
    sl_cv_kernel cv;
    bool subtract;
    vec3 closed = cv_closed_part(u, N, V, Ks, alpha, &cv, &subtract, trace);
    vec3 correction =
        specular_samples(u, N, V, R, A, B, pole, Ks, alpha, rotation, subtract ? &cv : NO_CV, h, task, trace);
    trace_cv(trace, &cv, closed, correction);
    return add(closed, correction);
}

/* lighting.c specular_cv's operations with mis: cv_samples' closed part and mis's pairs of
 * samples, less the kernel's terms. */
__attribute__((noinline)) static vec3 cvmis_samples(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha,
                                                    vec2 rotation, shade_horizon *h, sl_lighting_task *task,
                                                    sl_lighting_trace *trace)
{
    /* every pixel its own pairs; the trace of the kernel's terms; or no task, whose table
     * mis_samples would allocate and, failing that, fall back to plain mis */
    if (u->uRotate != 0 || trace || !task)
        return sl_shade_specular_cvmis(u, N, V, Ks, alpha, rotation, h, task, trace);
    sl_cv_kernel cv;
    bool subtract;
    vec3 closed = cv_closed_part(u, N, V, Ks, alpha, &cv, &subtract, trace);
    vec3 correction = mis_samples(u, N, V, Ks, alpha, rotation, subtract ? &cv : NO_CV, h, task, trace);
    trace_cv(trace, &cv, closed, correction);
    return add(closed, correction);
}

/* Every env light's visibility without shadow maps: env_lights_samples multiplies by it. */
static const float ones[SL_ENV_LIGHTS_MAX] = {
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
_Static_assert(SL_ENV_LIGHTS_MAX == 64, "ones[] has a 1 per env light");

/* The port's env_shadow_diffuse (lighting.c) with the lights' sums taken a group at a time
 * (env_light_groups.h), each group's lights sharing their map's visibility: E read along D less
 * the lights' part of it (returned, clamped at 0) and their diffuse about N times the visibility
 * (`lights`). The same sums as the port's loop over every light, in another order: a few dot
 * products a map where the port takes one a light. */
static vec3 env_shadow_diffuse(const sl_lighting_uniforms *u, vec3 E, bool bent, vec3 D, vec3 Nenv, vec3 Kd,
                               const float *vis, vec3 *lights)
{
    const sl_env_light_groups *g = &u->envLightGroups;
    vec3 all = vec3s(0.0f), seen = vec3s(0.0f);
    for (int k = 0; k < g->count; k++) {
        vec3 about_n = sl_env_light_group_irradiance(g, k, u->uEnvLightDir, u->uEnvLightRadiance, Nenv);
        seen = add(seen, scale(about_n, vis[g->member[g->group[k].first]]));
        all = add(all, bent ? sl_env_light_group_irradiance(g, k, u->uEnvLightDir, u->uEnvLightRadiance, D) : about_n);
    }
    *lights = scale(mul(scale(Kd, 1.0f / SL_PI), seen), u->uEnvIntensity);
    return vmax3(sub(E, all), vec3s(0.0f));
}

/* The specular term of covered pixel i of the span (0 with it off): the split sum's lookup (the
 * port's own: nothing to batch) or the samples, and the env lights; with their shadow maps
 * (env_shadow, its vis set) the env lights' sum times each one's visibility goes to
 * env_shadow->specular instead. With the sky maps the samples' part across the horizon goes to
 * h (shade_horizon_for's, set here). */
__attribute__((always_inline)) static inline vec3 pixel_specular(const sl_lighting_uniforms *u, const pixel_block *p,
                                                                 int i, vec3 Ks, float alpha, vec2 rotation, vec3 Fenv,
                                                                 shade_env_shadow *env_shadow, shade_horizon *h,
                                                                 sl_lighting_task *task, sl_lighting_trace *trace)
{
    const vec3 N = vec3(p->NEx[i], p->NEy[i], p->NEz[i]), V = vec3(p->VEx[i], p->VEy[i], p->VEz[i]);
    *h = shade_horizon_for(u, N, V, Fenv);
    if (env_shadow)
        shade_horizon_glow(h, u, env_shadow->map_vis);
    if (u->uSpecular == 0)
        return vec3s(0.0f);
    if (env_shadow)
        env_shadow->specular = vec3s(0.0f);
    const vec3 R = vec3(p->Rx[i], p->Ry[i], p->Rz[i]), A = vec3(p->Ax[i], p->Ay[i], p->Az[i]);
    vec3 specular;
    const int estimator = shade_estimator_of(u, alpha);
    if (estimator == ESTIMATOR_SPLITSUM) {
        specular = sl_shade_specular_splitsum(u, N, V, Ks, alpha, trace);
    } else if (estimator == ESTIMATOR_MIS) {
        specular = mis_samples(u, N, V, Ks, alpha, rotation, NO_CV, h, task, trace);
    } else if (estimator == ESTIMATOR_CV_MIS) {
        specular = cvmis_samples(u, N, V, Ks, alpha, rotation, h, task, trace);
    } else if (estimator == ESTIMATOR_CV) {
        specular = cv_samples(u, N, V, R, A, p->B[i], p->pole[i], Ks, alpha, rotation, h, task, trace);
    } else {
        specular = specular_samples(u, N, V, R, A, p->B[i], p->pole[i], Ks, alpha, rotation, NO_CV, h, task, trace);
    }
    if (env_shadow) /* kept apart: sl_shade_surface_color adds it after the occlusion */
        env_shadow->specular = env_lights_samples(u, N, V, Fenv, Ks, alpha, env_shadow->vis);
    else if (shade_env_lights_of(u, alpha)) {
        vec3 exact = env_lights_samples(u, N, V, Fenv, Ks, alpha, ones);
        specular = add(specular, exact);
        trace_env_lights(trace, u, N, V, alpha, exact);
    }
    return specular;
}

/* The sky visibility maps' V (src/shadow/sky.h) on covered pixel i's irradiance: the port's
 * scale(E, V), from the pass's plane (sky_row: the span's part of it) where it has one, else
 * looked up as the port does. */
static void sky_scale(const sl_lighting_uniforms *u, pixel_block *p, int i, vec3 P, const float *sky_row)
{
    if (u->uDiffuse == 0)
        return;
    float V = sky_row ? sky_row[i] : sl_shadow_sky_visibility(u->skyMaps, P, vec3(p->Nx[i], p->Ny[i], p->Nz[i]), NULL);
    p->Er[i] *= V;
    p->Eg[i] *= V;
    p->Eb[i] *= V;
}

/* main()'s sum and its NaN guard over the span, without a trace: sl_shade_surface_color's
 * operations in its order, then sl_shade_finish's, as vector loops around the point lights,
 * which each covered pixel adds one after another through the port's function (the same bits;
 * a term that is off is selected away, not added). c{r,g,b} hold each covered pixel's specular
 * term and each empty pixel's background on entry; l{r,g,b}, with the env lights' shadow maps,
 * their diffuse and specular times their visibility, added after the occlusion (read only then);
 * a{r,g,b}, with the sky maps, the specular's part across the horizon times its map's visibility
 * (sl_shade_horizon_visible), added after the specular's factor times the material's occlusion
 * (read only then). */
static void sum_stage(const sl_lighting_uniforms *u, const sl_gbuffer *gb, const sl_gbuffer_texel *t, int x0, int y,
                      int count, const pixel_block *p, const float *cr, const float *cg, const float *cb,
                      const float *lr, const float *lg, const float *lb, const float *ar, const float *ag,
                      const float *ab, sl_lighting_task *task, vec3 *out)
{
    float kr[SPAN], kg[SPAN], kb[SPAN], occ[SPAN], spo[SPAN], docc[SPAN], emr[SPAN], emg[SPAN], emb[SPAN];
    float mocc[SPAN]; /* the material's occlusion with the cone (the reflection join's and the part across the
                         horizon's), else 1 */
    int covered[SPAN];
    const sl_gbuffer_extra *ex = gb->extra ? gb->extra + (size_t)y * (size_t)gb->width + (size_t)x0 : NULL;
    const sl_vec4 *cone = gb->cone ? gb->cone + (size_t)y * (size_t)gb->width + (size_t)x0 : NULL;
    const vec2 *reflection = shade_reflection(gb, x0, y);
    /* the reflection occlusion's visibility, 1 without the plane (x * 1 is x, bit for bit), and
     * the rays it is over */
    float refl[SPAN], refl_rays[SPAN];
    for (int i = 0; i < count; i++) {
        refl[i] = reflection ? reflection[i].x : 1.0f;
        refl_rays[i] = reflection ? reflection[i].y : 0.0f;
    }
    for (int i = 0; i < count; i++) { /* to structure of arrays (shade_extra's "none" without the plane) */
        covered[i] = !(t[i].depth >= 1.0f);
        kr[i] = t[i].kd.x;
        kg[i] = t[i].kd.y;
        kb[i] = t[i].kd.z;
        occ[i] = ex ? ex[i].occlusion : 1.0f;
        emr[i] = ex ? ex[i].emissive.x : 0.0f;
        emg[i] = ex ? ex[i].emissive.y : 0.0f;
        emb[i] = ex ? ex[i].emissive.z : 0.0f;
    }
    /* with the cone, the specular's own occlusion (sl_shade_surface_color's, the same
     * functions): the cosines and the lobe's cone per pixel (the lobe's once per run of one
     * lobe parameter), then the factor for the span in one vector loop; an empty pixel's lane
     * is computed and never read */
    if (cone) {
        float bdr[SPAN], ndv[SPAN], acr[SPAN], ao[SPAN], lobe_cos[SPAN], lobe_angle[SPAN]; /* a float array each: vectorizes */
        float last_alpha = NAN;
        sl_so_lobe last = {1.0f, 0.0f};
        for (int i = 0; i < count; i++) {
            ao[i] = cone[i].w;
            docc[i] = shade_diffuse_occlusion(u, &cone[i], occ[i]);
            bdr[i] = ndv[i] = 1.0f;
            acr[i] = 0.0f;
            lobe_cos[i] = last.cos_s;
            lobe_angle[i] = last.ts;
            if (!covered[i])
                continue;
            shade_cone_cosines(u, &cone[i], vec3(p->NEx[i], p->NEy[i], p->NEz[i]), vec3(p->VEx[i], p->VEy[i], p->VEz[i]),
                               &bdr[i], &ndv[i], &acr[i]);
            float alpha = shade_lobe_param(t[i].alpha);
            if (!(alpha == last_alpha)) {
                last = sl_so_lobe_cone(alpha);
                last_alpha = alpha;
            }
            lobe_cos[i] = last.cos_s;
            lobe_angle[i] = last.ts;
        }
#pragma omp simd
        for (int i = 0; i < count; i++)
            spo[i] = shade_spec_occlusion(ao[i], occ[i], bdr[i], ndv[i], (sl_so_lobe){lobe_cos[i], lobe_angle[i]}, acr[i]);
#pragma omp simd
        for (int i = 0; i < count; i++)
            mocc[i] = shade_material_occlusion(ao[i], occ[i]);
        if (reflection) /* the port's join of the two factors */
#pragma omp simd
            for (int i = 0; i < count; i++)
                spo[i] = sl_reflection_specular_factor(spo[i], mocc[i], vec2(refl[i], refl_rays[i]));
        if (u->skyMaps) { /* a wide lobe's map of R's cell (shade_lobe_map), the span's looked up at once */
            shadow_points wide;
            wide.n = 0;
            float rx[SPAN], ry[SPAN], rz[SPAN];
            for (int i = 0; i < count; i++)
                if (covered[i] && shade_lobe_takes_map(u, lobe_angle[i], p->Rz[i])) {
                    rx[wide.n] = p->Rx[i], ry[wide.n] = p->Ry[i], rz[wide.n] = p->Rz[i];
                    shadow_points_add(&wide, p, i);
                }
            if (wide.n > 0) {
                float v[SPAN];
                sl_shadow_sky_cell_visibility_lanes(u->skyMaps, wide.n, rx, ry, rz, wide.px, wide.py, wide.pz,
                                                    wide.nx, wide.ny, wide.nz, v);
                for (int k = 0; k < wide.n; k++) {
                    const int i = wide.pixel[k];
                    spo[i] = shade_lobe_map_with(spo[i], mocc[i], v[k]);
                }
            }
        }
    } else {
        for (int i = 0; i < count; i++)
            mocc[i] = 1.0f;
    }
    const bool horizon = u->skyMaps != NULL;
    const bool with_cone = cone != NULL;
    const float *so_in = with_cone ? spo : occ; /* read in every lane: never an unset array */
    const float *do_in = with_cone ? docc : occ; /* likewise */
    const bool diffuse = u->uDiffuse != 0, specular = u->uSpecular != 0;
    const bool shadowed = u->envLightShadows != 0;
    const bool lights = u->uPointLights != 0 && u->uLightCount > 0;
    const float I = u->uEnvIntensity;
    float *o = &out[0].x;
    float tr[SPAN], tg[SPAN], tb[SPAN]; /* each pixel's sum before the point lights */
    int nonfinite = 0;
#pragma omp simd
    for (int i = 0; i < count; i++) {
        /* color = 0; + Kd/pi E I; + specular; times the occlusion; + emission: each sum formed,
         * then kept or not (an addition under a branch stops GCC's vectorizer) */
        float r = 0.0f, g = 0.0f, b = 0.0f;
        /* with the cone each term times its own occlusion, without it the sum times the one
         * occlusion; the factors not applied are 1 (x * 1 is x, bit for bit) */
        float so_i = so_in[i], do_i = do_in[i]; /* loaded in every lane, then selected */
        float d_occ = with_cone ? do_i : 1.0f, s_occ = with_cone ? so_i : refl[i];
        float sum_occ = with_cone ? 1.0f : occ[i];
        float dr = r + (((kr[i] * (1.0f / PI)) * p->Er[i]) * I) * d_occ;
        float dg = g + (((kg[i] * (1.0f / PI)) * p->Eg[i]) * I) * d_occ;
        float db = b + (((kb[i] * (1.0f / PI)) * p->Eb[i]) * I) * d_occ;
        r = diffuse ? dr : r;
        g = diffuse ? dg : g;
        b = diffuse ? db : b;
        float sr = r + cr[i] * s_occ, sg = g + cg[i] * s_occ, sb = b + cb[i] * s_occ;
        /* with the sky maps the port's spec * factor + across * its factor, then added */
        float hr = r + (cr[i] * s_occ + ar[i] * mocc[i]), hg = g + (cg[i] * s_occ + ag[i] * mocc[i]);
        float hb = b + (cb[i] * s_occ + ab[i] * mocc[i]);
        sr = horizon ? hr : sr;
        sg = horizon ? hg : sg;
        sb = horizon ? hb : sb;
        r = specular ? sr : r;
        g = specular ? sg : g;
        b = specular ? sb : b;
        r = r * sum_occ;
        g = g * sum_occ;
        b = b * sum_occ;
        float lit_r = r + lr[i], lit_g = g + lg[i], lit_b = b + lb[i];
        tr[i] = shadowed ? lit_r : r;
        tg[i] = shadowed ? lit_g : g;
        tb[i] = shadowed ? lit_b : b;
    }
    /* the point lights, one after another for each covered pixel as the port adds them (each a
     * direction and a BRDF: the port's own function); with shadow maps, a light's lookups for the
     * pixels it lights (sl_shade_point_light's condition) packed into one vector loop
     * (sl_shadow_point_visibility_lanes: the port's lookup's bits), each light scaled by its own */
    if (lights)
        for (int l = 0; l < u->uLightCount; l++) {
            float Lr[SPAN], Lg[SPAN], Lb[SPAN];
            shadow_points lit;
            lit.n = 0;
            for (int i = 0; i < count; i++) {
                if (!covered[i])
                    continue;
                const vec3 N = vec3(p->Nx[i], p->Ny[i], p->Nz[i]), V = vec3(p->Vx[i], p->Vy[i], p->Vz[i]);
                vec3 light = sl_shade_point_light_unshadowed(u, l, t[i].position, N, V, t[i].kd, t[i].ks,
                                                             shade_lobe_param(t[i].alpha));
                Lr[i] = light.x, Lg[i] = light.y, Lb[i] = light.z;
                if (u->shadowMaps && (light.x > 0.0f || light.y > 0.0f || light.z > 0.0f))
                    shadow_points_add(&lit, p, i);
            }
            if (lit.n > 0) {
                float vis[SPAN];
                sl_shadow_point_visibility_lanes(u->shadowMaps, l, lit.n, lit.px, lit.py, lit.pz, lit.nx, lit.ny,
                                                 lit.nz, vis);
                for (int k = 0; k < lit.n; k++) { /* scale(light, v) */
                    const int i = lit.pixel[k];
                    Lr[i] = Lr[i] * vis[k], Lg[i] = Lg[i] * vis[k], Lb[i] = Lb[i] * vis[k];
                }
            }
            for (int i = 0; i < count; i++) {
                if (!covered[i])
                    continue;
                tr[i] += Lr[i];
                tg[i] += Lg[i];
                tb[i] += Lb[i];
            }
        }
#pragma omp simd reduction(+ : nonfinite)
    for (int i = 0; i < count; i++) {
        float r = tr[i], g = tg[i], b = tb[i];
        float er = r + emr[i], eg = g + emg[i], eb = b + emb[i];
        r = diffuse ? er : r;
        g = diffuse ? eg : g;
        b = diffuse ? eb : b;
        r = covered[i] ? r : cr[i];
        g = covered[i] ? g : cg[i];
        b = covered[i] ? b : cb[i];
        bool finite = isfinite(r) && isfinite(g) && isfinite(b); /* sl_shade_finish */
        nonfinite += !finite;
        o[3 * i] = finite ? r : 0.0f;
        o[3 * i + 1] = finite ? g : 0.0f;
        o[3 * i + 2] = finite ? b : 0.0f;
    }
    if (task)
        task->stats.nonfinite += nonfinite;
}

/* main(), batched (lighting_internal.h): the pixel stage for the whole span, the background
 * stage when a pixel is empty, the irradiance for the span, then per pixel the specular samples;
 * main()'s sum for the span in vector loops (sum_stage), or per pixel through the port's
 * (sl_shade_surface_color) with a trace. */
void sl_shade_span(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count, sl_lighting_task *task,
                sl_lighting_trace *trace, vec3 *out)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x0, y);
    const bool vector_sum = !trace;
    /* with the env lights' shadow maps, their shadowed terms per pixel for sum_stage */
    const bool shadowed = u->envLightShadows != 0;
    float lr[SPAN], lg[SPAN], lb[SPAN];
    pixel_block pb;
    pixel_block *p = &pb;
    float cr[SPAN], cg[SPAN], cb[SPAN]; /* sum_stage's input: the specular term, or the background */
    float ar[SPAN], ag[SPAN], ab[SPAN]; /* with the sky maps: the part across the horizon, visible */
    struct {
        shadow_points at;                   /* the pixels with a part across, packed */
        float dx[SPAN], dy[SPAN], dz[SPAN]; /* its direction (sl_shade_horizon_dir) */
        float r[SPAN], g[SPAN], b[SPAN];    /* its sum */
        int n;
    } across_maps;
    across_maps.n = 0;
    across_maps.at.n = 0;
    int empty = 0;
    for (int i = 0; i < count; i++)
        empty += t[i].depth >= 1.0f;
    const bool irradiance = empty < count && u->uDiffuse != 0;
    const float *sky_row = shade_sky_row(task, gb, x0, y);
    if (empty < count) /* a span of background alone (most of ggx.json's) needs no frames */
        pixel_stage(u, t, count, p);
    /* the diffuse term's irradiance(NE) for the whole span in vector loops (an empty pixel's
     * lane looks up a harmless garbage direction), the port's lookup's bits */
    if (irradiance && gb->cone) { /* along each pixel's bent direction (shade_diffuse_dir) */
        float dx[SPAN], dy[SPAN], dz[SPAN];
        const sl_vec4 *cone = gb->cone + (size_t)y * (size_t)gb->width + (size_t)x0;
        for (int i = 0; i < count; i++) {
            vec3 NE = vec3(p->NEx[i], p->NEy[i], p->NEz[i]);
            vec3 D = t[i].depth >= 1.0f ? NE : shade_diffuse_dir(u, &cone[i], NE);
            dx[i] = D.x;
            dy[i] = D.y;
            dz[i] = D.z;
        }
        sl_irradiance_eval_span(u->uIrradiance, count, dx, dy, dz, p->Er, p->Eg, p->Eb);
    } else if (irradiance)
        sl_irradiance_eval_span(u->uIrradiance, count, p->NEx, p->NEy, p->NEz, p->Er, p->Eg, p->Eb);
    else if (vector_sum) /* read (and selected away) by sum_stage */
        for (int i = 0; i < count; i++)
            p->Er[i] = p->Eg[i] = p->Eb[i] = 0.0f;
    if (empty > 0)
        sl_shade_background_span(u, x0, y, count, p->bg_r, p->bg_g, p->bg_b);
    /* with the env lights' shadow maps, each map's visibility for the span's covered pixels in
     * one vector loop (sl_shadow_sun_visibility_lanes: the bits of the port's lookup), read per
     * pixel below; SPAN x SL_SHADOW_SUN_MAX, pixel-major */
    float sun_vis[SPAN][SL_SHADOW_SUN_MAX]; /* read only with the maps, and then set */
    if (shadowed && empty < count) {
        memset(sun_vis, 0, sizeof sun_vis); /* the slots past the maps' count: read, not used */
        shadow_points seen;
        seen.n = 0;
        for (int i = 0; i < count; i++)
            if (t[i].depth < 1.0f)
                shadow_points_add(&seen, p, i);
        for (int k = 0; k < u->envShadowMaps->count; k++) {
            float vis[SPAN];
            sl_shadow_sun_visibility_lanes(u->envShadowMaps, k, seen.n, seen.px, seen.py, seen.pz, seen.nx, seen.ny,
                                           seen.nz, vis);
            for (int j = 0; j < seen.n; j++)
                sun_vis[seen.pixel[j]][k] = vis[j];
        }
    }
    if (empty < count) /* B, a stack argument of specular_samples, from memory stored long before */
        for (int i = 0; i < count; i++)
            p->B[i] = vec3(p->Bx[i], p->By[i], p->Bz[i]);
    for (int i = 0; i < count; i++) {
        const int x = x0 + i;
        vec3 color;
        trace_texel(trace, &t[i], vec2((float)x + 0.5f, (float)y + 0.5f), false);
        if (t[i].depth >= 1.0f) {
            color = vec3(p->bg_r[i], p->bg_g[i], p->bg_b[i]);
            trace_background(task, trace, color);
        } else if (vector_sum) {
            /* no trace: the terms straight from the span's arrays and the texel (a shade_surface
             * built field by field and read back as arguments stalled on store forwarding) */
            count_bent(task, p->bent[i]);
            vec2 rotation = u->uRotate != 0 ? sl_shade_pixel_rotation(u, x, y) : vec2(0.0f, 0.0f);
            shade_horizon h;
            if (shadowed) {
                /* sl_shade_surface_color's env-shadow terms, the same functions: the specular
                 * keeps the lights apart, the irradiance loses their part, both come back
                 * times the visibility after the occlusion */
                shade_env_shadow es;
                vec3 NE = vec3(p->NEx[i], p->NEy[i], p->NEz[i]);
                sl_shade_env_light_visibility_of(u, sun_vis[i], es.vis);
                memcpy(es.map_vis, sun_vis[i], sizeof es.map_vis);
                color = pixel_specular(u, p, i, t[i].ks, shade_lobe_param(t[i].alpha), rotation,
                                       shade_facet_env(u, gb, x, y), &es, &h, task, NULL);
                vec3 lights = vec3s(0.0f);
                if (u->uDiffuse != 0) {
                    const sl_vec4 *cone = shade_cone(gb, x, y);
                    vec3 D = cone ? shade_diffuse_dir(u, cone, NE) : NE;
                    vec3 E = env_shadow_diffuse(u, vec3(p->Er[i], p->Eg[i], p->Eb[i]), cone != NULL, D, NE,
                                                         t[i].kd, es.vis, &lights);
                    p->Er[i] = E.x;
                    p->Eg[i] = E.y;
                    p->Eb[i] = E.z;
                }
                if (u->uSpecular != 0)
                    lights = add(lights, es.specular);
                lr[i] = lights.x;
                lg[i] = lights.y;
                lb[i] = lights.z;
            } else {
                color = pixel_specular(u, p, i, t[i].ks, shade_lobe_param(t[i].alpha), rotation,
                                       shade_facet_env(u, gb, x, y), NULL, &h, task, NULL);
            }
            if (u->skyMaps) { /* sl_shade_surface_color's V on the residual's irradiance */
                sky_scale(u, p, i, t[i].position, sky_row);
                /* sl_shade_horizon_visible, its lookup made for the span's pixels at once below */
                vec3 d;
                ar[i] = ag[i] = ab[i] = 0.0f;
                if (sl_shade_horizon_dir(&h, &d)) {
                    const int k = across_maps.n;
                    across_maps.dx[k] = d.x, across_maps.dy[k] = d.y, across_maps.dz[k] = d.z;
                    across_maps.r[k] = h.sum.x, across_maps.g[k] = h.sum.y, across_maps.b[k] = h.sum.z;
                    shadow_points_add(&across_maps.at, p, i);
                    across_maps.n++;
                }
            }
        } else {
            shade_surface s = {
                .P = t[i].position,
                .Kd = t[i].kd,
                .Ks = t[i].ks,
                .alpha = shade_lobe_param(t[i].alpha),
                .V = vec3(p->Vx[i], p->Vy[i], p->Vz[i]),
                .N = vec3(p->Nx[i], p->Ny[i], p->Nz[i]),
                .Nenv = vec3(p->NEx[i], p->NEy[i], p->NEz[i]),
                .Venv = vec3(p->VEx[i], p->VEy[i], p->VEz[i]),
                .rotation = u->uRotate != 0 ? sl_shade_pixel_rotation(u, x, y) : vec2(0.0f, 0.0f),
                .occlusion = shade_extra(gb, x, y).occlusion,
                .emissive = shade_extra(gb, x, y).emissive,
                .reflection = shade_reflection(gb, x, y),
                .cone = shade_cone(gb, x, y),
                .Fenv = shade_facet_env(u, gb, x, y),
            };
            vec3 A = vec3(p->Ax[i], p->Ay[i], p->Az[i]);
            trace_surface(u, task, trace, &s, p->bent[i]);
            /* the samples' count only when they run, as the port records it */
            int traced_samples = u->uSpecular != 0 ? (int)u->uHammersley.N : 0;
            trace_sample_frame(trace, s.Nenv, s.Venv, A, p->B[i], p->pole[i], traced_samples,
                               shade_microfacet_samples(u, s.alpha));
            shade_env_shadow es, *env_shadow = NULL;
            es.diffuse_given = false;
            vec3 E = irradiance ? vec3(p->Er[i], p->Eg[i], p->Eb[i]) : vec3s(0.0f); /* unread when off */
            if (u->envLightShadows != 0) {
                sl_shade_env_light_visibility_of(u, sun_vis[i], es.vis);
                memcpy(es.map_vis, sun_vis[i], sizeof es.map_vis);
                env_shadow = &es;
                if (u->uDiffuse != 0) { /* the lights' diffuse by group, as in the vector sum's branch */
                    vec3 D = s.cone ? shade_diffuse_dir(u, s.cone, s.Nenv) : s.Nenv;
                    E = env_shadow_diffuse(u, E, s.cone != NULL, D, s.Nenv, s.Kd, es.vis, &es.diffuse);
                    es.diffuse_given = true;
                }
            }
            if (u->skyMaps && irradiance) { /* as the vector sum's branch: E_given carries V */
                p->Er[i] = E.x;
                p->Eg[i] = E.y;
                p->Eb[i] = E.z;
                sky_scale(u, p, i, s.P, sky_row);
                E = vec3(p->Er[i], p->Eg[i], p->Eb[i]);
            }
            shade_horizon h;
            vec3 specular = pixel_specular(u, p, i, s.Ks, s.alpha, s.rotation, s.Fenv, env_shadow, &h, task, trace);
            vec3 across = sl_shade_horizon_visible(u, &h, s.P, s.N, trace);
            color = sl_shade_surface_color(u, &s, &E, &specular, &across, env_shadow, task, trace);
        }
        if (vector_sum && shadowed && t[i].depth >= 1.0f)
            lr[i] = lg[i] = lb[i] = 0.0f; /* read (and selected away) by sum_stage */
        if (vector_sum && u->skyMaps && t[i].depth >= 1.0f)
            ar[i] = ag[i] = ab[i] = 0.0f; /* likewise */
        if (vector_sum) {
            cr[i] = color.x;
            cg[i] = color.y;
            cb[i] = color.z;
        } else {
            out[i] = sl_shade_finish(color, task, trace);
        }
    }
    if (across_maps.n > 0) { /* scale(h.sum, v) */
        float v[SPAN];
        const shadow_points *at = &across_maps.at;
        sl_shadow_sky_cell_visibility_lanes(u->skyMaps, across_maps.n, across_maps.dx, across_maps.dy, across_maps.dz,
                                            at->px, at->py, at->pz, at->nx, at->ny, at->nz, v);
        for (int k = 0; k < across_maps.n; k++) {
            const int i = at->pixel[k];
            ar[i] = across_maps.r[k] * v[k], ag[i] = across_maps.g[k] * v[k], ab[i] = across_maps.b[k] * v[k];
        }
    }
    if (vector_sum)
        sum_stage(u, gb, t, x0, y, count, p, cr, cg, cb, shadowed ? lr : cr, shadowed ? lg : cg, shadowed ? lb : cb,
                  u->skyMaps ? ar : cr, u->skyMaps ? ag : cg, u->skyMaps ? ab : cb, task,
                  out); /* without maps l{r,g,b} and a{r,g,b} are read and selected away: never an unset array */
}
