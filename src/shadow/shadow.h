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
 * moved along its normal by one texel's footprint (normal offset); percentage-closer filtering
 * over the 4x4 texels around it, weighted by a 3-texel box convolved with the bilinear tent (a
 * 3x3 grid of bilinear comparisons), so the shadow's edge is about three texels wide and moves
 * smoothly as P moves. Each tap is compared with the depth at which its own ray meets the
 * receiver's plane (the slope-scaled bias, exact per tap), less a constant bias of one texel.
 * docs/lighting.md "Shadow maps" says why these and measures them.
 *
 * Consumes: the scene's objects (every mesh, opaque: alpha masks are not read) and light
 * positions. Produces: per light, its visibility in [0, 1] at a world point. A light that does
 * not cast is fully visible. Does not: soften with the light's size (point lights have none),
 * shadow the environment (its directions, the env lights included, cast nothing), or draw
 * masked texels as holes. */
#ifndef SL_SHADOW_H
#define SL_SHADOW_H

#include <stdbool.h>

#include "core/error.h"
#include "core/options.h"
#include "raster/raster.h"
#include "scene/scene.h"

#define SL_SHADOW_CUBE_SIZE 512 /* texels along a cube face's side, inside the guard band */
#define SL_SHADOW_GUARD 3       /* texels of guard band on each side: the filter's reach + 1 */

typedef struct {
    bool casts;            /* false: the light is never shadowed (no map) */
    vec3 position;         /* the light's, as drawn */
    float *depth[6];       /* per face (+X, -X, +Y, -Y, +Z, -Z), side x side view depths, row 0 =
                              bottom; +inf where nothing was drawn */
} sl_shadow_cube;

typedef struct {
    int side;              /* SL_SHADOW_CUBE_SIZE + 2 SL_SHADOW_GUARD */
    float proj;            /* a face's projection scale: NDC x = proj * (right . d) / (axis . d) */
    vec3 axis[6], right[6], up[6]; /* each face's frame: the direction it looks, its x and y */
    int count;             /* lights, 0 .. SL_LIGHTING_MAX_LIGHTS */
    sl_shadow_cube cubes[SL_LIGHTING_MAX_LIGHTS];
} sl_shadow_maps;

/* Draw the cube maps of the scene's point lights that cast: light i casts when `all` is set or
 * its "shadow" key is. `maps` is zeroed on entry or holds maps of an earlier call (reused); the
 * faces are drawn by r, on its threads. False (and err) on no memory. */
bool sl_shadow_build(sl_shadow_maps *maps, sl_raster *r, const sl_scene *scene, bool all, sl_error *err);
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

#endif
