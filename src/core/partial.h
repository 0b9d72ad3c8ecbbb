/* partial.h - one shard's part of a command's outputs, and the merge of all parts.
 *
 * `softlight render|truth ... --shard I/N` computes only image rows [y0, y1) (row 0 = top) of
 * band I of N, y0 = floor(H (I-1) / N), y1 = floor(H I / N), and writes instead of its outputs
 * one partial file holding, for each output the command would write, those rows of the float
 * image it would encode (and each directory it would make). `softlight merge` reads the N
 * partials, checks that they are the N shards of one run, each once, and writes the outputs
 * through one output set (all or nothing): the same bytes the unsharded command writes, since
 * each output is encoded from the same floats (docs/sharding.md).
 *
 * The file: a text header a person can read with `head`, then the rows as float32 little endian,
 * entry after entry, in the order of the header:
 *
 *     softlight partial v1
 *     command render
 *     identity 5f0c...        FNV-1a 64 of the command line without --shard/--partial and of
 *                             the scene file's bytes: shards of different runs are refused
 *     shard 2 of 4
 *     size 1280 720           the full image
 *     rows 180 360            the band, [y0, y1)
 *     entries 3
 *     dir out/aov             a directory to make
 *     image png 3 out.png     an image: encoder, channels, path (the rest of the line)
 *     image pfm 1 out/aov/mask.pfm
 *     data
 *
 * Does not: shard raw-byte outputs (sl_output_set_bytes refuses while capturing), or compress. */
#ifndef SL_PARTIAL_H
#define SL_PARTIAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "error.h"
#include "image.h"
#include "output_set.h"

#define SL_SHARD_MAX 4096        /* N of --shard I/N */
#define SL_PARTIAL_MAX_ENTRIES 64 /* outputs of one command */
#define SL_PARTIAL_MAX_HEADER 65536

typedef struct {
    bool is_dir;
    char encoder[8];  /* "png", "pfm", "hdr" (images) */
    int channels;     /* 1, 3 or 4 */
    char *path;
    float *rows;      /* (y1 - y0) * width * channels floats */
} sl_partial_entry;

typedef struct {
    char command[16];
    uint64_t identity;
    int shard, count;      /* I of N, 1 <= I <= N */
    int width, height, y0, y1;
    int entry_count;
    sl_partial_entry entries[SL_PARTIAL_MAX_ENTRIES];
} sl_partial;

/* Rows [y0, y1) of shard `shard` of `count` over `height` rows. */
void sl_shard_rows(int shard, int count, int height, int *y0, int *y1);

/* Start an empty partial for shard I of N of a width x height image. */
void sl_partial_init(sl_partial *p, const char *command, uint64_t identity, int shard, int count, int width,
                     int height);
/* The output set's capture function (output_set.h; user = the sl_partial): a directory, or an
 * image's band rows. Refuses an image of another size, an encoder without a name here, or a
 * path with a newline. */
bool sl_partial_capture(void *user, const char *path, sl_image_encoder encode, const sl_image *img, sl_error *err);
bool sl_partial_encode(const sl_partial *p, unsigned char **bytes, size_t *size, sl_error *err);
/* Parse a partial file from memory; every field is checked (the band against shard and size,
 * the data size exactly). `name` is used in messages. On failure p is left empty. */
bool sl_partial_parse(const unsigned char *bytes, size_t size, const char *name, sl_partial *p, sl_error *err);
bool sl_partial_read(const char *path, sl_partial *p, sl_error *err);
void sl_partial_free(sl_partial *p);

/* Check that parts[0..count) (read from names[]) are the N shards of one run, each present once,
 * and add the whole outputs to `set` (the caller commits). One line naming the file on error. */
bool sl_partial_merge(const sl_partial *parts, const char *const *names, int count, sl_output_set *set,
                      sl_error *err);

#endif
