/* scene_json.c - reading a scene file's JSON values (scene_read.h): each typed reader checks the
 * JSON type and range of one value and, when it fails, names the file and the JSON path of the
 * value (`bunny.json: objects[3].material: ...`); the paths themselves, and how bytes from the
 * file are shown in messages. A scene file is typed by hand, so strictness is a feature: unknown
 * and duplicate keys, wrong types, non-finite or out-of-range numbers are errors. */
#include "scene_read.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

bool sl_scene_fail(scene_parser *p, const char *path, sl_error_code code, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (path && path[0])
        return sl_fail(p->err, code, "%s: %s: %s", p->name, path, msg);
    return sl_fail(p->err, code, "%s: %s", p->name, msg);
}

/* Up to `max` (at most 64) bytes of a key or string from the file for a message, each byte that
 * is not printable ASCII shown as '?' and "..." after a longer one, as the .hdr and OBJ
 * readers do: a scene file cannot put escape sequences or broken UTF-8 on a terminal. */
const char *sl_scene_masked(const char *s, size_t max, char out[MASKED_MAX + 4])
{
    return sl_error_excerpt(s, max, out, MASKED_MAX + 4);
}

/* A path too long for the buffer (deep nesting, long names) ends in "..." rather than failing. */
static void mark_truncated(char *out, int written)
{
    if (written >= JSON_PATH_MAX)
        memcpy(out + JSON_PATH_MAX - 4, "...", 4);
}

void sl_scene_join_key(char *out, const char *path, const char *key)
{
    char shown[MASKED_MAX + 4];
    mark_truncated(out, snprintf(out, JSON_PATH_MAX, "%s%s%s", path, path[0] ? "." : "", sl_scene_masked(key, 64, shown)));
}

void sl_scene_join_index(char *out, const char *path, int i)
{
    mark_truncated(out, snprintf(out, JSON_PATH_MAX, "%s[%d]", path, i));
}


/* ---- typed readers: each checks the JSON type and range of one value ---- */

const cJSON *sl_scene_member(const cJSON *obj, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(obj, key);
}

bool sl_scene_comment_ok(const cJSON *item)
{
    if (cJSON_IsString(item))
        return true;
    if (!cJSON_IsArray(item))
        return false;
    for (const cJSON *line = item->child; line; line = line->next)
        if (!cJSON_IsString(line))
            return false;
    return true;
}

/* `item` must be an object whose keys are all in `allowed` (plus "comment"), none repeated. */
bool sl_scene_check_keys(scene_parser *p, const cJSON *item, const char *path, const char *const allowed[])
{
    if (!cJSON_IsObject(item))
        return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected an object {...}");
    char shown[MASKED_MAX + 4];
    for (const cJSON *child = item->child; child; child = child->next) {
        const char *key = child->string;
        for (const cJSON *prev = item->child; prev != child; prev = prev->next)
            if (strcmp(prev->string, key) == 0)
                return sl_scene_fail(p, path, SL_ERR_FORMAT, "duplicate key \"%s\"", sl_scene_masked(key, 64, shown));
        if (strcmp(key, "comment") == 0) {
            if (!sl_scene_comment_ok(child)) {
                char sub[JSON_PATH_MAX];
                sl_scene_join_key(sub, path, key);
                return sl_scene_fail(p, sub, SL_ERR_FORMAT, "expected a string or an array of strings");
            }
            continue;
        }
        bool known = false;
        for (int i = 0; allowed[i] && !known; i++)
            known = strcmp(allowed[i], key) == 0;
        if (!known) {
            char list[256] = "";
            size_t used = 0;
            for (int i = 0; allowed[i] && used < sizeof list; i++)
                used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", allowed[i]);
            return sl_scene_fail(p, path[0] ? path : NULL, SL_ERR_FORMAT, "unknown key \"%s\" (expected %s%scomment)",
                           sl_scene_masked(key, 64, shown), list, list[0] ? " or " : "");
        }
    }
    return true;
}

bool sl_scene_read_number(scene_parser *p, const cJSON *item, const char *path, double *out)
{
    if (!cJSON_IsNumber(item))
        return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected a number");
    double x = item->valuedouble;
    /* cJSON turns 1e999 into inf; anything beyond float's range would become inf later. */
    if (!isfinite(x) || fabs(x) > (double)FLT_MAX)
        return sl_scene_fail(p, path, SL_ERR_RANGE, "%g is not a finite float", x);
    *out = x;
    return true;
}

/* A float in [lo, hi]. */
bool sl_scene_read_float(scene_parser *p, const cJSON *item, const char *path, double lo, double hi, float *out)
{
    double x = 0.0;
    if (!sl_scene_read_number(p, item, path, &x))
        return false;
    if (x < lo || x > hi)
        return sl_scene_fail(p, path, SL_ERR_RANGE, "%g is outside %g..%g", x, lo, hi);
    *out = (float)x;
    return true;
}

bool sl_scene_read_int(scene_parser *p, const cJSON *item, const char *path, int lo, int hi, int *out)
{
    double x = 0.0;
    if (!sl_scene_read_number(p, item, path, &x))
        return false;
    if (x != floor(x))
        return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected an integer, got %g", x);
    if (x < lo || x > hi)
        return sl_scene_fail(p, path, SL_ERR_RANGE, "%g is outside %d..%d", x, lo, hi);
    *out = (int)x;
    return true;
}

/* An array of exactly n finite numbers. */
bool sl_scene_read_numbers(scene_parser *p, const cJSON *item, const char *path, int n, double *out)
{
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != n) {
        static const char *const shape[] = {"", "", "an array of 2 numbers", "an array of 3 numbers",
                                            "an array of 4 numbers"};
        return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected %s", shape[n]);
    }
    int i = 0;
    for (const cJSON *e = item->child; e; e = e->next, i++) {
        char sub[JSON_PATH_MAX];
        sl_scene_join_index(sub, path, i);
        if (!cJSON_IsNumber(e))
            return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected an array of %d numbers", n);
        if (!sl_scene_read_number(p, e, sub, &out[i]))
            return false;
    }
    return true;
}

bool sl_scene_read_vec3(scene_parser *p, const cJSON *item, const char *path, vec3 *out)
{
    double v[3];
    if (!sl_scene_read_numbers(p, item, path, 3, v))
        return false;
    *out = vec3(v[0], v[1], v[2]);
    return true;
}

/* IEC 61966-2-1 sRGB decoding, the exact piecewise curve (not the 2.2 power). */
static double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

static int hex_digit(char ch)
{
    if (ch >= '0' && ch <= '9')
        return ch - '0';
    if (ch >= 'a' && ch <= 'f')
        return ch - 'a' + 10;
    if (ch >= 'A' && ch <= 'F')
        return ch - 'A' + 10;
    return -1;
}

/* A colour: [r, g, b] linear, a single number (grey, linear) or "#rrggbb" (sRGB). Linear
 * components must lie in [0, hi]. */
bool sl_scene_read_color(scene_parser *p, const cJSON *item, const char *path, double hi, vec3 *out)
{
    if (cJSON_IsString(item)) {
        const char *s = item->valuestring;
        char shown[MASKED_MAX + 4];
        double c[3];
        bool ok = strlen(s) == 7 && s[0] == '#';
        for (int i = 0; ok && i < 3; i++) {
            int h = hex_digit(s[1 + 2 * i]), l = hex_digit(s[2 + 2 * i]);
            ok = h >= 0 && l >= 0;
            c[i] = srgb_to_linear((double)(16 * h + l) / 255.0);
        }
        if (!ok)
            return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected an sRGB colour \"#rrggbb\", got \"%s\"",
                           sl_scene_masked(s, 32, shown));
        *out = vec3(c[0], c[1], c[2]);
        return true;
    }
    if (cJSON_IsNumber(item)) {
        float g;
        if (!sl_scene_read_float(p, item, path, 0.0, hi, &g))
            return false;
        *out = vec3s(g);
        return true;
    }
    if (!cJSON_IsArray(item))
        return sl_scene_fail(p, path, SL_ERR_FORMAT,
                       "expected [r, g, b] (linear), a number (grey) or \"#rrggbb\" (sRGB)");
    vec3 v;
    if (!sl_scene_read_vec3(p, item, path, &v))
        return false;
    const float c[3] = {v.x, v.y, v.z};
    for (int i = 0; i < 3; i++) {
        if (c[i] < 0.0f || (double)c[i] > hi) {
            char sub[JSON_PATH_MAX];
            sl_scene_join_index(sub, path, i);
            return sl_scene_fail(p, sub, SL_ERR_RANGE, "%g is outside 0..%g", (double)c[i], hi);
        }
    }
    *out = v;
    return true;
}

/* A name or a path holds no control character (U+0001..U+001F, U+007F; U+0000 is refused
 * for every string, check_json): messages and `info` print them, and a file name with one is
 * surely a mistake. */
bool sl_scene_check_no_control(scene_parser *p, const char *s, const char *path)
{
    char shown[MASKED_MAX + 4];
    for (size_t i = 0; s[i]; i++)
        if ((unsigned char)s[i] < 32 || s[i] == 127)
            return sl_scene_fail(p, path, SL_ERR_FORMAT,
                           "\"%s\" holds a control character (byte 0x%02x at %zu): not allowed in names and paths",
                           sl_scene_masked(s, 64, shown), (unsigned)(unsigned char)s[i], i);
    return true;
}

bool sl_scene_read_string(scene_parser *p, const cJSON *item, const char *path, char *out, size_t cap)
{
    if (!cJSON_IsString(item))
        return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected a string");
    size_t n = strlen(item->valuestring);
    if (n == 0)
        return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected a non-empty string");
    if (n >= cap)
        return sl_scene_fail(p, path, SL_ERR_RANGE, "%zu bytes is longer than the %zu allowed", n, cap - 1);
    if (!sl_scene_check_no_control(p, item->valuestring, path))
        return false;
    memcpy(out, item->valuestring, n + 1);
    return true;
}

/* A file path from the scene, resolved relative to the scene file's folder. */
bool sl_scene_read_path(scene_parser *p, const cJSON *item, const char *path, char out[SL_PATH_MAX])
{
    char rel[SL_PATH_MAX];
    if (!sl_scene_read_string(p, item, path, rel, sizeof rel))
        return false;
    const char *dir = p->base_dir;
    int n;
    if (rel[0] == '/' || !dir[0])
        n = snprintf(out, SL_PATH_MAX, "%s", rel);
    else
        n = snprintf(out, SL_PATH_MAX, "%s%s%s", dir, dir[strlen(dir) - 1] == '/' ? "" : "/", rel);
    if (n < 0 || n >= SL_PATH_MAX)
        return sl_scene_fail(p, path, SL_ERR_RANGE, "resolved path is longer than %d bytes", SL_PATH_MAX - 1);
    return true;
}

/* Line and column (1-based) of a byte offset, for JSON syntax errors. */
void sl_scene_line_column(const char *text, size_t offset, size_t *line, size_t *column)
{
    *line = 1;
    *column = 1;
    for (size_t i = 0; i < offset; i++) {
        if (text[i] == '\n')
            ++*line, *column = 1;
        else
            ++*column;
    }
}
