/* latlong.c - the specification's longitude-latitude sphere map, both ways ("Odds and ends").
 *
 *   direction -> uv:  u = 1/2 - atan2(d.y, d.x) / (2 pi),  v = acos(d.z) / pi
 *   uv -> direction:  eq. (4)
 *
 * float32 as the GLSL computes it. Two edge cases the formulas leave open are pinned down:
 * atan2 = -pi (d.y = -0 with d.x < 0) would give u = 1, which is folded to u = 0 so that u is
 * always in [0, 1) and both sides of the seam read the same column; and d.z is clamped to
 * [-1, 1] before acos, because a normalised vector's z can round to 1 + 1 ulp (acos would
 * return NaN: one of the specification's "black pixels"). A direction with a NaN component
 * still gives a finite uv. d need not be unit length for u; v assumes it is. */
#include "ibl.h"

vec2 sl_dir_to_uv(vec3 d)
{
    float u = 0.5f - atan2f(d.y, d.x) / (2.0f * SL_PI);
    u = u < 1.0f ? u : u - 1.0f;
    u = u >= 0.0f ? u : 0.0f; /* NaN -> 0 */
    float z = fminf(fmaxf(d.z, -1.0f), 1.0f); /* NaN -> -1 */
    return vec2(u, acosf(z) / SL_PI);
}

vec3 sl_uv_to_dir(vec2 uv)
{
    float phi = 2.0f * SL_PI * (0.5f - uv.x);
    float theta = SL_PI * uv.y;
    float s = sinf(theta);
    return vec3(cosf(phi) * s, sinf(phi) * s, cosf(theta));
}
