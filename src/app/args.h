/* args.h - a small table-driven command-line parser shared by every softlight command
 * (and by softlight-gl), so options, ranges and error lines are the same everywhere.
 *
 * Each command lists its options once, as an sl_arg table; parsing checks types and ranges and
 * turns anything unknown, missing or malformed into one line in sl_error. The same table prints
 * --help, so the help text cannot drift from what is accepted. */
#ifndef SL_ARGS_H
#define SL_ARGS_H

#include <stdbool.h>
#include <stdio.h>

#include "core/error.h"

typedef enum {
    SL_ARG_FLAG,   /* bool, no value */
    SL_ARG_INT,    /* int within [min, max] */
    SL_ARG_FLOAT,  /* finite float within [min, max] */
    SL_ARG_STRING, /* const char * (points into argv) */
    SL_ARG_SIZE,   /* "WxH" into int[2], each within [min, max] */
    SL_ARG_PAIR,   /* "X,Y" into int[2], each within [min, max] */
    SL_ARG_CHOICE, /* one of `choices` ("a|b|c"), stored as `min` plus its index (int) */
    SL_ARG_VEC3,   /* "X,Y,Z" into float[3], each finite within [min, max] */
} sl_arg_type;

/* Where an option's appearance is noted: `bit` or-ed into *bits (the set bits of an
 * sl_option_values record, core/options.h). */
typedef struct {
    unsigned *bits;
    unsigned bit;
} sl_arg_mark;

typedef struct {
    const char *name;  /* "--samples" */
    const char *alias; /* "-o" or NULL */
    sl_arg_type type;
    void *value;       /* where the parsed value goes */
    double min, max;   /* for INT, FLOAT, SIZE, PAIR, VEC3 */
    const char *choices; /* for CHOICE: "spec|spec-d4|paper" */
    const char *metavar; /* "N", "FILE" */
    const char *help;
    const sl_arg_mark *mark; /* optional: noted when the option appears */
} sl_arg;

/* Parse argv[first..argc). Non-option words go to positional[] (at most max_positional).
 * Returns false with one line in err for unknown options, missing or malformed values and
 * out-of-range numbers, or too many positionals. "--help" sets *help and stops. */
bool sl_args_parse(int argc, char **argv, int first, const sl_arg *table, int count, const char **positional,
                   int max_positional, int *positional_count, bool *help, sl_error *err);
/* The entry `word` ("--name", "-n" or "--name=value") names, or NULL. */
const sl_arg *sl_args_find(const sl_arg *table, int count, const char *word);
void sl_args_print_help(FILE *out, const char *usage, const sl_arg *table, int count);

#endif
