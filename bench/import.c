/* import.c - model import time: the hand-written OBJ reader (sl_mesh_load_obj, what "mesh"
 * objects use) against assimp (sl_model_load, what "model" objects and `softlight render
 * FILE` use) on the same files, alternating, median of R rounds; what decided that both stay
 * (docs/performance.md "Import").
 * Usage: bench_import [--rounds R] FILE...   (OBJ files get both readers; others assimp only) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/timer.h"
#include "scene/model.h"

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    int rounds = 9, first = 1;
    if (argc > 2 && strcmp(argv[1], "--rounds") == 0) {
        rounds = atoi(argv[2]);
        first = 3;
    }
    if (rounds < 1 || rounds > 1000 || first >= argc) {
        fprintf(stderr, "usage: bench_import [--rounds R] FILE...\n");
        return 2;
    }
    double *t_obj = calloc((size_t)rounds, sizeof *t_obj), *t_ai = calloc((size_t)rounds, sizeof *t_ai);
    printf("%-40s %10s %12s %12s %8s\n", "file", "triangles", "obj.c ms", "assimp ms", "ratio");
    for (int f = first; f < argc; f++) {
        const char *path = argv[f];
        size_t n = strlen(path);
        bool obj = n > 4 && strcmp(path + n - 4, ".obj") == 0;
        long triangles = 0;
        for (int r = 0; r < rounds; r++) {
            sl_error err;
            if (obj) {
                sl_mesh m;
                double t0 = sl_now_seconds();
                if (!sl_mesh_load_obj(path, &m, &err)) {
                    fprintf(stderr, "%s\n", err.msg);
                    return 2;
                }
                t_obj[r] = sl_now_seconds() - t0;
                sl_mesh_free(&m);
            }
            sl_model model;
            double t0 = sl_now_seconds();
            if (!sl_model_load(path, &model, &err)) {
                fprintf(stderr, "%s\n", err.msg);
                return 2;
            }
            t_ai[r] = sl_now_seconds() - t0;
            triangles = 0;
            for (int i = 0; i < model.instance_count; i++)
                triangles += model.meshes[model.instances[i].mesh].mesh.triangle_count;
            sl_model_free(&model);
        }
        qsort(t_obj, (size_t)rounds, sizeof *t_obj, cmp);
        qsort(t_ai, (size_t)rounds, sizeof *t_ai, cmp);
        double a = 1e3 * t_ai[rounds / 2], o = 1e3 * t_obj[rounds / 2];
        if (obj)
            printf("%-40s %10ld %12.2f %12.2f %8.2f\n", path, triangles, o, a, a / o);
        else
            printf("%-40s %10ld %12s %12.2f %8s\n", path, triangles, "-", a, "-");
    }
    free(t_obj);
    free(t_ai);
    return 0;
}
