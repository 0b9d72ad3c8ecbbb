/* env_oct.c - the environment's mip chain in the octahedral layout, the pole-free option for
 * the specular samples (--env-layout oct; docs/ibl.md "Specular layouts").
 *
 * Why: the lat-long chain has its poles where floors and ceilings reflect (R = +-Z). A lookup
 * there reads row 0 at one azimuth, while the truth averages the whole cap around the pole; on
 * coarser levels that row is one wedge of 2^l columns, not the disc the lobe covers. The
 * octahedral map has no pole and no seam: +Z is the centre of the square, -Z its four corners,
 * and the texel solid angle varies by at most 3 sqrt 3 (about 5.2) across the map.
 *
 * Layout (texture_lod.h sl_oct_uv, the same in shaders/lighting.frag): S x S texels, S a power
 * of two; p = d.xy / |d|_1 for z >= 0, folded to ((1 - |p.y|) sgn p.x, (1 - |p.x|) sgn p.y)
 * below; u = (p.x + 1) / 2 (column), v = (p.y + 1) / 2 (row), texel centres at (i + 1/2) / S.
 * The outer edge folds onto itself ((-1, y) and (-1, -y) are one direction), so a bilinear tap
 * past the edge reads the texel mirrored across it (texture_lod.h sl_oct_texels_bilinear).
 *
 * Level 0: S is the smallest power of two >= the lat-long width (1024x512 -> 1024, at most
 * SL_ENV_OCT_MAX_SIZE): its largest texel (the face centres) is then about the lat-long
 * equator's, so no direction loses resolution. Each texel is the mean of OCT_SUB x OCT_SUB
 * trilinear lookups of the lat-long chain at its sub-texel centres, each at the lat-long level
 * whose texel solid angle matches the sub-texel's (lat-long texel at polar angle theta:
 * (2 pi / W)(pi / H) sin theta, floored at row 0's centre), so a texel averages what it covers
 * rather than point-sampling it.
 *
 * Level k+1 (S / 2^(k+1) on a side): each texel the SOLID-ANGLE-WEIGHTED mean of its 2 x 2
 * children, its solid angle their sum. Level-0 solid angles are exact: a texel splits along
 * the diagonal parallel to the fold in its quadrant into two triangles, each inside one face of
 * the octahedron, where the map is affine, so each is a spherical triangle (Van Oosterom and
 * Strackee's formula). Hence every level holds the same radiant power sum L Omega as level 0
 * (a delta environment keeps its energy per level) and each texel is the mean radiance over
 * the solid angle it covers, the footprint the lighting shader's lod rule assumes (its
 * distortion factor for this layout is Omega_texel / (4 pi / S^2) = |w|_1^3 / pi, lighting.frag
 * mip_level). A constant environment stays constant at every level. */
#include "../core/threads.h"
#include "ibl_internal.h"

#include <stdlib.h>

#include "texture_lod.h"

/* sub-samples per axis and texel of level 0 (measured: docs/ibl.md "Specular layouts") */
#ifndef OCT_SUB
#define OCT_SUB 2
#endif

/* The unit direction of octahedral coordinates p in [-1, 1]^2 with the quadrant signs (qx, qy)
 * and hemisphere given, so the corners of a triangle on one face map with that face's affine
 * map even where they lie on its edges. */
static void oct_face_dir(double px, double py, double qx, double qy, bool lower, double d[3])
{
    double z = 1.0 - qx * px - qy * py;
    double x = lower ? qx * (1.0 - qy * py) : px;
    double y = lower ? qy * (1.0 - qx * px) : py;
    double n = sqrt(x * x + y * y + z * z);
    d[0] = x / n;
    d[1] = y / n;
    d[2] = z / n;
}

/* Solid angle of the spherical triangle a b c (unit vectors): Van Oosterom and Strackee. */
static double tri_solid_angle(const double a[3], const double b[3], const double c[3])
{
    double bxc[3] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]};
    double det = fabs(a[0] * bxc[0] + a[1] * bxc[1] + a[2] * bxc[2]);
    double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
    double ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
    return 2.0 * atan2(det, 1.0 + ab + bc + ca);
}

/* One planar triangle of the parameter square (corners p[0..2], inside one face) on the sphere. */
static double param_tri_solid_angle(const double p[3][2])
{
    double cx = (p[0][0] + p[1][0] + p[2][0]) / 3.0, cy = (p[0][1] + p[1][1] + p[2][1]) / 3.0;
    double qx = cx >= 0.0 ? 1.0 : -1.0, qy = cy >= 0.0 ? 1.0 : -1.0;
    bool lower = fabs(cx) + fabs(cy) > 1.0;
    double d[3][3];
    for (int k = 0; k < 3; k++)
        oct_face_dir(p[k][0], p[k][1], qx, qy, lower, d[k]);
    return tri_solid_angle(d[0], d[1], d[2]);
}

double sl_env_oct_texel_solid_angle(int size, int i, int j)
{
    if (size <= 1)
        return 4.0 * 3.14159265358979323846;
    double x0 = -1.0 + 2.0 * i / size, x1 = -1.0 + 2.0 * (i + 1) / size;
    double y0 = -1.0 + 2.0 * j / size, y1 = -1.0 + 2.0 * (j + 1) / size;
    /* the fold |x| + |y| = 1 runs along the anti-diagonal in quadrants ++ and --, the diagonal
     * in +- and -+; S even puts it through texel corners, and the axes on texel edges */
    bool anti = (x0 + x1 >= 0.0) == (y0 + y1 >= 0.0);
    if (anti) {
        double t1[3][2] = {{x0, y0}, {x1, y0}, {x0, y1}}, t2[3][2] = {{x1, y1}, {x0, y1}, {x1, y0}};
        return param_tri_solid_angle(t1) + param_tri_solid_angle(t2);
    }
    double t1[3][2] = {{x0, y0}, {x1, y0}, {x1, y1}}, t2[3][2] = {{x0, y0}, {x1, y1}, {x0, y1}};
    return param_tri_solid_angle(t1) + param_tri_solid_angle(t2);
}

int sl_env_oct_default_size(const sl_env *latlong)
{
    int s = 1;
    while (s < latlong->levels[0].width && s < SL_ENV_OCT_MAX_SIZE)
        s *= 2;
    return s;
}

/* Level 0 from the lat-long chain (see the top of the file); rows split over threads, each
 * texel computed the same way whatever their number. */
static void resample_level0(const sl_env *ll, sl_env_level *dst, float *omega0, int threads)
{
    const int s = dst->width;
    const sl_env_level *l0 = &ll->levels[0];
    const float max_lod = (float)(ll->level_count - 1);
    /* a lat-long texel's solid angle is k sin(theta); a sub-texel's is |d|_1^3 / (S sub)^2
     * (texture_lod.h: the octahedral Jacobian) */
    const float k = (2.0f * SL_PI / (float)l0->width) * (SL_PI / (float)l0->height);
    const float sin_min = sinf(SL_PI / (2.0f * (float)l0->height));
    const float sub_area = 1.0f / ((float)s * (float)OCT_SUB * (float)s * (float)OCT_SUB);
#pragma omp parallel for schedule(static) num_threads(sl_threads(threads))
    for (int j = 0; j < s; j++) {
        for (int i = 0; i < s; i++) {
            vec3 sum = vec3s(0.0f);
            for (int b = 0; b < OCT_SUB; b++)
                for (int a = 0; a < OCT_SUB; a++) {
                    float u = ((float)i + ((float)a + 0.5f) / (float)OCT_SUB) / (float)s;
                    float v = ((float)j + ((float)b + 0.5f) / (float)OCT_SUB) / (float)s;
                    vec3 d = sl_oct_uv_to_dir(u, v);
                    float l1 = fabsf(d.x) + fabsf(d.y) + fabsf(d.z);
                    float st = maxf(sqrtf(d.x * d.x + d.y * d.y), sin_min);
                    float lod = 0.5f * log2f(l1 * l1 * l1 * sub_area / (k * st));
                    lod = minf(maxf(lod, 0.0f), max_lod);
                    float lu, lv;
                    sl_fast_dir_to_uv(d.x, d.y, d.z, &lu, &lv);
                    sum = add(sum, sl_texture_lod_clamped(ll, lu, lv, lod));
                }
            dst->texels[(size_t)j * (size_t)s + (size_t)i] = scale(sum, 1.0f / (float)(OCT_SUB * OCT_SUB));
            omega0[(size_t)j * (size_t)s + (size_t)i] = (float)sl_env_oct_texel_solid_angle(s, i, j);
        }
    }
}

/* src (2m x 2m) -> dst (m x m): the solid-angle-weighted mean of each 2 x 2 block; om_dst gets
 * the block's solid angle. Accumulated in double. */
static void downsample_weighted(const sl_env_level *src, const float *om_src, sl_env_level *dst, float *om_dst)
{
    const int m = dst->width;
    const size_t w = (size_t)src->width;
    for (int y = 0; y < m; y++)
        for (int x = 0; x < m; x++) {
            double r = 0.0, g = 0.0, b = 0.0, o = 0.0;
            for (int dy = 0; dy < 2; dy++)
                for (int dx = 0; dx < 2; dx++) {
                    size_t t = (size_t)(2 * y + dy) * w + (size_t)(2 * x + dx);
                    double om = (double)om_src[t];
                    r += om * (double)src->texels[t].x;
                    g += om * (double)src->texels[t].y;
                    b += om * (double)src->texels[t].z;
                    o += om;
                }
            size_t q = (size_t)y * (size_t)m + (size_t)x;
            dst->texels[q] = vec3((float)(r / o), (float)(g / o), (float)(b / o));
            om_dst[q] = (float)o;
        }
}

bool sl_env_build_oct(sl_env *oct, const sl_env *latlong, int size, int threads, sl_error *err)
{
    *oct = (sl_env){0};
    if (!latlong || latlong->level_count < 1)
        return sl_fail(err, SL_ERR_RANGE, "octahedral environment: no lat-long environment to resample");
    if (size == 0)
        size = sl_env_oct_default_size(latlong);
    if (size < 1 || size > SL_ENV_OCT_MAX_SIZE || (size & (size - 1)) != 0)
        return sl_fail(err, SL_ERR_RANGE, "octahedral environment: size %d is not a power of two in 1..%d", size,
                       SL_ENV_OCT_MAX_SIZE);
    int count = 0;
    size_t total = 0;
    for (int s = size; s >= 1; s /= 2, count++)
        total += (size_t)s * (size_t)s;
    vec3 *block = malloc(total * sizeof *block);
    float *omega = malloc(total * sizeof *omega);
    if (!block || !omega) {
        free(block);
        free(omega);
        return sl_fail(err, SL_ERR_MEMORY, "octahedral environment %dx%d: out of memory for the mip chain", size,
                       size);
    }
    size_t offset = 0;
    for (int l = 0, s = size; l < count; l++, s /= 2) {
        oct->levels[l] = (sl_env_level){.width = s, .height = s, .texels = block + offset};
        offset += (size_t)s * (size_t)s;
    }
    resample_level0(latlong, &oct->levels[0], omega, threads);
    float *om = omega;
    for (int l = 1; l < count; l++) {
        float *next = om + (size_t)oct->levels[l - 1].width * (size_t)oct->levels[l - 1].width;
        downsample_weighted(&oct->levels[l - 1], om, &oct->levels[l], next);
        om = next;
    }
    free(omega);
    oct->level_count = count;
    oct->block = block;
    oct->layout = SL_ENV_LAYOUT_OCT;
    return true;
}
