/* env.c - the environment's mip chain, built once per environment and read by textureLod.
 *
 * Sizes follow glGenerateMipmap: level k+1 is max(1, floor(size_k / 2)) on each axis, down
 * to 1x1 (1024x512 has 11 levels, 5x3 has 5x3, 2x1, 1x1).
 *
 * Filter: each texel of level k+1 is the EXACT AREA AVERAGE of the level-k texels its
 * footprint covers, the footprint being the same fraction of the image (an n-texel axis
 * shrinking to m texels gives each new texel n/m old ones). For even sizes that is GL's 2x2
 * box average. For odd sizes (n = 2m + 1) it is a 3- or 4-tap filter with rational weights;
 * e.g. 5 -> 2 is (1, 1, 1/2) / 2.5 and (1/2, 1, 1) / 2.5, and 3 -> 1 is (1, 1, 1) / 3. Every
 * input texel hands out total weight exactly 1, so each level has the mean of the one before
 * it and the 1x1 level is the mean of the image (texel-area mean, not solid-angle mean: the
 * mip chain is a texture, as in GL). The filter is separable (area of a rectangle overlap is
 * the product of the two 1-D overlaps) and accumulates in double.
 *
 * Layout: one contiguous array of vec3 per level, row 0 = top, as in sl_env_level, and all
 * levels in one allocation (sl_env.block), level after level.
 *
 * Memory: on a virtual machine the first touch of a fresh 4 KiB page costs about 10 us, so
 * filling a new 1024x512 chain's 8 MiB in such pages takes about 22 ms of page faults, while the
 * filter itself takes 2-3 ms, and every temporary copy of the image adds as many faults again.
 * So the block is asked for in 2 MiB transparent huge pages where the kernel offers them on
 * request (Linux, madvise mode; a no-op elsewhere), level 0 is converted straight into it (no
 * temporary), and the even path needs no scratch.
 *
 * Two implementations of that one filter, chosen per level, giving the same bits:
 * - downsample(): the general separable filter above, any sizes (used whenever an axis is odd
 *   or stays at 1: 5x3 -> 2x1, 2x1 -> 1x1). One thread; scratch of one pass's rows.
 * - downsample_even(): both axes even (w = 2 mw, h = 2 mh), which is every level but the last
 *   of a power-of-two map and the bulk of the time (1024x512 -> 512x256 alone is 3/4 of the
 *   work). make_taps gives each output exactly two taps of weight m / (2m) = 0.5 there, so
 *   this path performs the general path's double operations, in its order, for that case:
 *   per row and channel h = (0.0 + 0.5 a) + 0.5 b, then out = (float)((0.0 + 0.5 h0) + 0.5 h1)
 *   (the general path's accumulator starts at 0.0; adding it is kept, as it turns a -0.0
 *   input into +0.0). It fuses the two passes per output texel (no scratch), runs rows in
 *   a loop the compiler vectorizes (GCC 12 -O2: the channel block, 64-byte vectors; forcing
 *   the x loop with omp simd measured no faster: the level is memory-bound), and splits rows
 *   over OpenMP threads on levels large enough to pay for it (EVEN_PARALLEL_MIN; no level of
 *   a 1024x512 map). Every output texel is computed by the same operations whatever the
 *   thread count, so the chain does not depend on it. tests/unit/test_ibl.c compares the two
 *   paths bit for bit on even, odd and mixed sizes. */
/* madvise and MADV_HUGEPAGE are not POSIX (the build asks for POSIX 2008 only) */
#define _DEFAULT_SOURCE
#include "../core/threads.h"
#include "ibl_internal.h"
#include "texel_e5.h"

#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

/* One output texel's taps along one axis: at most 4 (a footprint of n/m <= 3 input texels
 * starting at a fractional position touches at most 4). */
typedef struct {
    int first, count;
    double w[4];
} axis_taps;

/* Footprint of output i in units of 1/m input texel: [i n, (i + 1) n); input k covers
 * [k m, (k + 1) m). The weight of k is the overlap over n, so each output's weights sum to 1. */
static void make_taps(int n, int m, axis_taps *taps)
{
    for (int i = 0; i < m; i++) {
        long long lo = (long long)i * n, hi = (long long)(i + 1) * n;
        int k0 = (int)(lo / m), k1 = (int)((hi - 1) / m);
        taps[i].first = k0;
        taps[i].count = k1 - k0 + 1;
        for (int k = k0; k <= k1; k++) {
            long long a = (long long)k * m, b = (long long)(k + 1) * m;
            long long overlap = (b < hi ? b : hi) - (a > lo ? a : lo);
            taps[i].w[k - k0] = (double)overlap / (double)n;
        }
    }
}

/* src (w x h) -> dst (mw x mh). `rows` is scratch of mw * h * 3 doubles. */
static void downsample(const sl_env_level *src, sl_env_level *dst, const axis_taps *tx, const axis_taps *ty,
                       double *rows)
{
    int w = src->width, h = src->height, mw = dst->width, mh = dst->height;
    for (int y = 0; y < h; y++) {
        const vec3 *in = src->texels + (size_t)y * (size_t)w;
        double *out = rows + (size_t)y * (size_t)mw * 3;
        for (int x = 0; x < mw; x++) {
            double r = 0, g = 0, b = 0;
            for (int t = 0; t < tx[x].count; t++) {
                vec3 v = in[tx[x].first + t];
                double wt = tx[x].w[t];
                r += wt * (double)v.x;
                g += wt * (double)v.y;
                b += wt * (double)v.z;
            }
            out[3 * x] = r;
            out[3 * x + 1] = g;
            out[3 * x + 2] = b;
        }
    }
    for (int y = 0; y < mh; y++) {
        vec3 *out = dst->texels + (size_t)y * (size_t)mw;
        for (int x = 0; x < mw; x++) {
            double r = 0, g = 0, b = 0;
            for (int t = 0; t < ty[y].count; t++) {
                const double *v = rows + ((size_t)(ty[y].first + t) * (size_t)mw + (size_t)x) * 3;
                double wt = ty[y].w[t];
                r += wt * v[0];
                g += wt * v[1];
                b += wt * v[2];
            }
            out[x] = vec3(r, g, b);
        }
    }
}

/* Output texels below which a level is filtered by one thread. Measured on the shared 2-core
 * machine (docs/ibl.md "Pole-free irradiance maps", the made-ready figures): a 1024x512 map's largest level (512x256, 0.8 ms on one
 * thread) gained at best 0.5 ms from a second thread and, whenever the other core was busy,
 * lost up to 25 ms waiting for it, so only levels four times larger (from a 2048x1024 map's
 * first level, about 3 ms of work) are split. The viewer renders on the other core during a
 * drag and drop anyway. -DEVEN_PARALLEL_MIN=0 forces threads on every level (for measuring). */
#ifndef EVEN_PARALLEL_MIN
#define EVEN_PARALLEL_MIN (1024 * 512)
#endif

/* src (2 mw x 2 mh) -> dst (mw x mh): downsample() for two taps of weight 0.5 on each axis,
 * with the same double operations in the same order (see the top of the file). */
static void downsample_even(const sl_env_level *src, sl_env_level *dst, int threads)
{
    /* The rows are read and written as flat floats, r g b r g b ..., for the vectorizer. */
    _Static_assert(sizeof(vec3) == 3 * sizeof(float), "vec3 is three packed floats");
    int mw = dst->width, mh = dst->height;
    size_t w = (size_t)src->width;
    const float *base = (const float *)src->texels;
    float *obase = (float *)dst->texels;
#pragma omp parallel for schedule(static) num_threads(sl_threads(threads)) if (mw * mh >= EVEN_PARALLEL_MIN)
    for (int y = 0; y < mh; y++) {
        const float *r0 = base + (size_t)(2 * y) * w * 3, *r1 = r0 + w * 3;
        float *out = obase + (size_t)y * (size_t)mw * 3;
        for (int x = 0; x < mw; x++) {
            for (int c = 0; c < 3; c++) {
                /* horizontal pass, rows 2y and 2y + 1: downsample()'s first loop */
                double h0 = 0.0;
                h0 += 0.5 * (double)r0[6 * x + c];
                h0 += 0.5 * (double)r0[6 * x + 3 + c];
                double h1 = 0.0;
                h1 += 0.5 * (double)r1[6 * x + c];
                h1 += 0.5 * (double)r1[6 * x + 3 + c];
                /* vertical pass: downsample()'s second loop, taps in row order */
                double v = 0.0;
                v += 0.5 * h0;
                v += 0.5 * h1;
                out[3 * x + c] = (float)v;
            }
        }
    }
}

/* The block for `bytes`, in transparent huge pages when it is big enough for them to matter
 * (see the top of the file). free() releases it either way. */
static void *alloc_block(size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const size_t huge = (size_t)2 << 20;
    if (bytes >= 2 * huge) {
        void *p = NULL;
        if (posix_memalign(&p, huge, bytes) != 0)
            return NULL;
        /* advice only: 4 KiB pages if refused; the tail past the last whole 2 MiB stays small */
        (void)madvise(p, bytes, MADV_HUGEPAGE);
        return p;
    }
#endif
    return malloc(bytes);
}

/* sl_env.pairs (ibl.h): every level's rows with their first texel repeated at the end, or NULL
 * (too large, or no memory: the fetch then reads the block; nothing is lost but speed). */
float *sl_ibl_env_build_pairs(const sl_env *env, size_t texels)
{
    size_t rows = 0;
    for (int l = 0; l < env->level_count; l++)
        rows += (size_t)env->levels[l].height;
    if (texels > SL_ENV_PAIRS_MAX_TEXELS)
        return NULL;
    float *pairs = malloc((texels + rows) * 3 * sizeof *pairs);
    if (!pairs)
        return NULL;
    float *out = pairs;
    for (int l = 0; l < env->level_count; l++) {
        const sl_env_level *lv = &env->levels[l];
        for (int y = 0; y < lv->height; y++) {
            const vec3 *row = lv->texels + (size_t)y * (size_t)lv->width;
            for (int x = 0; x <= lv->width; x++) {
                vec3 t = row[x < lv->width ? x : 0];
                *out++ = t.x;
                *out++ = t.y;
                *out++ = t.z;
            }
        }
    }
    return pairs;
}

/* Levels of at least this many texels encode their compact rows on all threads (0.25 ms of
 * work a thread at 4 ns a texel). */
#define E5_PARALLEL_MIN ((size_t)256 * 256)

/* sl_env.e5 (ibl.h): the chain in the compact texel (texel_e5.h) at one row stride, level l's
 * row y at row sl_e5_row(H, l) + y, and the chain's exponent offset in *emin; NULL when the
 * chain is too large or has sizes other than sl_env_build's, or no memory. Level 0 holds the
 * chain's brightest channel: every later level is an average of it. */
uint32_t *sl_ibl_env_build_e5(const sl_env *env, size_t texels, int *emin, int threads)
{
    if (texels > SL_ENV_PAIRS_MAX_TEXELS || env->level_count < 1)
        return NULL;
    const int W = env->levels[0].width, H = env->levels[0].height, L = env->level_count;
    for (int l = 0; l < L; l++) /* the sizes the fetch computes by shifts */
        if (env->levels[l].width != sl_e5_size(W, l) || env->levels[l].height != sl_e5_size(H, l))
            return NULL;
    const size_t stride = (size_t)W + 1, rows = (size_t)sl_e5_row(H, L);
    if (stride * rows > (size_t)INT32_MAX / 2) /* int indices in the fetch */
        return NULL;
    uint32_t *e5 = calloc(stride * rows, sizeof *e5);
    if (!e5)
        return NULL;
    const sl_env_level *l0 = &env->levels[0];
    float max_value = 0.0f;
    for (size_t k = 0, n = (size_t)l0->width * (size_t)l0->height; k < n; k++)
        max_value = maxf(max_value, maxf(maxf(l0->texels[k].x, l0->texels[k].y), l0->texels[k].z));
    *emin = sl_e5_emin(max_value);
    const int e = *emin;
    for (int l = 0; l < L; l++) {
        const sl_env_level *lv = &env->levels[l];
        /* rows in parallel (each texel on its own: the same bits on any thread count) on levels
         * of E5_PARALLEL_MIN texels or more: the encode (texel_e5.c, in double, about 4 ns a
         * texel) is most of the build; the split sum's two 1024x512 chains take 3 ms less of
         * sl_env_prefilter on 2 threads (docs/performance.md "Compact texels for the split
         * sum's chains") */
#pragma omp parallel for schedule(static) num_threads(sl_threads(threads)) if ((size_t)lv->width * (size_t)lv->height >= E5_PARALLEL_MIN)
        for (int y = 0; y < lv->height; y++) {
            const vec3 *row = lv->texels + (size_t)y * (size_t)lv->width;
            uint32_t *out = e5 + (size_t)(sl_e5_row(H, l) + y) * stride;
            for (int x = 0; x <= lv->width; x++) {
                vec3 t = row[x < lv->width ? x : 0];
                out[x] = sl_e5_encode(t.x, t.y, t.z, e);
            }
        }
    }
    return e5;
}

/* The whole chain; general_only forces downsample() on every level (the test's reference). */
bool sl_ibl_env_build_path(sl_env *env, const sl_image *img, bool general_only, int threads, sl_error *err)
{
    *env = (sl_env){0};
    if (!sl_ibl_check_image(img, "environment", err))
        return false;

    /* The chain's sizes first, so every level goes into one block (ibl.h, sl_env.block). */
    int sizes[SL_ENV_MAX_LEVELS][2], count = 0;
    size_t total = 0;
    for (int w = img->width, h = img->height;; w = w / 2 > 1 ? w / 2 : 1, h = h / 2 > 1 ? h / 2 : 1) {
        sizes[count][0] = w;
        sizes[count][1] = h;
        total += (size_t)w * (size_t)h;
        count++;
        if (w == 1 && h == 1)
            break;
    }
    int w = img->width, h = img->height;
    vec3 *block = alloc_block(total * sizeof *block);
    axis_taps *tx = malloc((size_t)w * sizeof *tx);
    axis_taps *ty = malloc((size_t)h * sizeof *ty);
    /* downsample()'s scratch (mw x h doubles x 3), allocated by the first level that takes the
     * general path: later levels are smaller, so it serves them too. */
    double *rows = NULL;
    bool ok = block && tx && ty;
    if (ok) {
        vec3 *next = block;
        for (int l = 0; l < count; l++) {
            env->levels[l] = (sl_env_level){.width = sizes[l][0], .height = sizes[l][1], .texels = next};
            next += (size_t)sizes[l][0] * (size_t)sizes[l][1];
        }
        /* Level 0 is the image as vec3, what sl_ibl_env_single_level makes, written in place
         * rather than copied twice. */
        for (size_t k = 0, n = (size_t)w * (size_t)h; k < n; k++)
            block[k] = vec3(img->data[3 * k], img->data[3 * k + 1], img->data[3 * k + 2]);
        for (int l = 1; l < count && ok; l++) {
            const sl_env_level *src = &env->levels[l - 1];
            sl_env_level *dst = &env->levels[l];
            if (!general_only && src->width == 2 * dst->width && src->height == 2 * dst->height) {
                downsample_even(src, dst, threads);
                continue;
            }
            if (!rows)
                rows = malloc((size_t)dst->width * (size_t)src->height * 3 * sizeof(double));
            if (!rows) {
                ok = false;
                break;
            }
            make_taps(src->width, dst->width, tx);
            make_taps(src->height, dst->height, ty);
            downsample(src, dst, tx, ty, rows);
        }
    }
    free(rows);
    free(tx);
    free(ty);
    if (!ok) {
        free(block);
        *env = (sl_env){0};
        return sl_fail(err, SL_ERR_MEMORY, "environment %dx%d: out of memory for the mip chain", img->width,
                       img->height);
    }
    env->level_count = count;
    env->block = block;
    env->pairs = sl_ibl_env_build_pairs(env, total);
    env->e5 = sl_ibl_env_build_e5(env, total, &env->e5_emin, threads);
    return true;
}

bool sl_env_build(sl_env *env, const sl_image *img, int threads, sl_error *err)
{
    return sl_ibl_env_build_path(env, img, false, threads, err);
}

void sl_env_free(sl_env *env)
{
    if (!env)
        return;
    free(env->pairs);
    free(env->e5);
    if (env->block)
        free(env->block);
    else
        for (int i = 0; i < env->level_count && i < SL_ENV_MAX_LEVELS; i++)
            free(env->levels[i].texels);
    memset(env, 0, sizeof *env);
}
