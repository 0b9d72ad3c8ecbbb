/* texture_path.c - finding the file a model's texture reference names, as other viewers do.
 *
 * Owns: the rules that turn a material's texture path, written on whatever machine made the
 * model, into a file beside the model here. Exporters write Windows separators (".\wood.jpg"),
 * Blender's "//" for "relative to the .blend", absolute paths of the author's disk
 * ("Q:/textures/wood.png", "/home/them/wood.png") and names whose case differs from the file's
 * ("WOOD.JPG" for "wood.jpg", harmless on Windows and macOS). In order, the first regular file
 * wins:
 *   1. the reference as written (separators made '/', "//" and "./" prefixes dropped), relative
 *      to the model's folder, or as is when it is an absolute path on this machine;
 *   2. the same relative path with each component matched without regard to case;
 *   3. the reference's last component in the model's folder, matched without regard to case
 *      (the texture copied beside the model, as packaged models are).
 * Nothing else is searched: no parent folders, no environment paths. */
#include "scene_internal.h"

#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

/* Directory entries read to match one component: far above a texture folder's, and a bound on
 * the time a folder of millions of files could take. */
#define MATCH_ENTRIES_MAX 65536

static bool regular_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* In the folder `dir` ("" is the current one), the entry named `name` ignoring case, exact
 * spelling preferred; written to `out` (of `cap` bytes). */
static bool match_entry(const char *dir, const char *name, char *out, size_t cap)
{
    DIR *d = opendir(dir[0] ? dir : ".");
    if (!d)
        return false;
    bool found = false;
    struct dirent *e;
    for (long seen = 0; (e = readdir(d)) && seen < MATCH_ENTRIES_MAX; seen++) {
        if (strcasecmp(e->d_name, name) != 0 || strlen(e->d_name) >= cap)
            continue;
        snprintf(out, cap, "%s", e->d_name);
        found = true;
        if (strcmp(e->d_name, name) == 0)
            break;
    }
    closedir(d);
    return found;
}

/* dir + rel, each component of rel matched ignoring case; dir itself is taken as given. */
static bool resolve_by_case(const char *dir, const char *rel, char out[SL_PATH_MAX])
{
    char built[SL_PATH_MAX];
    size_t n = (size_t)snprintf(built, sizeof built, "%s", dir);
    if (n >= sizeof built)
        return false;
    const char *p = rel;
    while (*p) {
        const char *slash = strchr(p, '/');
        size_t len = slash ? (size_t)(slash - p) : strlen(p);
        char component[256], entry[256];
        if (len == 0 || len >= sizeof component) {
            if (len)
                return false;
            p = slash + 1;
            continue;
        }
        memcpy(component, p, len);
        component[len] = '\0';
        char *folder = built;
        char here[SL_PATH_MAX];
        if (n > 0 && built[n - 1] == '/') { /* opendir wants the folder without its trailing '/' */
            snprintf(here, sizeof here, "%.*s", (int)(n > 1 ? n - 1 : n), built);
            folder = here;
        }
        if (!match_entry(folder, component, entry, sizeof entry))
            return false;
        int w = snprintf(built + n, sizeof built - n, "%s%s", entry, slash ? "/" : "");
        if (w < 0 || (size_t)w >= sizeof built - n)
            return false;
        n += (size_t)w;
        p = slash ? slash + 1 : p + len;
    }
    if (!regular_file(built))
        return false;
    memcpy(out, built, n + 1);
    return true;
}

bool scene_texture_path_resolve(const char *dir, const char *ref, char out[SL_PATH_MAX])
{
    char r[SL_PATH_MAX];
    if (snprintf(r, sizeof r, "%s", ref) >= (int)sizeof r)
        return false;
    for (char *c = r; *c; c++)
        if (*c == '\\')
            *c = '/';
    const char *rel = r;
    if (rel[0] == '/' && rel[1] == '/')
        rel += 2; /* Blender: relative to the file */
    while (rel[0] == '.' && rel[1] == '/')
        rel += 2;
    bool drive = ((rel[0] | 0x20) >= 'a' && (rel[0] | 0x20) <= 'z') && rel[1] == ':';
    bool absolute = rel[0] == '/' || drive;
    char path[SL_PATH_MAX];
    if (rel[0] == '/' && regular_file(rel)) {
        snprintf(out, SL_PATH_MAX, "%s", rel);
        return true;
    }
    if (!absolute) {
        if (snprintf(path, sizeof path, "%s%s", dir, rel) < (int)sizeof path && regular_file(path)) {
            memcpy(out, path, strlen(path) + 1);
            return true;
        }
        if (resolve_by_case(dir, rel, out))
            return true;
    }
    const char *base = strrchr(rel, '/');
    base = base ? base + 1 : (drive ? rel + 2 : rel);
    return base[0] && strcmp(base, ".") && strcmp(base, "..") && resolve_by_case(dir, base, out);
}
