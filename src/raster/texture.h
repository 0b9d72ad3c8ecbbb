/* texture.h - textures and samplers for C shaders: GL's 2D textures, sampler state and the
 * GLSL texture built-ins (textureLod, textureGrad, texelFetch, textureSize).
 *
 * Consumes: a level-0 image (memory, or a PNG / JPEG / Radiance .hdr file) and sampler state.
 * Produces: filtered texel values as GL returns them, for fragment shaders to use.
 *
 * Conventions (GL 4.6 section 8, checked against Mesa 22.3 llvmpipe by rendering):
 * - Storage: row 0 is the BOTTOM row (glTexImage2D's: t = 0 is the first row uploaded); texel
 *   centres at (i + 0.5) / size. sl_texture_load flips files (top row first) so that texture
 *   coordinate (0, 0) is the picture's bottom-left corner, as OBJ and Blender assume; the GL
 *   twin must upload the loaded level 0 as stored.
 * - Results: missing channels read as GL's (0, 0, 1): R -> (r, 0, 0, 1), RG -> (r, g, 0, 1),
 *   RGB -> (r, g, b, 1). UNORM8 / UNORM16 as code / 255 or / 65535, floats as stored, sRGB
 *   formats decoded per texel with the exact piecewise curve BEFORE filtering (alpha linear).
 * - Mip chain: level l is max(1, size >> l) on each side, each level made from the one above
 *   as llvmpipe's glGenerateMipmap makes it (a blit with bilinear filtering): the texel i of
 *   a level of width w' from a level of width w samples the latter at x = (i + 0.5) w / w' -
 *   0.5 (clamped to the edge), the same in y. For even sizes that is the 2x2 box average; for
 *   odd ones it is not a box (5 -> 2: texels 0 and 1 weighted 1/4, 3/4). Each level is stored
 *   (rounded to nearest) before the next is made from it. sRGB levels are filtered in linear
 *   and re-encoded with the exact curve; llvmpipe's encoder is an approximation, so a level
 *   can differ from llvmpipe's by one code (seen: exact 187.52 -> 188, llvmpipe 187; exact
 *   140.497 -> 140, llvmpipe 141); UNORM levels matched llvmpipe's bytes exactly.
 * - A texture made without mipmaps has one level; a sampler whose min filter is a *_MIPMAP_*
 *   one is then incomplete in GL's sense, and every sample returns (0, 0, 0, 1), as GL does.
 *
 * Level of detail (GL 4.6 section 8.14, as llvmpipe computes it, found by rendering a texture
 * whose levels hold their own index and reading back lambda; see docs/shader-api.md):
 *   rho^2  = max((ds/dx)^2 + (dt/dx)^2, (ds/dy)^2 + (dt/dy)^2), s, t in texels of level 0:
 *            the exact scale factor (llvmpipe's max-of-abs "rho_approx" is off by default);
 *   lambda = 0.5 * log2f_fast(rho^2) + shader bias + sampler bias, clamped to [min, max lod],
 *            where log2f_fast(m 2^e) = e + (m - 1), m in [1, 2): llvmpipe's piecewise linear
 *            log2, exact at powers of two, up to 0.086 below log2 (0.043 in lambda) between;
 *            a non-finite rho^2 counts as 0 for textureGrad, as +inf (the last level) for a
 *            quad (below). Matched bit for bit on 512 textureGrad samples.
 *   magnified when lambda <= 0 (c = 0 for every filter pair, as GL 4.6 and llvmpipe);
 *   *_MIPMAP_NEAREST: level round(lambda), halves to even as llvmpipe (textureLod 0.5 -> 0,
 *   1.5 -> 2; GL's ceil(lambda + 0.5) - 1 differs only at exact halves; llvmpipe's textureGrad
 *   without bias or lod clamps rounds an exact half up); *_MIPMAP_LINEAR: levels
 *   floor(lambda) and the next, weight fract(lambda),
 *   no "brilinear" (llvmpipe's is off by default); levels clamped to the chain.
 *   Explicit derivatives (textureGrad) and explicit lods (textureLod) give a lambda per pixel
 *   in llvmpipe; implicit derivatives (texture()) give one per 2x2 quad, from the coarse
 *   differences lane 1 - lane 0 and lane 2 - lane 0 (sl_texture_lambda_quad; helpers'
 *   inputs extrapolated unclamped, tile.c quad()). Tolerance against llvmpipe that results:
 *   lambda exact (bit for bit) for explicit derivatives, within 0.001 per quad (float
 *   rounding of uv; docs/shader-api.md "Level of detail"); bilinear values exact for float
 *   and sRGB textures; UNORM8 (non-sRGB) textures below 1/255 per level, since llvmpipe
 *   filters them in 8-bit fixed point and rounds the result to 8 bits (measured: at most
 *   0.955/255 over 1000 positions between two texels), about 2.5/255 trilinear (it also
 *   truncates the level weight to 1/256 and blends the levels in fixed point).
 *
 * Does not: cube maps, arrays, 3D, border colours (CLAMP_TO_BORDER), anisotropy, shadow
 * compare, texture swizzles, base/max level other than the whole chain, or the LOD bias clamp
 * to GL_MAX_TEXTURE_LOD_BIAS. The implicit-lod texture(in, s, uv) comes with the 2x2 quads
 * (src/raster, raster-quads), on top of sl_texture_lambda and sl_texture_sample. */
#ifndef SL_TEXTURE_H
#define SL_TEXTURE_H

#include <stdbool.h>
#include <stddef.h>

#include <softlight/glsl.h>
#include <softlight/texture.h>

#include "../core/error.h"
#include "../ibl/ibl.h" /* the environment's textureLod, the other overload of the name */
#include "raster.h"

/* The formats, textures, sampler state and the sampling functions are public
 * (softlight/texture.h); glsl.h spells the GLSL built-ins (textureLod, textureGrad, texelFetch,
 * textureSize, texture) on top of them. What follows is the library's own. */

/* The decoded copy the samplers read (texture_internal.h: small textures only), 0 if none. */
size_t sl_texture_plane_bytes(const sl_texture *t);
/* sl_texture_sample_quads in its two steps, so that maps of one layout sampled at the same
 * coordinates (glTF's base colour, normal and occlusion-roughness-metallic images, all one size)
 * share the first: sl_texture_plan_quads picks each quad's levels and computes each lane's texel
 * offsets and filter weights, which depend on the sampler state, the level sizes, u, v and lambda
 * but not on the texels; sl_texture_fetch_quads reads and filters the texels of s with a plan.
 * A plan made for sampler a serves sampler b (the same bits as b's own) when
 * sl_texture_same_plan(a, b): the same sampler state, completeness, levels and level sizes, and
 * both with a decoded plane of the same layout, or both without. The plan keeps u, v and lambda
 * (pointers): they must outlive it. */
typedef struct {
    int n;                                            /* quads */
    const float *u, *v, *lambda;                      /* what it was made for */
    bool complete, any_fast, any_two;                 /* any quad on the vector path; with two levels */
    bool slow[SL_QUADS_MAX];                          /* quads sampled four lanes at a time instead */
    _Alignas(64) int lv1[SL_QUAD_LANES];              /* second level of each lane, -1 for one level */
    _Alignas(64) float frac[SL_QUAD_LANES];           /* its weight */
    _Alignas(64) int o0[4][SL_QUAD_LANES], o1[4][SL_QUAD_LANES]; /* texel offsets in floats, per level */
    _Alignas(64) float a0[SL_QUAD_LANES], b0[SL_QUAD_LANES], a1[SL_QUAD_LANES], b1[SL_QUAD_LANES];
} sl_texture_quads_plan;
void sl_texture_plan_quads(const sl_sampler2D *s, int n, const float *u, const float *v, const float *lambda,
                           sl_texture_quads_plan *plan);
void sl_texture_fetch_quads(const sl_sampler2D *s, const sl_texture_quads_plan *plan, float *const rgba[4]);
bool sl_texture_same_plan(const sl_sampler2D *a, const sl_sampler2D *b);

#endif
