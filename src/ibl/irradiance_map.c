/* irradiance_map.c - pole-free irradiance maps (the specification's "missing feature" 2): E(n)
 * stored over a parametrisation of the sphere that has no pole and no seam singularity, built
 * fast enough for a drag and drop (docs/ibl.md, "Pole-free irradiance maps").
 *
 * Layouts (both vertex-centred: texel i of an S-texel side sits at p = 2 i / (S - 1) - 1, so the
 * lookup is uv = (p / 2 + 1/2) (S - 1) / S + 1 / (2 S), and bilinear filtering interpolates
 * between values stored exactly at the grid's points; CLAMP_TO_EDGE on both axes):
 *
 * OCT, octahedral (Praun & Hoppe 2003; Cigolle et al. 2014), an S x S map: p = n.xy / |n|_1,
 *   folded for n.z < 0 to (1 - |p.yx|) sign(p). +Z is the centre texel, -Z the four corners
 *   (all texels), the equator the diamond |p.x| + |p.y| = 1. The fold maps each edge of the
 *   square onto itself mirrored about its midpoint, and the grid is symmetric, so both sides of a
 *   fold read the same edge texels: the lookup is continuous everywhere.
 * DP, dual paraboloid (Heidrich & Seidel 1998; the specification's suggestion), a 2S x S map:
 *   the left half holds n.z >= 0 at p = n.xy / (1 + n.z), the right half n.z < 0 at
 *   p = n.xy / (1 - n.z). Each half covers the square p in [-1, 1]^2; the texels outside the unit
 *   disk hold E of the other hemisphere (the same formula continued), so the bilinear footprint
 *   of any point of the disk is valid and the halves meet at the equator up to interpolation.
 *
 * Build: E at every map texel from the level-0 image as nodes of two kinds.
 *  - Bright texels (a level-0 texel holding more power than SL_IRRADIANCE_BRIGHT_SHARE of an
 *    average node, at most bright_max of them, brightest first): exact ground-truth nodes
 *    (centroid direction, radiance times |integral of w|; ibl_internal.h), summed with
 *    max(0, n . m) like the ground truth.
 *  - Everything else, grouped by the texel grid of one mip level (source_level): per group the
 *    exact first moment S = sum L_t m_t (m_t = integral of w over texel t, in closed form), so
 *    a group wholly above the horizon of n contributes n . S exactly. A group cut by the horizon
 *    is where a point node goes wrong (max(0, n . S) is below the truth by Jensen's inequality,
 *    by an amount of order the group's power times its angular size). Here the clamp is
 *    smoothed: the group's light, seen along n, is taken as a box of the same variance, whose
 *    half-width a follows from the group's own spread: 1 - |S| / sum L_t |w_t| is the mean
 *    squared angular distance from the centroid over 2, i.e. the variance along one direction,
 *    so a = sqrt(3 (1 - rho)). The ramp max(0, e) averaged over [e - a, e + a] is
 *    (e + a)^2 / (4 a) in between and exact outside. This is data driven: a group whose power
 *    sits in one small spot gets a small a, a uniform one the size of the group. Per channel the
 *    group adds w_c ramp(e) + beta (n . S_c - w_c e), e = n . S^ (S of the luminance), w_c =
 *    S^ . S_c, beta = clamp((e + a) / 2a, 0, 1): exactly n . S_c above the horizon whatever the
 *    colours inside the group (a sun and a blue sky in one group have centroids apart), 0 below
 *    it, the smoothed clamp across.
 * Everything is accumulated in double per group; the sums per map texel are float, one sequential
 * loop per texel (OpenMP over texels), so the map does not depend on the thread count. */
#include "../core/threads.h"
#include "ibl_internal.h"
#include "irradiance_uv.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Rec. 709 luminance, as the env lights use to rank texels. */
static double luma(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

/* ---- layouts: direction -> uv (float, the lookup) and grid point -> direction (double, the build) ---- */

vec2 sl_irradiance_oct_uv(vec3 n, int size)
{
    vec2 t;
    sl_irradiance_oct_uv_inline(n.x, n.y, n.z, size, &t.x, &t.y);
    return t;
}

vec2 sl_irradiance_dp_uv(vec3 n, int size)
{
    vec2 t;
    sl_irradiance_dp_uv_inline(n.x, n.y, n.z, size, &t.x, &t.y);
    return t;
}

static void oct_dir(double px, double py, double d[3])
{
    double z = 1.0 - fabs(px) - fabs(py);
    if (z < 0.0) {
        double fx = (1.0 - fabs(py)) * (px >= 0.0 ? 1.0 : -1.0);
        double fy = (1.0 - fabs(px)) * (py >= 0.0 ? 1.0 : -1.0);
        px = fx;
        py = fy;
    }
    double len = sqrt(px * px + py * py + z * z);
    d[0] = px / len;
    d[1] = py / len;
    d[2] = z / len;
}

static void dp_dir(double px, double py, int back, double d[3])
{
    double r2 = px * px + py * py;
    d[0] = 2.0 * px / (1.0 + r2);
    d[1] = 2.0 * py / (1.0 + r2);
    d[2] = (back ? -1.0 : 1.0) * (1.0 - r2) / (1.0 + r2);
}

/* Map texel k (row-major) of a layout -> the direction E is stored for. */
static void texel_dir(sl_irradiance_method m, int size, long k, double d[3])
{
    int w = m == SL_IRRADIANCE_DP ? 2 * size : size;
    int i = (int)(k % w), j = (int)(k / w);
    int back = i >= size;
    i -= back ? size : 0;
    double px = 2.0 * i / (size - 1) - 1.0, py = 2.0 * j / (size - 1) - 1.0;
    if (m == SL_IRRADIANCE_DP)
        dp_dir(px, py, back, d);
    else
        oct_dir(px, py, d);
}

/* ---- nodes ---- */

typedef struct {
    size_t count;
    float *x, *y, *z, *r, *g, *b; /* unit direction; rgb weight */
    float *a, *inv4a;             /* box half-width (soft nodes only) */
    float *s[9];                  /* soft nodes: the first moment S of r, g, b (x, y, z each) */
    float *block;
} nodes;

static bool nodes_alloc(nodes *n, size_t count, int arrays)
{
    memset(n, 0, sizeof *n);
    n->block = malloc((count ? count : 1) * (size_t)arrays * sizeof(float));
    if (!n->block)
        return false;
    float **p[17] = {&n->x,    &n->y,    &n->z,    &n->r,    &n->g,    &n->b,    &n->a,    &n->inv4a, &n->s[0],
                     &n->s[1], &n->s[2], &n->s[3], &n->s[4], &n->s[5], &n->s[6], &n->s[7], &n->s[8]};
    for (int k = 0; k < arrays; k++)
        *p[k] = n->block + (size_t)k * count;
    n->count = count;
    return true;
}

typedef struct {
    double power;
    long index;
} candidate;

static int by_power_desc(const void *pa, const void *pb)
{
    const candidate *a = pa, *b = pb;
    if (a->power != b->power)
        return a->power > b->power ? -1 : 1;
    return a->index < b->index ? -1 : a->index > b->index;
}

/* Per-row and per-column factors of level 0 (ibl_internal.h). */
typedef struct {
    int w, h;
    double dphi;
    double *cc, *cs; /* column: integral of cos(phi), sin(phi) */
    double *rs, *rz, *rdz;  /* row: integral of sqrt(1 - z^2), z, 1 */
} grid;

static void grid_free(grid *g) { free(g->cc); }

static bool grid_init(grid *g, int w, int h)
{
    g->w = w;
    g->h = h;
    g->cc = malloc(((size_t)w * 2 + (size_t)h * 3) * sizeof(double));
    if (!g->cc)
        return false;
    g->cs = g->cc + w;
    g->rs = g->cs + w;
    g->rz = g->rs + h;
    g->rdz = g->rz + h;
    for (int i = 0; i < w; i++) {
        ibl_col_moments m;
        sl_ibl_col_moments_at(w, i, &m);
        g->cc[i] = m.c;
        g->cs[i] = m.s;
        g->dphi = m.dphi;
    }
    for (int j = 0; j < h; j++) {
        ibl_row_moments m;
        sl_ibl_row_moments_at(h, j, &m);
        g->rs[j] = m.s;
        g->rz[j] = m.z;
        g->rdz[j] = m.dz;
    }
    return true;
}

/* The bright texels: power Y(L) * solid angle above `threshold`, at most `max`, brightest first
 * (ties by index). Marks them in `taken`. */
static bool pick_bright(const sl_env_level *l0, const grid *gd, double threshold, int max, unsigned char *taken,
                        nodes *out)
{
    size_t cap = 1024, count = 0;
    candidate *c = malloc(cap * sizeof *c);
    if (!c)
        return false;
    for (int j = 0; j < gd->h; j++) {
        double omega = gd->rdz[j] * gd->dphi;
        const vec3 *row = l0->texels + (size_t)j * (size_t)gd->w;
        for (int i = 0; i < gd->w; i++) {
            double p = luma((double)row[i].x, (double)row[i].y, (double)row[i].z) * omega;
            if (!(p > threshold))
                continue;
            if (count == cap) {
                candidate *grown = realloc(c, 2 * cap * sizeof *c);
                if (!grown) {
                    free(c);
                    return false;
                }
                c = grown;
                cap *= 2;
            }
            c[count++] = (candidate){p, (long)j * gd->w + i};
        }
    }
    if (count > (size_t)max) {
        qsort(c, count, sizeof *c, by_power_desc);
        count = (size_t)max;
    }
    if (!nodes_alloc(out, count, 6)) {
        free(c);
        return false;
    }
    for (size_t k = 0; k < count; k++) {
        int i = (int)(c[k].index % gd->w), j = (int)(c[k].index / gd->w);
        taken[c[k].index] = 1;
        double m[3] = {gd->rs[j] * gd->cc[i], gd->rs[j] * gd->cs[i], gd->rz[j] * gd->dphi};
        double len = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        vec3 L = l0->texels[c[k].index];
        out->x[k] = (float)(m[0] / len);
        out->y[k] = (float)(m[1] / len);
        out->z[k] = (float)(m[2] / len);
        out->r[k] = (float)((double)L.x * len);
        out->g[k] = (float)((double)L.y * len);
        out->b[k] = (float)((double)L.z * len);
    }
    free(c);
    return true;
}

/* The groups: level-0 texels (less the taken ones) grouped by a cw x ch grid. */
static bool build_groups(const sl_env_level *l0, const grid *gd, int cw, int ch, const unsigned char *taken,
                         nodes *out, int threads)
{
    int w = gd->w, h = gd->h;
    size_t count = (size_t)cw * (size_t)ch;
    /* per group: S for r, g, b (3 x 3), and sum Y omega */
    double *acc = calloc(count * 10, sizeof(double));
    int *col_group = malloc((size_t)w * sizeof(int));
    bool ok = acc && col_group && nodes_alloc(out, count, 17);
    if (!ok) {
        free(acc);
        free(col_group);
        return false;
    }
    for (int i = 0; i < w; i++)
        col_group[i] = (int)((long)i * cw / w);
    bool failed = false;
#pragma omp parallel num_threads(sl_threads(threads))
    {
        double *rowacc = malloc((size_t)cw * 10 * sizeof(double));
        if (!rowacc) {
#pragma omp atomic write
            failed = true;
        }
#pragma omp for schedule(static)
        for (int J = 0; J < ch; J++) {
            if (!rowacc)
                continue;
            int j0 = (int)(((long)J * h + ch - 1) / ch), j1 = (int)(((long)(J + 1) * h + ch - 1) / ch);
            for (int j = j0; j < j1 && j < h; j++) {
                memset(rowacc, 0, (size_t)cw * 10 * sizeof(double));
                const vec3 *row = l0->texels + (size_t)j * (size_t)w;
                const unsigned char *tk = taken + (size_t)j * (size_t)w;
                for (int i = 0; i < w; i++) {
                    if (tk[i])
                        continue;
                    double *a = rowacc + (size_t)col_group[i] * 10;
                    double L[3] = {(double)row[i].x, (double)row[i].y, (double)row[i].z};
                    for (int c = 0; c < 3; c++) {
                        a[3 * c + 0] += L[c] * gd->cc[i];
                        a[3 * c + 1] += L[c] * gd->cs[i];
                        a[3 * c + 2] += L[c];
                    }
                    a[9] += luma(L[0], L[1], L[2]);
                }
                double s = gd->rs[j], zd = gd->rz[j] * gd->dphi, om = gd->rdz[j] * gd->dphi;
                for (int I = 0; I < cw; I++) {
                    const double *a = rowacc + (size_t)I * 10;
                    double *g = acc + ((size_t)J * cw + I) * 10;
                    for (int c = 0; c < 3; c++) {
                        g[3 * c + 0] += s * a[3 * c + 0];
                        g[3 * c + 1] += s * a[3 * c + 1];
                        g[3 * c + 2] += zd * a[3 * c + 2];
                    }
                    g[9] += om * a[9];
                }
            }
        }
        free(rowacc);
    }
    free(col_group);
    if (failed) {
        free(acc);
        free(out->block);
        return false;
    }
    for (size_t k = 0; k < count; k++) {
        const double *g = acc + k * 10;
        double S[3];
        for (int d = 0; d < 3; d++)
            S[d] = luma(g[d], g[3 + d], g[6 + d]);
        double len = sqrt(S[0] * S[0] + S[1] * S[1] + S[2] * S[2]);
        double dir[3] = {0.0, 0.0, 1.0}, wgt[3] = {0.0, 0.0, 0.0}, a = 1e-4;
        if (len > 0.0 && g[9] > 0.0) {
            for (int d = 0; d < 3; d++)
                dir[d] = S[d] / len;
            for (int c = 0; c < 3; c++) {
                double v = dir[0] * g[3 * c] + dir[1] * g[3 * c + 1] + dir[2] * g[3 * c + 2];
                wgt[c] = v > 0.0 ? v : 0.0;
            }
            double rho = len / g[9];
            double var = rho < 1.0 ? 1.0 - rho : 0.0;
            a = sqrt(3.0 * var);
            a = a > 1e-4 ? a : 1e-4;
        }
        out->x[k] = (float)dir[0];
        out->y[k] = (float)dir[1];
        out->z[k] = (float)dir[2];
        out->r[k] = (float)wgt[0];
        out->g[k] = (float)wgt[1];
        out->b[k] = (float)wgt[2];
        out->a[k] = (float)a;
        out->inv4a[k] = (float)(0.25 / a);
        for (int c = 0; c < 9; c++)
            out->s[c][k] = (float)g[c];
    }
    free(acc);
    return true;
}

/* E at one direction from both kinds of nodes (float; sequential per direction). */
static vec3 eval_nodes(const nodes *soft, const nodes *hard, float nx, float ny, float nz)
{
    float er = 0.0f, eg = 0.0f, eb = 0.0f;
    const float *restrict x = soft->x, *restrict y = soft->y, *restrict z = soft->z;
    const float *restrict r = soft->r, *restrict g = soft->g, *restrict b = soft->b;
    const float *restrict a = soft->a, *restrict q = soft->inv4a;
    const float *restrict s0 = soft->s[0], *restrict s1 = soft->s[1], *restrict s2 = soft->s[2];
    const float *restrict s3 = soft->s[3], *restrict s4 = soft->s[4], *restrict s5 = soft->s[5];
    const float *restrict s6 = soft->s[6], *restrict s7 = soft->s[7], *restrict s8 = soft->s[8];
#pragma omp simd reduction(+ : er, eg, eb)
    for (size_t k = 0; k < soft->count; k++) {
        /* w ramp(e) (the smoothed clamp) plus beta (n . S - w e): beta = 1 above (n . S, exact
         * per channel), 0 below (nothing: a group's colour offsets must not leak below its
         * horizon), linear across, so the sum is continuous in n */
        float e = nx * x[k] + ny * y[k] + nz * z[k];
        float t = e + a[k];
        t = t > 0.0f ? t : 0.0f;
        t = t < 2.0f * a[k] ? t : 2.0f * a[k];
        float above = e - a[k];
        above = above > 0.0f ? above : 0.0f;
        float ramp = t * t * q[k] + above;
        float beta = 2.0f * t * q[k];
        er += ramp * r[k] + beta * (nx * s0[k] + ny * s1[k] + nz * s2[k] - e * r[k]);
        eg += ramp * g[k] + beta * (nx * s3[k] + ny * s4[k] + nz * s5[k] - e * g[k]);
        eb += ramp * b[k] + beta * (nx * s6[k] + ny * s7[k] + nz * s8[k] - e * b[k]);
    }
    const float *restrict hx = hard->x, *restrict hy = hard->y, *restrict hz = hard->z;
    const float *restrict hr = hard->r, *restrict hg = hard->g, *restrict hb = hard->b;
#pragma omp simd reduction(+ : er, eg, eb)
    for (size_t k = 0; k < hard->count; k++) {
        float c = nx * hx[k] + ny * hy[k] + nz * hz[k];
        c = c > 0.0f ? c : 0.0f;
        er += c * hr[k];
        eg += c * hg[k];
        eb += c * hb[k];
    }
    return vec3(er, eg, eb);
}

int sl_irradiance_map_default_source_level(const sl_env *env)
{
    /* The finest level with at most SL_IRRADIANCE_MAP_GROUPS texels (docs/ibl.md has the error
     * of each choice). */
    int level = 0;
    while (level + 1 < env->level_count &&
           (long)env->levels[level].width * env->levels[level].height > SL_IRRADIANCE_MAP_GROUPS)
        level++;
    return level;
}

bool sl_irradiance_map(sl_irradiance *irr, const sl_env *env, const sl_irradiance_map_desc *desc, sl_error *err)
{
    memset(irr, 0, sizeof *irr);
    sl_irradiance_map_desc d = desc ? *desc : (sl_irradiance_map_desc){0};
    if (d.method == SL_IRRADIANCE_SH9)
        d.method = SL_IRRADIANCE_OCT;
    if (!d.size)
        d.size = SL_IRRADIANCE_MAP_SIZE;
    if (!d.bright_max)
        d.bright_max = SL_IRRADIANCE_BRIGHT_MAX;
    if (!env || env->level_count < 1)
        return sl_fail(err, SL_ERR_RANGE, "irradiance map: the environment has no levels");
    if (d.method != SL_IRRADIANCE_OCT && d.method != SL_IRRADIANCE_DP)
        return sl_fail(err, SL_ERR_RANGE, "irradiance map: method %d is not a pole-free layout", (int)d.method);
    if (d.size < 3 || d.size > 1025 || d.size % 2 == 0)
        return sl_fail(err, SL_ERR_RANGE, "irradiance map: size %d, must be odd, 3 .. 1025", d.size);
    if (d.bright_max < -1 || d.bright_max > (1 << 20))
        return sl_fail(err, SL_ERR_RANGE, "irradiance map: bright_max %d, must be -1 .. 2^20", d.bright_max);
    int level = d.source_level ? d.source_level : sl_irradiance_map_default_source_level(env);
    if (d.source_level < 0 || level >= env->level_count)
        return sl_fail(err, SL_ERR_RANGE, "irradiance map: source level %d, the environment has 0 .. %d", level,
                       env->level_count - 1);
    if (d.exact)
        level = 0;

    const sl_env_level *l0 = &env->levels[0];
    int mw = d.method == SL_IRRADIANCE_DP ? 2 * d.size : d.size, mh = d.size;
    vec3 *texels = malloc((size_t)mw * (size_t)mh * sizeof *texels);
    unsigned char *taken = calloc((size_t)l0->width * (size_t)l0->height, 1);
    grid gd = {0};
    nodes soft = {0}, hard = {0};
    bool ok = texels && taken && grid_init(&gd, l0->width, l0->height);
    if (ok && d.exact) {
        /* every level-0 texel a ground-truth node: the reference the fast build is measured by */
        ok = pick_bright(l0, &gd, -1.0, INT32_MAX, taken, &hard) && nodes_alloc(&soft, 0, 17);
    } else if (ok) {
        int cw = env->levels[level].width, ch = env->levels[level].height;
        double total = 0.0;
        for (int j = 0; j < l0->height; j++) {
            double row = 0.0;
            for (int i = 0; i < l0->width; i++) {
                vec3 L = l0->texels[(size_t)j * (size_t)l0->width + i];
                row += luma((double)L.x, (double)L.y, (double)L.z);
            }
            total += row * gd.rdz[j] * gd.dphi;
        }
        double threshold = SL_IRRADIANCE_BRIGHT_SHARE * total / ((double)cw * (double)ch);
        if (d.bright_max > 0 && level > 0)
            ok = pick_bright(l0, &gd, threshold, d.bright_max, taken, &hard);
        else
            ok = nodes_alloc(&hard, 0, 6);
        ok = ok && build_groups(l0, &gd, cw, ch, taken, &soft, d.threads);
    }
    free(taken);
    grid_free(&gd);
    if (!ok) {
        free(texels);
        free(soft.block);
        free(hard.block);
        return sl_fail(err, SL_ERR_MEMORY, "irradiance map: out of memory");
    }
    long total = (long)mw * (long)mh;
#pragma omp parallel for schedule(dynamic, 16) num_threads(sl_threads(d.threads))
    for (long k = 0; k < total; k++) {
        double n[3];
        texel_dir(d.method, d.size, k, n);
        texels[k] = eval_nodes(&soft, &hard, (float)n[0], (float)n[1], (float)n[2]);
    }
    irr->method = d.method;
    irr->map.level_count = 1;
    irr->map.levels[0] = (sl_env_level){.width = mw, .height = mh, .texels = texels};
    irr->bright_nodes = (int)hard.count;
    irr->group_nodes = (int)soft.count;
    free(soft.block);
    free(hard.block);
    return true;
}
