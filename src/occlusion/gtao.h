/* gtao.h - ambient occlusion of the environment, from the G-buffer alone: how much of each
 * surface point's cosine-weighted hemisphere the geometry drawn around it hides.
 *
 * Method: ground-truth-based ambient occlusion (GTAO; Jimenez, Wu, Pesce, Jarabo, "Practical
 * Realtime Strategies for Accurate Indirect Occlusion", 2016). For each covered pixel, a few
 * screen-space slices through the pixel, each a plane containing the view vector V; along each
 * slice the G-buffer's positions within `radius` world units give the highest horizon on either
 * side, and the cosine-weighted visible arc between the two horizons (clamped to the hemisphere
 * about the normal) is integrated in closed form. The slices' mean is
 *   AO = 1/pi * integral over the hemisphere of visible(w) (N.w) dw,
 * exactly the factor by which occlusion scales the irradiance under a constant environment, so
 * the diffuse term E(N) Kd / pi becomes AO E(N) Kd / pi.
 *
 * The same arcs give the bent normal, the cosine-weighted mean visible direction: per side of a
 * slice, integral (cos t V + sin t d) cos(t - n) |sin t| dt in closed form (bent_arc in gtao.c),
 * summed over the slices with the AO's weights and blurred with it. With the AO it describes the
 * visible directions as a cone (axis the bent normal, cosine-weighted share the AO), from which
 * the lighting takes its specular occlusion (src/occlusion/specular_occlusion.h).
 *
 * Consumes: a G-buffer (row 0 = bottom) and the camera that drew it. Produces: AO in [0, 1] per
 * texel, multiplied into the extra plane's occlusion (which the lighting stage applies to the
 * diffuse term, and which a material's occlusion map has already written): a texel that sees
 * everything keeps its occlusion; and the cone plane (sl_gbuffer.cone: bent normal, AO), which it
 * allocates the first time. The extra plane must exist.
 *
 * Does not: see what the G-buffer does not hold (surfaces behind others or off screen count as
 * open: screen-space occlusion's known blind spot), treat thickness (a thin pole hides the sky
 * behind it as a wall would), or shadow point lights. docs/lighting.md "Ambient occlusion"
 * measures it against a ground truth that traces the scene. */
#ifndef SL_GTAO_H
#define SL_GTAO_H

#include <stdbool.h>

#include "core/error.h"
#include "raster/gbuffer.h"
#include "scene/scene.h"

#define SL_GTAO_SLICES 2      /* slices per sample (each turned by the sample's pattern entry) */
#define SL_GTAO_STEPS 4       /* G-buffer reads per side of a slice */
#define SL_GTAO_MAX_SCREEN 0.25f /* the largest screen radius, as a share of the image height */
/* The blur's test of "the same surface": within this share of the view depth of the texel's
 * tangent plane, and normals within this cosine. */
#define SL_GTAO_BLUR_DEPTH 0.02f
#define SL_GTAO_BLUR_NORMAL 0.8f
/* shaders/gtao.frag and gtao_blur.frag are the GLSL twin (softlight-gl), given these as #defines. */

/* The camera as the pass sees it: its orthonormal frame and the screen radius in pixels of one
 * world unit at view depth 1, for an image `height` pixels tall. softlight-gl's twin
 * (src/gl/occlusion_pass.c) takes its uniforms from here, so both march the same screen. */
typedef struct {
    vec3 eye, forward, right, up;
    float pixels_per_unit;
} sl_gtao_view;
sl_gtao_view sl_gtao_view_of(const sl_camera *cam, int height);

/* The pass's working planes (the half-resolution grid's planes and its channels, 15 floats a
 * grid texel), kept by the caller from one frame to the next, as the reflection occlusion's are
 * (src/occlusion/reflection.h sl_reflection_scratch: memory taken afresh each frame costs the
 * kernel's first-touch faults). Zeroed: empty; grown by sl_gtao_apply as a frame needs; freed
 * by sl_gtao_scratch_free. */
typedef struct {
    size_t planes_floats, grid_floats; /* capacities */
    float *planes, *grid;
} sl_gtao_scratch;
void sl_gtao_scratch_free(sl_gtao_scratch *s);

/* Multiply every covered texel's extra.occlusion by its AO within `radius` world units (> 0)
 * around it and write its cone (gb->cone, allocated when NULL; an empty texel gets its normal and
 * AO 1); `threads` OpenMP threads (0: all), with `scratch`'s planes (NULL: the call's own, freed
 * before it returns). False (and err) without an extra plane, with a radius that is not
 * positive and finite, or out of memory. */
bool sl_gtao_apply(sl_gbuffer *gb, const sl_camera *cam, float radius, int threads, sl_gtao_scratch *scratch,
                   sl_error *err);

/* The cone of one texel (x, y), as sl_gtao_apply computes it: bent normal in xyz, AO in w,
 * through the plain per-texel march and blur (texel_ao and blurred() in gtao.c), the reference
 * tests/unit/test_gtao.c holds the frame's vector ones to bit for bit. */
sl_vec4 sl_gtao_texel(const sl_gbuffer *gb, const sl_camera *cam, float radius, int x, int y);

#endif
