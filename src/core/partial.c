/* partial.c - a shard's partial file: capture, encode, parse, merge (see partial.h).
 *
 * The parser is strict because partials travel between machines and are fuzzed
 * (fuzz/fuzz_partial.c): every header line must be exactly as written, numbers in range, the
 * band equal to the one shard and size give, and the data exactly as long as the entries say,
 * so nothing is allocated beyond the file's own size. */
#include "partial.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PARTIAL_MAGIC "softlight partial v1"

/* The encoders a partial can name; an output written with another cannot be sharded. */
static const struct {
    const char *name;
    sl_image_encoder encode;
} encoders[] = {{"png", sl_image_encode_png}, {"pfm", sl_image_encode_pfm}, {"hdr", sl_image_encode_hdr}};
#define ENCODER_COUNT (int)(sizeof encoders / sizeof encoders[0])

void sl_shard_rows(int shard, int count, int height, int *y0, int *y1)
{
    *y0 = (int)((long long)height * (shard - 1) / count);
    *y1 = (int)((long long)height * shard / count);
}

void sl_partial_init(sl_partial *p, const char *command, uint64_t identity, int shard, int count, int width,
                     int height)
{
    memset(p, 0, sizeof *p);
    snprintf(p->command, sizeof p->command, "%s", command);
    p->identity = identity;
    p->shard = shard;
    p->count = count;
    p->width = width;
    p->height = height;
    sl_shard_rows(shard, count, height, &p->y0, &p->y1);
}

void sl_partial_free(sl_partial *p)
{
    for (int i = 0; i < p->entry_count; i++) {
        free(p->entries[i].path);
        free(p->entries[i].rows);
    }
    memset(p, 0, sizeof *p);
}

static size_t band_floats(const sl_partial *p, int channels)
{
    return (size_t)(p->y1 - p->y0) * (size_t)p->width * (size_t)channels;
}

static char *dup_path(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

bool sl_partial_capture(void *user, const char *path, sl_image_encoder encode, const sl_image *img, sl_error *err)
{
    sl_partial *p = user;
    if (!path[0] || strchr(path, '\n') || strchr(path, '\r'))
        return sl_fail(err, SL_ERR_RANGE, "--shard: an output path must be one line and not empty");
    if (p->entry_count == SL_PARTIAL_MAX_ENTRIES)
        return sl_fail(err, SL_ERR_RANGE, "%s: more than %d outputs in one shard", path, SL_PARTIAL_MAX_ENTRIES);
    sl_partial_entry e = {.is_dir = encode == NULL};
    if (encode) {
        int k = 0;
        while (k < ENCODER_COUNT && encoders[k].encode != encode)
            k++;
        if (k == ENCODER_COUNT)
            return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: this output cannot be sharded (write it without --shard)",
                           path);
        if (img->width != p->width || img->height != p->height)
            return sl_fail(err, SL_ERR_RANGE, "%s: a %dx%d image in a shard of a %dx%d frame", path, img->width,
                           img->height, p->width, p->height);
        snprintf(e.encoder, sizeof e.encoder, "%s", encoders[k].name);
        e.channels = img->channels;
        size_t n = band_floats(p, e.channels);
        e.rows = malloc(n ? n * sizeof(float) : 1);
        if (!e.rows)
            return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for the shard's rows", path);
        memcpy(e.rows, img->data + (size_t)p->y0 * (size_t)p->width * (size_t)e.channels, n * sizeof(float));
    }
    e.path = dup_path(path);
    if (!e.path) {
        free(e.rows);
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", path);
    }
    p->entries[p->entry_count++] = e;
    return true;
}

bool sl_partial_encode(const sl_partial *p, unsigned char **bytes, size_t *size, sl_error *err)
{
    size_t head_cap = 512, data = 0;
    for (int i = 0; i < p->entry_count; i++) {
        head_cap += strlen(p->entries[i].path) + 32;
        if (!p->entries[i].is_dir)
            data += band_floats(p, p->entries[i].channels) * 4;
    }
    unsigned char *b = malloc(head_cap + data);
    if (!b)
        return sl_fail(err, SL_ERR_MEMORY, "partial: out of memory (%zu bytes)", head_cap + data);
    char *h = (char *)b;
    size_t n = (size_t)snprintf(h, head_cap,
                                PARTIAL_MAGIC "\ncommand %s\nidentity %016" PRIx64 "\nshard %d of %d\nsize %d %d\n"
                                              "rows %d %d\nentries %d\n",
                                p->command, p->identity, p->shard, p->count, p->width, p->height, p->y0, p->y1,
                                p->entry_count);
    for (int i = 0; i < p->entry_count; i++) {
        const sl_partial_entry *e = &p->entries[i];
        if (e->is_dir)
            n += (size_t)snprintf(h + n, head_cap - n, "dir %s\n", e->path);
        else
            n += (size_t)snprintf(h + n, head_cap - n, "image %s %d %s\n", e->encoder, e->channels, e->path);
    }
    n += (size_t)snprintf(h + n, head_cap - n, "data\n");
    unsigned char *q = b + n;
    for (int i = 0; i < p->entry_count; i++) {
        const sl_partial_entry *e = &p->entries[i];
        size_t count = e->is_dir ? 0 : band_floats(p, e->channels);
        for (size_t j = 0; j < count; j++, q += 4) {
            uint32_t u;
            memcpy(&u, &e->rows[j], 4);
            q[0] = (unsigned char)u;
            q[1] = (unsigned char)(u >> 8);
            q[2] = (unsigned char)(u >> 16);
            q[3] = (unsigned char)(u >> 24);
        }
    }
    *bytes = b;
    *size = (size_t)(q - b);
    return true;
}

/* ---- parsing ---- */

typedef struct {
    const char *s, *end, *name;
    int line;
} cursor;

/* The next line (without its newline) into buf; false at the end of the header space. */
static bool next_line(cursor *c, char *buf, size_t cap, sl_error *err)
{
    const char *nl = memchr(c->s, '\n', (size_t)(c->end - c->s));
    c->line++;
    if (!nl)
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: unexpected end of file in the header", c->name, c->line);
    size_t n = (size_t)(nl - c->s);
    if (n >= cap || memchr(c->s, '\0', n))
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: line too long or not text", c->name, c->line);
    memcpy(buf, c->s, n);
    buf[n] = '\0';
    c->s = nl + 1;
    return true;
}

/* A decimal integer in [lo, hi] at *s, advancing past it. */
static bool read_int(const char **s, long lo, long hi, int *out)
{
    const char *p = *s;
    if (*p < '0' || *p > '9')
        return false;
    long v = 0;
    while (*p >= '0' && *p <= '9') {
        v = v * 10 + (*p - '0');
        if (v > hi)
            return false;
        p++;
    }
    if (v < lo)
        return false;
    *out = (int)v;
    *s = p;
    return true;
}

static bool expect(const char **s, const char *word)
{
    size_t n = strlen(word);
    if (strncmp(*s, word, n))
        return false;
    *s += n;
    return true;
}

static bool parse_entry(cursor *c, const char *text, sl_partial_entry *e, sl_error *err)
{
    const char *s = text;
    if (expect(&s, "dir ")) {
        e->is_dir = true;
    } else if (expect(&s, "image ")) {
        int k = 0;
        while (k < ENCODER_COUNT && !(expect(&s, encoders[k].name) && *s == ' '))
            k++;
        if (k == ENCODER_COUNT || !(expect(&s, " ") && read_int(&s, 1, 4, &e->channels) && e->channels != 2 &&
                                    expect(&s, " ")))
            return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: expected \"image png|pfm|hdr 1|3|4 PATH\"", c->name,
                           c->line);
        snprintf(e->encoder, sizeof e->encoder, "%s", encoders[k].name);
    } else {
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: expected \"dir PATH\" or \"image ...\"", c->name, c->line);
    }
    if (!*s || strchr(s, '\r'))
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: empty path", c->name, c->line);
    e->path = dup_path(s);
    if (!e->path)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", c->name);
    return true;
}

static bool parse_header(cursor *c, sl_partial *p, sl_error *err)
{
    char line[4200];
    if (!next_line(c, line, sizeof line, err))
        return false;
    if (strcmp(line, PARTIAL_MAGIC))
        return sl_fail(err, SL_ERR_FORMAT, "%s: not a softlight partial file (expected \"%s\" on line 1)", c->name,
                       PARTIAL_MAGIC);
    const char *s;
    if (!next_line(c, line, sizeof line, err))
        return false;
    s = line;
    size_t n = strlen(line);
    if (!expect(&s, "command ") || n - 8 < 1 || n - 8 >= sizeof p->command || strspn(s, "abcdefghijklmnopqrstuvwxyz") != n - 8)
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: expected \"command NAME\"", c->name, c->line);
    memcpy(p->command, s, n - 8 + 1);
    if (!next_line(c, line, sizeof line, err))
        return false;
    s = line;
    if (!expect(&s, "identity ") || strlen(s) != 16 || strspn(s, "0123456789abcdef") != 16)
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: expected \"identity\" and 16 hex digits", c->name, c->line);
    p->identity = strtoull(s, NULL, 16);
    if (!next_line(c, line, sizeof line, err))
        return false;
    s = line;
    if (!(expect(&s, "shard ") && read_int(&s, 1, SL_SHARD_MAX, &p->shard) && expect(&s, " of ") &&
          read_int(&s, 1, SL_SHARD_MAX, &p->count) && !*s && p->shard <= p->count))
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: expected \"shard I of N\", 1 <= I <= N <= %d", c->name,
                       c->line, SL_SHARD_MAX);
    if (!next_line(c, line, sizeof line, err))
        return false;
    s = line;
    if (!(expect(&s, "size ") && read_int(&s, 1, SL_IMAGE_MAX_SIDE, &p->width) && expect(&s, " ") &&
          read_int(&s, 1, SL_IMAGE_MAX_SIDE, &p->height) && !*s) ||
        (long long)p->width * p->height > SL_IMAGE_MAX_PIXELS)
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: expected \"size W H\" within %dx%d", c->name, c->line,
                       SL_IMAGE_MAX_SIDE, SL_IMAGE_MAX_SIDE);
    int y0, y1, want0, want1;
    if (!next_line(c, line, sizeof line, err))
        return false;
    s = line;
    sl_shard_rows(p->shard, p->count, p->height, &want0, &want1);
    if (!(expect(&s, "rows ") && read_int(&s, 0, SL_IMAGE_MAX_SIDE, &y0) && expect(&s, " ") &&
          read_int(&s, 0, SL_IMAGE_MAX_SIDE, &y1) && !*s))
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: expected \"rows Y0 Y1\"", c->name, c->line);
    if (y0 != want0 || y1 != want1)
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: rows %d..%d, but shard %d of %d of %d rows is %d..%d",
                       c->name, c->line, y0, y1, p->shard, p->count, p->height, want0, want1);
    p->y0 = y0;
    p->y1 = y1;
    int count;
    if (!next_line(c, line, sizeof line, err))
        return false;
    s = line;
    if (!(expect(&s, "entries ") && read_int(&s, 0, SL_PARTIAL_MAX_ENTRIES, &count) && !*s))
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: expected \"entries K\", K <= %d", c->name, c->line,
                       SL_PARTIAL_MAX_ENTRIES);
    for (int i = 0; i < count; i++) {
        if (!next_line(c, line, sizeof line, err) || !parse_entry(c, line, &p->entries[i], err))
            return false;
        p->entry_count = i + 1;
    }
    if (!next_line(c, line, sizeof line, err))
        return false;
    if (strcmp(line, "data"))
        return sl_fail(err, SL_ERR_FORMAT, "%s: line %d: expected \"data\" after %d entries", c->name, c->line,
                       count);
    return true;
}

bool sl_partial_parse(const unsigned char *bytes, size_t size, const char *name, sl_partial *p, sl_error *err)
{
    memset(p, 0, sizeof *p);
    size_t head_size = size < SL_PARTIAL_MAX_HEADER ? size : SL_PARTIAL_MAX_HEADER;
    cursor c = {.s = (const char *)bytes, .end = (const char *)bytes + head_size, .name = name};
    if (!parse_header(&c, p, err)) {
        sl_partial_free(p);
        return false;
    }
    size_t offset = (size_t)((const unsigned char *)c.s - bytes), need = 0;
    for (int i = 0; i < p->entry_count; i++)
        if (!p->entries[i].is_dir)
            need += band_floats(p, p->entries[i].channels) * 4;
    if (size - offset != need) {
        sl_fail(err, SL_ERR_FORMAT, "%s: %zu bytes of data after the header, expected %zu (%s)", name,
                size - offset, need, size - offset < need ? "truncated" : "trailing bytes");
        sl_partial_free(p);
        return false;
    }
    const unsigned char *q = bytes + offset;
    for (int i = 0; i < p->entry_count; i++) {
        sl_partial_entry *e = &p->entries[i];
        if (e->is_dir)
            continue;
        size_t n = band_floats(p, e->channels);
        e->rows = malloc(n ? n * sizeof(float) : 1);
        if (!e->rows) {
            sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", name);
            sl_partial_free(p);
            return false;
        }
        for (size_t j = 0; j < n; j++, q += 4) {
            uint32_t u = (uint32_t)q[0] | (uint32_t)q[1] << 8 | (uint32_t)q[2] << 16 | (uint32_t)q[3] << 24;
            memcpy(&e->rows[j], &u, 4);
        }
    }
    return true;
}

bool sl_partial_read(const char *path, sl_partial *p, sl_error *err)
{
    unsigned char *bytes;
    size_t size;
    memset(p, 0, sizeof *p);
    if (!sl_read_file(path, SL_IMAGE_MAX_FILE_BYTES, &bytes, &size, err))
        return false;
    bool ok = sl_partial_parse(bytes, size, path, p, err);
    free(bytes);
    return ok;
}

/* ---- merging ---- */

static bool same_run(const sl_partial *a, const sl_partial *b)
{
    if (strcmp(a->command, b->command) || a->identity != b->identity || a->count != b->count ||
        a->width != b->width || a->height != b->height || a->entry_count != b->entry_count)
        return false;
    for (int i = 0; i < a->entry_count; i++) {
        const sl_partial_entry *x = &a->entries[i], *y = &b->entries[i];
        if (x->is_dir != y->is_dir || strcmp(x->encoder, y->encoder) || x->channels != y->channels ||
            strcmp(x->path, y->path))
            return false;
    }
    return true;
}

bool sl_partial_merge(const sl_partial *parts, const char *const *names, int count, sl_output_set *set,
                      sl_error *err)
{
    if (count < 1)
        return sl_fail(err, SL_ERR_RANGE, "merge: no partial files");
    const sl_partial *first = &parts[0];
    const int n = first->count;
    int *seen = calloc((size_t)n, sizeof *seen); /* index + 1 of the file holding shard I */
    if (!seen)
        return sl_fail(err, SL_ERR_MEMORY, "merge: out of memory");
    bool ok = false;
    for (int i = 0; i < count; i++) {
        const sl_partial *p = &parts[i];
        if (!same_run(first, p)) {
            sl_fail(err, SL_ERR_RANGE, "%s: not a shard of the same run as %s (command, options, scene, size, "
                    "outputs or shard count differ)", names[i], names[0]);
            goto done;
        }
        if (seen[p->shard - 1]) {
            sl_fail(err, SL_ERR_RANGE, "%s: shard %d of %d is also in %s", names[i], p->shard, n,
                    names[seen[p->shard - 1] - 1]);
            goto done;
        }
        seen[p->shard - 1] = i + 1;
    }
    for (int s = 0; s < n; s++)
        if (!seen[s]) {
            sl_fail(err, SL_ERR_RANGE, "merge: shard %d of %d is missing (%d of %d given, first %s)", s + 1, n, count,
                    n, names[0]);
            goto done;
        }
    for (int k = 0; k < first->entry_count; k++) {
        const sl_partial_entry *e = &first->entries[k];
        if (e->is_dir) {
            if (!sl_output_set_dir(set, e->path, err))
                goto done;
            continue;
        }
        sl_image img = {0};
        if (!sl_image_alloc(&img, first->width, first->height, e->channels, err))
            goto done;
        for (int s = 0; s < n; s++) {
            const sl_partial *p = &parts[seen[s] - 1];
            memcpy(img.data + (size_t)p->y0 * (size_t)p->width * (size_t)e->channels, p->entries[k].rows,
                   band_floats(p, e->channels) * sizeof(float));
        }
        int enc = 0;
        while (strcmp(encoders[enc].name, e->encoder))
            enc++;
        bool added = sl_output_set_image(set, e->path, encoders[enc].encode, &img, err);
        sl_image_free(&img);
        if (!added)
            goto done;
    }
    ok = true;
done:
    free(seen);
    return ok;
}
