/* args.c - see args.h. */
#include "args.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static bool parse_long(const char *s, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end)
        return false;
    *out = v;
    return true;
}

static bool parse_two_ints(const char *s, char sep, int out[2], double min, double max)
{
    const char *mid = strchr(s, sep);
    if (!mid)
        mid = strchr(s, sep == 'x' ? 'X' : sep);
    if (!mid)
        return false;
    char first[32];
    size_t n = (size_t)(mid - s);
    if (n == 0 || n >= sizeof first)
        return false;
    memcpy(first, s, n);
    first[n] = '\0';
    long a, b;
    if (!parse_long(first, &a) || !parse_long(mid + 1, &b))
        return false;
    if (a < min || a > max || b < min || b > max)
        return false;
    out[0] = (int)a;
    out[1] = (int)b;
    return true;
}

/* "X,Y,Z": three finite numbers within [lo, hi], nothing else. */
static bool parse_vec3(const char *s, float out[3], double lo, double hi)
{
    const char *p = s;
    for (int i = 0; i < 3; i++) {
        char *end;
        errno = 0;
        double v = strtod(p, &end);
        if (errno || end == p || !isfinite(v) || v < lo || v > hi || *end != (i < 2 ? ',' : '\0'))
            return false;
        out[i] = (float)v;
        p = end + 1;
    }
    return true;
}

static int choice_index(const char *choices, const char *word)
{
    size_t len = strlen(word);
    int index = 0;
    for (const char *p = choices; *p; index++) {
        const char *bar = strchr(p, '|');
        size_t n = bar ? (size_t)(bar - p) : strlen(p);
        if (n == len && !strncmp(p, word, n))
            return index;
        if (!bar)
            break;
        p = bar + 1;
    }
    return -1;
}

static bool parse_value(const sl_arg *a, const char *s, sl_error *err)
{
    switch (a->type) {
    case SL_ARG_INT: {
        long v;
        if (!parse_long(s, &v))
            return sl_fail(err, SL_ERR_RANGE, "%s: expected an integer, got '%s'", a->name, s);
        if (v < a->min || v > a->max)
            return sl_fail(err, SL_ERR_RANGE, "%s: %ld is outside %.0f..%.0f", a->name, v, a->min, a->max);
        *(int *)a->value = (int)v;
        return true;
    }
    case SL_ARG_FLOAT: {
        char *end;
        errno = 0;
        double v = strtod(s, &end);
        if (errno || end == s || *end || !isfinite(v))
            return sl_fail(err, SL_ERR_RANGE, "%s: expected a number, got '%s'", a->name, s);
        if (v < a->min || v > a->max)
            return sl_fail(err, SL_ERR_RANGE, "%s: %g is outside %g..%g", a->name, v, a->min, a->max);
        *(float *)a->value = (float)v;
        return true;
    }
    case SL_ARG_STRING:
        *(const char **)a->value = s;
        return true;
    case SL_ARG_SIZE:
        if (!parse_two_ints(s, 'x', (int *)a->value, a->min, a->max))
            return sl_fail(err, SL_ERR_RANGE, "%s: expected WxH with each in %.0f..%.0f, got '%s'", a->name, a->min,
                           a->max, s);
        return true;
    case SL_ARG_PAIR:
        if (!parse_two_ints(s, ',', (int *)a->value, a->min, a->max))
            return sl_fail(err, SL_ERR_RANGE, "%s: expected X,Y with each in %.0f..%.0f, got '%s'", a->name, a->min,
                           a->max, s);
        return true;
    case SL_ARG_VEC3:
        if (!parse_vec3(s, (float *)a->value, a->min, a->max))
            return sl_fail(err, SL_ERR_RANGE, "%s: expected X,Y,Z with each a number in %g..%g, got '%s'", a->name,
                           a->min, a->max, s);
        return true;
    case SL_ARG_CHOICE: {
        int i = choice_index(a->choices, s);
        if (i < 0)
            return sl_fail(err, SL_ERR_RANGE, "%s: expected one of %s, got '%s'", a->name, a->choices, s);
        *(int *)a->value = (int)a->min + i;
        return true;
    }
    case SL_ARG_FLAG:
        break;
    }
    return sl_fail(err, SL_ERR_RANGE, "%s: internal: bad option type", a->name);
}

const sl_arg *sl_args_find(const sl_arg *table, int count, const char *word)
{
    const char *eq = strchr(word, '=');
    size_t name_len = eq ? (size_t)(eq - word) : strlen(word);
    for (int k = 0; k < count; k++) {
        const char *names[2] = {table[k].name, table[k].alias};
        for (int j = 0; j < 2; j++)
            if (names[j] && strlen(names[j]) == name_len && !strncmp(names[j], word, name_len))
                return &table[k];
    }
    return NULL;
}

bool sl_args_parse(int argc, char **argv, int first, const sl_arg *table, int count, const char **positional,
                   int max_positional, int *positional_count, bool *help, sl_error *err)
{
    *positional_count = 0;
    *help = false;
    for (int i = first; i < argc; i++) {
        const char *word = argv[i];
        if (!strcmp(word, "--help") || !strcmp(word, "-h")) {
            *help = true;
            return true;
        }
        if (word[0] != '-' || word[1] == '\0') {
            if (*positional_count >= max_positional)
                return sl_fail(err, SL_ERR_RANGE, "unexpected argument '%s'", word);
            positional[(*positional_count)++] = word;
            continue;
        }
        /* "--name=value" is accepted as well as "--name value". */
        const char *eq = strchr(word, '=');
        size_t name_len = eq ? (size_t)(eq - word) : strlen(word);
        const sl_arg *a = sl_args_find(table, count, word);
        if (!a)
            return sl_fail(err, SL_ERR_RANGE, "unknown option '%.*s' (see --help)", (int)name_len, word);
        if (a->mark)
            *a->mark->bits |= a->mark->bit;
        if (a->type == SL_ARG_FLAG) {
            if (eq)
                return sl_fail(err, SL_ERR_RANGE, "%s takes no value", a->name);
            *(bool *)a->value = true;
            continue;
        }
        const char *value = eq ? eq + 1 : NULL;
        if (!value) {
            if (i + 1 >= argc)
                return sl_fail(err, SL_ERR_RANGE, "%s needs a value (%s)", a->name, a->metavar ? a->metavar : "?");
            value = argv[++i];
        }
        if (!parse_value(a, value, err))
            return false;
    }
    return true;
}

void sl_args_print_help(FILE *out, const char *usage, const sl_arg *table, int count)
{
    fprintf(out, "usage: %s\n\noptions:\n", usage);
    for (int k = 0; k < count; k++) {
        const sl_arg *a = &table[k];
        char left[96];
        const char *meta = a->type == SL_ARG_FLAG ? "" : (a->metavar ? a->metavar : "VALUE");
        if (a->type == SL_ARG_CHOICE)
            meta = a->choices;
        snprintf(left, sizeof left, "%s%s%s%s%s", a->alias ? a->alias : "", a->alias ? ", " : "", a->name,
                 meta[0] ? " " : "", meta);
        fprintf(out, "  %-34s %s\n", left, a->help);
    }
    fprintf(out, "  %-34s %s\n", "-h, --help", "show this help");
}
