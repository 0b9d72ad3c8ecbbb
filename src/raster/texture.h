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

#include "../core/error.h"
#include "../core/glsl.h"
#include "../ibl/ibl.h" /* the environment's textureLod, the other overload of the name */
#include "raster.h"        /* SL_QUADS_MAX, SL_QUAD_LANES: the multi-quad forms' sizes */

typedef enum {
    SL_TEX_R8, SL_TEX_RG8, SL_TEX_RGB8, SL_TEX_RGBA8,     /* UNORM8 */
    SL_TEX_SRGB8, SL_TEX_SRGB8_ALPHA8,                    /* GL_SRGB8, GL_SRGB8_ALPHA8 */
    SL_TEX_R16, SL_TEX_RG16, SL_TEX_RGB16, SL_TEX_RGBA16, /* UNORM16 (16-bit PNGs) */
    SL_TEX_R32F, SL_TEX_RGB32F, SL_TEX_RGBA32F
} sl_texture_format;
#define SL_TEX_FORMAT_COUNT (SL_TEX_RGBA32F + 1)

/* Largest side of a texture: image.h's SL_IMAGE_MAX_SIDE (32768, so at most 16 levels). */
#define SL_TEXTURE_MAX_LEVELS 16

typedef struct sl_texture sl_texture; /* a 2D image with its full mip chain (or level 0 alone) */

/* level0: width * height texels of fmt, tightly packed, row 0 = BOTTOM. mipmaps: build the
 * whole chain as glGenerateMipmap does (above). False (and err) for a size <= 0 or over
 * SL_IMAGE_MAX_SIDE, an unknown format, or no memory. */
bool sl_texture_create(sl_texture_format fmt, int width, int height, const void *level0, bool mipmaps,
                       sl_texture **out, sl_error *err);
void sl_texture_destroy(sl_texture *t); /* NULL is fine */
int sl_texture_levels(const sl_texture *t);
sl_texture_format sl_texture_get_format(const sl_texture *t);
size_t sl_texture_bytes(const sl_texture *t); /* storage incl. mips, for reports */
/* The decoded copy the samplers read (texture_internal.h: small textures only), 0 if none. */
size_t sl_texture_plane_bytes(const sl_texture *t);
const char *sl_texture_format_name(sl_texture_format fmt); /* "SRGB8_ALPHA8", for messages */
/* Level `level` as stored: width * height texels of the format, tightly packed, row 0 = bottom;
 * NULL outside the chain. softlight-gl uploads level 0 from here (and lets GL make the mips). */
const void *sl_texture_level_texels(const sl_texture *t, int level, int *width, int *height);
int sl_texture_format_bytes(sl_texture_format fmt);        /* bytes per texel */

/* Files, with the full mip chain: PNG (8 and 16 bit, 1-4 channels), JPEG, Radiance .hdr (the
 * hand-written reader of src/core/hdr.c), told apart by their first bytes.
 * srgb: 8-bit colour data is SRGB8 (RGB) or SRGB8_ALPHA8 (alpha stays linear), grey
 * replicated to RGB (GL has no one-channel sRGB format in core); otherwise UNORM: R8, RG8,
 * RGB8, RGBA8; 16-bit PNGs are always UNORM16 (GL has no 16-bit sRGB format), .hdr RGB32F
 * (NaN, Inf and negative texels set to 0, as every image reader does). budget: the image
 * memory budget in bytes (0 = default), counting the decoder's buffers and the texture with
 * its mips. Errors name the file. */
bool sl_texture_load(const char *path, bool srgb, size_t budget, sl_texture **out, sl_error *err);
/* The same from memory (what sl_texture_load calls once the file is read, and fuzz_texture);
 * `name` is used in messages. */
bool sl_texture_load_memory(const unsigned char *bytes, size_t size, const char *name, bool srgb, size_t budget,
                            sl_texture **out, sl_error *err);

typedef enum {
    SL_NEAREST, SL_LINEAR, SL_NEAREST_MIPMAP_NEAREST, SL_LINEAR_MIPMAP_NEAREST,
    SL_NEAREST_MIPMAP_LINEAR, SL_LINEAR_MIPMAP_LINEAR
} sl_filter;
typedef enum { SL_REPEAT, SL_CLAMP_TO_EDGE, SL_MIRRORED_REPEAT } sl_wrap;
typedef struct {
    sl_filter min_filter, mag_filter; /* mag_filter: SL_NEAREST or SL_LINEAR */
    sl_wrap wrap_s, wrap_t;
    float lod_bias, min_lod, max_lod;
} sl_sampler_state;
/* GL's defaults: NEAREST_MIPMAP_LINEAR, LINEAR, REPEAT, REPEAT, bias 0, lod in [-1000, 1000]. */
sl_sampler_state sl_sampler_default(void);

/* What a shader's uniforms hold for a GLSL `uniform sampler2D` (read-only while drawing). */
typedef struct {
    const sl_texture *texture;
    sl_sampler_state state;
} sl_sampler2D;

/* GLSL built-ins (GLSL names; results as GL returns them). textureLod is overloaded as in
 * GLSL: on an sl_sampler2D it is sl_texture_lod, on the environment (an sl_env, ibl.h) the
 * environment's own textureLod, chosen by _Generic on the first argument as glsl.h's are. */
vec4 sl_texture_lod(const sl_sampler2D *s, vec2 uv, float lod);
#define textureLod(s, uv, lod)                                                                              \
    _Generic((s), sl_sampler2D *: sl_texture_lod, const sl_sampler2D *: sl_texture_lod, default: textureLod)( \
        s, uv, lod)
vec4 textureGrad(const sl_sampler2D *s, vec2 uv, vec2 dPdx, vec2 dPdy);
/* Texel p of level lod, no filtering, no wrap: (0, 0, 0, 0) outside the level or the chain
 * (undefined in GL; what llvmpipe returns). */
vec4 texelFetch(const sl_sampler2D *s, ivec2 p, int lod);
/* Size of level lod: (0, 0) outside the chain (undefined in GL). */
ivec2 textureSize(const sl_sampler2D *s, int lod);

/* The level of detail GL computes from derivatives, as llvmpipe computes it (above). bias is
 * the shader's (texture(s, uv, bias)). sl_texture_lambda is textureGrad's (explicit
 * derivatives: a non-finite rho counts as 0, magnified); sl_texture_lambda_quad is texture()'s,
 * from a quad's coarse differences (a non-finite rho, from a helper lane's infinite or NaN
 * input, selects the last level, as llvmpipe). Equal for finite derivatives. */
float sl_texture_lambda(const sl_sampler2D *s, vec2 dPdx, vec2 dPdy, float bias);
float sl_texture_lambda_quad(const sl_sampler2D *s, vec2 dPdx, vec2 dPdy, float bias);
/* Sampling at a given (already biased and clamped) lambda: the min/mag choice and the level
 * selection of GL 4.6 section 8.14. */
vec4 sl_texture_sample(const sl_sampler2D *s, vec2 uv, float lambda);
/* The same for the four lanes of a quad at one lambda (a quad form's texture()): out[l] is
 * sl_texture_sample(s, uv[l], lambda), bit for bit, with one format dispatch for the four. */
void sl_texture_sample4(const sl_sampler2D *s, const vec2 uv[4], float lambda, vec4 out[4]);

/* The multi-quad forms (a shader's sl_program.fragment_quads): n quads (1 .. SL_QUADS_MAX), lane l
 * of quad q at 4 q + l of u and v. sl_texture_lambda_quads: lambda[q] is sl_texture_lambda_quad
 * of quad q's coarse differences (lane 1 - lane 0, lane 2 - lane 0), bit for bit.
 * sl_texture_sample_quads: rgba[c][4 q + l] is channel c of sl_texture_sample(s, (u, v),
 * lambda[q]), bit for bit; the plane's linear filtering runs in vector loops over the lanes. */
void sl_texture_lambda_quads(const sl_sampler2D *s, int n, const float *u, const float *v, float bias, float *lambda);
void sl_texture_sample_quads(const sl_sampler2D *s, int n, const float *u, const float *v, const float *lambda,
                             float *const rgba[4]);

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
