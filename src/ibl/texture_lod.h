/* texture_lod.h - the inline core of textureLod (texture_lod.c), for the lighting shader's
 * inner loop, where a function call per sample and the guards of the public entry point cost
 * more than the filtering itself.
 *
 * The caller guarantees what textureLod otherwise checks: env has at least one level, u is
 * finite and in [0, 1] (REPEAT already applied: 1.0 wraps to column 0 like 0.0), v finite,
 * lod finite and in [0, level_count - 1]. Under those conditions sl_texture_lod_clamped
 * returns exactly the bits textureLod returns: the same operations in the same order, and
 * when fract(lod) is 0 the second level is skipped (mix(a, b, 0) = a + (b - a) * 0 = a for
 * finite, non-negative texels, which sl_env_build guarantees). */
#ifndef SL_TEXTURE_LOD_H
#define SL_TEXTURE_LOD_H

#include <stddef.h>

#include "ibl.h"

/* GL_LINEAR within one level: REPEAT in u, CLAMP_TO_EDGE in v, texel centres at (i + 1/2) / size. */
static inline vec3 sl_env_bilinear(const sl_env_level *lv, float u, float v)
{
    int w = lv->width, h = lv->height;
    /* u in [0, 1], so x in [-1/2, w - 1/2] and x0 in [-1, w - 1]. */
    float x = u * (float)w - 0.5f;
    float xf = floorf(x);
    float fx = x - xf;
    int x0 = (int)xf;
    int x1 = x0 + 1;
    x0 = x0 < 0 ? x0 + w : x0;
    x1 = x1 >= w ? x1 - w : x1;
    /* Clamping the coordinate (not the index) gives CLAMP_TO_EDGE: at the clamp both rows
     * are the same or the fraction is 0. */
    float y = minf(maxf(v * (float)h - 0.5f, 0.0f), (float)(h - 1));
    int y0 = (int)y;
    float fy = y - (float)y0;
    int y1 = y0 + 1 < h ? y0 + 1 : h - 1;
    const vec3 *r0 = lv->texels + (size_t)y0 * (size_t)w;
    const vec3 *r1 = lv->texels + (size_t)y1 * (size_t)w;
    vec3 top = mix3(r0[x0], r0[x1], fx);
    vec3 bottom = mix3(r1[x0], r1[x1], fx);
    return mix3(top, bottom, fy);
}

/* GL_LINEAR_MIPMAP_LINEAR between levels floor(lod) and floor(lod) + 1 (the last one twice). */
static inline vec3 sl_texture_lod_clamped(const sl_env *env, float u, float v, float lod)
{
    int last = env->level_count - 1;
    int l0 = (int)lod;
    float f = lod - (float)l0;
    vec3 a = sl_env_bilinear(&env->levels[l0], u, v);
    if (f == 0.0f)
        return a;
    int l1 = l0 < last ? l0 + 1 : last;
    vec3 b = sl_env_bilinear(&env->levels[l1], u, v);
    return mix3(a, b, f);
}

#endif
