/* softlight/data.h - where softlight's data files are: the GLSL shaders (shaders/) and the
 * default environment (scenes/envmaps/studio.hdr, lighting a model loaded without a scene).
 *
 * A data directory has the source tree's layout: DIR/shaders/ and DIR/scenes/. The lookup, first
 * match wins (docs/install.md "Data files"):
 *   1. $SOFTLIGHT_DATA_DIR, when set and not empty (taken as given);
 *   2. the directory given to sl_set_data_dir;
 *   3. next to the running program: EXE_DIR/../share/softlight (an installed program);
 *   4. next to the shared library: LIB_DIR/../share/softlight (a program linking an installed
 *      libsoftlight.so from anywhere);
 *   5. in a build tree: the directory named by the file softlight-data-dir beside the program
 *      or the shared library, which softlight's build writes beside its programs and libraries
 *      (it names the source tree).
 * Candidates 3-5 count only when DIR/shaders and DIR/scenes exist. Nothing is compiled in:
 * the library and the programs hold no absolute path. */
#ifndef SOFTLIGHT_DATA_H
#define SOFTLIGHT_DATA_H

#include <stdbool.h>
#include <stddef.h>

#include <softlight/version.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The data directory, or NULL when none is found. Steps 3-5 are looked up once per process;
 * the string stays valid until the next sl_set_data_dir. */
SL_API const char *sl_data_dir(void);
/* Use `dir` (copied; NULL or "" clears it) ahead of the executable-relative lookup: for a
 * program that keeps softlight's data elsewhere. Not thread-safe against sl_data_dir. */
SL_API void sl_set_data_dir(const char *dir);
/* DIR/relative into out; false when there is no data directory or out is too small. */
SL_API bool sl_data_path(const char *relative, char *out, size_t size);

#ifdef __cplusplus
}
#endif

#endif
