/* bmp_decode.c - BMP decoding, for textures: the pixels as stored, 8 bits, RGB or RGBA, row 0 =
 * top.
 *
 * Read: the BITMAPINFOHEADER family (40-byte and the V4/V5 headers that extend it; the 12-byte
 * OS/2 core header), 1, 4 and 8 bits through a palette, 24 bits, and 16 or 32 bits either as
 * BI_RGB (5-5-5, 8-8-8 with the fourth byte unused) or through BI_BITFIELDS masks (an alpha
 * mask gives an RGBA image). Rows are bottom-up unless the height is negative. Not read: the
 * RLE, JPEG and PNG compressions (refused by name). Every field is checked against the file's
 * size before it is used: the header's sizes and offsets come from the file. */
#include "raw_decode.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint32_t le16(const unsigned char *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8; }
static uint32_t le32(const unsigned char *p) { return le16(p) | le16(p + 2) << 16; }

/* A channel of `mask` (contiguous bits) scaled to 0..255. */
static unsigned char from_mask(uint32_t v, uint32_t mask)
{
    if (!mask)
        return 0;
    int shift = 0;
    while (!(mask & 1u))
        mask >>= 1, shift++;
    uint64_t c = (v >> shift) & mask;
    return (unsigned char)((c * 255u + (mask >> 1)) / mask);
}

bool sl_bmp_decode(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_raw_extra_fn extra,
                   sl_raw_image *out, sl_error *err)
{
    *out = (sl_raw_image){0};
    if (size < 26)
        return sl_fail(err, SL_ERR_FORMAT, "%s: truncated BMP header (%zu bytes)", name, size);
    uint32_t data_at = le32(bytes + 10), header = le32(bytes + 14);
    int64_t w, h;
    uint32_t bpp, compression = 0, palette_count = 0, masks[4] = {0};
    size_t palette_at = 14 + (size_t)header, palette_entry = 4;
    if (header == 12) { /* OS/2 core header: 16-bit sizes, 3-byte palette entries */
        w = le16(bytes + 18);
        h = (int16_t)le16(bytes + 20);
        bpp = le16(bytes + 24);
        palette_entry = 3;
    } else if (header >= 40 && header <= 124 && size >= 14 + (size_t)header) {
        w = (int32_t)le32(bytes + 18);
        h = (int32_t)le32(bytes + 22);
        bpp = le16(bytes + 28);
        compression = le32(bytes + 30);
        palette_count = le32(bytes + 46);
        if (compression == 3 || compression == 6) { /* BI_BITFIELDS, BI_ALPHABITFIELDS */
            size_t at = 14 + 40; /* after the 40-byte header, or inside the longer ones */
            int n = compression == 6 || header >= 56 ? 4 : 3;
            if (at + 4 * (size_t)n > size)
                return sl_fail(err, SL_ERR_FORMAT, "%s: truncated BMP colour masks", name);
            for (int i = 0; i < n; i++)
                masks[i] = le32(bytes + at + 4 * (size_t)i);
            if (header < 52)
                palette_at += 4 * (size_t)n;
        }
    } else {
        return sl_fail(err, SL_ERR_FORMAT, "%s: BMP header of %u bytes (softlight reads 12, and 40 to 124)", name,
                       header);
    }
    bool top_down = h < 0;
    if (top_down)
        h = -h;
    if (w <= 0 || h <= 0 || w > SL_IMAGE_MAX_SIDE || h > SL_IMAGE_MAX_SIDE)
        return sl_fail(err, SL_ERR_RANGE, "%s: BMP of %lldx%lld pixels (each side 1..%d)", name, (long long)w,
                       (long long)h, SL_IMAGE_MAX_SIDE);
    if (compression != 0 && compression != 3 && compression != 6)
        return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: compressed BMP (compression %u: RLE, JPEG or PNG inside a BMP), "
                       "which softlight does not read; save it uncompressed", name, compression);
    if (bpp != 1 && bpp != 4 && bpp != 8 && bpp != 16 && bpp != 24 && bpp != 32)
        return sl_fail(err, SL_ERR_FORMAT, "%s: BMP of %u bits per pixel (1, 4, 8, 16, 24 or 32)", name, bpp);
    if (compression && bpp != 16 && bpp != 32)
        return sl_fail(err, SL_ERR_FORMAT, "%s: BMP colour masks on %u bits per pixel (16 or 32)", name, bpp);
    if (!compression && bpp == 16)
        masks[0] = 0x7c00, masks[1] = 0x03e0, masks[2] = 0x001f;
    if (!compression && bpp == 32)
        masks[0] = 0xff0000, masks[1] = 0xff00, masks[2] = 0xff;
    if (bpp <= 8) {
        uint32_t most = 1u << bpp;
        if (palette_count == 0 || palette_count > most)
            palette_count = most;
        if (palette_at + palette_count * palette_entry > size)
            return sl_fail(err, SL_ERR_FORMAT, "%s: truncated BMP palette", name);
    }
    int channels = masks[3] ? 4 : 3;
    size_t stride = ((size_t)w * bpp + 31) / 32 * 4;
    if (data_at > size || stride * (size_t)h > size - data_at)
        return sl_fail(err, SL_ERR_FORMAT, "%s: truncated BMP: %lld rows of %zu bytes from byte %u, the file has %zu",
                       name, (long long)h, stride, data_at, size);
    if (!sl_raw_admit(name, 18, (int)w, (int)h, channels, 8, 0, budget, extra, err))
        return false;
    unsigned char *pixels = malloc((size_t)w * (size_t)h * (size_t)channels);
    if (!pixels)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for a %lldx%lld BMP", name, (long long)w, (long long)h);
    for (int64_t y = 0; y < h; y++) {
        const unsigned char *row = bytes + data_at + stride * (size_t)(top_down ? y : h - 1 - y);
        unsigned char *o = pixels + (size_t)y * (size_t)w * (size_t)channels;
        for (int64_t x = 0; x < w; x++, o += channels) {
            if (bpp <= 8) {
                size_t bit = (size_t)x * bpp;
                uint32_t index = (row[bit / 8] >> (8 - bpp - bit % 8)) & ((1u << bpp) - 1);
                if (index >= palette_count)
                    index = 0; /* an index past a short palette: the first colour, as viewers show it */
                const unsigned char *e = bytes + palette_at + index * palette_entry;
                o[0] = e[2], o[1] = e[1], o[2] = e[0];
            } else if (bpp == 24) {
                const unsigned char *p = row + 3 * (size_t)x;
                o[0] = p[2], o[1] = p[1], o[2] = p[0];
            } else {
                uint32_t v = bpp == 16 ? le16(row + 2 * (size_t)x) : le32(row + 4 * (size_t)x);
                for (int c = 0; c < channels; c++)
                    o[c] = from_mask(v, masks[c]);
            }
        }
    }
    *out = (sl_raw_image){.width = (int)w, .height = (int)h, .channels = channels, .bits = 8, .pixels = pixels};
    return true;
}
