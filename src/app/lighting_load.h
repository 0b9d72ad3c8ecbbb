/* lighting_load.h - a lighting program from the command line (`--lighting my.c`): a C source
 * compiled and cached, or a shared object, loaded by the one loader of run-time programs
 * (program_load.h) as the lighting kind: it exports sl_lighting_program_abi (= SL_LIGHTING_ABI)
 * and sl_lighting_program_entry with a shade function. Only the command line names such a file:
 * a scene never does. docs/lighting-programs.md describes the whole of it. */
#ifndef SL_APP_LIGHTING_LOAD_H
#define SL_APP_LIGHTING_LOAD_H

#include <stdbool.h>
#include <stddef.h>

#include <softlight/lighting.h>

#include "program_load.h"

typedef sl_program_load_options sl_lighting_load_options;

/* Load `path` (a C source or a shared object). On failure, false with one line in msg naming
 * the file (a compile error: the compiler's first error, file:line). The shared object stays
 * loaded for the life of the process. */
bool sl_lighting_load(const char *path, const sl_lighting_load_options *opt, const sl_lighting_program **program,
                      char *msg, size_t msg_size);

/* The command's --lighting FILE (NULL: none, *program left alone) loaded into *program; a failure
 * is printed as "softlight COMMAND: ..." on stderr and returns false (the command exits 2). */
bool sl_lighting_load_arg(const char *command, const char *path, bool debug, bool verbose,
                          const sl_lighting_program **program);

#endif
