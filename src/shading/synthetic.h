/* synthetic.h - G-buffers filled analytically (ray-traced spheres), for the lighting stage's
 * tests, benchmark and trace demos without the rasterizer.
 *
 * Every covered texel holds exactly what the fragment shader would write for that surface:
 * the hit position, the exact unit normal, the sphere's material and the window depth of the
 * hit under the given camera (GL conventions: row 0 = bottom, pixel centres at +0.5, depth
 * z/w mapped to [0, 1]). Empty texels are cleared (depth 1).
 *
 * Does not: rasterize meshes (src/raster), or anti-alias. */
#ifndef SL_SYNTHETIC_H
#define SL_SYNTHETIC_H

#include <stdbool.h>

#include "../core/error.h"
#include <softlight/glsl.h>
#include "../raster/gbuffer.h"
#include "../scene/scene.h"

typedef struct {
    vec3 center;
    float radius;
    vec3 kd, ks;
    float alpha;
} sl_synthetic_sphere;


/* Resize gb to width x height and fill it with the nearest sphere hit per pixel centre.
 * *inv_view_proj (may be NULL) receives inverse(view_proj), what the lighting uniforms need. */
bool sl_gbuffer_synthetic_spheres(sl_gbuffer *gb, int width, int height, const sl_camera *camera,
                                  const sl_synthetic_sphere *spheres, int count, mat4 *inv_view_proj,
                                  int threads,
                                  sl_error *err);

#endif
