/* sky.c - the sky visibility maps (sky.h): the directions, their cells' weights from the
 * environment, the maps (drawn by shadow.c's orthographic machinery, into one block) and the
 * lookups: a point's, every map in one loop, a lane a map; a run of points', the maps one after
 * another, a lane a point (the plane the batched lighting reads); a run of points' each in the
 * map of its own direction's cell, a lane a point (the batched lighting's part across the
 * horizon and wide lobes); each equal bit for bit to the scalar lookup of one map
 * (sl_shadow_sky_map_visibility, which the GLSL twin mirrors and trace reports). */
#include "sky.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The lookup's offsets, in map texels: the receiver moved along its normal (at most: shadow.h
 * sl_shadow_offset_share), and the bias past the receiver plane's depth per tap (shadow.c's
 * values for the env lights' maps). */
#define SKY_NORMAL_OFFSET 1.0f
#define SKY_BIAS_CONST 1.0f

/* The directions on the sky's side of the horizon: the first count - count / 2; the ground's
 * are the rest (sky.h). Without the split (SL_SKY_MAPS_SPLIT 0) every direction is one side's. */
static int sky_side_count(int count) { return SL_SKY_MAPS_SPLIT ? count - count / 2 : count; }

vec3 sl_shadow_sky_direction(int k, int count)
{
    /* each half a hemispherical Fibonacci set: equal-area bands in |z| over (0, 1], a
     * golden-angle turn per point; the ground's half mirrored below the horizon (without the
     * split, one set over the sphere: equal-area bands in z over (-1, 1)) */
    const float golden = SL_PI * (3.0f - sqrtf(5.0f));
    if (!SL_SKY_MAPS_SPLIT) {
        float z = 1.0f - (2.0f * (float)k + 1.0f) / (float)count;
        float r = sqrtf(fmaxf(1.0f - z * z, 0.0f));
        return vec3(r * cosf(golden * (float)k), r * sinf(golden * (float)k), z);
    }
    const int sky = sky_side_count(count);
    const bool ground = k >= sky;
    const int j = ground ? k - sky : k, n = ground ? count - sky : sky;
    float z = 1.0f - ((float)j + 0.5f) / (float)n;
    float r = sqrtf(fmaxf(1.0f - z * z, 0.0f));
    float phi = golden * (float)j;
    return vec3(r * cosf(phi), r * sinf(phi), ground ? -z : z);
}

/* The index of the site among dirs[0 .. count) nearest w on w's side of the horizon (z >= 0 is
 * the sky's), or the nearest of all when that side has none (count 1). */
static int nearest_site(const vec3 *dirs, int count, vec3 w)
{
    const int sky = sky_side_count(count);
    int first = 0, last = count;
    if (count > sky) { /* both sides have directions */
        first = w.z >= 0.0f ? 0 : sky;
        last = w.z >= 0.0f ? sky : count;
    }
    int best = first;
    float best_dot = -2.0f;
    for (int k = first; k < last; k++) { /* selects, not a branch: which site wins is data */
        float d = dot(w, dirs[k]);
        bool nearer = d > best_dot;
        best = nearer ? k : best;
        best_dot = nearer ? d : best_dot;
    }
    return best;
}

/* m_k = sum over cell k's level-0 texels of lum(L) w dOmega (environment space). A texel joins
 * the cell of its centre's direction (nearest_site). */
static void cell_weights(const sl_env *env, const vec3 *dirs, int count, vec3 *m)
{
    for (int k = 0; k < count; k++)
        m[k] = vec3s(0.0f);
    if (!env || env->level_count < 1)
        return;
    const sl_env_level *l = &env->levels[0];
    /* a lat-long texel's solid angle: (2 pi / W) (pi / H) sin(theta) */
    const float texel_sr = 2.0f * SL_PI * SL_PI / ((float)l->width * (float)l->height);
    for (int y = 0; y < l->height; y++) {
        float v = ((float)y + 0.5f) / (float)l->height;
        for (int x = 0; x < l->width; x++) {
            float lum = sl_luminance(l->texels[(size_t)y * (size_t)l->width + (size_t)x]);
            if (!(lum > 0.0f))
                continue;
            vec3 w = sl_uv_to_dir(vec2(((float)x + 0.5f) / (float)l->width, v));
            int best = nearest_site(dirs, count, w);
            float sin_theta = sqrtf(fmaxf(1.0f - w.z * w.z, 0.0f));
            m[best] = add(m[best], scale(w, lum * texel_sr * sin_theta));
        }
    }
}

/* Each map's lookup constants in its lane, formed as sl_shadow_sky_map_visibility forms them per
 * call (so that both round alike); its first texel's offset in the block when it has one. */
static void sky_lanes(sl_shadow_sky *sky)
{
    sl_shadow_sky_lanes *l = &sky->lanes;
    for (int k = 0; k < sky->count; k++) {
        const sl_shadow_sun *map = &sky->maps[k];
        l->wx[k] = sky->weight[k].x;
        l->wy[k] = sky->weight[k].y;
        l->wz[k] = sky->weight[k].z;
        l->ax[k] = map->axis.x;
        l->ay[k] = map->axis.y;
        l->az[k] = map->axis.z;
        l->rx[k] = map->right.x;
        l->ry[k] = map->right.y;
        l->rz[k] = map->right.z;
        l->ux[k] = map->up.x;
        l->uy[k] = map->up.y;
        l->uz[k] = map->up.z;
        l->x0[k] = map->x0;
        l->y0[k] = map->y0;
        l->offset[k] = map->texel * SKY_NORMAL_OFFSET;
        l->stepx[k] = map->stepx;
        l->stepy[k] = map->stepy;
        l->bias[k] = map->texel * SKY_BIAS_CONST + map->sz * 1e-6f;
        l->first[k] = sky->block && map->depth ? (int)(map->depth - sky->block) : 0;
        l->size[k] = map->size;
    }
}

bool sl_shadow_sky_frames(sl_shadow_sky *sky, int count, const sl_env *env, float env_rotation_deg,
                          const sl_scene *scene)
{
    /* environment -> world: a turn by +rotation about +Z (shadow.c sl_shadow_suns_frames) */
    float phi = radians(env_rotation_deg), c = cosf(phi), s = sinf(phi);
    vec3 dirs[SL_SKY_MAPS_MAX], m[SL_SKY_MAPS_MAX];
    for (int k = 0; k < count; k++)
        sky->site[k] = dirs[k] = sl_shadow_sky_direction(k, count);
    cell_weights(env, dirs, count, m);
    for (int k = 0; k < count; k++) {
        /* each map looks along its cell's luminous centroid, normalize(m_k), where the cell's
         * light comes from (a sun in one corner of it, a window), not its centre; d_k for a
         * black cell */
        float len = length(m[k]);
        vec3 e = len > 0.0f && SL_SKY_MAPS_CENTROID ? scale(m[k], 1.0f / len) : dirs[k];
        sky->maps[k].dir = vec3(c * e.x - s * e.y, s * e.x + c * e.y, e.z);
        sky->weight[k] = vec3(c * m[k].x - s * m[k].y, s * m[k].x + c * m[k].y, m[k].z);
    }
    sky->count = count;
    sky->cell_angle = acosf(1.0f - 2.0f / (float)count);
    sky->sky_sites = sky_side_count(count);
    bool geometry = sl_shadow_ortho_frames(sky->maps, count, SL_SKY_MAP_SIZE, scene);
    sky_lanes(sky);
    return geometry;
}

bool sl_shadow_sky_build(sl_shadow_sky *sky, int count, const sl_env *env, float env_rotation_deg, sl_raster *r,
                         const sl_scene *scene, const sl_scene_textures *tex, sl_error *err)
{
    if (count < 1 || count > SL_SKY_MAPS_MAX)
        return sl_fail(err, SL_ERR_RANGE, "sky maps: %d directions (1..%d)", count, SL_SKY_MAPS_MAX);
    /* one block for the maps (an earlier build's is reused when it holds as many: it keeps the
     * most maps asked for) */
    const size_t n = (size_t)SL_SKY_MAP_SIZE * (size_t)SL_SKY_MAP_SIZE;
    if (sky->block_maps < count) {
        free(sky->block);
        sky->block_maps = 0;
        sky->block = malloc((size_t)count * n * sizeof(float));
        if (!sky->block) {
            for (int k = 0; k < SL_SKY_MAPS_MAX; k++)
                sky->maps[k].depth = NULL;
            sky->count = 0;
            return sl_fail(err, SL_ERR_MEMORY, "sky maps: out of memory for %d %dx%d maps", count,
                           SL_SKY_MAP_SIZE, SL_SKY_MAP_SIZE);
        }
        sky->block_maps = count;
    }
    for (int k = 0; k < SL_SKY_MAPS_MAX; k++)
        sky->maps[k].depth = k < count ? sky->block + (size_t)k * n : NULL;
    sl_shadow_sky_frames(sky, count, env, env_rotation_deg, scene);
    sky->count = 0;
    if (!sl_shadow_ortho_build(sky->maps, count, SL_SKY_MAP_SIZE, r, scene, tex, err))
        return false;
    sky->count = count;
    return true;
}

void sl_shadow_sky_free(sl_shadow_sky *sky)
{
    free(sky->block);
    memset(sky, 0, sizeof *sky);
}

/* GLSL: sky_map_visibility (softlight-gl's maps, read with texelFetch) */
float sl_shadow_sky_map_visibility(const sl_shadow_sky *sky, int k, vec3 P, vec3 N)
{
    const sl_shadow_sun *map = &sky->maps[k];
    sl_shadow_ortho_at at;
    if (!sl_shadow_ortho_locate(map, P, N, map->texel * SKY_NORMAL_OFFSET, &at))
        return 1.0f; /* the direction below P's plane, or off the map: nothing there casts */
    const float xq = at.xq, yq = at.yq, zq = at.zq, fx = at.fx, fy = at.fy, tx = at.tx, ty = at.ty;
    const float stepx = at.stepx, stepy = at.stepy, gx = at.gx, gy = at.gy;
    int x0 = (int)fx, y0 = (int)fy;
    float bias = map->texel * SKY_BIAS_CONST + map->sz * 1e-6f;
    const float wx[2] = {1.0f - tx, tx}, wy[2] = {1.0f - ty, ty};
    const int last = map->size - 1;
    /* each column's and row's offset from q and clamped index once: ((float)(x0 + a) + 0.5f) is
     * fx + a + 0.5, formed in float (exact: |fx| < 1e6) rather than converted per tap */
    float dxs[2], dys[2];
    int xs[2];
    for (int a = 0; a < 2; a++) {
        xs[a] = x0 + a < 0 ? 0 : x0 + a > last ? last : x0 + a;
        dxs[a] = (fx + (float)a + 0.5f) * stepx + map->x0 - xq;
        dys[a] = (fy + (float)a + 0.5f) * stepy + map->y0 - yq;
    }
    float vis = 0.0f;
    for (int b = 0; b < 2; b++) {
        int y = y0 + b < 0 ? 0 : y0 + b > last ? last : y0 + b;
        for (int a = 0; a < 2; a++) {
            float receiver = zq + gx * dxs[a] + gy * dys[b];
            float stored = map->depth[sl_shadow_tile_index(xs[a], y, map->size)];
            vis += stored + bias >= receiver ? wx[a] * wy[b] : 0.0f;
        }
    }
    return fminf(vis, 1.0f);
}

/* The two lane loops' shared bodies, each the operations of sl_shadow_sky_map_visibility for map
 * k at point P with normal N, in its order, its branches as selects; map k's constants read from
 * the lanes (a lane each in the loop over the maps, the same for every lane in the loop over the
 * points). Two loops, the place and then the taps: with the place's holding select and the taps'
 * truncation in one loop, GCC has moved the truncation into the select's branch. */

/* Where P lands on map k: N along the map's axis (na), the receiver moved off along N (q) and seen
 * in the map's frame (xq, yq, zq), and its texel coordinates (ux, uy), held within 1e7 (NaN too)
 * for the truncation in lane_lookup: whatever lies beyond floors beyond 1e6, as the held value
 * does, and is not read. */
typedef struct {
    float na, xq, yq, zq, ux, uy;
} lane_place;

__attribute__((always_inline)) static inline lane_place lane_place_of(const sl_shadow_sky_lanes *l, int k, float px,
                                                                      float py, float pz, float nx, float ny,
                                                                      float nz)
{
    lane_place p;
    p.na = nx * l->ax[k] + ny * l->ay[k] + nz * l->az[k];
    const float off = l->offset[k] * sl_shadow_offset_share(p.na);
    const float qx = px + nx * off, qy = py + ny * off, qz = pz + nz * off;
    p.xq = qx * l->rx[k] + qy * l->ry[k] + qz * l->rz[k];
    p.yq = qx * l->ux[k] + qy * l->uy[k] + qz * l->uz[k];
    p.zq = qx * l->ax[k] + qy * l->ay[k] + qz * l->az[k];
    const float ux = (p.xq - l->x0[k]) / l->stepx[k] - 0.5f, uy = (p.yq - l->y0[k]) / l->stepy[k] - 0.5f;
    p.ux = fabsf(ux) < 1e7f ? ux : 1e7f;
    p.uy = fabsf(uy) < 1e7f ? uy : 1e7f;
    return p;
}

/* The places of a loop's lanes, structure of arrays (an array of lane_place stops GCC's
 * vectorizer): lane i's stored and read back whole. */
typedef struct {
    float na[SL_SKY_MAPS_MAX], xq[SL_SKY_MAPS_MAX], yq[SL_SKY_MAPS_MAX], zq[SL_SKY_MAPS_MAX];
    float ux[SL_SKY_MAPS_MAX], uy[SL_SKY_MAPS_MAX];
} lane_places;
_Static_assert(SL_SKY_POINTS <= SL_SKY_MAPS_MAX, "a loop over the points fits the places' arrays");

__attribute__((always_inline)) static inline void lane_place_store(lane_places *s, int i, lane_place p)
{
    s->na[i] = p.na, s->xq[i] = p.xq, s->yq[i] = p.yq, s->zq[i] = p.zq, s->ux[i] = p.ux, s->uy[i] = p.uy;
}

__attribute__((always_inline)) static inline lane_place lane_place_load(const lane_places *s, int i)
{
    return (lane_place){s->na[i], s->xq[i], s->yq[i], s->zq[i], s->ux[i], s->uy[i]};
}

/* Map k's 2x2 percentage-closer lookup at the place p of a point with normal N: 1 where the map is
 * not read (it weighs nothing there, faces away, or the point is off it), and then its texels
 * are not read either (the maps outgrow the caches: a map not read costs no memory traffic);
 * every index is clamped onto the map, so a value no one reads is computed from nothing
 * undefined. */
__attribute__((always_inline)) static inline float lane_lookup(const sl_shadow_sky_lanes *l, int k, const float *depth,
                                                               bool weighs, lane_place p, float nx, float ny,
                                                               float nz)
{
    const float stepx = l->stepx[k], stepy = l->stepy[k], x0 = l->x0[k], y0 = l->y0[k];
    const int size = l->size[k], first = l->first[k];
    /* floorf by truncation (exact below 2^24; it vectorizes where floorf does not) */
    const int tx0 = (int)p.ux, ty0 = (int)p.uy;
    const float ftx = (float)tx0, fty = (float)ty0;
    const bool downx = ftx > p.ux, downy = fty > p.uy;
    const int ix = downx ? tx0 - 1 : tx0, iy = downy ? ty0 - 1 : ty0;
    const float fx = downx ? ftx - 1.0f : ftx, fy = downy ? fty - 1.0f : fty;
    const bool read = weighs & (p.na < -1e-6f) & (fabsf(fx) < 1e6f) & (fabsf(fy) < 1e6f);
    const float tx = p.ux - fx, ty = p.uy - fy;
    const float gx = -(nx * l->rx[k] + ny * l->ry[k] + nz * l->rz[k]) / p.na;
    const float gy = -(nx * l->ux[k] + ny * l->uy[k] + nz * l->uz[k]) / p.na;
    const float bias = l->bias[k];
    const float wx0 = 1.0f - tx, wy0 = 1.0f - ty;
    const int last = size - 1;
    const int xa = sl_shadow_clamp_index(ix, last), xb = sl_shadow_clamp_index(ix + 1, last);
    const int ya = sl_shadow_clamp_index(iy, last), yb = sl_shadow_clamp_index(iy + 1, last);
    const float dxa = (fx + 0.0f + 0.5f) * stepx + x0 - p.xq, dxb = (fx + 1.0f + 0.5f) * stepx + x0 - p.xq;
    const float dya = (fy + 0.0f + 0.5f) * stepy + y0 - p.yq, dyb = (fy + 1.0f + 0.5f) * stepy + y0 - p.yq;
    const int iaa = first + sl_shadow_tile_index(xa, ya, size), iab = first + sl_shadow_tile_index(xb, ya, size);
    const int iba = first + sl_shadow_tile_index(xa, yb, size), ibb = first + sl_shadow_tile_index(xb, yb, size);
    const float daa = read ? depth[iaa] : 0.0f, dab = read ? depth[iab] : 0.0f;
    const float dba = read ? depth[iba] : 0.0f, dbb = read ? depth[ibb] : 0.0f;
    const float zq = p.zq;
    float vis = 0.0f;
    vis += daa + bias >= zq + gx * dxa + gy * dya ? wx0 * wy0 : 0.0f;
    vis += dab + bias >= zq + gx * dxb + gy * dya ? tx * wy0 : 0.0f;
    vis += dba + bias >= zq + gx * dxa + gy * dyb ? wx0 * ty : 0.0f;
    vis += dbb + bias >= zq + gx * dxb + gy * dyb ? tx * ty : 0.0f;
    vis = vis < 1.0f ? vis : 1.0f; /* fminf: vis is finite where read */
    return read ? vis : 1.0f;
}

/* Lanes a chunk of sky_visibility_lanes: one vector of 8 floats (AVX2). The directions are in
 * bands of height, zenith to horizon on the sky's side, then nadir to horizon on the ground's
 * (sl_shadow_sky_direction), so a chunk's maps face about the same way and a receiver turned
 * away from all of them (a floor from the ground's maps) skips the chunk whole. */
#define SKY_CHUNK 8

/* sl_shadow_sky_visibility's loop over the maps when they are drawn into the block, a lane a
 * map: sl_shadow_sky_map_visibility's operations in its order (so each v_k is its value bit for
 * bit), its branches as selects. A chunk of maps none of which weighs anything at N is skipped;
 * in a chunk that is read, a lane whose map is not read (weight 0, direction below the plane,
 * off the map) computes a value no one reads, from coordinates kept finite and small before they
 * become indices and every index clamped onto its map: nothing undefined. */
static float sky_visibility_lanes(const sl_shadow_sky *sky, vec3 P, vec3 N, float *each)
{
    const sl_shadow_sky_lanes *l = &sky->lanes;
    const float *depth = sky->block;
    const int count = sky->count;
    float ws[SL_SKY_MAPS_MAX], vs[SL_SKY_MAPS_MAX];
    lane_places places;
    const float px = P.x, py = P.y, pz = P.z, nx = N.x, ny = N.y, nz = N.z;
#pragma omp simd
    for (int k = 0; k < count; k++) {
        const float wd = nx * l->wx[k] + ny * l->wy[k] + nz * l->wz[k];
        ws[k] = wd > 0.0f ? wd : 0.0f; /* fmaxf(wd, 0) but for NaN and -0, which weigh 0 alike */
    }
    for (int c0 = 0; c0 < count; c0 += SKY_CHUNK) {
        const int c1 = c0 + SKY_CHUNK < count ? c0 + SKY_CHUNK : count;
        bool any = false;
        for (int k = c0; k < c1; k++)
            any |= ws[k] > 0.0f;
        if (!any)
            continue; /* no v_k of the chunk is read */
#pragma omp simd
        for (int k = c0; k < c1; k++)
            lane_place_store(&places, k, lane_place_of(l, k, px, py, pz, nx, ny, nz));
#pragma omp simd
        for (int k = c0; k < c1; k++)
            vs[k] = lane_lookup(l, k, depth, ws[k] > 0.0f, lane_place_load(&places, k), nx, ny, nz);
    }
    float seen = 0.0f, all = 0.0f;
    for (int k = 0; k < count; k++) {
        const float w = ws[k];
        if (each)
            each[k] = w > 0.0f ? vs[k] : -1.0f;
        if (w > 0.0f) {
            seen += vs[k] * w;
            all += w;
        }
    }
    return all > 0.0f ? seen / all : 1.0f;
}

/* The lanes' loop turned about: a lane a point, the maps one after another. Per point and map
 * the operations of sky_visibility_lanes (and so of sl_shadow_sky_map_visibility) in their order,
 * and per point the sums over the maps in k's order, adding 0 (which leaves a sum's bits) where a
 * map weighs nothing: V's bits are the one-point lookup's. */
void sl_shadow_sky_visibility_points(const sl_shadow_sky *sky, const sl_shadow_sky_points *pts, float *V)
{
    enum { L = SL_SKY_POINTS };
    if (!sky->block || sky->count <= 0) {
        for (int i = 0; i < L; i++)
            V[i] = sl_shadow_sky_visibility(sky, vec3(pts->px[i], pts->py[i], pts->pz[i]),
                                            vec3(pts->nx[i], pts->ny[i], pts->nz[i]), NULL);
        return;
    }
    const sl_shadow_sky_lanes *l = &sky->lanes;
    const float *depth = sky->block;
    const float *px = pts->px, *py = pts->py, *pz = pts->pz, *nx = pts->nx, *ny = pts->ny, *nz = pts->nz;
    float seen[L] = {0}, all[L] = {0};
    for (int k = 0; k < sky->count; k++) {
        const float wkx = l->wx[k], wky = l->wy[k], wkz = l->wz[k];
        float ws[L];
        bool any = false;
#pragma omp simd
        for (int i = 0; i < L; i++) {
            const float wd = nx[i] * wkx + ny[i] * wky + nz[i] * wkz;
            ws[i] = wd > 0.0f ? wd : 0.0f;
        }
        for (int i = 0; i < L; i++)
            any |= ws[i] > 0.0f;
        if (!any)
            continue; /* no point reads map k */
        lane_places places;
#pragma omp simd
        for (int i = 0; i < L; i++)
            lane_place_store(&places, i, lane_place_of(l, k, px[i], py[i], pz[i], nx[i], ny[i], nz[i]));
#pragma omp simd
        for (int i = 0; i < L; i++) {
            const float v = lane_lookup(l, k, depth, ws[i] > 0.0f, lane_place_load(&places, i), nx[i], ny[i], nz[i]);
            seen[i] += ws[i] > 0.0f ? v * ws[i] : 0.0f;
            all[i] += ws[i];
        }
    }
    for (int i = 0; i < L; i++)
        V[i] = all[i] > 0.0f ? seen[i] / all[i] : 1.0f;
}

/* GLSL: sky_visibility */
float sl_shadow_sky_visibility(const sl_shadow_sky *sky, vec3 P, vec3 N, float *each)
{
    if (sky->block && sky->count > 0)
        return sky_visibility_lanes(sky, P, N, each);
    float seen = 0.0f, all = 0.0f;
    for (int k = 0; k < sky->count; k++) {
        float w = fmaxf(dot(N, sky->weight[k]), 0.0f);
        float v = w > 0.0f ? sl_shadow_sky_map_visibility(sky, k, P, N) : -1.0f;
        if (each)
            each[k] = v;
        if (w > 0.0f) {
            seen += v * w;
            all += w;
        }
    }
    return all > 0.0f ? seen / all : 1.0f;
}

/* GLSL: sky_cell */
int sl_shadow_sky_cell(const sl_shadow_sky *sky, vec3 d) { return nearest_site(sky->site, sky->count, d); }

/* sl_shadow_sky_map_visibility of each point's own map, that of the cell of a direction
 * (sl_shadow_sky_cell), for `count` points (at most SL_SHADOW_LANES): the batched
 * lighting's part of the specular across the horizon and a wide lobe's map of R's cell. The
 * cells by nearest_site's loop with a lane a point (its sites in its order, those of the other
 * side of the horizon masked), the lookups by the lanes' bodies with each lane's map constants
 * gathered: each cell and value the one-point functions' bits (tests/unit/test_sky_maps.c). */
__attribute__((noinline)) /* inlined into its caller's loop, clang does not vectorize it */
static void cell_visibility_run(const sl_shadow_sky *sky, int count, const float *dx, const float *dy,
                                const float *dz, const float *px, const float *py, const float *pz, const float *nx,
                                const float *ny, const float *nz, float *v)
{
    enum { L = SL_SHADOW_LANES };
    if (!sky->block || sky->count <= 0) {
        for (int i = 0; i < count; i++)
            v[i] = sl_shadow_sky_map_visibility(sky, sl_shadow_sky_cell(sky, vec3(dx[i], dy[i], dz[i])),
                                                vec3(px[i], py[i], pz[i]), vec3(nx[i], ny[i], nz[i]));
        return;
    }
    const int sites = sky->count, sky_sites = sky_side_count(sites);
    const bool split = sites > sky_sites; /* both sides have sites */
    int cell[L];
    float best_dot[L];
#pragma omp simd
    for (int i = 0; i < count; i++) {
        cell[i] = split && !(dz[i] >= 0.0f) ? sky_sites : 0;
        best_dot[i] = -2.0f;
    }
    for (int k = 0; k < sites; k++) {
        const vec3 s = sky->site[k];
        const bool on_sky = k < sky_sites;
#pragma omp simd
        for (int i = 0; i < count; i++) {
            const bool side = !split || ((dz[i] >= 0.0f) == on_sky);
            const float d = dx[i] * s.x + dy[i] * s.y + dz[i] * s.z;
            const bool nearer = side & (d > best_dot[i]);
            cell[i] = nearer ? k : cell[i];
            best_dot[i] = nearer ? d : best_dot[i];
        }
    }
    const sl_shadow_sky_lanes *l = &sky->lanes;
    lane_places places;
    _Static_assert(L <= SL_SKY_MAPS_MAX, "a lanes lookup fits the places' arrays");
#pragma omp simd
    for (int i = 0; i < count; i++)
        lane_place_store(&places, i, lane_place_of(l, cell[i], px[i], py[i], pz[i], nx[i], ny[i], nz[i]));
    float out[L]; /* through a local array, as shadow.c's lanes */
#pragma omp simd
    for (int i = 0; i < count; i++)
        out[i] = lane_lookup(l, cell[i], sky->block, true, lane_place_load(&places, i), nx[i], ny[i], nz[i]);
    for (int i = 0; i < count; i++)
        v[i] = out[i];
}

/* Any number of points: runs of at most SL_SHADOW_LANES, each in one pass. */
void sl_shadow_sky_cell_visibility_lanes(const sl_shadow_sky *sky, int count, const float *dx, const float *dy,
                                         const float *dz, const float *px, const float *py, const float *pz,
                                         const float *nx, const float *ny, const float *nz, float *v)
{
    for (int i = 0; i < count; i += SL_SHADOW_LANES)
        cell_visibility_run(sky, count - i < SL_SHADOW_LANES ? count - i : SL_SHADOW_LANES, dx + i, dy + i, dz + i,
                            px + i, py + i, pz + i, nx + i, ny + i, nz + i, v + i);
}
