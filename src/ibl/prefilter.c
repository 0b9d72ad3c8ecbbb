/* prefilter.c - the environment convolved with a reflection lobe, one lobe width per mip level:
 * the first half of the split-sum approximation (Karis 2013, "Real Shading in Unreal Engine 4";
 * --estimator splitsum, docs/lighting.md "Split sum") and the control variate's known integral
 * (--estimator cv, docs/lighting.md "Control variate"). The second half, the BRDF's scale and bias
 * over (N.V, width), is the lighting stage's (src/shading/splitsum_lut.c): it owns the BRDF.
 *
 * Level k of the chain (lat-long, the sizes of the environment's own mip chain, so GL's
 * textureLod reads it as a mip chain) holds, at the direction d of each texel centre, the mean of
 * the environment under the lobe of width r_k = k / (levels - 1) at N = V = d:
 *
 *     P_k(d) = integral of L(w) k(w) dw,   k = D(h) G'(w.d) (w.d) / (4 Z)   (Karis' assumption)
 *
 * the microfacet estimator's density of w at normal view, D (N.H) / (4 V.H) = D / 4, times its
 * weight there, G' (N.w) (G' = G / ((N.w)(N.V)) of brdf.h), normalised (ibl.h
 * sl_prefilter_kernel). So P at normal view is exactly the BRDF-weighted mean the true integral
 * takes (F aside). Karis weights by N.w alone, which drops G': for narrow lobes G' (N.w) is
 * nearly constant, but the wide ones' G' doubles towards their edge (Phong's 1/(L.H)^2, Smith's
 * 1/(N.w) part), and without it their chain is too narrow: on the default scene's alpha 1 spheres
 * the centre was 15% too bright. The lobes are brdf.h's, written here again because ibl sits
 * left of shading: GGX with a = max(r^2, 1e-4) (the width is the perceptual roughness), and the
 * Phong set with the exponent of equal peak, alpha = 2 / a^2 - 2 (brdf.h,
 * sl_ggx_phong_equivalent). Level 0 (r = 0, a mirror) is the environment itself.
 *
 * Two ways to a level:
 *  - The narrow levels (r < SL_PREFILTER_EXACT_WIDTH: level 1 of the default six) are sampled:
 *    H drawn from D(H) (N.H), w = reflect(-d, H), each sample read at the level of its own
 *    footprint (filtered importance sampling: Colbert and Krivanek, GPU Gems 3 ch. 20.4, the
 *    --lod pdf rule with the lat-long texel's sin(theta) in its solid angle), 64 samples at
 *    level 1, doubling per level up to SL_HAMMERSLEY_MAX. A lobe a few texels wide would need a
 *    sum over a million texels for each of the level's 131 072 texels.
 *  - The wide levels are exact (exact_level): a sum of k over every texel of a source level fine
 *    enough for the lobe, each texel one node at its centroid weighted by its solid angle, the
 *    ground truth's quadrature, normalised by the same sum of k alone. Sampled as level 1 is,
 *    they are 1-5% off that integral on 256x128 maps (the coarse source levels the wide lobes'
 *    samples read), too far for a control variate, whose known integral must be the integral. */
#include "../core/threads.h"
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "ibl.h"
#include "ibl_internal.h"
#include "texture_lod.h"

#define PI_F 3.14159265358979f
#define MIN_A 1e-4f    /* brdf.h SL_GGX_MIN_A */
#define MAX_ALPHA 1e7f /* the lighting shader's MAX_ALPHA */

float sl_prefilter_width(int level, int levels)
{
    return levels > 1 ? (float)level / (float)(levels - 1) : 0.0f;
}

int sl_prefilter_first_exact(int levels)
{
    for (int k = 1; k < levels; k++)
        if (sl_prefilter_width(k, levels) >= SL_PREFILTER_EXACT_WIDTH)
            return k;
    return levels;
}

/* Z = integral of D(h) G'(c) c / 4 over w, at N = V = d. With dw = 4 (d.h) dh it is the mean of
 * G'(c) c under the density D(h) (d.h) of h, whose inverse CDF is the samples' (lobe_samples):
 * a midpoint rule over xi in double, 2^16 nodes (the integrand is smooth in xi). */
sl_prefilter_kernel sl_prefilter_kernel_of(int level, int levels, bool ggx, bool g_one)
{
    float r = sl_prefilter_width(level, levels);
    float a = fmaxf(r * r, MIN_A);
    sl_prefilter_kernel k = {.ggx = ggx, .g_one = g_one, .a2 = a * a, .alpha = fminf(2.0f / (a * a) - 2.0f, MAX_ALPHA),
                             .inv_norm = 1.0f};
    enum { NODES = 1 << 16 };
    double sum = 0.0;
    for (int i = 0; i < NODES; i++) {
        double xi = (i + 0.5) / NODES;
        double a2 = (double)k.a2, alpha = (double)k.alpha;
        double nh2 = ggx ? (1.0 - xi) / ((1.0 - xi) + a2 * xi) : pow(xi, 2.0 / (alpha + 2.0));
        double c = 2.0 * nh2 - 1.0;
        if (c <= 0.0)
            continue;
        double G = ggx ? 2.0 / (c + sqrt(c * c * (1.0 - a2) + a2)) : g_one ? 1.0 : 1.0 / fmax(nh2, 1e-6);
        sum += G * c;
    }
    k.inv_norm = sum > 0.0 ? (float)(NODES / sum) : 0.0f;
    return k;
}

int sl_prefilter_samples(int level, int samples)
{
    long n = samples;
    for (int k = 1; k < level && n < SL_HAMMERSLEY_MAX; k++)
        n *= 2;
    return n < SL_HAMMERSLEY_MAX ? (int)n : SL_HAMMERSLEY_MAX;
}

/* One sample of a level's lobe in the frame where R = +Z: w about +Z, its cosine, and the
 * part of its source lod that does not depend on where w points. */
typedef struct {
    float wx, wy, wz;
    float weight; /* G' (N.w) at V = N: the microfacet estimator's weight */
    float lod0;
} lobe_sample;

/* The samples of width r: H from D(H) (N.H) by the Hammersley pairs (phi = 2 pi xi1,
 * cos(theta_H) from xi2), w = reflect(-Z, H), kept when w.Z > 0; their density
 * p(w) = D (N.H) / (4 V.H) = D / 4 since V = N. G' at V = N (N.V = 1, V.H = N.H = c):
 * GGX's 2 / ((N.w) + sqrt((N.w)^2 (1 - a^2) + a^2)) (brdf.h sl_ggx_G), the Phong set's
 * 1 / max(c, 1e-3)^2 (sl_brdf_G, --g inv-lh2) or 1 (g_one). Returns how many were kept. */
static int lobe_samples(const sl_hammersley *set, float r, bool ggx, bool g_one, int src_w, int src_h,
                        lobe_sample *out)
{
    float a = fmaxf(r * r, MIN_A), a2 = a * a;
    float alpha = fminf(2.0f / a2 - 2.0f, MAX_ALPHA);
    /* Omega_p: a level-0 texel's solid angle over sin(theta), 2 pi^2 / (W H) */
    float omega_p = 2.0f * PI_F * PI_F / ((float)src_w * (float)src_h);
    int n = 0;
    for (int k = 0; k < set->n; k++) {
        float xi1 = set->points[k].x, xi2 = set->points[k].y;
        float c, D;
        if (ggx) {
            c = sqrtf((1.0f - xi2) / ((1.0f - xi2) + a2 * xi2));
            float t = (1.0f - c * c) + c * c * a2;
            D = a2 / (PI_F * t * t);
        } else {
            c = powf(xi2, 1.0f / (alpha + 2.0f));
            D = (alpha + 2.0f) / (2.0f * PI_F) * powf(fmaxf(c, 1e-30f), alpha);
        }
        float s = sqrtf(fmaxf(1.0f - c * c, 0.0f));
        float phi = 2.0f * PI_F * xi1;
        float hx = s * cosf(phi), hy = s * sinf(phi);
        lobe_sample ls = {2.0f * c * hx, 2.0f * c * hy, 2.0f * c * c - 1.0f, 0.0f, 0.0f};
        if (ls.wz <= 0.0f)
            continue;
        float G = 1.0f;
        if (ggx)
            G = 2.0f / (ls.wz + sqrtf(ls.wz * ls.wz * (1.0f - a2) + a2));
        else if (!g_one)
            G = 1.0f / (fmaxf(c, 1e-3f) * fmaxf(c, 1e-3f));
        ls.weight = G * ls.wz;
        float pdf = D / 4.0f;
        /* pdf rule: 1/2 log2(Omega_s / Omega_p), Omega_s = 1 / (n p(w)); sin(theta) added per texel */
        ls.lod0 = 0.5f * log2f(1.0f / ((float)set->n * fmaxf(pdf, 1e-30f) * omega_p));
        out[n++] = ls;
    }
    return n;
}

/* Level `dst` of the chain: every texel the lobe-weighted mean of the source around its
 * direction. The lat-long map makes the work per row, not per texel: the texels of a row differ
 * by a rotation about +Z, which moves every sample by the same azimuth, i.e. adds i / W to its u
 * and leaves its v, lod and weight alone. So a row draws its samples once, for texel 0, and each
 * texel is then only the fetches, shifted. Rows in parallel; each texel is independent of the
 * others, so the result does not depend on the thread count. `scratch`: 4 n floats per thread. */
static void filter_level(const sl_env *src, sl_env_level *dst, const lobe_sample *ls, int n, float *scratch,
                         int threads)
{
    const float max_lod = (float)(src->level_count - 1);
    const float sin_min = sinf(PI_F / (2.0f * (float)src->levels[0].height));
    const float du = 1.0f / (float)dst->width;
#pragma omp parallel for schedule(dynamic, 2) num_threads(threads)
    for (int j = 0; j < dst->height; j++) {
        float *su = scratch + (size_t)omp_get_thread_num() * 4 * (size_t)n;
        float *sv = su + n, *slod = sv + n, *sw = slod + n;
        vec3 R = sl_uv_to_dir(vec2(0.5f * du, ((float)j + 0.5f) / (float)dst->height));
        vec3 axis = R.z * R.z < 0.999f ? vec3(0.0f, 0.0f, 1.0f) : vec3(1.0f, 0.0f, 0.0f);
        vec3 A = normalize(cross(axis, R));
        vec3 B = cross(R, A);
        float wsum = 0.0f;
        for (int s = 0; s < n; s++) {
            vec3 w = add(add(scale(A, ls[s].wx), scale(B, ls[s].wy)), scale(R, ls[s].wz));
            float sin_t = sqrtf(fmaxf(1.0f - w.z * w.z, 0.0f));
            float lod = ls[s].lod0 - 0.5f * log2f(fmaxf(sin_t, sin_min));
            vec2 t = sl_dir_to_uv(w);
            su[s] = t.x;
            sv[s] = t.y;
            slod[s] = fminf(fmaxf(lod, 0.0f), max_lod);
            sw[s] = ls[s].weight;
            wsum += ls[s].weight;
        }
        float norm = wsum > 0.0f ? 1.0f / wsum : 0.0f;
        for (int i = 0; i < dst->width; i++) {
            float shift = (float)i * du;
            vec3 sum = vec3s(0.0f);
            for (int s = 0; s < n; s++) {
                float u = su[s] + shift;
                u = u >= 1.0f ? u - 1.0f : u; /* both in [0, 1): REPEAT */
                sum = add(sum, scale(sl_texture_lod_clamped(src, u, sv[s], slod[s]), sw[s]));
            }
            dst->texels[(size_t)j * (size_t)dst->width + (size_t)i] = scale(sum, norm);
        }
    }
}

/* Exact levels. The texel at direction d holds sum_t k(w_t . d) L_t O_t / sum_t k(w_t . d) O_t
 * over every texel t of a source level as wide as the sum (w_t its centroid, O_t its solid
 * angle): the quadrature the ground truth takes of level 0, of the kernel the control variate
 * evaluates, normalised by its own sum so that a constant environment is kept to the bit's
 * worth. A source texel of such a level is at most a seventh of the lobe's half width (0.0245
 * rad at 256 texels a row, against 0.18 for r = 0.4), so one node a texel stands for the texel.
 * As filter_level, the rows make the work small: source texel i' of row j' seen from the
 * destination texel i of row j depends on i' - i alone, so a row pair's weights are computed
 * once (W kernel values) and each texel of the row is a dot product with the source row, stored
 * three times over so that the shifted index needs no wrap. Rows in parallel, each one thread's:
 * the result does not depend on the thread count. */
typedef struct {
    float x, y, z; /* the texel's centroid direction */
    float solid_angle;
} latlong_node;

/* The centroid and solid angle of texel (i, j) of a w x h lat-long level, from its row's and
 * column's moments (texel.c, the ground truth's): the centroid is the normalised integral of the
 * direction over the texel. */
static latlong_node latlong_node_of(const ibl_row_moments *rm, const ibl_col_moments *cm)
{
    double x = rm->s * cm->c, y = rm->s * cm->s, z = rm->z * cm->dphi;
    double len = sqrt(x * x + y * y + z * z);
    double inv = len > 0.0 ? 1.0 / len : 0.0;
    return (latlong_node){(float)(x * inv), (float)(y * inv), (float)(z * inv), (float)(rm->dz * cm->dphi)};
}

/* Sum level `src` (w x h) with kernel k into `out`, a grid of (w / step) x (h / step) texels
 * (step divides both): the sum at each of its texel centres. From texel i0 of an output row to
 * texel i is a turn of (i - i0) step source texels. */
static bool exact_sum(const sl_env_level *src, const sl_prefilter_kernel *k, int step, vec3 *out, int threads)
{
    const int w = src->width, h = src->height, ow = w / step, oh = h / step;
    latlong_node *nodes = malloc((size_t)w * (size_t)h * sizeof *nodes);
    float *rows = malloc((size_t)h * 9 * (size_t)w * sizeof *rows); /* planar r, g, b, each row thrice */
    float *weights = malloc((size_t)threads * (size_t)w * sizeof *weights);
    if (!nodes || !rows || !weights) {
        free(nodes);
        free(rows);
        free(weights);
        return false;
    }
    for (int j = 0; j < h; j++) {
        ibl_row_moments rm;
        sl_ibl_row_moments_at(h, j, &rm);
        for (int i = 0; i < w; i++) {
            ibl_col_moments cm;
            sl_ibl_col_moments_at(w, i, &cm);
            nodes[(size_t)j * w + i] = latlong_node_of(&rm, &cm);
            vec3 t = src->texels[(size_t)j * w + i];
            float *row = rows + (size_t)j * 9 * w;
            row[i] = row[w + i] = row[2 * w + i] = t.x;
            row[3 * w + i] = row[4 * w + i] = row[5 * w + i] = t.y;
            row[6 * w + i] = row[7 * w + i] = row[8 * w + i] = t.z;
        }
    }
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int j = 0; j < oh; j++) {
        float *wt = weights + (size_t)omp_get_thread_num() * w;
        /* the weights are for texel i0 of row j, mid-row, so a lobe's nonzero range does not wrap */
        const int i0 = ow / 2;
        vec3 dir = sl_uv_to_dir(vec2(((float)i0 + 0.5f) / (float)ow, ((float)j + 0.5f) / (float)oh));
        double norm = 0.0;
        vec3 *dst = out + (size_t)j * ow;
        for (int i = 0; i < ow; i++)
            dst[i] = vec3s(0.0f);
        for (int jj = 0; jj < h; jj++) {
            const latlong_node *row_nodes = &nodes[(size_t)jj * w];
            int first = w, last = -1;
            double row_norm = 0.0;
            for (int q = 0; q < w; q++) {
                const latlong_node *n = &row_nodes[q];
                float c = n->x * dir.x + n->y * dir.y + n->z * dir.z;
                wt[q] = sl_prefilter_kernel_eval(k, c) * n->solid_angle;
                if (wt[q] > 0.0f) {
                    first = q < first ? q : first;
                    last = q;
                }
                row_norm += (double)wt[q];
            }
            if (last < 0)
                continue;
            norm += row_norm;
            const float *row = rows + (size_t)jj * 9 * w;
            for (int i = 0; i < ow; i++) {
                float r = 0.0f, g = 0.0f, b = 0.0f;
                /* texel q + (i - i0) step; the turn is within a row's width either way */
                const float *R = row + w + (i - i0) * step, *G = R + 3 * w, *B = R + 6 * w;
#pragma omp simd reduction(+ : r, g, b)
                for (int q = first; q <= last; q++) {
                    r += wt[q] * R[q];
                    g += wt[q] * G[q];
                    b += wt[q] * B[q];
                }
                dst[i] = add(dst[i], vec3(r, g, b));
            }
        }
        float inv = norm > 0.0 ? (float)(1.0 / norm) : 0.0f;
        for (int i = 0; i < ow; i++)
            dst[i] = scale(dst[i], inv);
    }
    free(nodes);
    free(rows);
    free(weights);
    return true;
}

/* Exact level `level` of the chain into dst. The sum runs over one source level, the coarsest
 * whose row holds at least 39 / a texels (eight a half width, which is about 1.3 a at N = V), at
 * least 128 and at most SL_PREFILTER_EXACT_MAX_WIDTH (or level 0, when it is narrower), to the
 * centres of a grid coarser by `step`, the largest power of two that leaves a quarter of a half
 * width a texel (19 / a texels a row, at least 64) or dst's own texels, whichever is coarser: the
 * summed lobe is smooth at that scale, and the sum's cost is the source's texels times the
 * grid's. dst is then that grid read with the Catmull-Rom filter at its own texel centres (a
 * coarse level's texel is the lobe's value at its centre, not an average; the filter passes
 * through the grid's texels with an error of third order). */
static bool exact_level(const sl_env *src, sl_env_level *dst, const sl_prefilter_kernel *k, int threads)
{
    float a = sqrtf(k->a2 > 0.0f ? k->a2 : 0.0f);
    if (!k->ggx) /* the Phong set: the width of equal peak, a^2 = 2 / (alpha + 2) */
        a = sqrtf(2.0f / (k->alpha + 2.0f));
    a = fmaxf(a, 1e-3f);
    float want = fminf(fmaxf(39.0f / a, 128.0f), (float)SL_PREFILTER_EXACT_MAX_WIDTH);
    int m = 0;
    while (m + 1 < src->level_count && (float)src->levels[m + 1].width >= want)
        m++;
    const sl_env_level *s = &src->levels[m];
    /* the grid: no finer than dst (its texel centres are all a reader sees of a coarse level) */
    float fine = fminf(fmaxf(19.0f / a, 64.0f), (float)dst->width);
    int step = 1;
    while (s->width % (2 * step) == 0 && s->height % (2 * step) == 0 && (float)(s->width / (2 * step)) >= fine)
        step *= 2;
    sl_env_level grid = {s->width / step, s->height / step, NULL};
    if (grid.width == dst->width && grid.height == dst->height)
        return exact_sum(s, k, step, dst->texels, threads);
    grid.texels = malloc((size_t)grid.width * (size_t)grid.height * sizeof *grid.texels);
    if (!grid.texels || !exact_sum(s, k, step, grid.texels, threads)) {
        free(grid.texels);
        return false;
    }
    for (int j = 0; j < dst->height; j++)
        for (int i = 0; i < dst->width; i++)
            dst->texels[(size_t)j * dst->width + i] =
                sl_env_catmull_rom(&grid, ((float)i + 0.5f) / (float)dst->width, ((float)j + 0.5f) / (float)dst->height);
    free(grid.texels);
    return true;
}

bool sl_env_prefilter(sl_env *out, const sl_env *src, const sl_prefilter_desc *desc, sl_error *err)
{
    memset(out, 0, sizeof *out);
    int levels = desc->levels ? desc->levels : SL_PREFILTER_LEVELS;
    int samples = desc->samples ? desc->samples : SL_PREFILTER_SAMPLES;
    int threads = sl_threads(desc->threads);
    if (!src || src->level_count < 1 || (src->layout != SL_ENV_LAYOUT_DEFAULT && src->layout != SL_ENV_LAYOUT_LATLONG))
        return sl_fail(err, SL_ERR_RANGE, "prefilter: needs a lat-long environment chain");
    if (levels < 1 || levels > SL_ENV_MAX_LEVELS)
        return sl_fail(err, SL_ERR_RANGE, "prefilter: %d levels, expected 1..%d", levels, SL_ENV_MAX_LEVELS);
    if (samples < 1 || samples > SL_HAMMERSLEY_MAX)
        return sl_fail(err, SL_ERR_RANGE, "prefilter: %d samples, expected 1..%d", samples, SL_HAMMERSLEY_MAX);
    int most = sl_prefilter_samples(levels - 1, samples);
    lobe_sample *ls = malloc((size_t)most * sizeof *ls);
    float *scratch = malloc((size_t)threads * 4 * (size_t)most * sizeof *scratch);
    if (!ls || !scratch) {
        free(ls);
        free(scratch);
        return sl_fail(err, SL_ERR_MEMORY, "prefilter: no memory for %d samples", most);
    }
    const sl_env_level *l0 = &src->levels[0];
    out->layout = SL_ENV_LAYOUT_LATLONG;
    /* One block for the chain, as sl_env_build makes it: the port and the GL upload read it, and
     * the split-sum fetch of the lighting pass (lighting_splitsum.c) gathers from it with one
     * index per texel where the chain has no compact rows (below). */
    size_t total = 0;
    for (int k = 0; k < levels; k++) {
        /* GL's mip sizes: max(1, floor(size / 2^k)) */
        int w = l0->width >> k, h = l0->height >> k;
        out->levels[k].width = w > 0 ? w : 1;
        out->levels[k].height = h > 0 ? h : 1;
        total += (size_t)out->levels[k].width * (size_t)out->levels[k].height;
    }
    out->block = malloc(total * sizeof(vec3));
    if (!out->block) {
        free(ls);
        free(scratch);
        memset(out, 0, sizeof *out);
        return sl_fail(err, SL_ERR_MEMORY, "prefilter: no memory for the chain (%zu texels)", total);
    }
    out->level_count = levels;
    size_t offset = 0;
    for (int k = 0; k < levels; k++) {
        out->levels[k].texels = out->block + offset;
        offset += (size_t)out->levels[k].width * (size_t)out->levels[k].height;
    }
    for (int k = 0; k < levels; k++) {
        int w = out->levels[k].width, h = out->levels[k].height;
        sl_env_level *dst = &out->levels[k];
        if (k == 0) { /* r = 0: the mirror reads the environment itself */
            memcpy(dst->texels, l0->texels, (size_t)w * (size_t)h * sizeof(vec3));
            continue;
        }
        if (k >= sl_prefilter_first_exact(levels)) {
            sl_prefilter_kernel kernel = sl_prefilter_kernel_of(k, levels, desc->ggx, desc->g_one);
            if (!exact_level(src, dst, &kernel, threads)) {
                free(ls);
                free(scratch);
                sl_env_free(out);
                return sl_fail(err, SL_ERR_MEMORY, "prefilter: no memory for level %d's sum", k);
            }
            continue;
        }
        sl_hammersley set;
        if (!sl_hammersley_build(&set, sl_prefilter_samples(k, samples), err)) {
            free(ls);
            free(scratch);
            sl_env_free(out);
            return false;
        }
        int n = lobe_samples(&set, sl_prefilter_width(k, levels), desc->ggx, desc->g_one, l0->width, l0->height, ls);
        filter_level(src, dst, ls, n, scratch, threads);
    }
    free(ls);
    free(scratch);
    /* the compact rows (ibl.h sl_env.e5, texel_e5.h), as sl_env_build has them: the split-sum
     * fetch (lighting_splitsum.c fetch_chain) reads a bilinear row pair in one 64-bit read, 4
     * gathers a sample where the float pair rows take 12, a third of their bytes (level 0 of a
     * 1024x512 chain: 2.1 MB against 6.3), within 2^-9 of a texel's largest channel
     * (docs/performance.md "Compact texels for the split sum's chains"). No pair rows: nothing
     * else reads a prefiltered chain fast (the port and GL read the block). NULL costs only
     * speed: the fetch then reads the block. */
    out->e5 = sl_ibl_env_build_e5(out, total, &out->e5_emin, threads);
    return true;
}
