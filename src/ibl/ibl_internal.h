/* ibl_internal.h - what the files of src/ibl share and nothing outside it should use.
 *
 * Texel geometry of a W x H lat-long image (specification eq. (4)): column i spans
 * u in [i/W, (i+1)/W], i.e. azimuth phi = 2 pi (1/2 - u) in [pi - 2 pi (i+1)/W, pi - 2 pi i/W];
 * row j spans v in [j/H, (j+1)/H], i.e. polar angle theta = pi v in [pi j/H, pi (j+1)/H].
 * With z = cos(theta), dw = dz dphi and x = sqrt(1 - z^2) cos(phi), y = sqrt(1 - z^2) sin(phi),
 * so every integral over a texel of a polynomial in (x, y, z) of degree <= 2 separates into
 * a row factor (an integral over z) and a column factor (an integral over phi). Those
 * factors, in closed form and in double, are what makes the solid angles, the texel
 * centroids and the SH9 projection exact for a piecewise-constant environment. */
#ifndef SL_IBL_INTERNAL_H
#define SL_IBL_INTERNAL_H

#include <stddef.h>

#include "ibl.h"

/* pi in double, for the module's closed forms */
#define PI_D 3.14159265358979323846

/* Integrals over one row, z from cos(theta1) to cos(theta0). */
typedef struct {
    double dz;  /* integral of 1       = cos(theta0) - cos(theta1) */
    double s;   /* integral of sqrt(1 - z^2) */
    double z;   /* integral of z */
    double zs;  /* integral of z sqrt(1 - z^2) */
    double zz;  /* integral of z^2 */
} ibl_row_moments;

/* Integrals over one column, phi over its interval. */
typedef struct {
    double dphi; /* integral of 1 = 2 pi / W */
    double c;    /* integral of cos(phi) */
    double s;    /* integral of sin(phi) */
    double c2;   /* integral of cos(2 phi) */
    double s2;   /* integral of sin(2 phi) */
} ibl_col_moments;

void sl_ibl_row_moments_at(int height, int j, ibl_row_moments *m);
void sl_ibl_col_moments_at(int width, int i, ibl_col_moments *m);

/* Every texel of one level as quadrature nodes for cosine-weighted integrals, in double,
 * structure of arrays so the loops over them vectorise. For texel t:
 *   (x, y, z)[t]  unit direction of the texel's centroid m = integral of w dw over the texel,
 *   (r, g, b)[t]  radiance times |m|,
 * so that  L * (n . m) = (n . dir) * rgb  is EXACTLY the integral of L (n . w) over the texel
 * whenever the whole texel lies above the horizon of n (the cosine is linear in w). */
typedef struct {
    int width, height;
    size_t count;
    double *x, *y, *z;
    double *r, *g, *b;
} ibl_texels;

bool sl_ibl_texels_build(ibl_texels *t, const sl_env_level *level, sl_error *err);
void sl_ibl_texels_free(ibl_texels *t);

/* Checks shared by every entry point that takes an image: 3 channels, a sane size, and
 * only finite, non-negative texels. `what` names the image in the message. */
bool sl_ibl_check_image(const sl_image *img, const char *what, sl_error *err);

/* An sl_env with level 0 only, a copy of `img` (already checked). */
bool sl_ibl_env_single_level(sl_env *env, const sl_image *img, sl_error *err);

/* sl_env_build, with general_only = true forcing env.c's general filter on every level instead
 * of its even-size fast path (the same bits; tests/unit/test_ibl.c checks that). */
bool sl_ibl_env_build_path(sl_env *env, const sl_image *img, bool general_only, int threads, sl_error *err);

/* sl_env.pairs for a lat-long chain of `texels` texels in all (env.c; the prefiltered chains
 * have them too): NULL when over SL_ENV_PAIRS_MAX_TEXELS or out of memory. */
float *sl_ibl_env_build_pairs(const sl_env *env, size_t texels);

/* sl_env.e5 for a lat-long chain of `texels` texels, and its exponent offset in *emin (env.c):
 * NULL when over SL_ENV_PAIRS_MAX_TEXELS or out of memory. */
uint32_t *sl_ibl_env_build_e5(const sl_env *env, size_t texels, int *emin, int threads);

#endif
