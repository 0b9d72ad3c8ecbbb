/* shard.h - `--shard I/N` for the commands that can be split over processes and machines
 * (render, truth; the sweep's truth through truth): the argument, the identity of a run, and the
 * partial file a shard writes in place of its outputs (core/partial.h; `softlight merge` joins
 * them). docs/sharding.md says how to run shards with GNU parallel and Slurm. */
#ifndef SL_SHARD_H
#define SL_SHARD_H

#include <stdbool.h>
#include <stdint.h>

#include "core/error.h"
#include "core/output_set.h"
#include "core/partial.h"

typedef struct {
    int index, count;     /* I of N; count 0 = not sharded */
    const char *partial;  /* where the partial goes (--partial, or FIRST_OUTPUT.shard-I-of-N) */
    char partial_buf[1100];
    sl_partial part;      /* heap-free, filled by the output set's capture */
} sl_shard;

/* "I/N", 1 <= I <= N <= SL_SHARD_MAX. */
bool sl_shard_parse(const char *text, sl_shard *s, sl_error *err);
/* FNV-1a 64 of the command name, its arguments except those that may differ between the shards
 * of one run (--shard, --partial, --threads/-j, --cache, with their values) and the scene file's
 * bytes. False (err) when the scene cannot be read. */
bool sl_shard_identity(const char *command, int argc, char **argv, const char *scene_path, uint64_t *identity,
                       sl_error *err);
/* Set `out` to capture into s->part for a width x height frame; the partial's path defaults to
 * `first_output`.shard-I-of-N. */
bool sl_shard_begin(sl_shard *s, sl_output_set *out, const char *command, uint64_t identity, int width, int height,
                    const char *first_output, sl_error *err);
/* Write the partial (atomically) once the command added its outputs to the capturing set. */
bool sl_shard_finish(sl_shard *s, sl_error *err);
void sl_shard_free(sl_shard *s);

#endif
