/* irradiance_uv.h - the lookup coordinates of the pole-free irradiance maps (irradiance_map.c
 * builds them; docs/ibl.md "Pole-free irradiance maps"), inline and branch-free so a vectorized
 * loop (sl_irradiance_eval_span, irradiance.c, which the lighting pass's batched and split-sum
 * paths call) computes them per lane; the public sl_irradiance_oct_uv and sl_irradiance_dp_uv
 * are these, so both give the same bits. */
#ifndef SL_IRRADIANCE_UV_H
#define SL_IRRADIANCE_UV_H

#include "../core/fast_math.h"
#include "octahedral.h"

/* Texel centre coordinate of grid point p in [-1, 1] on a side of s texels, clamped so the
 * bilinear footprint never leaves the side (CLAMP_TO_EDGE semantics under any wrap mode). */
SL_FM_INLINE float sl_irradiance_grid_coord(float p, int s)
{
    float t = (p * 0.5f + 0.5f) * ((float)(s - 1) / (float)s) + 0.5f / (float)s;
    float lo = 0.5f / (float)s, hi = 1.0f - 0.5f / (float)s;
    t = t > lo ? t : lo; /* NaN -> lo */
    return t < hi ? t : hi;
}

/* OCT: the fold of octahedral.h at the grid's texel centres. */
SL_FM_INLINE void sl_irradiance_oct_uv_inline(float x, float y, float z, int size, float *u, float *v)
{
    float px, py;
    sl_oct_fold(x, y, z, &px, &py);
    *u = sl_irradiance_grid_coord(px, size);
    *v = sl_irradiance_grid_coord(py, size);
}

/* DP: the hemisphere of n.z's sign, p = n.xy / (1 + |n.z|), the lower half in the right half. */
SL_FM_INLINE void sl_irradiance_dp_uv_inline(float x, float y, float z, int size, float *u, float *v)
{
    float half = z >= 0.0f ? 0.0f : 1.0f;
    float d = 1.0f + fabsf(z);
    float px = x / d, py = y / d;
    *u = (sl_irradiance_grid_coord(px, size) + half) * 0.5f;
    *v = sl_irradiance_grid_coord(py, size);
}

#endif
