/* pfm.c - Portable Float Map (.pfm) images: float32 pixels behind a short text header.
 *
 *   "PF" (RGB) or "Pf" (grey), whitespace, width, whitespace, height, whitespace,
 *   scale, ONE whitespace character, then width * height * channels float32 values,
 *   rows from the BOTTOM of the image to the top.
 * The sign of the scale gives the byte order (negative = little endian, positive =
 * big endian); its magnitude is a unit hint that softlight ignores. Both byte orders are
 * read; files are written little endian with scale -1. The declared size is checked against the
 * image memory budget (image.h) before the image is allocated. The header is parsed strictly
 * and by hand (no strtod, so the locale cannot change it); a short data section, or
 * bytes after it, is an error naming the offset. */
#include "image.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    const unsigned char *p;
    size_t size, pos;
    const char *name;
    sl_error *err;
} reader;

static bool is_space(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

static uint32_t load_u32(const unsigned char *s, bool little_endian)
{
    if (little_endian)
        return (uint32_t)s[0] | (uint32_t)s[1] << 8 | (uint32_t)s[2] << 16 | (uint32_t)s[3] << 24;
    return (uint32_t)s[3] | (uint32_t)s[2] << 8 | (uint32_t)s[1] << 16 | (uint32_t)s[0] << 24;
}

static char printable(unsigned char c) { return (c >= 32 && c < 127) ? (char)c : '?'; }

/* At least one whitespace character, then any more; `next` names what must follow. */
static bool skip_space(reader *r, const char *after, const char *next)
{
    if (r->pos >= r->size)
        return sl_fail(r->err, SL_ERR_FORMAT, "%s: byte %zu: unexpected end of file, expected whitespace and %s",
                       r->name, r->size, next);
    if (!is_space(r->p[r->pos]))
        return sl_fail(r->err, SL_ERR_FORMAT, "%s: byte %zu: expected whitespace after %s, found '%c'", r->name,
                       r->pos, after, printable(r->p[r->pos]));
    while (r->pos < r->size && is_space(r->p[r->pos]))
        r->pos++;
    if (r->pos >= r->size)
        return sl_fail(r->err, SL_ERR_FORMAT, "%s: byte %zu: unexpected end of file, expected %s", r->name,
                       r->size, next);
    return true;
}

/* A positive decimal of at most 9 digits. */
static bool parse_dim(reader *r, const char *what, int *value)
{
    size_t begin = r->pos;
    long v = 0;
    while (r->pos < r->size && r->p[r->pos] >= '0' && r->p[r->pos] <= '9' && r->pos - begin < 9)
        v = v * 10 + (r->p[r->pos++] - '0');
    if (r->pos == begin)
        return sl_fail(r->err, SL_ERR_FORMAT, "%s: byte %zu: expected the %s (a decimal number), found '%c'",
                       r->name, begin, what, printable(r->p[begin]));
    if (r->pos < r->size && r->p[r->pos] >= '0' && r->p[r->pos] <= '9')
        return sl_fail(r->err, SL_ERR_RANGE, "%s: byte %zu: the %s has more than 9 digits", r->name, begin, what);
    if (v == 0)
        return sl_fail(r->err, SL_ERR_FORMAT, "%s: byte %zu: the %s is 0, expected a positive number", r->name,
                       begin, what);
    *value = (int)v;
    return true;
}

/* The scale: [+-] digits [. digits] [e [+-] digits], not zero. Only its sign is used. */
static bool parse_scale(reader *r, bool *little_endian)
{
    size_t begin = r->pos, i = r->pos;
    const unsigned char *s = r->p;
    bool negative = false, nonzero = false;
    size_t digits = 0;
    if (i < r->size && (s[i] == '+' || s[i] == '-'))
        negative = s[i++] == '-';
    for (; i < r->size && s[i] >= '0' && s[i] <= '9'; i++, digits++)
        nonzero |= s[i] != '0';
    if (i < r->size && s[i] == '.')
        for (i++; i < r->size && s[i] >= '0' && s[i] <= '9'; i++, digits++)
            nonzero |= s[i] != '0';
    bool ok = digits > 0;
    if (ok && i < r->size && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        if (i < r->size && (s[i] == '+' || s[i] == '-'))
            i++;
        size_t exp_begin = i;
        while (i < r->size && s[i] >= '0' && s[i] <= '9')
            i++;
        ok = i > exp_begin;
    }
    if (i >= r->size)
        return sl_fail(r->err, SL_ERR_FORMAT,
                       "%s: byte %zu: unexpected end of file, expected one whitespace character after the scale",
                       r->name, r->size);
    if (!ok || !is_space(s[i])) {
        char ex[24];
        size_t n = 0;
        for (size_t k = begin; k < r->size && n < 16 && !is_space(s[k]); k++)
            ex[n++] = printable(s[k]);
        ex[n] = '\0';
        return sl_fail(r->err, SL_ERR_FORMAT,
                       "%s: byte %zu: expected the scale (a number such as -1.0), found '%s'", r->name, begin, ex);
    }
    if (!nonzero)
        return sl_fail(r->err, SL_ERR_FORMAT,
                       "%s: byte %zu: the scale is 0; its sign must give the byte order (negative = little endian)",
                       r->name, begin);
    r->pos = i + 1; /* exactly one whitespace character ends the header */
    *little_endian = negative;
    return true;
}

bool sl_image_magic_pfm(const unsigned char *head, size_t size, const char *name, sl_error *err)
{
    if (!head)
        size = 0;
    if (size < 2 && (size == 0 || head[0] == 'P'))
        return sl_fail(err, SL_ERR_FORMAT, "%s: byte %zu: unexpected end of file, expected 'PF' or 'Pf'", name, size);
    if (head[0] != 'P' || (head[1] != 'F' && head[1] != 'f'))
        return sl_fail(err, SL_ERR_FORMAT,
                       "%s: byte 0: not a PFM file: expected 'PF' (colour) or 'Pf' (grey), found '%c%c'", name,
                       printable(head[0]), size > 1 ? printable(head[1]) : ' ');
    return true;
}

/* The PFM parser; `signed_values` keeps negative floats (positions, normals) and turns NaN/Inf
 * into an error instead of repairing them. */
static bool parse_pfm(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_image *img,
                      sl_image_repairs *repairs, bool signed_values, sl_error *err)
{
    *img = (sl_image){0};
    if (repairs)
        *repairs = (sl_image_repairs){0};
    reader r = {.p = bytes, .size = bytes ? size : 0, .name = name ? name : "(memory)", .err = err};
    if (!sl_image_magic_pfm(r.p, r.size, r.name, err))
        return false;
    int channels = r.p[1] == 'F' ? 3 : 1;
    r.pos = 2;
    int width = 0, height = 0;
    bool little_endian = true;
    size_t header_at = 0; /* where the width begins */
    if (!skip_space(&r, "'PF'", "the width") || (header_at = r.pos, !parse_dim(&r, "width", &width)) ||
        !skip_space(&r, "the width", "the height") || !parse_dim(&r, "height", &height) ||
        !skip_space(&r, "the height", "the scale") || !parse_scale(&r, &little_endian))
        return false;
    if (width > SL_IMAGE_MAX_SIDE || height > SL_IMAGE_MAX_SIDE ||
        (long long)width * height > SL_IMAGE_MAX_PIXELS)
        return sl_fail(err, SL_ERR_RANGE, "%s: image size %dx%d is over the limits (%d on a side, %lld pixels)",
                       r.name, width, height, SL_IMAGE_MAX_SIDE, SL_IMAGE_MAX_PIXELS);
    size_t row_floats = (size_t)width * (size_t)channels;
    size_t need = row_floats * (size_t)height * 4;
    size_t left = r.size - r.pos;
    if (left < need)
        return sl_fail(err, SL_ERR_FORMAT,
                       "%s: byte %zu: unexpected end of file, expected %zu bytes of pixel data (%dx%dx%d floats) "
                       "from byte %zu",
                       r.name, r.size, need, width, height, channels, r.pos);
    if (left > need)
        return sl_fail(err, SL_ERR_FORMAT, "%s: byte %zu: %zu unexpected bytes after the pixel data", r.name,
                       r.pos + need, left - need);
    if (!sl_image_check_budget(r.name, header_at, width, height,
                               (size_t)width * (size_t)height * (size_t)channels * sizeof(float), budget, err))
        return false;
    if (!sl_image_alloc(img, width, height, channels, err)) {
        sl_error_prefix(err, "%s: ", r.name);
        return false;
    }
    const unsigned char *src = r.p + r.pos;
    for (int fy = 0; fy < height; fy++) {
        float *dst = sl_image_pixel(img, 0, height - 1 - fy); /* file rows run bottom to top */
        for (size_t i = 0; i < row_floats; i++, src += 4) {
            uint32_t u = load_u32(src, little_endian);
            memcpy(&dst[i], &u, 4);
        }
    }
    if (!signed_values) {
        sl_image_repair(img, repairs);
        return true;
    }
    long nan_count = 0, inf_count = 0;
    for (size_t i = 0; i < row_floats * (size_t)height; i++) {
        nan_count += isnan(img->data[i]) != 0;
        inf_count += isinf(img->data[i]) != 0;
    }
    if (nan_count || inf_count) {
        sl_image_free(img);
        return sl_fail(err, SL_ERR_FORMAT, "%s: %ld NaN and %ld infinite values", r.name, nan_count, inf_count);
    }
    return true;
}

bool sl_image_parse_pfm(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_image *img,
                        sl_image_repairs *repairs, sl_error *err)
{
    return parse_pfm(bytes, size, name, budget, img, repairs, false, err);
}

bool sl_image_parse_pfm_signed(const unsigned char *bytes, size_t size, const char *name, size_t budget,
                               sl_image *img, sl_image_repairs *repairs, sl_error *err)
{
    return parse_pfm(bytes, size, name, budget, img, repairs, true, err);
}

bool sl_image_read_pfm_signed(const char *path, size_t budget, sl_image *img, sl_error *err)
{
    return sl_image_read_with(path, budget, sl_image_magic_pfm, sl_image_parse_pfm_signed, img, NULL, err);
}

bool sl_image_read_pfm(const char *path, size_t budget, sl_image *img, sl_image_repairs *repairs, sl_error *err)
{
    return sl_image_read_with(path, budget, sl_image_magic_pfm, sl_image_parse_pfm, img, repairs, err);
}

bool sl_image_encode_pfm(const sl_image *img, unsigned char **bytes, size_t *size, sl_error *err)
{
    *bytes = NULL;
    *size = 0;
    if (!img || !img->data || img->width <= 0 || img->height <= 0)
        return sl_fail(err, SL_ERR_RANGE, "pfm writer: empty image");
    if (img->channels != 1 && img->channels != 3)
        return sl_fail(err, SL_ERR_RANGE, "pfm writer: needs 1 or 3 channels, the image has %d", img->channels);
    char header[64];
    int hlen = snprintf(header, sizeof header, "%s\n%d %d\n-1.0\n", img->channels == 3 ? "PF" : "Pf", img->width,
                        img->height);
    size_t row_floats = (size_t)img->width * (size_t)img->channels;
    if (row_floats > (SIZE_MAX - 64) / 4 / (size_t)img->height)
        return sl_fail(err, SL_ERR_MEMORY, "pfm writer: image %dx%d is too large", img->width, img->height);
    size_t total = (size_t)hlen + row_floats * (size_t)img->height * 4;
    unsigned char *buf = malloc(total);
    if (!buf)
        return sl_fail(err, SL_ERR_MEMORY, "pfm writer: out of memory for %zu bytes", total);
    memcpy(buf, header, (size_t)hlen);
    unsigned char *o = buf + hlen;
    for (int fy = 0; fy < img->height; fy++) {
        const float *row = sl_image_pixel(img, 0, img->height - 1 - fy);
        for (size_t i = 0; i < row_floats; i++, o += 4) {
            uint32_t u;
            memcpy(&u, &row[i], 4);
            o[0] = (unsigned char)u;
            o[1] = (unsigned char)(u >> 8);
            o[2] = (unsigned char)(u >> 16);
            o[3] = (unsigned char)(u >> 24);
        }
    }
    *bytes = buf;
    *size = total;
    return true;
}

bool sl_image_write_pfm(const char *path, const sl_image *img, sl_error *err)
{
    return sl_image_write_with(path, sl_image_encode_pfm, img, err);
}
