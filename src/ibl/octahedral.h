/* octahedral.h - the octahedral map of a direction, written once for the two octahedral
 * layouts: the irradiance map (irradiance_uv.h) and the specular mip chain (texture_lod.h,
 * env_oct.c). Inline and branch-free, so vectorized loops compute it per lane and every caller
 * gets the same bits. */
#ifndef SL_OCTAHEDRAL_H
#define SL_OCTAHEDRAL_H

#include <math.h>

#include "../core/fast_math.h"

/* p = d.xy / |d|_1, folded below the equator (d.z < 0) to ((1 - |p.y|) sgn p.x,
 * (1 - |p.x|) sgn p.y) with sgn 0 = +1; p in [-1, 1]^2 (NaN for a zero d). d need not be unit. */
SL_FM_INLINE void sl_oct_fold(float x, float y, float z, float *px, float *py)
{
    float a = fabsf(x) + fabsf(y) + fabsf(z);
    float qx = x / a, qy = y / a;
    float fx = (1.0f - fabsf(qy)) * (qx >= 0.0f ? 1.0f : -1.0f);
    float fy = (1.0f - fabsf(qx)) * (qy >= 0.0f ? 1.0f : -1.0f);
    *px = z < 0.0f ? fx : qx;
    *py = z < 0.0f ? fy : qy;
}

#endif
