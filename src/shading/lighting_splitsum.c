/* lighting_splitsum.c - the split-sum estimator's fast path (--estimator splitsum without
 * --plain): main() of shaders/lighting.frag with specular_splitsum, over a span of a tile row
 * in loops that GCC vectorizes (`#pragma omp simd`). The port (lighting.c, specular_splitsum)
 * stays the reference; test_lighting_splitsum bounds the difference.
 *
 * Why a file of its own: a split-sum pixel has no samples, so the batched path's structure
 * (lighting_batched.c: a per-pixel call into the sample loops) leaves nothing to vectorize: in
 * scalar calls a 1280x720 frame takes 29-63 ms on 2 cores (the port's textureLod, sl_dir_to_uv's
 * acos and atan2, the table's filter, the irradiance, point lights with powf; docs/performance.md
 * "Split sum: the fast path"). Here every stage runs over the whole span at once, structure of
 * arrays (the background first; a span of background alone skips (1) to (6)):
 *   (1) the texels to arrays (empty pixels get a harmless stand-in, so every lane stays finite);
 *   (2) V, facing_normal, the environment frame and R (the batched pixel stage's operations);
 *   (3) the lobe width r (splitsum_width), the level r (levels - 1), the table (splitsum_lut)
 *       gathered from its texels, the lookup direction (splitsum_dir) and its lat-long uv
 *       through core/fast_math.h's atan2;
 *   (4) the prefiltered chain's trilinear fetch gathered from its compact rows (ibl/texel_e5.h,
 *       texture_lod.h sl_e5_gather_lod; within 2^-9 of a texel's largest channel of the port's
 *       float texels), the Phong or the GGX chain: one loop per chain a span uses, a select
 *       when it mixes;
 *   (5) the irradiance, vectorized: sl_irradiance_eval_span (the port's bits) for SH9 and the
 *       pole-free maps, the lat-long map's bilinear fetch at the fast atan2's uv; with the sky
 *       visibility maps, times their V a covered pixel at a time (sky_stage: the lighting pass's
 *       plane, sky_plane.c, or the port's lookup);
 *   (6) main()'s sum in the port's order: diffuse + specular, times the occlusion, each point
 *       light (a loop per light over the span; Phong's D through fast log2/exp2), emission;
 *   (7) the background of empty pixels (sl_shade_background_span, the batched path's);
 *   (8) each pixel's colour and the NaN guard: vector loops without a trace (finish_stage),
 *       else per pixel with the trace hooks.
 * Each stage is a function of its own, kept out of line: it shows in a profile, and GCC
 * vectorizes it alone (inlined into one large caller, some loops stay scalar).
 * The same operations run whether a loop is vectorized or not (only +, -, *, /, sqrt and
 * selects; -ffp-contract=off), so the pass, sl_lighting_shade and the trace agree bit for bit.
 *
 * Does not: env lights (their exact term is the batched path's loop, lighting_pass.c sends
 * those frames there), the per-pixel estimators, an environment chain without a block. */
#include <string.h>

#include "../core/fast_math.h"
#include "../ibl/texture_lod.h"
#include "lighting_internal.h"

/* GLSL constants, as lighting.c has them */
static const float TINY = SL_BRDF_TINY;
static const float MIN_LIGHT_D2 = 1e-8f; /* lighting.c point_light */
#define PI SL_PI

/* One span, structure of arrays. */
typedef struct {
    /* (1) the texels */
    float Px[SPAN], Py[SPAN], Pz[SPAN], nx[SPAN], ny[SPAN], nz[SPAN];
    float kdr[SPAN], kdg[SPAN], kdb[SPAN], ksr[SPAN], ksg[SPAN], ksb[SPAN], alpha[SPAN];
    float occ[SPAN], emr[SPAN], emg[SPAN], emb[SPAN];
    /* (2) the frame: world V, N; environment NE, VE, R */
    float Vx[SPAN], Vy[SPAN], Vz[SPAN], Nx[SPAN], Ny[SPAN], Nz[SPAN];
    float NEx[SPAN], NEy[SPAN], NEz[SPAN], Rx[SPAN], Ry[SPAN], Rz[SPAN], NdotV[SPAN];
    int bent[SPAN];
    /* (3) the lookup: width, level, R's uv, the table's A and B */
    float r[SPAN], lod[SPAN], u[SPAN], v[SPAN], A[SPAN], B[SPAN], T[SPAN];
    float Dx[SPAN], Dy[SPAN], Dz[SPAN]; /* the lookup direction (splitsum_dir) */
    /* (4) the prefiltered radiance along R (a second chain's, for a mixed span) */
    float pr[SPAN], pg[SPAN], pb[SPAN], qr[SPAN], qg[SPAN], qb[SPAN];
    /* (5) the irradiance; (6) the specular term and the colour */
    float er[SPAN], eg[SPAN], eb[SPAN], sr[SPAN], sg[SPAN], sb[SPAN], cr[SPAN], cg[SPAN], cb[SPAN];
    /* (7) the background of empty pixels */
    float bgr[SPAN], bgg[SPAN], bgb[SPAN];
} splitsum_block;

bool sl_shade_splitsum_fast(const sl_lighting_uniforms *u)
{
    return u->uEstimator == SL_ESTIMATOR_SPLITSUM && u->uEstimatorGGX == SL_ESTIMATOR_SPLITSUM && !u->options.plain && u->uEnvLightCount == 0 &&
           u->splitSumPhongGather.gather && u->splitSumGGXGather.gather &&
           u->uSplitSumPhong->level_count == u->uSplitSumGGX->level_count &&
           u->uSplitSumPhong->levels[0].width == u->uSplitSumGGX->levels[0].width &&
           u->uSplitSumPhong->levels[0].height == u->uSplitSumGGX->levels[0].height;
}

static inline float select_f(bool c, float a, float b) { return c ? a : b; }

/* (1) texels to arrays. An empty pixel (depth >= 1) gets a stand-in, a point one unit below
 * the eye with an upward normal and zero colour, so its lanes compute finite values nobody
 * reads. The extra plane (occlusion, emission; shade_extra) in a loop of its own, so neither
 * loop tests for the plane per pixel. The loop stays scalar (GCC has no vector type for the
 * texel's stride of 14 floats, and a gather from a table of offsets measures no faster). */
__attribute__((noinline)) /* a stage: see the top of the file */
static void load_stage(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                       splitsum_block *b)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x0, y);
    const vec3 below = sub(u->uEye, vec3(0.0f, 0.0f, 1.0f));
    for (int i = 0; i < count; i++) {
        bool empty = t[i].depth >= 1.0f;
        b->Px[i] = select_f(empty, below.x, t[i].position.x);
        b->Py[i] = select_f(empty, below.y, t[i].position.y);
        b->Pz[i] = select_f(empty, below.z, t[i].position.z);
        b->nx[i] = select_f(empty, 0.0f, t[i].normal.x);
        b->ny[i] = select_f(empty, 0.0f, t[i].normal.y);
        b->nz[i] = select_f(empty, 1.0f, t[i].normal.z);
        b->kdr[i] = select_f(empty, 0.0f, t[i].kd.x);
        b->kdg[i] = select_f(empty, 0.0f, t[i].kd.y);
        b->kdb[i] = select_f(empty, 0.0f, t[i].kd.z);
        b->ksr[i] = select_f(empty, 0.0f, t[i].ks.x);
        b->ksg[i] = select_f(empty, 0.0f, t[i].ks.y);
        b->ksb[i] = select_f(empty, 0.0f, t[i].ks.z);
        b->alpha[i] = select_f(empty, 1.0f, shade_lobe_param(t[i].alpha));
    }
    if (!gb->extra) { /* shade_extra's "none" */
#pragma omp simd
        for (int i = 0; i < count; i++) {
            b->occ[i] = 1.0f;
            b->emr[i] = 0.0f;
            b->emg[i] = 0.0f;
            b->emb[i] = 0.0f;
        }
        return;
    }
    const sl_gbuffer_extra *e = gb->extra + (size_t)y * (size_t)gb->width + (size_t)x0;
#pragma omp simd
    for (int i = 0; i < count; i++) {
        b->occ[i] = e[i].occlusion;
        b->emr[i] = e[i].emissive.x;
        b->emg[i] = e[i].emissive.y;
        b->emb[i] = e[i].emissive.z;
    }
}

/* (2) main() up to the estimator: shade_view_frame_at (V, facing_normal, the environment frame,
 * R = reflect(-V, N)) into the span's arrays. */
__attribute__((noinline)) /* a stage: see the top of the file */
static void frame_stage(const sl_lighting_uniforms *u, int count, splitsum_block *b)
{
    const vec3 eye = u->uEye;
    const vec3 r[3] = {u->uEnvRotation.c[0], u->uEnvRotation.c[1], u->uEnvRotation.c[2]};
#pragma omp simd
    for (int i = 0; i < count; i++) {
        shade_view_frame f =
            shade_view_frame_at(eye, vec3(b->Px[i], b->Py[i], b->Pz[i]), vec3(b->nx[i], b->ny[i], b->nz[i]), r);
        b->bent[i] = f.bent;
        b->Vx[i] = f.V.x;
        b->Vy[i] = f.V.y;
        b->Vz[i] = f.V.z;
        b->Nx[i] = f.N.x;
        b->Ny[i] = f.N.y;
        b->Nz[i] = f.N.z;
        b->NEx[i] = f.NE.x;
        b->NEy[i] = f.NE.y;
        b->NEz[i] = f.NE.z;
        b->Rx[i] = f.R.x;
        b->Ry[i] = f.R.y;
        b->Rz[i] = f.R.z;
        b->NdotV[i] = f.NdotV;
    }
}

/* x clamped to [0, hi], NaN to 0: these values index texels. */
static inline float clamp_index(float x, float hi)
{
    x = x > 0.0f ? x : 0.0f;
    return x < hi ? x : hi;
}

/* (3) splitsum_width, the level, the table's A, B, t (splitsum_lut: texel centres of the
 * pixel's set; the set is GGX for alpha < 0, else the Phong set of uGTerm), the lookup
 * direction and its lat-long uv. */
__attribute__((noinline)) /* a stage: see the top of the file */
static void lookup_stage(const sl_lighting_uniforms *u, int count, splitsum_block *b)
{
    enum { S = SL_SPLITSUM_LUT_SIZE };
    const float max_lod = u->uSplitSumMaxLod;
    const float phong_set = (float)(u->uGTerm == SL_GTERM_INV_LH2 ? SL_SPLITSUM_PHONG_INV_LH2 : SL_SPLITSUM_PHONG_ONE);
    const vec3 *lut = u->uSplitSumLut->texels;
    float tx[SPAN], ty[SPAN];
#pragma omp simd
    for (int i = 0; i < count; i++) {
        float alpha = b->alpha[i];
        /* sl_splitsum_width of either set, blended by a 0/1 factor (exact: x 1 + y 0 = x for
         * finite y; a select lets GCC sink the division into a branch and give up) */
        float g = alpha < 0.0f ? 1.0f : 0.0f;
        float r = (-1.0f - alpha) * g + sqrtf(sqrtf(2.0f / (maxf(alpha, 0.0f) + 2.0f))) * (1.0f - g);
        float set = g * (float)SL_SPLITSUM_GGX + (1.0f - g) * phong_set;
        b->r[i] = r;
        b->lod[i] = clamp_index(r * max_lod, max_lod);
        /* the table's texel coordinates: the port's uv times the size, minus half a texel,
         * without the round trip (so within float rounding of the port's) */
        tx[i] = clamp_index(b->NdotV[i], 1.0f) * (float)(S - 1);
        ty[i] = set * (float)S + clamp_index(r, 1.0f) * (float)(S - 1);
    }
    /* Bilinear within the set: the coordinates are in range, so no wrap, and the last row and
     * column of a set clamp to themselves. A texel's A and B are adjacent floats, read as one
     * 64-bit value (texture_lod.h sl_load_float2: 4 gathered elements a pixel instead of 8, the
     * same bits); the offsets are float indices from the table's base (the form GCC gathers). */
    const float *L = &lut[0].x;
#pragma omp simd
    for (int i = 0; i < count; i++) {
        int x0 = (int)tx[i], y0 = (int)ty[i];
        float fx = tx[i] - (float)x0, fy = ty[i] - (float)y0;
        int x1 = x0 + (fx > 0.0f ? 1 : 0), y1 = y0 + (fy > 0.0f ? 1 : 0);
        float a00, b00, a10, b10, a01, b01, a11, b11;
        sl_load_float2(L + 3 * (y0 * S + x0), &a00, &b00);
        sl_load_float2(L + 3 * (y0 * S + x1), &a10, &b10);
        sl_load_float2(L + 3 * (y1 * S + x0), &a01, &b01);
        sl_load_float2(L + 3 * (y1 * S + x1), &a11, &b11);
        b->A[i] = mixf(mixf(a00, a10, fx), mixf(a01, a11, fx), fy);
        b->B[i] = mixf(mixf(b00, b10, fx), mixf(b01, b11, fx), fy);
        float t00 = L[3 * (y0 * S + x0) + 2], t10 = L[3 * (y0 * S + x1) + 2];
        float t01 = L[3 * (y1 * S + x0) + 2], t11 = L[3 * (y1 * S + x1) + 2];
        b->T[i] = mixf(mixf(t00, t10, fx), mixf(t01, t11, fx), fy);
    }
    /* the lookup direction splitsum_dir = normalize(mix(N, R, t)) and its lat-long uv */
#pragma omp simd
    for (int i = 0; i < count; i++) {
        float t = b->T[i];
        vec3 d = normalize(add(scale(vec3(b->NEx[i], b->NEy[i], b->NEz[i]), 1.0f - t),
                               scale(vec3(b->Rx[i], b->Ry[i], b->Rz[i]), t)));
        float uu, vv;
        sl_fast_dir_to_uv(d.x, d.y, d.z, &uu, &vv);
        b->Dx[i] = d.x;
        b->Dy[i] = d.y;
        b->Dz[i] = d.z;
        b->u[i] = uu;
        b->v[i] = vv;
    }
}

/* (4) one chain's trilinear fetch along R for the whole span, into (r, g, b): from the chain's
 * compact rows when it has them (ibl.h sl_env.e5, built by sl_env_prefilter: 4 64-bit gathers a
 * sample, texels within 2^-9 of their largest channel, texel_e5.h), else from its block (the
 * port's bits). Both chains of a span go through here, so the viewer's moving frame and its
 * exact frame read the same texels. */
static void fetch_chain(const sl_env_gather *g, int count, const splitsum_block *b, float *fr, float *fg, float *fb)
{
    if (g->e5) {
#pragma omp simd
        for (int i = 0; i < count; i++) {
            vec3 c = sl_e5_gather_lod(g, b->u[i], b->v[i], b->lod[i]);
            fr[i] = c.x;
            fg[i] = c.y;
            fb[i] = c.z;
        }
        return;
    }
#pragma omp simd
    for (int i = 0; i < count; i++) {
        vec3 c = sl_env_gather_lod(g, b->u[i], b->v[i], b->lod[i]);
        fr[i] = c.x;
        fg[i] = c.y;
        fb[i] = c.z;
    }
}

/* (4) the prefiltered radiance P, then the specular term P (Ks A + B) times the intensity. */
__attribute__((noinline)) /* a stage: see the top of the file */
static void specular_stage(const sl_lighting_uniforms *u, int count, splitsum_block *b)
{
    int ggx = 0;
    for (int i = 0; i < count; i++)
        ggx += b->alpha[i] < 0.0f;
    if (ggx < count) /* the Phong chain for the span */
        fetch_chain(&u->splitSumPhongGather, count, b, b->pr, b->pg, b->pb);
    if (ggx > 0 && ggx < count) { /* mixed: the GGX chain too, and a select */
        fetch_chain(&u->splitSumGGXGather, count, b, b->qr, b->qg, b->qb);
#pragma omp simd
        for (int i = 0; i < count; i++) {
            bool g = b->alpha[i] < 0.0f;
            b->pr[i] = select_f(g, b->qr[i], b->pr[i]);
            b->pg[i] = select_f(g, b->qg[i], b->pg[i]);
            b->pb[i] = select_f(g, b->qb[i], b->pb[i]);
        }
    } else if (ggx == count) {
        fetch_chain(&u->splitSumGGXGather, count, b, b->pr, b->pg, b->pb);
    }
    const float I = u->uEnvIntensity;
#pragma omp simd
    for (int i = 0; i < count; i++) {
        float A = b->A[i], B = b->B[i];
        b->sr[i] = (b->pr[i] * (b->ksr[i] * A + B)) * I;
        b->sg[i] = (b->pg[i] * (b->ksg[i] * A + B)) * I;
        b->sb[i] = (b->pb[i] * (b->ksb[i] * A + B)) * I;
    }
}

/* (5) irradiance(Nenv), as sl_irradiance_eval computes it: SH9 and the OCT and DP maps through
 * sl_irradiance_eval_span (ibl/irradiance.c: vector loops, the same bits); the lat-long maps
 * here through the fast atan2 (within 2.4e-7 rad of the port's uv), where the span lookup would
 * call libm a lane at a time. Negative (SH ringing) and NaN become 0. */
__attribute__((noinline)) /* a stage: see the top of the file */
static void irradiance_stage(const sl_lighting_uniforms *u, int count, splitsum_block *b)
{
    const sl_irradiance *irr = u->uIrradiance;
    if (irr->method == SL_IRRADIANCE_SH9 || irr->method == SL_IRRADIANCE_OCT || irr->method == SL_IRRADIANCE_DP) {
        sl_irradiance_eval_span(irr, count, b->NEx, b->NEy, b->NEz, b->er, b->eg, b->eb);
        return;
    }
    const sl_env_level *l0 = &irr->map.levels[0];
    float tu[SPAN], tv[SPAN];
#pragma omp simd
    for (int i = 0; i < count; i++)
        sl_fast_dir_to_uv(b->NEx[i], b->NEy[i], b->NEz[i], &tu[i], &tv[i]);
    const vec3 *T = l0->texels;
    const int w = l0->width, h = l0->height;
#pragma omp simd
    for (int i = 0; i < count; i++) {
        vec3 e = sl_texels_bilinear(T, w, h, 0, tu[i], tv[i]);
        b->er[i] = e.x > 0.0f ? e.x : 0.0f;
        b->eg[i] = e.y > 0.0f ? e.y : 0.0f;
        b->eb[i] = e.z > 0.0f ? e.z : 0.0f;
    }
}

/* (5) with the sky visibility maps, their V on each covered pixel's irradiance: the port's
 * scale(E, V), V from the pass's plane (sky_row: the span's part of it) where it has one, else
 * the port's lookup (src/shadow/sky.h: one over the maps a pixel). */
__attribute__((noinline)) /* a stage: see the top of the file */
static void sky_stage(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                      const float *sky_row, splitsum_block *b)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x0, y);
    for (int i = 0; i < count; i++) {
        if (t[i].depth >= 1.0f)
            continue;
        float V = sky_row ? sky_row[i]
                          : sl_shadow_sky_visibility(u->skyMaps, t[i].position, vec3(b->Nx[i], b->Ny[i], b->Nz[i]), NULL);
        b->er[i] *= V;
        b->eg[i] *= V;
        b->eb[i] *= V;
    }
}

/* (6) main()'s sum without the point lights, in sl_shade_surface_color's order: diffuse
 * (Kd / pi) E I, plus the specular term, times the occlusion. */
__attribute__((noinline)) /* a stage: see the top of the file */
static void sum_stage(const sl_lighting_uniforms *u, int count, splitsum_block *b)
{
    const float I = u->uEnvIntensity;
    const float d = u->uDiffuse != 0 ? 1.0f : 0.0f, s = u->uSpecular != 0 ? 1.0f : 0.0f;
#pragma omp simd
    for (int i = 0; i < count; i++) {
        /* a term that is off adds exactly 0 (0 x finite); the port skips it */
        float dr = ((b->kdr[i] * (1.0f / PI)) * b->er[i]) * I;
        float dg = ((b->kdg[i] * (1.0f / PI)) * b->eg[i]) * I;
        float db = ((b->kdb[i] * (1.0f / PI)) * b->eb[i]) * I;
        b->cr[i] = (dr * d + b->sr[i] * s) * b->occ[i];
        b->cg[i] = (dg * d + b->sg[i] * s) * b->occ[i];
        b->cb[i] = (db * d + b->sb[i] * s) * b->occ[i];
    }
}

/* (6) point_light j for the span, added to the colour: lighting.c's formula, Phong's
 * (N.H)^alpha as exp2(alpha log2 N.H) with the argument kept >= -126 (below, D < 1e-37),
 * GGX's D and G as brdf.h has them, each set computed and one selected. */
__attribute__((noinline)) /* a stage: see the top of the file */
static void point_light_stage(const sl_lighting_uniforms *u, int j, int count, splitsum_block *b,
                              sl_lighting_trace *trace)
{
    const vec3 LP = u->uLightPosition[j];
    const vec3 LC = u->uLightColor[j];
    const float LI = u->uLightIntensity[j];
    const float diffuse = u->uDiffuse != 0 ? 1.0f : 0.0f, specular = u->uSpecular != 0 ? 1.0f : 0.0f;
    const float g_inv = u->uGTerm == SL_GTERM_INV_LH2 ? 1.0f : 0.0f;
    float lr[SPAN], lg[SPAN], lb[SPAN];
#pragma omp simd
    for (int i = 0; i < count; i++) {
        float tx = LP.x - b->Px[i], ty = LP.y - b->Py[i], tz = LP.z - b->Pz[i];
        float d2 = (tx * tx + ty * ty) + tz * tz;
        float il = 1.0f / sqrtf(maxf(d2, MIN_LIGHT_D2));
        vec3 L = vec3(tx * il, ty * il, tz * il);
        vec3 N = vec3(b->Nx[i], b->Ny[i], b->Nz[i]), V = vec3(b->Vx[i], b->Vy[i], b->Vz[i]);
        float NdotL = dot(N, L);
        vec3 H = normalize(add(L, V));
        float LdotH = dot(L, H), NdotH = dot(N, H), NdotV = dot(N, V);
        float alpha = b->alpha[i];
        float gsel = alpha < 0.0f ? 1.0f : 0.0f;
        /* Phong: D = (alpha + 2) / (2 pi) (N.H)^alpha, G = 1/(L.H)^2 or 1 */
        float pa = maxf(alpha, 0.0f);
        /* exp2 needs its argument >= -126: the log2 is floored at -125 / alpha (D < 1e-37
         * there), not the product (GCC does not vectorize a max of exp2's argument) */
        float l2 = maxf(sl_fast_log2(maxf(NdotH, TINY)), -125.0f / maxf(pa, 1.0f));
        float Dp = (pa + 2.0f) / (2.0f * PI) * sl_fast_exp2(pa * l2);
        float LH = maxf(LdotH, SL_BRDF_MIN_LDOTH);
        float Gp = (1.0f / (LH * LH)) * g_inv + (1.0f - g_inv); /* 0/1 blend, as in lookup_stage */
        /* GGX: a^2 from alpha in [-2, -1] (clamped for Phong lanes, whose value is dropped) */
        float rg = -1.0f - minf(alpha, -1.0f);
        float a = maxf(rg * rg, SL_GGX_MIN_A);
        float a2 = a * a;
        float c2 = NdotH * NdotH;
        float t = maxf(1.0f - c2, 0.0f) + c2 * a2;
        float Dg = a2 / (PI * t * t);
        float gv = NdotL * sqrtf(NdotV * NdotV * (1.0f - a2) + a2);
        float gl = NdotV * sqrtf(NdotL * NdotL * (1.0f - a2) + a2);
        float Gg = 2.0f / maxf(gv + gl, TINY); /* > 0 wherever the light is lit */
        float D = Dg * gsel + Dp * (1.0f - gsel), G = Gg * gsel + Gp * (1.0f - gsel); /* 0/1 blends */
        float m = maxf(1.0f - LdotH, 0.0f);
        float m2 = m * m;
        float m5 = m2 * m2 * m;
        float k = D * G / 4.0f * specular;
        float fr = b->kdr[i] * (1.0f / PI) * diffuse + (b->ksr[i] + (1.0f - b->ksr[i]) * m5) * k;
        float fg = b->kdg[i] * (1.0f / PI) * diffuse + (b->ksg[i] + (1.0f - b->ksg[i]) * m5) * k;
        float fb = b->kdb[i] * (1.0f / PI) * diffuse + (b->ksb[i] + (1.0f - b->ksb[i]) * m5) * k;
        float w = LI / maxf(d2, MIN_LIGHT_D2) * NdotL; /* d2 itself wherever lit */
        bool lit = (d2 >= MIN_LIGHT_D2) & (NdotL > 0.0f); /* &, not &&: no branch in the loop */
        lr[i] = select_f(lit, fr * LC.x * w, 0.0f);
        lg[i] = select_f(lit, fg * LC.y * w, 0.0f);
        lb[i] = select_f(lit, fb * LC.z * w, 0.0f);
    }
    /* the light's shadow-map visibility where it adds something (lighting.c's
     * shadowed_point_light), a scalar loop: each lookup is a filtered read of its cube */
    if (u->shadowMaps)
        for (int i = 0; i < count; i++)
            if (lr[i] > 0.0f || lg[i] > 0.0f || lb[i] > 0.0f) {
                float v = sl_shadow_point_visibility(u->shadowMaps, j, vec3(b->Px[i], b->Py[i], b->Pz[i]),
                                                     vec3(b->Nx[i], b->Ny[i], b->Nz[i]));
                lr[i] *= v;
                lg[i] *= v;
                lb[i] *= v;
            }
#pragma omp simd
    for (int i = 0; i < count; i++) {
        b->cr[i] += lr[i];
        b->cg[i] += lg[i];
        b->cb[i] += lb[i];
    }
    trace_light(trace, j, vec3(lr[0], lg[0], lb[0]));
}

/* Stages (1) to (6) for a span with covered pixels (an empty pixel's lanes compute values that
 * nobody reads). */
static void surface_stages(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                           const float *sky_row, splitsum_block *b, sl_lighting_trace *trace)
{
    load_stage(u, gb, x0, y, count, b);
    frame_stage(u, count, b);
    lookup_stage(u, count, b);
    specular_stage(u, count, b);
    if (u->uDiffuse != 0) {
        irradiance_stage(u, count, b);
        if (u->skyMaps)
            sky_stage(u, gb, x0, y, count, sky_row, b);
    } else { /* sum_stage multiplies the diffuse term by 0 */
        memset(b->er, 0, sizeof b->er);
        memset(b->eg, 0, sizeof b->eg);
        memset(b->eb, 0, sizeof b->eb);
    }
    sum_stage(u, count, b);
    if (u->uPointLights != 0)
        for (int j = 0; j < u->uLightCount; j++)
            point_light_stage(u, j, count, b, trace);
}

/* x - x is 0 exactly for a finite x, NaN for NaN and Inf (isfinite does not vectorize). */
static inline bool finite3(float r, float g, float b) { return (r - r == 0.0f) & (g - g == 0.0f) & (b - b == 0.0f); }

/* (8) without a trace (the pass, the viewer): each pixel's colour, the background or the
 * surface's sum plus its emission, through sl_shade_finish's NaN guard, in vector loops over the
 * span (per pixel calls were 10% of the stage). The same operations as the traced loop below,
 * so the same bits. The counters as sl_shade_finish, trace_background and the bent normals. */
__attribute__((noinline)) /* a stage: see the top of the file */
static void finish_stage(const sl_lighting_uniforms *u, const sl_gbuffer_texel *t, int count, int empty,
                         sl_lighting_task *task, splitsum_block *b, vec3 *out)
{
    float *cr = b->cr, *cg = b->cg, *cb = b->cb;
    if (empty == count) { /* the surface stages did not run */
        cr = b->bgr;
        cg = b->bgg;
        cb = b->bgb;
    } else {
        if (u->uDiffuse == 0) { /* emission travels with the diffuse term: + 0, as the loop below */
            memset(b->emr, 0, sizeof b->emr);
            memset(b->emg, 0, sizeof b->emg);
            memset(b->emb, 0, sizeof b->emb);
        }
        int bent = 0;
        if (empty == 0) {
#pragma omp simd reduction(+ : bent)
            for (int i = 0; i < count; i++) {
                cr[i] = cr[i] + b->emr[i];
                cg[i] = cg[i] + b->emg[i];
                cb[i] = cb[i] + b->emb[i];
                bent += b->bent[i];
            }
        } else { /* mixed: the background arrays are filled too */
#pragma omp simd reduction(+ : bent)
            for (int i = 0; i < count; i++) {
                bool covered = !(t[i].depth >= 1.0f);
                cr[i] = select_f(covered, cr[i] + b->emr[i], b->bgr[i]);
                cg[i] = select_f(covered, cg[i] + b->emg[i], b->bgg[i]);
                cb[i] = select_f(covered, cb[i] + b->emb[i], b->bgb[i]);
                bent += covered ? b->bent[i] : 0;
            }
        }
        if (task)
            task->stats.bent_normals += bent;
    }
    int nonfinite = 0;
#pragma omp simd reduction(+ : nonfinite)
    for (int i = 0; i < count; i++) {
        bool ok = finite3(cr[i], cg[i], cb[i]);
        out[i].x = select_f(ok, cr[i], 0.0f);
        out[i].y = select_f(ok, cg[i], 0.0f);
        out[i].z = select_f(ok, cb[i], 0.0f);
        nonfinite += ok ? 0 : 1;
    }
    if (task) {
        task->stats.nonfinite += nonfinite;
        task->stats.background += empty;
    }
}

void sl_shade_span_splitsum(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                         sl_lighting_task *task, sl_lighting_trace *trace, vec3 *out)
{
    splitsum_block blk;
    splitsum_block *b = &blk;
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x0, y);
    int empty = 0;
    for (int i = 0; i < count; i++)
        empty += t[i].depth >= 1.0f;
    if (empty > 0)
        sl_shade_background_span(u, x0, y, count, b->bgr, b->bgg, b->bgb);
    if (empty < count) /* a span of background alone (much of a frame) lights nothing */
        surface_stages(u, gb, x0, y, count, shade_sky_row(task, gb, x0, y), b, trace);
    if (!trace) {
        finish_stage(u, t, count, empty, task, b, out);
        return;
    }
    for (int i = 0; i < count; i++) {
        const int x = x0 + i;
        vec3 color;
        trace_texel(trace, &t[i], vec2((float)x + 0.5f, (float)y + 0.5f), false);
        if (t[i].depth >= 1.0f) {
            color = vec3(b->bgr[i], b->bgg[i], b->bgb[i]);
            trace_background(task, trace, color);
        } else {
            /* emission travels with the diffuse term (lighting.c sl_shade_surface_color) */
            vec3 em = u->uDiffuse != 0 ? vec3(b->emr[i], b->emg[i], b->emb[i]) : vec3s(0.0f);
            color = add(vec3(b->cr[i], b->cg[i], b->cb[i]), em);
            if (task)
                task->stats.bent_normals += b->bent[i];
            if (trace) { /* count is 1: what the pixel computed, at the port's hooks */
                shade_surface s = {
                    .P = t[i].position, .Kd = t[i].kd, .Ks = t[i].ks, .alpha = b->alpha[i],
                    .V = vec3(b->Vx[i], b->Vy[i], b->Vz[i]), .N = vec3(b->Nx[i], b->Ny[i], b->Nz[i]),
                    .Nenv = vec3(b->NEx[i], b->NEy[i], b->NEz[i]),
                    .Venv = mat3_mul_vec3(u->uEnvRotation, vec3(b->Vx[i], b->Vy[i], b->Vz[i])),
                    .occlusion = b->occ[i], .emissive = vec3(b->emr[i], b->emg[i], b->emb[i])};
                trace_surface(u, NULL, trace, &s, b->bent[i]);
                vec3 E = vec3(b->er[i], b->eg[i], b->eb[i]);
                if (u->uDiffuse != 0)
                    trace_diffuse(trace, E, scale(mul(scale(s.Kd, 1.0f / PI), E), u->uEnvIntensity));
                trace_splitsum(trace, s.Nenv, s.Venv, vec3(b->Rx[i], b->Ry[i], b->Rz[i]), b->r[i], b->lod[i],
                               vec3(b->Dx[i], b->Dy[i], b->Dz[i]), vec3(b->pr[i], b->pg[i], b->pb[i]),
                               vec3(b->A[i], b->B[i], b->T[i]));
                if (u->uSpecular != 0)
                    trace_specular(trace, vec3(b->sr[i], b->sg[i], b->sb[i]));
                trace_extra(trace, s.occlusion, s.emissive);
            }
        }
        out[i] = sl_shade_finish(color, task, trace);
    }
}
