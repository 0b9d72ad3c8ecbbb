/* raster.h - the rasterization pipeline: C vertex and fragment shaders, clipping,
 * fixed-point setup, tile binning and the parallel tile rasterizer.
 *
 * Consumes: a triangle mesh (sl_mesh: positions, normals, texcoords, indices), a
 *           program (vertex + fragment shader) with uniforms, and a render target.
 * Produces: texels of the target, written by the fragment shader, in GL window
 *           coordinates (row 0 = bottom, pixel centres at x+0.5, y+0.5).
 *
 * One draw call runs: vertex shader over every vertex -> homogeneous clipping
 * (near, far; guard-band planes only for triangles that leave the guard band) ->
 * triangle setup (8 sub-pixel bits, top-left rule, optional back-face culling,
 * degenerate and non-finite triangles dropped) -> binning into tiles -> per tile,
 * in parallel: clear (when asked), coverage tile -> 8x8 block -> row span -> pixel,
 * early depth test (LESS), then the fragment shader with perspective-correct
 * varyings, once per row span (fragment_span) or per fragment. A program that takes
 * derivatives (sl_program.derivatives) runs in aligned 2x2 quads instead, with helper
 * invocations for the quad's uncovered or occluded pixels; one that may discard
 * (sl_program.discards) writes depth and texel after the shader, only if it did not
 * discard. Programs with neither flag take the span and per-pixel paths unchanged.
 * A draw list bins several draws together and draws each tile once for all of them.
 * Primitive order within a tile is kept, so the result is bitwise identical for any
 * thread count and tile size, and the span path's to the per-pixel path's
 * (sl_raster_desc.plain), quads included. The shader API, the fragment built-ins
 * (softlight/program.h, spelled dFdx, dFdy, fwidth, discard by softlight/glsl.h) and how derivatives of any value a C
 * shader computes are found are described in docs/shader-api.md.
 *
 * Depth lives in the target's texels at `depth_offset` (the G-buffer texel's depth
 * field); while a tile is rasterized it is copied into a tile-local plane.
 *
 * Does not: blend, multisample, stencil, scissor, draw lines or points, or
 * clip against user planes. Fragment shaders cannot move depth. */
#ifndef SL_RASTER_H
#define SL_RASTER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <softlight/glsl.h>
#include <softlight/raster.h>

#include "../core/error.h"
#include "../core/options.h" /* SL_RASTER_MAX_SIZE, SL_TILE_DEFAULT/MIN/MAX */
#include "../scene/scene.h"
#include "gbuffer.h"

/* The program contract (sl_vertex_in, sl_fragment_in, the span and quad forms, sl_program) is
 * softlight/program.h; targets, draws, stats and the rasterizer's entry points softlight/raster.h. */
_Static_assert(SL_SPAN_MAX == SL_TILE_MAX, "a span is at most a tile's row");

/* ---- the built-in G-buffer program (gbuffer_shader.c; GLSL twin: shaders/gbuffer.vert/.frag) ---- */
typedef struct {
    mat4 uModel;
    mat4 uViewProj;
    mat3 uNormalMatrix; /* transpose(inverse(mat3(uModel))) */
    vec3 uKd, uKs;
    float uAlpha;
} sl_gbuffer_uniforms;

/* Varyings of the built-in pair: vWorldPos (3 floats), then vNormal (3 floats). */
#define SL_GBUFFER_VARYINGS 6
void sl_gbuffer_vert(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings);
void sl_gbuffer_frag(const void *uniforms, const sl_fragment_in *in, void *texel);
void sl_gbuffer_frag_span(const void *uniforms, const sl_fragment_span *span);
extern const sl_program sl_gbuffer_program;

/* Keep the G-buffer's extra plane (cleared and resolved per frame with the texels) even when no
 * drawn material writes it: a pass after the draws writes it (ambient occlusion, src/occlusion). */
void sl_raster_keep_extra(sl_raster *r, bool keep);
bool sl_raster_keeps_extra(const sl_raster *r);

/* Fill the uniforms from a model matrix, view-projection and material. */
void sl_gbuffer_uniforms_init(sl_gbuffer_uniforms *u, mat4 model, mat4 view_proj, const sl_material *m);
/* sl_gbuffer_target and sl_raster_scene are public (softlight/gbuffer.h): the G-buffer as a
 * target, whose tile hooks clear the extra plane with the texels and resolve it after each tile
 * pass (gbuffer.c); and every object of a scene drawn with the built-in pair, both faces, the
 * clear fused into the first object's draw (sl_draw.clear). */

#endif
