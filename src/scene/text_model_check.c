/* text_model_check.c - checks on OBJ and OFF files that their importer does not make.
 *
 * Owns: what softlight refuses in the two plain-text formats before assimp reads them. assimp's
 * OBJ importer makes a grey default for a material that `usemtl` names and no `newmtl` defines
 * (a missing or misspelt .mtl), and its OFF importer takes a face whose vertex index is past the
 * vertex list without a word: both draw a picture that is not the file's. The scans are linear,
 * line by line, and bounded by the file's size; they read nothing but the file and the .mtl
 * libraries it names (found as texture_path.c finds textures). */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "model.h"
#include "scene_internal.h"

/* The next line of [*p, end) without its end-of-line, leading and trailing blanks; false at end. */
static bool next_line(const char **p, const char *end, const char **line, size_t *len)
{
    if (*p >= end)
        return false;
    const char *s = *p, *nl = memchr(s, '\n', (size_t)(end - s));
    const char *e = nl ? nl : end;
    *p = nl ? nl + 1 : end;
    while (s < e && (*s == ' ' || *s == '\t'))
        s++;
    while (e > s && (e[-1] == '\r' || e[-1] == ' ' || e[-1] == '\t'))
        e--;
    *line = s;
    *len = (size_t)(e - s);
    return true;
}

/* The argument of `keyword` when the line is "keyword ARG" (ARG the rest of the line). */
static bool keyword_arg(const char *line, size_t len, const char *keyword, const char **arg, size_t *arg_len)
{
    size_t k = strlen(keyword);
    if (len <= k || strncmp(line, keyword, k) != 0 || (line[k] != ' ' && line[k] != '\t'))
        return false;
    const char *a = line + k;
    while (a < line + len && (*a == ' ' || *a == '\t'))
        a++;
    *arg = a;
    *arg_len = (size_t)(line + len - a);
    return *arg_len > 0;
}

/* ---- OBJ: every usemtl names a newmtl of a library the file names ---- */

typedef struct {
    char (*names)[SL_NAME_MAX];
    int count, cap;
} name_set;

static bool name_add(name_set *s, const char *name, size_t len)
{
    if (len >= SL_NAME_MAX)
        len = SL_NAME_MAX - 1;
    for (int i = 0; i < s->count; i++)
        if (strncmp(s->names[i], name, len) == 0 && s->names[i][len] == '\0')
            return true;
    if (s->count == SL_MODEL_MAX_MATERIALS)
        return true; /* the import's own cap refuses the file */
    if (s->count == s->cap) {
        int cap = s->cap ? 2 * s->cap : 16;
        void *grown = realloc(s->names, (size_t)cap * sizeof *s->names);
        if (!grown)
            return false;
        s->names = grown;
        s->cap = cap;
    }
    memcpy(s->names[s->count], name, len);
    s->names[s->count++][len] = '\0';
    return true;
}

static bool name_has(const name_set *s, const char *name, size_t len)
{
    if (len >= SL_NAME_MAX)
        len = SL_NAME_MAX - 1;
    for (int i = 0; i < s->count; i++)
        if (strncmp(s->names[i], name, len) == 0 && s->names[i][len] == '\0')
            return true;
    return false;
}

/* The newmtl names of the library `ref` (as the OBJ writes it) into `defined`; the reason it
 * could not be read into `why` otherwise. */
static bool read_library(const char *dir, const char *ref, name_set *defined, char *why, size_t why_size)
{
    char path[SL_PATH_MAX];
    if (!dir) {
        snprintf(why, why_size, "not reachable from a model in memory");
        return false;
    }
    if (!sl_scene_texture_path_resolve(dir, ref, path)) {
        snprintf(why, why_size, "no such file");
        return false;
    }
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(why, why_size, "%s", strerror(errno));
        return false;
    }
    char buf[4096];
    while (fgets(buf, sizeof buf, f)) {
        size_t len = strlen(buf);
        const char *line = buf, *arg;
        size_t arg_len;
        while (len && (buf[len - 1] == '\n' || buf[len - 1] == '\r' || buf[len - 1] == ' ' || buf[len - 1] == '\t'))
            buf[--len] = '\0';
        while (*line == ' ' || *line == '\t')
            line++, len--;
        if (keyword_arg(line, len, "newmtl", &arg, &arg_len) && !name_add(defined, arg, arg_len)) {
            fclose(f);
            snprintf(why, why_size, "out of memory");
            return false;
        }
    }
    fclose(f);
    return true;
}

bool sl_scene_obj_check(const char *text, size_t size, const char *dir, const char *name, sl_error *err)
{
    name_set defined = {0};
    const char *p = text, *end = text + size, *line;
    size_t len;
    char missing_lib[SL_PATH_MAX] = "", why[96] = "";
    bool ok = true, any_lib = false;
    /* The libraries first: OBJ allows usemtl before mtllib. */
    while (ok && next_line(&p, end, &line, &len)) {
        const char *arg;
        size_t arg_len;
        if (!keyword_arg(line, len, "mtllib", &arg, &arg_len))
            continue;
        any_lib = true;
        if (arg_len >= SL_PATH_MAX)
            continue;
        char ref[SL_PATH_MAX];
        memcpy(ref, arg, arg_len);
        ref[arg_len] = '\0';
        if (!read_library(dir, ref, &defined, why, sizeof why) && !missing_lib[0])
            snprintf(missing_lib, sizeof missing_lib, "%s", ref);
    }
    for (p = text; ok && next_line(&p, end, &line, &len);) {
        const char *arg;
        size_t arg_len;
        if (!keyword_arg(line, len, "usemtl", &arg, &arg_len) || name_has(&defined, arg, arg_len))
            continue;
        char mat[72], lib[72];
        char shown[SL_NAME_MAX];
        snprintf(shown, sizeof shown, "%.*s", (int)(arg_len < SL_NAME_MAX - 1 ? arg_len : SL_NAME_MAX - 1), arg);
        sl_error_excerpt(shown, 64, mat, sizeof mat);
        if (missing_lib[0])
            ok = sl_fail(err, SL_ERR_IO, "%s: material \"%s\" (usemtl) is not defined: its library \"%s\" cannot be "
                         "read (%s)", name, mat, sl_error_excerpt(missing_lib, 64, lib, sizeof lib), why);
        else if (!any_lib)
            ok = sl_fail(err, SL_ERR_FORMAT, "%s: material \"%s\" (usemtl) is not defined: the file names no .mtl "
                         "library (no mtllib line)", name, mat);
        else
            ok = sl_fail(err, SL_ERR_FORMAT, "%s: material \"%s\" (usemtl) is defined by no newmtl of its .mtl "
                         "libraries", name, mat);
    }
    free(defined.names);
    return ok;
}

/* ---- OFF: the counts line, then every face's indices within the vertex list ---- */

/* The next line that holds data: not blank, not a '#' comment. */
static bool next_data_line(const char **p, const char *end, const char **line, size_t *len)
{
    while (next_line(p, end, line, len))
        if (*len && (*line)[0] != '#')
            return true;
    return false;
}

bool sl_scene_off_check(const char *text, size_t size, const char *name, sl_error *err)
{
    const char *p = text, *end = text + size, *line;
    size_t len;
    if (!next_data_line(&p, end, &line, &len))
        return true; /* the importer says what is wrong with an empty file */
    /* "OFF", "COFF", "NOFF", "STOFF", ... alone on its line, or followed by the counts. */
    const char *counts = line;
    size_t counts_len = len;
    size_t k = 0;
    while (k < len && isalpha((unsigned char)line[k]))
        k++;
    if (k >= 3 && strncasecmp(line + k - 3, "OFF", 3) == 0) {
        counts = line + k;
        counts_len = len - k;
        while (counts_len && isspace((unsigned char)*counts))
            counts++, counts_len--;
        if (!counts_len && !next_data_line(&p, end, &counts, &counts_len))
            return true;
    }
    /* The counts must be two integers: what the importer would make of anything else (a count
     * run together with the keyword, a number past 64 bits) is its own guess. */
    char buf[96], *at = buf, *num_end;
    snprintf(buf, sizeof buf, "%.*s", (int)(counts_len < 95 ? counts_len : 95), counts);
    errno = 0;
    long long vertices = strtoll(at, &num_end, 10);
    bool ok = num_end != at && errno == 0;
    at = num_end;
    long long faces = ok ? strtoll(at, &num_end, 10) : 0;
    ok = ok && num_end != at && errno == 0 && (*num_end == '\0' || isspace((unsigned char)*num_end));
    if (!ok || vertices < 0 || faces < 0)
        return sl_fail(err, SL_ERR_FORMAT, "%s: OFF header: expected the vertex and face counts (two non-negative "
                       "integers) after the OFF keyword", name);
    if (vertices > SCENE_MAX_TOTAL_VERTICES || faces > SCENE_MAX_TRIANGLES)
        return sl_fail(err, SL_ERR_RANGE, "%s: declares %lld vertices and %lld faces (softlight reads at most %d and %d)",
                       name, vertices, faces, SCENE_MAX_TOTAL_VERTICES, SCENE_MAX_TRIANGLES);
    /* A file holds a line per vertex and per face it declares: the importer sizes its arrays by
     * the counts, so counts a short file does not back are refused before it allocates them. */
    for (long long v = 0; v < vertices; v++)
        if (!next_data_line(&p, end, &line, &len))
            return sl_fail(err, SL_ERR_FORMAT, "%s: truncated OFF: it declares %lld vertices and holds %lld", name,
                           vertices, v);
    for (long long f = 0; f < faces; f++) {
        if (!next_data_line(&p, end, &line, &len))
            return sl_fail(err, SL_ERR_FORMAT, "%s: truncated OFF: it declares %lld faces and holds %lld", name,
                           faces, f);
        /* A NUL-terminated copy: strtol must not read on into the next line or past the file. A
         * face line longer than the copy is checked as far as it goes. */
        char face[4096];
        size_t n_copy = len < sizeof face - 1 ? len : sizeof face - 1;
        memcpy(face, line, n_copy);
        face[n_copy] = '\0';
        char *s = face, *stop;
        long n = strtol(s, &stop, 10);
        if (stop == s)
            continue;
        s = stop;
        for (long i = 0; i < n && *s; i++) {
            long long index = strtoll(s, &stop, 10);
            if (stop == s)
                break;
            s = stop;
            if (index < 0 || index >= vertices)
                return sl_fail(err, SL_ERR_FORMAT, "%s: face %lld: vertex index %lld out of range (%lld vertices)", name,
                               f, index, vertices);
        }
    }
    return true;
}
