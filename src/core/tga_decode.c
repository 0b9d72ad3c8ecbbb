/* tga_decode.c - TGA (Truevision) decoding, for textures: the pixels as stored, 8 bits, grey, RGB
 * or RGBA, row 0 = top.
 *
 * Read: colour-mapped (8-bit indices into a 15/16/24/32-bit map), true-colour (15/16, 24, 32
 * bits: BGR, BGRA) and grey (8 bits), each uncompressed or run-length encoded; the origin bits
 * (bottom-up unless bit 5 of the descriptor is set; right-to-left when bit 4 is). TGA has no
 * signature: a file is taken for a TGA by its name (.tga) and a header whose fields make sense.
 * A run may not cross the image's end, and every read is checked against the file's size. */
#include "raw_decode.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static uint32_t le16(const unsigned char *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8; }

bool sl_tga_header_plausible(const unsigned char *h, size_t size)
{
    if (size < 18)
        return false;
    int map_type = h[1], type = h[2], depth = h[16];
    bool mapped = type == 1 || type == 9, truecolour = type == 2 || type == 10, grey = type == 3 || type == 11;
    return map_type <= 1 && (mapped || truecolour || grey) && le16(h + 12) > 0 && le16(h + 14) > 0 &&
           (mapped ? map_type == 1 && depth == 8 && (h[7] == 15 || h[7] == 16 || h[7] == 24 || h[7] == 32)
                   : truecolour ? depth == 15 || depth == 16 || depth == 24 || depth == 32 : depth == 8);
}

/* One stored pixel of `bytes_per` bytes (BGR order, 5-5-5 packed at two bytes) as RGBA. */
static void expand(const unsigned char *p, int bytes_per, bool grey, unsigned char rgba[4])
{
    if (grey) {
        rgba[0] = rgba[1] = rgba[2] = p[0];
        rgba[3] = 255;
    } else if (bytes_per == 2) {
        uint32_t v = le16(p);
        rgba[0] = (unsigned char)(((v >> 10) & 31) * 255 / 31);
        rgba[1] = (unsigned char)(((v >> 5) & 31) * 255 / 31);
        rgba[2] = (unsigned char)((v & 31) * 255 / 31);
        rgba[3] = 255;
    } else {
        rgba[0] = p[2], rgba[1] = p[1], rgba[2] = p[0];
        rgba[3] = bytes_per == 4 ? p[3] : 255;
    }
}

bool sl_tga_decode(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_raw_extra_fn extra,
                   sl_raw_image *out, sl_error *err)
{
    *out = (sl_raw_image){0};
    if (!sl_tga_header_plausible(bytes, size))
        return sl_fail(err, SL_ERR_FORMAT, "%s: not a TGA file softlight reads (image types 1-3 and 9-11; 8-bit "
                       "indices or grey, 15-32-bit colour)", name);
    int type = bytes[2], depth = bytes[16], descriptor = bytes[17];
    bool mapped = type == 1 || type == 9, grey = type == 3 || type == 11, rle = type >= 9;
    int w = (int)le16(bytes + 12), h = (int)le16(bytes + 14);
    size_t at = 18 + (size_t)bytes[0];
    size_t map_first = le16(bytes + 3), map_count = le16(bytes + 5), map_bytes = ((size_t)bytes[7] + 7) / 8;
    const unsigned char *map = bytes + at;
    if (bytes[1] == 1) {
        if (at + map_count * map_bytes > size)
            return sl_fail(err, SL_ERR_FORMAT, "%s: truncated TGA colour map", name);
        at += map_count * map_bytes;
    }
    int bytes_per = (depth + 7) / 8;
    int channels = grey ? 1 : (mapped ? (bytes[7] == 32 ? 4 : 3) : (depth == 32 ? 4 : 3));
    if (!sl_raw_admit(name, 12, w, h, channels, 8, 0, budget, extra, err))
        return false;
    size_t count = (size_t)w * (size_t)h;
    unsigned char *pixels = malloc(count * (size_t)channels);
    if (!pixels)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for a %dx%d TGA", name, w, h);
    bool bottom_up = !(descriptor & 0x20), right_to_left = (descriptor & 0x10) != 0;
    size_t i = 0;
    const char *why = NULL;
    while (i < count && !why) {
        size_t run = 1;
        bool repeat = false;
        if (rle) {
            if (at >= size) {
                why = "truncated TGA: its pixel data ends early";
                break;
            }
            repeat = bytes[at] & 0x80;
            run = (size_t)(bytes[at] & 0x7f) + 1;
            at++;
            if (run > count - i) {
                why = "TGA run past the image's end";
                break;
            }
        } else {
            run = count - i; /* raw: every pixel follows */
        }
        for (size_t k = 0; k < run; k++, i++) {
            if (k == 0 || !repeat) {
                if (at > size || (size_t)bytes_per > size - at) {
                    why = "truncated TGA: its pixel data ends early";
                    break;
                }
            }
            const unsigned char *src = bytes + at;
            unsigned char rgba[4];
            if (mapped) {
                size_t index = src[0];
                if (index < map_first || index - map_first >= map_count) {
                    why = "TGA colour index outside its colour map";
                    break;
                }
                expand(map + (index - map_first) * map_bytes, (int)map_bytes, false, rgba);
            } else {
                expand(src, bytes_per, grey, rgba);
            }
            if (!repeat || k + 1 == run)
                at += (size_t)bytes_per;
            size_t x = i % (size_t)w, y = i / (size_t)w;
            if (right_to_left)
                x = (size_t)w - 1 - x;
            if (bottom_up)
                y = (size_t)h - 1 - y;
            memcpy(pixels + (y * (size_t)w + x) * (size_t)channels, rgba, (size_t)channels);
        }
    }
    if (why) {
        free(pixels);
        return sl_fail(err, SL_ERR_FORMAT, "%s: %s", name, why);
    }
    *out = (sl_raw_image){.width = w, .height = h, .channels = channels, .bits = 8, .pixels = pixels};
    return true;
}
