/* texture_lod.c - GLSL textureLod(sampler2D, uv, lod) for the environment, the inner loop of
 * the lighting shader (called for each of its 20..40 samples per pixel).
 *
 * Semantics of GL_LINEAR_MIPMAP_LINEAR (OpenGL 4.6 core, sections 8.14.2 - 8.14.3):
 *   - lod is clamped to [0, level_count - 1]; levels floor(lod) and floor(lod) + 1 (the
 *     last one twice at the top) are blended by fract(lod);
 *   - within a level, bilinear between the four texels around (u W - 1/2, v H - 1/2), so
 *     texel centres sit at (i + 1/2) / size;
 *   - u wraps (REPEAT): u = 0.999 blends the last and the first column;
 *   - v clamps to the edge (CLAMP_TO_EDGE): above the first row centre only row 0 is read.
 * Non-finite inputs never index outside the level: a NaN or infinite u or v reads as 0, a
 * NaN lod as 0, +-Inf lod clamps. Weights are float (no 8-bit GPU fixed point), so values
 * equal GL's up to float rounding.
 *
 * This file holds the guards; the filtering itself is the inline core in texture_lod.h,
 * which the lighting shader's batched path calls directly with inputs it has already
 * clamped. The only data-dependent branch skips the second level when fract(lod) = 0,
 * which returns the same bits as blending it with weight 0. */
#include "texture_lod.h"

#include <stdint.h>

vec3 sl_env_texture_lod(const sl_env *env, vec2 uv, float lod)
{
    if (env->level_count <= 0)
        return vec3s(0.0f);
    float u = isfinite(uv.x) ? uv.x : 0.0f;
    float v = isfinite(uv.y) ? uv.y : 0.0f;
    u -= floorf(u); /* REPEAT; a tiny negative u rounds to 1.0, which the wrap handles */
    int last = env->level_count - 1;
    lod = lod > 0.0f ? lod : 0.0f; /* NaN -> 0 */
    lod = lod < (float)last ? lod : (float)last;
    return sl_texture_lod_clamped(env, u, v, lod);
}

vec3 sl_oct_texture_lod(const sl_env *env, vec3 d, float lod)
{
    if (env->level_count <= 0)
        return vec3s(0.0f);
    float u, v;
    sl_oct_dir_to_uv(d.x, d.y, d.z, &u, &v);
    int last = env->level_count - 1;
    lod = lod > 0.0f ? lod : 0.0f; /* NaN -> 0 */
    lod = lod < (float)last ? lod : (float)last;
    return sl_oct_lod_clamped(env, u, v, lod);
}

void sl_env_gather_init(sl_env_gather *g, const sl_env *env)
{
    size_t total = 0;
    for (int l = 0; l < env->level_count; l++)
        total += (size_t)env->levels[l].width * (size_t)env->levels[l].height;
    g->gather = env->block != NULL && total < (size_t)INT32_MAX / 3; /* 3 floats a texel */
    g->texels = g->gather ? env->block : env->levels[0].texels;
    g->last = env->level_count - 1;
    /* the pair rows have one texel more a row; SL_ENV_PAIRS_MAX_TEXELS keeps their indices in int */
    g->pairs = g->gather && env->layout != SL_ENV_LAYOUT_OCT ? env->pairs : NULL;
    g->e5 = g->gather && env->layout != SL_ENV_LAYOUT_OCT ? env->e5 : NULL;
    g->e5_w = env->levels[0].width;
    g->e5_h = env->levels[0].height;
    g->e5_bias = env->e5_emin + 127;
    size_t offset = 0, pair_offset = 0;
    for (int l = 0; l < SL_ENV_MAX_LEVELS; l++) {
        const sl_env_level *lv = &env->levels[g->gather && l < env->level_count ? l : 0];
        g->offset[l] = (int)offset;
        g->pair_offset[l] = (int)pair_offset;
        g->width[l] = lv->width;
        g->height[l] = lv->height;
        if (g->gather) {
            offset += (size_t)lv->width * (size_t)lv->height;
            pair_offset += (size_t)(lv->width + 1) * (size_t)lv->height;
        }
    }
}
