/* softlight/texture.h - GL's 2D textures and samplers for C shaders.
 *
 * A texture is an image with its full mip chain (built as glGenerateMipmap builds it) or level 0
 * alone, row 0 = bottom (glTexImage2D's order; sl_texture_load flips files so that texture
 * coordinate (0, 0) is the picture's bottom-left corner). Samples are what GL 4.6 returns
 * (checked against Mesa's llvmpipe): missing channels read as (0, 0, 1), UNORM as code / 255 or
 * / 65535, sRGB decoded per texel before filtering, levels of detail as llvmpipe computes them.
 * An incomplete sampler (a mipmapped filter on a texture without mips) returns (0, 0, 0, 1).
 *
 * glsl.h spells the sampling functions as GLSL does (texture, textureLod, textureGrad,
 * texelFetch, textureSize). */
#ifndef SOFTLIGHT_TEXTURE_H
#define SOFTLIGHT_TEXTURE_H

#include <stdbool.h>
#include <stddef.h>

#include <softlight/types.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sl_texture_format {
    SL_TEX_R8, SL_TEX_RG8, SL_TEX_RGB8, SL_TEX_RGBA8,     /* UNORM8 */
    SL_TEX_SRGB8, SL_TEX_SRGB8_ALPHA8,                    /* GL_SRGB8, GL_SRGB8_ALPHA8 */
    SL_TEX_R16, SL_TEX_RG16, SL_TEX_RGB16, SL_TEX_RGBA16, /* UNORM16 (16-bit PNGs) */
    SL_TEX_R32F, SL_TEX_RGB32F, SL_TEX_RGBA32F
} sl_texture_format;
#define SL_TEX_FORMAT_COUNT (SL_TEX_RGBA32F + 1)

/* Largest side of a texture is 32768, so at most 16 levels. */
#define SL_TEXTURE_MAX_LEVELS 16

typedef struct sl_texture sl_texture; /* a 2D image with its full mip chain (or level 0 alone) */

/* level0: width * height texels of fmt, tightly packed, row 0 = BOTTOM. mipmaps: build the
 * whole chain. False (and err) for a size <= 0 or over 32768, an unknown format, or no memory. */
SL_API bool sl_texture_create(sl_texture_format fmt, int width, int height, const void *level0, bool mipmaps,
                              sl_texture **out, sl_error *err);
SL_API void sl_texture_destroy(sl_texture *t); /* NULL is fine */
SL_API int sl_texture_levels(const sl_texture *t);
SL_API sl_texture_format sl_texture_get_format(const sl_texture *t);
SL_API size_t sl_texture_bytes(const sl_texture *t);                    /* storage incl. mips */
SL_API const char *sl_texture_format_name(sl_texture_format fmt);       /* "SRGB8_ALPHA8" */
SL_API int sl_texture_format_bytes(sl_texture_format fmt);              /* bytes per texel */
/* Level `level` as stored: width * height texels of the format, tightly packed, row 0 = bottom;
 * NULL outside the chain. */
SL_API const void *sl_texture_level_texels(const sl_texture *t, int level, int *width, int *height);

/* Files, with the full mip chain: PNG (8 and 16 bit, 1-4 channels), JPEG, Radiance .hdr, told
 * apart by their first bytes. srgb: 8-bit colour data is SRGB8 or SRGB8_ALPHA8 (grey replicated
 * to RGB); otherwise UNORM; 16-bit PNGs are UNORM16, .hdr RGB32F. budget: the bytes the decoder
 * and the texture may take (0 = the default, 1 GiB). Errors name the file. */
SL_API bool sl_texture_load(const char *path, bool srgb, size_t budget, sl_texture **out, sl_error *err);
/* The same from memory; `name` is used in messages. */
SL_API bool sl_texture_load_memory(const unsigned char *bytes, size_t size, const char *name, bool srgb,
                                   size_t budget, sl_texture **out, sl_error *err);

typedef enum sl_filter {
    SL_NEAREST, SL_LINEAR, SL_NEAREST_MIPMAP_NEAREST, SL_LINEAR_MIPMAP_NEAREST,
    SL_NEAREST_MIPMAP_LINEAR, SL_LINEAR_MIPMAP_LINEAR
} sl_filter;
typedef enum sl_wrap { SL_REPEAT, SL_CLAMP_TO_EDGE, SL_MIRRORED_REPEAT } sl_wrap;
typedef struct sl_sampler_state {
    sl_filter min_filter, mag_filter; /* mag_filter: SL_NEAREST or SL_LINEAR */
    sl_wrap wrap_s, wrap_t;
    float lod_bias, min_lod, max_lod;
} sl_sampler_state;
/* GL's defaults: NEAREST_MIPMAP_LINEAR, LINEAR, REPEAT, REPEAT, bias 0, lod in [-1000, 1000]. */
SL_API sl_sampler_state sl_sampler_default(void);

/* What a shader's uniforms hold for a GLSL `uniform sampler2D` (read-only while drawing). */
typedef struct sl_sampler2D {
    const sl_texture *texture;
    sl_sampler_state state;
} sl_sampler2D;

/* GLSL textureLod, textureGrad, texelFetch (no filtering, no wrap: (0, 0, 0, 0) outside the
 * level or the chain) and textureSize ((0, 0) outside the chain). */
SL_API sl_vec4 sl_texture_lod(const sl_sampler2D *s, sl_vec2 uv, float lod);
SL_API sl_vec4 sl_texture_grad(const sl_sampler2D *s, sl_vec2 uv, sl_vec2 dPdx, sl_vec2 dPdy);
SL_API sl_vec4 sl_texel_fetch(const sl_sampler2D *s, sl_ivec2 p, int lod);
SL_API sl_ivec2 sl_texture_size(const sl_sampler2D *s, int lod);

/* The level of detail GL computes from derivatives, as llvmpipe computes it. bias is the
 * shader's. sl_texture_lambda is textureGrad's (a non-finite rho counts as 0, magnified);
 * sl_texture_lambda_quad is texture()'s, from a quad's coarse differences (a non-finite rho
 * selects the last level). Equal for finite derivatives. */
SL_API float sl_texture_lambda(const sl_sampler2D *s, sl_vec2 dPdx, sl_vec2 dPdy, float bias);
SL_API float sl_texture_lambda_quad(const sl_sampler2D *s, sl_vec2 dPdx, sl_vec2 dPdy, float bias);
/* Sampling at a given (already biased and clamped) lambda: GL 4.6 section 8.14. */
SL_API sl_vec4 sl_texture_sample(const sl_sampler2D *s, sl_vec2 uv, float lambda);
/* The same for the four lanes of a quad at one lambda (a quad form's texture()): out[l] is
 * sl_texture_sample(s, uv[l], lambda), bit for bit. */
SL_API void sl_texture_sample4(const sl_sampler2D *s, const sl_vec2 uv[4], float lambda, sl_vec4 out[4]);
/* The multi-quad forms (program.h, sl_program.fragment_quads): n quads (1 .. SL_QUADS_MAX),
 * lane l of quad q at 4 q + l of u and v. lambda[q] is sl_texture_lambda_quad of quad q's coarse
 * differences; rgba[c][4 q + l] is channel c of sl_texture_sample(s, (u, v), lambda[q]), bit for
 * bit. */
SL_API void sl_texture_lambda_quads(const sl_sampler2D *s, int n, const float *u, const float *v, float bias,
                                    float *lambda);
SL_API void sl_texture_sample_quads(const sl_sampler2D *s, int n, const float *u, const float *v,
                                    const float *lambda, float *const rgba[4]);

#ifdef __cplusplus
}
#endif

#endif
