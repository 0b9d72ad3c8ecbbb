/* hdr.c - Radiance RGBE (.hdr) images, read and written by hand.
 *
 * Why not stb_image: Debian 12's stb_image can loop forever on a truncated .hdr
 * (docs/conventions.md, erratum 6). This reader bounds-checks every byte it reads, and every error names
 * the file, the byte offset and what was expected there; a truncated file is
 * reported at the offset where it ends.
 *
 * What is read: the "#?RADIANCE" or "#?RGBE" magic, header lines up to a blank line
 * (FORMAT=32-bit_rle_rgbe required if present, XYZE refused, EXPOSURE and the rest
 * ignored: values are returned as stored, as rgbe.c does), the resolution line
 * "-Y height +X width" (other orientations are refused by name), then scanlines, each
 * either new-style run-length coded (2, 2, width_hi, width_lo, then each component's runs)
 * or flat pixels with the old-style runs of the pre-1991 format: a pixel (1, 1, 1, n)
 * repeats the pixel before it n << shift times, where shift is 0 and grows by 8 with each
 * run that directly follows another (Radiance's oldreadcolrs). As there, runs stay inside
 * their scanline; one that starts a scanline or overflows it is an error.
 *
 * Header lines may end in CRLF (the magic, the blank line and the resolution line too). Such a
 * file has usually been through a text conversion that also turned 0x0A bytes of its pixels
 * into 0x0D 0x0A, so it is read only if its pixels end exactly at the end of the file, and any
 * error in its pixels says that the header's lines end in CRLF. A header line that looks like
 * the resolution line, or holds control bytes, is reported where it starts: the blank line
 * that ends the header is missing.
 *
 * The declared size is checked against the image memory budget (image.h) before the image
 * is allocated.
 *
 * Decoding: (m, e) -> m * 2^(e - 136), and e = 0 -> 0, as in Greg Ward's rgbe.c, the
 * library the specification ships (Radiance itself adds 0.5 to m; the difference is
 * half a mantissa step). The writer rounds to nearest for this decoding, so a written
 * value returns within half a mantissa step of the largest component. */
#include "image.h"

#include <softlight/glsl.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* RLE scanlines exist only for widths 8..32767: the width must fit the 15-bit field. */
#define RLE_MIN_WIDTH 8
#define RLE_MAX_WIDTH 32767
/* A run is one count byte (128 + length, length 1..127) and one value byte. */
#define RLE_MAX_RUN 127
#define RLE_MAX_LITERAL 128
/* Runs shorter than this are cheaper as literals. */
#define RLE_MIN_RUN 4

typedef struct {
    const unsigned char *p;
    size_t size, pos;
    const char *name;
    sl_error *err;
    bool crlf; /* a header line ended in "\r\n" */
} reader;

/* Copy up to 40 bytes of the file into `out` for a message, replacing what is not printable. */
static const char *excerpt(const unsigned char *s, size_t len, char out[48])
{
    size_t n = len < 40 ? len : 40;
    for (size_t i = 0; i < n; i++)
        out[i] = (s[i] >= 32 && s[i] < 127) ? (char)s[i] : '?';
    if (len > n) {
        memcpy(out + n, "...", 3);
        n += 3;
    }
    out[n] = '\0';
    return out;
}

/* The next header line [*start, *start + *len) without its '\n' (or "\r\n"); the reader moves past it. */
static bool next_line(reader *r, size_t *start, size_t *len, const char *what)
{
    const unsigned char *nl = r->pos < r->size ? memchr(r->p + r->pos, '\n', r->size - r->pos) : NULL;
    if (!nl)
        return sl_fail(r->err, SL_ERR_FORMAT, "%s: byte %zu: unexpected end of file, expected the end of the %s",
                       r->name, r->size, what);
    *start = r->pos;
    *len = (size_t)(nl - (r->p + r->pos));
    r->pos += *len + 1;
    if (*len > 0 && r->p[*start + *len - 1] == '\r') {
        --*len;
        r->crlf = true;
    }
    return true;
}

/* Add to a message about the pixels of a file whose header lines end in CRLF what probably happened. */
static bool crlf_hint(const reader *r)
{
    if (r->crlf && r->err) {
        size_t n = strlen(r->err->msg);
        snprintf(r->err->msg + n, sizeof r->err->msg - n,
                 " (the header's lines end in CRLF: was the file converted as text, which also changes its pixels?)");
    }
    return false;
}

static bool parse_magic(reader *r)
{
    static const char *const magics[] = {"#?RADIANCE\n", "#?RADIANCE\r\n", "#?RGBE\n", "#?RGBE\r\n"};
    for (size_t i = 0; i < sizeof magics / sizeof magics[0]; i++) {
        size_t n = strlen(magics[i]);
        size_t avail = r->size < n ? r->size : n;
        if (avail > 0 && memcmp(r->p, magics[i], avail) != 0)
            continue;
        if (avail < n)
            return sl_fail(r->err, SL_ERR_FORMAT,
                           "%s: byte %zu: unexpected end of file, expected the line '#?RADIANCE' or '#?RGBE'",
                           r->name, r->size);
        r->pos = n;
        r->crlf = magics[i][n - 2] == '\r';
        return true;
    }
    char ex[48];
    return sl_fail(r->err, SL_ERR_FORMAT,
                   "%s: byte 0: not a Radiance .hdr file: expected the line '#?RADIANCE' or '#?RGBE', found '%s'",
                   r->name, excerpt(r->p, r->size, ex));
}

bool sl_image_magic_hdr(const unsigned char *head, size_t size, const char *name, sl_error *err)
{
    reader r = {.p = head, .size = head ? size : 0, .name = name ? name : "(memory)", .err = err};
    return parse_magic(&r);
}

/* "-Y 512 ...": what a resolution line starts with. */
static bool looks_like_resolution(const unsigned char *s, size_t len)
{
    return len >= 4 && (s[0] == '-' || s[0] == '+') && (s[1] == 'X' || s[1] == 'Y') && s[2] == ' ' && s[3] >= '0' &&
           s[3] <= '9';
}

/* Header lines up to the blank line; only FORMAT matters. */
static bool parse_header_lines(reader *r)
{
    for (;;) {
        size_t start, len;
        if (!next_line(r, &start, &len, "header (a blank line ends it)"))
            return false;
        if (len == 0)
            return true;
        const unsigned char *s = r->p + start;
        char ex[48];
        if (looks_like_resolution(s, len))
            return sl_fail(r->err, SL_ERR_FORMAT,
                           "%s: byte %zu: found the resolution line '%s' in the header: expected a blank line "
                           "before it (the end of the header)",
                           r->name, start, excerpt(s, len, ex));
        for (size_t i = 0; i < len; i++)
            if (s[i] < 32 && s[i] != '\t')
                return sl_fail(r->err, SL_ERR_FORMAT,
                               "%s: byte %zu: binary data (byte 0x%02x) in the header line starting at byte %zu: "
                               "expected text lines ended by a blank line",
                               r->name, start + i, s[i], start);
        static const char key[] = "FORMAT=";
        if (len < sizeof key - 1 || memcmp(s, key, sizeof key - 1) != 0)
            continue; /* EXPOSURE, GAMMA, SOFTWARE, comments: not needed to read the pixels */
        const unsigned char *v = s + sizeof key - 1;
        size_t vlen = len - (sizeof key - 1);
        if (vlen == 15 && !memcmp(v, "32-bit_rle_rgbe", 15))
            continue;
        if (vlen == 15 && !memcmp(v, "32-bit_rle_xyze", 15))
            return sl_fail(r->err, SL_ERR_UNSUPPORTED,
                           "%s: byte %zu: FORMAT=32-bit_rle_xyze (CIE XYZ) is not supported, only "
                           "32-bit_rle_rgbe; convert the file to RGB first",
                           r->name, start);
        return sl_fail(r->err, SL_ERR_FORMAT, "%s: byte %zu: unknown FORMAT '%s', expected 32-bit_rle_rgbe",
                       r->name, start, excerpt(v, vlen, ex));
    }
}

/* One axis token of the resolution line: [+-][XY]. */
static bool parse_axis(const unsigned char *s, size_t len, size_t *i, char *sign, char *axis)
{
    if (*i + 2 > len || (s[*i] != '+' && s[*i] != '-') || (s[*i + 1] != 'X' && s[*i + 1] != 'Y'))
        return false;
    *sign = (char)s[*i];
    *axis = (char)s[*i + 1];
    *i += 2;
    return true;
}

/* A decimal count of at most 9 digits (so it cannot overflow an int). */
static bool parse_count(const unsigned char *s, size_t len, size_t *i, int *value)
{
    size_t begin = *i;
    long v = 0;
    while (*i < len && s[*i] >= '0' && s[*i] <= '9' && *i - begin < 9)
        v = v * 10 + (s[(*i)++] - '0');
    if (*i == begin || (*i < len && s[*i] >= '0' && s[*i] <= '9'))
        return false;
    *value = (int)v;
    return true;
}

/* "-Y height +X width": rows top to bottom, pixels left to right (the only orientation read). */
static bool parse_resolution(reader *r, int *width, int *height, size_t *at)
{
    size_t start, len;
    if (!next_line(r, &start, &len, "resolution line (like '-Y 512 +X 1024')"))
        return false;
    const unsigned char *s = r->p + start;
    size_t i = 0;
    char s1 = 0, a1 = 0, s2 = 0, a2 = 0;
    int n1 = 0, n2 = 0;
    bool ok = parse_axis(s, len, &i, &s1, &a1) && i < len && s[i++] == ' ' && parse_count(s, len, &i, &n1) &&
              i < len && s[i++] == ' ' && parse_axis(s, len, &i, &s2, &a2) && i < len && s[i++] == ' ' &&
              parse_count(s, len, &i, &n2) && i == len && a1 != a2;
    char ex[48];
    if (!ok)
        return sl_fail(r->err, SL_ERR_FORMAT,
                       "%s: byte %zu: expected a resolution line like '-Y 512 +X 1024', found '%s'", r->name, start,
                       excerpt(s, len, ex));
    if (!(s1 == '-' && a1 == 'Y' && s2 == '+' && a2 == 'X'))
        return sl_fail(r->err, SL_ERR_UNSUPPORTED,
                       "%s: byte %zu: orientation '%c%c %c%c' ('%s') is not supported, only '-Y height +X width' "
                       "(rows top to bottom, pixels left to right)",
                       r->name, start, s1, a1, s2, a2, excerpt(s, len, ex));
    *height = n1;
    *width = n2;
    *at = start;
    if (n1 <= 0 || n2 <= 0)
        return sl_fail(r->err, SL_ERR_FORMAT, "%s: byte %zu: image size %dx%d: width and height must be positive",
                       r->name, start, n2, n1);
    if (n1 > SL_IMAGE_MAX_SIDE || n2 > SL_IMAGE_MAX_SIDE || (long long)n1 * n2 > SL_IMAGE_MAX_PIXELS)
        return sl_fail(r->err, SL_ERR_RANGE,
                       "%s: byte %zu: image size %dx%d is over the limits (%d on a side, %lld pixels)", r->name,
                       start, n2, n1, SL_IMAGE_MAX_SIDE, SL_IMAGE_MAX_PIXELS);
    return true;
}

/* The fewest bytes one scanline can take: a first pixel and old-style runs, k of them in a row
 * repeating up to 256^k - 1 pixels (new-style scanlines take more). Checking height * this
 * against what is left turns a truncated file into an error before a large allocation; the
 * memory budget bounds what a short file can declare. */
static size_t min_scanline_bytes(int width)
{
    size_t bytes = 4;
    for (unsigned long long covered = 1; covered < (unsigned long long)width; covered = covered * 256 + 255)
        bytes += 4;
    return bytes;
}

/* Decode scanline `y` into four planes (r, g, b, e), each `width` bytes. */
static bool read_scanline(reader *r, int y, int width, unsigned char *planes)
{
    const unsigned char *s = r->p + r->pos;
    size_t left = r->size - r->pos;
    bool rle = width >= RLE_MIN_WIDTH && width <= RLE_MAX_WIDTH && left >= 4 && s[0] == 2 && s[1] == 2 &&
               !(s[2] & 0x80);
    if (!rle) {
        /* flat pixels and old-style runs */
        int shift = 0;
        for (int x = 0; x < width;) {
            if (r->size - r->pos < 4)
                return sl_fail(r->err, SL_ERR_FORMAT,
                               "%s: byte %zu: unexpected end of file in scanline %d, expected the RGBE pixel %d "
                               "(4 bytes) from byte %zu",
                               r->name, r->size, y, x, r->pos);
            s = r->p + r->pos;
            if (!(s[0] == 1 && s[1] == 1 && s[2] == 1)) {
                for (int c = 0; c < 4; c++)
                    planes[(size_t)c * (size_t)width + (size_t)x] = s[c];
                x++;
                shift = 0;
                r->pos += 4;
                continue;
            }
            if (x == 0)
                return sl_fail(r->err, SL_ERR_FORMAT,
                               "%s: byte %zu: scanline %d starts with an old-style run (1,1,1,%d): expected a "
                               "pixel before it to repeat",
                               r->name, r->pos, y, s[3]);
            /* shift stays below 64; past 24, any non-zero count is more than a scanline holds */
            unsigned long long run = shift > 24 ? (s[3] ? ~0ull : 0) : (unsigned long long)s[3] << shift;
            if (run > (unsigned long long)(width - x))
                return sl_fail(r->err, SL_ERR_FORMAT,
                               "%s: byte %zu: scanline %d: old-style run of %s%llu at pixel %d overflows width %d",
                               r->name, r->pos, y, run == ~0ull ? "more than " : "",
                               run == ~0ull ? (unsigned long long)width : run, x, width);
            for (int c = 0; c < 4; c++) {
                unsigned char *plane = planes + (size_t)c * (size_t)width;
                memset(plane + x, plane[x - 1], (size_t)run);
            }
            x += (int)run;
            shift = shift > 24 ? shift : shift + 8;
            r->pos += 4;
        }
        return true;
    }
    int declared = (s[2] << 8) | s[3];
    if (declared != width)
        return sl_fail(r->err, SL_ERR_FORMAT, "%s: byte %zu: scanline %d declares width %d, the image is %d wide",
                       r->name, r->pos, y, declared, width);
    r->pos += 4;
    for (int c = 0; c < 4; c++) {
        unsigned char *plane = planes + (size_t)c * (size_t)width;
        int x = 0;
        while (x < width) {
            if (r->pos >= r->size)
                return sl_fail(r->err, SL_ERR_FORMAT,
                               "%s: byte %zu: unexpected end of file in scanline %d, expected the run count of "
                               "component %d at pixel %d",
                               r->name, r->size, y, c, x);
            size_t at = r->pos;
            int count = r->p[r->pos++];
            if (count > 128) {
                int run = count - 128;
                if (run > width - x)
                    return sl_fail(r->err, SL_ERR_FORMAT,
                                   "%s: byte %zu: scanline %d component %d: run of %d at pixel %d overflows width %d",
                                   r->name, at, y, c, run, x, width);
                if (r->pos >= r->size)
                    return sl_fail(r->err, SL_ERR_FORMAT,
                                   "%s: byte %zu: unexpected end of file in scanline %d, expected the value of a "
                                   "run of %d in component %d",
                                   r->name, r->size, y, run, c);
                memset(plane + x, r->p[r->pos++], (size_t)run);
                x += run;
            } else {
                if (count == 0)
                    return sl_fail(r->err, SL_ERR_FORMAT,
                                   "%s: byte %zu: scanline %d component %d: literal of length 0 at pixel %d",
                                   r->name, at, y, c, x);
                if (count > width - x)
                    return sl_fail(r->err, SL_ERR_FORMAT,
                                   "%s: byte %zu: scanline %d component %d: literal of %d at pixel %d overflows "
                                   "width %d",
                                   r->name, at, y, c, count, x, width);
                if (r->size - r->pos < (size_t)count)
                    return sl_fail(r->err, SL_ERR_FORMAT,
                                   "%s: byte %zu: unexpected end of file in scanline %d, expected %d literal "
                                   "bytes of component %d from byte %zu",
                                   r->name, r->size, y, count, c, r->pos);
                memcpy(plane + x, r->p + r->pos, (size_t)count);
                r->pos += (size_t)count;
                x += count;
            }
        }
    }
    return true;
}

bool sl_image_parse_hdr(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_image *img,
                        sl_image_repairs *repairs, sl_error *err)
{
    *img = (sl_image){0};
    if (repairs)
        *repairs = (sl_image_repairs){0};
    reader r = {.p = bytes, .size = bytes ? size : 0, .name = name ? name : "(memory)", .err = err};
    int width = 0, height = 0;
    size_t res_at = 0;
    if (!parse_magic(&r) || !parse_header_lines(&r) || !parse_resolution(&r, &width, &height, &res_at))
        return false;
    size_t min_bytes = min_scanline_bytes(width) * (size_t)height;
    if (r.size - r.pos < min_bytes) {
        sl_fail(err, SL_ERR_FORMAT,
                "%s: byte %zu: unexpected end of file: %d scanlines of width %d need at least %zu bytes "
                "from byte %zu, only %zu remain",
                r.name, r.size, height, width, min_bytes, r.pos, r.size - r.pos);
        return crlf_hint(&r);
    }
    size_t need = (size_t)width * (size_t)height * 3 * sizeof(float); /* and 4 * width for one scanline */
    if (!sl_image_check_budget(r.name, res_at, width, height, need, budget, err))
        return false;
    unsigned char *planes = malloc(4 * (size_t)width);
    if (!planes)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for a scanline of width %d", r.name, width);
    if (!sl_image_alloc(img, width, height, 3, err)) {
        free(planes);
        sl_error_prefix(err, "%s: ", r.name);
        return false;
    }
    /* 2^(e - 136) for every exponent byte; e = 0 means black. Products m * 2^k are exact in float
     * (subnormal results included: they are multiples of 2^-149). */
    float scale[256];
    scale[0] = 0.0f;
    for (int e = 1; e < 256; e++)
        scale[e] = ldexpf(1.0f, e - 136);
    for (int y = 0; y < height; y++) {
        if (!read_scanline(&r, y, width, planes)) {
            free(planes);
            sl_image_free(img);
            return crlf_hint(&r);
        }
        const unsigned char *pr = planes, *pg = planes + width, *pb = planes + 2 * width, *pe = planes + 3 * width;
        float *out = sl_image_pixel(img, 0, y);
        for (int x = 0; x < width; x++) {
            float f = scale[pe[x]];
            out[3 * x + 0] = (float)pr[x] * f;
            out[3 * x + 1] = (float)pg[x] * f;
            out[3 * x + 2] = (float)pb[x] * f;
        }
    }
    free(planes);
    if (r.crlf && r.pos != r.size) {
        sl_image_free(img);
        sl_fail(err, SL_ERR_FORMAT, "%s: byte %zu: %zu bytes after the pixel data", r.name, r.pos, r.size - r.pos);
        return crlf_hint(&r);
    }
    /* RGBE cannot encode NaN, Inf or negatives; the pass keeps the loader contract uniform. */
    sl_image_repair(img, repairs);
    return true;
}

bool sl_image_read_hdr(const char *path, size_t budget, sl_image *img, sl_image_repairs *repairs, sl_error *err)
{
    return sl_image_read_with(path, budget, sl_image_magic_hdr, sl_image_parse_hdr, img, repairs, err);
}

/* ---- writing ---- */

/* The largest RGBE value: mantissa 255, exponent byte 255. */
#define RGBE_MAX 0x1.fep126f /* 255 * 2^119 */

/* Round-to-nearest RGBE for the m * 2^(e - 136) decoding. Values are made safe first
 * (NaN and negatives -> 0, above RGBE_MAX -> RGBE_MAX) so the writer never emits an
 * exponent byte outside 1..255. */
static void float_to_rgbe(const float *rgb, unsigned char out[4])
{
    float c[3];
    for (int i = 0; i < 3; i++)
        c[i] = rgb[i] > 0.0f ? (rgb[i] < RGBE_MAX ? rgb[i] : RGBE_MAX) : 0.0f;
    float v = maxf(c[0], maxf(c[1], c[2]));
    if (v < 1e-32f) { /* as rgbe.c: too small to matter, and keeps e + 128 >= 1 */
        out[0] = out[1] = out[2] = out[3] = 0;
        return;
    }
    int e;
    frexpf(v, &e); /* v = f * 2^e, f in [0.5, 1) */
    float s = ldexpf(1.0f, 8 - e); /* v * s in [128, 256), exact: s is a power of two */
    if (v * s + 0.5f >= 256.0f) {  /* would round up to 256: use the next exponent */
        e += 1;
        s *= 0.5f;
    }
    for (int i = 0; i < 3; i++)
        out[i] = (unsigned char)(c[i] * s + 0.5f);
    out[3] = (unsigned char)(e + 128);
}

/* Run-length code one plane of `width` bytes; returns the bytes written to `out`
 * (at most width + ceil(width / 128)). */
static size_t rle_plane(const unsigned char *data, int width, unsigned char *out)
{
    size_t o = 0;
    int cur = 0;
    while (cur < width) {
        /* find the next run worth coding as a run */
        int beg = cur, run = 0;
        while (beg < width) {
            run = 1;
            while (beg + run < width && run < RLE_MAX_RUN && data[beg + run] == data[beg])
                run++;
            if (run >= RLE_MIN_RUN)
                break;
            beg += run;
        }
        while (cur < beg) {
            int n = beg - cur < RLE_MAX_LITERAL ? beg - cur : RLE_MAX_LITERAL;
            out[o++] = (unsigned char)n;
            memcpy(out + o, data + cur, (size_t)n);
            o += (size_t)n;
            cur += n;
        }
        if (beg < width) {
            out[o++] = (unsigned char)(128 + run);
            out[o++] = data[beg];
            cur = beg + run;
        }
    }
    return o;
}

bool sl_image_encode_hdr(const sl_image *img, unsigned char **bytes, size_t *size, sl_error *err)
{
    *bytes = NULL;
    *size = 0;
    if (!img || !img->data || img->width <= 0 || img->height <= 0)
        return sl_fail(err, SL_ERR_RANGE, "hdr writer: empty image");
    if (img->channels != 3)
        return sl_fail(err, SL_ERR_RANGE, "hdr writer: needs 3 channels (RGB), the image has %d", img->channels);
    int w = img->width, h = img->height;
    char header[128];
    int hlen = snprintf(header, sizeof header,
                        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nSOFTWARE=softlight\n\n-Y %d +X %d\n", h, w);
    bool rle = w >= RLE_MIN_WIDTH && w <= RLE_MAX_WIDTH;
    size_t line_max = rle ? 4 + 4 * ((size_t)w + (size_t)w / RLE_MAX_LITERAL + 1) : 4 * (size_t)w;
    if ((size_t)h > (SIZE_MAX - (size_t)hlen) / line_max)
        return sl_fail(err, SL_ERR_MEMORY, "hdr writer: image %dx%d is too large", w, h);
    size_t cap = (size_t)hlen + line_max * (size_t)h;
    unsigned char *buf = malloc(cap);
    unsigned char *planes = malloc(4 * (size_t)w);
    if (!buf || !planes) {
        free(buf);
        free(planes);
        return sl_fail(err, SL_ERR_MEMORY, "hdr writer: out of memory for %zu bytes", cap);
    }
    memcpy(buf, header, (size_t)hlen);
    size_t o = (size_t)hlen;
    for (int y = 0; y < h; y++) {
        const float *row = sl_image_pixel(img, 0, y);
        if (!rle) {
            for (int x = 0; x < w; x++, o += 4)
                float_to_rgbe(row + 3 * x, buf + o);
            continue;
        }
        for (int x = 0; x < w; x++) {
            unsigned char p[4];
            float_to_rgbe(row + 3 * x, p);
            for (int c = 0; c < 4; c++)
                planes[(size_t)c * (size_t)w + (size_t)x] = p[c];
        }
        buf[o++] = 2;
        buf[o++] = 2;
        buf[o++] = (unsigned char)(w >> 8);
        buf[o++] = (unsigned char)(w & 0xff);
        for (int c = 0; c < 4; c++)
            o += rle_plane(planes + (size_t)c * (size_t)w, w, buf + o);
    }
    free(planes);
    *bytes = buf;
    *size = o;
    return true;
}

bool sl_image_write_hdr(const char *path, const sl_image *img, sl_error *err)
{
    return sl_image_write_with(path, sl_image_encode_hdr, img, err);
}
