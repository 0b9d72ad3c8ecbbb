/* softlight/gbuffer.h - the G-buffer: what rasterization leaves for the lighting stage.
 *
 * One texel per pixel, ROW 0 IS THE BOTTOM ROW (GL window coordinates). Cleared per frame to
 * depth = 1 (the far plane), so the coverage mask is exactly depth < 1. The specular lobe
 * travels in `alpha`: alpha >= 0 is a Phong exponent, alpha <= -1 a GGX lobe of perceptual
 * roughness -1 - alpha. A scene whose materials use occlusion or emission adds a plane of extra
 * texels beside (sl_gbuffer.extra). docs/gbuffer.md has the layout. */
#ifndef SOFTLIGHT_GBUFFER_H
#define SOFTLIGHT_GBUFFER_H

#include <stdbool.h>

#include <softlight/image.h>
#include <softlight/raster.h>
#include <softlight/scene.h>
#include <softlight/types.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sl_gbuffer_texel {
    sl_vec3 position; /* world space */
    sl_vec3 normal;   /* unit, world space */
    sl_vec3 kd;       /* linear RGB diffuse albedo */
    sl_vec3 ks;       /* linear RGB Schlick F0 */
    float alpha;      /* the lobe parameter: >= 0 the Phong exponent; <= -1 GGX with roughness
                         r = -1 - alpha */
    float depth;      /* window depth in [0,1]; 1 = nothing drawn */
} sl_gbuffer_texel;

/* The extra channels: after the draws, each texel is that of the fragment that won the depth
 * test, or "none" (occlusion 1, emission 0). */
typedef struct sl_gbuffer_extra {
    float occlusion;    /* scales the image-based terms (diffuse, specular, env lights), not point lights */
    sl_vec3 emissive;   /* linear RGB radiance added to the pixel's */
    float depth;        /* the writer's window depth: the tag the resolve compares */
} sl_gbuffer_extra;

typedef struct sl_gbuffer {
    int width, height;
    sl_gbuffer_texel *texels; /* width * height, row 0 = bottom */
    sl_gbuffer_extra *extra;  /* NULL, or width * height extra texels */
    sl_vec4 *cone;            /* NULL, or width * height: the ambient occlusion pass's visibility
                                 cone per texel, its axis (the bent normal, unit, world space) in
                                 xyz and its AO in w (src/occlusion/gtao.h; the lighting reads it
                                 for the image-based terms) */
    sl_vec2 *reflection;      /* NULL, or width * height: the reflection occlusion pass's share of
                                 each texel's specular lobe whose rays leave the scene in x, and
                                 how many rays that share is over in y (1 .. 5; 0 for an empty
                                 texel) (src/occlusion/reflection.h; the lighting reads it for
                                 the image-based specular) */
    sl_vec3 *facet;           /* NULL, or width * height: the world-space unit normal of the triangle
                                 drawn at each texel, on the camera's side (0 where empty): the
                                 surface itself, which a smooth mesh's or a normal map's normal
                                 leans away from (sl_target.facets; the reflection occlusion asks for
                                 it, src/occlusion/reflection.h) */
} sl_gbuffer;

/* Allocate for width x height (no-op when the size is unchanged; contents undefined until
 * cleared). An empty {0} sl_gbuffer is a valid start. */
SL_API bool sl_gbuffer_resize(sl_gbuffer *gb, int width, int height, sl_error *err);
/* Per frame: every field 0, depth 1 (and the extra plane's texels "none"). */
SL_API void sl_gbuffer_clear(sl_gbuffer *gb, int threads);
/* Allocate the extra plane (on) or free it. */
SL_API bool sl_gbuffer_use_extra(sl_gbuffer *gb, bool on, int threads, sl_error *err);
/* Allocate the facet plane (on: sl_raster_scene fills it from then on) or free it. */
SL_API bool sl_gbuffer_use_facet(sl_gbuffer *gb, bool on, sl_error *err);
SL_API void sl_gbuffer_free(sl_gbuffer *gb);
/* The G-buffer as a render target (depth in the texel's depth field; with the extra plane, its
 * tile hooks clear and resolve the plane; with the facet plane, the target's facets, whose
 * facet_view_proj the caller sets to the camera's view-projection). */
SL_API sl_target sl_gbuffer_target(sl_gbuffer *gb);

/* Clear the G-buffer and draw every object of the scene with the built-in programs from `cam`,
 * both faces. The G-buffer must already be sized. */
SL_API bool sl_raster_scene(sl_raster *r, const sl_scene *scene, const sl_camera *cam, sl_gbuffer *gb,
                            sl_error *err);

/* The channels as PFM files in `dir`, shown upright by a PFM viewer: position.pfm, normal.pfm,
 * view.pfm (normalize(eye - position), 0 where empty), kd.pfm, ks.pfm, alpha.pfm, depth.pfm,
 * mask.pfm (1 where covered); with the extra plane occlusion.pfm and emissive.pfm, with the cone
 * plane bent.pfm and ao.pfm, with the facet plane facet.pfm; and the reverse (resizes gb to the
 * files' size and takes each plane whose files are there). */
SL_API bool sl_gbuffer_write_aovs(const sl_gbuffer *gb, sl_vec3 eye, const char *dir, sl_error *err);
SL_API bool sl_gbuffer_read_aovs(const char *dir, sl_gbuffer *gb, sl_error *err);
/* Debug view: normal * 0.5 + 0.5 as RGB, row 0 = top, 0 where empty. Allocates img. */
SL_API bool sl_gbuffer_normal_image(const sl_gbuffer *gb, sl_image *img, sl_error *err);

#ifdef __cplusplus
}
#endif

#endif
