/* env_dist.c - the environment's luminance as a piecewise-constant distribution in solid angle
 * (env_dist.h): its CDFs and densities, built once per environment. */
#include "env_dist.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Rec. 709 luminance, as env_lights.c ranks texels */
static double luminance(vec3 c) { return 0.2126 * (double)c.x + 0.7152 * (double)c.y + 0.0722 * (double)c.z; }

bool sl_env_dist_build(sl_env_dist *dist, const sl_env *env, sl_error *err)
{
    memset(dist, 0, sizeof *dist);
    if (!env || env->level_count < 1 || env->layout == SL_ENV_LAYOUT_OCT)
        return sl_fail(err, SL_ERR_RANGE, "environment distribution: needs a lat-long chain");
    int level = 0;
    /* down only through levels of exactly half the size, so that level-0 texel (i, j) lies in
     * the grid's (i >> level, j >> level) */
    while (level + 1 < env->level_count && env->levels[level].width > SL_ENV_DIST_MAX_WIDTH &&
           env->levels[level].width % 2 == 0 && env->levels[level].height % 2 == 0)
        level++;
    const sl_env_level *l = &env->levels[level];
    const int W = l->width, H = l->height;
    const size_t n = (size_t)W * (size_t)H;
    dist->cdf = malloc(n * sizeof *dist->cdf);
    dist->density = malloc(n * sizeof *dist->density);
    dist->marginal = malloc((size_t)H * sizeof *dist->marginal);
    double *row = malloc((size_t)H * sizeof *row);
    double *cum = malloc((size_t)W * sizeof *cum);
    if (!dist->cdf || !dist->density || !dist->marginal || !row || !cum) {
        free(row);
        free(cum);
        sl_env_dist_free(dist);
        return sl_fail(err, SL_ERR_MEMORY, "environment distribution: no memory for %dx%d", W, H);
    }
    dist->width = W;
    dist->height = H;
    dist->level = level;
    dist->src_width = env->levels[0].width;
    dist->src_height = env->levels[0].height;

    /* the total first: without any luminance every texel weighs its solid angle alone */
    const double pi = 3.14159265358979323846;
    double total = 0.0;
    for (int j = 0; j < H; j++) {
        double omega = 2.0 * pi / W * (cos(pi * j / H) - cos(pi * (j + 1) / H));
        double y = 0.0;
        for (int i = 0; i < W; i++)
            y += luminance(l->texels[(size_t)j * (size_t)W + (size_t)i]);
        total += y * omega;
    }
    const bool uniform = !(total > 0.0) || !isfinite(total);
    dist->total = uniform ? 0.0 : total;

    double all = 0.0;
    for (int j = 0; j < H; j++) {
        double omega = 2.0 * pi / W * (cos(pi * j / H) - cos(pi * (j + 1) / H));
        double s = 0.0;
        for (int i = 0; i < W; i++) {
            size_t k = (size_t)j * (size_t)W + (size_t)i;
            double y = uniform ? 1.0 : luminance(l->texels[k]);
            s += y;
            cum[i] = s;
        }
        for (int i = 0; i < W; i++)
            dist->cdf[(size_t)j * (size_t)W + (size_t)i] = s > 0.0 ? (float)(cum[i] / s) : (float)(i + 1) / (float)W;
        dist->cdf[(size_t)j * (size_t)W + (size_t)(W - 1)] = 1.0f;
        row[j] = s * omega;
        all += row[j];
    }
    double c = 0.0;
    for (int j = 0; j < H; j++) {
        c += row[j];
        dist->marginal[j] = (float)(c / all);
    }
    dist->marginal[H - 1] = 1.0f;
    /* The density is what the float CDFs draw, not the luminance they were made from: a dim
     * texel whose CDF step rounded to 0 beside a sun is never drawn, and must not claim a
     * density the MIS weights would then count on. */
    for (int j = 0; j < H; j++) {
        double omega = 2.0 * pi / W * (cos(pi * j / H) - cos(pi * (j + 1) / H));
        double pj = (double)dist->marginal[j] - (j > 0 ? (double)dist->marginal[j - 1] : 0.0);
        for (int i = 0; i < W; i++) {
            size_t k = (size_t)j * (size_t)W + (size_t)i;
            double pi_j = (double)dist->cdf[k] - (i > 0 ? (double)dist->cdf[k - 1] : 0.0);
            dist->density[k] = (float)(pj * pi_j / omega);
        }
    }
    free(row);
    free(cum);
    const sl_env_level *l0 = &env->levels[0];
    const size_t n0 = (size_t)l0->width * (size_t)l0->height;
    if (n0 <= SL_ENV_PAIRS_MAX_TEXELS) {
        dist->texel_pdf = malloc(4 * n0 * sizeof *dist->texel_pdf);
        if (!dist->texel_pdf) {
            sl_env_dist_free(dist);
            return sl_fail(err, SL_ERR_MEMORY, "environment distribution: no memory for %dx%d", l0->width, l0->height);
        }
        for (int j = 0; j < l0->height; j++)
            for (int i = 0; i < l0->width; i++) {
                size_t k = (size_t)j * (size_t)l0->width + (size_t)i;
                float *t = dist->texel_pdf + 4 * k;
                t[0] = l0->texels[k].x;
                t[1] = l0->texels[k].y;
                t[2] = l0->texels[k].z;
                t[3] = dist->density[(size_t)(j >> level) * (size_t)W + (size_t)(i >> level)];
            }
    }
    return true;
}

void sl_env_dist_free(sl_env_dist *dist)
{
    if (!dist)
        return;
    free(dist->cdf);
    free(dist->density);
    free(dist->marginal);
    free(dist->texel_pdf);
    memset(dist, 0, sizeof *dist);
}
