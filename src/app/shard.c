/* shard.c - the `--shard I/N` argument, a run's identity, and writing a shard's partial file
 * (see shard.h). */
#include "shard.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/hash.h"

bool sl_shard_parse(const char *text, sl_shard *s, sl_error *err)
{
    int i, n, used = 0;
    if (sscanf(text, "%d/%d%n", &i, &n, &used) != 2 || text[used] || n < 1 || n > SL_SHARD_MAX || i < 1 || i > n)
        return sl_fail(err, SL_ERR_RANGE, "--shard: \"%s\" is not I/N with 1 <= I <= N <= %d", text, SL_SHARD_MAX);
    s->index = i;
    s->count = n;
    return true;
}

/* Options whose values may differ between the shards of one run without changing a pixel. */
static bool per_shard(const char *word, bool *takes_value)
{
    static const char *const names[] = {"--shard", "--partial", "--threads", "-j", "--cache"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
        size_t n = strlen(names[k]);
        if (!strncmp(word, names[k], n) && (word[n] == '\0' || word[n] == '=')) {
            *takes_value = word[n] == '\0';
            return true;
        }
    }
    return false;
}

bool sl_shard_identity(const char *command, int argc, char **argv, const char *scene_path, uint64_t *identity,
                       sl_error *err)
{
    uint64_t h = sl_fnv1a_str(SL_FNV1A_START, command);
    for (int k = 2; k < argc; k++) {
        bool takes_value;
        if (per_shard(argv[k], &takes_value)) {
            k += takes_value;
            continue;
        }
        h = sl_fnv1a_str(h, argv[k]);
    }
    unsigned char *bytes;
    size_t size;
    if (!sl_read_file(scene_path, (size_t)1 << 28, &bytes, &size, err))
        return false;
    *identity = sl_fnv1a(h, bytes, size);
    free(bytes);
    return true;
}

bool sl_shard_begin(sl_shard *s, sl_output_set *out, const char *command, uint64_t identity, int width, int height,
                    const char *first_output, sl_error *err)
{
    if (!s->partial) {
        if (!first_output)
            return sl_fail(err, SL_ERR_RANGE, "--shard: no output to shard");
        snprintf(s->partial_buf, sizeof s->partial_buf, "%s.shard-%d-of-%d", first_output, s->index, s->count);
        s->partial = s->partial_buf;
    }
    sl_partial_init(&s->part, command, identity, s->index, s->count, width, height);
    out->capture = sl_partial_capture;
    out->capture_user = &s->part;
    return true;
}

bool sl_shard_finish(sl_shard *s, sl_error *err)
{
    unsigned char *bytes;
    size_t size;
    if (!sl_partial_encode(&s->part, &bytes, &size, err))
        return false;
    bool ok = sl_write_file_atomic(s->partial, bytes, size, err);
    free(bytes);
    return ok;
}

void sl_shard_free(sl_shard *s) { sl_partial_free(&s->part); }
