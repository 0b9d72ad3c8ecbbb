/* irradiance.c - E(n) = integral of L(w) max(0, n . w) dw for the diffuse term Kd/pi E(n)
 * (specification, "Diffuse calculation equations"), three ways:
 *
 * SH9 (Ramamoorthi & Hanrahan 2001, "An efficient representation for irradiance environment
 *   maps"): L is projected onto the 9 real spherical harmonics of bands 0..2, treating the
 *   level-0 image as constant over each texel. Every basis function is a polynomial of
 *   degree <= 2 in (x, y, z), so its integral over a texel is exact in closed form (row and
 *   column moments, texel.c): the projection has no quadrature error, only double rounding.
 *   Coefficients are then scaled by the clamped-cosine factors A0 = pi, A1 = 2 pi / 3,
 *   A2 = pi / 4, so E(n) = sum_i sh_i Y_i(n). Order and constants are in ibl.h.
 *   Exact for environments of bands 0..2 (constant, linear, quadratic in w) and for the
 *   half sky (E = pi (1 + n.z) / 2 has no band above 1); ringing, and even negative values
 *   opposite a strong sun, elsewhere: sl_irradiance_eval clamps at 0.
 *
 * BRUTE: a small lat-long map of E, each texel the quadrature over every texel of one mip
 *   level with centroid nodes (ibl_texels: exact for texels wholly above the horizon).
 *   Which level: see sl_irradiance_brute and docs/ibl.md (the error of coarser levels was
 *   measured against the full-resolution quadrature). OpenMP over map texels; each sum is
 *   sequential in a fixed order, so the map does not depend on the thread count.
 *
 * MAP: a precomputed lat-long irradiance image from the scene.
 *
 * BRUTE and MAP are looked up with textureLod at lod 0 (bilinear, REPEAT in u, CLAMP in v).
 * OCT and DP, the pole-free layouts, are built in irradiance_map.c; their lookup is here, per
 * direction (sl_irradiance_eval) and per span of directions (sl_irradiance_eval_span, the
 * lighting pass's batched path: vector loops, the same bits). */
/* clang honours `omp simd` too but may not vectorize the span lookup's gathers; a missed
 * optimisation, not an error in a -Werror build (as lighting_batched.c). */
#ifdef __clang__
#pragma clang diagnostic ignored "-Wpass-failed"
#endif

#include "../core/threads.h"
#include "ibl_internal.h"
#include "irradiance_uv.h"
#include "texture_lod.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Real SH normalisation constants (the same numbers as the float ones in sl_irradiance_eval). */
#define K0 0.28209479177387814 /* sqrt(1 / (4 pi)) */
#define K1 0.48860251190291992 /* sqrt(3 / (4 pi)) */
#define K2 1.09254843059207907 /* sqrt(15 / (4 pi)) */
#define K3 0.31539156525252005 /* sqrt(5 / (16 pi)) */
#define K4 0.54627421529603953 /* sqrt(15 / (16 pi)) */

bool sl_irradiance_sh9(sl_irradiance *irr, const sl_env *env, sl_error *err)
{
    memset(irr, 0, sizeof *irr);
    if (!env || env->level_count < 1)
        return sl_fail(err, SL_ERR_RANGE, "SH9 irradiance: the environment has no levels");
    const sl_env_level *lv = &env->levels[0];
    int w = lv->width, h = lv->height;
    ibl_col_moments *cols = malloc((size_t)w * sizeof *cols);
    if (!cols)
        return sl_fail(err, SL_ERR_MEMORY, "SH9 irradiance: out of memory");
    for (int i = 0; i < w; i++)
        sl_ibl_col_moments_at(w, i, &cols[i]);

    double c[9][3] = {{0}};
    for (int j = 0; j < h; j++) {
        /* Per row, sum L times each column factor; the row factor multiplies afterwards. */
        double sp[3] = {0}, ss[3] = {0}, sc[3] = {0}, ss2[3] = {0}, sc2[3] = {0};
        const vec3 *row = lv->texels + (size_t)j * (size_t)w;
        for (int i = 0; i < w; i++) {
            double l[3] = {(double)row[i].x, (double)row[i].y, (double)row[i].z};
            for (int ch = 0; ch < 3; ch++) {
                sp[ch] += l[ch] * cols[i].dphi;
                ss[ch] += l[ch] * cols[i].s;
                sc[ch] += l[ch] * cols[i].c;
                ss2[ch] += l[ch] * cols[i].s2;
                sc2[ch] += l[ch] * cols[i].c2;
            }
        }
        ibl_row_moments m;
        sl_ibl_row_moments_at(h, j, &m);
        double one_minus_zz = m.dz - m.zz; /* integral of 1 - z^2 = x^2 + y^2 */
        for (int ch = 0; ch < 3; ch++) {
            c[0][ch] += K0 * m.dz * sp[ch];                     /* 1 */
            c[1][ch] += K1 * m.s * ss[ch];                      /* y */
            c[2][ch] += K1 * m.z * sp[ch];                      /* z */
            c[3][ch] += K1 * m.s * sc[ch];                      /* x */
            c[4][ch] += K2 * one_minus_zz * 0.5 * ss2[ch];      /* xy = (1 - z^2) sin(2 phi) / 2 */
            c[5][ch] += K2 * m.zs * ss[ch];                     /* yz */
            c[6][ch] += K3 * (3.0 * m.zz - m.dz) * sp[ch];      /* 3 z^2 - 1 */
            c[7][ch] += K2 * m.zs * sc[ch];                     /* xz */
            c[8][ch] += K4 * one_minus_zz * sc2[ch];            /* x^2 - y^2 = (1 - z^2) cos(2 phi) */
        }
    }
    free(cols);
    static const double band_a[9] = {PI_D,       2.0 * PI_D / 3.0, 2.0 * PI_D / 3.0,
                                      2.0 * PI_D / 3.0, PI_D / 4.0, PI_D / 4.0,
                                      PI_D / 4.0, PI_D / 4.0,       PI_D / 4.0};
    irr->method = SL_IRRADIANCE_SH9;
    for (int k = 0; k < 9; k++)
        irr->sh[k] = vec3(band_a[k] * c[k][0], band_a[k] * c[k][1], band_a[k] * c[k][2]);
    return true;
}

/* The map texel (i, j) holds E at its centre direction, so bilinear lookup is exact there. */
static void brute_fill(sl_env_level *map, const ibl_texels *src, int threads)
{
    int mw = map->width, mh = map->height;
    const double *restrict x = src->x, *restrict y = src->y, *restrict z = src->z;
    const double *restrict r = src->r, *restrict g = src->g, *restrict b = src->b;
    size_t count = src->count;
    long total = (long)mw * (long)mh;
#pragma omp parallel for schedule(static) num_threads(sl_threads(threads))
    for (long k = 0; k < total; k++) {
        double u = ((double)(k % mw) + 0.5) / (double)mw;
        double v = ((double)(k / mw) + 0.5) / (double)mh;
        double phi = 2.0 * PI_D * (0.5 - u), theta = PI_D * v;
        double nx = cos(phi) * sin(theta), ny = sin(phi) * sin(theta), nz = cos(theta);
        double er = 0, eg = 0, eb = 0;
#pragma omp simd reduction(+ : er, eg, eb)
        for (size_t t = 0; t < count; t++) {
            double c = nx * x[t] + ny * y[t] + nz * z[t];
            c = c > 0.0 ? c : 0.0;
            er += c * r[t];
            eg += c * g[t];
            eb += c * b[t];
        }
        map->texels[k] = vec3(er, eg, eb);
    }
}

bool sl_irradiance_brute_level(sl_irradiance *irr, const sl_env *env, int map_width, int level, int threads, sl_error *err)
{
    memset(irr, 0, sizeof *irr);
    if (!env || env->level_count < 1)
        return sl_fail(err, SL_ERR_RANGE, "brute-force irradiance: the environment has no levels");
    if (map_width < 1 || map_width > 4096)
        return sl_fail(err, SL_ERR_RANGE, "brute-force irradiance: map width %d, must be 1 .. 4096", map_width);
    if (level < 0 || level >= env->level_count)
        return sl_fail(err, SL_ERR_RANGE, "brute-force irradiance: level %d, the environment has 0 .. %d", level,
                       env->level_count - 1);
    int mw = map_width, mh = map_width / 2 > 1 ? map_width / 2 : 1;
    ibl_texels src;
    if (!sl_ibl_texels_build(&src, &env->levels[level], err))
        return false;
    vec3 *texels = malloc((size_t)mw * (size_t)mh * sizeof *texels);
    if (!texels) {
        sl_ibl_texels_free(&src);
        return sl_fail(err, SL_ERR_MEMORY, "brute-force irradiance: out of memory for a %dx%d map", mw, mh);
    }
    irr->method = SL_IRRADIANCE_BRUTE;
    irr->map.level_count = 1;
    irr->map.levels[0] = (sl_env_level){.width = mw, .height = mh, .texels = texels};
    brute_fill(&irr->map.levels[0], &src, threads);
    sl_ibl_texels_free(&src);
    return true;
}

int sl_irradiance_brute_default_level(const sl_env *env)
{
    /* The finest level with at most SL_IRRADIANCE_BRUTE_TEXELS texels (docs/ibl.md has the
     * error of each level against level 0). */
    int level = 0;
    while (level + 1 < env->level_count &&
           (long)env->levels[level].width * env->levels[level].height > SL_IRRADIANCE_BRUTE_TEXELS)
        level++;
    return level;
}

bool sl_irradiance_brute(sl_irradiance *irr, const sl_env *env, int map_width, int threads, sl_error *err)
{
    if (!env || env->level_count < 1) {
        memset(irr, 0, sizeof *irr);
        return sl_fail(err, SL_ERR_RANGE, "brute-force irradiance: the environment has no levels");
    }
    return sl_irradiance_brute_level(irr, env, map_width, sl_irradiance_brute_default_level(env), threads, err);
}

bool sl_irradiance_from_image(sl_irradiance *irr, const sl_image *map, sl_error *err)
{
    memset(irr, 0, sizeof *irr);
    if (!sl_ibl_check_image(map, "irradiance map", err))
        return false;
    if (!sl_ibl_env_single_level(&irr->map, map, err))
        return false;
    irr->method = SL_IRRADIANCE_MAP;
    return true;
}

/* The SH9 sum at unit n, in one order of operations for the scalar and the span lookup (the
 * same bits). Inline, so a span's vector loop keeps the coefficients in registers. */
__attribute__((always_inline)) static inline vec3 sh9_sum(const vec3 *c, float x, float y, float z)
{
    const float k0 = 0.282094792f, k1 = 0.488602512f, k2 = 1.092548431f, k3 = 0.315391565f, k4 = 0.546274215f;
    vec3 e = scale3(c[0], k0);
    e = add3(e, scale3(c[1], k1 * y));
    e = add3(e, scale3(c[2], k1 * z));
    e = add3(e, scale3(c[3], k1 * x));
    e = add3(e, scale3(c[4], k2 * x * y));
    e = add3(e, scale3(c[5], k2 * y * z));
    e = add3(e, scale3(c[6], k3 * (3.0f * z * z - 1.0f)));
    e = add3(e, scale3(c[7], k2 * x * z));
    e = add3(e, scale3(c[8], k4 * (x * x - y * y)));
    return e;
}

/* SH9 rings below 0 opposite a strong sun; "x > 0 ? x : 0" also turns NaN into 0. */
static inline float clamp_e(float e) { return e > 0.0f ? e : 0.0f; }

vec3 sl_irradiance_eval(const sl_irradiance *irr, vec3 n)
{
    vec3 e;
    if (irr->method == SL_IRRADIANCE_SH9) {
        e = sh9_sum(irr->sh, n.x, n.y, n.z);
    } else if (irr->method == SL_IRRADIANCE_OCT) {
        e = textureLod(&irr->map, sl_irradiance_oct_uv(n, irr->map.levels[0].height), 0.0f);
    } else if (irr->method == SL_IRRADIANCE_DP) {
        e = textureLod(&irr->map, sl_irradiance_dp_uv(n, irr->map.levels[0].height), 0.0f);
    } else {
        e = textureLod(&irr->map, sl_dir_to_uv(n), 0.0f);
    }
    return vec3(clamp_e(e.x), clamp_e(e.y), clamp_e(e.z));
}

/* sl_irradiance_eval over a span (ibl.h), one vector loop per method. The pole-free
 * maps' uv is clamped into (0, 1) (sl_irradiance_grid_coord), where textureLod's guards (a
 * non-finite coordinate reads as 0, u wraps) change nothing and lod 0 is level 0's bilinear
 * filter alone: the fetch is sl_texels_bilinear, the same bits. The lat-long maps go through
 * libm's atan2 and acos (sl_dir_to_uv), which have no vector form of the same bits: a lane at
 * a time, sl_irradiance_eval itself. */
void sl_irradiance_eval_span(const sl_irradiance *irr, int count, const float *x, const float *y, const float *z,
                             float *er, float *eg, float *eb)
{
    const bool map = irr->method == SL_IRRADIANCE_OCT || irr->method == SL_IRRADIANCE_DP;
    if (irr->method == SL_IRRADIANCE_SH9) {
        const vec3 *c = irr->sh;
#pragma omp simd
        for (int i = 0; i < count; i++) {
            vec3 e = sh9_sum(c, x[i], y[i], z[i]);
            er[i] = clamp_e(e.x);
            eg[i] = clamp_e(e.y);
            eb[i] = clamp_e(e.z);
        }
    } else if (map && irr->map.level_count > 0) {
        const sl_env_level *l0 = &irr->map.levels[0];
        const vec3 *T = l0->texels;
        const int w = l0->width, h = l0->height;
        float tu[SL_IRRADIANCE_SPAN], tv[SL_IRRADIANCE_SPAN];
        for (int i0 = 0; i0 < count; i0 += SL_IRRADIANCE_SPAN) {
            const int m = count - i0 < SL_IRRADIANCE_SPAN ? count - i0 : SL_IRRADIANCE_SPAN;
            /* the uv per layout (a loop each: one loop choosing per lane does not vectorize) */
            if (irr->method == SL_IRRADIANCE_OCT) {
#pragma omp simd
                for (int i = 0; i < m; i++)
                    sl_irradiance_oct_uv_inline(x[i0 + i], y[i0 + i], z[i0 + i], h, &tu[i], &tv[i]);
            } else {
#pragma omp simd
                for (int i = 0; i < m; i++)
                    sl_irradiance_dp_uv_inline(x[i0 + i], y[i0 + i], z[i0 + i], h, &tu[i], &tv[i]);
            }
#pragma omp simd
            for (int i = 0; i < m; i++) {
                vec3 e = sl_texels_bilinear(T, w, h, 0, tu[i], tv[i]);
                er[i0 + i] = clamp_e(e.x);
                eg[i0 + i] = clamp_e(e.y);
                eb[i0 + i] = clamp_e(e.z);
            }
        }
    } else {
        for (int i = 0; i < count; i++) {
            vec3 e = sl_irradiance_eval(irr, vec3(x[i], y[i], z[i]));
            er[i] = e.x;
            eg[i] = e.y;
            eb[i] = e.z;
        }
    }
}

void sl_irradiance_free(sl_irradiance *irr)
{
    if (!irr)
        return;
    sl_env_free(&irr->map);
    memset(irr, 0, sizeof *irr);
}
