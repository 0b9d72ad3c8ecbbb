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
 * No branch depends on the data: the wrap and clamp are selects, and both levels are always
 * read (a fract of 0 just weights the second by 0). */
#include "ibl.h"

static inline vec3 bilinear(const sl_env_level *lv, float u, float v)
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
    float y = clampf(v * (float)h - 0.5f, 0.0f, (float)(h - 1));
    int y0 = (int)y;
    float fy = y - (float)y0;
    int y1 = y0 + 1 < h ? y0 + 1 : h - 1;
    const vec3 *r0 = lv->texels + (size_t)y0 * (size_t)w;
    const vec3 *r1 = lv->texels + (size_t)y1 * (size_t)w;
    vec3 top = mix3(r0[x0], r0[x1], fx);
    vec3 bottom = mix3(r1[x0], r1[x1], fx);
    return mix3(top, bottom, fy);
}

vec3 textureLod(const sl_env *env, vec2 uv, float lod)
{
    if (env->level_count <= 0)
        return vec3s(0.0f);
    float u = isfinite(uv.x) ? uv.x : 0.0f;
    float v = isfinite(uv.y) ? uv.y : 0.0f;
    u -= floorf(u); /* REPEAT; a tiny negative u rounds to 1.0, which the wrap handles */
    int last = env->level_count - 1;
    lod = lod > 0.0f ? lod : 0.0f; /* NaN -> 0 */
    lod = lod < (float)last ? lod : (float)last;
    int l0 = (int)lod;
    float f = lod - (float)l0;
    int l1 = l0 < last ? l0 + 1 : last;
    vec3 a = bilinear(&env->levels[l0], u, v);
    vec3 b = bilinear(&env->levels[l1], u, v);
    return mix3(a, b, f);
}
