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
 * levels in one allocation (sl_env.block), level after level. */
#include "ibl_internal.h"

#include <stdlib.h>
#include <string.h>

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

bool sl_env_build(sl_env *env, const sl_image *img, sl_error *err)
{
    *env = (sl_env){0};
    if (!ibl_check_image(img, "environment", err))
        return false;
    sl_env single;
    if (!ibl_env_single_level(&single, img, err))
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
    vec3 *block = malloc(total * sizeof *block);
    double *rows = malloc((size_t)(w / 2 > 1 ? w / 2 : 1) * (size_t)h * 3 * sizeof(double));
    axis_taps *tx = malloc((size_t)w * sizeof *tx);
    axis_taps *ty = malloc((size_t)h * sizeof *ty);
    bool ok = block && rows && tx && ty;
    if (ok) {
        vec3 *next = block;
        for (int l = 0; l < count; l++) {
            env->levels[l] = (sl_env_level){.width = sizes[l][0], .height = sizes[l][1], .texels = next};
            next += (size_t)sizes[l][0] * (size_t)sizes[l][1];
        }
        memcpy(block, single.levels[0].texels, (size_t)w * (size_t)h * sizeof *block);
        env->level_count = count;
        env->block = block;
        for (int l = 1; l < count; l++) {
            make_taps(env->levels[l - 1].width, env->levels[l].width, tx);
            make_taps(env->levels[l - 1].height, env->levels[l].height, ty);
            downsample(&env->levels[l - 1], &env->levels[l], tx, ty, rows);
        }
    } else {
        free(block);
    }
    sl_env_free(&single);
    free(rows);
    free(tx);
    free(ty);
    if (!ok) {
        *env = (sl_env){0};
        return sl_fail(err, SL_ERR_MEMORY, "environment %dx%d: out of memory for the mip chain", img->width,
                       img->height);
    }
    return true;
}

void sl_env_free(sl_env *env)
{
    if (!env)
        return;
    if (env->block)
        free(env->block);
    else
        for (int i = 0; i < env->level_count && i < SL_ENV_MAX_LEVELS; i++)
            free(env->levels[i].texels);
    memset(env, 0, sizeof *env);
}
