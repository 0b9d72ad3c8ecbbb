/* shadow.h - shadow maps: which lights a surface point sees, from depth maps the rasterizer
 * (src/raster) draws from each light with a depth-only program.
 *
 * A point light that casts gets a cube map: six square faces of SL_SHADOW_CUBE_SIZE texels
 * inside a guard band of SL_SHADOW_GUARD texels on every side (each face's frustum widened to
 * cover it), so a filter kernel that steps past a face's edge still reads the face's own texels
 * and no lookup crosses a seam. A texel holds the distance along the face's axis from the light
 * to the nearest surface (the view depth, 1/w of the rasterizer's fragment), so the comparison
 * and its bias are in world units.
 *
 * Lookup (sl_shadow_point_visibility): the face of the major axis of P - light, the receiver
 * moved along its normal by one texel's footprint times the sine of its angle to the light
 * (normal offset, sl_shadow_offset_share); percentage-closer filtering
 * over the 4x4 texels around it, weighted by a 3-texel box convolved with the bilinear tent (a
 * 3x3 grid of bilinear comparisons), so the shadow's edge is about three texels wide and moves
 * smoothly as P moves. Each tap is compared with the depth at which its own ray meets the
 * receiver's plane (the slope-scaled bias, exact per tap), less a constant bias of one texel.
 * docs/lighting.md "Shadow maps" says why these and measures them.
 *
 * The env lights (src/ibl/env_lights.h: the environment's brightest texels, summed exactly) cast
 * through orthographic maps. A sun spans a few adjacent texels, so the lights are clustered by
 * direction, brightest first: a light within SL_SHADOW_SUN_CLUSTER_DEG of a cluster's first
 * (brightest) light joins it, another starts a cluster while there are fewer than
 * SL_SHADOW_SUN_MAX. A cluster that carries under SL_SHADOW_SUN_MIN_SHARE of the environment's
 * luminous power (a studio's brightest texels) is dropped: its shadow could darken a pixel by
 * about that share of its light at most, not worth a map and a lookup a pixel. Each remaining
 * cluster gets one map of SL_SHADOW_SUN_SIZE texels a side, drawn along
 * its power-weighted mean direction (the environment's rotation applied: world space) over the
 * scene's bounds in light space, so the whole scene is in it. A texel holds the depth along the
 * map's axis. Lights outside the mapped clusters stay unshadowed (visibility 1).
 *
 * Lookup (sl_shadow_sun_visibility): the same normal offset, per-tap receiver plane and constant
 * bias as the cube maps, in the map's texels, and the same 3-texel box of bilinear comparisons.
 * The filter is not widened by the cluster's angular spread: a sun of a few lat-long texels
 * (city.hdr's: under a degree) makes a penumbra under a texel wide for occluders a few units
 * above the receiver.
 *
 * Both lookups also come for a run of points at once, a SIMD lane a point, each lane the
 * one-point lookup's bits (sl_shadow_point_visibility_lanes, sl_shadow_sun_visibility_lanes):
 * the batched lighting's span; the one-point lookups are the twins of lighting.frag's.
 *
 * Consumes: the scene's objects (every mesh, opaque: alpha masks are not read), light positions
 * and the env lights' directions. Produces: per light, its visibility in [0, 1] at a world
 * point. A light that does not cast is fully visible. Does not: soften a point light with its
 * size (point lights have none), shadow the environment's residual (the irradiance and the
 * samples see every direction open: the ambient occlusion's job, src/occlusion), or draw masked
 * texels as holes. */
#ifndef SL_SHADOW_H
#define SL_SHADOW_H

#include <math.h>
#include <stdbool.h>

#include "core/error.h"
#include "core/options.h"
#include "ibl/env_lights.h"
#include "raster/gbuffer_textured.h"
#include "raster/raster.h"
#include "scene/scene.h"

#define SL_SHADOW_CUBE_SIZE 512 /* texels along a cube face's side, inside the guard band */
#define SL_SHADOW_GUARD 3       /* texels of guard band on each side: the filter's reach + 1 */

typedef struct {
    bool casts;            /* false: the light is never shadowed (no map) */
    vec3 position;         /* the light's, as drawn */
    float *depth[6];       /* per face (+X, -X, +Y, -Y, +Z, -Z), side x side view depths, row 0 =
                              bottom; +inf where nothing was drawn */
    float *block;          /* the six faces one after another, depth[f] = block + f side^2 (a
                              lanes lookup reads any face through one base) */
} sl_shadow_cube;

#define SL_SHADOW_SUN_MAX 4            /* the most env-light clusters that get a map */
#define SL_SHADOW_SUN_SIZE 2048        /* texels along an env-light map's side */
#define SL_SHADOW_SUN_CLUSTER_DEG 5.0f /* a light this close to a cluster's brightest joins it */
#define SL_SHADOW_SUN_MIN_SHARE 0.01   /* a cluster with less of the environment's luminous power gets no map */
/* A sun's glow: the environment's samples (the residual the env lights leave) within this angle
 * beyond the cap a cluster's lights spread over take the cluster's map's visibility too
 * (src/shading/lighting_internal.h shade_glow; docs/lighting.md "Shadow maps", why 7 degrees).
 * A build defining another (a negative one: no glow) is for bench/visibility-variants.sh's
 * comparison. */
#ifndef SL_SHADOW_GLOW_DEG
#define SL_SHADOW_GLOW_DEG 7.0f
#endif

/* One orthographic map (an env-light cluster's, or a sky direction's: src/shadow/sky.h):
 * x = right . P, y = up . P, depth = axis . P (axis = -dir). */
typedef struct {
    vec3 dir;              /* world, towards the lights (their power-weighted mean) or the sky */
    vec3 axis, right, up;  /* the map's frame: the direction it looks, its x and y */
    float x0, y0, z0;      /* the box's lowest corner in the frame */
    float sx, sy, sz;      /* its extent along right, up and axis */
    float stepx, stepy;    /* world units per texel along right and up: sx / size, sy / size */
    float texel;           /* the larger of a texel's two sides, world units */
    float spread;          /* tangent of the largest angle between a light and dir (report) */
    int lights;            /* env lights in the cluster */
    int size;              /* texels along the map's side (SL_SHADOW_SUN_SIZE for an env light's) */
    float *depth;          /* size^2 depths along axis, in tiles (sl_shadow_tile_index), row 0 =
                              low y; +inf empty */
} sl_shadow_sun;

/* An orthographic map's texels are stored in tiles of SL_SHADOW_TILE x SL_SHADOW_TILE, 64 bytes
 * (a cache line), the tiles row after row and each tile's texels row after row: a lookup's
 * percentage-closer taps lie in fewer lines than in rows of texels, and the points of a run of
 * an image row, which land along a line across the map in any direction, touch fewer lines too.
 * Texel (x, y)'s place in a map of size x size (size a multiple of the tile). */
#define SL_SHADOW_TILE 4
static inline int sl_shadow_tile_index(int x, int y, int size)
{
    const int tiles = size / SL_SHADOW_TILE;
    return ((y / SL_SHADOW_TILE) * tiles + x / SL_SHADOW_TILE) * (SL_SHADOW_TILE * SL_SHADOW_TILE) +
           (y % SL_SHADOW_TILE) * SL_SHADOW_TILE + x % SL_SHADOW_TILE;
}
/* A texel index clamped onto a map's 0 .. last (the lookups' taps past its edge read the edge). */
static inline int sl_shadow_clamp_index(int i, int last)
{
    int lo = i < 0 ? 0 : i;
    return lo > last ? last : lo;
}
_Static_assert(SL_SHADOW_SUN_SIZE % SL_SHADOW_TILE == 0, "an env light's map is a whole number of tiles");

typedef struct {
    int side;              /* SL_SHADOW_CUBE_SIZE + 2 SL_SHADOW_GUARD */
    float proj;            /* a face's projection scale: NDC x = proj * (right . d) / (axis . d) */
    vec3 axis[6], right[6], up[6]; /* each face's frame: the direction it looks, its x and y */
    int count;             /* lights, 0 .. SL_LIGHTING_MAX_LIGHTS */
    sl_shadow_cube cubes[SL_LIGHTING_MAX_LIGHTS];
} sl_shadow_maps;

/* The env lights' maps: one per cluster. */
typedef struct {
    int count;             /* maps, 0 .. SL_SHADOW_SUN_MAX */
    sl_shadow_sun maps[SL_SHADOW_SUN_MAX];
    int env_light_count;   /* the env lights the clusters were made from */
    signed char env_light_sun[SL_ENV_LIGHTS_MAX]; /* each env light's map, -1: none (unshadowed) */
} sl_shadow_suns;

/* Draw the cube maps of the scene's point lights that cast: light i casts when `all` is set or
 * its "shadow" key is. `maps` is zeroed on entry or holds maps of an earlier call (reused); the
 * faces are drawn by r, on its threads. A masked material casts where its mask in tex keeps it
 * (raster/coverage.h); tex NULL: every caster opaque (the same for every map below). False (and
 * err) on no memory. */
bool sl_shadow_build(sl_shadow_maps *maps, sl_raster *r, const sl_scene *scene, const sl_scene_textures *tex, bool all,
                     sl_error *err);
/* Cluster the env lights (environment space, rotated by env_rotation_deg about +Z into the
 * world as the lighting does) and draw a map per cluster, up to SL_SHADOW_SUN_MAX, on r's
 * threads; lights == NULL or without any leaves no map. `suns` is zeroed on entry or holds maps
 * of an earlier call (reused). False (and err) on no memory. */
bool sl_shadow_suns_build(sl_shadow_suns *suns, sl_raster *r, const sl_scene *scene, const sl_scene_textures *tex,
                          const sl_env_lights *lights, float env_rotation_deg, sl_error *err);
void sl_shadow_suns_free(sl_shadow_suns *suns);
/* The clusters and each map's frame and box as sl_shadow_suns_build makes them, without drawing
 * (each map's depth is left as it was): softlight-gl draws its own maps from these. False when
 * there is no map or the scene has no geometry (every depth +inf). */
bool sl_shadow_suns_frames(sl_shadow_suns *suns, const sl_scene *scene, const sl_env_lights *lights,
                           float env_rotation_deg);
/* The world -> clip transform sl_shadow_suns_build draws a map with: x, y and the depth along the
 * axis over the map's box mapped linearly onto [-1, 1] (the window depth is then (depth along
 * the axis - z0) / sz). */
mat4 sl_shadow_sun_view_proj(const sl_shadow_sun *sun);
/* Frame each of maps[0 .. count - 1] from its dir (set) over the scene's bounds, `size` texels a
 * side, and draw it on r's threads: the env lights' maps and the sky visibility maps
 * (src/shadow/sky.h) both. Each map's depth is allocated when NULL (kept at this size otherwise)
 * and stored in tiles (sl_shadow_tile_index). False (and err) on a size that is not a multiple of
 * SL_SHADOW_TILE, no memory or a failed draw. */
bool sl_shadow_ortho_build(sl_shadow_sun *maps, int count, int size, sl_raster *r, const sl_scene *scene,
                           const sl_scene_textures *tex, sl_error *err);
/* The normal offset's share of its full length (a texel's footprint) for a receiver whose normal
 * makes cosine c with the direction to the light: the sine, sqrt(1 - c^2). The offset keeps a
 * receiver off its own texels where its footprint spans a range of depth, which is where the
 * light grazes it (all of it); a receiver that faces the light has no such span, and the offset
 * would only move it towards what stands in front of it (a ball's underside a few texels over a
 * floor, seen from below by a sky map, reads lit). Every lookup takes it: the cube maps, the
 * env lights' maps and the sky maps (shadow.c, sky.c). */
/* GLSL: shadow_offset_share */
static inline float sl_shadow_offset_share(float c)
{
    float s = 1.0f - c * c;
    return sqrtf(s > 0.0f ? s : 0.0f);
}

/* Where a receiver, world point P with unit normal N, falls on orthographic map `map`: the point
 * moved along N by `offset` (world units) times sl_shadow_offset_share of N and the axis, in the
 * map's frame (xq, yq, zq); its texel coordinates (texel centres at integers) as floor (fx, fy)
 * and fraction (tx, ty); world units per texel; and the slope of the receiver's plane (through
 * the moved point, normal N), whose depth at a lateral offset (dx, dy) from it is
 * zq + gx dx + gy dy: each tap of a lookup is compared with the receiver's own depth under it, so
 * a tilted plane needs no slope-sized bias. False where the map has nothing to say: N.axis >= 0
 * (every tap's ray runs along the axis: the surface faces away from the map's light or grazes
 * it, and the plane is never met) or a point off the map (or non-finite). The env lights' lookup
 * (sl_shadow_sun_visibility) and the sky maps' (sky.c) start here. */
typedef struct {
    float xq, yq, zq;
    float fx, fy, tx, ty;
    float stepx, stepy;
    float gx, gy;
} sl_shadow_ortho_at;

static inline bool sl_shadow_ortho_locate(const sl_shadow_sun *map, vec3 P, vec3 N, float offset,
                                          sl_shadow_ortho_at *at)
{
    float na = dot(N, map->axis);
    if (!(na < -1e-6f))
        return false;
    vec3 q = add(P, scale(N, offset * sl_shadow_offset_share(na)));
    at->xq = dot(q, map->right);
    at->yq = dot(q, map->up);
    at->zq = dot(q, map->axis);
    at->stepx = map->stepx;
    at->stepy = map->stepy;
    float ux = (at->xq - map->x0) / at->stepx - 0.5f, uy = (at->yq - map->y0) / at->stepy - 0.5f;
    at->fx = floorf(ux);
    at->fy = floorf(uy);
    if (!(fabsf(at->fx) < 1e6f && fabsf(at->fy) < 1e6f))
        return false;
    at->tx = ux - at->fx;
    at->ty = uy - at->fy;
    at->gx = -dot(N, map->right) / na;
    at->gy = -dot(N, map->up) / na;
    return true;
}

/* The frames and boxes sl_shadow_ortho_build gives maps[0 .. count - 1], without drawing (each
 * map's depth is left as it was): softlight-gl draws its own sky maps from these. False when the
 * scene has no geometry (every depth +inf). */
bool sl_shadow_ortho_frames(sl_shadow_sun *maps, int count, int size, const sl_scene *scene);
/* Does any of the scene's point lights cast (so that a frame needs maps)? */
bool sl_shadow_any(const sl_scene *scene, bool all);
void sl_shadow_free(sl_shadow_maps *maps);
/* The view-projection sl_shadow_build draws face f (0 .. 5) of a cube at light position L with,
 * over this scene (its depth range comes from the scene's box): softlight-gl draws its own maps
 * with it. False when the scene has no geometry (every depth +inf) or f is out of range. */
bool sl_shadow_face_view_proj(const sl_scene *scene, vec3 L, int f, mat4 *vp);

/* Visibility of point light i from world point P with unit normal N facing the light's side:
 * 1 lit, 0 shadowed, between on a filtered edge; 1 for a light without a map. */
float sl_shadow_point_visibility(const sl_shadow_maps *maps, int i, vec3 P, vec3 N);
#define SL_SHADOW_LANES 32 /* the most points of one lanes lookup (the batched lighting's span) */
/* sl_shadow_point_visibility of light i at `count` points (world positions px, py, pz, unit
 * normals nx, ny, nz), SL_SHADOW_LANES at a time, bit for bit, into vis. */
void sl_shadow_point_visibility_lanes(const sl_shadow_maps *maps, int i, int count, const float *px, const float *py,
                                      const float *pz, const float *nx, const float *ny, const float *nz, float *vis);
/* Visibility of env-light map s (0 .. count - 1) from world point P with unit normal N: 1
 * lit, 0 shadowed; 1 for a normal facing away from the lights (they add nothing there). */
float sl_shadow_sun_visibility(const sl_shadow_suns *suns, int s, vec3 P, vec3 N);
/* sl_shadow_sun_visibility of map s at `count` points (world positions px, py, pz, unit normals
 * nx, ny, nz), SL_SHADOW_LANES at a time, bit for bit, into vis. */
void sl_shadow_sun_visibility_lanes(const sl_shadow_suns *suns, int s, int count, const float *px, const float *py,
                                    const float *pz, const float *nx, const float *ny, const float *nz, float *vis);

#endif
