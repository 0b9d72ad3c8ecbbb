/* png.c - PNG and JPEG through stb: PNG writing (stb_image_write, 8-bit), PNG/JPEG decoding
 * as stored (8 or 16 bits, 1 to 4 channels: sl_image_parse_raw, what raster/texture.c loads)
 * and the linear float reading of sl_image_read_texture (the exact sRGB -> linear curve).
 *
 * This file holds the one copy of stb_image and stb_image_write in softlight (their
 * IMPLEMENTATION macros are defined here and nowhere else). stb_image is built for PNG
 * and JPEG only: .hdr files must never reach it (docs/conventions.md, erratum 6: it can loop forever on a
 * truncated one); hdr.c reads those.
 *
 * stb's own limits: STBI_MAX_DIMENSIONS (set to SL_IMAGE_MAX_SIDE below) and sizes that overflow
 * an int; nothing else. Its inflater grows its output by doubling up to 2 GiB whatever the
 * image's size, so a small PNG whose compressed data inflates past the image (a zlib bomb)
 * could take gigabytes. Every allocation stb makes therefore goes through stb_alloc below,
 * which refuses to let stb's live buffers exceed the image memory budget of the read in
 * progress. stb has no context pointer for its allocator, so that budget is per thread
 * (_Thread_local), set by sl_image_parse_raw for the length of the stb call only. */
#include "image.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* stb is third-party code: its own warnings are not ours to fix. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
/* What stb may still allocate in the current thread's read (SIZE_MAX outside one), and the size
 * stored before each block so that a free or a realloc gives its bytes back. */
static _Thread_local size_t stb_left = SIZE_MAX;
#define STB_HEADER 16 /* keeps stb's blocks aligned as malloc's */

static void *stb_alloc(void *old, size_t size)
{
    size_t old_size = 0;
    unsigned char *base = NULL;
    if (old) {
        base = (unsigned char *)old - STB_HEADER;
        memcpy(&old_size, base, sizeof old_size);
    }
    if (size > SIZE_MAX - STB_HEADER || (size > old_size && size - old_size > stb_left))
        return NULL;
    unsigned char *p = realloc(base, size + STB_HEADER);
    if (!p)
        return NULL;
    if (stb_left != SIZE_MAX)
        stb_left = stb_left + old_size - size;
    memcpy(p, &size, sizeof size);
    return p + STB_HEADER;
}

static void stb_free(void *p)
{
    if (!p)
        return;
    unsigned char *base = (unsigned char *)p - STB_HEADER;
    size_t size;
    memcpy(&size, base, sizeof size);
    if (stb_left != SIZE_MAX)
        stb_left += size;
    free(base);
}

#define STBI_MALLOC(sz) stb_alloc(NULL, sz)
#define STBI_REALLOC(p, newsz) stb_alloc(p, newsz)
#define STBI_FREE(p) stb_free(p)
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#define STBI_MAX_DIMENSIONS SL_IMAGE_MAX_SIDE
#include <stb/stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

/* ---- writing ---- */

typedef struct {
    unsigned char *data;
    size_t size, cap;
    bool failed;
} mem_sink;

/* stb_image_write hands over the finished PNG through this callback (in one or more pieces). */
static void sink_write(void *context, void *data, int size)
{
    mem_sink *s = context;
    if (s->failed || size <= 0)
        return;
    if (s->size + (size_t)size > s->cap) {
        size_t cap = s->cap ? s->cap : 4096;
        while (cap < s->size + (size_t)size)
            cap *= 2;
        unsigned char *grown = realloc(s->data, cap);
        if (!grown) {
            s->failed = true;
            return;
        }
        s->data = grown;
        s->cap = cap;
    }
    memcpy(s->data + s->size, data, (size_t)size);
    s->size += (size_t)size;
}

/* [0, 1] -> 0..255 (sl_unorm8, image.h). */
static unsigned char to_byte(float v) { return (unsigned char)sl_unorm8(v); }

bool sl_image_encode_png(const sl_image *img, unsigned char **bytes, size_t *size, sl_error *err)
{
    *bytes = NULL;
    *size = 0;
    if (!img || !img->data || img->width <= 0 || img->height <= 0)
        return sl_fail(err, SL_ERR_RANGE, "png writer: empty image");
    if (img->channels != 1 && img->channels != 3)
        return sl_fail(err, SL_ERR_RANGE, "png writer: needs 1 or 3 channels, the image has %d", img->channels);
    if (img->width > SL_IMAGE_MAX_SIDE || img->height > SL_IMAGE_MAX_SIDE)
        return sl_fail(err, SL_ERR_RANGE, "png writer: image %dx%d is over %d on a side", img->width, img->height,
                       SL_IMAGE_MAX_SIDE);
    size_t count = (size_t)img->width * (size_t)img->height * (size_t)img->channels;
    unsigned char *pixels = malloc(count);
    if (!pixels)
        return sl_fail(err, SL_ERR_MEMORY, "png writer: out of memory for %zu bytes", count);
    for (size_t i = 0; i < count; i++)
        pixels[i] = to_byte(img->data[i]);
    mem_sink sink = {0};
    int ok = stbi_write_png_to_func(sink_write, &sink, img->width, img->height, img->channels, pixels,
                                    img->width * img->channels);
    free(pixels);
    if (!ok || sink.failed) {
        free(sink.data);
        return sl_fail(err, SL_ERR_MEMORY, "png writer: encoding a %dx%d image failed (out of memory)", img->width,
                       img->height);
    }
    *bytes = sink.data;
    *size = sink.size;
    return true;
}

bool sl_image_write_png(const char *path, const sl_image *img, sl_error *err)
{
    return sl_image_write_with(path, sl_image_encode_png, img, err);
}

/* ---- reading ---- */

/* IEC 61966-2-1: c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055)^2.4, in double, then rounded once. */
float sl_srgb8_to_linear(unsigned char code)
{
    double c = code / 255.0;
    return (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
}

/* The PNG signature or a JPEG's SOI marker and the first marker after it. */
bool sl_image_magic_texture(const unsigned char *head, size_t size, const char *name, sl_error *err)
{
    static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}, jpeg[3] = {0xff, 0xd8, 0xff};
    if ((size >= sizeof png && !memcmp(head, png, sizeof png)) || (size >= sizeof jpeg && !memcmp(head, jpeg, sizeof jpeg)))
        return true;
    return sl_fail(err, SL_ERR_FORMAT, "%s: byte 0: not a PNG or JPEG file (expected the PNG signature or a JPEG "
                   "start-of-image marker)", name);
}

/* Debian 12's stb_image trusts a JPEG's Huffman tables in two ways that are undefined
 * behaviour on corrupt files (both found by fuzz_texture; later stb versions check the first):
 * - more than 256 codes in one table (DHT, its 16 code counts) write past its 257-entry size
 *   list and 256-entry value list;
 * - a scan (SOS) naming a table no DHT defined decodes with that table's uninitialised memory
 *   (stb mallocs its decoder): the result depends on the heap, and a garbage table indexes past
 *   its lists. A baseline scan uses each component's DC and AC tables; a progressive scan its DC
 *   table in a first DC scan (Ss = 0, Ah = 0), its AC table in an AC scan (Ss > 0).
 * Walk the JPEG's marker segments, skipping entropy-coded data (progressive files have tables
 * between scans), and refuse either before stb sees it. Anything else malformed is left to stb's
 * own checks. */
static bool jpeg_tables_ok(const unsigned char *b, size_t size, const char *name, sl_error *err)
{
    bool defined[2][4] = {{false}}; /* [DC 0, AC 1][table id] */
    bool progressive = false;
    size_t pos = 2; /* after SOI */
    while (pos + 4 <= size) {
        if (b[pos] != 0xff) { /* entropy-coded data: up to the next marker that is not a stuffed 0 or a restart */
            pos++;
            continue;
        }
        unsigned marker = b[pos + 1];
        if (marker == 0xff || marker == 0x00 || marker == 0x01 || marker == 0xd8 || (marker >= 0xd0 && marker <= 0xd7)) {
            pos += marker == 0xff ? 1 : 2;
            continue;
        }
        if (marker == 0xd9)
            return true;
        size_t end = pos + 2 + (((size_t)b[pos + 2] << 8) | b[pos + 3]);
        if (marker == 0xc2)
            progressive = true;
        if (marker == 0xc4) /* tables while the segment lasts; stb reads bytes past the file's end as 0 */
            for (size_t q = pos + 4; q < end;) {
                size_t n = 0;
                for (size_t i = q + 1; i <= q + 16 && i < size; i++)
                    n += b[i];
                if (n > 256)
                    return sl_fail(err, SL_ERR_FORMAT,
                                   "%s: byte %zu: corrupt JPEG: a Huffman table (DHT) of %zu codes, more than 256",
                                   name, q, n);
                unsigned class = q < size ? b[q] >> 4 : 0, id = q < size ? b[q] & 15 : 0;
                if (class < 2 && id < 4) /* stb refuses other classes and ids itself */
                    defined[class][id] = true;
                q += 17 + n;
            }
        if (marker == 0xda && pos + 5 <= size) {
            size_t count = b[pos + 4], spectral = pos + 5 + 2 * count; /* Ss, Se, Ah/Al after the components */
            if (spectral + 3 > size)
                return true; /* stb reports the cut header */
            bool dc_scan = progressive ? b[spectral] == 0 && (b[spectral + 2] >> 4) == 0 : true;
            bool ac_scan = progressive ? b[spectral] > 0 : true;
            for (size_t c = 0; c < count; c++) {
                unsigned dc = b[pos + 6 + 2 * c] >> 4, ac = b[pos + 6 + 2 * c] & 15;
                bool dc_missing = dc_scan && dc < 4 && !defined[0][dc], ac_missing = ac_scan && ac < 4 && !defined[1][ac];
                if (dc_missing || ac_missing)
                    return sl_fail(err, SL_ERR_FORMAT,
                                   "%s: byte %zu: corrupt JPEG: a scan (SOS) uses Huffman table %s%u, which no "
                                   "DHT before it defines", name, pos, dc_missing ? "DC" : "AC", dc_missing ? dc : ac);
            }
        }
        pos = end;
    }
    return true;
}

/* Debian 12's stb_image, given an empty IDAT chunk before any image data, adds its length to
 * a NULL buffer pointer (undefined behaviour; found by fuzz_texture under UBSan). No PNG writer
 * makes one; refuse it before stb reads the file. */
static bool png_chunks_ok(const unsigned char *b, size_t size, const char *name, sl_error *err)
{
    for (size_t pos = 8; pos + 8 <= size;) {
        size_t len = ((size_t)b[pos] << 24) | ((size_t)b[pos + 1] << 16) | ((size_t)b[pos + 2] << 8) | b[pos + 3];
        const unsigned char *type = b + pos + 4;
        if (!memcmp(type, "IDAT", 4)) {
            if (len == 0)
                return sl_fail(err, SL_ERR_FORMAT, "%s: byte %zu: corrupt PNG: an empty IDAT chunk before the "
                               "image data", name, pos);
            return true; /* image data from here on: stb's own checks */
        }
        if (!memcmp(type, "IEND", 4) || len > size)
            return true;
        pos += 12 + len;
    }
    return true;
}

bool sl_image_parse_raw(const unsigned char *bytes, size_t size, const char *name, size_t budget,
                        size_t (*extra)(int width, int height, int channels, int bits), sl_raw_image *out,
                        sl_error *err)
{
    *out = (sl_raw_image){0};
    if (!budget)
        budget = SL_IMAGE_BUDGET_DEFAULT;
    if (!sl_image_magic_texture(bytes, size, name, err))
        return false;
    if (size > (size_t)INT_MAX)
        return sl_fail(err, SL_ERR_RANGE, "%s: the file is over %d bytes", name, INT_MAX);
    if (bytes[0] == 0xff ? !jpeg_tables_ok(bytes, size, name, err) : !png_chunks_ok(bytes, size, name, err))
        return false;
    int w, h, n;
    if (!stbi_info_from_memory(bytes, (int)size, &w, &h, &n))
        return sl_fail(err, SL_ERR_FORMAT, "%s: not a PNG or JPEG image this reader accepts (stb_image: %s)", name,
                       stbi_failure_reason());
    if ((long long)w * h > SL_IMAGE_MAX_PIXELS)
        return sl_fail(err, SL_ERR_RANGE, "%s: image %dx%d has more than %lld pixels", name, w, h,
                       SL_IMAGE_MAX_PIXELS);
    /* stb's result and at most two buffers of the file's own depth inside stb (inflated data and
     * unfiltered image, or a JPEG's planes and the converted result), then what the caller makes
     * of it; the header's offset is 16 in a PNG, unknown in a JPEG (reported as 0). */
    size_t depth = stbi_is_16_bit_from_memory(bytes, (int)size) ? 2 : 1;
    size_t pixels_count = (size_t)w * (size_t)h;
    size_t stb_need = pixels_count * 3 * (size_t)n * depth + (size_t)h;
    size_t more = extra ? extra(w, h, n, (int)depth * 8) : 0;
    if (!sl_image_check_budget(name, bytes[0] == 0x89 ? 16 : 0, w, h, stb_need + more, budget, err))
        return false;
    stb_left = stb_need + ((size_t)1 << 20); /* and a MiB for stb's tables */
    void *pixels = depth == 2 ? (void *)stbi_load_16_from_memory(bytes, (int)size, &w, &h, &n, 0)
                              : (void *)stbi_load_from_memory(bytes, (int)size, &w, &h, &n, 0);
    stb_left = SIZE_MAX;
    if (!pixels && !strcmp(stbi_failure_reason(), "outofmem"))
        return sl_fail(err, SL_ERR_RANGE,
                       "%s: decoding the %dx%d image needs more memory than the image memory budget of %zu MiB "
                       "allows (its compressed data inflates past the image?); raise it with %s",
                       name, w, h, budget >> 20, sl_options[SL_OPT_IMAGE_MEMORY].cli);
    if (!pixels)
        return sl_fail(err, SL_ERR_FORMAT, "%s: cannot decode the image (stb_image: %s)", name,
                       stbi_failure_reason());
    *out = (sl_raw_image){w, h, n, (int)depth * 8, pixels};
    return true;
}

void sl_raw_image_free(sl_raw_image *img)
{
    if (img->pixels)
        stbi_image_free(img->pixels);
    *img = (sl_raw_image){0};
}

/* The float RGB image sl_image_read_texture makes, beside stb's buffers. */
static size_t float_rgb_bytes(int width, int height, int channels, int bits)
{
    (void)channels;
    (void)bits;
    return (size_t)width * (size_t)height * 3 * sizeof(float);
}

bool sl_image_read_texture(const char *path, size_t budget, sl_image *img, sl_error *err)
{
    *img = (sl_image){0};
    unsigned char *bytes;
    size_t size;
    if (!budget)
        budget = SL_IMAGE_BUDGET_DEFAULT;
    size_t cap = budget < (size_t)INT_MAX - SL_IMAGE_HEADER_SLACK ? budget + SL_IMAGE_HEADER_SLACK : (size_t)INT_MAX;
    char why[96];
    snprintf(why, sizeof why, " by the image memory budget (raise it with %s)", sl_options[SL_OPT_IMAGE_MEMORY].cli);
    if (!sl_read_file_checked(path, cap, why, SL_IMAGE_MAGIC_BYTES, sl_image_magic_texture, &bytes, &size, err))
        return false;
    sl_raw_image raw;
    bool ok = sl_image_parse_raw(bytes, size, path, budget, float_rgb_bytes, &raw, err);
    free(bytes);
    if (!ok)
        return false;
    if (!sl_image_alloc(img, raw.width, raw.height, 3, err)) {
        sl_raw_image_free(&raw);
        sl_error_prefix(err, "%s: ", path);
        return false;
    }
    /* grey is replicated, alpha dropped; 16-bit codes through the same curve in double */
    float lut[256];
    for (int i = 0; i < 256; i++)
        lut[i] = sl_srgb8_to_linear((unsigned char)i);
    size_t count = (size_t)raw.width * (size_t)raw.height;
    int n = raw.channels, colour = n >= 3 ? 3 : 1;
    for (size_t i = 0; i < count; i++)
        for (int c = 0; c < 3; c++) {
            size_t k = i * (size_t)n + (size_t)(colour == 3 ? c : 0);
            if (raw.bits == 8) {
                img->data[3 * i + (size_t)c] = lut[((const unsigned char *)raw.pixels)[k]];
            } else {
                double v = ((const unsigned short *)raw.pixels)[k] / 65535.0;
                img->data[3 * i + (size_t)c] = (float)(v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4));
            }
        }
    sl_raw_image_free(&raw);
    return true;
}
