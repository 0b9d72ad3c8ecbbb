/* texture.c - textures: storage in the format's own width, the mip chain as llvmpipe's
 * glGenerateMipmap makes it, the decoded plane of small textures (what the samplers read:
 * texture_internal.h), and loading from PNG / JPEG / .hdr files.
 *
 * The layout and the per-texel decode are in texture_internal.h (shared with sampler.c); the
 * rules every function here follows (row 0 at the bottom, how levels are made) are in
 * texture.h. Decoding files is core's: PNG / JPEG through sl_image_parse_raw (raw_image.c:
 * libpng, libjpeg-turbo), .hdr through hdr.c. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/image.h"
#include "texture_internal.h"

static const struct {
    const char *name;
    int channels, channel_bytes;
} formats[SL_TEX_FORMAT_COUNT] = {
    [SL_TEX_R8] = {"R8", 1, 1},         [SL_TEX_RG8] = {"RG8", 2, 1},
    [SL_TEX_RGB8] = {"RGB8", 3, 1},     [SL_TEX_RGBA8] = {"RGBA8", 4, 1},
    [SL_TEX_SRGB8] = {"SRGB8", 3, 1},   [SL_TEX_SRGB8_ALPHA8] = {"SRGB8_ALPHA8", 4, 1},
    [SL_TEX_R16] = {"R16", 1, 2},       [SL_TEX_RG16] = {"RG16", 2, 2},
    [SL_TEX_RGB16] = {"RGB16", 3, 2},   [SL_TEX_RGBA16] = {"RGBA16", 4, 2},
    [SL_TEX_R32F] = {"R32F", 1, 4},     [SL_TEX_RGB32F] = {"RGB32F", 3, 4},
    [SL_TEX_RGBA32F] = {"RGBA32F", 4, 4},
};

static bool format_valid(sl_texture_format fmt) { return (unsigned)fmt < SL_TEX_FORMAT_COUNT; }

const char *sl_texture_format_name(sl_texture_format fmt)
{
    return format_valid(fmt) ? formats[fmt].name : "unknown";
}

int sl_texture_format_bytes(sl_texture_format fmt)
{
    return format_valid(fmt) ? formats[fmt].channels * formats[fmt].channel_bytes : 0;
}

static bool is_srgb(sl_texture_format fmt) { return fmt == SL_TEX_SRGB8 || fmt == SL_TEX_SRGB8_ALPHA8; }

/* IEC 61966-2-1 linear -> sRGB, in double (the decode is core's sl_srgb8_to_linear). */
static double srgb_encode(double v)
{
    return v <= 0.0031308 ? v * 12.92 : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

/* [0, 1] -> 0..max, rounded to nearest (NaN -> 0). */
static unsigned unorm(float v, unsigned max)
{
    if (!(v > 0.0f))
        return 0;
    if (v >= 1.0f)
        return max;
    return (unsigned)(v * (float)max + 0.5f);
}

/* Store one filtered value into texel p: the inverse of tex_texel (sRGB re-encoded exactly). */
static void encode_texel(sl_texture_format fmt, vec4 v, unsigned char *p)
{
    float c[4] = {v.x, v.y, v.z, v.w};
    int n = formats[fmt].channels;
    for (int i = 0; i < n; i++) {
        if (is_srgb(fmt) && i < 3) {
            p[i] = (unsigned char)unorm((float)srgb_encode((double)clampf(c[i], 0.0f, 1.0f)), 255);
        } else if (formats[fmt].channel_bytes == 1) {
            p[i] = (unsigned char)unorm(c[i], 255);
        } else if (formats[fmt].channel_bytes == 2) {
            uint16_t h = (uint16_t)unorm(c[i], 65535);
            memcpy(p + 2 * i, &h, 2);
        } else {
            memcpy(p + 4 * i, &c[i], 4);
        }
    }
}

/* One level from the one above: each texel samples it bilinearly at its own centre, clamped
 * to the edge, as llvmpipe's mipmap blit does (texture.h). */
static void build_level(sl_texture *t, int l)
{
    const tex_level *src = &t->level[l - 1];
    tex_level *dst = &t->level[l];
    unsigned char *out = (unsigned char *)dst->texels;
    float sx = (float)src->width / (float)dst->width, sy = (float)src->height / (float)dst->height;
    for (int y = 0; y < dst->height; y++)
        for (int x = 0; x < dst->width; x++) {
            vec4 v = sl_tex_bilinear(t, src, ((float)x + 0.5f) * sx - 0.5f, ((float)y + 0.5f) * sy - 0.5f,
                                  SL_CLAMP_TO_EDGE, SL_CLAMP_TO_EDGE);
            encode_texel(t->format, v, out + ((size_t)y * (size_t)dst->width + (size_t)x) * (size_t)t->texel_bytes);
        }
}

/* Levels of a width x height texture, and the bytes of all of them. */
static int chain_levels(int width, int height, bool mipmaps)
{
    int levels = 1;
    while (mipmaps && (width >> levels || height >> levels))
        levels++;
    return levels;
}

static size_t chain_bytes(sl_texture_format fmt, int width, int height, bool mipmaps)
{
    size_t bytes = 0;
    int levels = chain_levels(width, height, mipmaps);
    for (int l = 0; l < levels; l++) {
        size_t w = (size_t)(width >> l ? width >> l : 1), h = (size_t)(height >> l ? height >> l : 1);
        bytes += w * h * (size_t)sl_texture_format_bytes(fmt);
    }
    return bytes;
}

/* A texture with its storage allocated and its levels laid out, level 0 not yet filled. */
static bool texture_alloc(sl_texture_format fmt, int width, int height, bool mipmaps, sl_texture **out,
                          sl_error *err)
{
    *out = NULL;
    if (!format_valid(fmt))
        return sl_fail(err, SL_ERR_RANGE, "texture: unknown format %d", (int)fmt);
    if (width <= 0 || height <= 0 || width > SL_IMAGE_MAX_SIDE || height > SL_IMAGE_MAX_SIDE)
        return sl_fail(err, SL_ERR_RANGE, "texture: size %dx%d is not in 1..%d on each side", width, height,
                       SL_IMAGE_MAX_SIDE);
    sl_texture *t = calloc(1, sizeof *t);
    size_t bytes = chain_bytes(fmt, width, height, mipmaps);
    unsigned char *storage = t ? malloc(bytes) : NULL;
    if (!storage) {
        free(t);
        return sl_fail(err, SL_ERR_MEMORY, "texture: out of memory for a %dx%d %s texture (%zu bytes)", width, height,
                       formats[fmt].name, bytes);
    }
    t->format = fmt;
    t->channels = formats[fmt].channels;
    t->texel_bytes = sl_texture_format_bytes(fmt);
    t->levels = chain_levels(width, height, mipmaps);
    t->mipmapped = t->levels == chain_levels(width, height, true);
    t->storage = storage;
    t->bytes = bytes;
    size_t offset = 0;
    for (int l = 0; l < t->levels; l++) {
        int w = width >> l ? width >> l : 1, h = height >> l ? height >> l : 1;
        t->level[l] = (tex_level){w, h, storage + offset};
        offset += (size_t)w * (size_t)h * (size_t)t->texel_bytes;
    }
    if (is_srgb(fmt))
        for (int i = 0; i < 256; i++)
            t->srgb[i] = sl_srgb8_to_linear((unsigned char)i);
    *out = t;
    return true;
}

/* Every level after level 0, then the decoded plane of the final levels. */
static void build_mips(sl_texture *t)
{
    for (int l = 1; l < t->levels; l++)
        build_level(t, l);
    sl_tex_plane_build(t);
}

void sl_tex_plane_build(sl_texture *t)
{
    size_t texels = 0;
    for (int l = 0; l < t->levels; l++)
        texels += (size_t)t->level[l].width * (size_t)t->level[l].height;
    size_t bytes = texels * 4 * sizeof(float);
    if (t->plane_storage || t->format == SL_TEX_RGBA32F || bytes > TEX_PLANE_MAX_BYTES)
        return; /* RGBA32F: the stored levels are that plane already */
    float *p = malloc(bytes);
    if (!p)
        return; /* optional: the samplers read the stored levels instead */
    size_t offset = 0;
    for (int l = 0; l < t->levels; l++) {
        const tex_level *lv = &t->level[l];
        t->plane[l] = (tex_level){lv->width, lv->height, (const unsigned char *)(p + offset)};
        for (int y = 0; y < lv->height; y++)
            for (int x = 0; x < lv->width; x++, offset += 4) {
                vec4 v = tex_texel(t, lv, x, y);
                memcpy(p + offset, &v, sizeof v);
            }
    }
    t->plane_storage = p;
    t->plane_bytes = bytes;
}

void sl_tex_plane_drop(sl_texture *t)
{
    free(t->plane_storage);
    t->plane_storage = NULL;
    t->plane_bytes = 0;
    memset(t->plane, 0, sizeof t->plane);
}

bool sl_texture_create(sl_texture_format fmt, int width, int height, const void *level0, bool mipmaps,
                       sl_texture **out, sl_error *err)
{
    if (!level0) {
        *out = NULL;
        return sl_fail(err, SL_ERR_RANGE, "texture: no level 0 data");
    }
    if (!texture_alloc(fmt, width, height, mipmaps, out, err))
        return false;
    memcpy((*out)->storage, level0, (size_t)width * (size_t)height * (size_t)(*out)->texel_bytes);
    build_mips(*out);
    return true;
}

void sl_texture_destroy(sl_texture *t)
{
    if (!t)
        return;
    free(t->storage);
    free(t->plane_storage);
    free(t);
}

int sl_texture_levels(const sl_texture *t) { return t->levels; }
sl_texture_format sl_texture_get_format(const sl_texture *t) { return t->format; }
size_t sl_texture_bytes(const sl_texture *t) { return t->bytes; }
size_t sl_texture_plane_bytes(const sl_texture *t) { return t->plane_bytes; }

const void *sl_texture_level_texels(const sl_texture *t, int level, int *width, int *height)
{
    if (!t || level < 0 || level >= t->levels)
        return NULL;
    *width = t->level[level].width;
    *height = t->level[level].height;
    return t->level[level].texels;
}

/* ---- files ---- */

/* The format a decoded PNG / JPEG becomes (texture.h: sl_texture_load). */
static sl_texture_format raw_format(int channels, int bits, bool srgb)
{
    static const sl_texture_format unorm8[4] = {SL_TEX_R8, SL_TEX_RG8, SL_TEX_RGB8, SL_TEX_RGBA8};
    static const sl_texture_format unorm16[4] = {SL_TEX_R16, SL_TEX_RG16, SL_TEX_RGB16, SL_TEX_RGBA16};
    if (bits == 16)
        return unorm16[channels - 1];
    if (srgb)
        return channels == 2 || channels == 4 ? SL_TEX_SRGB8_ALPHA8 : SL_TEX_SRGB8;
    return unorm8[channels - 1];
}

/* What the texture of a decoded image takes beside the decoder's buffers (the budget's share). */
static size_t raw_texture_bytes_srgb(int width, int height, int channels, int bits)
{
    return chain_bytes(raw_format(channels, bits, true), width, height, true);
}

static size_t raw_texture_bytes_linear(int width, int height, int channels, int bits)
{
    return chain_bytes(raw_format(channels, bits, false), width, height, true);
}

/* Level 0 from the decoder's rows (top first): flipped, grey replicated where sRGB asks. */
static void fill_from_raw(sl_texture *t, const sl_raw_image *raw)
{
    size_t in_texel = (size_t)raw->channels * (size_t)(raw->bits / 8);
    size_t out_texel = (size_t)t->texel_bytes;
    unsigned char *dst = t->storage;
    const unsigned char *src = raw->pixels;
    bool expand = (raw->channels <= 2) && t->channels >= 3;
    for (int y = 0; y < raw->height; y++) {
        const unsigned char *row = src + (size_t)(raw->height - 1 - y) * (size_t)raw->width * in_texel;
        unsigned char *out = dst + (size_t)y * (size_t)raw->width * out_texel;
        if (!expand) {
            memcpy(out, row, (size_t)raw->width * in_texel);
            continue;
        }
        for (int x = 0; x < raw->width; x++) {
            const unsigned char *p = row + (size_t)x * in_texel;
            unsigned char *q = out + (size_t)x * out_texel;
            q[0] = q[1] = q[2] = p[0];
            if (raw->channels == 2)
                q[3] = p[1];
        }
    }
}

static bool load_png_jpeg(const unsigned char *bytes, size_t size, const char *name, bool srgb, size_t budget,
                          sl_texture **out, sl_error *err)
{
    sl_raw_image raw;
    if (!sl_image_parse_raw(bytes, size, name, budget, srgb ? raw_texture_bytes_srgb : raw_texture_bytes_linear,
                            &raw, err))
        return false;
    sl_texture_format fmt = raw_format(raw.channels, raw.bits, srgb);
    if (!texture_alloc(fmt, raw.width, raw.height, true, out, err)) {
        sl_raw_image_free(&raw);
        sl_error_prefix(err, "%s: ", name);
        return false;
    }
    fill_from_raw(*out, &raw);
    sl_raw_image_free(&raw);
    build_mips(*out);
    return true;
}

static bool load_hdr(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_texture **out,
                     sl_error *err)
{
    sl_image img;
    if (!sl_image_parse_hdr(bytes, size, name, budget, &img, NULL, err))
        return false;
    size_t need = (size_t)img.width * (size_t)img.height * 3 * sizeof(float) +
                  chain_bytes(SL_TEX_RGB32F, img.width, img.height, true);
    if (!sl_image_check_budget(name, 0, img.width, img.height, need, budget, err)) {
        sl_image_free(&img);
        return false;
    }
    if (!texture_alloc(SL_TEX_RGB32F, img.width, img.height, true, out, err)) {
        sl_image_free(&img);
        sl_error_prefix(err, "%s: ", name);
        return false;
    }
    sl_image_flip_rows(&img); /* top first -> bottom first */
    memcpy((*out)->storage, img.data, (size_t)img.width * (size_t)img.height * 3 * sizeof(float));
    sl_image_free(&img);
    build_mips(*out);
    return true;
}

bool sl_texture_load_memory(const unsigned char *bytes, size_t size, const char *name, bool srgb, size_t budget,
                            sl_texture **out, sl_error *err)
{
    *out = NULL;
    if (size >= 2 && bytes[0] == '#' && bytes[1] == '?')
        return load_hdr(bytes, size, name, budget, out, err);
    return load_png_jpeg(bytes, size, name, srgb, budget, out, err);
}

/* The first bytes of a PNG, JPEG, BMP, TGA or Radiance file; anything else fails before the rest is read. */
static bool magic_any(const unsigned char *head, size_t size, const char *name, sl_error *err)
{
    if (size >= 2 && head[0] == '#' && head[1] == '?')
        return true;
    if (sl_image_magic_texture(head, size, name, NULL))
        return true;
    return sl_fail(err, SL_ERR_FORMAT, "%s: byte 0: not a PNG, JPEG, BMP, TGA or Radiance .hdr file (expected the "
                   "PNG signature, a JPEG start-of-image marker, \"BM\", a .tga name with a TGA header, or \"#?\")",
                   name);
}

bool sl_texture_load(const char *path, bool srgb, size_t budget, sl_texture **out, sl_error *err)
{
    *out = NULL;
    if (!budget)
        budget = SL_IMAGE_BUDGET_DEFAULT;
    size_t cap = budget < (size_t)INT_MAX - SL_IMAGE_HEADER_SLACK ? budget + SL_IMAGE_HEADER_SLACK : (size_t)INT_MAX;
    char why[96];
    snprintf(why, sizeof why, " by the image memory budget (raise it with %s)", sl_options[SL_OPT_IMAGE_MEMORY].cli);
    unsigned char *bytes;
    size_t size;
    if (!sl_read_file_checked(path, cap, why, SL_IMAGE_MAGIC_BYTES, magic_any, &bytes, &size, err))
        return false;
    bool ok = sl_texture_load_memory(bytes, size, path, srgb, budget, out, err);
    free(bytes);
    return ok;
}
