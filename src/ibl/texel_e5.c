/* texel_e5.c - encoding the compact shared-exponent texel (texel_e5.h), in double so that the
 * rounding is the one stated there: round to nearest, halves up. */
#include "texel_e5.h"

#include <math.h>

int sl_e5_emin(float max_value)
{
    if (!(max_value > 0.0f))
        return -126;
    int ex;
    (void)frexp((double)max_value, &ex); /* max_value in [2^(ex - 1), 2^ex) */
    /* e + emin = ex - 9 puts the mantissa in [256, 512); the brightest gets e = 30 */
    int emin = ex - 9 - (SL_E5_EXP_MAX - 1);
    return emin < -126 ? -126 : emin; /* finite floats give ex <= 128, emin <= 89: 2^(31 + emin) is normal */
}

uint32_t sl_e5_encode(float r, float g, float b, int emin)
{
    double m = (double)(r > g ? r : g);
    m = m > (double)b ? m : (double)b;
    if (!(m > 0.0))
        return 0;
    int ex;
    (void)frexp(m, &ex);
    int e = ex - 9 - emin;
    e = e < 0 ? 0 : (e > SL_E5_EXP_MAX ? SL_E5_EXP_MAX : e);
    double s = ldexp(1.0, -(e + emin));
    if (floor(m * s + 0.5) > (double)SL_E5_MANT_MAX && e < SL_E5_EXP_MAX) { /* rounded up to 512 */
        e++;
        s *= 0.5;
    }
    uint32_t t = (uint32_t)e << 27;
    const double c[3] = {(double)r, (double)g, (double)b};
    for (int k = 0; k < 3; k++) {
        double q = floor(c[k] * s + 0.5);
        q = q < (double)SL_E5_MANT_MAX ? q : (double)SL_E5_MANT_MAX;
        t |= (uint32_t)q << (9 * k);
    }
    return t;
}
