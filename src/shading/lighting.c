/* lighting.c - the lighting shader: a line-by-line C port of shaders/lighting.frag, and the
 * batched fast path the pass runs by default (lighting_pass.c runs them over a G-buffer).
 *
 * Two paths, one result (docs/lighting.md "Two paths"):
 *   - the PORT: every function below tagged "GLSL: name" is the GLSL function of that name, in
 *     the same order, with the same variable names; a uniform uX is u->uX. It runs when
 *     options.plain is set (the debug switch), and is what a reader compares with the GLSL.
 *     Two deliberate differences, both exact (the same float operations, so the same bits):
 *     specular_ibl takes its per-sample (xi, L, pdf) from a per-alpha table when a task is
 *     given (hoisting, below), and the trace's `if (trace)` blocks, which change nothing.
 *   - the BATCHED path (shade_span, pixel_stage, background_stage, specular_samples; the
 *     default): the same formulas, reorganised into loops over arrays that GCC vectorizes
 *     (`#pragma omp simd`): per tile row, every pixel's V, N and sample frame; per pixel, the
 *     samples in stages: (1) directions w, H, the dot products, G, the Fresnel factor and the
 *     lat-long uv; (2) the mip levels; (3) the texture fetches (gathers from the environment's
 *     single block) and contributions; (4) the sum. lighting_math.h's log2 and atan2 replace
 *     libm's powf/log2f/atan2f/acosf (the lod needs only log2(N.H), since log2 D =
 *     log2((alpha+2)/2pi) + alpha log2(N.H), and the spec estimator never needs D itself). Its
 *     results differ from the port's by float rounding (test_lighting_fast bounds it); it is
 *     deterministic, and the trace follows it.
 * Three estimators (uEstimator): spec and consistent share specular_ibl (directions about R);
 * the microfacet one is specular_microfacet (H about N, w = reflect(-V, H)). The batched path
 * runs both through specular_samples, with a stage (1) loop and spec-rule lod loop of its own
 * for the microfacet estimator, since its samples and weights differ while the fetch and the sum
 * are the same.
 * Everything else that is C only (options, uniforms, tasks, the pass, accumulation, the trace
 * printer) is in lighting_pass.c.
 *
 * Hoisting: skewed_sample and sample_pdf (microfacet_sample and microfacet_D) depend on the
 * material's alpha and the sample index only, yet cost an acos, a pow, two sincos and a second
 * pow per sample. A task keeps the tables of the last SLOTS distinct alphas it met (scenes have
 * few materials), so a pixel pays a table lookup; 1/2 log2(W H / N) is uLodBase, computed once
 * per frame. With rotation on (uRotate) every pixel has its own pairs, so the tables cannot
 * serve; the batched path then turns the xi1 offset into one rotation of the azimuths per pixel
 * (xi1 only sets the azimuth) and computes the xi2 part per sample with the fast log2/exp2.
 *
 * GCC vectorizes a loop only if no floating-point operation sits under a branch (its default
 * -ftrapping-math); hence selects between constants multiplied in, and a loop per option
 * where the port has an `if`. */
#include "lighting_internal.h"

/* clang honours `omp simd` too but cannot vectorize every one of these loops (gathers through a
 * computed level); that is a missed optimisation, not an error in a -Werror build. */
#ifdef __clang__
#pragma clang diagnostic ignored "-Wpass-failed"
#endif

#include <math.h>

#include "../ibl/texture_lod.h"
#include "lighting_math.h"

/* GLSL constants, same names and values. */
static const int LOD_NONE = SL_LOD_NONE;
static const int LOD_SPEC = SL_LOD_SPEC;
static const int LOD_SPEC_D4 = SL_LOD_SPEC_D4;
static const int LOD_GEMS = SL_LOD_GEMS;
static const int LOD_PDF = SL_LOD_PDF;
static const int ESTIMATOR_CONSISTENT = SL_ESTIMATOR_CONSISTENT;
static const int ESTIMATOR_MICROFACET = SL_ESTIMATOR_MICROFACET;
static const float MIN_NDOTV = 0.01f;
static const float POLE_EPS = 1e-6f;
static const float TINY = SL_BRDF_TINY;
static const float MAX_ALPHA = 1e7f;
static const float MIN_LIGHT_D2 = 1e-8f;
#define PI SL_PI

/* ======================= the port of shaders/lighting.frag ======================= */

/* GLSL: hammersley_point */
static vec2 hammersley_point(const sl_lighting_uniforms *u, int k)
{
    vec4 h = u->uHammersley.hammersley[k >> 1];
    return ((k & 1) == 0) ? vec2(h.x, h.y) : vec2(h.z, h.w);
}

/* GLSL: hash_u32 (Wellons' lowbias32: two multiply-xorshift rounds, full avalanche) */
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
    vec2 uv = vec2(xi.x, acosf(clamp(powf(xi.y, 1.0f / (alpha + 1.0f)), -1.0f, 1.0f)) / PI);
    return sl_uv_to_dir(uv);
}

/* GLSL: sample_pdf */
static float sample_pdf(vec2 xi, float alpha)
{
    return (alpha + 1.0f) / (2.0f * PI) * powf(xi.y, alpha / (alpha + 1.0f));
}

/* GLSL: microfacet_sample */
static vec3 microfacet_sample(vec2 xi, float alpha)
{
    vec2 uv = vec2(xi.x, acosf(clamp(powf(xi.y, 1.0f / (alpha + 2.0f)), -1.0f, 1.0f)) / PI);
    return sl_uv_to_dir(uv);
}

/* GLSL: microfacet_D */
static float microfacet_D(vec2 xi, float alpha)
{
    return (alpha + 2.0f) / (2.0f * PI) * powf(xi.y, alpha / (alpha + 2.0f));
}

/* GLSL: mip_level */
static float mip_level(const sl_lighting_uniforms *u, float D, float pdf, vec3 w)
{
    if (u->uLodRule == LOD_NONE)
        return 0.0f;
    float d = 1.0f;
    if (u->uDistortion != 0)
        d = 0.5f * PI * maxf(sqrtf(maxf(1.0f - w.z * w.z, 0.0f)), u->uSinThetaMin);
    float lod;
    if (u->uLodRule == LOD_SPEC)
        lod = u->uLodBase - 0.5f * log2f(maxf(D * d, TINY));
    else if (u->uLodRule == LOD_SPEC_D4)
        lod = u->uLodBase - 0.5f * log2f(maxf(D / 4.0f * d, TINY));
    else if (u->uLodRule == LOD_GEMS)
        lod = u->uLodBase - 0.5f * log2f(maxf(4.0f * PI * pdf * d, TINY)) + 1.0f;
    else
        lod = u->uLodBase - 0.5f * log2f(maxf(4.0f * PI * pdf * d, TINY));
    return clamp(lod, 0.0f, u->uEnvMaxLod);
}

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

/* GLSL: irradiance. sl_irradiance_eval (src/ibl/irradiance.c) is both branches: the SH9 sum
 * over uSH and the map lookup of uIrradianceMap. */
static vec3 irradiance(const sl_lighting_uniforms *u, vec3 N)
{
    return sl_irradiance_eval(u->uIrradiance, N);
}

/* Find or build the table for alpha (C only: the hoisted part of specular_ibl, or of
 * specular_microfacet when `microfacet`). */
static const lobe_table *lobe_for(const sl_lighting_uniforms *u, sl_lighting_task *task, float alpha, bool microfacet)
{
    int n = (int)u->uHammersley.N;
    if (task->owner != u) {
        sl_lighting_task_reset(task);
        task->owner = u;
    }
    for (int s = 0; s < SLOTS; s++) {
        const lobe_table *t = &task->slots[s];
        if (t->valid && t->alpha == alpha && t->n == n && t->microfacet == microfacet)
            return t;
    }
    lobe_table *t = &task->slots[task->next];
    task->next = (task->next + 1) % SLOTS;
    for (int k = 0; k < n; k++) {
        vec2 xi = hammersley_point(u, k);
        vec3 L = microfacet ? microfacet_sample(xi, alpha) : skewed_sample(xi, alpha);
        t->xi1[k] = xi.x;
        t->xi2[k] = xi.y;
        t->Lx[k] = L.x;
        t->Ly[k] = L.y;
        t->Lz[k] = L.z;
        t->pdf[k] = microfacet ? microfacet_D(xi, alpha) : sample_pdf(xi, alpha);
    }
    t->microfacet = microfacet;
    t->alpha = alpha;
    t->n = n;
    t->valid = true;
    return t;
}

/* GLSL: specular_ibl */
static vec3 specular_ibl(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation,
                         sl_lighting_task *task, sl_lighting_trace *trace)
{
    float NdotV = dot(N, V);
    vec3 R = normalize(sub(scale(N, 2.0f * NdotV), V));
    vec3 axis = (R.x * R.x + R.y * R.y < POLE_EPS) ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 0.0f, 1.0f);
    vec3 A = normalize(cross(axis, R));
    vec3 B = normalize(cross(R, A));
    int n = (int)u->uHammersley.N;
    vec3 sum = vec3s(0.0f);
    /* the table holds the unrotated pairs: with rotation on every pixel has its own */
    const lobe_table *lobe = task && u->uRotate == 0 ? lobe_for(u, task, alpha, false) : NULL;
    int below = 0;
    if (trace) {
        trace->NdotV = NdotV;
        trace->R = R;
        trace->A = A;
        trace->B = B;
        trace->pole_frame = axis.x == 1.0f;
        trace->sample_count = n;
    }
    for (int k = 0; k < n; k++) {
        vec2 xi = lobe ? vec2(lobe->xi1[k], lobe->xi2[k]) : hammersley_point(u, k);
        if (u->uRotate != 0)
            xi = vec2(fract(xi.x + rotation.x), fract(xi.y + rotation.y));
        vec3 L = lobe ? vec3(lobe->Lx[k], lobe->Ly[k], lobe->Lz[k]) : skewed_sample(xi, alpha);
        float pdf = lobe ? lobe->pdf[k] : sample_pdf(xi, alpha);
        vec3 w = normalize(add(add(scale(A, L.x), scale(B, L.y)), scale(R, L.z)));
        float wN = dot(w, N);
        if (trace) {
            sl_lighting_trace_sample *ts = &trace->samples[k];
            memset(ts, 0, sizeof *ts);
            ts->xi = xi;
            ts->L = L;
            ts->pdf = pdf;
            ts->w = w;
            ts->wN = wN;
            ts->sum = sum;
        }
        if (wN <= 0.0f) {
            below++;
            continue;
        }
        vec3 H = normalize(add(w, V));
        float NdotH = dot(N, H);
        float LdotH = dot(w, H);
        float D = sl_brdf_D(NdotH, alpha);
        vec3 F = sl_brdf_F(Ks, LdotH);
        float G = sl_brdf_G(LdotH, (sl_gterm)u->uGTerm);
        float lod = mip_level(u, D, pdf, w);
        vec3 Li = scale(textureLod(u->uEnvResidual, sl_dir_to_uv(w), lod), u->uEnvIntensity);
        float weight = G * wN / 4.0f;
        if (u->uEstimator == ESTIMATOR_CONSISTENT)
            weight = weight * D / pdf;
        vec3 c = scale(mul(F, Li), weight);
        sum = add(sum, c);
        if (trace) {
            sl_lighting_trace_sample *ts = &trace->samples[k];
            ts->H = H;
            ts->NdotH = NdotH;
            ts->LdotH = LdotH;
            ts->D = D;
            ts->F = F;
            ts->G = G;
            ts->lod = lod;
            ts->Li = Li;
            ts->c = c;
            ts->sum = sum;
        }
    }
    if (task) {
        task->stats.samples += n;
        task->stats.below_horizon += below;
        task->stats.pole_frames += axis.x == 1.0f;
    }
    return scale(sum, 1.0f / (float)(n > 1 ? n : 1));
}

/* GLSL: specular_microfacet (the derivation is in the GLSL). The per-sample (xi, H about +Z, D)
 * come from the per-alpha table when a task is given, as in specular_ibl. */
static vec3 specular_microfacet(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation,
                                sl_lighting_task *task, sl_lighting_trace *trace)
{
    vec3 axis = (N.x * N.x + N.y * N.y < POLE_EPS) ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 0.0f, 1.0f);
    vec3 A = normalize(cross(axis, N));
    vec3 B = normalize(cross(N, A));
    int n = (int)u->uHammersley.N;
    vec3 sum = vec3s(0.0f);
    const lobe_table *lobe = task && u->uRotate == 0 ? lobe_for(u, task, alpha, true) : NULL;
    int below = 0;
    if (trace) {
        float NdotV = dot(N, V);
        trace->NdotV = NdotV;
        trace->R = normalize(sub(scale(N, 2.0f * NdotV), V)); /* not used by this estimator */
        trace->A = A;
        trace->B = B;
        trace->pole_frame = axis.x == 1.0f;
        trace->sample_count = n;
        trace->microfacet = true;
    }
    for (int k = 0; k < n; k++) {
        vec2 xi = lobe ? vec2(lobe->xi1[k], lobe->xi2[k]) : hammersley_point(u, k);
        if (u->uRotate != 0)
            xi = vec2(fract(xi.x + rotation.x), fract(xi.y + rotation.y));
        vec3 Hl = lobe ? vec3(lobe->Lx[k], lobe->Ly[k], lobe->Lz[k]) : microfacet_sample(xi, alpha);
        float D = lobe ? lobe->pdf[k] : microfacet_D(xi, alpha);
        vec3 H = normalize(add(add(scale(A, Hl.x), scale(B, Hl.y)), scale(N, Hl.z)));
        float VdotH = dot(V, H);
        vec3 w = normalize(sub(scale(H, 2.0f * VdotH), V));
        float wN = dot(w, N);
        if (trace) {
            sl_lighting_trace_sample *ts = &trace->samples[k];
            memset(ts, 0, sizeof *ts);
            ts->xi = xi;
            ts->L = Hl;
            ts->w = w;
            ts->wN = wN;
            ts->H = H;
            ts->NdotH = Hl.z;
            ts->LdotH = VdotH;
            ts->D = D;
            ts->sum = sum;
        }
        if (VdotH <= 0.0f || wN <= 0.0f) {
            below++;
            continue;
        }
        float NdotH = Hl.z;
        float pdf = D * NdotH / (4.0f * VdotH);
        vec3 F = sl_brdf_F(Ks, VdotH);
        float G = sl_brdf_G(VdotH, (sl_gterm)u->uGTerm);
        float lod = mip_level(u, D, pdf, w);
        vec3 Li = scale(textureLod(u->uEnvResidual, sl_dir_to_uv(w), lod), u->uEnvIntensity);
        float weight = G * wN * VdotH / NdotH;
        vec3 c = scale(mul(F, Li), weight);
        sum = add(sum, c);
        if (trace) {
            sl_lighting_trace_sample *ts = &trace->samples[k];
            ts->pdf = pdf;
            ts->F = F;
            ts->G = G;
            ts->lod = lod;
            ts->Li = Li;
            ts->c = c;
            ts->sum = sum;
        }
    }
    if (task) {
        task->stats.samples += n;
        task->stats.below_horizon += below;
        task->stats.pole_frames += axis.x == 1.0f;
    }
    return scale(sum, 1.0f / (float)(n > 1 ? n : 1));
}

/* GLSL: specular_env_lights. Each env light is one texel's quadrature node (its centroid
 * direction w, its radiance times the node weight), so this is the ground truth's sum over
 * those texels: the BRDF of eq. (2) at w, times w.N; 0 below the horizon and for facets
 * facing away (N.H <= 0). */
static vec3 specular_env_lights(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha)
{
    vec3 sum = vec3s(0.0f);
    for (int j = 0; j < u->uEnvLightCount; j++) {
        vec3 w = xyz(u->uEnvLightDir[j]);
        float wN = dot(w, N);
        if (wN <= 0.0f)
            continue;
        vec3 H = normalize(add(w, V));
        float NdotH = dot(N, H);
        if (NdotH <= 0.0f)
            continue;
        float LdotH = dot(w, H);
        vec3 f = scale(sl_brdf_F(Ks, LdotH), sl_brdf_D(NdotH, alpha) * sl_brdf_G(LdotH, (sl_gterm)u->uGTerm) / 4.0f);
        sum = add(sum, scale(mul(f, xyz(u->uEnvLightRadiance[j])), wN));
    }
    return scale(sum, u->uEnvIntensity);
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
    if (u->uSpecular != 0)
        f = add(f, scale(sl_brdf_F(Ks, LdotH),
                         sl_brdf_D(dot(N, H), alpha) * sl_brdf_G(LdotH, (sl_gterm)u->uGTerm) / 4.0f));
    return scale(mul(f, u->uLightColor[i]), u->uLightIntensity[i] / d2 * NdotL);
}

/* The view ray of background(), for both paths: m = uInvViewProj, r = uEnvRotation, passed by
 * column so a vectorized caller keeps them in registers. mat4_mul_vec4's operations. */
__attribute__((always_inline)) static inline vec3 background_dir(const vec4 m[4], const vec3 r[3], vec2 viewport, vec2 fragCoord)
{
    vec2 ndc = sub(scale(vec2(fragCoord.x / viewport.x, fragCoord.y / viewport.y), 2.0f), vec2s(1.0f));
    vec4 nearP = add(add(scale(m[0], ndc.x), scale(m[1], ndc.y)), add(scale(m[2], -1.0f), scale(m[3], 1.0f)));
    vec4 farP = add(add(scale(m[0], ndc.x), scale(m[1], ndc.y)), add(scale(m[2], 1.0f), scale(m[3], 1.0f)));
    vec3 d = normalize(sub(scale(xyz(farP), 1.0f / farP.w), scale(xyz(nearP), 1.0f / nearP.w)));
    return add(add(scale(r[0], d.x), scale(r[1], d.y)), scale(r[2], d.z));
}

/* GLSL: background */
static vec3 background(const sl_lighting_uniforms *u, vec2 fragCoord)
{
    vec3 d = background_dir(u->uInvViewProj.c, u->uEnvRotation.c, u->uViewport, fragCoord);
    return scale(textureLod(u->uEnv, sl_dir_to_uv(d), 0.0f), u->uEnvIntensity);
}

static bool finite3(vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* GLSL: main. pixel = (x, y) = ivec2(gl_FragCoord.xy); the texel fields are the texelFetches. */
static vec3 shade_plain(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y, sl_lighting_task *task,
                        sl_lighting_trace *trace)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
    vec2 fragCoord = vec2((float)x + 0.5f, (float)y + 0.5f);
    float depth = t->depth;
    vec3 color = vec3s(0.0f);
    if (trace) {
        trace->frag_coord = fragCoord;
        trace->texel = *t;
        trace->covered = !(depth >= 1.0f);
        trace->plain = true;
    }
    if (depth >= 1.0f) {
        color = background(u, fragCoord);
        if (trace)
            trace->background = color;
        if (task)
            task->stats.background++;
    } else {
        vec3 P = t->position;
        vec3 Kd = t->kd;
        vec3 Ks = t->ks;
        float alpha = clamp(t->alpha, 0.0f, MAX_ALPHA);
        vec3 V = normalize(sub(u->uEye, P));
        vec3 N = facing_normal(t->normal, V);
        vec3 Nenv = mat3_mul_vec3(u->uEnvRotation, N);
        vec3 Venv = mat3_mul_vec3(u->uEnvRotation, V);
        vec2 rotation = u->uRotate != 0 ? pixel_rotation(u, x, y) : vec2(0.0f, 0.0f);
        if (task)
            task->stats.bent_normals += dot(t->normal, V) < MIN_NDOTV * length(t->normal);
        if (trace) {
            trace->V = V;
            trace->N = N;
            trace->bent = dot(t->normal, V) < MIN_NDOTV * length(t->normal);
            trace->Nenv = Nenv;
            trace->Venv = Venv;
            trace->rotation = rotation;
            trace->alpha = alpha;
        }
        if (u->uDiffuse != 0) {
            vec3 E = irradiance(u, Nenv);
            vec3 diffuse = scale(mul(scale(Kd, 1.0f / PI), E), u->uEnvIntensity);
            color = add(color, diffuse);
            if (trace) {
                trace->irradiance = E;
                trace->diffuse = diffuse;
            }
        }
        if (u->uSpecular != 0) {
            vec3 specular = u->uEstimator == ESTIMATOR_MICROFACET
                                ? specular_microfacet(u, Nenv, Venv, Ks, alpha, rotation, task, trace)
                                : specular_ibl(u, Nenv, Venv, Ks, alpha, rotation, task, trace);
            if (u->uEnvLightCount > 0) {
                vec3 exact = specular_env_lights(u, Nenv, Venv, Ks, alpha);
                specular = add(specular, exact);
                if (trace) {
                    trace->env_light_count = u->uEnvLightCount;
                    trace->env_lights = exact;
                }
            }
            color = add(color, specular);
            if (trace)
                trace->specular = specular;
        }
        if (u->uPointLights != 0) {
            for (int i = 0; i < u->uLightCount; i++) {
                vec3 light = point_light(u, i, P, N, V, Kd, Ks, alpha);
                color = add(color, light);
                if (trace) {
                    trace->light[i] = light;
                    trace->lights = add(trace->lights, light);
                }
            }
        }
    }
    bool finite = finite3(color);
    if (!finite && task)
        task->stats.nonfinite++;
    if (trace) {
        trace->repaired = !finite;
        trace->total = finite ? color : vec3s(0.0f);
    }
    return finite ? color : vec3s(0.0f);
}

/* ======================= the batched path (C only) ======================= */

/* Samples are processed in blocks of BLOCK, so the per-sample arrays live on the stack (5 KB)
 * whatever N is; N = 40 is one block. */
enum { BLOCK = 64 };

/* One block of samples, structure of arrays: stage (1) writes them, (2) and (3) read them. */
typedef struct {
    float xi1[BLOCK], xi2[BLOCK], Lx[BLOCK], Ly[BLOCK], Lz[BLOCK], pdf[BLOCK]; /* when not from a table */
    float wx[BLOCK], wy[BLOCK], wz[BLOCK], wN[BLOCK];
    float hx[BLOCK], hy[BLOCK], hz[BLOCK], NdotH[BLOCK], LdotH[BLOCK];
    float m5[BLOCK], lod[BLOCK], u[BLOCK], v[BLOCK];
    float weight[BLOCK], cr[BLOCK], cg[BLOCK], cb[BLOCK];
    float vh[BLOCK], pw[BLOCK]; /* microfacet only: V.H and p(w) */
} sample_block;

/* log2(TINY): the floor of every log2 in mip_level */
static const float LOG2_TINY = -99.6578428f;

/* The unrotated pairs and cos/sin of their azimuth phi = 2 pi (1/2 - xi1), as sl_uv_to_dir
 * computes them (rotation on). The task's copy is built once per uniforms; without a task the
 * caller's `local` is filled. */
static const azimuth_table *azimuth_for(const sl_lighting_uniforms *u, sl_lighting_task *task,
                                        azimuth_table *local)
{
    int n = (int)u->uHammersley.N;
    azimuth_table *t = local;
    if (task) {
        if (task->owner != u) {
            sl_lighting_task_reset(task);
            task->owner = u;
        }
        t = &task->azimuth;
        if (t->n == n)
            return t;
    }
    for (int k = 0; k < n; k++) {
        vec2 xi = hammersley_point(u, k);
        float phi = 2.0f * PI * (0.5f - xi.x);
        t->xi1[k] = xi.x;
        t->xi2[k] = xi.y;
        t->cphi[k] = cosf(phi);
        t->sphi[k] = sinf(phi);
    }
    t->n = n;
    return t;
}

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

/* sl_env_bilinear (texture_lod.h) for the level of size w x h that starts at texel `o` of
 * the environment's block: the same operations, so the same bits; inlined into a simd loop it
 * becomes gathers. */
/* clamp(lod, 0, max_lod) with NaN -> 0 (the fetch indexes with it) */
static inline float clamp_lod(float lod, float max_lod)
{
    lod = lod > 0.0f ? lod : 0.0f;
    return lod < max_lod ? lod : max_lod;
}

/* mix3(T[a], T[b], t), reading the texels component by component (no struct copies, which stop
 * GCC's vectorizer). */
static inline vec3 mix_texels(const vec3 *T, int a, int b, float t)
{
    return vec3(mixf(T[a].x, T[b].x, t), mixf(T[a].y, T[b].y, t), mixf(T[a].z, T[b].z, t));
}

__attribute__((always_inline)) static inline vec3 block_bilinear(const vec3 *T, int w, int h, int o, float u, float v)
{
    float x = u * (float)w - 0.5f;
    float xf = sl_fast_floor(x);
    float fx = x - xf;
    int x0 = (int)xf;
    int x1 = x0 + 1;
    x0 = x0 < 0 ? x0 + w : x0;
    x1 = x1 >= w ? x1 - w : x1;
    float y = minf(maxf(v * (float)h - 0.5f, 0.0f), (float)(h - 1));
    int y0 = (int)y;
    float fy = y - (float)y0;
    int y1 = y0 + 1 < h ? y0 + 1 : h - 1;
    int r0 = o + y0 * w, r1 = o + y1 * w;
    vec3 top = mix_texels(T, r0 + x0, r0 + x1, fx);
    vec3 bottom = mix_texels(T, r1 + x0, r1 + x1, fx);
    return mix3(top, bottom, fy);
}

/* specular_ibl (or specular_microfacet, uEstimator = 3), batched, for one pixel whose frame (N,
 * V, R and A, B: about R, or about N for the microfacet estimator; environment space) the pixel
 * stage computed: see the top of the file. Same samples, same sum order. */
__attribute__((noinline)) /* a call per pixel; inlined, it keeps shade_span from vectorizing */
static vec3 specular_samples(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 R, vec3 A, vec3 B, bool pole,
                             vec3 Ks, float alpha, vec2 rotation, sl_lighting_task *task, sl_lighting_trace *trace)
{
    int n = (int)u->uHammersley.N;
    if (trace)
        trace->sample_count = n;
    const bool rotate = u->uRotate != 0;
    const bool mf = u->uEstimator == ESTIMATOR_MICROFACET;
    const lobe_table *lobe = task && !rotate ? lobe_for(u, task, alpha, mf) : NULL;
    azimuth_table local_az; /* 16 KB, filled only without a task (tests, traces) */
    const azimuth_table *az = rotate ? azimuth_for(u, task, &local_az) : NULL;
    const bool inv_lh2 = u->uGTerm == SL_GTERM_INV_LH2;
    const int rule = u->uLodRule;
    const bool consistent = u->uEstimator == ESTIMATOR_CONSISTENT;
    const bool distortion = u->uDistortion != 0;
    const float base = u->uLodBase, max_lod = u->uEnvMaxLod, sin_min = u->uSinThetaMin;
    const float intensity = u->uEnvIntensity;
    /* log2 of D's constant (alpha + 2)/(2 pi); the lod of spec-d4 takes D/4 */
    const float log2_c_lod = sl_fast_log2((alpha + 2.0f) / (2.0f * PI)) - (rule == LOD_SPEC_D4 ? 2.0f : 0.0f);
    const float log2_d4 = rule == LOD_SPEC_D4 ? 2.0f : 0.0f; /* microfacet: log2 D - log2 4 */
    const vec3 F1 = sub(vec3s(1.0f), Ks);
    /* the texture: the block's layout when there is one, else level 0's described as every
     * level (uniforms_init), and the fetch below redoes it texel by texel */
    const int gather = u->envGather;
    const vec3 *T = gather ? u->uEnvResidual->block : u->uEnvResidual->levels[0].texels;
    const int *W = u->envWidth, *H = u->envHeight, *O = u->envOffset;
    const int last = u->uEnvResidual->level_count - 1;
    sample_block blk;
    sample_block *b = &blk;
    vec3 acc[4] = {vec3s(0.0f), vec3s(0.0f), vec3s(0.0f), vec3s(0.0f)};
    vec3 trace_sum = vec3s(0.0f);
    int below = 0;
    for (int k0 = 0; k0 < n; k0 += BLOCK) {
        const int m = n - k0 < BLOCK ? n - k0 : BLOCK;
        /* (0) the skewed samples: table, recomputed (no task), or rotated */
        const float *xi1 = b->xi1, *xi2 = b->xi2, *Lx = b->Lx, *Ly = b->Ly, *Lz = b->Lz, *pdf = b->pdf;
        if (lobe) {
            xi1 = lobe->xi1 + k0;
            xi2 = lobe->xi2 + k0;
            Lx = lobe->Lx + k0;
            Ly = lobe->Ly + k0;
            Lz = lobe->Lz + k0;
            pdf = lobe->pdf + k0;
        } else if (rotate) {
            rotated_lobe(az, k0, m, alpha, mf ? 2.0f : 1.0f, rotation, b);
        } else {
            for (int i = 0; i < m; i++) {
                vec2 xi = hammersley_point(u, k0 + i);
                vec3 L = mf ? microfacet_sample(xi, alpha) : skewed_sample(xi, alpha);
                b->xi1[i] = xi.x;
                b->xi2[i] = xi.y;
                b->Lx[i] = L.x;
                b->Ly[i] = L.y;
                b->Lz[i] = L.z;
                b->pdf[i] = mf ? microfacet_D(xi, alpha) : sample_pdf(xi, alpha);
            }
        }
        /* (1) directions, dot products, G, the Fresnel factor and the uv: specular_ibl's
         * operations, vectorized over the samples; or specular_microfacet's, where (L, pdf) are
         * (H about +Z, D(H)) and A, B span the frame about N. A sample with N.H = 0 (a rotated
         * xi2 of 0) divides by 0 here; it has w.N < 0, so stage (4) drops it. */
        if (mf) {
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
                float LH = maxf(VdotH, SL_BRDF_MIN_LDOTH);
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
                b->pw[i] = pdf[i] * NdotH / (4.0f * VdotH); /* p(w) = D (N.H) / (4 V.H) */
                b->m5[i] = m2 * m2 * mm;
                b->weight[i] = (inv_lh2 ? 1.0f / (LH * LH) : 1.0f) * wN * VdotH / NdotH; /* G' (w.N)(V.H)/(N.H) */
                sl_fast_dir_to_uv(wx, wy, wz, &b->u[i], &b->v[i]);
            }
        } else {
#pragma omp simd
            for (int i = 0; i < m; i++) {
                float wx = (A.x * Lx[i] + B.x * Ly[i]) + R.x * Lz[i];
                float wy = (A.y * Lx[i] + B.y * Ly[i]) + R.y * Lz[i];
                float wz = (A.z * Lx[i] + B.z * Ly[i]) + R.z * Lz[i];
                float iw = 1.0f / sqrtf((wx * wx + wy * wy) + wz * wz);
                wx *= iw;
                wy *= iw;
                wz *= iw;
                float hx = wx + V.x, hy = wy + V.y, hz = wz + V.z;
                float ih = 1.0f / sqrtf((hx * hx + hy * hy) + hz * hz);
                hx *= ih;
                hy *= ih;
                hz *= ih;
                float LdotH = (wx * hx + wy * hy) + wz * hz;
                float LH = maxf(LdotH, SL_BRDF_MIN_LDOTH);
                float mm = maxf(1.0f - LdotH, 0.0f);
                float m2 = mm * mm;
                float wN = (wx * N.x + wy * N.y) + wz * N.z;
                b->wx[i] = wx;
                b->wy[i] = wy;
                b->wz[i] = wz;
                b->wN[i] = wN;
                b->hx[i] = hx;
                b->hy[i] = hy;
                b->hz[i] = hz;
                b->NdotH[i] = (N.x * hx + N.y * hy) + N.z * hz;
                b->LdotH[i] = LdotH;
                b->m5[i] = m2 * m2 * mm;
                b->weight[i] = (inv_lh2 ? 1.0f / (LH * LH) : 1.0f) * wN / 4.0f; /* G w.N / 4 */
                sl_fast_dir_to_uv(wx, wy, wz, &b->u[i], &b->v[i]);
            }
        }
        /* (2) mip levels, mip_level in the log domain: log2(max(D d, TINY)) = max(log2 c +
         * alpha log2(max(N.H, TINY)) + log2 d, log2 TINY); one loop per rule */
        if (distortion) {
#pragma omp simd
            for (int i = 0; i < m; i++)
                b->lod[i] = sl_fast_log2(0.5f * PI * maxf(sqrtf(maxf(1.0f - b->wz[i] * b->wz[i], 0.0f)), sin_min));
        } else {
            memset(b->lod, 0, sizeof(float) * (size_t)m); /* log2 d = 0 */
        }
        if (mf && (rule == LOD_SPEC || rule == LOD_SPEC_D4)) { /* D(H) is at hand: log2 of it */
#pragma omp simd
            for (int i = 0; i < m; i++) {
                float lg = sl_fast_log2(maxf(pdf[i], TINY)) - log2_d4 + b->lod[i];
                b->lod[i] = clamp_lod(base - 0.5f * maxf(lg, LOG2_TINY), max_lod);
            }
        } else if (rule == LOD_SPEC || rule == LOD_SPEC_D4) {
#pragma omp simd
            for (int i = 0; i < m; i++) {
                float lg = log2_c_lod + alpha * sl_fast_log2(maxf(b->NdotH[i], TINY)) + b->lod[i];
                b->lod[i] = clamp_lod(base - 0.5f * maxf(lg, LOG2_TINY), max_lod);
            }
        } else if (rule == LOD_GEMS || rule == LOD_PDF) {
            const float *pw = mf ? b->pw : pdf; /* the density of w */
            const float bias = rule == LOD_GEMS ? 1.0f : 0.0f; /* Gems' +1; pdf has none */
#pragma omp simd
            for (int i = 0; i < m; i++) {
                float lg = sl_fast_log2(maxf(4.0f * PI * pw[i], TINY)) + b->lod[i];
                b->lod[i] = clamp_lod(base - 0.5f * maxf(lg, LOG2_TINY) + bias, max_lod);
            }
        } else {
            memset(b->lod, 0, sizeof(float) * (size_t)m);
        }
        /* the consistent estimator: weight D / pdf, with the port's D (a pow per sample) */
        if (consistent)
            for (int i = 0; i < m; i++)
                b->weight[i] = b->weight[i] * sl_brdf_D(b->NdotH[i], alpha) / pdf[i];
        /* (3) radiance and contribution: textureLod from the block (texture_lod.h's operations
         * on the block's layout: gathers), c = F Li weight */
#pragma omp simd
        for (int i = 0; i < m; i++) {
            int l0 = (int)b->lod[i];
            float f = b->lod[i] - (float)l0;
            int l1 = l0 < last ? l0 + 1 : last;
            vec3 ta = block_bilinear(T, W[l0], H[l0], O[l0], b->u[i], b->v[i]);
            vec3 tb = block_bilinear(T, W[l1], H[l1], O[l1], b->u[i], b->v[i]);
            vec3 t = mix3(ta, tb, f);
            float m5 = b->m5[i], weight = b->weight[i];
            b->cr[i] = (Ks.x + F1.x * m5) * (t.x * intensity) * weight;
            b->cg[i] = (Ks.y + F1.y * m5) * (t.y * intensity) * weight;
            b->cb[i] = (Ks.z + F1.z * m5) * (t.z * intensity) * weight;
        }
        if (!gather) { /* no block: the same filter through texture_lod.h, texel by texel */
            for (int i = 0; i < m; i++) {
                vec3 t = sl_texture_lod_clamped(u->uEnvResidual, b->u[i], b->v[i], b->lod[i]);
                float weight = b->weight[i];
                b->cr[i] = (Ks.x + F1.x * b->m5[i]) * (t.x * intensity) * weight;
                b->cg[i] = (Ks.y + F1.y * b->m5[i]) * (t.y * intensity) * weight;
                b->cb[i] = (Ks.z + F1.z * b->m5[i]) * (t.z * intensity) * weight;
            }
        }
        /* (4) the sum. Samples below the horizon add nothing. Sample k goes into partial sum
         * k mod 4 and the four are added at the end, (0 + 1) + (2 + 3): four short dependency
         * chains instead of one long one (the port adds in sample order; the difference is float
         * rounding). The same order whatever the vectorization, so the pass, sl_lighting_shade
         * and the trace agree bit for bit. */
        for (int i = 0; i < m; i++) {
            bool above = !(b->wN[i] <= 0.0f) && !(mf && b->vh[i] <= 0.0f);
            int j = (k0 + i) & 3;
            below += !above;
            acc[j].x += above ? b->cr[i] : 0.0f;
            acc[j].y += above ? b->cg[i] : 0.0f;
            acc[j].z += above ? b->cb[i] : 0.0f;
        }
        for (int i = 0; trace && i < m; i++) { /* the trace's running sum is in sample order */
            sl_lighting_trace_sample *ts = &trace->samples[k0 + i];
            memset(ts, 0, sizeof *ts);
            ts->xi = vec2(xi1[i], xi2[i]);
            ts->L = vec3(Lx[i], Ly[i], Lz[i]);
            ts->pdf = pdf[i];
            ts->w = vec3(b->wx[i], b->wy[i], b->wz[i]);
            ts->wN = b->wN[i];
            ts->sum = trace_sum;
            if (mf) { /* as specular_microfacet records them: H, N.H, V.H, D before the test */
                ts->H = vec3(b->hx[i], b->hy[i], b->hz[i]);
                ts->NdotH = b->NdotH[i];
                ts->LdotH = b->LdotH[i];
                ts->D = pdf[i];
                ts->pdf = 0.0f;
            }
            if (b->wN[i] <= 0.0f || (mf && b->vh[i] <= 0.0f))
                continue;
            vec3 c = vec3(b->cr[i], b->cg[i], b->cb[i]);
            trace_sum = add(trace_sum, c);
            ts->H = vec3(b->hx[i], b->hy[i], b->hz[i]);
            ts->NdotH = b->NdotH[i];
            ts->LdotH = b->LdotH[i];
            ts->pdf = mf ? b->pw[i] : pdf[i];
            ts->D = mf ? pdf[i] : sl_brdf_D(b->NdotH[i], alpha);
            ts->F = add(Ks, scale(F1, b->m5[i]));
            ts->G = sl_brdf_G(b->LdotH[i], (sl_gterm)u->uGTerm);
            ts->lod = b->lod[i];
            /* Li is not kept by the pass: fetched again through texture_lod.h (same bits) */
            ts->Li = scale(sl_texture_lod_clamped(u->uEnvResidual, b->u[i], b->v[i], b->lod[i]), intensity);
            ts->c = c;
            ts->sum = trace_sum;
        }
    }
    vec3 sum = add(add(acc[0], acc[1]), add(acc[2], acc[3]));
    if (task) {
        task->stats.samples += n;
        task->stats.below_horizon += below;
        task->stats.pole_frames += pole;
    }
    return scale(sum, 1.0f / (float)(n > 1 ? n : 1));
}

/* specular_env_lights, batched: the lights vectorized (structure of arrays in the uniforms),
 * D through the fast log2/exp2 as the lod does, and the sum in light order. */
__attribute__((noinline)) static vec3 env_lights_samples(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks,
                                                         float alpha)
{
    /* Whole vectors: the arrays are zero past uEnvLightCount (a zero direction and radiance add
     * exactly 0), so rounding the count up to 16 keeps a small K off the scalar remainder loop,
     * which made K = 8 cost as much as K = 24. */
    const int n = (u->uEnvLightCount + 15) & ~15;
    const float *X = u->envLightX, *Y = u->envLightY, *Z = u->envLightZ;
    const float *LR = u->envLightR, *LG = u->envLightG, *LB = u->envLightB;
    const bool inv_lh2 = u->uGTerm == SL_GTERM_INV_LH2;
    const float log2_c = sl_fast_log2((alpha + 2.0f) / (2.0f * PI));
    /* sl_fast_exp2 needs its argument in [-126, 127]: log2_c + alpha log2(N.H) >= -120 when
     * N.H >= 2^((-120 - log2_c)/alpha). Clamping N.H, not the sum, keeps the loop vectorizable
     * (GCC gives up on a max of the exp2's argument); below that floor D < 2^-120 anyway. */
    const float nh_floor = alpha > 0.0f ? maxf(sl_fast_exp2(maxf((-120.0f - log2_c) / alpha, -126.0f)), TINY) : TINY;
    const vec3 F1 = sub(vec3s(1.0f), Ks);
    float cr[SL_ENV_LIGHTS_MAX], cg[SL_ENV_LIGHTS_MAX], cb[SL_ENV_LIGHTS_MAX];
#pragma omp simd
    for (int j = 0; j < n; j++) {
        float wN = (X[j] * N.x + Y[j] * N.y) + Z[j] * N.z;
        float hx = X[j] + V.x, hy = Y[j] + V.y, hz = Z[j] + V.z;
        float ih = 1.0f / sqrtf((hx * hx + hy * hy) + hz * hz);
        hx *= ih;
        hy *= ih;
        hz *= ih;
        float NdotH = (N.x * hx + N.y * hy) + N.z * hz;
        float LdotH = (X[j] * hx + Y[j] * hy) + Z[j] * hz;
        /* D = (alpha + 2)/(2 pi) (N.H)^alpha, exp2 of a log2 kept >= -120 by the floor on N.H */
        float D = sl_fast_exp2(log2_c + alpha * sl_fast_log2(maxf(NdotH, nh_floor)));
        float LH = maxf(LdotH, SL_BRDF_MIN_LDOTH);
        float mm = maxf(1.0f - LdotH, 0.0f);
        float m2 = mm * mm;
        float m5 = m2 * m2 * mm;
        float lit = (wN > 0.0f ? 1.0f : 0.0f) * (NdotH > 0.0f ? 1.0f : 0.0f); /* products, not &&: vectorizes */
        float g = 1.0f / (LH * LH); /* computed, then selected: a division under a branch stops GCC */
        float k = D * (inv_lh2 ? g : 1.0f) / 4.0f * wN * lit;
        cr[j] = (Ks.x + F1.x * m5) * k * LR[j];
        cg[j] = (Ks.y + F1.y * m5) * k * LG[j];
        cb[j] = (Ks.z + F1.z * m5) * k * LB[j];
    }
    vec3 sum = vec3s(0.0f);
    for (int j = 0; j < n; j++)
        sum = add(sum, vec3(cr[j], cg[j], cb[j]));
    return scale(sum, u->uEnvIntensity);
}

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
    float bg_r[SPAN], bg_g[SPAN], bg_b[SPAN]; /* background(), for the empty pixels */
} pixel_block;

static inline float select_f(bool c, float a, float b) { return c ? a : b; }

/* main() up to the samples (V, facing_normal, the environment frame) and specular_ibl's frame
 * (R, A, B; A, B about N for specular_microfacet), for pixels x0 .. x0 + count - 1 of G-buffer row y; empty pixels compute garbage
 * that nothing reads. facing_normal's two branches are selects: the chosen value is computed
 * by the same operations, so the same bits. */
static void pixel_stage(const sl_lighting_uniforms *u, const sl_gbuffer_texel *t, int count, pixel_block *p)
{
    const float ex = u->uEye.x, ey = u->uEye.y, ez = u->uEye.z;
    const vec3 c0 = u->uEnvRotation.c[0], c1 = u->uEnvRotation.c[1], c2 = u->uEnvRotation.c[2];
    const bool mf = u->uEstimator == ESTIMATOR_MICROFACET; /* the frame is about N, not R */
    for (int i = 0; i < count; i++) { /* to structure of arrays: the G-buffer texel is 56 bytes */
        p->Px[i] = t[i].position.x;
        p->Py[i] = t[i].position.y;
        p->Pz[i] = t[i].position.z;
        p->nx[i] = t[i].normal.x;
        p->ny[i] = t[i].normal.y;
        p->nz[i] = t[i].normal.z;
    }
#pragma omp simd
    for (int i = 0; i < count; i++) {
        vec3 V = normalize(vec3(ex - p->Px[i], ey - p->Py[i], ez - p->Pz[i]));
        /* facing_normal */
        vec3 n = vec3(p->nx[i], p->ny[i], p->nz[i]);
        float len2 = dot(n, n);
        vec3 Nn = scale(n, 1.0f / sqrtf(len2));
        float NdotV0 = dot(Nn, V);
        vec3 Nb = normalize(add(Nn, scale(V, MIN_NDOTV - NdotV0)));
        bool keep = len2 > TINY, bend = NdotV0 < MIN_NDOTV;
        vec3 N = vec3(select_f(keep, select_f(bend, Nb.x, Nn.x), V.x), select_f(keep, select_f(bend, Nb.y, Nn.y), V.y),
                      select_f(keep, select_f(bend, Nb.z, Nn.z), V.z));
        vec3 NE = add(add(scale(c0, N.x), scale(c1, N.y)), scale(c2, N.z)); /* mat3_mul_vec3 */
        vec3 VE = add(add(scale(c0, V.x), scale(c1, V.y)), scale(c2, V.z));
        /* specular_ibl's frame about R, or specular_microfacet's about N */
        float NdotV = dot(NE, VE);
        vec3 R = normalize(sub(scale(NE, 2.0f * NdotV), VE));
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
        p->bent[i] = dot(n, V) < MIN_NDOTV * length(n);
    }
}

/* background(), batched over the span: the same view ray, the fast lat-long map, and level 0
 * alone (lod 0), gathered from the block when there is one. */
static void background_stage(const sl_lighting_uniforms *u, int x0, int y, int count, pixel_block *p)
{
    const float I = u->uEnvIntensity;
    const sl_env_level *l0 = &u->uEnv->levels[0];
    const vec4 m[4] = {u->uInvViewProj.c[0], u->uInvViewProj.c[1], u->uInvViewProj.c[2], u->uInvViewProj.c[3]};
    const vec3 r[3] = {u->uEnvRotation.c[0], u->uEnvRotation.c[1], u->uEnvRotation.c[2]};
    const vec2 viewport = u->uViewport;
    if (u->envGather) {
        const vec3 *T = u->uEnv->block;
        const int W = u->envWidth[0], H = u->envHeight[0];
#pragma omp simd
        for (int i = 0; i < count; i++) {
            vec3 d = background_dir(m, r, viewport, vec2((float)(x0 + i) + 0.5f, (float)y + 0.5f));
            float bu, bv;
            sl_fast_dir_to_uv(d.x, d.y, d.z, &bu, &bv);
            vec3 c = block_bilinear(T, W, H, 0, bu, bv);
            p->bg_r[i] = c.x * I;
            p->bg_g[i] = c.y * I;
            p->bg_b[i] = c.z * I;
        }
    } else {
        for (int i = 0; i < count; i++) {
            vec3 d = background_dir(m, r, viewport, vec2((float)(x0 + i) + 0.5f, (float)y + 0.5f));
            float bu, bv;
            sl_fast_dir_to_uv(d.x, d.y, d.z, &bu, &bv);
            vec3 c = sl_env_bilinear(l0, bu, bv);
            p->bg_r[i] = c.x * I;
            p->bg_g[i] = c.y * I;
            p->bg_b[i] = c.z * I;
        }
    }
}

/* main(), batched: pixels x0 .. x0 + count - 1 (count <= SPAN) of G-buffer row y into out[].
 * A trace (count 1) records what the pixel computed. */
static void shade_span(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                       sl_lighting_task *task, sl_lighting_trace *trace, vec3 *out)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x0, y);
    pixel_block pb;
    pixel_block *p = &pb;
    pixel_stage(u, t, count, p);
    int empty = 0;
    for (int i = 0; i < count; i++)
        empty += t[i].depth >= 1.0f;
    if (empty > 0)
        background_stage(u, x0, y, count, p);
    for (int i = 0; i < count; i++) {
        const int x = x0 + i;
        vec3 color = vec3s(0.0f);
        if (trace) {
            trace->frag_coord = vec2((float)x + 0.5f, (float)y + 0.5f);
            trace->texel = t[i];
            trace->covered = !(t[i].depth >= 1.0f);
            trace->plain = false;
        }
        if (t[i].depth >= 1.0f) {
            color = vec3(p->bg_r[i], p->bg_g[i], p->bg_b[i]);
            if (trace)
                trace->background = color;
            if (task)
                task->stats.background++;
        } else {
            vec3 P = t[i].position;
            vec3 Kd = t[i].kd;
            vec3 Ks = t[i].ks;
            float alpha = clamp(t[i].alpha, 0.0f, MAX_ALPHA);
            vec3 V = vec3(p->Vx[i], p->Vy[i], p->Vz[i]);
            vec3 N = vec3(p->Nx[i], p->Ny[i], p->Nz[i]);
            vec3 Nenv = vec3(p->NEx[i], p->NEy[i], p->NEz[i]);
            vec3 Venv = vec3(p->VEx[i], p->VEy[i], p->VEz[i]);
            vec2 rotation = u->uRotate != 0 ? pixel_rotation(u, x, y) : vec2(0.0f, 0.0f);
            if (task)
                task->stats.bent_normals += p->bent[i];
            if (trace) {
                trace->V = V;
                trace->N = N;
                trace->bent = p->bent[i];
                trace->Nenv = Nenv;
                trace->Venv = Venv;
                trace->rotation = rotation;
                trace->alpha = alpha;
                trace->NdotV = p->NdotV[i];
                trace->R = vec3(p->Rx[i], p->Ry[i], p->Rz[i]);
                trace->A = vec3(p->Ax[i], p->Ay[i], p->Az[i]);
                trace->B = vec3(p->Bx[i], p->By[i], p->Bz[i]);
                trace->pole_frame = p->pole[i];
                trace->microfacet = u->uEstimator == ESTIMATOR_MICROFACET;
            }
            if (u->uDiffuse != 0) {
                vec3 E = irradiance(u, Nenv);
                vec3 diffuse = scale(mul(scale(Kd, 1.0f / PI), E), u->uEnvIntensity);
                color = add(color, diffuse);
                if (trace) {
                    trace->irradiance = E;
                    trace->diffuse = diffuse;
                }
            }
            if (u->uSpecular != 0) {
                vec3 specular = specular_samples(u, Nenv, Venv, vec3(p->Rx[i], p->Ry[i], p->Rz[i]),
                                                 vec3(p->Ax[i], p->Ay[i], p->Az[i]),
                                                 vec3(p->Bx[i], p->By[i], p->Bz[i]), p->pole[i], Ks, alpha,
                                                 rotation, task, trace);
                if (u->uEnvLightCount > 0) {
                    vec3 exact = env_lights_samples(u, Nenv, Venv, Ks, alpha);
                    specular = add(specular, exact);
                    if (trace) {
                        trace->env_light_count = u->uEnvLightCount;
                        trace->env_lights = exact;
                    }
                }
                color = add(color, specular);
                if (trace)
                    trace->specular = specular;
            }
            if (u->uPointLights != 0) {
                for (int l = 0; l < u->uLightCount; l++) {
                    vec3 light = point_light(u, l, P, N, V, Kd, Ks, alpha);
                    color = add(color, light);
                    if (trace) {
                        trace->light[l] = light;
                        trace->lights = add(trace->lights, light);
                    }
                }
            }
        }
        bool finite = finite3(color);
        if (!finite && task)
            task->stats.nonfinite++;
        if (trace) {
            trace->repaired = !finite;
            trace->total = finite ? color : vec3s(0.0f);
        }
        out[i] = finite ? color : vec3s(0.0f);
    }
}

/* The port or the batched path, as options.plain says; both count into the task. */
vec3 sl_lighting_shade(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y,
                       sl_lighting_task *task, sl_lighting_trace *trace)
{
    if (u->options.plain)
        return shade_plain(u, gb, x, y, task, trace);
    vec3 c;
    shade_span(u, gb, x, y, 1, task, trace, &c);
    return c;
}

void sl_lighting_shade_row(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                           sl_lighting_task *task, vec3 *out)
{
    for (int x = x0; x < x0 + count; x += SPAN) {
        int n = x0 + count - x < SPAN ? x0 + count - x : SPAN;
        if (u->options.plain)
            for (int i = 0; i < n; i++)
                out[x - x0 + i] = shade_plain(u, gb, x + i, y, task, NULL);
        else
            shade_span(u, gb, x, y, n, task, NULL, out + (x - x0));
    }
}

/* The shader's helpers, for tests and the viewer's mip-level view. */
float sl_lighting_mip_level(const sl_lighting_uniforms *u, float D, float pdf, vec3 w)
{
    return mip_level(u, D, pdf, w);
}

uint32_t sl_lighting_hash(uint32_t x) { return hash_u32(x); }

vec2 sl_lighting_pixel_rotation(int x, int y, uint32_t frame)
{
    sl_lighting_uniforms u = {.uFrame = frame};
    return pixel_rotation(&u, x, y);
}
