/* visibility.h - what a surface point sees: every object's triangles in world space, traced with
 * Embree 3, for the ground truth's visibility (ground_truth_image.h, `softlight truth
 * --visibility`). It lives in the shading stage beside the truth it serves: it reads the scene's
 * meshes and objects (src/scene) the way the rasterizer places them (position = model * p, in
 * float), and answers occlusion queries; nothing in the lighting pass calls it.
 *
 * Geometry: every object's mesh (OBJ meshes, built-in sphere, plane and box, models' meshes),
 * each triangle as the rasterizer draws it, both sides (the raster culls nothing). A masked
 * material (discard below a cutoff) occludes where its mask keeps the surface: an Embree filter
 * reads the mask at the hit's texture coordinate (raster/coverage.h, as the shadow maps' depth
 * programs do), and a ray goes on through a cut-out. Without the textures every caster is opaque.
 *
 * Rays: a ray leaves P + offset * Ng, where Ng is the geometric normal of the triangle the eye
 * sees at P turned towards the eye (found by tracing the eye ray, sl_visibility_surface) and
 * offset = 1e-4 max(min(1, X / 10), |P|max) + 1e-6 X, X the scene's largest absolute vertex
 * coordinate: above the float error of a G-buffer position (a few ulps of P and of the triangle's
 * vertices), well below any feature of the shipped scenes (0.1 mm on a floor 8 units wide), and
 * in proportion to a scene under 10 units across, so that one modelled in millimetres has the
 * truth it has in metres.
 *
 * Threads: the build uses `threads` (Embree's own build threads, counted by the caller); every
 * query only reads the built structure, so callers may query from many threads at once.
 * Without Embree (configured with -DSL_EMBREE=OFF, or libembree-dev not installed),
 * sl_visibility_available is false and sl_visibility_create fails with one message. */
#ifndef SL_VISIBILITY_H
#define SL_VISIBILITY_H

#include <stdbool.h>
#include <stdint.h>

#include "../core/error.h"
#include "../raster/gbuffer_textured.h"
#include "../scene/scene.h"

typedef struct sl_visibility sl_visibility;

/* Whether this build traces visibility (was built with Embree). */
bool sl_visibility_available(void);

/* The scene's triangles, transformed and built into Embree's structure, masked casters filtered
 * by their masks in tex (NULL: every caster opaque; tex must outlive the structure); NULL (and
 * err) without Embree, on a mesh or object out of range, or when Embree fails. A scene without
 * triangles gives a structure that occludes nothing. */
sl_visibility *sl_visibility_create(const sl_scene *scene, const sl_scene_textures *tex, int threads, sl_error *err);
void sl_visibility_free(sl_visibility *v); /* NULL is fine */

/* FNV-1a 64 of the world-space triangles (each object's transformed vertices and indices) and
 * of each masked caster's mask in tex and texture coordinates: part of the truth's cache key,
 * since geometry the camera does not see still occludes. Needs no Embree and builds nothing. */
uint64_t sl_visibility_scene_hash(const sl_scene *scene, const sl_scene_textures *tex);
long sl_visibility_triangle_count(const sl_visibility *v);
/* The distance a ray's origin at P is moved along Ng. */
double sl_visibility_offset(const sl_visibility *v, vec3 p);

/* The unit geometric normal at P of the triangle the eye ray (eye -> P) hits within 0.1% of
 * P's distance, turned towards the eye, into ng[3]. False when it hits nothing there (ng
 * untouched). */
bool sl_visibility_surface(const sl_visibility *v, vec3 eye, vec3 p, double ng[3]);

/* Whether anything lies on the ray from `org` along unit `dir` within (0, tmax] (tmax INFINITY:
 * a direction). */
bool sl_visibility_occluded(const sl_visibility *v, const double org[3], const double dir[3], double tmax);

#endif
