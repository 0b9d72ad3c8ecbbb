/* gbuffer_load.c - the G-buffer kind of run-time program (gbuffer_load.h): its symbols, its ABI
 * and its entry check, for the one loader (program_load.c). */
#include <stdio.h>

#include "gbuffer_load.h"

static bool gbuffer_entry_ok(const void *entry)
{
    return ((const sl_gbuffer_fragment_program *)entry)->fragment != NULL;
}

static const sl_program_kind gbuffer_kind = {
    .abi_symbol = "sl_gbuffer_program_abi",
    .entry_symbol = "sl_gbuffer_program_entry",
    .abi = SL_GBUFFER_ABI,
    .what = "G-buffer program",
    .macro = "SL_GBUFFER_PROGRAM",
    .entry_needs = "a fragment function",
    .entry_ok = gbuffer_entry_ok,
};

bool sl_gbuffer_program_load(const char *path, const sl_program_load_options *opt,
                             const sl_gbuffer_fragment_program **program, char *msg, size_t msg_size)
{
    const void *entry;
    if (!sl_program_load(path, &gbuffer_kind, opt, &entry, msg, msg_size))
        return false;
    *program = entry;
    return true;
}

bool sl_gbuffer_program_load_arg(const char *command, const char *path, bool debug, bool verbose,
                                 const sl_gbuffer_fragment_program **program)
{
    if (!path)
        return true;
    char msg[1200];
    sl_program_load_options lo = {.debug = debug, .verbose = verbose};
    if (sl_gbuffer_program_load(path, &lo, program, msg, sizeof msg))
        return true;
    fprintf(stderr, "softlight %s: %s\n", command, msg);
    return false;
}
