/* sky_plane.c - the sky maps' diffuse visibility V (src/shadow/sky.h) for a whole G-buffer, with
 * a seventh to two fifths of the lookups at 1280x720, for the batched lighting paths.
 *
 * A lookup reads every map that faces the normal (half of them, four taps each) and is the
 * costliest part of the sky maps' frame. V is smooth along a surface at the scale of the maps'
 * texels: its taps are filtered, and its weights turn with the normal over cells some 20 degrees
 * wide. So the pass looks V up at the anchors, every SL_SKY_PLANE_SPACING-th texel each way, and
 * fills the grids between a level at a time, halving the spacing: each texel of a grid that is
 * not on the coarser one from the coarser grid's texels around it, the two beside it, the two
 * below and above it or the four at its corners, as their mean, where each of them is covered,
 * on the texel's surface (within SL_SKY_PLANE_SAME_DEPTH of its view distance from its tangent
 * plane, the normals within SL_SKY_PLANE_SAME_NORMAL) and within SL_SKY_PLANE_REACH texels of
 * the finest map from it, and their V lie within SL_SKY_PLANE_AGREE of each other. Anywhere else
 * (an object's edge, a crease, a shadow's border, the image's last rows or columns, pixels
 * coarser than the maps' texels) the texel is looked up itself, and the finer grids read that
 * lookup. Where V is linear along the surface the mean is exact; where it bends between texels
 * that agree, the mean is off by about what the agreement allows, a level's error carried into
 * the next; a feature narrower than the spacing that both miss (a thin shadow between them) is
 * missed. The lookups, the anchors' and the fill's alike, are made SL_SKY_POINTS texels of a row
 * at a time, a SIMD lane a texel (sl_shadow_sky_visibility_points), with the bits of the
 * one-texel lookup.
 *
 * The port (--plain) and lighting.frag look V up per pixel; `softlight trace` shows that lookup.
 * The fill's error against it and its speed: docs/lighting.md "Sky visibility maps"
 * (bench_sky_plane). */

#include <math.h>
#include <omp.h>
#include <stdint.h>

#include "lighting_internal.h"

/* Texels waiting for their lookups, made SL_SKY_POINTS at a time (sl_shadow_sky_visibility_points:
 * the texels of a run of a row read the same few cache lines of each map): their points, the
 * normals the lighting uses there (shade_view_frame_at: the G-buffer's normal, turned toward the
 * eye where it faces away), and where each V goes. */
typedef struct {
    sl_shadow_sky_points points;
    float *dest[SL_SKY_POINTS];
    int n;
    vec3 env_rotation[3]; /* the frame's, for shade_view_frame_at */
} lookup_batch;

static lookup_batch lookup_batch_for(const sl_lighting_uniforms *u)
{
    return (lookup_batch){.n = 0, .env_rotation = {u->uEnvRotation.c[0], u->uEnvRotation.c[1], u->uEnvRotation.c[2]}};
}

static void lookup_flush(const sl_lighting_uniforms *u, lookup_batch *b)
{
    if (b->n == 0)
        return;
    for (int i = b->n; i < SL_SKY_POINTS; i++) { /* a lane not used: N = 0 weighs no map */
        b->points.px[i] = b->points.py[i] = b->points.pz[i] = 0.0f;
        b->points.nx[i] = b->points.ny[i] = b->points.nz[i] = 0.0f;
    }
    float V[SL_SKY_POINTS];
    sl_shadow_sky_visibility_points(u->skyMaps, &b->points, V);
    for (int i = 0; i < b->n; i++)
        *b->dest[i] = V[i];
    b->n = 0;
}

/* Texel (x, y)'s lookup into *dest, made with the batch's (1 at once for an empty texel, which
 * is not read). Returns whether it is a lookup (the texel is covered). */
static bool lookup_add(const sl_lighting_uniforms *u, const sl_gbuffer *gb, lookup_batch *b, int x, int y,
                       float *dest)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
    if (t->depth >= 1.0f) {
        *dest = 1.0f;
        return false;
    }
    shade_view_frame f = shade_view_frame_at(u->uEye, t->position, t->normal, b->env_rotation);
    const int i = b->n;
    b->points.px[i] = t->position.x, b->points.py[i] = t->position.y, b->points.pz[i] = t->position.z;
    b->points.nx[i] = f.N.x, b->points.ny[i] = f.N.y, b->points.nz[i] = f.N.z;
    b->dest[i] = dest;
    if (++b->n == SL_SKY_POINTS)
        lookup_flush(u, b);
    return true;
}

/* The farthest an anchor may lie from the texel it fills, squared (world units): SL_SKY_PLANE_REACH
 * texels of the finest map. Farther, V can change between them by more than the maps resolve,
 * unseen by both (a shadow's edge, a thin occluder's shadow): a frame too small for the maps'
 * texels (a floor far off at a grazing view, an image of 160x90) is looked up texel by texel.
 * A map's texel is the larger of its two sides (as its bias and normal offset take it): a scene
 * thin along one of a map's axes (default.json's spheres, all in one plane) draws it with a
 * short side that resolves only that thickness, and would leave every texel looked up. */
static float reach_squared(const sl_shadow_sky *sky)
{
    float texel = INFINITY;
    for (int k = 0; k < sky->count; k++) {
        const float side = sky->lanes.stepx[k] > sky->lanes.stepy[k] ? sky->lanes.stepx[k] : sky->lanes.stepy[k];
        texel = side < texel ? side : texel;
    }
    float reach = SL_SKY_PLANE_REACH * texel;
    return reach * reach;
}

/* Texel p's side of the same-surface test, once per texel: its normal (the G-buffer's,
 * unnormalized) and squared length, the square of the tangent plane's allowance, and the reach. */
typedef struct {
    vec3 P, n;
    float n2, allowance2, reach2;
} surface_test;

static surface_test surface_test_of(const sl_lighting_uniforms *u, const sl_gbuffer_texel *p, float reach2)
{
    vec3 eye_to_p = sub(p->position, u->uEye);
    float depth2 = SL_SKY_PLANE_SAME_DEPTH * SL_SKY_PLANE_SAME_DEPTH * dot(eye_to_p, eye_to_p);
    float n2 = dot(p->normal, p->normal);
    return (surface_test){p->position, p->normal, n2, depth2 * n2, reach2};
}

/* Whether covered texel q may stand for p: q covered, within the reach of p, its normal within
 * SL_SKY_PLANE_SAME_NORMAL of p's, and within SL_SKY_PLANE_SAME_DEPTH of p's view distance from
 * p's tangent plane (each compared squared: no square root in the fill). */
static bool same_surface(const surface_test *p, const sl_gbuffer_texel *q)
{
    if (q->depth >= 1.0f)
        return false;
    vec3 pq = sub(q->position, p->P);
    if (!(dot(pq, pq) <= p->reach2))
        return false;
    float d = dot(p->n, q->normal), q2 = dot(q->normal, q->normal);
    if (!(d > 0.0f) || d * d < SL_SKY_PLANE_SAME_NORMAL * SL_SKY_PLANE_SAME_NORMAL * p->n2 * q2)
        return false;
    float off = dot(pq, p->n); /* the distance times |n| */
    return off * off <= p->allowance2;
}

/* Texel (x, y)'s V from the anchors at the given offsets (n of them) into *dest, or else its own
 * lookup into the batch (counted in *lookups). */
static void fill_texel(const sl_lighting_uniforms *u, const sl_gbuffer *gb, const float *plane, int x, int y,
                       const int (*offsets)[2], int n, float agree, float reach2, lookup_batch *batch, float *dest,
                       int64_t *lookups)
{
    const sl_gbuffer_texel *p = sl_gbuffer_at(gb, x, y);
    if (p->depth >= 1.0f) {
        *dest = 1.0f;
        return;
    }
    const surface_test test = surface_test_of(u, p, reach2);
    float lo = 1.0f, hi = 0.0f, sum = 0.0f;
    bool stand_in = agree >= 0.0f && test.n2 > 0.0f;
    for (int k = 0; k < n && stand_in; k++) {
        int ax = x + offsets[k][0], ay = y + offsets[k][1];
        stand_in = ax >= 0 && ay >= 0 && ax < gb->width && ay < gb->height &&
                   same_surface(&test, sl_gbuffer_at(gb, ax, ay));
        if (stand_in) {
            float v = plane[(size_t)ay * (size_t)gb->width + (size_t)ax];
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
            sum += v;
        }
    }
    if (stand_in && hi - lo <= agree)
        *dest = sum / (float)n;
    else
        *lookups += lookup_add(u, gb, batch, x, y, dest);
}

/* One level of the fill: the texels of the grid of spacing `step` that are not on the grid of
 * twice it, each from the grid of twice it around it (beside, across or at the corners, `step`
 * away). The texels of the coarser grid are all set before. */
static int64_t fill_level(const sl_lighting_uniforms *u, const sl_gbuffer *gb, float *plane, int step, float agree,
                          float reach2, int threads)
{
    const int w = gb->width, h = gb->height, s = step;
    const int beside[2][2] = {{-s, 0}, {s, 0}}, across[2][2] = {{0, -s}, {0, s}},
              corners[4][2] = {{-s, -s}, {s, -s}, {-s, s}, {s, s}};
    int64_t lookups = 0;
    /* Each row's count is added atomically, not by a reduction clause: clang makes one a global
     * lock symbol in the library (tests/cli/exports.sh). */
#pragma omp parallel for schedule(dynamic) num_threads(threads)
    for (int y = 0; y < h; y += s) {
        float *row = plane + (size_t)y * (size_t)w;
        lookup_batch batch = lookup_batch_for(u);
        int64_t row_lookups = 0;
        if (y % (2 * s) == 0) { /* a row of the coarser grid: from the two beside */
            for (int x = s; x < w; x += 2 * s)
                fill_texel(u, gb, plane, x, y, beside, 2, agree, reach2, &batch, &row[x], &row_lookups);
        } else { /* between: from the two below and above, or the four at the corners */
            for (int x = 0; x < w; x += s) {
                const bool on_coarser = x % (2 * s) == 0;
                fill_texel(u, gb, plane, x, y, on_coarser ? across : corners, on_coarser ? 2 : 4, agree, reach2,
                           &batch, &row[x], &row_lookups);
            }
        }
        lookup_flush(u, &batch);
#pragma omp atomic
        lookups += row_lookups;
    }
    return lookups;
}

int64_t sl_sky_plane_fill(const sl_lighting_uniforms *u, const sl_gbuffer *gb, float *plane, float agree,
                          int threads)
{
    const int w = gb->width, h = gb->height, coarsest = SL_SKY_PLANE_SPACING;
    const float reach2 = reach_squared(u->skyMaps);
    int64_t lookups = 0;
    /* The anchors first, every `coarsest` texels each way; then each finer grid from the one
     * above it. */
#pragma omp parallel for schedule(dynamic) num_threads(threads)
    for (int y = 0; y < h; y += coarsest) {
        float *row = plane + (size_t)y * (size_t)w;
        lookup_batch batch = lookup_batch_for(u);
        int64_t row_lookups = 0;
        for (int x = 0; x < w; x += coarsest)
            row_lookups += lookup_add(u, gb, &batch, x, y, &row[x]);
        lookup_flush(u, &batch);
#pragma omp atomic
        lookups += row_lookups;
    }
    for (int step = coarsest / 2; step >= 1; step /= 2)
        lookups += fill_level(u, gb, plane, step, agree, reach2, threads);
    return lookups;
}
