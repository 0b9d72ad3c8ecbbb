/* exr.c - OpenEXR images (.exr) read and written through OpenEXRCore, the C library under
 * Debian's libopenexr-dev (openexr.h; it needs only zlib, no C++ runtime).
 *
 * Reading (environments): part 0 of a file, scanline or tiled (level 0 of a mip- or ripmapped
 * file), any compression the library decodes; channels R, G, B (A and any others ignored) or a
 * lone Y (grey, replicated), each half, float or uint, converted to float by the library's
 * unpacker. The pixels are the data window, row 0 = its top (EXR's y grows downwards, as an
 * sl_image's rows do). The library reads through callbacks over memory (the fuzz target, tests)
 * or over a file descriptor (pread), so a file is never read whole: what is held is the float
 * image and one chunk's buffers, which is what the budget (image.h) is checked against, from
 * the header, before anything that size is allocated. Every chunk's declared sizes are checked
 * against the file and the header before the library allocates for it, and the library's
 * "reconstruction" of damaged chunk tables is turned off, so a damaged file is an error naming
 * it rather than a slow search. The library's own messages go into the one error line, never
 * to stderr.
 *
 * Writing (exr.h): one part of named channels from several sl_images, encoded into memory
 * through a write callback, so the output set (output_set.h) writes the file atomically. */
#include "exr.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <openexr.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---------------------------------------------------------------- the byte source ---- */

/* The library's user data: what it reads from (bytes in memory, or a file read by offset) or
 * writes into (a growing buffer), and where its messages go. */
typedef struct {
    const unsigned char *bytes; /* memory source, or NULL */
    int fd;                     /* file source when bytes is NULL */
    uint64_t size;
    unsigned char *out; /* writing: the file so far (out_size bytes of out_capacity) */
    size_t out_size, out_capacity;
    const char *name;
    char lib_msg[200]; /* the library's first message (on_error) */
    bool writing;
    bool io_failed;
    int io_errno;
} source;

static int64_t source_read(exr_const_context_t ctxt, void *user, void *buffer, uint64_t sz, uint64_t offset,
                           exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    source *s = user;
    if (offset >= s->size)
        return 0;
    uint64_t n = s->size - offset < sz ? s->size - offset : sz;
    if (s->bytes) {
        memcpy(buffer, s->bytes + offset, (size_t)n);
        return (int64_t)n;
    }
    uint64_t done = 0;
    while (done < n) {
        ssize_t got = pread(s->fd, (unsigned char *)buffer + done, (size_t)(n - done), (off_t)(offset + done));
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0) {
            if (got < 0) {
                s->io_failed = true;
                s->io_errno = errno;
                return -1;
            }
            break; /* the file shrank under us: a short read, which the library reports */
        }
        done += (uint64_t)got;
    }
    return (int64_t)done;
}

static int64_t source_size(exr_const_context_t ctxt, void *user)
{
    (void)ctxt;
    return (int64_t)((source *)user)->size;
}

/* The library's messages land here instead of on stderr; the first is kept, being the cause. */
static void on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *user = NULL;
    if (!ctxt || exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user)
        return;
    source *s = user;
    if (s->lib_msg[0])
        return;
    char clean[sizeof s->lib_msg];
    sl_error_excerpt(msg ? msg : exr_get_default_error_message(code), sizeof clean, clean, sizeof clean);
    snprintf(s->lib_msg, sizeof s->lib_msg, "%s", clean);
}

/* One error line for a failed library call: the library's message when it gave one. */
static bool lib_fail(const source *s, exr_result_t rv, const char *doing, sl_error *err)
{
    const char *why = s->lib_msg[0] ? s->lib_msg : exr_get_default_error_message(rv);
    if (s->writing)
        return sl_fail(err, s->io_failed ? SL_ERR_MEMORY : SL_ERR_FORMAT, "exr writer: %s failed: %s", doing,
                       s->io_failed ? strerror(s->io_errno) : why);
    if (s->io_failed)
        return sl_fail(err, SL_ERR_IO, "%s: read failed while %s: %s", s->name, doing, strerror(s->io_errno));
    return sl_fail(err, rv == EXR_ERR_OUT_OF_MEMORY ? SL_ERR_MEMORY : SL_ERR_FORMAT, "%s: not a readable OpenEXR file (%s): %s",
                   s->name, doing, why);
}

/* ---------------------------------------------------------------- reading ---- */

bool sl_image_magic_exr(const unsigned char *head, size_t size, const char *name, sl_error *err)
{
    static const unsigned char magic[4] = {0x76, 0x2f, 0x31, 0x01};
    if (!head)
        size = 0;
    size_t n = size < 4 ? size : 4;
    if (memcmp(head ? head : magic, magic, n) != 0 || size == 0) {
        if (size == 0)
            return sl_fail(err, SL_ERR_FORMAT, "%s: byte 0: unexpected end of file, expected the OpenEXR magic 76 2f 31 01", name);
        return sl_fail(err, SL_ERR_FORMAT,
                       "%s: byte 0: not an OpenEXR file: expected the magic 76 2f 31 01, found %02x %02x %02x %02x",
                       name, head[0], size > 1 ? head[1] : 0, size > 2 ? head[2] : 0, size > 3 ? head[3] : 0);
    }
    if (size < 4)
        return sl_fail(err, SL_ERR_FORMAT, "%s: byte %zu: unexpected end of file in the OpenEXR magic", name, size);
    return true;
}

/* What a read asks for: a layer's channels (component k of the image = channel names[k]), or
 * the environment's R, G, B falling back to a grey Y. */
typedef struct {
    char names[4][80];
    int count;         /* channels named, 1..4 */
    int img_channels;  /* channels of the image decoded into (>= count; 3 for a grey Y) */
    bool environment;  /* R, G, B or Y, repaired; a layer read keeps signed values */
    char layer[72];    /* a layer whose suffixes are to be found: RGB, XYZ or none (names unset) */
    int index[4];      /* each name's index in the file's channel list */
} channel_map;

static int find_channel(const exr_attr_chlist_t *list, const char *name)
{
    for (int i = 0; i < list->num_channels; i++)
        if (list->entries[i].name.str && !strcmp(list->entries[i].name.str, name))
            return i;
    return -1;
}

static bool missing_channels(const source *s, const exr_attr_chlist_t *list, const char *wanted, sl_error *err)
{
    char names[160] = "";
    size_t used = 0;
    int i = 0;
    for (; i < list->num_channels && used + 24 < sizeof names; i++) {
        char ex[20];
        used += (size_t)snprintf(names + used, sizeof names - used, "%s%s", i ? ", " : "",
                                 sl_error_excerpt(list->entries[i].name.str ? list->entries[i].name.str : "", 15, ex, sizeof ex));
    }
    return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: no %s in the first part; it has %d channel%s: %s%s", s->name, wanted,
                   list->num_channels, list->num_channels == 1 ? "" : "s", names, i < list->num_channels ? ", ..." : "");
}

static bool map_channels(const source *s, const exr_attr_chlist_t *list, channel_map *m, sl_error *err)
{
    if (m->environment) {
        bool rgb = find_channel(list, "R") >= 0 && find_channel(list, "G") >= 0 && find_channel(list, "B") >= 0;
        if (!rgb && find_channel(list, "Y") >= 0) {
            if (find_channel(list, "RY") >= 0 || find_channel(list, "BY") >= 0)
                return sl_fail(err, SL_ERR_UNSUPPORTED,
                               "%s: luminance/chroma channels (Y, RY, BY) are not read: convert the file to R, G, B",
                               s->name);
            snprintf(m->names[0], sizeof m->names[0], "Y");
            m->count = 1;
        }
        if (!rgb && m->count != 1)
            return missing_channels(s, list, "R, G, B channels (nor a grey Y)", err);
    }
    if (m->layer[0]) {
        static const char *const sets[] = {"RGB", "XYZ"};
        char first[80], ex[40];
        m->count = m->img_channels = 1;
        snprintf(m->names[0], sizeof m->names[0], "%s", m->layer);
        for (int i = 0; i < 2; i++) {
            snprintf(first, sizeof first, "%s.%c", m->layer, sets[i][0]);
            if (find_channel(list, first) < 0)
                continue;
            m->count = m->img_channels = 3;
            for (int k = 0; k < 3; k++)
                snprintf(m->names[k], sizeof m->names[k], "%s.%c", m->layer, sets[i][k]);
        }
        if (m->count == 1 && find_channel(list, m->layer) < 0) {
            char wanted[200];
            sl_error_excerpt(m->layer, 32, ex, sizeof ex);
            snprintf(wanted, sizeof wanted, "layer %s (%s.R/G/B, %s.X/Y/Z or a channel %s)", ex, ex, ex, ex);
            return missing_channels(s, list, wanted, err);
        }
    }
    for (int k = 0; k < m->count; k++) {
        if ((m->index[k] = find_channel(list, m->names[k])) < 0) {
            char wanted[100], ex[84];
            snprintf(wanted, sizeof wanted, "channel %s", sl_error_excerpt(m->names[k], 79, ex, sizeof ex));
            return missing_channels(s, list, wanted, err);
        }
        const exr_attr_chlist_entry_t *e = &list->entries[m->index[k]];
        if (e->x_sampling != 1 || e->y_sampling != 1)
            return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: channel %s is subsampled (%dx%d); only full-resolution channels are read",
                           s->name, m->names[k], e->x_sampling, e->y_sampling);
    }
    return true;
}

/* Point the decoder's channels at the image: the mapped ones into their component as float,
 * the others skipped (a NULL pointer). `base` is the chunk's first pixel in the image. */
static void aim_decoder(exr_decode_pipeline_t *dec, const channel_map *m, float *base, int width, float *unused,
                        int32_t chunk_width)
{
    for (int c = 0; c < dec->channel_count; c++) {
        exr_coding_channel_info_t *ch = &dec->channels[c];
        int comp = -1;
        for (int k = 0; k < m->count; k++)
            if (!strcmp(ch->channel_name, m->names[k]))
                comp = k;
        ch->user_bytes_per_element = (int16_t)sizeof(float);
        ch->user_data_type = EXR_PIXEL_FLOAT;
        if (comp < 0) { /* decoded and dropped: the library's NULL "skip" crashed under fuzzing */
            ch->decode_to_ptr = (uint8_t *)unused;
            ch->user_pixel_stride = (int32_t)sizeof(float);
            ch->user_line_stride = chunk_width * (int32_t)sizeof(float);
            continue;
        }
        ch->decode_to_ptr = (uint8_t *)(base + comp);
        ch->user_pixel_stride = m->img_channels * (int32_t)sizeof(float);
        ch->user_line_stride = width * m->img_channels * (int32_t)sizeof(float);
    }
}

/* A chunk's first pixel in the image. OpenEXRCore 3.1 gives a scanline chunk's start_y in
 * pixels but a tile's start_x, start_y as tile indices, so a tile's origin is its index times
 * the tile size. */
static void chunk_origin(const exr_chunk_info_t *ci, bool tiled, const exr_attr_box2i_t *dw, int32_t tile_w,
                         int32_t tile_h, int64_t *x0, int64_t *y0)
{
    *x0 = tiled ? (int64_t)ci->start_x * tile_w : (int64_t)ci->start_x - dw->min.x;
    *y0 = tiled ? (int64_t)ci->start_y * tile_h : (int64_t)ci->start_y - dw->min.y;
}

/* The window of a chunk, checked against the image (the library derives it from the header, so
 * a failure here is a library or header inconsistency, reported rather than trusted), and its
 * declared sizes against the file and the header before the library allocates for them. */
static bool chunk_in_image(const source *s, const exr_chunk_info_t *ci, int64_t x0, int64_t y0, int width,
                           int height, uint64_t chunk_bound, sl_error *err)
{
    if (x0 < 0 || y0 < 0 || ci->width <= 0 || ci->height <= 0 || x0 + ci->width > width || y0 + ci->height > height)
        return sl_fail(err, SL_ERR_FORMAT, "%s: chunk %d covers (%lld, %lld) %dx%d, outside the data window", s->name,
                       ci->idx, (long long)x0, (long long)y0, ci->width, ci->height);
    if (ci->packed_size > s->size || ci->data_offset > s->size - ci->packed_size)
        return sl_fail(err, SL_ERR_FORMAT, "%s: byte %llu: chunk %d declares %llu bytes, past the end of the file (%llu bytes)",
                       s->name, (unsigned long long)ci->data_offset, ci->idx, (unsigned long long)ci->packed_size,
                       (unsigned long long)s->size);
    if (ci->unpacked_size > chunk_bound)
        return sl_fail(err, SL_ERR_FORMAT, "%s: chunk %d unpacks to %llu bytes, more than its %dx%d pixels hold",
                       s->name, ci->idx, (unsigned long long)ci->unpacked_size, ci->width, ci->height);
    return true;
}

/* A layer read keeps signed values (positions, normals) but, as sl_image_read_pfm_signed, calls
 * NaN or Inf an error. */
static bool all_finite(const source *s, const sl_image *img, sl_error *err)
{
    size_t n = (size_t)img->width * (size_t)img->height * (size_t)img->channels;
    long nan_count = 0, inf_count = 0;
    for (size_t i = 0; i < n; i++) {
        nan_count += isnan(img->data[i]) != 0;
        inf_count += isinf(img->data[i]) != 0;
    }
    if (nan_count || inf_count)
        return sl_fail(err, SL_ERR_FORMAT, "%s: %ld NaN and %ld infinite values", s->name, nan_count, inf_count);
    return true;
}

static void replicate_grey(sl_image *img)
{
    size_t n = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < n; i++)
        img->data[3 * i + 1] = img->data[3 * i + 2] = img->data[3 * i];
}

/* The reader over a source whose magic was checked. */
static bool parse_source(source *s, channel_map *map, size_t budget, sl_image *img, sl_image_repairs *repairs,
                         sl_error *err)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_error;
    init.user_data = s;
    init.read_fn = source_read;
    init.size_fn = source_size;
    init.max_image_width = init.max_image_height = SL_IMAGE_MAX_SIDE;
    init.max_tile_width = init.max_tile_height = SL_IMAGE_MAX_SIDE;
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    exr_context_t ctx = NULL;
    exr_result_t rv = exr_start_read(&ctx, s->name, &init);
    if (rv != EXR_ERR_SUCCESS) {
        exr_finish(&ctx);
        return lib_fail(s, rv, "reading the header", err);
    }
    exr_decode_pipeline_t dec = {0};
    bool have_decoder = false, ok = false;
    float *unused = NULL; /* where channels the image does not keep are decoded to */
    exr_storage_t storage;
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *list = NULL;
    if ((rv = exr_get_storage(ctx, 0, &storage)) || (rv = exr_get_data_window(ctx, 0, &dw)) ||
        (rv = exr_get_channels(ctx, 0, &list)) || !list) {
        lib_fail(s, rv ? rv : EXR_ERR_MISSING_REQ_ATTR, "reading the header", err);
        goto done;
    }
    if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED) {
        sl_fail(err, SL_ERR_UNSUPPORTED, "%s: a deep OpenEXR image (several samples per pixel) is not an environment",
                s->name);
        goto done;
    }
    int64_t w64 = (int64_t)dw.max.x - dw.min.x + 1, h64 = (int64_t)dw.max.y - dw.min.y + 1;
    if (w64 < 1 || h64 < 1 || w64 > SL_IMAGE_MAX_SIDE || h64 > SL_IMAGE_MAX_SIDE || w64 * h64 > SL_IMAGE_MAX_PIXELS) {
        sl_fail(err, SL_ERR_RANGE, "%s: data window (%d, %d)-(%d, %d) is %lldx%lld, outside the limits (1 to %d on a side, %lld pixels)",
                s->name, dw.min.x, dw.min.y, dw.max.x, dw.max.y, (long long)w64, (long long)h64, SL_IMAGE_MAX_SIDE,
                SL_IMAGE_MAX_PIXELS);
        goto done;
    }
    int width = (int)w64, height = (int)h64;
    if (!map_channels(s, list, map, err))
        goto done;

    /* One chunk's pixels over every channel of the file: what the decoder's packed and unpacked
     * buffers hold at most (plus a scratch buffer of the same size for PIZ, B44, ...). */
    uint64_t pixel_bytes = 0;
    for (int i = 0; i < list->num_channels; i++)
        pixel_bytes += list->entries[i].pixel_type == EXR_PIXEL_HALF ? 2 : 4;
    int32_t cw = width, ch = 1, levels_x = 1, levels_y = 1;
    if (storage == EXR_STORAGE_SCANLINE) {
        rv = exr_get_scanlines_per_chunk(ctx, 0, &ch);
    } else if (!(rv = exr_get_tile_levels(ctx, 0, &levels_x, &levels_y))) {
        rv = exr_get_tile_sizes(ctx, 0, 0, 0, &cw, &ch);
    }
    if (rv || cw < 1 || ch < 1) {
        lib_fail(s, rv ? rv : EXR_ERR_INVALID_ATTR, "reading the chunk layout", err);
        goto done;
    }
    cw = cw < width ? cw : width;
    ch = ch < height ? ch : height;
    uint64_t chunk_bound = (uint64_t)cw * (uint64_t)ch * pixel_bytes;
    uint64_t image_bytes = (uint64_t)width * (uint64_t)height * (uint64_t)map->img_channels * sizeof(float);
    uint64_t unused_bytes = (uint64_t)cw * (uint64_t)ch * sizeof(float);
    uint64_t need = image_bytes + 3 * chunk_bound + unused_bytes;
    if (need > SIZE_MAX || !sl_image_check_budget(s->name, 8, width, height, (size_t)need, budget, err))
        goto done;
    if (!sl_image_alloc(img, width, height, map->img_channels, err)) {
        sl_error_prefix(err, "%s: ", s->name);
        goto done;
    }
    if (!(unused = malloc((size_t)unused_bytes))) {
        sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for a chunk's unused channels", s->name);
        goto done;
    }

    int tiles_x = (width + cw - 1) / cw, tiles_y = (height + ch - 1) / ch;
    for (int ty = 0; ty < tiles_y; ty++) {
        for (int tx = 0; tx < tiles_x; tx++) {
            exr_chunk_info_t ci;
            if (storage == EXR_STORAGE_SCANLINE) {
                rv = exr_read_scanline_chunk_info(ctx, 0, (int)(dw.min.y + (int64_t)ty * ch), &ci);
            } else {
                rv = exr_read_tile_chunk_info(ctx, 0, tx, ty, 0, 0, &ci);
            }
            if (rv) {
                lib_fail(s, rv, "reading a chunk's position", err);
                goto done;
            }
            int64_t x0, y0;
            chunk_origin(&ci, storage == EXR_STORAGE_TILED, &dw, cw, ch, &x0, &y0);
            if (!chunk_in_image(s, &ci, x0, y0, width, height, chunk_bound, err))
                goto done;
            rv = have_decoder ? exr_decoding_update(ctx, 0, &ci, &dec) : exr_decoding_initialize(ctx, 0, &ci, &dec);
            if (rv) {
                lib_fail(s, rv, "setting up a chunk's decoder", err);
                goto done;
            }
            bool first = !have_decoder;
            have_decoder = true;
            aim_decoder(&dec, map, sl_image_pixel(img, (int)x0, (int)y0), width, unused, cw);
            if ((first && (rv = exr_decoding_choose_default_routines(ctx, 0, &dec))) ||
                (rv = exr_decoding_run(ctx, 0, &dec))) {
                char doing[64];
                snprintf(doing, sizeof doing, "decoding chunk %d", ci.idx);
                lib_fail(s, rv, doing, err);
                goto done;
            }
        }
    }
    if (map->environment) {
        if (map->count == 1)
            replicate_grey(img);
        sl_image_repair(img, repairs);
        ok = true;
    } else {
        ok = all_finite(s, img, err);
    }
done:
    free(unused);
    if (have_decoder)
        exr_decoding_destroy(ctx, &dec);
    exr_finish(&ctx);
    if (!ok)
        sl_image_free(img);
    return ok;
}

/* The environment's channels: R, G, B into a 3-channel image (map_channels falls back to Y). */
static channel_map environment_map(void)
{
    return (channel_map){.names = {"R", "G", "B"}, .count = 3, .img_channels = 3, .environment = true};
}

/* A layer's channel names, as sl_exr_encode writes them (suffixes NULL: found in the file). */
static bool layer_map(const char *layer, const char *suffixes, channel_map *m, sl_error *err)
{
    *m = (channel_map){0};
    if (!suffixes && layer && layer[0] && strlen(layer) < sizeof m->layer) {
        snprintf(m->layer, sizeof m->layer, "%s", layer);
        return true;
    }
    size_t n = suffixes ? strlen(suffixes) : 0;
    if (n > 4 || (!n && (!layer || !layer[0])) || (layer && strlen(layer) > 64))
        return sl_fail(err, SL_ERR_RANGE, "exr reader: bad layer request '%.20s' '%.8s'", layer ? layer : "",
                       suffixes ? suffixes : "");
    m->count = m->img_channels = n ? (int)n : 1;
    for (int k = 0; k < m->count; k++) {
        if (!n)
            snprintf(m->names[k], sizeof m->names[k], "%s", layer);
        else if (layer && layer[0])
            snprintf(m->names[k], sizeof m->names[k], "%s.%c", layer, suffixes[k]);
        else
            snprintf(m->names[k], sizeof m->names[k], "%c", suffixes[k]);
    }
    return true;
}

/* Read `size` bytes from memory when `bytes` is not NULL (`path` then only names them), else the
 * file at `path`; `map` says which channels. */
static bool read_exr(const unsigned char *bytes, size_t size, const char *path, channel_map *map, size_t budget,
                     sl_image *img, sl_image_repairs *repairs, sl_error *err)
{
    *img = (sl_image){0};
    if (repairs)
        *repairs = (sl_image_repairs){0};
    if (bytes) {
        source s = {.bytes = bytes, .fd = -1, .size = size, .name = path};
        return sl_image_magic_exr(bytes, s.size, s.name, err) && parse_source(&s, map, budget, img, repairs, err);
    }
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK /* a FIFO must not block the open */);
    if (fd < 0)
        return sl_fail(err, SL_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    bool ok = false;
    if (fstat(fd, &st) != 0) {
        sl_fail(err, SL_ERR_IO, "%s: cannot stat: %s", path, strerror(errno));
    } else if (!S_ISREG(st.st_mode)) {
        /* an .exr is read by offsets (its chunk table points into it), which a pipe cannot do */
        sl_fail(err, SL_ERR_IO, "%s: not a regular file (an OpenEXR file is read by offsets, not as a stream)", path);
    } else {
        unsigned char head[4] = {0};
        source s = {.fd = fd, .size = (uint64_t)st.st_size, .name = path};
        int64_t got = source_read(NULL, &s, head, sizeof head, 0, NULL);
        if (got < 0)
            sl_fail(err, SL_ERR_IO, "%s: read failed at byte 0: %s", path, strerror(s.io_errno));
        else
            ok = sl_image_magic_exr(head, (size_t)got, path, err) && parse_source(&s, map, budget, img, repairs, err);
    }
    close(fd);
    return ok;
}

bool sl_image_parse_exr(const unsigned char *bytes, size_t size, const char *name, size_t budget, sl_image *img,
                        sl_image_repairs *repairs, sl_error *err)
{
    channel_map m = environment_map();
    return read_exr(bytes ? bytes : (const unsigned char *)"", bytes ? size : 0, name ? name : "(memory)", &m, budget,
                    img, repairs, err);
}

bool sl_image_read_exr(const char *path, size_t budget, sl_image *img, sl_image_repairs *repairs, sl_error *err)
{
    channel_map m = environment_map();
    return read_exr(NULL, 0, path, &m, budget, img, repairs, err);
}

bool sl_exr_read_layer(const char *path, const char *layer, const char *suffixes, size_t budget, sl_image *img,
                       sl_error *err)
{
    *img = (sl_image){0};
    channel_map m;
    return layer_map(layer, suffixes, &m, err) && read_exr(NULL, 0, path, &m, budget, img, NULL, err);
}

bool sl_exr_parse_layer(const unsigned char *bytes, size_t size, const char *layer, const char *suffixes,
                        size_t budget, sl_image *img, sl_error *err)
{
    *img = (sl_image){0};
    channel_map m;
    return layer_map(layer, suffixes, &m, err) &&
           read_exr(bytes ? bytes : (const unsigned char *)"", bytes ? size : 0, "(memory)", &m, budget, img, NULL, err);
}

/* ---------------------------------------------------------------- writing ---- */

/* The library writes into a growing buffer, by offset (it goes back for the chunk table). */
static int64_t sink_write(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t sz, uint64_t offset,
                          exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    source *k = user;
    if (offset > SIZE_MAX / 2 || sz > SIZE_MAX / 2 - offset) {
        k->io_failed = true;
        k->io_errno = ENOMEM;
        return -1;
    }
    size_t end = (size_t)(offset + sz);
    if (end > k->out_capacity) {
        size_t cap = k->out_capacity ? k->out_capacity : 65536;
        while (cap < end)
            cap *= 2;
        unsigned char *grown = realloc(k->out, cap);
        if (!grown) {
            k->io_failed = true;
            k->io_errno = ENOMEM;
            return -1;
        }
        k->out = grown;
        k->out_capacity = cap;
    }
    if (offset > k->out_size)
        memset(k->out + k->out_size, 0, (size_t)offset - k->out_size);
    memcpy(k->out + offset, buffer, (size_t)sz);
    if (end > k->out_size)
        k->out_size = end;
    return (int64_t)sz;
}

/* Where one written channel's floats come from. */
typedef struct {
    char name[64];
    const sl_image *img;
    int comp;
} out_channel;

static bool collect_channels(const sl_exr_layer *layers, int count, out_channel *out, int *n, sl_error *err)
{
    *n = 0;
    if (count < 1 || !layers[0].img || !layers[0].img->data)
        return sl_fail(err, SL_ERR_RANGE, "exr writer: no image to write");
    for (int l = 0; l < count; l++) {
        const sl_exr_layer *L = &layers[l];
        const char *name = L->name ? L->name : "", *suffixes = L->suffixes ? L->suffixes : "";
        int want = suffixes[0] ? (int)strlen(suffixes) : 1;
        if (!L->img || !L->img->data || L->img->width != layers[0].img->width || L->img->height != layers[0].img->height)
            return sl_fail(err, SL_ERR_RANGE, "exr writer: layer '%s' is missing or differs in size from the first", name);
        if (L->img->channels != want)
            return sl_fail(err, SL_ERR_RANGE, "exr writer: layer '%s' has %d channels for %d names", name,
                           L->img->channels, want);
        if (!name[0] && !suffixes[0])
            return sl_fail(err, SL_ERR_RANGE, "exr writer: a one-channel layer needs a name");
        for (int c = 0; c < want; c++) {
            if (*n == SL_EXR_MAX_CHANNELS)
                return sl_fail(err, SL_ERR_RANGE, "exr writer: more than %d channels", SL_EXR_MAX_CHANNELS);
            out_channel *o = &out[(*n)++];
            int len = !suffixes[0] ? snprintf(o->name, sizeof o->name, "%s", name)
                      : name[0]    ? snprintf(o->name, sizeof o->name, "%s.%c", name, suffixes[c])
                                   : snprintf(o->name, sizeof o->name, "%c", suffixes[c]);
            if (len < 0 || (size_t)len >= sizeof o->name)
                return sl_fail(err, SL_ERR_RANGE, "exr writer: layer name '%.20s...' too long", name);
            o->img = L->img;
            o->comp = c;
            for (int k = 0; k + 1 < *n; k++)
                if (!strcmp(out[k].name, o->name))
                    return sl_fail(err, SL_ERR_RANGE, "exr writer: two channels named '%s'", o->name);
        }
    }
    return true;
}

static void aim_encoder(exr_encode_pipeline_t *enc, const out_channel *chans, int n, int x, int y)
{
    for (int c = 0; c < enc->channel_count; c++) {
        exr_coding_channel_info_t *ch = &enc->channels[c];
        for (int k = 0; k < n; k++) {
            if (strcmp(ch->channel_name, chans[k].name))
                continue;
            const sl_image *im = chans[k].img;
            ch->encode_from_ptr = (const uint8_t *)(sl_image_pixel(im, x, y) + chans[k].comp);
            ch->user_pixel_stride = im->channels * (int32_t)sizeof(float);
            ch->user_line_stride = im->width * im->channels * (int32_t)sizeof(float);
            ch->user_bytes_per_element = (int16_t)sizeof(float);
            ch->user_data_type = EXR_PIXEL_FLOAT;
        }
    }
}

/* OpenEXRCore 3.1 stores a chunk's compressed bytes whenever they are not MORE than the raw
 * ones; but every reader (this library's and OpenEXR's C++ one) takes a chunk whose stored size
 * equals its raw size as uncompressed, so a chunk that compresses to exactly its raw size reads
 * back as garbage (found by fuzz_exr's write-and-reread; small or noisy images hit it). The
 * writer's compress step is wrapped: the raw bytes are kept, and such a chunk stores them. */
typedef struct {
    exr_result_t (*compress)(exr_encode_pipeline_t *enc); /* the library's default */
    void *raw;                                            /* the chunk's raw bytes, kept */
    size_t raw_capacity;
} compress_guard;

static exr_result_t compress_or_store_raw(exr_encode_pipeline_t *enc)
{
    compress_guard *g = enc->encoding_user_data;
    size_t raw_bytes = (size_t)enc->packed_bytes;
    if (raw_bytes > g->raw_capacity) {
        void *grown = realloc(g->raw, raw_bytes);
        if (!grown)
            return EXR_ERR_OUT_OF_MEMORY;
        g->raw = grown;
        g->raw_capacity = raw_bytes;
    }
    memcpy(g->raw, enc->packed_buffer, raw_bytes);
    exr_result_t rv = g->compress(enc);
    if (rv == EXR_ERR_SUCCESS && enc->compressed_bytes == raw_bytes && enc->compressed_buffer != enc->packed_buffer)
        memcpy(enc->compressed_buffer, g->raw, raw_bytes);
    return rv;
}

bool sl_exr_encode(const sl_exr_layer *layers, int count, const sl_exr_options *options, unsigned char **bytes,
                   size_t *size, sl_error *err)
{
    *bytes = NULL;
    *size = 0;
    static const sl_exr_options defaults = {0};
    const sl_exr_options *o = options ? options : &defaults;
    out_channel chans[SL_EXR_MAX_CHANNELS];
    int n;
    if (!collect_channels(layers, count, chans, &n, err))
        return false;
    if (o->compression < SL_EXR_NONE || o->compression > SL_EXR_B44A || o->tile < 0)
        return sl_fail(err, SL_ERR_RANGE, "exr writer: compression %d or tile size %d out of range", (int)o->compression,
                       o->tile);
    int width = layers[0].img->width, height = layers[0].img->height;
    source k = {.fd = -1, .name = "exr writer", .writing = true};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_error;
    init.user_data = &k;
    init.write_fn = sink_write;
    exr_context_t ctx = NULL;
    exr_encode_pipeline_t enc = {0};
    compress_guard guard = {0};
    bool have_encoder = false, ok = false;
    int part = 0;
    exr_result_t rv = exr_start_write(&ctx, "(memory)", EXR_WRITE_FILE_DIRECTLY, &init);
    if (!rv)
        rv = exr_add_part(ctx, "", o->tile ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE, &part);
    if (!rv)
        rv = exr_initialize_required_attr_simple(ctx, part, width, height, (exr_compression_t)o->compression);
    if (!rv && o->tile)
        rv = exr_set_tile_descriptor(ctx, part, (uint32_t)o->tile, (uint32_t)o->tile, EXR_TILE_ONE_LEVEL,
                                     EXR_TILE_ROUND_DOWN);
    for (int c = 0; !rv && c < n; c++)
        rv = exr_add_channel(ctx, part, chans[c].name, o->half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                             EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1); /* pLinear 0, as OpenEXR writes RGB */
    if (!rv)
        rv = exr_write_header(ctx);
    if (rv) {
        lib_fail(&k, rv, "writing the header", err);
        goto done;
    }
    int32_t cw = width, ch = 1;
    if (o->tile)
        cw = ch = o->tile;
    else if ((rv = exr_get_scanlines_per_chunk(ctx, part, &ch))) {
        lib_fail(&k, rv, "writing the header", err);
        goto done;
    }
    int tiles_x = (width + cw - 1) / cw, tiles_y = (height + ch - 1) / ch;
    for (int ty = 0; ty < tiles_y; ty++) {
        for (int tx = 0; tx < tiles_x; tx++) {
            exr_chunk_info_t ci;
            rv = o->tile ? exr_write_tile_chunk_info(ctx, part, tx, ty, 0, 0, &ci)
                         : exr_write_scanline_chunk_info(ctx, part, ty * ch, &ci);
            if (!rv)
                rv = have_encoder ? exr_encoding_update(ctx, part, &ci, &enc) : exr_encoding_initialize(ctx, part, &ci, &enc);
            if (!rv) {
                bool first = !have_encoder;
                have_encoder = true;
                aim_encoder(&enc, chans, n, o->tile ? tx * cw : 0, o->tile ? ty * ch : ci.start_y);
                if (first && !(rv = exr_encoding_choose_default_routines(ctx, part, &enc)) && enc.compress_fn) {
                    guard.compress = enc.compress_fn;
                    enc.compress_fn = compress_or_store_raw;
                    enc.encoding_user_data = &guard;
                }
                if (!rv)
                    rv = exr_encoding_run(ctx, part, &enc);
            }
            if (rv) {
                lib_fail(&k, rv, "encoding a chunk", err);
                goto done;
            }
        }
    }
    ok = true;
done:
    if (have_encoder)
        exr_encoding_destroy(ctx, &enc);
    free(guard.raw);
    rv = exr_finish(&ctx); /* writes the chunk table */
    if (ok && (rv || k.io_failed))
        ok = lib_fail(&k, rv ? rv : EXR_ERR_WRITE_IO, "finishing the file", err);
    if (!ok) {
        free(k.out);
        return false;
    }
    *bytes = k.out;
    *size = k.out_size;
    return true;
}

bool sl_image_encode_exr(const sl_image *img, unsigned char **bytes, size_t *size, sl_error *err)
{
    if (img && img->channels != 1 && img->channels != 3)
        return sl_fail(err, SL_ERR_RANGE, "exr writer: needs 1 or 3 channels, the image has %d", img ? img->channels : 0);
    sl_exr_layer layer = {.name = img && img->channels == 1 ? "Y" : "", .suffixes = img && img->channels == 1 ? "" : "RGB",
                          .img = img};
    return sl_exr_encode(&layer, 1, &(sl_exr_options){.compression = SL_EXR_ZIP}, bytes, size, err);
}
