/* gbuffer.h - the G-buffer: what rasterization leaves for the lighting stage.
 *
 * One texel per pixel, array of structs, ROW 0 IS THE BOTTOM ROW (OpenGL window
 * coordinates, docs/conventions.md "Coordinate frames"). The built-in fragment shader fills every field; the
 * lighting shader reads them and nothing else. Cleared per frame to depth = 1
 * (the far plane), which with the LESS test means "no geometry": the coverage
 * mask is exactly `depth < 1`. The vector toward the eye is not stored: it is
 * normalize(eye - position), derived where needed from the camera.
 *
 * 14 floats = 56 bytes per pixel (116 MB at 1920x1080; docs/gbuffer.md); 20 more in the extra
 * plane (occlusion, emission) for a scene that uses them (below).
 *
 * The specular lobe travels in `alpha` alone, so a scene without GGX has the texel it always had:
 * alpha >= 0 is the Phong exponent, alpha <= -1 is a GGX lobe of perceptual roughness
 * r = -1 - alpha in [0, 1] (so -1 .. -2). The gap (-1, 0) keeps r = 0 apart from Phong 0 with
 * room for rounding; nothing writes it and the lighting shader reads it as Phong 0. Float
 * targets keep the sign (GL: RGBA32F), and alpha.pfm shows the value raw. */
#ifndef SL_GBUFFER_H
#define SL_GBUFFER_H

#include <stdbool.h>

#include <softlight/gbuffer.h>
#include <softlight/glsl.h>

#include "../core/error.h"
#include "../core/image.h"
#include "../core/output_set.h"

/* sl_gbuffer_texel, sl_gbuffer_extra and sl_gbuffer are public: softlight/gbuffer.h. */

/* The extra channels, in a plane beside the texels that exists only for a scene with a material
 * that writes them (scene.h sl_material_extra): a scene without occlusion or emission keeps the
 * 56-byte texel, its memory and its speed. The textured program writes a fragment's extra texel
 * directly (its uniforms carry the plane, like an image store in GLSL), tagged with its depth;
 * the untextured program does not know the plane exists. After the draws, sl_gbuffer_extra_resolve
 * keeps the extra texels whose tag equals the G-buffer texel's depth (the fragment that won) and
 * sets the others to "none" (occlusion 1, emission 0), so readers take them as they are.
 * Drawn through sl_gbuffer_target, the plane is cleared and resolved tile by tile in the tile pass
 * (the target's tile hooks, raster.h), against the tile's depths while they are in cache; the
 * resolve is idempotent (a kept texel's tag stays its winner's depth, "none" has tag -1, never a
 * depth), so resolving after every tile pass leaves what one resolve after the draws leaves. */

/* Bytes per pixel of a G-buffer: 56, or 76 with the extra plane. */
static inline size_t sl_gbuffer_pixel_bytes(bool extra)
{
    return sizeof(sl_gbuffer_texel) + (extra ? sizeof(sl_gbuffer_extra) : 0);
}

static inline bool sl_gbuffer_covered(const sl_gbuffer_texel *t) { return t->depth < 1.0f; }
static inline sl_gbuffer_texel *sl_gbuffer_at(const sl_gbuffer *gb, int x, int y)
{
    return gb->texels + (size_t)y * (size_t)gb->width + (size_t)x;
}

/* The alpha of a GGX lobe of roughness r in [0, 1]: -1 - r (see above). */
static inline float sl_gbuffer_ggx_alpha(float r) { return -1.0f - r; }

/* sl_gbuffer_resize, sl_gbuffer_clear (the extra plane's texels "none", tag -1),
 * sl_gbuffer_use_extra (the plane for the G-buffer's size, kept while the size is) and
 * sl_gbuffer_free are public (softlight/gbuffer.h). */
/* Per frame, before the draws: every extra texel "none" with tag -1 (no depth equals it). */
void sl_gbuffer_extra_clear(sl_gbuffer *gb, int threads);
/* After the draws: extra texels whose tag differs from the texel's depth become "none". */
void sl_gbuffer_extra_resolve(sl_gbuffer *gb);
/* The same two over pixels x0..x1, y0..y1 (inclusive); the resolve takes the rectangle's depths
 * from depth[(y - y0) * stride + (x - x0)], or from the texels when depth is NULL. */
void sl_gbuffer_extra_clear_rect(sl_gbuffer *gb, int x0, int y0, int x1, int y1);
void sl_gbuffer_extra_resolve_rect(sl_gbuffer *gb, int x0, int y0, int x1, int y1, const float *depth, int stride);

/* AOVs (gbuffer_io.c): sl_gbuffer_write_aovs, sl_gbuffer_read_aovs (softlight/gbuffer.h).
 * The same files added to a command's output set (core/output_set.h), so that they are replaced
 * together with its other outputs or not at all; `dir` must exist (sl_output_set_dir). */
bool sl_gbuffer_add_aovs(const sl_gbuffer *gb, vec3 eye, const char *dir, sl_output_set *out, sl_error *err);
/* The same channels and the radiance (RGB, row 0 = top: the renderer's r.radiance) as one
 * multi-layer OpenEXR file added to the output set (softlight render --exr): R, G, B, then
 * position.X/Y/Z, normal.X/Y/Z, view.X/Y/Z, kd.R/G/B, ks.R/G/B, alpha, depth, mask, 32-bit float
 * (the same numbers as the PFMs), ZIP-compressed, rows top first. */
bool sl_gbuffer_add_exr(const sl_gbuffer *gb, vec3 eye, const sl_image *radiance, const char *path,
                        sl_output_set *out, sl_error *err);
/* sl_gbuffer_read_aovs reads position, normal, kd, ks, alpha, depth, mask (view is derived,
 * not read); a mask that disagrees with depth < 1 is an error.
 * One AOV file as written: negative values kept (sl_image_read_pfm repairs them to 0,
 * right for radiance, wrong for positions, normals and view vectors); NaN or Inf refused. */
bool sl_gbuffer_read_aov_image(const char *path, sl_image *img, sl_error *err);

#endif
