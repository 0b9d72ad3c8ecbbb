/* lighting.c - the lighting shader: a line-by-line C port of shaders/lighting.frag.
 *
 * Every function tagged with a comment line of its own, exactly `/ * GLSL: name * /` (without the
 * spaces) right above it, is the GLSL function of that name, in the GLSL file's order, with the
 * same variable names; a uniform uX is u->uX. One tag per GLSL function: main's two helpers say
 * "Part of GLSL main"; the BRDF (brdf.h) and lobe_param (lighting_internal.h) are tagged where
 * they live, and the functions ported in src/ibl (the lat-long map, the octahedral layout, the
 * irradiance maps) have a tag here, at their place in the order, that says where they are.
 * tests/cli/maps.sh checks the tags against the GLSL's functions and order.
 *
 * This is the reference path: it runs when options.plain is set (the debug switch,
 * docs/lighting.md "Two paths") and is what a reader compares with the GLSL. The C-only lines are the trace hooks and counters (lighting_internal.h:
 * a pixel's trace is filled at a few named points, a no-op when the trace is NULL) and main()'s
 * split in three (sl_shade_plain, then sl_shade_surface_color for a covered pixel's sum and
 * sl_shade_finish for the NaN guard), so the batched path (lighting_batched.c) shares all but the
 * specular loops. It also reuses the sample generators exported at the end.
 *
 * Does not: run over a G-buffer (lighting_pass.c), build uniforms (lighting_uniforms.c). */
#include <math.h>

#include "../ibl/texture_lod.h"
#include "lighting_internal.h"
#include "occlusion/specular_occlusion.h"

/* GLSL constants, same names and values. */
static const int LOD_NONE = SL_LOD_NONE;
static const int LOD_SPEC = SL_LOD_SPEC;
static const int LOD_SPEC_D4 = SL_LOD_SPEC_D4;
static const int LOD_GEMS = SL_LOD_GEMS;
static const int ESTIMATOR_CONSISTENT = SL_ESTIMATOR_CONSISTENT;
static const int ESTIMATOR_MICROFACET = SL_ESTIMATOR_MICROFACET;
static const int ENV_LAYOUT_OCT = SL_ENV_LAYOUT_OCT;
static const int ESTIMATOR_SPLITSUM = SL_ESTIMATOR_SPLITSUM;
static const int ESTIMATOR_MIS = SL_ESTIMATOR_MIS;
static const int ESTIMATOR_CV = SL_ESTIMATOR_CV;
static const int ESTIMATOR_CV_MIS = SL_ESTIMATOR_CV_MIS;
static const int GTERM_INV_LH2 = SL_GTERM_INV_LH2;
static const int SPLITSUM_LUT_SIZE = SL_SPLITSUM_LUT_SIZE;
static const int SPLITSUM_SETS = SL_SPLITSUM_SETS;
static const int SPLITSUM_PHONG_INV_LH2 = SL_SPLITSUM_PHONG_INV_LH2;
static const int SPLITSUM_PHONG_ONE = SL_SPLITSUM_PHONG_ONE;
static const int SPLITSUM_GGX = SL_SPLITSUM_GGX;
static const float MIN_NDOTV = SHADE_MIN_NDOTV;
static const float POLE_EPS = SHADE_POLE_EPS;
static const float TINY = SL_BRDF_TINY;
static const float MIN_LIGHT_D2 = 1e-8f;
#define PI SL_PI

/* GLSL: sl_dir_to_uv, ported in src/ibl (latlong.c, and inline in texture_lod.h) */
/* GLSL: sl_uv_to_dir, ported in src/ibl (latlong.c) */
/* The BRDF's functions, sl_brdf_D to sl_lobe_G, are in brdf.h, tagged there. */

/* GLSL: ggx_cos_theta */
static float ggx_cos_theta(float xi2, float a2)
{
    return sqrtf((1.0f - xi2) / ((1.0f - xi2) + a2 * xi2));
}

/* GLSL: ggx_D_of_xi */
static float ggx_D_of_xi(float xi2, float a2)
{
    float t = (1.0f - xi2) + a2 * xi2;
    return t * t / (PI * a2);
}

/* GLSL: hammersley_point */
static vec2 hammersley_point(const sl_lighting_uniforms *u, int k)
{
    vec4 h = u->uHammersley.hammersley[k >> 1];
    return ((k & 1) == 0) ? vec2(h.x, h.y) : vec2(h.z, h.w);
}

/* hash_u32: Wellons' lowbias32: two multiply-xorshift rounds, full avalanche */
/* GLSL: hash_u32 */
static uint32_t hash_u32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

/* GLSL: pixel_rotation */
static vec2 pixel_rotation(const sl_lighting_uniforms *u, int x, int y)
{
    uint32_t h = hash_u32((uint32_t)x + hash_u32((uint32_t)y + hash_u32(u->uFrame + 0x9e3779b9u)));
    uint32_t h2 = hash_u32(h + 0x68e31da4u);
    return vec2((float)(h >> 8) * (1.0f / 16777216.0f), (float)(h2 >> 8) * (1.0f / 16777216.0f));
}

/* GLSL: skewed_sample */
static vec3 skewed_sample(vec2 xi, float alpha)
{
    float c = sl_lobe_is_ggx(alpha) ? ggx_cos_theta(xi.y, sl_ggx_a2(alpha)) : powf(xi.y, 1.0f / (alpha + 1.0f));
    vec2 uv = vec2(xi.x, acosf(clamp(c, -1.0f, 1.0f)) / PI);
    return sl_uv_to_dir(uv);
}

/* GLSL: sample_pdf */
static float sample_pdf(vec2 xi, float alpha)
{
    if (sl_lobe_is_ggx(alpha)) {
        float a2 = sl_ggx_a2(alpha);
        return ggx_D_of_xi(xi.y, a2) * ggx_cos_theta(xi.y, a2);
    }
    return (alpha + 1.0f) / (2.0f * PI) * powf(xi.y, alpha / (alpha + 1.0f));
}

/* GLSL: mip_level (alpha: the lobe, whose set has its rule) */
static float mip_level(const sl_lighting_uniforms *u, float alpha, float D, float pdf, vec3 w)
{
    const int rule = shade_lod_rule_of(u, alpha), distortion = shade_distortion_of(u, alpha);
    if (rule == LOD_NONE)
        return 0.0f;
    float d = 1.0f;
    if (distortion != 0 && u->uEnvLayout == ENV_LAYOUT_OCT) {
        float l1 = fabsf(w.x) + fabsf(w.y) + fabsf(w.z);
        d = l1 * l1 * l1 / PI;
    } else if (distortion != 0) {
        d = 0.5f * PI * maxf(sqrtf(maxf(1.0f - w.z * w.z, 0.0f)), u->uSinThetaMin);
    }
    float lod;
    if (rule == LOD_SPEC)
        lod = u->uLodBase - 0.5f * log2f(maxf(D * d, TINY));
    else if (rule == LOD_SPEC_D4)
        lod = u->uLodBase - 0.5f * log2f(maxf(D / 4.0f * d, TINY));
    else if (rule == LOD_GEMS)
        lod = u->uLodBase - 0.5f * log2f(maxf(4.0f * PI * pdf * d, TINY)) + 1.0f;
    else
        lod = u->uLodBase - 0.5f * log2f(maxf(4.0f * PI * pdf * d, TINY));
    return clamp(lod, 0.0f, u->uEnvMaxLod);
}

/* env_lod: the octahedral branch is texture_lod.h's sl_oct_texture_lod: env_oct_uv, then
 * the trilinear filter of env_oct_bilinear */
/* GLSL: env_oct_uv, ported in src/ibl/texture_lod.h (the octahedral chain's fetch) */
/* GLSL: env_oct_tap, ported in src/ibl/texture_lod.h */
/* GLSL: env_oct_bilinear, ported in src/ibl/texture_lod.h */

/* GLSL: env_lod (alpha: the lobe, whose set's samples read the residual or, where the env
 * lights are the GGX set's alone, a Phong lobe's the whole map) */
static vec3 env_lod(const sl_lighting_uniforms *u, float alpha, vec3 w, float lod)
{
    const sl_env *chain = shade_samples_chain(u, alpha);
    if (u->uEnvLayout == ENV_LAYOUT_OCT)
        return sl_oct_texture_lod(chain, w, lod);
    return textureLod(chain, sl_dir_to_uv(w), lod);
}

/* lobe_param is in lighting_internal.h (shade_lobe_param), tagged there. */

/* GLSL: facing_normal */
static vec3 facing_normal(vec3 N, vec3 V)
{
    float len2 = dot(N, N);
    if (!(len2 > TINY))
        return V;
    N = scale(N, 1.0f / sqrtf(len2));
    float NdotV = dot(N, V);
    if (NdotV < MIN_NDOTV)
        N = normalize(add(N, scale(V, MIN_NDOTV - NdotV)));
    return N;
}

/* irradiance: sl_irradiance_eval (src/ibl/irradiance.c) is both branches: the SH9 sum
 * over uSH and the map lookup of uIrradianceMap. */
/* GLSL: irradiance_grid_coord, ported in src/ibl/irradiance_uv.h (sl_irradiance_grid_coord) */
/* GLSL: irradiance_oct_uv, ported in src/ibl/irradiance_uv.h and irradiance_map.c */
/* GLSL: irradiance_dp_uv, ported in src/ibl/irradiance_uv.h and irradiance_map.c */

/* GLSL: irradiance */
static vec3 irradiance(const sl_lighting_uniforms *u, vec3 N)
{
    return sl_irradiance_eval(u->uIrradiance, N);
}

/* GLSL: specular_ibl */
static vec3 specular_ibl(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation,
                         shade_horizon *h, sl_lighting_task *task, sl_lighting_trace *trace)
{
    float NdotV = dot(N, V);
    vec3 R = normalize(sub(scale(N, 2.0f * NdotV), V));
    vec3 axis = (R.x * R.x + R.y * R.y < POLE_EPS) ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 0.0f, 1.0f);
    vec3 A = normalize(cross(axis, R));
    vec3 B = normalize(cross(R, A));
    int n = (int)u->uHammersley.N;
    vec3 sum = vec3s(0.0f);
    int below = 0;
    trace_sample_frame(trace, N, V, A, B, axis.x == 1.0f, n, false);
    for (int k = 0; k < n; k++) {
        vec2 xi = hammersley_point(u, k);
        if (u->uRotate != 0)
            xi = vec2(fract(xi.x + rotation.x), fract(xi.y + rotation.y));
        vec3 L = skewed_sample(xi, alpha);
        float pdf = sample_pdf(xi, alpha);
        vec3 w = normalize(add(add(scale(A, L.x), scale(B, L.y)), scale(R, L.z)));
        float wN = dot(w, N);
        bool hidden = shade_facet_hides(h, w);
        if (wN <= 0.0f || hidden) {
            below++;
            trace_sample(trace, k,
                         &(sl_lighting_trace_sample){.xi = xi, .L = L, .pdf = pdf, .w = w, .wN = wN, .hidden = hidden,
                                                     .sum = sum});
            continue;
        }
        vec3 H = normalize(add(w, V));
        float NdotH = dot(N, H);
        float LdotH = dot(w, H);
        float D = sl_lobe_D(NdotH, alpha);
        vec3 F = sl_brdf_F(Ks, LdotH);
        float G = sl_lobe_G(LdotH, wN, NdotV, alpha, (sl_gterm)u->uGTerm);
        float lod = mip_level(u, alpha, D, pdf, w);
        vec3 Li = scale(env_lod(u, alpha, w, lod), u->uEnvIntensity);
        float weight = G * wN / 4.0f;
        if (shade_estimator_of(u, alpha) == ESTIMATOR_CONSISTENT)
            weight = weight * D / pdf;
        vec3 c = scale(mul(F, Li), weight);
        int glow;
        c = shade_glow(h, w, c, &glow);
        bool across = shade_horizon_across(h, w);
        if (across)
            shade_horizon_add(h, w, c);
        else
            sum = add(sum, c);
        trace_sample(trace, k,
                     &(sl_lighting_trace_sample){.xi = xi, .L = L, .pdf = pdf, .w = w, .wN = wN, .H = H, .NdotH = NdotH,
                                                 .LdotH = LdotH, .D = D, .F = F, .G = G, .lod = lod, .Li = Li, .c = c,
                                                 .across = across, .glow = glow + 1, .sum = sum});
    }
    count_samples(task, n, below, axis.x == 1.0f);
    h->sum = scale(h->sum, 1.0f / (float)(n > 1 ? n : 1));
    return scale(sum, 1.0f / (float)(n > 1 ? n : 1));
}

/* GLSL: microfacet_sample */
static vec3 microfacet_sample(vec2 xi, float alpha)
{
    float c = sl_lobe_is_ggx(alpha) ? ggx_cos_theta(xi.y, sl_ggx_a2(alpha)) : powf(xi.y, 1.0f / (alpha + 2.0f));
    vec2 uv = vec2(xi.x, acosf(clamp(c, -1.0f, 1.0f)) / PI);
    return sl_uv_to_dir(uv);
}

/* GLSL: microfacet_D */
static float microfacet_D(vec2 xi, float alpha)
{
    if (sl_lobe_is_ggx(alpha))
        return ggx_D_of_xi(xi.y, sl_ggx_a2(alpha));
    return (alpha + 2.0f) / (2.0f * PI) * powf(xi.y, alpha / (alpha + 2.0f));
}

/* GLSL: ggx_visible_normal (the derivation is in the GLSL) */
static vec3 ggx_visible_normal(vec2 xi, vec3 Vh, float a)
{
    float phi = 2.0f * PI * (0.5f - xi.x);
    float z = (1.0f - xi.y) * (1.0f + Vh.z) - Vh.z;
    float st = sqrtf(clamp(1.0f - z * z, 0.0f, 1.0f));
    vec3 h = add(vec3(st * cosf(phi), st * sinf(phi), z), Vh);
    vec3 H = vec3(a * h.x, a * h.y, h.z);
    return scale(H, 1.0f / maxf(length(H), TINY));
}

/* GLSL: ggx_stretched_view */
static vec3 ggx_stretched_view(vec3 Vl, float a) { return normalize(vec3(a * Vl.x, a * Vl.y, Vl.z)); }

/* GLSL: ggx_visible_norm */
static float ggx_visible_norm(float NdotV, float a2)
{
    return 2.0f * (NdotV + sqrtf(NdotV * NdotV * (1.0f - a2) + a2));
}

/* specular_microfacet: the derivation is in the GLSL. The trace records a sample's H,
 * N.H, V.H (as L.H) and D before the test, its p(w) after it. cv: the control variate's kernel,
 * whose K(w) / p(w) beta E Li every sample subtracts (NULL for the mf estimator; specular_cv). */
/* GLSL: specular_microfacet */
static vec3 specular_microfacet(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation,
                                const sl_cv_kernel *cv, shade_horizon *h, sl_lighting_task *task,
                                sl_lighting_trace *trace)
{
    float NdotV = dot(N, V);
    vec3 axis = (N.x * N.x + N.y * N.y < POLE_EPS) ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 0.0f, 1.0f);
    vec3 A = normalize(cross(axis, N));
    vec3 B = normalize(cross(N, A));
    /* GGX: the stretched view and the visible normals' norm, once a pixel (a Phong lobe reads neither) */
    const bool ggx = sl_lobe_is_ggx(alpha);
    const float a2 = ggx ? sl_ggx_a2(alpha) : 0.0f, a = sqrtf(a2);
    const vec3 Vh = ggx ? ggx_stretched_view(vec3(dot(V, A), dot(V, B), NdotV), a) : vec3s(0.0f);
    const float norm = ggx ? ggx_visible_norm(NdotV, a2) : 1.0f;
    int n = (int)u->uHammersley.N;
    vec3 sum = vec3s(0.0f);
    int below = 0;
    trace_sample_frame(trace, N, V, A, B, axis.x == 1.0f, n, true);
    for (int k = 0; k < n; k++) {
        vec2 xi = hammersley_point(u, k);
        if (u->uRotate != 0)
            xi = vec2(fract(xi.x + rotation.x), fract(xi.y + rotation.y));
        vec3 Hl = ggx ? ggx_visible_normal(xi, Vh, a) : microfacet_sample(xi, alpha);
        float D = ggx ? sl_ggx_D(Hl.z, a2) : microfacet_D(xi, alpha);
        vec3 H = normalize(add(add(scale(A, Hl.x), scale(B, Hl.y)), scale(N, Hl.z)));
        float VdotH = dot(V, H);
        vec3 w = normalize(sub(scale(H, 2.0f * VdotH), V));
        float wN = dot(w, N);
        bool hidden = shade_facet_hides(h, w);
        bool lit = wN > 0.0f && !hidden;
        if (VdotH <= 0.0f || !lit)
            below++;
        if (VdotH <= 0.0f || (!lit && !cv)) {
            trace_sample(trace, k,
                         &(sl_lighting_trace_sample){.xi = xi, .L = Hl, .w = w, .wN = wN, .H = H, .NdotH = Hl.z,
                                                     .LdotH = VdotH, .D = D, .hidden = hidden, .sum = sum});
            continue;
        }
        float NdotH = Hl.z;
        float pdf = ggx ? D / norm : D * NdotH / (4.0f * VdotH);
        vec3 F = sl_brdf_F(Ks, VdotH);
        float G = sl_lobe_G(VdotH, wN, NdotV, alpha, (sl_gterm)u->uGTerm);
        float lod = mip_level(u, alpha, D, pdf, w);
        vec3 Li = scale(env_lod(u, alpha, w, lod), u->uEnvIntensity);
        float weight = ggx ? G * wN * norm / 4.0f : G * wN * VdotH / NdotH;
        vec3 c = lit ? scale(mul(F, Li), weight) : vec3s(0.0f);
        float kp = 0.0f;
        if (cv) { /* below the horizon too: the kernel reaches there, the BRDF does not */
            kp = sl_cv_kernel_eval(u, cv, dot(w, cv->dir)) / pdf;
            c = sub(c, scale(mul(cv->scale, Li), kp));
        }
        int glow;
        c = shade_glow(h, w, c, &glow);
        bool across = shade_horizon_across(h, w);
        if (across)
            shade_horizon_add(h, w, c);
        else
            sum = add(sum, c);
        trace_sample(trace, k,
                     &(sl_lighting_trace_sample){.xi = xi, .L = Hl, .pdf = pdf, .w = w, .wN = wN, .H = H,
                                                 .NdotH = NdotH, .LdotH = VdotH, .D = D, .F = F, .G = G, .lod = lod,
                                                 .Li = Li, .c = c, .cv_kp = kp, .hidden = hidden, .across = across,
                                                 .glow = glow + 1, .sum = sum});
    }
    count_samples(task, n, below, axis.x == 1.0f);
    h->sum = scale(h->sum, 1.0f / (float)(n > 1 ? n : 1));
    return scale(sum, 1.0f / (float)(n > 1 ? n : 1));
}

/* GLSL's min and clamp of ints */
static inline int mini(int a, int b) { return a < b ? a : b; }
static inline int clampi(int x, int lo, int hi) { return x < lo ? lo : x > hi ? hi : x; }

/* env_texel: the level-0 texel of uEnvResidual holding w (its size is textureSize's). */
/* GLSL: env_texel */
static ivec2 env_texel(const sl_lighting_uniforms *u, vec3 w)
{
    vec2 uv = sl_dir_to_uv(w);
    const sl_env_level *l0 = &u->uEnvResidual->levels[0];
    return ivec2(mini((int)(uv.x * (float)l0->width), l0->width - 1), mini((int)(uv.y * (float)l0->height), l0->height - 1));
}

/* GLSL: env_dist_pdf */
static float env_dist_pdf(const sl_lighting_uniforms *u, ivec2 t)
{
    const sl_env_dist *d = u->uEnvDist;
    return d->density[(size_t)(t.y >> u->uEnvDistShift) * (size_t)d->width + (size_t)(t.x >> u->uEnvDistShift)];
}

/* env_dist_sample: texelFetch(uEnvDistMarginal, (j, 0)) is marginal[j], texelFetch(uEnvDist,
 * (i, j)) is (cdf, density)[j W + i]. */
/* GLSL: env_dist_sample */
static vec4 env_dist_sample(const sl_lighting_uniforms *u, vec2 xi, ivec2 *texel)
{
    const sl_env_dist *d = u->uEnvDist;
    ivec2 size = ivec2(d->width, d->height);
    int lo = 0;
    int hi = size.y - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (d->marginal[mid] > xi.y)
            hi = mid;
        else
            lo = mid + 1;
    }
    int j = lo;
    float m0 = j > 0 ? d->marginal[j - 1] : 0.0f;
    float m1 = d->marginal[j];
    float t = (xi.y - m0) / (m1 - m0);
    const float *cdf = d->cdf + (size_t)j * (size_t)size.x;
    lo = 0;
    hi = size.x - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (cdf[mid] > xi.x)
            hi = mid;
        else
            lo = mid + 1;
    }
    int i = lo;
    float c0 = i > 0 ? cdf[i - 1] : 0.0f;
    float c1 = cdf[i];
    float s = (xi.x - c0) / (c1 - c0);
    float z0 = cosf(PI * (float)j / (float)size.y);
    float z1 = cosf(PI * (float)(j + 1) / (float)size.y);
    float z = z0 + (z1 - z0) * t;
    float uu = ((float)i + s) / (float)size.x;
    float phi = 2.0f * PI * (0.5f - uu);
    float st = sqrtf(maxf(1.0f - z * z, 0.0f));
    vec3 w = vec3(cosf(phi) * st, sinf(phi) * st, z);
    int f = 1 << u->uEnvDistShift;
    const sl_env_level *l0 = &u->uEnvResidual->levels[0];
    int i0 = (int)(uu * (float)l0->width);
    int j0 = (int)(acosf(clamp(z, -1.0f, 1.0f)) / PI * (float)l0->height);
    *texel = ivec2(clampi(i0, i * f, i * f + f - 1), clampi(j0, j * f, j * f + f - 1));
    return vec4_from3(w, d->density[(size_t)j * (size_t)size.x + (size_t)i]);
}

/* GLSL: mis_power */
static float mis_power(float p, float q)
{
    float r = q / maxf(p, TINY);
    return 1.0f / (1.0f + r * r);
}

/* texelFetch(uEnvResidual, t, 0): level 0's texel t */
static vec3 env_texel_fetch(const sl_lighting_uniforms *u, ivec2 t)
{
    const sl_env_level *l0 = &u->uEnvResidual->levels[0];
    return l0->texels[(size_t)t.y * (size_t)l0->width + (size_t)t.x];
}

/* specular_mis: the derivation is in the GLSL. The trace records the BRDF's sample of pair k in
 * samples[k] (as specular_microfacet does) and the environment's in env_samples[k], each with
 * its own density (pdf), the other strategy's (pdf_other) and its weight (mis). cv: the control
 * variate's kernel, whose beta E K(w) Li / p(w) times the weight every sample subtracts, below
 * the horizon too (NULL for the mis estimator; specular_cv for cvmis). */
/* GLSL: specular_mis */
static vec3 specular_mis(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation,
                         const sl_cv_kernel *cv, shade_horizon *h, sl_lighting_task *task, sl_lighting_trace *trace)
{
    float NdotV = dot(N, V);
    vec3 axis = (N.x * N.x + N.y * N.y < POLE_EPS) ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 0.0f, 1.0f);
    vec3 A = normalize(cross(axis, N));
    vec3 B = normalize(cross(N, A));
    int n = (int)u->uHammersley.N;
    float half_ = 0.5f / (float)(n > 1 ? n : 1);
    vec3 sum = vec3s(0.0f);
    int below = 0;
    trace_sample_frame(trace, N, V, A, B, axis.x == 1.0f, n, true);
    trace_mis(trace);
    for (int k = 0; k < n; k++) {
        vec2 xi = hammersley_point(u, k);
        if (u->uRotate != 0)
            xi = vec2(fract(xi.x + rotation.x), fract(xi.y + rotation.y));
        vec3 Hl = microfacet_sample(xi, alpha);
        float D = microfacet_D(xi, alpha);
        vec3 H = normalize(add(add(scale(A, Hl.x), scale(B, Hl.y)), scale(N, Hl.z)));
        float VdotH = dot(V, H);
        vec3 w = normalize(sub(scale(H, 2.0f * VdotH), V));
        float wN = dot(w, N);
        bool hidden = shade_facet_hides(h, w);
        bool lit = wN > 0.0f && !hidden;
        if (VdotH > 0.0f && (lit || cv)) {
            float NdotH = Hl.z;
            float pdf = D * NdotH / (4.0f * VdotH);
            ivec2 t = env_texel(u, w);
            float pe = env_dist_pdf(u, t);
            float mis = mis_power(pdf, pe);
            vec3 F = sl_brdf_F(Ks, VdotH);
            float G = sl_lobe_G(VdotH, wN, NdotV, alpha, (sl_gterm)u->uGTerm);
            vec3 Li = scale(env_texel_fetch(u, t), u->uEnvIntensity);
            float weight = lit ? G * wN * VdotH / NdotH * mis : 0.0f;
            vec3 c = scale(mul(F, Li), weight);
            float kp = 0.0f;
            if (cv) {
                kp = sl_cv_kernel_eval(u, cv, dot(w, cv->dir)) / pdf;
                c = sub(c, scale(mul(cv->scale, Li), kp * mis));
            }
            below += !lit;
            int glow;
            c = shade_glow(h, w, c, &glow);
            bool across = shade_horizon_across(h, w);
            if (across)
                shade_horizon_add(h, w, c);
            else
                sum = add(sum, c);
            trace_sample(trace, k,
                         &(sl_lighting_trace_sample){.xi = xi, .L = Hl, .pdf = pdf, .pdf_other = pe, .mis = mis, .w = w,
                                                     .wN = wN, .H = H, .NdotH = NdotH, .LdotH = VdotH, .D = D, .F = F,
                                                     .G = G, .Li = Li, .c = c, .cv_kp = kp, .hidden = hidden,
                                                     .across = across, .glow = glow + 1, .sum = sum});
        } else {
            below++;
            trace_sample(trace, k,
                         &(sl_lighting_trace_sample){.xi = xi, .L = Hl, .w = w, .wN = wN, .H = H, .NdotH = Hl.z,
                                                     .LdotH = VdotH, .D = D, .hidden = hidden, .sum = sum});
        }
        ivec2 te;
        vec2 xe = vec2(fract(xi.x + half_), xi.y);
        vec4 e = env_dist_sample(u, xe, &te);
        vec3 we = xyz(e);
        float weN = dot(we, N);
        vec3 He = normalize(add(we, V));
        float NdotHe = dot(N, He);
        float LdotHe = dot(we, He);
        bool hidden_e = shade_facet_hides(h, we);
        bool lit_e = weN > 0.0f && NdotHe > 0.0f && LdotHe > 0.0f && !hidden_e;
        if (lit_e || cv) {
            /* the BRDF's density of we: 0 where its draws cannot reach (N.H <= 0 or w.H <= 0) */
            bool reached = NdotHe > 0.0f && LdotHe > 0.0f;
            float De = reached ? sl_lobe_D(NdotHe, alpha) : 0.0f;
            float pb = reached ? De * NdotHe / (4.0f * LdotHe) : 0.0f;
            float mis = mis_power(e.w, pb);
            vec3 F = sl_brdf_F(Ks, LdotHe);
            float G = lit_e ? sl_lobe_G(LdotHe, weN, NdotV, alpha, (sl_gterm)u->uGTerm) : 0.0f;
            vec3 Li = scale(env_texel_fetch(u, te), u->uEnvIntensity);
            float weight = lit_e ? De * G * weN / (4.0f * e.w) * mis : 0.0f;
            vec3 c = scale(mul(F, Li), weight);
            float kp = 0.0f;
            if (cv) {
                kp = sl_cv_kernel_eval(u, cv, dot(we, cv->dir)) / e.w;
                c = sub(c, scale(mul(cv->scale, Li), kp * mis));
            }
            below += !lit_e;
            int glow;
            c = shade_glow(h, we, c, &glow);
            bool across = shade_horizon_across(h, we);
            if (across)
                shade_horizon_add(h, we, c);
            else
                sum = add(sum, c);
            trace_env_sample(trace, k,
                             &(sl_lighting_trace_sample){.xi = xe, .pdf = e.w, .pdf_other = pb, .mis = mis, .w = we,
                                                         .wN = weN, .H = He, .NdotH = NdotHe, .LdotH = LdotHe, .D = De,
                                                         .F = F, .G = G, .Li = Li, .c = c, .cv_kp = kp,
                                                         .hidden = hidden_e, .across = across, .glow = glow + 1,
                                                         .sum = sum});
        } else {
            below++;
            trace_env_sample(trace, k,
                             &(sl_lighting_trace_sample){.xi = xe, .pdf = e.w, .w = we, .wN = weN, .H = He,
                                                         .NdotH = NdotHe, .LdotH = LdotHe, .hidden = hidden_e,
                                                         .sum = sum});
        }
    }
    count_samples(task, 2 * n, below, axis.x == 1.0f);
    h->sum = scale(h->sum, 1.0f / (float)(n > 1 ? n : 1));
    return scale(sum, 1.0f / (float)(n > 1 ? n : 1));
}

/* splitsum_width: brdf.h's sl_splitsum_width, GGX's roughness or the Phong exponent's equal-peak one */
/* GLSL: splitsum_width */
static float splitsum_width(float alpha)
{
    return sl_splitsum_width(alpha);
}

/* splitsum_lut: texture() of the table at the texel centres of set `set`: N.V = i / (S - 1)
 * is column i, r = j / (S - 1) row set S + j (splitsum_lut.h). A, B, t and the control
 * variate's beta, the four values of one texel (GL's RGBA). */
/* GLSL: splitsum_lut */
static vec4 splitsum_lut(const sl_lighting_uniforms *u, int set, float NdotV, float r)
{
    enum { W = SL_SPLITSUM_LUT_SIZE, H = SL_SPLITSUM_SETS * SL_SPLITSUM_LUT_SIZE };
    float s = (float)SPLITSUM_LUT_SIZE;
    vec2 uv = vec2((clamp(NdotV, 0.0f, 1.0f) * (s - 1.0f) + 0.5f) / s,
                   ((float)set * s + clamp(r, 0.0f, 1.0f) * (s - 1.0f) + 0.5f) / (s * (float)SPLITSUM_SETS));
    vec3 abt = sl_texels_bilinear(u->uSplitSumLut->texels, W, H, 0, uv.x, uv.y);
    /* beta at the same taps (the uv stays within the texel centres: no wrap) */
    const sl_latlong_taps t = sl_latlong_taps_at(W, H, uv.x, uv.y);
    const float *b = u->uSplitSumLut->beta;
    int x1 = t.x0 + 1 < W ? t.x0 + 1 : t.x0;
    float beta = mix(mix(b[t.y0 * W + t.x0], b[t.y0 * W + x1], t.fx), mix(b[t.y1 * W + t.x0], b[t.y1 * W + x1], t.fx),
                     t.fy);
    return vec4_from3(abt, beta);
}

/* splitsum_dir: the lookup direction normalize(mix(N, R, t)), t the table's (splitsum_lut.h):
 * the lobe's centroid, which leans from R towards N away from normal view */
/* GLSL: splitsum_dir */
static vec3 splitsum_dir(vec3 N, vec3 R, float t)
{
    return normalize(add(scale(N, 1.0f - t), scale(R, t)));
}

/* splitsum_lookup: the split sum's prefiltered radiance for the pixel (before the intensity):
 * the chain of the lobe's set read along the lobe's centroid at the lobe's level; the table's
 * A, B and t in ab. */
/* GLSL: splitsum_lookup */
static vec3 splitsum_lookup(const sl_lighting_uniforms *u, vec3 N, vec3 V, float alpha, vec3 *ab,
                            sl_lighting_trace *trace)
{
    float NdotV = dot(N, V);
    vec3 R = normalize(sub(scale(N, 2.0f * NdotV), V));
    float r = splitsum_width(alpha);
    float lod = r * u->uSplitSumMaxLod;
    int set = sl_lobe_is_ggx(alpha) ? SPLITSUM_GGX : u->uGTerm == GTERM_INV_LH2 ? SPLITSUM_PHONG_INV_LH2 : SPLITSUM_PHONG_ONE;
    *ab = xyz(splitsum_lut(u, set, NdotV, r));
    vec3 dir = splitsum_dir(N, R, ab->z);
    vec2 uv = sl_dir_to_uv(dir);
    vec3 P = sl_lobe_is_ggx(alpha) ? textureLod(u->uSplitSumGGX, uv, lod) : textureLod(u->uSplitSumPhong, uv, lod);
    trace_splitsum(trace, N, V, R, r, lod, dir, P, *ab);
    return P;
}

/* specular_splitsum: The split-sum approximation (Karis 2013): the environment
 * prefiltered with the lobe at N = V = R (src/ibl/prefilter.c), read along the lobe's centroid
 * at the lobe's level, times the BRDF's albedo Ks A + B (splitsum_lut.h). No samples. */
/* GLSL: specular_splitsum */
static vec3 specular_splitsum(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha,
                              sl_lighting_trace *trace)
{
    vec3 ab;
    vec3 P = splitsum_lookup(u, N, V, alpha, &ab, trace);
    return scale(mul(P, add(scale(Ks, ab.x), vec3s(ab.y))), u->uEnvIntensity);
}

/* chain_catmull_rom: level `level` of a chain read with the Catmull-Rom filter (texture_lod.h
 * sl_env_catmull_rom; GLSL: 16 texelFetch) */
/* GLSL: chain_catmull_rom */
static vec3 chain_catmull_rom(const sl_env *chain, int level, vec2 uv)
{
    return sl_env_catmull_rom(&chain->levels[level], uv.x, uv.y);
}

/* cv_setup: the control variate's kernel for the pixel (docs/lighting.md "Control variate"). The
 * chain's exact levels (prefilter.c) hold the integral of the environment against a known kernel
 * k about the lookup direction, so with K = ca k_a + cb k_b the part of the read that is exact
 * (sl_cv_levels) and E = Ks A + B the albedo,
 *     integral of f (N.w) L = beta E (ca C_a + cb C_b) + integral of (f (N.w) - beta E K) L.
 * This is what the samples subtract: the kernel's axis, levels and shares, and beta E. */
/* GLSL: cv_setup */
static sl_cv_kernel cv_setup(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha)
{
    sl_cv_kernel cv;
    float NdotV = dot(N, V);
    cv.R = normalize(sub(scale(N, 2.0f * NdotV), V));
    cv.r = splitsum_width(alpha);
    cv.lod = cv.r * u->uSplitSumMaxLod;
    cv.set = sl_lobe_is_ggx(alpha) ? SPLITSUM_GGX : u->uGTerm == GTERM_INV_LH2 ? SPLITSUM_PHONG_INV_LH2 : SPLITSUM_PHONG_ONE;
    vec4 lut = splitsum_lut(u, cv.set, NdotV, cv.r);
    cv.ab = xyz(lut);
    cv.dir = splitsum_dir(N, cv.R, cv.ab.z);
    cv.levels = sl_cv_levels_at(cv.lod, (int)u->uSplitSumMaxLod, u->uSplitSumExactLevel);
    cv.beta = lut.w;
    cv.E = add(scale(Ks, cv.ab.x), vec3s(cv.ab.y));
    cv.scale = scale(cv.E, cv.beta);
    return cv;
}

/* cv_closed: the first term, beta E (ca C_a + cb C_b), times the intensity: the chain read along
 * the kernel's axis at its two levels, with the Catmull-Rom filter (the levels are exact at their
 * texel centres; the bilinear filter between them is not, on the coarse levels of the widest
 * lobes). N and V are the trace's. */
/* GLSL: cv_closed */
static vec3 cv_closed(const sl_lighting_uniforms *u, vec3 N, vec3 V, const sl_cv_kernel *cv, sl_lighting_trace *trace)
{
    vec2 uv = sl_dir_to_uv(cv->dir);
    const sl_env *chain = cv->set == SPLITSUM_GGX ? u->uSplitSumGGX : u->uSplitSumPhong;
    vec3 C = vec3s(0.0f);
    if (cv->levels.ca > 0.0f)
        C = add(C, scale(chain_catmull_rom(chain, cv->levels.la, uv), cv->levels.ca));
    if (cv->levels.cb > 0.0f)
        C = add(C, scale(chain_catmull_rom(chain, cv->levels.lb, uv), cv->levels.cb));
    trace_splitsum(trace, N, V, cv->R, cv->r, cv->lod, cv->dir, C, cv->ab);
    return scale(mul(cv->scale, C), u->uEnvIntensity);
}

/* specular_cv: the split sum as a control variate: the closed part plus the samples' estimate of
 * the rest, the microfacet estimator's, 1/N sum (F W - beta E K / p) Li, or with `mis` (the cvmis
 * estimator) mis's pairs, each sample's (f (N.w) - beta E K) Li / p times its power-heuristic
 * weight. The subtracted kernel follows L across the lobe, so where beta E K is close to the lobe
 * f (N.w) the samples pay only for the difference; beta (the table's) scales the kernel down where
 * it is not. Any beta leaves the expectation where the samples' estimator has it. With mis the
 * environment's draws find the small bright sources that the BRDF's miss, and the kernel takes
 * the smooth rest off both. */
/* GLSL: specular_cv */
static vec3 specular_cv(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation, bool mis,
                        shade_horizon *h, sl_lighting_task *task, sl_lighting_trace *trace)
{
    sl_cv_kernel cv = cv_setup(u, N, V, Ks, alpha);
    vec3 closed = cv_closed(u, N, V, &cv, trace);
    vec3 correction = mis ? specular_mis(u, N, V, Ks, alpha, rotation, &cv, h, task, trace)
                          : specular_microfacet(u, N, V, Ks, alpha, rotation, &cv, h, task, trace);
    trace_cv(trace, &cv, closed, correction);
    return add(closed, correction);
}

#define CELLS_PER_WIDTH ((float)SL_TEXEL_SPLIT_CELLS_PER_WIDTH)
#define NEAR_WIDTHS ((float)SL_ENV_LIGHT_NEAR_WIDTHS)

/* GLSL: env_light_split. Where the lobe is narrower than a few texels (a sharp lobe, or any lobe
 * seen at a grazing angle), one node a texel misses or overshoots its peak: the env lights whose
 * centroid lies near R are then read over cells of their texel, by the ground truth's rule
 * (core/options.h SL_TEXEL_SPLIT_*) but along each of the texel's axes apart. Reflected about a
 * facet spread by a (the lobe's width in H: GGX's a, or the Phong exponent's of equal peak), R
 * spreads 2 a in the plane of N and V (along B) and 2 a N.V across it (along T): at grazing view
 * the lobe is a sliver, and a texel needs many cells across it and fewer along it. Along it the
 * G term changes on a scale of N.V too (L.H and L.N are about N.V near R at grazing), hence the
 * cells' width 2 min(a, N.V) there; which lights are near is measured against the lobe's own
 * reach, 2 a. cells: the most any texel needs (1: no light is split). */
shade_env_light_split sl_shade_env_light_split(const sl_lighting_uniforms *u, vec3 N, vec3 V, float alpha)
{
    float a = sl_lobe_is_ggx(alpha) ? sqrtf(sl_ggx_a2(alpha)) : sqrtf(2.0f / (alpha + 2.0f));
    float NdotV = dot(N, V);
    float nv = clampf(NdotV, (float)SL_TEXEL_SPLIT_MIN_NV, 1.0f);
    float across = 2.0f * a * nv, along = 2.0f * minf(a, nv);
    shade_env_light_split split;
    split.R = sub(scale(N, 2.0f * NdotV), V);
    vec3 T = cross(N, V); /* N = V: the lobe is round, any T across R serves */
    float t = length(T);
    vec3 other = fabsf(split.R.z) < 0.9f ? vec3(0.0f, 0.0f, 1.0f) : vec3(1.0f, 0.0f, 0.0f);
    split.T = t > 1e-6f ? scale(T, 1.0f / t) : normalize(cross(split.R, other));
    split.B = cross(split.R, split.T);
    split.across = across;
    split.along = along;
    split.reach = 2.0f * a;
    split.side = u->uEnvLightSide;
    split.cells = (int)minf(ceilf(CELLS_PER_WIDTH * u->uEnvLightSide / across), (float)SL_TEXEL_SPLIT_MAX);
    split.cos_near = cosf(minf(NEAR_WIDTHS * split.reach + 2.0f * u->uEnvLightSide, SL_PI));
    return split;
}

/* GLSL: env_light_brdf. The BRDF of eq. (2) at unit w times w.N: 0 below the horizon and for
 * facets facing away (N.H <= 0). */
static vec3 env_light_brdf(const sl_lighting_uniforms *u, vec3 w, vec3 N, vec3 V, vec3 Ks, float alpha)
{
    float wN = dot(w, N);
    if (wN <= 0.0f)
        return vec3s(0.0f);
    vec3 H = normalize(add(w, V));
    float NdotH = dot(N, H);
    if (NdotH <= 0.0f)
        return vec3s(0.0f);
    float LdotH = dot(w, H);
    float G = sl_lobe_G(LdotH, wN, dot(N, V), alpha, (sl_gterm)u->uGTerm);
    return scale(sl_brdf_F(Ks, LdotH), sl_lobe_D(NdotH, alpha) * G / 4.0f * wN);
}

/* GLSL: env_light_near. Whether env light j's texel lies within NEAR_WIDTHS lobe widths of R
 * (2 a N.V across, 2 a along) along both of the lobe's axes, give or take two texels: R.l >
 * cos_near bounds it round R, then the offset l - R is measured along T and B (in radians, near
 * R). */
bool sl_shade_env_light_near(const shade_env_light_split *split, vec3 l)
{
    if (split->cells <= 1 || dot(split->R, l) <= split->cos_near)
        return false;
    vec3 q = sub(l, split->R);
    float t = maxf(fabsf(dot(q, split->T)) - 2.0f * split->side, 0.0f) / split->across;
    float b = maxf(fabsf(dot(q, split->B)) - 2.0f * split->side, 0.0f) / split->reach;
    return t * t + b * b < NEAR_WIDTHS * NEAR_WIDTHS;
}

/* GLSL: env_light_cells_along. The cells a texel side of length `side` along unit e needs: that
 * many cells per width of the lobe as e crosses it (T, B), 1 .. SL_TEXEL_SPLIT_MAX. */
static int env_light_cells_along(const shade_env_light_split *split, vec3 e, float side)
{
    float t = dot(e, split->T) / split->across, b = dot(e, split->B) / split->along;
    return (int)clampf(ceilf(CELLS_PER_WIDTH * side * sqrtf(t * t + b * b)), 1.0f, (float)SL_TEXEL_SPLIT_MAX);
}

/* GLSL: env_light_grid. The rows and columns of cells that env light j's texel is split into:
 * as many along each of its sides (its centroid's south and east) as the lobe's width across that
 * side asks. */
void sl_shade_env_light_grid(const sl_lighting_uniforms *u, int j, const shade_env_light_split *split, int *rows,
                             int *cols)
{
    vec3 c = xyz(u->uEnvLightDir[j]);
    float st = maxf(sqrtf(c.x * c.x + c.y * c.y), 1e-6f); /* sin(theta) of the centroid */
    vec3 east = vec3(-c.y / st, c.x / st, 0.0f), south = vec3(c.z * c.x / st, c.z * c.y / st, -st);
    *rows = env_light_cells_along(split, south, u->uEnvLightMeridian);
    *cols = env_light_cells_along(split, east, fabsf(u->uEnvLightAzimuth) * st);
}

/* GLSL: env_light_cells. Env light j's texel split into cells of equal solid angle (z = cos(theta)
 * and phi uniform over its box), as many along each of its sides as the lobe's width across that
 * side asks (env_light_split), the BRDF times the cosine read at each cell's middle, each cell
 * weighing its share of the texel's solid angle over its node weight (the radiance carries the
 * node weight). */
static vec3 env_light_cells(const sl_lighting_uniforms *u, int j, vec3 N, vec3 V, vec3 Ks, float alpha,
                            const shade_env_light_split *split)
{
    vec4 box = u->uEnvLightTexel[j];
    int rows, cols;
    sl_shade_env_light_grid(u, j, split, &rows, &cols);
    if (rows * cols == 1) /* the centroid, the better node */
        return env_light_brdf(u, xyz(u->uEnvLightDir[j]), N, V, Ks, alpha);
    vec3 sum = vec3s(0.0f);
    for (int b = 0; b < rows; b++) {
        float z = mixf(box.x, box.y, ((float)b + 0.5f) / (float)rows);
        float sz = sqrtf(maxf(1.0f - z * z, 0.0f));
        for (int a = 0; a < cols; a++) {
            float phi = box.z + u->uEnvLightAzimuth * ((float)a + 0.5f) / (float)cols;
            vec3 w = vec3(cosf(phi) * sz, sinf(phi) * sz, z);
            sum = add(sum, env_light_brdf(u, w, N, V, Ks, alpha));
        }
    }
    return scale(sum, u->uEnvLightRadiance[j].w / (float)(rows * cols));
}

/* specular_env_lights: Each env light is one texel's quadrature node (its centroid
 * direction w, its radiance times the node weight), so this is the ground truth's sum over
 * those texels: the BRDF of eq. (2) at w, times w.N, or over the texel's cells near a narrow
 * lobe's peak (env_light_split); 0 for a light below the horizon or under the facet (h's,
 * shade_facet_hides). */
/* GLSL: specular_env_lights (vis: each light's shadow-map visibility; NULL: all 1, the GLSL's
 * shadowed = false) */
static vec3 specular_env_lights(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, const float *vis,
                                const shade_horizon *h)
{
    shade_env_light_split split = sl_shade_env_light_split(u, N, V, alpha);
    vec3 sum = vec3s(0.0f);
    for (int j = 0; j < u->uEnvLightCount; j++) {
        vec3 w = xyz(u->uEnvLightDir[j]);
        if (dot(w, N) <= 0.0f || shade_facet_hides(h, w)) /* a light under the facet: its centroid's */
            continue;
        vec3 f = sl_shade_env_light_near(&split, w) ? env_light_cells(u, j, N, V, Ks, alpha, &split)
                                                    : env_light_brdf(u, w, N, V, Ks, alpha);
        float v = vis ? vis[j] : 1.0f; /* x 1 is exact: without maps, the same bits */
        sum = add(sum, scale(mul(f, xyz(u->uEnvLightRadiance[j])), v));
    }
    return scale(sum, u->uEnvIntensity);
}

/* GLSL: env_light_visibility. Each env light's visibility from world point P with normal N,
 * that of its cluster's map (src/shadow: sl_shadow_sun_visibility, lighting.frag's
 * shadow_sun_visibility), 1 for a light no map covers, 0 past the count (the batched path reads
 * whole vectors), into es->vis, and each map's into es->map_vis (the glow's). One lookup per map. */
static void env_light_visibility(const sl_lighting_uniforms *u, vec3 P, vec3 N, shade_env_shadow *es)
{
    const sl_shadow_suns *m = u->envShadowMaps;
    float *map_vis = es->map_vis, *vis = es->vis;
    for (int k = 0; k < SL_SHADOW_SUN_MAX; k++)
        map_vis[k] = k < m->count ? sl_shadow_sun_visibility(m, k, P, N) : 0.0f;
    for (int j = 0; j < SL_ENV_LIGHTS_MAX; j++) {
        int k = j < u->uEnvLightCount ? m->env_light_sun[j] : -2;
        vis[j] = k >= 0 ? map_vis[k] : k == -1 ? 1.0f : 0.0f;
    }
}

/* GLSL: env_lights_irradiance. The env lights' part of the irradiance E(N) (N in
 * environment space), sum L_k max(N.l_k, 0) over every light (`all`: what the irradiance holds)
 * and times each one's visibility (`seen`). */
static void env_lights_irradiance(const sl_lighting_uniforms *u, vec3 N, const float *vis, vec3 *all, vec3 *seen)
{
    vec3 a = vec3s(0.0f), s = vec3s(0.0f);
    for (int j = 0; j < u->uEnvLightCount; j++) {
        float c = maxf(dot(xyz(u->uEnvLightDir[j]), N), 0.0f);
        vec3 L = scale(xyz(u->uEnvLightRadiance[j]), c);
        a = add(a, L);
        s = add(s, scale(L, vis[j]));
    }
    *all = a;
    *seen = s;
}

/* C only, beside env_lights_irradiance: with the env lights' shadow maps, the irradiance E read
 * along D (`bent`: the cone's direction, else N) less what it holds of the lights (returned),
 * and the lights' diffuse about N times their visibility (`lights`), added after the occlusion. */
static vec3 env_shadow_diffuse(const sl_lighting_uniforms *u, vec3 E, bool bent, vec3 D, vec3 Nenv, vec3 Kd,
                               const float *vis, vec3 *lights)
{
    /* E - sum L_k (D.l_k)+ >= 0 in theory; a smoothing irradiance (SH9, the maps' filter) can put
     * a sun's lobe where E is below it: clamped, the error of that smoothing. What E holds of
     * the lights is along D; what the maps add back is about N. */
    vec3 all, seen, unused;
    env_lights_irradiance(u, Nenv, vis, &all, &seen);
    if (bent) /* D is not N: one more pass over the lights */
        env_lights_irradiance(u, D, vis, &all, &unused);
    *lights = scale(mul(scale(Kd, 1.0f / PI), seen), u->uEnvIntensity);
    return vmax3(sub(E, all), vec3s(0.0f));
}

/* GLSL: point_light */
static vec3 point_light(const sl_lighting_uniforms *u, int i, vec3 P, vec3 N, vec3 V, vec3 Kd, vec3 Ks,
                        float alpha)
{
    vec3 toLight = sub(u->uLightPosition[i], P);
    float d2 = dot(toLight, toLight);
    if (d2 < MIN_LIGHT_D2)
        return vec3s(0.0f);
    vec3 L = scale(toLight, 1.0f / sqrtf(d2));
    float NdotL = dot(N, L);
    if (NdotL <= 0.0f)
        return vec3s(0.0f);
    vec3 H = normalize(add(L, V));
    float LdotH = dot(L, H);
    vec3 f = vec3s(0.0f);
    if (u->uDiffuse != 0)
        f = add(f, scale(Kd, 1.0f / PI));
    if (u->uSpecular != 0) {
        float G = sl_lobe_G(LdotH, NdotL, dot(N, V), alpha, (sl_gterm)u->uGTerm);
        f = add(f, scale(sl_brdf_F(Ks, LdotH), sl_lobe_D(dot(N, H), alpha) * G / 4.0f));
    }
    return scale(mul(f, u->uLightColor[i]), u->uLightIntensity[i] / d2 * NdotL);
}

/* GLSL: horizon_visible - the part across the horizon times the visibility of the sky map whose
 * cell holds its luminous direction: one map for the part, as the lobe's tail across the
 * horizon lies within a cell or two */
bool sl_shade_horizon_dir(const shade_horizon *h, vec3 *d)
{
    float len = length(h->dir);
    if (!(len > 0.0f))
        return false; /* nothing across, or only black */
    *d = scale(h->dir, 1.0f / len);
    return true;
}

vec3 sl_shade_horizon_visible(const sl_lighting_uniforms *u, const shade_horizon *h, vec3 P, vec3 N,
                              sl_lighting_trace *trace)
{
    vec3 d;
    if (!sl_shade_horizon_dir(h, &d))
        return vec3s(0.0f);
    int k = sl_shadow_sky_cell(u->skyMaps, d);
    float v = sl_shadow_sky_map_visibility(u->skyMaps, k, P, N);
    vec3 visible = scale(h->sum, v);
    trace_horizon(trace, h, d, k, v, visible);
    return visible;
}

/* GLSL: shadowed_point_light. point_light times the light's visibility from P in its shadow
 * maps (src/shadow: sl_shadow_point_visibility, lighting.frag's shadow_point_visibility),
 * looked up only where the light adds something. */
static vec3 shadowed_point_light(const sl_lighting_uniforms *u, int i, vec3 P, vec3 N, vec3 V, vec3 Kd, vec3 Ks,
                                 float alpha)
{
    vec3 light = point_light(u, i, P, N, V, Kd, Ks, alpha);
    if (u->shadowMaps && (light.x > 0.0f || light.y > 0.0f || light.z > 0.0f))
        light = scale(light, sl_shadow_point_visibility(u->shadowMaps, i, P, N));
    return light;
}

/* GLSL: background */
static vec3 background(const sl_lighting_uniforms *u, vec2 fragCoord)
{
    vec3 d = shade_background_dir(u->uInvViewProj.c, u->uEnvRotation.c, u->uViewport, fragCoord);
    return scale(textureLod(u->uEnv, sl_dir_to_uv(d), 0.0f), u->uEnvIntensity);
}

/* Part of GLSL main: from `if (uDiffuse != 0)` on (lighting_internal.h: sl_shade_surface_color). */
vec3 sl_shade_surface_color(const sl_lighting_uniforms *u, const shade_surface *s, const vec3 *E_given,
                            const vec3 *specular, const vec3 *across, const shade_env_shadow *env_shadow,
                            sl_lighting_task *task, sl_lighting_trace *trace)
{
    vec3 color = vec3s(0.0f);
    /* With the ambient occlusion's cone (GLSL uHasCone): the diffuse times the occlusion, the
     * specular times the material's share of it and the specular occlusion, each term scaled
     * before the sum. Without: the sum times the occlusion. The reflection occlusion (GLSL
     * uReflectionDistance > 0) joins the cone's factor by its rays' count
     * (sl_reflection_specular_factor), or scales the specular without the cone; with the sky maps
     * a wide lobe's factor is at most its material's occlusion times the map of R's cell
     * (shade_lobe_map). */
    const sl_vec4 *cone = s->cone;
    float spec_occlusion = s->occlusion;
    /* the material's share of the occlusion: the reflection occlusion's join and the specular's
     * part across the horizon take it (1 without the cone: the sum's occlusion scales those) */
    float material_occlusion = cone ? shade_material_occlusion(cone->w, s->occlusion) : 1.0f;
    if (cone) {
        float b_dot_r, n_dot_v, cone_across;
        shade_cone_cosines(u, cone, s->Nenv, s->Venv, &b_dot_r, &n_dot_v, &cone_across);
        const sl_so_lobe lobe = sl_so_lobe_cone(s->alpha);
        spec_occlusion = shade_spec_occlusion(cone->w, s->occlusion, b_dot_r, n_dot_v, lobe, cone_across);
        if (s->reflection)
            spec_occlusion = sl_reflection_specular_factor(spec_occlusion, material_occlusion, *s->reflection);
        float before_map = spec_occlusion;
        vec3 R = normalize(sub(scale(s->Nenv, 2.0f * dot(s->Nenv, s->Venv)), s->Venv)); /* the batched path's p->R */
        spec_occlusion = shade_lobe_map(u, spec_occlusion, material_occlusion, s->P, s->N, R, lobe.ts);
        trace_cone(trace, cone, s->occlusion, spec_occlusion, cone_across,
                   spec_occlusion < before_map ? before_map : -1.0f);
    }
    /* With the env lights' shadow maps: each env light's visibility from the point (given by the
     * batched path, else looked up here). The lights' part of the irradiance is taken out of E
     * and added back times the visibility, and the specular's exact part is times it too; both
     * are added after the occlusion, as the point lights are: the maps are their occlusion. */
    shade_env_shadow own;
    own.diffuse_given = false;
    if (u->envLightShadows != 0 && !env_shadow) {
        env_light_visibility(u, s->P, s->N, &own);
        env_shadow = &own;
    }
    vec3 shadowed_lights = vec3s(0.0f); /* the env lights' diffuse and specular, times their visibility */
    if (u->uDiffuse != 0) {
        /* with the cone the irradiance along the bent direction D (bent_irradiance.h), else N */
        vec3 D = cone ? shade_diffuse_dir(u, cone, s->Nenv) : s->Nenv;
        vec3 E = E_given ? *E_given : irradiance(u, D); /* the batched path's, the same bits */
        if (env_shadow && env_shadow->diffuse_given)
            shadowed_lights = env_shadow->diffuse;
        else if (env_shadow)
            E = env_shadow_diffuse(u, E, cone != NULL, D, s->Nenv, s->Kd, env_shadow->vis, &shadowed_lights);
        /* the sky visibility maps' V on the residual's irradiance (the env lights' part, added
         * back after the occlusion, has its own maps); the batched path's E_given has it */
        if (u->skyMaps && !E_given)
            E = scale(E, sl_shadow_sky_visibility(u->skyMaps, s->P, s->N, NULL));
        vec3 diffuse = scale(mul(scale(s->Kd, 1.0f / PI), E), u->uEnvIntensity);
        trace_diffuse(trace, E, diffuse);
        if (cone)
            diffuse = scale(diffuse, shade_diffuse_occlusion(u, cone, s->occlusion));
        color = add(color, diffuse);
    }
    if (u->uSpecular != 0) {
        vec3 spec;
        /* with the sky maps, the samples' part from across the horizon (shade_horizon), times its
         * map's visibility: added after the pixel's specular factor, times the material's
         * occlusion (with the cone; without it the sum's occlusion below scales it) */
        vec3 beyond = vec3s(0.0f);
        shade_horizon h = shade_horizon_for(u, s->Nenv, s->Venv, s->Fenv);
        if (specular) {
            spec = *specular; /* the batched path's, env lights included */
            beyond = across ? *across : vec3s(0.0f);
        } else {
            if (env_shadow)
                shade_horizon_glow(&h, u, env_shadow->map_vis);
            const int estimator = shade_estimator_of(u, s->alpha);
            if (estimator == ESTIMATOR_SPLITSUM)
                spec = specular_splitsum(u, s->Nenv, s->Venv, s->Ks, s->alpha, trace);
            else if (estimator == ESTIMATOR_MICROFACET)
                spec = specular_microfacet(u, s->Nenv, s->Venv, s->Ks, s->alpha, s->rotation, NO_CV, &h, task,
                                           trace);
            else if (estimator == ESTIMATOR_CV || estimator == ESTIMATOR_CV_MIS)
                spec = specular_cv(u, s->Nenv, s->Venv, s->Ks, s->alpha, s->rotation, estimator == ESTIMATOR_CV_MIS,
                                   &h, task, trace);
            else if (estimator == ESTIMATOR_MIS)
                spec = specular_mis(u, s->Nenv, s->Venv, s->Ks, s->alpha, s->rotation, NO_CV, &h, task, trace);
            else
                spec = specular_ibl(u, s->Nenv, s->Venv, s->Ks, s->alpha, s->rotation, &h, task, trace);
            beyond = sl_shade_horizon_visible(u, &h, s->P, s->N, trace);
            if (shade_env_lights_of(u, s->alpha) && !env_shadow) {
                vec3 exact = specular_env_lights(u, s->Nenv, s->Venv, s->Ks, s->alpha, NULL, &h);
                spec = add(spec, exact);
                trace_env_lights(trace, u, s->Nenv, s->Venv, s->alpha, exact);
            }
        }
        vec3 exact = vec3s(0.0f); /* shadowed: kept apart from the occluded rest */
        if (env_shadow) {
            exact = specular ? env_shadow->specular
                             : specular_env_lights(u, s->Nenv, s->Venv, s->Ks, s->alpha, env_shadow->vis, &h);
            trace_env_lights(trace, u, s->Nenv, s->Venv, s->alpha, exact);
            shadowed_lights = add(shadowed_lights, exact);
        }
        trace_specular(trace, add(add(spec, beyond), exact));
        if (cone)
            spec = scale(spec, spec_occlusion);
        else if (s->reflection)
            spec = scale(spec, s->reflection->x);
        if (u->skyMaps)
            spec = add(spec, scale(beyond, material_occlusion));
        color = add(color, spec);
    }
    if (!cone)
        color = scale(color, s->occlusion);
    if (env_shadow)
        color = add(color, shadowed_lights);
    if (u->uPointLights != 0) {
        for (int i = 0; i < u->uLightCount; i++) {
            vec3 light = shadowed_point_light(u, i, s->P, s->N, s->V, s->Kd, s->Ks, s->alpha);
            color = add(color, light);
            trace_light(trace, i, light);
        }
    }
    /* emission is view-independent: it travels with the diffuse term (--specular-only drops it,
     * and the ground truth's diffuse part carries it) */
    if (u->uDiffuse != 0)
        color = add(color, s->emissive);
    trace_extra(trace, s->occlusion, s->emissive);
    return color;
}

/* Part of GLSL main: its last two lines (the batched path ends its pixels here too). */
vec3 sl_shade_finish(vec3 color, sl_lighting_task *task, sl_lighting_trace *trace)
{
    bool finite = isfinite(color.x) && isfinite(color.y) && isfinite(color.z);
    if (!finite && task)
        task->stats.nonfinite++;
    if (trace) {
        trace->repaired = !finite;
        trace->total = finite ? color : vec3s(0.0f);
    }
    return finite ? color : vec3s(0.0f);
}

/* main: pixel = (x, y) = ivec2(gl_FragCoord.xy); the texel fields are the texelFetches. */
/* GLSL: main */
vec3 sl_shade_plain(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y, sl_lighting_task *task,
                 sl_lighting_trace *trace)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
    vec2 fragCoord = vec2((float)x + 0.5f, (float)y + 0.5f);
    float depth = t->depth;
    vec3 color = vec3s(0.0f);
    trace_texel(trace, t, fragCoord, true);
    if (depth >= 1.0f) {
        color = background(u, fragCoord);
        trace_background(task, trace, color);
    } else {
        vec3 P = t->position;
        vec3 Kd = t->kd;
        vec3 Ks = t->ks;
        float alpha = shade_lobe_param(t->alpha); /* GLSL lobe_param (lighting_internal.h) */
        vec3 V = normalize(sub(u->uEye, P));
        vec3 N = facing_normal(t->normal, V);
        vec3 Nenv = mat3_mul_vec3(u->uEnvRotation, N);
        vec3 Venv = mat3_mul_vec3(u->uEnvRotation, V);
        vec2 rotation = u->uRotate != 0 ? pixel_rotation(u, x, y) : vec2(0.0f, 0.0f);
        sl_gbuffer_extra e = shade_extra(gb, x, y);
        shade_surface s = {.P = P, .Kd = Kd, .Ks = Ks, .alpha = alpha, .V = V, .N = N, .Nenv = Nenv, .Venv = Venv,
                           .rotation = rotation, .occlusion = e.occlusion, .emissive = e.emissive,
                           .reflection = shade_reflection(gb, x, y), .cone = shade_cone(gb, x, y),
                           .Fenv = shade_facet_env(u, gb, x, y)};
        trace_surface(u, task, trace, &s, dot(t->normal, V) < MIN_NDOTV * length(t->normal));
        color = sl_shade_surface_color(u, &s, NULL, NULL, NULL, NULL, task, trace);
    }
    return sl_shade_finish(color, task, trace);
}

/* ---- exported for the other files of the stage (lighting_internal.h) ---- */

vec2 sl_shade_hammersley_point(const sl_lighting_uniforms *u, int k) { return hammersley_point(u, k); }
vec2 sl_shade_pixel_rotation(const sl_lighting_uniforms *u, int x, int y) { return pixel_rotation(u, x, y); }
vec3 sl_shade_skewed_sample(vec2 xi, float alpha) { return skewed_sample(xi, alpha); }
float sl_shade_sample_pdf(vec2 xi, float alpha) { return sample_pdf(xi, alpha); }
vec3 sl_shade_microfacet_sample(vec2 xi, float alpha) { return microfacet_sample(xi, alpha); }
float sl_shade_microfacet_D(vec2 xi, float alpha) { return microfacet_D(xi, alpha); }
vec3 sl_shade_ggx_stretched_view(vec3 Vl, float a) { return ggx_stretched_view(Vl, a); }
vec3 sl_shade_facing_normal(vec3 N, vec3 V) { return facing_normal(N, V); }
vec3 sl_shade_specular_mis(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation,
                           shade_horizon *h, sl_lighting_task *task, sl_lighting_trace *trace)
{
    return specular_mis(u, N, V, Ks, alpha, rotation, NO_CV, h, task, trace);
}
vec3 sl_shade_specular_cvmis(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation,
                             shade_horizon *h, sl_lighting_task *task, sl_lighting_trace *trace)
{
    return specular_cv(u, N, V, Ks, alpha, rotation, true, h, task, trace);
}
vec4 sl_shade_env_dist_sample(const sl_lighting_uniforms *u, vec2 xi, ivec2 *texel)
{
    return env_dist_sample(u, xi, texel);
}
ivec2 sl_shade_env_texel(const sl_lighting_uniforms *u, vec3 w) { return env_texel(u, w); }
float sl_shade_env_dist_pdf(const sl_lighting_uniforms *u, ivec2 t) { return env_dist_pdf(u, t); }
float sl_shade_mis_power(float p, float q) { return mis_power(p, q); }
vec3 sl_shade_env_texel_fetch(const sl_lighting_uniforms *u, ivec2 t) { return env_texel_fetch(u, t); }
vec3 sl_shade_specular_splitsum(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha,
                             sl_lighting_trace *trace)
{
    return specular_splitsum(u, N, V, Ks, alpha, trace);
}
sl_cv_kernel sl_shade_cv_setup(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha)
{
    return cv_setup(u, N, V, Ks, alpha);
}

vec3 sl_shade_env_lod(const sl_lighting_uniforms *u, vec3 w, float lod)
{
    return env_lod(u, -1.0f, w, lod); /* uEnvResidual: the GGX set's always */
}
vec3 sl_shade_irradiance(const sl_lighting_uniforms *u, vec3 N) { return irradiance(u, N); }
vec3 sl_shade_env_lights(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha)
{
    const shade_horizon open = shade_horizon_for(u, N, V, vec3s(0.0f)); /* no facet: nothing hidden */
    return specular_env_lights(u, N, V, Ks, alpha, NULL, &open);
}
void sl_shade_env_light_visibility_of(const sl_lighting_uniforms *u, const float *map_vis, float *vis)
{
    /* env_light_visibility's values, each light's picked by its slot (envLightVisSlot) in one
     * vector loop of compares and selects (a gather from the slots is slower) instead of a branch
     * a light: a light past the count is 0, one no map covers 1. Only as far as the batched
     * loops read (shade_env_light_lanes), not all SL_ENV_LIGHTS_MAX. */
    _Static_assert(SL_SHADOW_SUN_MAX == 4, "a select per map below");
    const int lanes = shade_env_light_lanes(u);
    /* held before the loop: read through the pointer in it, clang does not vectorize the loop */
    const float v0 = map_vis[0], v1 = map_vis[1], v2 = map_vis[2], v3 = map_vis[3];
#pragma omp simd
    for (int j = 0; j < lanes; j++) {
        int k = u->envLightVisSlot[j];
        float v = k == SL_SHADOW_SUN_MAX ? 1.0f : 0.0f;
        v = k == 0 ? v0 : v;
        v = k == 1 ? v1 : v;
        v = k == 2 ? v2 : v;
        v = k == 3 ? v3 : v;
        vis[j] = v;
    }
}
vec3 sl_shade_point_light(const sl_lighting_uniforms *u, int i, vec3 P, vec3 N, vec3 V, vec3 Kd, vec3 Ks, float alpha)
{
    return shadowed_point_light(u, i, P, N, V, Kd, Ks, alpha);
}
vec3 sl_shade_point_light_unshadowed(const sl_lighting_uniforms *u, int i, vec3 P, vec3 N, vec3 V, vec3 Kd, vec3 Ks,
                                     float alpha)
{
    return point_light(u, i, P, N, V, Kd, Ks, alpha);
}
vec3 sl_shade_background(const sl_lighting_uniforms *u, vec2 fragCoord) { return background(u, fragCoord); }

/* ---- public helpers (lighting.h): for tests and the viewer's mip-level view ---- */

float sl_lighting_mip_level(const sl_lighting_uniforms *u, float D, float pdf, vec3 w)
{
    return mip_level(u, 0.0f, D, pdf, w); /* the frame's rule (a Phong lobe's) */
}

uint32_t sl_lighting_hash(uint32_t x) { return hash_u32(x); }

vec2 sl_lighting_pixel_rotation(int x, int y, uint32_t frame)
{
    sl_lighting_uniforms u = {.uFrame = frame};
    return pixel_rotation(&u, x, y);
}
