/* texel.c - exact geometry of lat-long texels (row and column moments, centroid nodes) and
 * the input checks every ibl entry point shares. See ibl_internal.h for the parametrisation.
 *
 * The closed forms are written with products of sines rather than differences of cosines
 * where the two would cancel: near the poles a row's cos(theta0) - cos(theta1) is ~1e-5 and
 * the difference form would lose five digits of the double. */
#include "ibl_internal.h"

#include <math.h>
#include <stdlib.h>

void sl_ibl_row_moments_at(int height, int j, ibl_row_moments *m)
{
    double t0 = PI_D * (double)j / (double)height;
    double t1 = PI_D * (double)(j + 1) / (double)height;
    double sum = t0 + t1, d = t1 - t0;
    double s0 = sin(t0), s1 = sin(t1), c0 = cos(t0), c1 = cos(t1);
    m->dz = 2.0 * sin(0.5 * sum) * sin(0.5 * d);          /* cos t0 - cos t1 */
    m->s = 0.5 * d - 0.5 * cos(sum) * sin(d);              /* int sin^2 t dt */
    m->z = 0.5 * sin(sum) * sin(d);                        /* (sin^2 t1 - sin^2 t0) / 2 */
    m->zs = (s1 * s1 * s1 - s0 * s0 * s0) / 3.0;           /* int cos t sin^2 t dt */
    m->zz = (c0 * c0 * c0 - c1 * c1 * c1) / 3.0;           /* int cos^2 t sin t dt */
}

void sl_ibl_col_moments_at(int width, int i, ibl_col_moments *m)
{
    double lo = PI_D - 2.0 * PI_D * (double)(i + 1) / (double)width;
    double hi = PI_D - 2.0 * PI_D * (double)i / (double)width;
    m->dphi = 2.0 * PI_D / (double)width;
    m->c = sin(hi) - sin(lo);
    m->s = cos(lo) - cos(hi);
    m->c2 = 0.5 * (sin(2.0 * hi) - sin(2.0 * lo));
    m->s2 = 0.5 * (cos(2.0 * lo) - cos(2.0 * hi));
}

bool sl_ibl_texels_build(ibl_texels *t, const sl_env_level *level, sl_error *err)
{
    *t = (ibl_texels){0};
    int w = level->width, h = level->height;
    size_t n = (size_t)w * (size_t)h;
    double *block = malloc(6 * n * sizeof(double));
    ibl_col_moments *cols = malloc((size_t)w * sizeof *cols);
    if (!block || !cols) {
        free(block);
        free(cols);
        return sl_fail(err, SL_ERR_MEMORY, "environment %dx%d: no memory for the quadrature table", w, h);
    }
    *t = (ibl_texels){.width = w, .height = h, .count = n, .x = block, .y = block + n, .z = block + 2 * n,
                      .r = block + 3 * n, .g = block + 4 * n, .b = block + 5 * n};
    for (int i = 0; i < w; i++)
        sl_ibl_col_moments_at(w, i, &cols[i]);
    for (int j = 0; j < h; j++) {
        ibl_row_moments rm;
        sl_ibl_row_moments_at(h, j, &rm);
        for (int i = 0; i < w; i++) {
            size_t k = (size_t)j * (size_t)w + (size_t)i;
            double mx = rm.s * cols[i].c, my = rm.s * cols[i].s, mz = rm.z * cols[i].dphi;
            double len = sqrt(mx * mx + my * my + mz * mz);
            /* A texel whose centroid is the origin (a 1x1 image, the middle row of a 1-wide
             * image) has no direction: it gets weight 0. Its |m| is rounding noise (~1e-16)
             * against a solid angle of order 1, so the test is relative to the solid angle;
             * a real texel's |m| is within a few percent of its solid angle. Only absurdly
             * coarse images have one. */
            double degenerate = 1e-9 * rm.dz * cols[i].dphi;
            double inv = len > degenerate ? 1.0 / len : 0.0;
            len = len > degenerate ? len : 0.0;
            vec3 l = level->texels[k];
            t->x[k] = mx * inv;
            t->y[k] = my * inv;
            t->z[k] = mz * inv;
            t->r[k] = (double)l.x * len;
            t->g[k] = (double)l.y * len;
            t->b[k] = (double)l.z * len;
        }
    }
    free(cols);
    return true;
}

void sl_ibl_texels_free(ibl_texels *t)
{
    if (!t)
        return;
    free(t->x);
    *t = (ibl_texels){0};
}

bool sl_ibl_check_image(const sl_image *img, const char *what, sl_error *err)
{
    if (!img || !img->data)
        return sl_fail(err, SL_ERR_RANGE, "%s: no image", what);
    if (img->channels != 3)
        return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: %d channels, an environment needs 3 (RGB)", what,
                       img->channels);
    if (img->width < 1 || img->height < 1 || img->width > 65535 || img->height > 65535)
        return sl_fail(err, SL_ERR_RANGE, "%s: size %dx%d, each side must be 1 .. 65535", what, img->width,
                       img->height);
    size_t n = (size_t)img->width * (size_t)img->height * 3;
    for (size_t k = 0; k < n; k++) {
        float v = img->data[k];
        if (!(v >= 0.0f && isfinite(v))) {
            size_t px = k / 3;
            return sl_fail(err, SL_ERR_RANGE, "%s: texel (%zu, %zu) channel %zu is %g: must be finite and >= 0",
                           what, px % (size_t)img->width, px / (size_t)img->width, k % 3, (double)v);
        }
    }
    return true;
}

bool sl_ibl_env_single_level(sl_env *env, const sl_image *img, sl_error *err)
{
    *env = (sl_env){0};
    size_t n = (size_t)img->width * (size_t)img->height;
    vec3 *texels = malloc(n * sizeof *texels);
    if (!texels)
        return sl_fail(err, SL_ERR_MEMORY, "%dx%d map: out of memory", img->width, img->height);
    for (size_t k = 0; k < n; k++)
        texels[k] = vec3(img->data[3 * k], img->data[3 * k + 1], img->data[3 * k + 2]);
    env->level_count = 1;
    env->levels[0] = (sl_env_level){.width = img->width, .height = img->height, .texels = texels};
    return true;
}
