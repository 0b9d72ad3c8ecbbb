/* data_dir.c - the data directory lookup (include/softlight/data.h).
 *
 * The relative steps from the programs' and the library's install directories to the data
 * directory (SL_DATA_FROM_BINDIR, SL_DATA_FROM_LIBDIR, e.g. "../share/softlight") come from the
 * build (GNUInstallDirs), so a package installed under any prefix, or moved, finds its data. */
#define _GNU_SOURCE /* dladdr */
#include "softlight/data.h"

#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef SL_DATA_FROM_BINDIR
#define SL_DATA_FROM_BINDIR "../share/softlight"
#endif
#ifndef SL_DATA_FROM_LIBDIR
#define SL_DATA_FROM_LIBDIR "../share/softlight"
#endif
/* The file beside a build tree's programs naming the source tree (CMakeLists.txt writes it). */
#define BUILD_TREE_MARKER "softlight-data-dir"

static char set_dir[PATH_MAX];
static char found_dir[PATH_MAX];
static pthread_once_t found_once = PTHREAD_ONCE_INIT;

static bool is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* DIR holds shaders/ and scenes/: copy its canonical form into found_dir. */
static bool try_dir(const char *dir)
{
    char sub[PATH_MAX], canon[PATH_MAX];
    int n = snprintf(sub, sizeof sub, "%s/shaders", dir);
    if (n < 0 || (size_t)n >= sizeof sub || !is_dir(sub))
        return false;
    n = snprintf(sub, sizeof sub, "%s/scenes", dir);
    if (n < 0 || (size_t)n >= sizeof sub || !is_dir(sub))
        return false;
    if (!realpath(dir, canon))
        return false;
    snprintf(found_dir, sizeof found_dir, "%s", canon);
    return true;
}

/* The directory part of a file's path, into out (no trailing slash); false when there is none. */
static bool dir_of(const char *file, char *out, size_t size)
{
    const char *slash = strrchr(file, '/');
    if (!slash || (size_t)(slash - file) >= size)
        return false;
    memcpy(out, file, (size_t)(slash - file));
    out[slash - file] = '\0';
    return true;
}

static bool try_relative(const char *base_dir, const char *relative)
{
    char dir[PATH_MAX];
    int n = snprintf(dir, sizeof dir, "%s/%s", base_dir, relative);
    return n >= 0 && (size_t)n < sizeof dir && try_dir(dir);
}

/* The build tree's marker: one line, the source directory. */
static bool try_marker(const char *exe_dir)
{
    char path[PATH_MAX], line[PATH_MAX];
    int n = snprintf(path, sizeof path, "%s/" BUILD_TREE_MARKER, exe_dir);
    if (n < 0 || (size_t)n >= sizeof path)
        return false;
    FILE *f = fopen(path, "r");
    if (!f)
        return false;
    bool ok = fgets(line, sizeof line, f) != NULL;
    fclose(f);
    if (!ok)
        return false;
    line[strcspn(line, "\r\n")] = '\0';
    return line[0] == '/' && try_dir(line);
}

static void find_once(void)
{
    found_dir[0] = '\0';
    char exe[PATH_MAX], exe_dir[PATH_MAX] = "", lib_dir[PATH_MAX] = "";
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        exe[n] = '\0';
        if (!dir_of(exe, exe_dir, sizeof exe_dir))
            exe_dir[0] = '\0';
    }
    Dl_info info;
    char lib[PATH_MAX];
    if (dladdr((void *)&sl_data_dir, &info) && info.dli_fname && realpath(info.dli_fname, lib) &&
        (n <= 0 || strcmp(lib, exe) != 0)) /* linked statically: the program itself, step 3 */
        if (!dir_of(lib, lib_dir, sizeof lib_dir))
            lib_dir[0] = '\0';
    if (exe_dir[0] && try_relative(exe_dir, SL_DATA_FROM_BINDIR))
        return;
    if (lib_dir[0] && try_relative(lib_dir, SL_DATA_FROM_LIBDIR))
        return;
    if (exe_dir[0] && try_marker(exe_dir))
        return;
    if (lib_dir[0] && try_marker(lib_dir))
        return;
    found_dir[0] = '\0';
}

const char *sl_data_dir(void)
{
    const char *env = getenv("SOFTLIGHT_DATA_DIR");
    if (env && env[0])
        return env;
    if (set_dir[0])
        return set_dir;
    pthread_once(&found_once, find_once);
    return found_dir[0] ? found_dir : NULL;
}

void sl_set_data_dir(const char *dir)
{
    snprintf(set_dir, sizeof set_dir, "%s", dir ? dir : "");
}

bool sl_data_path(const char *relative, char *out, size_t size)
{
    const char *dir = sl_data_dir();
    if (!dir)
        return false;
    int n = snprintf(out, size, "%s/%s", dir, relative);
    return n >= 0 && (size_t)n < size;
}
