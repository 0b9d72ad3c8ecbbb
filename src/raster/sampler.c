/* sampler.c - samplers: wrap modes, nearest and bilinear filtering of a level, the level of
 * detail from derivatives and the min/mag and mip-level choice, and the GLSL built-ins on top.
 *
 * Every rule here is GL 4.6 section 8.14 as Mesa 22.3's llvmpipe implements it (texture.h says
 * what was measured and how). The shader-facing functions are plain C calls a fragment shader
 * makes per fragment; they only read the texture and the sampler, so any number of threads may
 * sample one texture at once. */
#include <math.h>
#include <stdint.h>
#include <string.h>
#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "raster.h" /* SL_QUADS_MAX: the most quads a multi-quad call samples */
#include "texture_internal.h"

sl_sampler_state sl_sampler_default(void)
{
    return (sl_sampler_state){
        .min_filter = SL_NEAREST_MIPMAP_LINEAR,
        .mag_filter = SL_LINEAR,
        .wrap_s = SL_REPEAT,
        .wrap_t = SL_REPEAT,
        .lod_bias = 0.0f,
        .min_lod = -1000.0f,
        .max_lod = 1000.0f,
    };
}

/* A texel-space coordinate made safe to convert to int: NaN -> 0, beyond +-2^24 clamped (a
 * float there has no fraction left, so no sample position is lost). */
static inline __attribute__((always_inline)) float safe_coord(float x)
{
    const float limit = 16777216.0f;
    /* plain selects (no nested one): GCC 12 if-converts them, so the multi-quad loops vectorize */
    float c = x <= limit ? x : limit, d = x < 0.0f ? -limit : 0.0f;
    return x >= -limit ? c : d;
}

/* Texel index i of a level n texels wide, wrapped (GL 4.6 table 8.20, on integer indices). */
static inline __attribute__((always_inline)) int wrap_index(int i, int n, sl_wrap mode)
{
    if ((unsigned)i < (unsigned)n) /* inside: every mode leaves it (and skips the divisions) */
        return i;
    switch (mode) {
    case SL_REPEAT: {
        if ((n & (n - 1)) == 0) /* a power of two: the remainder is a mask (two's complement) */
            return (int)((unsigned)i & (unsigned)(n - 1));
        int r = i % n;
        return r < 0 ? r + n : r;
    }
    case SL_MIRRORED_REPEAT: {
        int r = i % (2 * n);
        if (r < 0)
            r += 2 * n;
        return r < n ? r : 2 * n - 1 - r;
    }
    case SL_CLAMP_TO_EDGE:
        break;
    }
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

/* The two indices bilinear filtering reads, i and i + 1, wrapped: wrap_index on each, with one
 * wrap instead of two for REPEAT (i + 1 wraps to 0 exactly when i wrapped to n - 1). */
static inline __attribute__((always_inline)) void wrap_pair(int i, int n, sl_wrap mode, int *i0, int *i1)
{
    if (i >= 0 && i < n - 1) {
        *i0 = i;
        *i1 = i + 1;
    } else if (mode == SL_REPEAT) {
        *i0 = wrap_index(i, n, mode);
        *i1 = *i0 + 1 < n ? *i0 + 1 : 0;
    } else {
        *i0 = wrap_index(i, n, mode);
        *i1 = wrap_index(i + 1, n, mode);
    }
}

/* The fetch path, written once and instantiated per format (FORMAT_FUNCTIONS below): fmt is a
 * constant in each instance, so tex_decode's switch and the texel size fold away and a sample
 * pays one indirect call for its format instead of a switch per texel. */

/* Bilinear filtering of level lv at texel-space (x, y) (texture_internal.h's sl_tex_bilinear). */
static inline __attribute__((always_inline)) vec4 bilinear_as(sl_texture_format fmt, const sl_texture *t,
                                                               const tex_level *lv, float x, float y,
                                                               sl_wrap wrap_s, sl_wrap wrap_t)
{
    x = safe_coord(x);
    y = safe_coord(y);
    float fx = floorf(x), fy = floorf(y);
    float a = x - fx, b = y - fy;
    int i0, i1, j0, j1;
    wrap_pair((int)fx, lv->width, wrap_s, &i0, &i1);
    wrap_pair((int)fy, lv->height, wrap_t, &j0, &j1);
    const size_t tb = (size_t)tex_format_bytes(fmt), row = (size_t)lv->width * tb;
    const unsigned char *r0 = lv->texels + (size_t)j0 * row, *r1 = lv->texels + (size_t)j1 * row;
    vec4 bottom = mix4(tex_decode(t, fmt, r0 + (size_t)i0 * tb), tex_decode(t, fmt, r0 + (size_t)i1 * tb), a);
    vec4 top = mix4(tex_decode(t, fmt, r1 + (size_t)i0 * tb), tex_decode(t, fmt, r1 + (size_t)i1 * tb), a);
    return mix4(bottom, top, b);
}

/* Level l filtered at uv: nearest (the texel containing uv) or bilinear (the four around it). */
static inline __attribute__((always_inline)) vec4 level_as(sl_texture_format fmt, const sl_texture *t,
                                                            const tex_level *lv, vec2 uv, bool linear,
                                                            const sl_sampler_state *st)
{
    float x = uv.x * (float)lv->width, y = uv.y * (float)lv->height;
    if (linear)
        return bilinear_as(fmt, t, lv, x - 0.5f, y - 0.5f, st->wrap_s, st->wrap_t);
    int i = wrap_index((int)floorf(safe_coord(x)), lv->width, st->wrap_s);
    int j = wrap_index((int)floorf(safe_coord(y)), lv->height, st->wrap_t);
    return tex_decode(t, fmt, lv->texels + ((size_t)j * (size_t)lv->width + (size_t)i) * (size_t)tex_format_bytes(fmt));
}

/* The levels a sample at an (already biased and clamped) lambda reads: the min/mag choice and
 * the level selection of GL 4.6 section 8.14 (sl_texture_sample), made once per sample (and once
 * per quad by the four-lane form, whose lanes share lambda). Level `level`, and with two levels
 * level + 1 mixed in by `frac`; each filtered bilinearly (`linear`) or nearest. */
typedef struct {
    int level, count;
    float frac;
    bool linear;
} tex_pick;

static inline __attribute__((always_inline)) tex_pick pick_levels(const sl_texture *t, const sl_sampler_state *st,
                                                                   float lambda)
{
    if (!(lambda > 0.0f)) /* magnified (c = 0 for every filter pair; NaN lands here too) */
        return (tex_pick){0, 1, 0.0f, st->mag_filter == SL_LINEAR};
    int last = t->levels - 1;
    bool linear = st->min_filter == SL_LINEAR || st->min_filter == SL_LINEAR_MIPMAP_NEAREST ||
                  st->min_filter == SL_LINEAR_MIPMAP_LINEAR;
    switch (st->min_filter) {
    case SL_NEAREST:
    case SL_LINEAR:
        return (tex_pick){0, 1, 0.0f, linear};
    case SL_NEAREST_MIPMAP_NEAREST:
    case SL_LINEAR_MIPMAP_NEAREST:
        /* the nearest level: round(lambda), halves to even as llvmpipe's iround (measured:
         * 0.5 -> 0, 1.5 -> 2, 2.5 -> 2); GL's ceil(lambda + 1/2) - 1 rounds them down */
        return (tex_pick){lambda >= (float)last ? last : (int)rintf(lambda), 1, 0.0f, linear};
    case SL_NEAREST_MIPMAP_LINEAR:
    case SL_LINEAR_MIPMAP_LINEAR:
        break;
    }
    if (lambda >= (float)last)
        return (tex_pick){last, 1, 0.0f, linear};
    float fl = floorf(lambda);
    return (tex_pick){(int)fl, 2, lambda - fl, linear};
}

/* A complete texture sampled at an (already biased and clamped) lambda (sl_texture_sample). `lv`
 * is the chain read: the stored levels (t->level, format fmt) or the decoded plane (t->plane,
 * RGBA32F). */
static inline __attribute__((always_inline)) vec4 sample_as(sl_texture_format fmt, const sl_texture *t,
                                                             const tex_level *lv, const sl_sampler_state *st,
                                                             vec2 uv, float lambda)
{
    tex_pick p = pick_levels(t, st, lambda);
    vec4 v = level_as(fmt, t, &lv[p.level], uv, p.linear, st);
    if (p.count == 1)
        return v;
    return mix4(v, level_as(fmt, t, &lv[p.level + 1], uv, p.linear, st), p.frac);
}

/* One instance of each per format, and the tables that pick them by t->format. */
typedef vec4 bilinear_fn(const sl_texture *t, const tex_level *lv, float x, float y, sl_wrap wrap_s, sl_wrap wrap_t);
typedef vec4 sample_fn(const sl_texture *t, const sl_sampler_state *st, vec2 uv, float lambda);
typedef void sample4_fn(const sl_texture *t, const sl_sampler_state *st, const vec2 uv[4], float lambda, vec4 out[4]);
#define FORMAT_FUNCTIONS(F)                                                                                    \
    static vec4 bilinear_##F(const sl_texture *t, const tex_level *lv, float x, float y, sl_wrap ws, sl_wrap wt) \
    {                                                                                                          \
        return bilinear_as(SL_TEX_##F, t, lv, x, y, ws, wt);                                                   \
    }                                                                                                          \
    static vec4 sample_##F(const sl_texture *t, const sl_sampler_state *st, vec2 uv, float lambda)             \
    {                                                                                                          \
        return sample_as(SL_TEX_##F, t, t->level, st, uv, lambda);                                             \
    }                                                                                                          \
    static void sample4_##F(const sl_texture *t, const sl_sampler_state *st, const vec2 uv[4], float lambda,    \
                            vec4 out[4])                                                                       \
    {                                                                                                          \
        for (int l = 0; l < 4; l++)                                                                            \
            out[l] = sample_as(SL_TEX_##F, t, t->level, st, uv[l], lambda);                                    \
    }
FORMAT_FUNCTIONS(R8)
FORMAT_FUNCTIONS(RG8)
FORMAT_FUNCTIONS(RGB8)
FORMAT_FUNCTIONS(RGBA8)
FORMAT_FUNCTIONS(SRGB8)
FORMAT_FUNCTIONS(SRGB8_ALPHA8)
FORMAT_FUNCTIONS(R16)
FORMAT_FUNCTIONS(RG16)
FORMAT_FUNCTIONS(RGB16)
FORMAT_FUNCTIONS(RGBA16)
FORMAT_FUNCTIONS(R32F)
FORMAT_FUNCTIONS(RGB32F)
FORMAT_FUNCTIONS(RGBA32F)
#define FORMAT_ENTRY(prefix, F) [SL_TEX_##F] = prefix##F
#define FORMAT_TABLE(prefix)                                                                                    \
    {FORMAT_ENTRY(prefix, R8),    FORMAT_ENTRY(prefix, RG8),    FORMAT_ENTRY(prefix, RGB8),                     \
     FORMAT_ENTRY(prefix, RGBA8), FORMAT_ENTRY(prefix, SRGB8),  FORMAT_ENTRY(prefix, SRGB8_ALPHA8),             \
     FORMAT_ENTRY(prefix, R16),   FORMAT_ENTRY(prefix, RG16),   FORMAT_ENTRY(prefix, RGB16),                    \
     FORMAT_ENTRY(prefix, RGBA16), FORMAT_ENTRY(prefix, R32F),  FORMAT_ENTRY(prefix, RGB32F),                   \
     FORMAT_ENTRY(prefix, RGBA32F)}
static bilinear_fn *const bilinear_for[SL_TEX_FORMAT_COUNT] = FORMAT_TABLE(bilinear_);
static sample_fn *const sample_for[SL_TEX_FORMAT_COUNT] = FORMAT_TABLE(sample_);
static sample4_fn *const sample4_for[SL_TEX_FORMAT_COUNT] = FORMAT_TABLE(sample4_);

/* The decoded plane (texture_internal.h): every format's texels already decoded to RGBA32F, so
 * one instance serves them all; a texel is one 16-byte load and the filter's mixes are vec4 mixes
 * of floats the byte path would have decoded to the same bits. */
static vec4 sample_plane(const sl_texture *t, const sl_sampler_state *st, vec2 uv, float lambda)
{
    return sample_as(SL_TEX_RGBA32F, t, t->plane, st, uv, lambda);
}

/* Level lv of the decoded plane filtered bilinearly at four lanes' uv, each lane with
 * level_as's and bilinear_as's operations in their order (so their bits): the texel-space
 * coordinates of the four lanes first (an omp simd loop that GCC 12 still compiles to scalar
 * code, -fopt-info-vec: "no vectype" for the vec2 reads, also with them copied to float arrays
 * first), then each lane's four texels, 16-byte loads, mixed a channel at a time. */
static inline __attribute__((always_inline)) void bilinear4_plane(const tex_level *lv, const vec2 uv[4],
                                                                   const sl_sampler_state *st, vec4 out[4])
{
    const float *texels = (const float *)(const void *)lv->texels;
    const int w = lv->width, h = lv->height;
    float a[4], b[4];
    int i[4], j[4];
#pragma omp simd
    for (int l = 0; l < 4; l++) {
        float x = safe_coord(uv[l].x * (float)w - 0.5f), y = safe_coord(uv[l].y * (float)h - 0.5f);
        float fx = floorf(x), fy = floorf(y);
        a[l] = x - fx;
        b[l] = y - fy;
        i[l] = (int)fx;
        j[l] = (int)fy;
    }
    for (int l = 0; l < 4; l++) {
        int i0, i1, j0, j1;
        wrap_pair(i[l], w, st->wrap_s, &i0, &i1);
        wrap_pair(j[l], h, st->wrap_t, &j0, &j1);
        const float *r0 = texels + (size_t)j0 * (size_t)w * 4, *r1 = texels + (size_t)j1 * (size_t)w * 4;
        const float *p00 = r0 + (size_t)i0 * 4, *p01 = r0 + (size_t)i1 * 4;
        const float *p10 = r1 + (size_t)i0 * 4, *p11 = r1 + (size_t)i1 * 4;
        float v[4];
        for (int c = 0; c < 4; c++)
            v[c] = mixf(mixf(p00[c], p01[c], a[l]), mixf(p10[c], p11[c], a[l]), b[l]);
        out[l] = vec4(v[0], v[1], v[2], v[3]);
    }
}

/* The quad form's sample from the plane: the levels picked once for the four lanes (they share
 * lambda), each level filtered for all four at once; each lane's value is sample_plane's. */
static void sample4_plane(const sl_texture *t, const sl_sampler_state *st, const vec2 uv[4], float lambda, vec4 out[4])
{
    tex_pick p = pick_levels(t, st, lambda);
    if (!p.linear) {
        for (int l = 0; l < 4; l++)
            out[l] = sample_as(SL_TEX_RGBA32F, t, t->plane, st, uv[l], lambda);
        return;
    }
    bilinear4_plane(&t->plane[p.level], uv, st, out);
    if (p.count == 1)
        return;
    vec4 next[4];
    bilinear4_plane(&t->plane[p.level + 1], uv, st, next);
    for (int l = 0; l < 4; l++)
        out[l] = mix4(out[l], next[l], p.frac);
}

static bool is_mipmap_filter(sl_filter f) { return f >= SL_NEAREST_MIPMAP_NEAREST; }

/* GL's completeness: a mipmap min filter on a texture without its chain samples (0, 0, 0, 1). */
static bool complete(const sl_texture *t, const sl_sampler_state *st)
{
    return t && (t->mipmapped || !is_mipmap_filter(st->min_filter));
}

/* ---- the multi-quad form: n quads' lanes in structure-of-arrays form ----
 * The same values as sample4_plane's, lane for lane, from vector loops over up to 64 lanes:
 * the levels picked per quad (pick_levels), then each lane's texel-space coordinates, its wrapped
 * indices and its eight texels (16-byte loads from the plane, where every level lies in one
 * allocation) and the mixes in sample_as's order (with AVX two lanes' four channels a vector,
 * a quad at a time: bilinear_pair). Only the plane and linear filtering: a quad
 * magnified or minified with a NEAREST filter, and textures without a plane, go through
 * sl_texture_sample4 (the same bits, four lanes at a time). */

/* Wrapped index pairs of n lanes (wrap_pair's results): the vector forms where there is one
 * (CLAMP_TO_EDGE clamps both; REPEAT of a power of two masks), else wrap_pair per lane. */
static inline __attribute__((always_inline)) void wrap_pairs(int lanes, const int *i, const int *size, sl_wrap mode,
                                                             bool pow2, int *i0, int *i1)
{
    if (mode == SL_CLAMP_TO_EDGE) {
#pragma omp simd
        for (int j = 0; j < lanes; j++) {
            int last = size[j] - 1, a = i[j], b = i[j] + 1;
            i0[j] = a < 0 ? 0 : (a > last ? last : a);
            i1[j] = b < 0 ? 0 : (b > last ? last : b);
        }
    } else if (mode == SL_REPEAT && pow2) {
#pragma omp simd
        for (int j = 0; j < lanes; j++) {
            int mask = size[j] - 1, a = i[j] & mask;
            i0[j] = a;
            i1[j] = (a + 1) & mask;
        }
    } else {
        for (int j = 0; j < lanes; j++)
            wrap_pair(i[j], size[j], mode, &i0[j], &i1[j]);
    }
}

static bool is_pow2(int n) { return (n & (n - 1)) == 0; }

/* Where bilinear filtering of level lv[j] at (u[j], v[j]) reads, for each lane: the offsets (in
 * floats, from the plane's start: its levels lie in one allocation) of its four texels, o[0..3]
 * = (i0, j0), (i1, j0), (i0, j1), (i1, j1), and the weights a, b; bilinear4_plane's operations,
 * lane for lane, in vector loops. */
static void bilinear_offsets(const sl_texture *t, const sl_sampler_state *st, int lanes, const float *u,
                             const float *v, const int *lv, int (*o)[SL_QUAD_LANES], float *a, float *b)
{
    const float *plane = t->plane_storage;
    int base[SL_TEXTURE_MAX_LEVELS], wl[SL_TEXTURE_MAX_LEVELS], hl[SL_TEXTURE_MAX_LEVELS];
    for (int l = 0; l < t->levels; l++) {
        base[l] = (int)((const float *)(const void *)t->plane[l].texels - plane);
        wl[l] = t->plane[l].width;
        hl[l] = t->plane[l].height;
    }
    _Alignas(64) int w[SL_QUAD_LANES], h[SL_QUAD_LANES], bs[SL_QUAD_LANES], i[SL_QUAD_LANES], jj[SL_QUAD_LANES];
    _Alignas(64) int i0[SL_QUAD_LANES], i1[SL_QUAD_LANES], j0[SL_QUAD_LANES], j1[SL_QUAD_LANES];
    for (int j = 0; j < lanes; j++) {
        w[j] = wl[lv[j]];
        h[j] = hl[lv[j]];
        bs[j] = base[lv[j]];
    }
#pragma omp simd
    for (int j = 0; j < lanes; j++) {
        float x = safe_coord(u[j] * (float)w[j] - 0.5f), y = safe_coord(v[j] * (float)h[j] - 0.5f);
        /* floorf by truncation (GCC 12 does not vectorize floorf under -ftrapping-math): exact
         * for safe_coord's range, and x is never -0 (u w - 0.5 rounds an exact 0 to +0) */
        float tx = (float)(int)x, ty = (float)(int)y;
        float fx = tx > x ? tx - 1.0f : tx, fy = ty > y ? ty - 1.0f : ty;
        a[j] = x - fx;
        b[j] = y - fy;
        i[j] = (int)fx;
        jj[j] = (int)fy;
    }
    wrap_pairs(lanes, i, w, st->wrap_s, is_pow2(t->level[0].width), i0, i1);
    wrap_pairs(lanes, jj, h, st->wrap_t, is_pow2(t->level[0].height), j0, j1);
#pragma omp simd
    for (int j = 0; j < lanes; j++) {
        int row0 = bs[j] + j0[j] * w[j] * 4, row1 = bs[j] + j1[j] * w[j] * 4;
        o[0][j] = row0 + i0[j] * 4;
        o[1][j] = row0 + i1[j] * 4;
        o[2][j] = row1 + i0[j] * 4;
        o[3][j] = row1 + i1[j] * 4;
    }
}

#if defined(__AVX__)
/* Lanes j and j + 1's bilinear values from their four texels each (16-byte loads), lane j's
 * channels in the low half: bilinear4_plane's mixes, operation for operation (a + (b - a) t, no
 * contraction under -std=c11), so the same bits. */
static inline __attribute__((always_inline)) __m256 bilinear_pair(const float *plane, int j,
                                                                  const int (*o)[SL_QUAD_LANES], const float *a,
                                                                  const float *b)
{
    __m256 p00 = _mm256_loadu2_m128(plane + o[0][j + 1], plane + o[0][j]);
    __m256 p01 = _mm256_loadu2_m128(plane + o[1][j + 1], plane + o[1][j]);
    __m256 p10 = _mm256_loadu2_m128(plane + o[2][j + 1], plane + o[2][j]);
    __m256 p11 = _mm256_loadu2_m128(plane + o[3][j + 1], plane + o[3][j]);
    __m256 wa = _mm256_set_m128(_mm_set1_ps(a[j + 1]), _mm_set1_ps(a[j]));
    __m256 wb = _mm256_set_m128(_mm_set1_ps(b[j + 1]), _mm_set1_ps(b[j]));
    __m256 top = _mm256_add_ps(p00, _mm256_mul_ps(_mm256_sub_ps(p01, p00), wa));
    __m256 bot = _mm256_add_ps(p10, _mm256_mul_ps(_mm256_sub_ps(p11, p10), wa));
    return _mm256_add_ps(top, _mm256_mul_ps(_mm256_sub_ps(bot, top), wb));
}

/* mixf(c0, c1, frac) for lanes j and j + 1. */
static inline __attribute__((always_inline)) __m256 mix_pair(__m256 c0, __m256 c1, const float *frac, int j)
{
    __m256 t = _mm256_set_m128(_mm_set1_ps(frac[j + 1]), _mm_set1_ps(frac[j]));
    return _mm256_add_ps(c0, _mm256_mul_ps(_mm256_sub_ps(c1, c0), t));
}
#else
/* One lane's bilinear value from its four texels (16-byte loads; the channels mixed together):
 * bilinear4_plane's mixes. */
static inline __attribute__((always_inline)) void bilinear_texels(const float *plane, int j, const int (*o)[SL_QUAD_LANES],
                                                                   float a, float b, float out[4])
{
    const float *p00 = plane + o[0][j], *p01 = plane + o[1][j], *p10 = plane + o[2][j], *p11 = plane + o[3][j];
    for (int c = 0; c < 4; c++)
        out[c] = mixf(mixf(p00[c], p01[c], a), mixf(p10[c], p11[c], a), b);
}
#endif

void sl_texture_plan_quads(const sl_sampler2D *s, int n, const float *u, const float *v, const float *lambda,
                           sl_texture_quads_plan *plan)
{
    const sl_texture *t = s->texture;
    const sl_sampler_state *st = &s->state;
    const int lanes = 4 * n;
    plan->n = n;
    plan->u = u;
    plan->v = v;
    plan->lambda = lambda;
    plan->complete = complete(t, st);
    plan->any_fast = plan->any_two = false;
    if (!plan->complete)
        return;
    /* the levels of each quad; quads the vector path does not take are sampled four lanes at a
     * time (slow) */
    _Alignas(64) int lv0[SL_QUAD_LANES], lv[SL_QUAD_LANES];
    for (int q = 0; q < n; q++) {
        tex_pick p = pick_levels(t, st, lambda[q]);
        bool slow = !t->plane_storage || !p.linear;
        plan->slow[q] = slow;
        plan->any_fast |= !slow;
        plan->any_two |= !slow && p.count == 2;
        for (int l = 0; l < 4; l++) {
            lv0[4 * q + l] = slow ? 0 : p.level;
            plan->lv1[4 * q + l] = slow || p.count == 1 ? -1 : p.level + 1;
            plan->frac[4 * q + l] = p.frac;
        }
    }
    if (!plan->any_fast)
        return;
    /* the texel offsets and weights in vector loops */
    bilinear_offsets(t, st, lanes, u, v, lv0, plan->o0, plan->a0, plan->b0);
    if (plan->any_two) {
        for (int j = 0; j < lanes; j++)
            lv[j] = plan->lv1[j] < 0 ? lv0[j] : plan->lv1[j];
        bilinear_offsets(t, st, lanes, u, v, lv, plan->o1, plan->a1, plan->b1);
    }
}

void sl_texture_fetch_quads(const sl_sampler2D *s, const sl_texture_quads_plan *plan, float *const rgba[4])
{
    const int n = plan->n, lanes = 4 * n;
    if (!plan->complete) {
        for (int j = 0; j < lanes; j++) {
            rgba[0][j] = rgba[1][j] = rgba[2][j] = 0.0f;
            rgba[3][j] = 1.0f;
        }
        return;
    }
    if (plan->any_fast) {
        /* a texel a 16-byte load (gathers, a float each, were slower: four times the loads) */
        const float *plane = s->texture->plane_storage;
        float *r = rgba[0], *g = rgba[1], *bl = rgba[2], *al = rgba[3];
#if defined(__AVX__)
        /* a quad at a time: two lanes' texels to a 256-bit vector, the mixes for two lanes' four
         * channels at once, the four lanes' values transposed into the channel arrays */
        for (int q = 0; q < n; q++) {
            if (plan->slow[q])
                continue;
            const int j = 4 * q;
            __m256 v01 = bilinear_pair(plane, j, plan->o0, plan->a0, plan->b0);
            __m256 v23 = bilinear_pair(plane, j + 2, plan->o0, plan->a0, plan->b0);
            if (plan->lv1[j] >= 0) { /* the quad's levels are one pick: all its lanes have two or one */
                __m256 w01 = bilinear_pair(plane, j, plan->o1, plan->a1, plan->b1);
                __m256 w23 = bilinear_pair(plane, j + 2, plan->o1, plan->a1, plan->b1);
                v01 = mix_pair(v01, w01, plan->frac, j);
                v23 = mix_pair(v23, w23, plan->frac, j + 2);
            }
            __m128 l0 = _mm256_castps256_ps128(v01), l1 = _mm256_extractf128_ps(v01, 1);
            __m128 l2 = _mm256_castps256_ps128(v23), l3 = _mm256_extractf128_ps(v23, 1);
            _MM_TRANSPOSE4_PS(l0, l1, l2, l3);
            _mm_storeu_ps(r + j, l0);
            _mm_storeu_ps(g + j, l1);
            _mm_storeu_ps(bl + j, l2);
            _mm_storeu_ps(al + j, l3);
        }
#else
        for (int j = 0; j < lanes; j++) {
            float c0[4], c1[4];
            bilinear_texels(plane, j, plan->o0, plan->a0[j], plan->b0[j], c0);
            if (plan->lv1[j] >= 0) {
                bilinear_texels(plane, j, plan->o1, plan->a1[j], plan->b1[j], c1);
                for (int c = 0; c < 4; c++)
                    c0[c] = mixf(c0[c], c1[c], plan->frac[j]);
            }
            r[j] = c0[0];
            g[j] = c0[1];
            bl[j] = c0[2];
            al[j] = c0[3];
        }
#endif
    }
    for (int q = 0; q < n; q++) {
        if (!plan->slow[q])
            continue;
        vec2 uv[4];
        vec4 out[4];
        for (int l = 0; l < 4; l++)
            uv[l] = vec2(plan->u[4 * q + l], plan->v[4 * q + l]);
        sl_texture_sample4(s, uv, plan->lambda[q], out);
        for (int l = 0; l < 4; l++) {
            rgba[0][4 * q + l] = out[l].x;
            rgba[1][4 * q + l] = out[l].y;
            rgba[2][4 * q + l] = out[l].z;
            rgba[3][4 * q + l] = out[l].w;
        }
    }
}

void sl_texture_sample_quads(const sl_sampler2D *s, int n, const float *u, const float *v, const float *lambda,
                             float *const rgba[4])
{
    sl_texture_quads_plan plan;
    sl_texture_plan_quads(s, n, u, v, lambda, &plan);
    sl_texture_fetch_quads(s, &plan, rgba);
}

/* Floats compared bitwise: 0 and -0, or two NaNs, are not assumed to act alike. */
static bool same_float(float a, float b) { return !memcmp(&a, &b, sizeof a); }

bool sl_texture_same_plan(const sl_sampler2D *a, const sl_sampler2D *b)
{
    const sl_texture *ta = a->texture, *tb = b->texture;
    const sl_sampler_state *sa = &a->state, *sb = &b->state;
    if (!ta || !tb || sa->min_filter != sb->min_filter || sa->mag_filter != sb->mag_filter ||
        sa->wrap_s != sb->wrap_s || sa->wrap_t != sb->wrap_t || !same_float(sa->lod_bias, sb->lod_bias) ||
        !same_float(sa->min_lod, sb->min_lod) || !same_float(sa->max_lod, sb->max_lod))
        return false;
    if (complete(ta, sa) != complete(tb, sb) || ta->levels != tb->levels || !ta->plane_storage != !tb->plane_storage)
        return false;
    for (int l = 0; l < ta->levels; l++) {
        if (ta->level[l].width != tb->level[l].width || ta->level[l].height != tb->level[l].height)
            return false;
        if (ta->plane_storage && (const float *)(const void *)ta->plane[l].texels - ta->plane_storage !=
                                     (const float *)(const void *)tb->plane[l].texels - tb->plane_storage)
            return false;
    }
    return true;
}

vec4 sl_tex_bilinear(const sl_texture *t, const tex_level *lv, float x, float y, sl_wrap wrap_s, sl_wrap wrap_t)
{
    return bilinear_for[t->format](t, lv, x, y, wrap_s, wrap_t);
}

vec4 sl_texture_sample(const sl_sampler2D *s, vec2 uv, float lambda)
{
    const sl_texture *t = s->texture;
    if (!complete(t, &s->state))
        return vec4(0, 0, 0, 1);
    return t->plane_storage ? sample_plane(t, &s->state, uv, lambda) : sample_for[t->format](t, &s->state, uv, lambda);
}

void sl_texture_sample4(const sl_sampler2D *s, const vec2 uv[4], float lambda, vec4 out[4])
{
    const sl_texture *t = s->texture;
    if (!complete(t, &s->state)) {
        for (int l = 0; l < 4; l++)
            out[l] = vec4(0, 0, 0, 1);
        return;
    }
    if (t->plane_storage)
        sample4_plane(t, &s->state, uv, lambda, out);
    else
        sample4_for[t->format](t, &s->state, uv, lambda, out);
}

/* llvmpipe's lp_build_fast_log2: for x = m 2^e (m in [1, 2)), e + (m - 1): exact at powers of
 * two, piecewise linear between (at most 0.086 below log2). Zero gives -127 (magnified),
 * +infinity 128. */
static inline __attribute__((always_inline)) float log2_fast_bits(uint32_t bits)
{
    int e = (int)((bits >> 23) & 0xffu) - 127;
    bits = (bits & 0x007fffffu) | 0x3f800000u;
    float m;
    memcpy(&m, &bits, sizeof m);
    return (float)(e - 1) + m;
}
static inline __attribute__((always_inline)) float log2_fast(float x)
{
    uint32_t bits;
    memcpy(&bits, &x, sizeof bits);
    return log2_fast_bits(bits);
}

/* lambda clamped as llvmpipe clamps it: to max_lod first, then to min_lod. */
static float clamp_lambda(float lambda, const sl_sampler_state *st)
{
    lambda = lambda < st->max_lod ? lambda : st->max_lod;
    return lambda > st->min_lod ? lambda : st->min_lod;
}

/* lambda from derivatives (texture.h): rho^2 the larger squared length in texels of level 0,
 * 0.5 log2_fast(rho^2), the biases, the clamps. A non-finite rho^2 (an infinite or NaN
 * derivative) gives what llvmpipe gives: with explicit derivatives it counts as 0 (lp_build_rho
 * zeroes it: magnified), with a quad's implicit ones it is not checked and log2_fast of it is
 * 128 or more (the last level; measured: a NaN or an infinite uv in lane 0 makes the other lanes
 * read the 1x1 level). */
static float lambda_from(const sl_sampler2D *s, vec2 dPdx, vec2 dPdy, float bias, bool explicit_derivatives)
{
    const sl_texture *t = s->texture;
    if (!t)
        return 0.0f;
    float w = (float)t->level[0].width, h = (float)t->level[0].height;
    float sx = dPdx.x * w, tx = dPdx.y * h, sy = dPdy.x * w, ty = dPdy.y * h;
    float rx = sx * sx + tx * tx, ry = sy * sy + ty * ty;
    float rho2 = rx > ry ? rx : ry;
    if (!isfinite(rho2))
        rho2 = explicit_derivatives ? 0.0f : INFINITY;
    float lambda = 0.5f * log2_fast(rho2) + bias;
    return clamp_lambda(lambda + s->state.lod_bias, &s->state);
}

/* lambda_from's implicit form for n quads at once: the coarse differences of each quad's lanes
 * (glsl.h's sl_quad_dfdx_coarse / sl_quad_dfdy_coarse), then lambda_from's operations in its
 * order, with a select for its non-finite branch, in one vector loop over the quads. */
void sl_texture_lambda_quads(const sl_sampler2D *s, int n, const float *u, const float *v, float bias, float *lambda)
{
    const sl_texture *t = s->texture;
    if (!t) {
        for (int q = 0; q < n; q++)
            lambda[q] = 0.0f;
        return;
    }
    const float w = (float)t->level[0].width, h = (float)t->level[0].height;
    const float lod_bias = s->state.lod_bias, min_lod = s->state.min_lod, max_lod = s->state.max_lod;
#pragma omp simd
    for (int q = 0; q < n; q++) {
        const float *uq = u + 4 * q, *vq = v + 4 * q;
        float sx = (uq[1] - uq[0]) * w, tx = (vq[1] - vq[0]) * h;
        float sy = (uq[2] - uq[0]) * w, ty = (vq[2] - vq[0]) * h;
        float rx = sx * sx + tx * tx, ry = sy * sy + ty * ty;
        float rho2 = rx > ry ? rx : ry;
        uint32_t bits;
        memcpy(&bits, &rho2, sizeof bits);
        /* !isfinite: +inf, the last level (as a mask: GCC 12 does not if-convert this select) */
        uint32_t nonfinite = (uint32_t) - (int32_t)((bits & 0x7f800000u) == 0x7f800000u);
        bits = (bits & ~nonfinite) | (0x7f800000u & nonfinite);
        float l = 0.5f * log2_fast_bits(bits) + bias + lod_bias;
        l = l < max_lod ? l : max_lod;
        lambda[q] = l > min_lod ? l : min_lod;
    }
}

float sl_texture_lambda(const sl_sampler2D *s, vec2 dPdx, vec2 dPdy, float bias)
{
    return lambda_from(s, dPdx, dPdy, bias, true);
}

float sl_texture_lambda_quad(const sl_sampler2D *s, vec2 dPdx, vec2 dPdy, float bias)
{
    return lambda_from(s, dPdx, dPdy, bias, false);
}

vec4 sl_texture_grad(const sl_sampler2D *s, vec2 uv, vec2 dPdx, vec2 dPdy)
{
    return sl_texture_sample(s, uv, sl_texture_lambda(s, dPdx, dPdy, 0.0f));
}

vec4 sl_texture_lod(const sl_sampler2D *s, vec2 uv, float lod)
{
    return sl_texture_sample(s, uv, clamp_lambda(lod + s->state.lod_bias, &s->state));
}

vec4 sl_texel_fetch(const sl_sampler2D *s, ivec2 p, int lod)
{
    const sl_texture *t = s->texture;
    if (!complete(t, &s->state))
        return vec4(0, 0, 0, 1);
    if (lod < 0 || lod >= t->levels)
        return vec4(0, 0, 0, 0);
    const tex_level *lv = &t->level[lod];
    if (p.x < 0 || p.y < 0 || p.x >= lv->width || p.y >= lv->height)
        return vec4(0, 0, 0, 0);
    return tex_texel(t, lv, p.x, p.y);
}

ivec2 sl_texture_size(const sl_sampler2D *s, int lod)
{
    const sl_texture *t = s->texture;
    if (!t || lod < 0 || lod >= t->levels)
        return ivec2(0, 0);
    return ivec2(t->level[lod].width, t->level[lod].height);
}
