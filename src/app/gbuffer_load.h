/* gbuffer_load.h - a G-buffer fragment program from the command line (`--gbuffer-shader my.c`):
 * a C source compiled and cached, or a shared object, loaded by the one loader of run-time
 * programs (program_load.h) as the G-buffer kind: it exports sl_gbuffer_program_abi
 * (= SL_GBUFFER_ABI) and sl_gbuffer_program_entry with a fragment function
 * (softlight/gbuffer_program.h). Only the command line names such a file: a scene never does.
 * docs/gbuffer-programs.md describes the contract. */
#ifndef SL_APP_GBUFFER_LOAD_H
#define SL_APP_GBUFFER_LOAD_H

#include <stdbool.h>
#include <stddef.h>

#include <softlight/gbuffer_program.h>

#include "program_load.h"

/* Load `path` (a C source or a shared object). On failure, false with one line in msg naming
 * the file (a compile error: the compiler's first error, file:line). */
bool sl_gbuffer_program_load(const char *path, const sl_program_load_options *opt,
                             const sl_gbuffer_fragment_program **program, char *msg, size_t msg_size);

/* The command's --gbuffer-shader FILE (NULL: none, *program left alone) loaded into *program; a
 * failure is printed as "softlight COMMAND: ..." on stderr and returns false (the command exits 2). */
bool sl_gbuffer_program_load_arg(const char *command, const char *path, bool debug, bool verbose,
                                 const sl_gbuffer_fragment_program **program);

#endif
