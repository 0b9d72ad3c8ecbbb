/* program_load.h - a program named on the command line, loaded at run time: a C source compiled
 * with the system C compiler ($CC, else cc) against softlight's own headers into a shared object,
 * cached by content hash under $XDG_CACHE_HOME/softlight (or ~/.cache/softlight), or a shared
 * object (an ELF file) taken as it is; either dlopened, its exported ABI version checked and its
 * entry symbol returned. One loader for every kind of program (a lighting program,
 * lighting_load.h; a G-buffer fragment program, gbuffer_load.h): a kind names its two symbols,
 * its ABI and how its entry is checked. Only the command line names such a file: a scene never
 * does. docs/lighting-programs.md "How softlight builds and loads it" describes the whole of it. */
#ifndef SL_APP_PROGRAM_LOAD_H
#define SL_APP_PROGRAM_LOAD_H

#include <stdbool.h>
#include <stddef.h>

typedef struct {
    bool debug;   /* --debug-shader: -g -O0 instead of -O2 */
    bool verbose; /* -v: print the compiler command (or the cached object used) on stderr */
} sl_program_load_options;

/* What one kind of program exports, and the words its errors use. */
typedef struct {
    const char *abi_symbol;   /* "sl_lighting_program_abi": a const int */
    const char *entry_symbol; /* "sl_lighting_program_entry" */
    int abi;                  /* the value abi_symbol must hold */
    const char *what;         /* "lighting program" */
    const char *macro;        /* "SL_LIGHTING_PROGRAM": what writes both symbols */
    const char *entry_needs;  /* "a shade function": what entry_ok checks */
    bool (*entry_ok)(const void *entry);
} sl_program_kind;

/* Load `path` (a C source or a shared object) as a program of `kind`: *entry is its entry symbol.
 * On failure, false with one line in msg naming the file (a compile error: the compiler's first
 * error, file:line). The shared object stays loaded for the life of the process. Safe to call
 * from several threads at once (the viewer compiles on threads of its own). */
bool sl_program_load(const char *path, const sl_program_kind *kind, const sl_program_load_options *opt,
                     const void **entry, char *msg, size_t msg_size);

#endif
