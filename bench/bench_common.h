/* bench_common.h - what the scene benchmarks that take --size and --rounds share
 * (bench_sky_plane, bench_visibility_cost): those two options' parsing and an ascending order of
 * doubles for qsort. Header-only: each benchmark is one program built from its own .c. */
#ifndef SL_BENCH_COMMON_H
#define SL_BENCH_COMMON_H

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* argv[*i] is `--size WxH` with both positive: w, h set and *i moved past the value. */
static inline bool bench_size_arg(int argc, char **argv, int *i, int *w, int *h)
{
    if (strcmp(argv[*i], "--size") || *i + 1 >= argc || sscanf(argv[*i + 1], "%dx%d", w, h) != 2 || *w <= 0 || *h <= 0)
        return false;
    ++*i;
    return true;
}

/* argv[*i] is `--rounds N` with N in 1 .. max: rounds set and *i moved past the value. */
static inline bool bench_rounds_arg(int argc, char **argv, int *i, int *rounds, int max)
{
    if (strcmp(argv[*i], "--rounds") || *i + 1 >= argc || (*rounds = atoi(argv[*i + 1])) <= 0 || *rounds > max)
        return false;
    ++*i;
    return true;
}

/* qsort's order of doubles, ascending */
static inline int bench_ascending(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

#endif
