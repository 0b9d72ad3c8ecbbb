/* texture_internal.h - what texture.c (storage, mips, files) and sampler.c (filtering) share:
 * the texture's layout and the decode of one texel. Not for shaders: they see texture.h.
 *
 * Layout, chosen for fetch cost: each level is its texels tightly packed in the format's own
 * width (UNORM8 stays 1 byte a channel, UNORM16 2, floats 4), rows bottom first, the levels one
 * after the other in one allocation. A trilinear sample reads 8 texels: keeping 8-bit data
 * 8-bit keeps a texture 4x smaller than floats would (more of it stays in cache), and the
 * decode is a multiply (UNORM) or a lookup in the texture's own 256-entry table (sRGB), which
 * costs less than the cache misses a float copy would add. The format is switched on per
 * texel; a draw samples one texture with one format, so the branch predicts perfectly. */
#ifndef SL_TEXTURE_INTERNAL_H
#define SL_TEXTURE_INTERNAL_H

#include <stdint.h>
#include <string.h>

#include "texture.h"

typedef struct {
    int width, height;
    const unsigned char *texels; /* width * height texels, row 0 = bottom */
} tex_level;

struct sl_texture {
    sl_texture_format format;
    int channels, texel_bytes;
    int levels;
    bool mipmapped;         /* the whole chain (a 1x1 texture is its own chain) */
    tex_level level[SL_TEXTURE_MAX_LEVELS];
    unsigned char *storage; /* every level, level 0 first */
    size_t bytes;
    float srgb[256];        /* sRGB formats: code -> linear, the exact curve (unused otherwise) */
};

/* Texel (x, y) of a level, decoded to GL's vec4 (missing channels (0, 0, 1)). */
static inline vec4 tex_texel(const sl_texture *t, const tex_level *lv, int x, int y)
{
    const unsigned char *p = lv->texels + ((size_t)y * (size_t)lv->width + (size_t)x) * (size_t)t->texel_bytes;
    const float u8 = 1.0f / 255.0f, u16 = 1.0f / 65535.0f;
    uint16_t h[4];
    float f[4];
    switch (t->format) {
    case SL_TEX_R8: return vec4(p[0] * u8, 0, 0, 1);
    case SL_TEX_RG8: return vec4(p[0] * u8, p[1] * u8, 0, 1);
    case SL_TEX_RGB8: return vec4(p[0] * u8, p[1] * u8, p[2] * u8, 1);
    case SL_TEX_RGBA8: return vec4(p[0] * u8, p[1] * u8, p[2] * u8, p[3] * u8);
    case SL_TEX_SRGB8: return vec4(t->srgb[p[0]], t->srgb[p[1]], t->srgb[p[2]], 1);
    case SL_TEX_SRGB8_ALPHA8: return vec4(t->srgb[p[0]], t->srgb[p[1]], t->srgb[p[2]], p[3] * u8);
    case SL_TEX_R16: memcpy(h, p, 2); return vec4(h[0] * u16, 0, 0, 1);
    case SL_TEX_RG16: memcpy(h, p, 4); return vec4(h[0] * u16, h[1] * u16, 0, 1);
    case SL_TEX_RGB16: memcpy(h, p, 6); return vec4(h[0] * u16, h[1] * u16, h[2] * u16, 1);
    case SL_TEX_RGBA16: memcpy(h, p, 8); return vec4(h[0] * u16, h[1] * u16, h[2] * u16, h[3] * u16);
    case SL_TEX_R32F: memcpy(f, p, 4); return vec4(f[0], 0, 0, 1);
    case SL_TEX_RGB32F: memcpy(f, p, 12); return vec4(f[0], f[1], f[2], 1);
    case SL_TEX_RGBA32F: memcpy(f, p, 16); return vec4(f[0], f[1], f[2], f[3]);
    }
    return vec4(0, 0, 0, 1);
}

/* Bilinear filtering of one level at texel-space position (x, y) = (u w - 0.5, v h - 0.5),
 * each axis wrapped as given (sampler.c; the mip builder uses it clamped to the edge). */
vec4 tex_bilinear(const sl_texture *t, const tex_level *lv, float x, float y, sl_wrap wrap_s, sl_wrap wrap_t);

#endif
