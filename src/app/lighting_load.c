/* lighting_load.c - the lighting kind of run-time program (lighting_load.h): its symbols, its ABI
 * and its entry check, for the one loader (program_load.c). */
#include <stdio.h>

#include "lighting_load.h"

static bool lighting_entry_ok(const void *entry) { return ((const sl_lighting_program *)entry)->shade != NULL; }

static const sl_program_kind lighting_kind = {
    .abi_symbol = "sl_lighting_program_abi",
    .entry_symbol = "sl_lighting_program_entry",
    .abi = SL_LIGHTING_ABI,
    .what = "lighting program",
    .macro = "SL_LIGHTING_PROGRAM",
    .entry_needs = "a shade function",
    .entry_ok = lighting_entry_ok,
};

bool sl_lighting_load(const char *path, const sl_lighting_load_options *opt, const sl_lighting_program **program,
                      char *msg, size_t msg_size)
{
    const void *entry;
    if (!sl_program_load(path, &lighting_kind, opt, &entry, msg, msg_size))
        return false;
    *program = entry;
    return true;
}

bool sl_lighting_load_arg(const char *command, const char *path, bool debug, bool verbose,
                          const sl_lighting_program **program)
{
    if (!path)
        return true;
    char msg[1200];
    sl_lighting_load_options lo = {.debug = debug, .verbose = verbose};
    if (sl_lighting_load(path, &lo, program, msg, sizeof msg))
        return true;
    fprintf(stderr, "softlight %s: %s\n", command, msg);
    return false;
}
