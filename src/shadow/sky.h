/* sky.h - sky visibility maps: a world-space occlusion of the environment for the diffuse term
 * and for the specular's part across the horizon.
 *
 * Screen-space ambient occlusion (src/occlusion) sees only what the G-buffer holds within its
 * radius: the sky a large object hides from the ground beside it, or an occluder behind the
 * camera, it cannot see. These maps see the whole scene: K directions d_k spread evenly over the
 * sphere (environment space), half over the sky and half over the ground (a hemispherical
 * Fibonacci set each, the ground's mirrored below the horizon), cut each side of the horizon into
 * their Voronoi cells: no cell lies across the horizon, where the sky meets the ground and where a
 * floor, the commonest occluder, cuts the environment (a cell across it would take one
 * visibility for a sky a floor leaves open and a ground it hides). Per cell, from the environment the
 * diffuse term's irradiance holds (the residual left after the env lights when their shadow maps
 * take them out of it, else the whole environment), a luminance-weighted vector
 *     m_k = sum over the cell's level-0 texels of lum(L(w)) w dOmega,
 * so that max(N . m_k, 0) approximates the cell's share of the irradiance about N. Each cell
 * gets an orthographic depth map of S x S texels over the scene's bounds, drawn towards its
 * luminous centroid normalize(m_k) (d_k for a black cell; the environment's rotation applied:
 * world space) by the machinery of the env lights' maps (shadow.h: sl_shadow_ortho_build), once
 * per scene, environment and rotation. The centroid, not d_k: a cell's light is uneven (a sun in
 * one corner, a window), and the map looks where it comes from (measured: docs/lighting.md "Sky
 * visibility maps"). Per point P
 * with normal N (world), each map's visibility v_k (a 2x2 bilinear percentage-closer lookup
 * with the env lights' maps' normal offset and per-tap receiver plane) gives
 *     V = sum_k v_k max(N . m_k, 0) / sum_k max(N . m_k, 0)   (1 where the sum is 0),
 * and the diffuse term's irradiance (the residual's part) is multiplied by V. A map whose weight
 * is 0 at N is not read. The specular's samples across the horizon from the reflection direction
 * take the visibility of one map, that of the cell holding their luminous direction
 * (sl_shadow_sky_cell; src/shading/lighting_internal.h shade_horizon), and a lobe at least half
 * a cell wide the map of the cell holding R (shade_lobe_map).
 *
 * Limits: the angular resolution is a cell, 4 pi / K steradians (K = 32: about 0.39 sr, a cone
 * of about 20 degrees half-angle): an occluder's edge in the sky moves V in steps of a cell's
 * weight (banding on smooth surfaces as N turns); a map's texel is the scene's bounds over S, so
 * occluders thinner than a texel or two drop out and contact shadows are a texel or two wide.
 * Interreflection is not counted (the occluded sky is dark, not the occluder's radiance).
 * docs/lighting.md "Sky visibility maps" measures it. */
#ifndef SL_SHADOW_SKY_H
#define SL_SHADOW_SKY_H

#include <stdbool.h>

#include "core/error.h"
#include "ibl/ibl.h"
#include "shadow/shadow.h"

#ifndef SL_SKY_MAP_SIZE
#define SL_SKY_MAP_SIZE 1024 /* texels along a sky map's side */
#endif
_Static_assert(SL_SKY_MAP_SIZE % SL_SHADOW_TILE == 0, "a sky map is a whole number of tiles (sl_shadow_tile_index)");
/* The three choices docs/lighting.md "Sky visibility maps" measures, each 1 here; a build defining
 * one as 0 takes the alternative, for bench/visibility-variants.sh: SL_SKY_MAPS_SPLIT 0, one
 * spherical Fibonacci set over the whole sphere and cells across the horizon;
 * SL_SKY_MAPS_CENTROID 0, each map drawn along its direction d_k; SL_SKY_MAPS_HORIZON 0, the
 * specular's samples across the horizon keep the pixel's factor (the C paths only: the GLSL twin
 * does not follow such a build). */
#ifndef SL_SKY_MAPS_SPLIT
#define SL_SKY_MAPS_SPLIT 1
#endif
#ifndef SL_SKY_MAPS_CENTROID
#define SL_SKY_MAPS_CENTROID 1
#endif
#ifndef SL_SKY_MAPS_HORIZON
#define SL_SKY_MAPS_HORIZON 1
#endif

/* The maps' lookup constants, a lane a map (structure of arrays), for sl_shadow_sky_visibility's
 * loop over the maps: each value as sl_shadow_sky_map_visibility forms it per call. */
typedef struct {
    float wx[SL_SKY_MAPS_MAX], wy[SL_SKY_MAPS_MAX], wz[SL_SKY_MAPS_MAX]; /* m_k */
    float ax[SL_SKY_MAPS_MAX], ay[SL_SKY_MAPS_MAX], az[SL_SKY_MAPS_MAX]; /* axis */
    float rx[SL_SKY_MAPS_MAX], ry[SL_SKY_MAPS_MAX], rz[SL_SKY_MAPS_MAX]; /* right */
    float ux[SL_SKY_MAPS_MAX], uy[SL_SKY_MAPS_MAX], uz[SL_SKY_MAPS_MAX]; /* up */
    float x0[SL_SKY_MAPS_MAX], y0[SL_SKY_MAPS_MAX];
    float offset[SL_SKY_MAPS_MAX];           /* the normal offset at its longest, world units */
    float stepx[SL_SKY_MAPS_MAX], stepy[SL_SKY_MAPS_MAX]; /* world units per texel */
    float bias[SL_SKY_MAPS_MAX];
    int first[SL_SKY_MAPS_MAX];              /* the map's first texel in the block */
    int size[SL_SKY_MAPS_MAX];
} sl_shadow_sky_lanes;

typedef struct {
    int count;                        /* maps, 0 .. SL_SKY_MAPS_MAX */
    sl_shadow_sun maps[SL_SKY_MAPS_MAX]; /* maps[k].dir: normalize(weight[k]), or d_k (world) */
    vec3 weight[SL_SKY_MAPS_MAX];     /* m_k in the world (the environment's rotation applied) */
    vec3 site[SL_SKY_MAPS_MAX];       /* d_k, environment space: the cells' sites (sl_shadow_sky_cell) */
    int sky_sites;                    /* the sites on the sky's side: the first sky_sites */
    float cell_angle;                 /* a cell's size as the angle of a cap of 4 pi / count
                                         steradians, acos(1 - 2 / count) (the lighting's
                                         shade_lobe_map compares a lobe's cone with it) */
    /* the drawn maps' depths, one block (maps[k].depth points into it), so that one lookup
     * reads every map's texels by 32-bit offsets from one base; NULL for frames alone */
    float *block;
    int block_maps;                   /* maps the block holds */
    sl_shadow_sky_lanes lanes;        /* set by sl_shadow_sky_frames */
} sl_shadow_sky;

/* The k-th of `count` directions (environment space, unit): the first count - count / 2 over the
 * sky (z > 0), the rest over the ground (z < 0), each a hemispherical Fibonacci set. */
vec3 sl_shadow_sky_direction(int k, int count);
/* Set `count` (1 .. SL_SKY_MAPS_MAX) directions, their cells' weights from env's level 0 (a
 * lat-long map: the lighting's environment or its residual) and draw the maps on r's threads
 * (a masked material casting where its mask in tex keeps it: shadow.h).
 * `sky` is zeroed on entry or holds maps of an earlier call (reused). False (and err) on no
 * memory or a count out of range. */
bool sl_shadow_sky_build(sl_shadow_sky *sky, int count, const sl_env *env, float env_rotation_deg, sl_raster *r,
                         const sl_scene *scene, const sl_scene_textures *tex, sl_error *err);
/* The directions, their cells' weights and each map's frame and box as sl_shadow_sky_build makes
 * them (count 1 .. SL_SKY_MAPS_MAX; count set), without drawing (each map's depth is left as it
 * was): softlight-gl draws its own maps from these. False when the scene has no geometry (every
 * depth +inf). */
bool sl_shadow_sky_frames(sl_shadow_sky *sky, int count, const sl_env *env, float env_rotation_deg,
                          const sl_scene *scene);
void sl_shadow_sky_free(sl_shadow_sky *sky);
/* The cell holding direction d (environment space, unit): the nearest site on d's side of the
 * horizon (z >= 0 is the sky's), or the nearest of all when that side has none (count 1); the
 * rule by which the cells' weights take the environment's texels. */
int sl_shadow_sky_cell(const sl_shadow_sky *sky, vec3 d);
/* Map k's visibility from world point P with unit normal N: 1 open, 0 hidden; 1 where the
 * direction is below P's plane (its ray never meets the receiver). */
float sl_shadow_sky_map_visibility(const sl_shadow_sky *sky, int k, vec3 P, vec3 N);
/* V at world point P with unit normal N (world); each (may be NULL) receives every map's v_k,
 * -1 for a map not read (its weight is 0 at N). Every map in one loop, a lane a map, when they
 * are drawn (the block): V and each v_k equal, bit for bit, those of a loop over
 * sl_shadow_sky_map_visibility (tests/unit/test_sky_maps.c). */
float sl_shadow_sky_visibility(const sl_shadow_sky *sky, vec3 P, vec3 N, float *each);

/* Points for sl_shadow_sky_visibility_points, a lane a point (structure of arrays): world P and
 * unit N. A lane not used holds N = 0, which no map weighs: its V is 1 and it reads nothing. */
#define SL_SKY_POINTS 16
typedef struct {
    float px[SL_SKY_POINTS], py[SL_SKY_POINTS], pz[SL_SKY_POINTS];
    float nx[SL_SKY_POINTS], ny[SL_SKY_POINTS], nz[SL_SKY_POINTS];
} sl_shadow_sky_points;

/* V at every point of pts into V[0 .. SL_SKY_POINTS): each sl_shadow_sky_visibility(P, N)'s
 * bits. The maps one after another, each read at all the points at once: points that lie near
 * each other (a run of a row of the image) read the same few cache lines of each map, and a map
 * that faces none of them is skipped (tests/unit/test_sky_maps.c). */
void sl_shadow_sky_visibility_points(const sl_shadow_sky *sky, const sl_shadow_sky_points *pts, float *V);

/* For `count` points (directions d in environment space, world P and unit N), SL_SHADOW_LANES at
 * a time: sl_shadow_sky_map_visibility(sky, sl_shadow_sky_cell(sky, d), P, N), bit for bit, into
 * v. */
void sl_shadow_sky_cell_visibility_lanes(const sl_shadow_sky *sky, int count, const float *dx, const float *dy,
                                         const float *dz, const float *px, const float *py, const float *pz,
                                         const float *nx, const float *ny, const float *nz, float *v);

#endif
