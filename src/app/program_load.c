/* program_load.c - compile, cache and load a program named on the command line, of any kind
 * (program_load.h).
 *
 * The cache key is a 64-bit FNV-1a hash of: the source's bytes, the compiler's name and its
 * `--version` output, the flags (the include directory among them), the contents of the public
 * headers there, the ABI versions of every kind (SL_LIGHTING_ABI, SL_GBUFFER_ABI) and softlight's
 * version. The key does not depend on the kind that asks: the same source is the same object for
 * either. The object is written to a temporary name in the cache and renamed into place, so
 * concurrent runs never see half a file; the compiler's log and the temporary object are named
 * by process and by call, so that compiles on several threads of one process stay apart. */
#include <dirent.h>
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stdatomic.h>

#include <softlight/data.h>
#include <softlight/gbuffer_program.h>
#include <softlight/lighting.h>
#include <softlight/version.h>

#include "core/hash.h"
#include "program_load.h"
#include "subprocess.h"

enum { MAX_ARGS = 48, PATH_SIZE = 4096 };

static bool fail(char *msg, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, size, fmt, ap);
    va_end(ap);
    return false;
}


/* The whole file into a malloc'd buffer (NUL-terminated); NULL if it cannot be read. */
static char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    while (buf) {
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (n < cap)
            break;
        char *bigger = realloc(buf, 2 * cap + 1);
        if (!bigger) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = bigger;
        cap *= 2;
    }
    bool bad = ferror(f);
    fclose(f);
    if (!buf || bad) {
        free(buf);
        return NULL;
    }
    buf[n] = '\0';
    if (size)
        *size = n;
    return buf;
}

static bool is_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* The directory holding softlight/lighting.h: $SOFTLIGHT_INCLUDE_DIR, else beside the data
 * directory: DATA/include (a build tree, whose data directory is the source tree) or
 * DATA/../../include (an installed PREFIX/share/softlight and PREFIX/include). */
static bool find_include_dir(char *out, size_t size)
{
    const char *env = getenv("SOFTLIGHT_INCLUDE_DIR");
    char probe[PATH_SIZE];
    if (env && *env) {
        snprintf(out, size, "%s", env);
        return true;
    }
    const char *data = sl_data_dir();
    if (!data)
        return false;
    const char *candidates[] = {"include", "../../include"};
    for (size_t i = 0; i < sizeof candidates / sizeof *candidates; i++) {
        snprintf(probe, sizeof probe, "%s/%s/softlight/lighting.h", data, candidates[i]);
        if (is_file(probe)) {
            return snprintf(out, size, "%s/%s", data, candidates[i]) < (int)size;
        }
    }
    return false;
}

/* $XDG_CACHE_HOME/softlight or $HOME/.cache/softlight, created; false when neither is usable. */
static bool cache_dir(char *out, size_t size)
{
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    char base[PATH_SIZE];
    if (xdg && *xdg)
        snprintf(base, sizeof base, "%s", xdg);
    else if (home && *home)
        snprintf(base, sizeof base, "%s/.cache", home);
    else
        return false;
    mkdir(base, 0755);
    if (snprintf(out, size, "%s/softlight", base) >= (int)size)
        return false;
    return mkdir(out, 0755) == 0 || errno == EEXIST;
}

/* The compiler's first error line (file:line:col: error: ...), else its first line. */
static void first_error(const char *log, char *out, size_t size)
{
    char *text = read_all(log, NULL);
    snprintf(out, size, "the compiler failed");
    if (!text)
        return;
    char *line = text, *pick = NULL, *first = NULL;
    while (line && *line) {
        char *end = strchr(line, '\n');
        if (end)
            *end = '\0';
        if (!first && *line)
            first = line;
        if (!pick && (strstr(line, ": error:") || strstr(line, ": fatal error:")))
            pick = line;
        line = end ? end + 1 : NULL;
    }
    if (pick || first)
        snprintf(out, size, "%s", pick ? pick : first);
    free(text);
}

/* Hash every header in include_dir/softlight. */
static uint64_t hash_headers(uint64_t h, const char *include_dir)
{
    char dir[PATH_SIZE];
    if (snprintf(dir, sizeof dir, "%s/softlight", include_dir) >= (int)sizeof dir)
        return h;
    DIR *d = opendir(dir);
    if (!d)
        return h;
    /* readdir's order is the file system's: sum per-file hashes, which does not depend on it */
    uint64_t sum = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t n = strlen(e->d_name);
        if (n < 3 || strcmp(e->d_name + n - 2, ".h") != 0)
            continue;
        char path[PATH_SIZE + 256];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        size_t size;
        char *text = read_all(path, &size);
        if (text)
            sum += sl_fnv1a(sl_fnv1a_str(SL_FNV1A_START, e->d_name), text, size);
        free(text);
    }
    closedir(d);
    return sl_fnv1a(h, &sum, sizeof sum);
}

/* Compile the C source `path` (text already read) into the cache; the object's path in `so`. */
static bool compile(const char *path, const char *text, size_t text_size, const sl_program_load_options *opt,
                    char *so, size_t so_size, char *msg, size_t msg_size)
{
    /* this call's own names for the log and the temporary object (not frame state: a serial) */
    static atomic_uint serial;
    const unsigned call = atomic_fetch_add(&serial, 1u);
    char include_dir[PATH_SIZE], include_flag[PATH_SIZE + 2], cache[PATH_SIZE];
    if (!find_include_dir(include_dir, sizeof include_dir))
        return fail(msg, msg_size, "%s: softlight's headers were not found (set SOFTLIGHT_INCLUDE_DIR)", path);
    snprintf(include_flag, sizeof include_flag, "-I%s", include_dir);
    /* the compiler: $CC split at spaces (as make does), else cc */
    const char *cc_env = getenv("CC");
    char cc[1024];
    snprintf(cc, sizeof cc, "%s", cc_env && *cc_env ? cc_env : "cc");
    char *argv[MAX_ARGS];
    int argc = 0;
    for (char *tok = strtok(cc, " \t"); tok && argc < MAX_ARGS - 20; tok = strtok(NULL, " \t"))
        argv[argc++] = tok;
    if (argc == 0)
        return fail(msg, msg_size, "%s: $CC names no compiler", path);
    const int cc_args = argc;
    const char *flags[] = {"-std=c11", "-shared", "-fPIC", "-fno-math-errno", "-fno-trapping-math", "-ffp-contract=off",
                           "-Wall"};
    for (size_t i = 0; i < sizeof flags / sizeof *flags; i++)
        argv[argc++] = (char *)flags[i];
    if (opt->debug) {
        argv[argc++] = "-g";
        argv[argc++] = "-O0";
    } else {
        argv[argc++] = "-O2";
    }
    argv[argc++] = include_flag;

    /* the key: source, compiler and its version, flags, headers, ABI, softlight's version */
    char tmpdir_log[PATH_SIZE];
    snprintf(tmpdir_log, sizeof tmpdir_log, "%s/softlight-cc-%ld-%u.log",
             getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (long)getpid(), call);
    uint64_t h = sl_fnv1a(SL_FNV1A_START, text, text_size);
    for (int i = 0; i < argc; i++)
        h = sl_fnv1a_str(h, argv[i]);
    {
        char *vargv[MAX_ARGS];
        memcpy(vargv, argv, sizeof(char *) * (size_t)cc_args);
        vargv[cc_args] = "--version";
        vargv[cc_args + 1] = NULL;
        if (sl_spawn_wait(vargv, tmpdir_log, NULL) != 0) {
            unlink(tmpdir_log);
            return fail(msg, msg_size, "%s: cannot run the C compiler '%s' (set CC)", path, argv[0]);
        }
        char *version = read_all(tmpdir_log, NULL);
        h = sl_fnv1a_str(h, version ? version : "");
        free(version);
    }
    h = hash_headers(h, include_dir);
    const int abi[2] = {SL_LIGHTING_ABI, SL_GBUFFER_ABI}; /* every kind's: the key is the kind's neither */
    h = sl_fnv1a(h, abi, sizeof abi);
    h = sl_fnv1a_str(h, SL_VERSION_STRING);

    if (!cache_dir(cache, sizeof cache))
        return fail(msg, msg_size, "%s: no cache directory ($XDG_CACHE_HOME or $HOME)", path);
    snprintf(so, so_size, "%s/%016llx.so", cache, (unsigned long long)h);
    if (is_file(so)) {
        if (opt->verbose)
            fprintf(stderr, "softlight: %s: cached %s\n", path, so);
        unlink(tmpdir_log);
        return true;
    }
    char tmp[PATH_SIZE + 64];
    snprintf(tmp, sizeof tmp, "%s/%016llx.tmp-%ld-%u.so", cache, (unsigned long long)h, (long)getpid(), call);
    argv[argc++] = "-o";
    argv[argc++] = tmp;
    argv[argc++] = (char *)path;
    argv[argc++] = "-lm";
    argv[argc] = NULL;
    if (opt->verbose) {
        fprintf(stderr, "softlight:");
        for (int i = 0; i < argc; i++)
            fprintf(stderr, " %s", argv[i]);
        fprintf(stderr, "\n");
    }
    int rc = sl_spawn_wait(argv, tmpdir_log, NULL);
    if (rc != 0) {
        char line[1024];
        first_error(tmpdir_log, line, sizeof line);
        unlink(tmpdir_log);
        unlink(tmp);
        if (rc < 0)
            return fail(msg, msg_size, "%s: cannot run the C compiler '%s' (set CC)", path, argv[0]);
        return fail(msg, msg_size, "%s", line);
    }
    unlink(tmpdir_log);
    if (rename(tmp, so) != 0) {
        unlink(tmp);
        return fail(msg, msg_size, "%s: cannot write %s: %s", path, so, strerror(errno));
    }
    return true;
}

bool sl_program_load(const char *path, const sl_program_kind *kind, const sl_program_load_options *opt,
                     const void **entry, char *msg, size_t msg_size)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return fail(msg, msg_size, "%s: %s", path, strerror(errno));
    if (!S_ISREG(st.st_mode))
        return fail(msg, msg_size, "%s: not a regular file", path);
    size_t size;
    char *text = read_all(path, &size);
    if (!text)
        return fail(msg, msg_size, "%s: cannot read it", path);
    char so[PATH_SIZE + 64];
    bool elf = size >= 4 && memcmp(text, "\177ELF", 4) == 0;
    if (elf) { /* a prebuilt object: as it is; a name without a slash would send dlopen searching */
        snprintf(so, sizeof so, "%s%s", strchr(path, '/') ? "" : "./", path);
    } else if (!compile(path, text, size, opt, so, sizeof so, msg, msg_size)) {
        free(text);
        return false;
    }
    free(text);
    void *handle = dlopen(so, RTLD_NOW | RTLD_LOCAL);
    if (!handle)
        return fail(msg, msg_size, "%s: cannot load it: %s", path, dlerror());
    const int *abi = (const int *)dlsym(handle, kind->abi_symbol);
    if (!abi) {
        dlclose(handle);
        return fail(msg, msg_size, "%s: exports no %s: not a %s (%s)", path, kind->abi_symbol, kind->what,
                    kind->macro);
    }
    if (*abi != kind->abi) {
        int found = *abi;
        dlclose(handle);
        return fail(msg, msg_size, "%s: %s ABI %d, this softlight takes %d: rebuild it", path, kind->what, found,
                    kind->abi);
    }
    const void *p = dlsym(handle, kind->entry_symbol);
    if (!p || !kind->entry_ok(p)) {
        dlclose(handle);
        return fail(msg, msg_size, "%s: no entry point: %s with %s", path, kind->entry_symbol, kind->entry_needs);
    }
    *entry = p; /* the handle stays open: the program runs until the process ends */
    return true;
}
