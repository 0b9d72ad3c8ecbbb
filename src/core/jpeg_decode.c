/* jpeg_decode.c - JPEG decoding through libjpeg-turbo, for textures: 8-bit grey (one component)
 * or RGB (three: YCbCr or RGB; four: CMYK or YCCK, multiplied into RGB), row 0 = top.
 *
 * libjpeg-turbo is the reference decoder and is maintained for untrusted input; this file feeds
 * it from memory and chooses its settings: the accurate integer IDCT (JDCT_ISLOW), fancy
 * (triangle) chroma upsampling and no block smoothing, the closest match to other common
 * decoders' output.
 *
 * libjpeg calls error_exit on a fatal error and would exit(); here it longjmp's back. A warning
 * from libjpeg means corrupt or missing entropy-coded data (it would go on, filling the gap
 * with grey), so every warning about the data is an error too: a texture is whole or refused.
 * Limits: each side at most SL_IMAGE_MAX_SIDE, at most JPEG_MAX_SCANS scans (a progressive file
 * can spend unbounded time in thousands of tiny scans), and the budget (sl_raw_admit) counts
 * the coefficient buffer of a progressive or multi-scan file as libjpeg allocates it (blocks
 * padded to whole MCUs) before anything that size is allocated. */
#include "raw_decode.h"

#include <limits.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jerror.h>
#include <jpeglib.h>

#define JPEG_MAX_SCANS 500

typedef struct {
    struct jpeg_error_mgr mgr; /* first: libjpeg hands back a pointer to it */
    struct jpeg_progress_mgr progress;
    struct jpeg_decompress_struct d;
    jmp_buf jump;
    int too_many_scans;
    unsigned char *pixels, *cmyk; /* what is allocated while libjpeg may longjmp, freed on failure */
} jpeg_state;

static void on_error_exit(j_common_ptr c)
{
    longjmp(((jpeg_state *)(void *)c->err)->jump, 1);
}

/* Level -1 is a warning; higher levels are trace messages. Two warnings are about metadata
 * whose value libjpeg then replaces by the usual default, and leave the pixels defined. */
static void on_message(j_common_ptr c, int level)
{
    int code = c->err->msg_code;
    if (level < 0 && code != JWRN_JFIF_MAJOR && code != JWRN_ADOBE_XFORM)
        on_error_exit(c);
}

static void on_output(j_common_ptr c)
{
    (void)c;
}

static void on_progress(j_common_ptr c)
{
    j_decompress_ptr d = (j_decompress_ptr)(void *)c;
    if (d->input_scan_number > JPEG_MAX_SCANS) {
        ((jpeg_state *)(void *)c->err)->too_many_scans = 1;
        on_error_exit(c);
    }
}

/* (x * y + 128) / 255 rounded, in integers: a CMYK channel times K. */
static unsigned char times_k(unsigned x, unsigned k)
{
    unsigned t = x * k + 128;
    return (unsigned char)((t + (t >> 8)) >> 8);
}

static size_t round_up(size_t v, size_t m)
{
    return (v + m - 1) / m * m;
}

static bool fail_libjpeg(j_decompress_ptr d, jpeg_state *s, const char *name, size_t size, sl_error *err)
{
    size_t at = d->src ? size - d->src->bytes_in_buffer : 0;
    int code = s->mgr.msg_code;
    if (s->too_many_scans)
        return sl_fail(err, SL_ERR_FORMAT, "%s: byte %zu: corrupt JPEG: more than %d scans", name, at, JPEG_MAX_SCANS);
    if (code == JWRN_JPEG_EOF || code == JERR_INPUT_EOF || code == JERR_INPUT_EMPTY)
        return sl_fail(err, SL_ERR_FORMAT, "%s: byte %zu: truncated JPEG", name, at);
    char text[JMSG_LENGTH_MAX];
    s->mgr.format_message((j_common_ptr)d, text);
    const char *what = text; /* libjpeg's data warnings start with this, which the message says already */
    if (!strncmp(what, "Corrupt JPEG data: ", 19))
        what += 19;
    if (code == JERR_OUT_OF_MEMORY || code == JERR_NO_BACKING_STORE)
        return sl_fail(err, SL_ERR_MEMORY, "%s: JPEG: out of memory (%s)", name, what);
    return sl_fail(err, SL_ERR_FORMAT, "%s: byte %zu: corrupt JPEG: %s", name, at, what);
}

/* Everything between jpeg_create_decompress and its destruction: libjpeg's errors come back
 * here through setjmp (the state that must survive the jump lives in *s, outside this frame). */
static bool decode(jpeg_state *s, const unsigned char *bytes, size_t size, const char *name, size_t budget,
                   sl_raw_extra_fn extra, sl_raw_image *out, sl_error *err)
{
    j_decompress_ptr d = &s->d;
    if (setjmp(s->jump))
        return fail_libjpeg(d, s, name, size, err);
    jpeg_create_decompress(d);
    s->progress.progress_monitor = on_progress;
    d->progress = &s->progress;
    jpeg_mem_src(d, bytes, (unsigned long)size);
    jpeg_read_header(d, TRUE);
    int w = (int)d->image_width, h = (int)d->image_height, n = d->num_components;
    if (w > SL_IMAGE_MAX_SIDE || h > SL_IMAGE_MAX_SIDE)
        return sl_fail(err, SL_ERR_RANGE, "%s: JPEG: image too large: %dx%d is over %d on a side", name, w, h,
                       SL_IMAGE_MAX_SIDE);
    if (n != 1 && n != 3 && n != 4)
        return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: JPEG: %d colour components (expected 1, 3 or 4)", name, n);
    int channels = n == 1 ? 1 : 3;
    d->out_color_space = n == 1 ? JCS_GRAYSCALE : n == 3 ? JCS_RGB : JCS_CMYK;
    d->dct_method = JDCT_ISLOW;
    d->do_fancy_upsampling = TRUE;
    d->do_block_smoothing = FALSE;
    /* libjpeg's buffers: the whole-image coefficient array (JCOEF per sample, blocks padded to
     * the MCU) when the file has several scans, and a few MCU rows for upsampling and colour
     * conversion; the output image and a row of CMYK beside them */
    size_t coefficients = 0, row_samples = 0;
    for (int c = 0; c < n; c++) {
        const jpeg_component_info *ci = &d->comp_info[c];
        size_t bw = round_up(ci->width_in_blocks, (size_t)ci->h_samp_factor);
        size_t bh = round_up(ci->height_in_blocks, (size_t)ci->v_samp_factor);
        coefficients += bw * bh * DCTSIZE2 * sizeof(JCOEF);
        row_samples += bw * DCTSIZE * (size_t)d->max_v_samp_factor;
    }
    size_t image = (size_t)w * (size_t)h * (size_t)channels;
    size_t decoder = coefficients + image + 4 * row_samples * (size_t)d->max_h_samp_factor + 4 * (size_t)w;
    if (!sl_raw_admit(name, 0, w, h, channels, 8, decoder, budget, extra, err))
        return false;
    d->mem->max_memory_to_use = (long)(decoder + ((size_t)1 << 20) < (size_t)LONG_MAX ? decoder + ((size_t)1 << 20)
                                                                                     : (size_t)LONG_MAX);

    jpeg_start_decompress(d);
    if (d->output_width != (JDIMENSION)w || d->output_height != (JDIMENSION)h ||
        d->output_components != (n == 4 ? 4 : channels))
        return sl_fail(err, SL_ERR_FORMAT, "%s: JPEG: unexpected output layout (%ux%u, %d components)", name,
                       (unsigned)d->output_width, (unsigned)d->output_height, d->output_components);
    s->pixels = malloc(image);
    if (n == 4)
        s->cmyk = malloc(4 * (size_t)w);
    if (!s->pixels || (n == 4 && !s->cmyk))
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for a %dx%d image", name, w, h);
    while (d->output_scanline < d->output_height) {
        unsigned char *row = s->pixels + (size_t)d->output_scanline * (size_t)w * (size_t)channels;
        JSAMPROW into = n == 4 ? s->cmyk : row;
        if (jpeg_read_scanlines(d, &into, 1) != 1)
            return sl_fail(err, SL_ERR_FORMAT, "%s: truncated JPEG", name);
        if (n == 4) /* Adobe's CMYK is stored inverted: each colour channel times K is the RGB value */
            for (int x = 0; x < w; x++) {
                const unsigned char *p = s->cmyk + 4 * (size_t)x;
                for (int c = 0; c < 3; c++)
                    row[3 * (size_t)x + (size_t)c] = times_k(p[c], p[3]);
            }
    }
    jpeg_finish_decompress(d);
    *out = (sl_raw_image){w, h, channels, 8, s->pixels};
    s->pixels = NULL;
    return true;
}

bool sl_jpeg_decode(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_raw_extra_fn extra,
                    sl_raw_image *out, sl_error *err)
{
    *out = (sl_raw_image){0};
    jpeg_state *s = calloc(1, sizeof *s);
    if (!s)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for the JPEG decoder", name);
    s->d.err = jpeg_std_error(&s->mgr); /* kept by jpeg_create_decompress, which clears the rest */
    s->mgr.error_exit = on_error_exit;
    s->mgr.emit_message = on_message;
    s->mgr.output_message = on_output;
    bool ok = decode(s, bytes, size, name, budget, extra, out, err);
    jpeg_destroy_decompress(&s->d); /* also after a failed create: it frees what exists */
    free(s->pixels);
    free(s->cmyk);
    free(s);
    return ok;
}
