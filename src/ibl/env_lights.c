/* env_lights.c - extraction of the brightest texels as exact lights (env_lights.h). */
#include "env_lights.h"

#include <math.h>
#include <string.h>

#include "ibl_internal.h"

/* Rec. 709 luminance */
static double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }
static double luminance3(vec3 c) { return luminance((double)c.x, (double)c.y, (double)c.z); }

/* Keep best[0 .. kept) sorted by luminance, brightest first (ties: lower index first), at most
 * `cap` entries: one pass over the map, and a texel dimmer than the last kept costs a compare. */
typedef struct {
    double y;
    size_t index;
} ranked;

static void rank_insert(ranked *best, int *kept, int cap, double y, size_t index)
{
    if (*kept == cap && !(y > best[cap - 1].y))
        return;
    int at = *kept < cap ? (*kept)++ : cap - 1;
    while (at > 0 && y > best[at - 1].y) {
        best[at] = best[at - 1];
        at--;
    }
    best[at] = (ranked){y, index};
}

/* How many of the ranked texels best[0 .. kept) are worth taking as lights, at most `most`
 * (SL_ENV_LIGHTS_WORTH_*, core/options.h). k lights clamped at the next texel's luminance Y_k
 * take (Y_j - Y_k) / Y_j of each texel j's power P_j (its node's luminance); that is monotone
 * in k, so the fewest within WORTH_REST of the ceiling's take is found by a walk up. */
static int lights_worth(const ranked *best, int kept, int most, const ibl_texels *nodes)
{
    double power[SL_ENV_LIGHTS_MAX];
    for (int j = 0; j < kept && j < most; j++) {
        size_t k = best[j].index;
        power[j] = luminance(nodes->r[k], nodes->g[k], nodes->b[k]);
    }
    /* what k lights take, and the power of their texels */
    double taken[SL_ENV_LIGHTS_MAX + 1] = {0}, own = 0.0;
    int ceiling = kept < most ? kept : most;
    for (int k = 1; k <= ceiling; k++) {
        double clamp = kept > k ? best[k].y : 0.0;
        for (int j = 0; j < k; j++)
            taken[k] += best[j].y > 0.0 ? power[j] * (1.0 - clamp / best[j].y) : 0.0;
    }
    for (int j = 0; j < ceiling; j++)
        own += power[j];
    if (!(taken[ceiling] >= SL_ENV_LIGHTS_WORTH_PEAK * own) || !(taken[ceiling] > 0.0))
        return 0;
    int k = 1;
    while (k < ceiling && taken[k] < (1.0 - SL_ENV_LIGHTS_WORTH_REST) * taken[ceiling])
        k++;
    return k;
}

static bool extract(sl_env_lights *lights, const sl_env *env, int count, bool worth, int threads, sl_error *err);

bool sl_env_lights_extract(sl_env_lights *lights, const sl_env *env, int count, int threads, sl_error *err)
{
    return extract(lights, env, count, false, threads, err);
}

bool sl_env_lights_extract_worth(sl_env_lights *lights, const sl_env *env, int most, int threads, sl_error *err)
{
    return extract(lights, env, most, true, threads, err);
}

/* The `count` brightest texels (`worth`: `count` a ceiling, lights_worth's part of it). */
static bool extract(sl_env_lights *lights, const sl_env *env, int count, bool worth, int threads, sl_error *err)
{
    memset(lights, 0, sizeof *lights);
    if (!env || env->level_count < 1)
        return sl_fail(err, SL_ERR_RANGE, "env lights: the environment has no levels");
    if (count < 1 || count > SL_ENV_LIGHTS_MAX)
        return sl_fail(err, SL_ERR_RANGE, "env lights: %d requested, expected 1..%d", count, SL_ENV_LIGHTS_MAX);
    const sl_env_level *l0 = &env->levels[0];
    ibl_texels nodes;
    if (!sl_ibl_texels_build(&nodes, l0, err))
        return false;

    /* The count + 1 brightest: the last one sets the clamp. Texels without a direction (weight
     * 0, only in absurdly coarse maps) cannot be lights and stay in the residual. */
    ranked best[SL_ENV_LIGHTS_MAX + 1];
    int kept = 0;
    double total = 0.0;
    for (size_t k = 0; k < nodes.count; k++) {
        double len2 = nodes.x[k] * nodes.x[k] + nodes.y[k] * nodes.y[k] + nodes.z[k] * nodes.z[k];
        if (!(len2 > 0.5))
            continue;
        total += luminance(nodes.r[k], nodes.g[k], nodes.b[k]);
        rank_insert(best, &kept, count + 1, luminance3(l0->texels[k]), k);
    }
    if (worth) {
        count = lights_worth(best, kept, count, &nodes);
        if (count == 0) { /* none worth it: no lights, and no residual to build */
            sl_ibl_texels_free(&nodes);
            return true;
        }
    }
    int n = kept < count ? kept : count;
    double clamp = kept > count ? best[count].y : 0.0;

    sl_image img;
    if (!sl_image_alloc(&img, l0->width, l0->height, 3, err)) {
        sl_ibl_texels_free(&nodes);
        return false;
    }
    _Static_assert(sizeof(vec3) == 3 * sizeof(float), "a level's texels are the image's floats");
    memcpy(img.data, l0->texels, (size_t)l0->width * (size_t)l0->height * sizeof(vec3));
    double taken = 0.0;
    const double dphi = 2.0 * PI_D / l0->width;
    lights->azimuth = (float)-dphi;
    for (int j = 0; j < n; j++) {
        size_t k = best[j].index;
        vec3 L = l0->texels[k];
        /* r = L * clamp / Y keeps the colour; the light gets the rest, times the node weight
         * |integral of w| = (node radiance) / L, which sl_ibl_texels_build already multiplied in */
        double keep = best[j].y > 0.0 ? clamp / best[j].y : 0.0;
        vec3 residual = vec3((float)((double)L.x * keep), (float)((double)L.y * keep), (float)((double)L.z * keep));
        img.data[3 * k + 0] = residual.x;
        img.data[3 * k + 1] = residual.y;
        img.data[3 * k + 2] = residual.z;
        double node = nodes.r[k] + nodes.g[k] + nodes.b[k];
        double sum = (double)L.x + (double)L.y + (double)L.z;
        double weight = sum > 0.0 ? node / sum : 0.0; /* a black texel taken (K > lit texels) adds 0 */
        /* what was taken out, in float as the residual holds it: the two parts sum to L */
        lights->radiance[j] = vec3((float)(((double)L.x - (double)residual.x) * weight),
                                   (float)(((double)L.y - (double)residual.y) * weight),
                                   (float)(((double)L.z - (double)residual.z) * weight));
        lights->dir[j] = vec3((float)nodes.x[k], (float)nodes.y[k], (float)nodes.z[k]);
        lights->texel[j] = k;
        /* the texel's bounds and solid angle (2 pi / W)(cos theta0 - cos theta1), in double */
        const int row = (int)(k / (size_t)l0->width), col = (int)(k % (size_t)l0->width);
        const double z0 = cos(PI_D * row / l0->height), z1 = cos(PI_D * (row + 1) / l0->height);
        lights->box[j] = vec3((float)z0, (float)z1, (float)(PI_D - dphi * col));
        lights->spread[j] = weight > 0.0 ? (float)(dphi * (z0 - z1) / weight) : 0.0f;
        taken += luminance3(lights->radiance[j]);
    }
    sl_ibl_texels_free(&nodes);
    bool ok = sl_env_build(&lights->residual, &img, threads, err);
    sl_image_free(&img);
    if (!ok) {
        memset(lights, 0, sizeof *lights);
        return false;
    }
    lights->count = n;
    lights->clamp = (float)clamp;
    lights->share = total > 0.0 ? taken / total : 0.0;
    return true;
}

void sl_env_lights_free(sl_env_lights *lights)
{
    if (!lights)
        return;
    sl_env_free(&lights->residual);
    memset(lights, 0, sizeof *lights);
}
