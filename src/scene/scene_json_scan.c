/* scene_json_scan.c - what cJSON does not say about a scene file: arrays and objects nested past
 * its limit (it answers only "invalid JSON") and the escape \u0000 inside a string or key (which it
 * decodes to a NUL that silently ends the string), each reported with its line, column and JSON
 * path. A walk over the text, keeping the path of where it is; scene.c calls it before and after
 * cJSON reads the document. */
#include "scene_read.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* cJSON refuses arrays and objects nested deeper than this (CJSON_NESTING_LIMIT, 1000 in the
 * packaged library) without a reason; scan_json says so, and where. */
#define JSON_MAX_DEPTH CJSON_NESTING_LIMIT

/* The JSON path of the place scan_json has reached. Bytes past the buffer are counted, not
 * stored, so that leaving a deep level restores the path exactly; a path that long is shown
 * ending in "..." (as mark_truncated does). */
typedef struct {
    char buf[JSON_PATH_MAX];
    size_t len;
} json_path;

static void path_put(json_path *jp, const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++, jp->len++)
        if (jp->len < JSON_PATH_MAX - 1)
            jp->buf[jp->len] = s[i];
}

/* "t.json:3:14: objects[0].name" (no path at the top level), for the message at `offset`. */
static const char *json_where(const scene_parser *p, const char *text, size_t offset, json_path *jp,
                              char out[JSON_PATH_MAX + 128])
{
    size_t line, column;
    sl_scene_line_column(text, offset, &line, &column);
    if (jp->len < JSON_PATH_MAX - 1)
        jp->buf[jp->len] = '\0';
    else
        memcpy(jp->buf + JSON_PATH_MAX - 4, "...", 4);
    snprintf(out, JSON_PATH_MAX + 128, "%.100s:%zu:%zu%s%s", p->name, line, column, jp->len ? ": " : "",
             jp->len ? jp->buf : "");
    return out;
}

typedef struct {
    size_t base;     /* path length of the array or object itself */
    long index;      /* array: the element being read */
    bool object;     /* an object: its strings alternate key, value */
    bool expect_key; /* object: the next string is a key */
} json_frame;

/* Walks the JSON text [0, end), which cJSON has read as valid JSON as far as it goes, keeping
 * the path of where it is, and stops at the first of: an array or object opened deeper than
 * JSON_MAX_DEPTH (when `depth`; cJSON's own error is only "invalid JSON"), or a string, key or
 * value, holding the escape \u0000 (when `nul`), which cJSON decodes to a NUL byte that
 * silently ends the string ("na\u0000me" is read as the key "na"). False with the error
 * (line, column and path); true when neither is found. */
bool sl_scene_scan_json(scene_parser *p, const char *text, size_t end, bool depth, bool nul)
{
    json_frame *frames = calloc(JSON_MAX_DEPTH + 1, sizeof *frames);
    if (!frames)
        return sl_fail(p->err, SL_ERR_MEMORY, "%s: out of memory for the JSON checks", p->name);
    json_path jp = {.len = 0};
    int level = 0;
    bool ok = true;
    char where[JSON_PATH_MAX + 128], shown[MASKED_MAX + 4], number[24];
    for (size_t i = 0; i < end && ok; i++) {
        json_frame *top = level > 0 ? &frames[level - 1] : NULL;
        switch (text[i]) {
        case '{':
        case '[':
            if (level == JSON_MAX_DEPTH) {
                if (depth)
                    ok = sl_fail(p->err, SL_ERR_FORMAT,
                                 "%s: arrays and objects nested deeper than %d levels (the JSON parser's limit)",
                                 json_where(p, text, i, &jp, where), JSON_MAX_DEPTH);
                i = end; /* cJSON read no further */
                break;
            }
            frames[level++] = (json_frame){.base = jp.len, .object = text[i] == '{', .expect_key = text[i] == '{'};
            if (text[i] == '[')
                path_put(&jp, "[0]", 3);
            break;
        case '}':
        case ']':
            if (top) {
                jp.len = top->base;
                level--;
            }
            break;
        case ',':
            if (top) {
                jp.len = top->base;
                top->expect_key = top->object;
                if (!top->object)
                    path_put(&jp, number, (size_t)snprintf(number, sizeof number, "[%ld]", ++top->index));
            }
            break;
        case '"': {
            /* The string as written (escapes not decoded), and its first \u0000. */
            size_t start = i + 1, j = start, zero = 0;
            bool has_zero = false;
            for (; j < end && text[j] != '"'; j++) {
                if (text[j] != '\\')
                    continue;
                if (!has_zero && j + 5 < end && text[j + 1] == 'u' && memcmp(text + j + 2, "0000", 4) == 0)
                    has_zero = true, zero = j;
                j++; /* the escaped character: \" and \\ neither end nor start anything */
            }
            if (j > end) /* a backslash as the last byte: the string ends with the text */
                j = end;
            char raw[MASKED_MAX + 2];
            size_t n = j - start <= MASKED_MAX ? j - start : MASKED_MAX + 1; /* sl_scene_masked() adds "..." */
            memcpy(raw, text + start, n);
            raw[n] = '\0';
            sl_scene_masked(raw, MASKED_MAX, shown);
            bool key = top && top->object && top->expect_key;
            if (key) { /* the path of the object; its value's path adds the key */
                jp.len = top->base;
                top->expect_key = false;
            }
            if (has_zero && nul) {
                ok = key ? sl_fail(p->err, SL_ERR_FORMAT,
                                   "%s: the key \"%s\" holds \\u0000 (a NUL character), which would cut it short",
                                   json_where(p, text, zero, &jp, where), shown)
                         : sl_fail(p->err, SL_ERR_FORMAT,
                                   "%s: the string \"%s\" holds \\u0000 (a NUL character), which would cut it short",
                                   json_where(p, text, zero, &jp, where), shown);
            }
            if (key) {
                if (top->base > 0)
                    path_put(&jp, ".", 1);
                path_put(&jp, shown, strlen(shown));
            }
            i = j;
            break;
        }
        default: break; /* ':', numbers, true, false, null, white space */
        }
    }
    free(frames);
    return ok;
}
