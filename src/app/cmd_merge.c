/* cmd_merge.c - `softlight merge PARTIAL...`: the outputs of a sharded `render` or `truth` run
 * (--shard I/N, app/shard.h), joined from its N partial files and written all together or not
 * at all, byte-identical to what the unsharded command writes (tests/cli/shard.sh).
 *
 * Refused, with one line and exit status 2, nothing written: a file that is not a partial or is
 * truncated, shards of different runs (command line, scene file, size, outputs or N differ), a
 * shard given twice, a shard missing. */
#include <stdio.h>
#include <stdlib.h>

#include "args.h"
#include "commands.h"
#include "core/output_set.h"
#include "core/partial.h"

int cmd_merge(int argc, char **argv)
{
    bool quiet = false;
    sl_arg table[] = {
        {"--quiet", "-q", SL_ARG_FLAG, &quiet, 0, 0, NULL, NULL, "print nothing but errors", NULL},
    };
    const char **names = calloc((size_t)argc, sizeof *names);
    sl_partial *parts = calloc((size_t)argc, sizeof *parts);
    int npos = 0, status = 2, read = 0;
    bool help = false;
    sl_error err = {0};
    sl_output_set out = {0};
    if (!names || !parts) {
        fprintf(stderr, "softlight merge: out of memory\n");
        goto done;
    }
    if (!sl_args_parse(argc, argv, 2, table, 1, names, argc, &npos, &help, &err)) {
        fprintf(stderr, "softlight merge: %s\n", err.msg);
        goto done;
    }
    if (help || npos < 1) {
        sl_args_print_help(help ? stdout : stderr, "softlight merge PARTIAL... (the N files of one --shard run)",
                           table, 1);
        status = help ? 0 : 2;
        goto done;
    }
    for (; read < npos; read++)
        if (!sl_partial_read(names[read], &parts[read], &err))
            goto fail;
    if (!sl_partial_merge(parts, names, npos, &out, &err) || !sl_output_set_commit(&out, &err))
        goto fail;
    if (!quiet)
        for (int k = 0; k < parts[0].entry_count; k++)
            if (!parts[0].entries[k].is_dir)
                printf("wrote %s\n", parts[0].entries[k].path);
    status = 0;
    goto done;
fail:
    fprintf(stderr, "softlight merge: %s\n", err.msg);
done:
    sl_output_set_free(&out);
    for (int k = 0; k < read; k++)
        sl_partial_free(&parts[k]);
    free(parts);
    free(names);
    return status;
}
