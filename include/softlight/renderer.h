/* softlight/renderer.h - one frame of a scene through every stage: the G-buffer (raster), linear
 * HDR radiance (image-based and point lighting) and the tone-mapped display image in [0,1].
 *
 * The renderer owns what outlives frames: the environment with its mips and irradiance, the
 * materials' textures, the G-buffer and the images, each built once and reused. */
#ifndef SOFTLIGHT_RENDERER_H
#define SOFTLIGHT_RENDERER_H

#include <stdbool.h>

#include <softlight/gbuffer.h>
#include <softlight/image.h>
#include <softlight/scene.h>
#include <softlight/types.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Settings; zero means the scene's value (size, samples, exposure, contrast). */
typedef struct sl_renderer_options {
    int width, height; /* 1 .. 8192 */
    int samples;       /* specular samples N, 1 .. 1024 */
    float exposure;    /* the tone map's exposure e */
    float contrast;    /* the tone map's contrast c (exponent c / 2.2) */
    int threads;       /* 0 = all cores */
} sl_renderer_options;

typedef struct sl_renderer sl_renderer;

/* A renderer of `scene` (which must outlive it): loads the environment, builds its mips and
 * irradiance and decodes the materials' textures. opt may be NULL (all the scene's). */
SL_API sl_renderer *sl_renderer_create(const sl_scene *scene, const sl_renderer_options *opt, sl_error *err);
SL_API void sl_renderer_destroy(sl_renderer *r); /* NULL is fine */

/* One frame from `cam` (NULL = the scene's camera): raster, lighting, tone map. */
SL_API bool sl_renderer_frame(sl_renderer *r, const sl_camera *cam, sl_error *err);
/* The lighting and tone map of sl_renderer_frame on a G-buffer the caller drew (its own programs
 * into sl_gbuffer_target, or sl_raster_scene) as seen from `cam` (NULL = the scene's camera): the
 * scene's environment and lights shade it into sl_renderer_radiance and sl_renderer_display. gb
 * must have the renderer's size (SL_ERR_RANGE otherwise); sl_renderer_gbuffer is left as it was. */
SL_API bool sl_renderer_light(sl_renderer *r, const sl_gbuffer *gb, const sl_camera *cam, sl_error *err);
/* Change the render size (reallocates only when it changes). */
SL_API bool sl_renderer_resize(sl_renderer *r, int width, int height, sl_error *err);
/* Replace the environment (an .hdr, .exr or .pfm lat-long map). On failure the old one stays. */
SL_API bool sl_renderer_set_environment(sl_renderer *r, const char *path, sl_error *err);

/* The last frame: linear radiance (3 channels, row 0 = top), the display image (3 channels in
 * [0,1], row 0 = top, ready for sl_image_write_png) and the G-buffer. Owned by the renderer. */
SL_API const sl_image *sl_renderer_radiance(const sl_renderer *r);
SL_API const sl_image *sl_renderer_display(const sl_renderer *r);
SL_API const sl_gbuffer *sl_renderer_gbuffer(const sl_renderer *r);

#ifdef __cplusplus
}
#endif

#endif
