/* texture_internal.h - what texture.c (storage, mips, files) and sampler.c (filtering) share:
 * the texture's layout and the decode of one texel. Not for shaders: they see texture.h.
 *
 * Layout, chosen for fetch cost: each level is its texels tightly packed in the format's own
 * width (UNORM8 stays 1 byte a channel, UNORM16 2, floats 4), rows bottom first, the levels one
 * after the other in one allocation. A trilinear sample reads 8 texels: keeping 8-bit data
 * 8-bit keeps a texture 4x smaller than floats would (more of it stays in cache), and the
 * decode is a multiply (UNORM) or a lookup in the texture's own 256-entry table (sRGB): for a
 * large texture that costs less than the cache misses a float copy would add (small ones keep
 * such a copy as well: the decoded plane, below). The format is switched on once per
 * sample (sampler.c instantiates its filtering for each format, with tex_decode inlined and
 * folded), not per texel.
 *
 * The decoded plane: a texture whose chain decoded to RGBA32F takes at most
 * TEX_PLANE_MAX_BYTES also keeps that copy (`plane`, the same level sizes, 16 bytes a texel),
 * and the samplers read it instead of the stored bytes. Each texel in it is tex_decode's value
 * (for sRGB the exact curve, per texel, before filtering, as on the byte path), so a sample
 * gives the same bits from either; what it saves is the work per texel: a trilinear sRGB sample
 * on the byte path is 8 texels of 3 byte loads and 3 table lookups each, from the plane 8
 * 16-byte loads, and the filter's mixes work on whole vec4s. Small textures only, because the copy is 4x the bytes of RGBA8 (5.3x
 * RGB8): a texture that stays in cache either way gains the decode, a large one would lose
 * more to cache misses on 4x the bytes than it gains (not measured; the cap keeps such textures
 * on the byte path). The stored levels stay as they are: texelFetch, the mip builder and
 * sl_texture_level_texels (the GL upload) read them. */
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
    tex_level plane[SL_TEXTURE_MAX_LEVELS]; /* the decoded plane (above): RGBA32F texels */
    float *plane_storage;   /* NULL: no plane, the samplers read `level` */
    size_t plane_bytes;
};

/* The largest decoded plane kept (above): 4 MiB, a 512x512 texture with its mips (5.3 MiB would
 * be over; 256x256 is 1.3 MiB), small enough that a few of them share a core's L2 and L3. */
#define TEX_PLANE_MAX_BYTES ((size_t)4 << 20)

/* Make the decoded plane of a texture whose levels are final (texture.c calls it after the
 * mips), when it fits TEX_PLANE_MAX_BYTES and memory allows: without it sampling is the same,
 * only slower. sl_tex_plane_drop frees it (the tests compare the two paths with it). */
void sl_tex_plane_build(sl_texture *t);
void sl_tex_plane_drop(sl_texture *t);

/* Bytes of one texel of fmt, as a constant where fmt is one (the per-format fetch functions of
 * sampler.c are instantiated with a constant format, so this and tex_decode fold away). */
static inline int tex_format_bytes(sl_texture_format fmt)
{
    switch (fmt) {
    case SL_TEX_R8: return 1;
    case SL_TEX_RG8: case SL_TEX_R16: return 2;
    case SL_TEX_RGB8: case SL_TEX_SRGB8: return 3;
    case SL_TEX_RGBA8: case SL_TEX_SRGB8_ALPHA8: case SL_TEX_RG16: case SL_TEX_R32F: return 4;
    case SL_TEX_RGB16: return 6;
    case SL_TEX_RGBA16: return 8;
    case SL_TEX_RGB32F: return 12;
    case SL_TEX_RGBA32F: return 16;
    }
    return 0;
}

/* The texel at p, of format fmt, decoded to GL's vec4 (missing channels (0, 0, 1)). The one
 * decode: tex_texel and every fetch of sampler.c go through it. */
static inline vec4 tex_decode(const sl_texture *t, sl_texture_format fmt, const unsigned char *p)
{
    const float u8 = 1.0f / 255.0f, u16 = 1.0f / 65535.0f;
    uint16_t h[4];
    float f[4];
    switch (fmt) {
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

/* Texel (x, y) of a level, decoded (texelFetch, the mip builder). */
static inline vec4 tex_texel(const sl_texture *t, const tex_level *lv, int x, int y)
{
    const unsigned char *p = lv->texels + ((size_t)y * (size_t)lv->width + (size_t)x) * (size_t)t->texel_bytes;
    return tex_decode(t, t->format, p);
}

/* Bilinear filtering of one level at texel-space position (x, y) = (u w - 0.5, v h - 0.5),
 * each axis wrapped as given (sampler.c; the mip builder uses it clamped to the edge). */
vec4 sl_tex_bilinear(const sl_texture *t, const tex_level *lv, float x, float y, sl_wrap wrap_s, sl_wrap wrap_t);

#endif
