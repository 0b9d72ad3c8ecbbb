/* hammersley.c - the specification's low-discrepancy point set ("Building a low-discrepancy
 * list of pairs of pseudo-random points"), computed exactly as its loop does, in float, so
 * that the C shader and the GLSL (which receives these very numbers in its uniform block)
 * draw the same sample directions. */
#include "ibl.h"

#include <string.h>

bool sl_hammersley_build(sl_hammersley *set, int n, sl_error *err)
{
    memset(set, 0, sizeof *set);
    if (n < 1 || n > SL_HAMMERSLEY_MAX)
        return sl_fail(err, SL_ERR_RANGE, "Hammersley set of %d points: must be 1 .. %d", n, SL_HAMMERSLEY_MAX);
    set->n = n;
    for (int k = 0; k < n; k++) {
        float p, u;
        int kk;
        /* u = radical inverse of k in base 2: bit i of k contributes 2^-(i+1). */
        for (p = 0.5f, kk = k, u = 0.0f; kk; p *= 0.5f, kk >>= 1)
            if (kk & 1)
                u += p;
        float v = (float)((k + 0.5) / n); /* the specification's expression, in double as written */
        set->points[k] = vec2(u, v);
    }
    return true;
}
