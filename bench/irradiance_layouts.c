/* bench/irradiance_layouts.c - the pole-free irradiance maps against each other and against the
 * ground truth (docs/ibl.md, "Pole-free irradiance maps"): error per texel count, build time,
 * lookup cost, on the shipped maps, any .hdr given, and synthesized hard cases.
 *
 *   bench_irradiance_layouts [map.hdr ...]   (default: scenes/envmaps/ and three synthetic maps)
 *   SL_BENCH_QUICK=1: the default layouts only
 *   SL_BENCH_READY=1 [map.hdr]: the time to make a new environment ready (read, mips, irradiance)
 *   SL_BENCH_EXACT=1: the fast build against the exact one (every level-0 texel a node): the
 *   error the build adds and the error the interpolation adds, apart
 *
 * Reference: E(n) = sum over every level-0 texel of L |m| max(0, n . m^) in double, the ground
 * truth's diffuse quadrature (ground_truth.c), at 4096 Fibonacci-sphere directions plus the
 * hard ones: +Z, -Z, the seam (-1, 0, 0), 64 normals within 3 degrees of +Z (a floor) and
 * directions on the octahedral folds. Errors are relative, per channel, the worst channel
 * counting (as `softlight compare` counts a pixel).
 * Build times are wall, all threads, each configuration timed in turn in one alternating loop
 * (the median of 5 rounds): on a shared machine only ratios within one run mean much. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/image.h"
#include "core/timer.h"
#include "ibl/ibl.h"

#define PI 3.14159265358979323846
#define FIB 4096
#define FLOOR 64
#define MAXDIR (FIB + FLOOR + 16)

typedef struct {
    int count;
    double d[MAXDIR][3];
    double ref[MAXDIR][3];
} probes;

static void add_dir(probes *p, double x, double y, double z)
{
    double l = sqrt(x * x + y * y + z * z);
    p->d[p->count][0] = x / l;
    p->d[p->count][1] = y / l;
    p->d[p->count][2] = z / l;
    p->count++;
}

static void probes_init(probes *p)
{
    p->count = 0;
    for (int k = 0; k < FIB; k++) {
        double z = 1.0 - (2.0 * k + 1.0) / FIB, r = sqrt(1.0 - z * z), phi = k * PI * (3.0 - sqrt(5.0));
        add_dir(p, r * cos(phi), r * sin(phi), z);
    }
    for (int k = 0; k < FLOOR; k++) { /* a floor's normals: within 3 degrees of +Z */
        double t = (3.0 * PI / 180.0) * sqrt((k + 0.5) / FLOOR), phi = k * 2.399963;
        add_dir(p, sin(t) * cos(phi), sin(t) * sin(phi), cos(t));
    }
    add_dir(p, 0, 0, 1);
    add_dir(p, 0, 0, -1);
    add_dir(p, -1, 0, 0);       /* the lat-long seam */
    add_dir(p, -1, 0, 0.3);
    add_dir(p, 0.6, 0, -0.8);   /* octahedral folds (y = 0 or x = 0 below the equator) */
    add_dir(p, 0, -0.6, -0.8);
    add_dir(p, 0.7, 0.7, -0.1); /* near the dual-paraboloid equator */
}

/* The ground truth's diffuse quadrature per channel (double): every level-0 texel as its
 * centroid vector m and its radiance (the nodes of ground_truth.c). */
static void reference(probes *p, const sl_env *env)
{
    const sl_env_level *l = &env->levels[0];
    int w = l->width, h = l->height;
    size_t n = (size_t)w * h;
    double *m = malloc(n * 6 * sizeof *m);
    if (!m)
        exit(1);
    for (int j = 0; j < h; j++) {
        double t0 = PI * j / h, t1 = PI * (j + 1) / h;
        double s = 0.5 * (t1 - t0) - 0.5 * cos(t0 + t1) * sin(t1 - t0), zz = 0.5 * sin(t0 + t1) * sin(t1 - t0);
        for (int i = 0; i < w; i++) {
            double lo = PI - 2.0 * PI * (i + 1) / w, hi = PI - 2.0 * PI * i / w;
            size_t t = (size_t)j * w + i;
            m[t] = s * (sin(hi) - sin(lo));
            m[n + t] = s * (cos(lo) - cos(hi));
            m[2 * n + t] = zz * 2.0 * PI / w;
            m[3 * n + t] = l->texels[t].x;
            m[4 * n + t] = l->texels[t].y;
            m[5 * n + t] = l->texels[t].z;
        }
    }
#pragma omp parallel for schedule(dynamic, 8)
    for (int k = 0; k < p->count; k++) {
        double er = 0.0, eg = 0.0, eb = 0.0, x = p->d[k][0], y = p->d[k][1], z = p->d[k][2];
#pragma omp simd reduction(+ : er, eg, eb)
        for (size_t t = 0; t < n; t++) {
            double c = x * m[t] + y * m[n + t] + z * m[2 * n + t];
            c = c > 0.0 ? c : 0.0;
            er += c * m[3 * n + t];
            eg += c * m[4 * n + t];
            eb += c * m[5 * n + t];
        }
        p->ref[k][0] = er;
        p->ref[k][1] = eg;
        p->ref[k][2] = eb;
    }
    free(m);
}

typedef struct {
    const char *name;
    sl_irradiance_method method;
    int size;       /* OCT/DP side; BRUTE map width */
    int level;      /* OCT/DP source level (0 = default) */
    int bright;     /* OCT/DP bright_max */
    int exact;      /* OCT/DP: every level-0 texel exact (the interpolation error alone) */
} config;

static bool build(sl_irradiance *irr, const sl_env *env, const config *c)
{
    sl_error err;
    bool ok;
    if (c->method == SL_IRRADIANCE_SH9)
        ok = sl_irradiance_sh9(irr, env, &err);
    else if (c->method == SL_IRRADIANCE_BRUTE)
        ok = sl_irradiance_brute(irr, env, c->size, 0, &err);
    else
        ok = sl_irradiance_map(irr, env,
                               &(sl_irradiance_map_desc){.method = c->method, .size = c->size,
                                                         .source_level = c->level, .bright_max = c->bright,
                                                         .exact = c->exact != 0},
                               &err);
    if (!ok)
        fprintf(stderr, "%s: %s\n", c->name, err.msg);
    return ok;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void run(const char *label, const sl_env *env, const config *cfg, int ncfg)
{
    static probes p;
    probes_init(&p);
    double t0 = sl_now_seconds();
    reference(&p, env);
    printf("\n%s (%dx%d), reference %.1f s\n", label, env->levels[0].width, env->levels[0].height,
           sl_now_seconds() - t0);
    printf("  %-26s %7s %8s %8s %8s %8s %8s %8s %9s %7s\n", "layout", "texels", "mean", "p99", "max", "+Z",
           "-Z", "seam", "floor max", "build");
    double times[32][5];
    for (int round = 0; round < 5; round++)
        for (int c = 0; c < ncfg; c++) {
            sl_irradiance irr;
            double t = sl_now_seconds();
            if (!build(&irr, env, &cfg[c]))
                exit(1);
            times[c][round] = (sl_now_seconds() - t) * 1e3;
            sl_irradiance_free(&irr);
        }
    for (int c = 0; c < ncfg; c++) {
        sl_irradiance irr;
        build(&irr, env, &cfg[c]);
        static double rel[MAXDIR];
        double sum = 0.0, floor_max = 0.0;
        for (int k = 0; k < p.count; k++) {
            vec3 n = vec3((float)p.d[k][0], (float)p.d[k][1], (float)p.d[k][2]);
            vec3 e = sl_irradiance_eval(&irr, n);
            double got[3] = {e.x, e.y, e.z};
            rel[k] = 0.0;
            for (int ch = 0; ch < 3; ch++) { /* as softlight compare: the worst channel */
                double den = fmax(fmax(fabs(got[ch]), p.ref[k][ch]), 1e-30);
                rel[k] = fmax(rel[k], fabs(got[ch] - p.ref[k][ch]) / den);
            }
            if (k < FIB)
                sum += rel[k];
            else if (k < FIB + FLOOR)
                floor_max = rel[k] > floor_max ? rel[k] : floor_max;
        }
        double special[3] = {rel[FIB + FLOOR], rel[FIB + FLOOR + 1], rel[FIB + FLOOR + 2]};
        static double sorted[FIB];
        memcpy(sorted, rel, sizeof sorted);
        qsort(sorted, FIB, sizeof(double), cmp_double);
        qsort(times[c], 5, sizeof(double), cmp_double);
        long texels = irr.method == SL_IRRADIANCE_SH9 ? 9
                                                      : (long)irr.map.levels[0].width * irr.map.levels[0].height;
        printf("  %-26s %7ld %7.3f%% %7.3f%% %7.3f%% %7.3f%% %7.3f%% %7.3f%% %8.3f%% %5.1f ms", cfg[c].name, texels,
               100 * sum / FIB, 100 * sorted[(int)(0.99 * FIB)], 100 * sorted[FIB - 1], 100 * special[0],
               100 * special[1], 100 * special[2], 100 * floor_max, times[c][2]);
        if (irr.method == SL_IRRADIANCE_OCT || irr.method == SL_IRRADIANCE_DP)
            printf("  (%d bright, %d groups)", irr.bright_nodes, irr.group_nodes);
        printf("\n");
        sl_irradiance_free(&irr);
    }
}

/* Lookup cost: ns per sl_irradiance_eval over random unit normals, configurations alternating. */
static void lookup_cost(const sl_env *env, const config *cfg, int ncfg)
{
    enum { N = 1 << 16 };
    static vec3 dirs[N];
    unsigned s = 12345;
    for (int k = 0; k < N; k++) {
        double a[3], l;
        do {
            for (int c = 0; c < 3; c++) {
                s = s * 1664525u + 1013904223u;
                a[c] = (s >> 8) / 8388608.0 - 1.0;
            }
            l = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
        } while (l > 1.0 || l < 1e-4);
        l = sqrt(l);
        dirs[k] = vec3((float)(a[0] / l), (float)(a[1] / l), (float)(a[2] / l));
    }
    sl_irradiance irr[16];
    for (int c = 0; c < ncfg; c++)
        build(&irr[c], env, &cfg[c]);
    double best[16];
    for (int c = 0; c < ncfg; c++)
        best[c] = 1e30;
    float sink = 0.0f;
    for (int round = 0; round < 7; round++)
        for (int c = 0; c < ncfg; c++) {
            struct timespec a, b;
            clock_gettime(CLOCK_THREAD_CPUTIME_ID, &a);
            for (int k = 0; k < N; k++)
                sink += sl_irradiance_eval(&irr[c], dirs[k]).x;
            clock_gettime(CLOCK_THREAD_CPUTIME_ID, &b);
            double ns = ((b.tv_sec - a.tv_sec) * 1e9 + (b.tv_nsec - a.tv_nsec)) / N;
            best[c] = ns < best[c] ? ns : best[c];
        }
    printf("\nlookup, sl_irradiance_eval, random normals, one thread CPU time (best of 7, alternating):\n");
    for (int c = 0; c < ncfg; c++) {
        printf("  %-26s %5.1f ns\n", cfg[c].name, best[c]);
        sl_irradiance_free(&irr[c]);
    }
    if (sink == 1.2345f)
        printf("(sink)\n");
}

/* A new environment made ready as the viewer's drag and drop does it (renderer.c
 * sl_renderer_set_environment): read the .hdr, build the mip chain, build the default irradiance.
 * Wall time with all threads and process CPU time (all threads), median of 9, each stage timed
 * in turn; the brute-force lat-long map (the old accurate option) alternates with it as a yardstick. */
static void ready_time(const char *path)
{
    double wall[4][9], cpu[4][9];
    for (int round = 0; round < 9; round++) {
        sl_error err;
        sl_image img;
        sl_env env;
        sl_irradiance irr;
        double t0 = sl_now_seconds(), c0 = (double)clock() / CLOCKS_PER_SEC;
        if (!sl_image_read_hdr(path, 0, &img, NULL, &err))
            exit(1);
        double t1 = sl_now_seconds(), c1 = (double)clock() / CLOCKS_PER_SEC;
        if (!sl_env_build(&env, &img, 0, &err))
            exit(1);
        double t2 = sl_now_seconds(), c2 = (double)clock() / CLOCKS_PER_SEC;
        if (!sl_irradiance_map(&irr, &env, NULL, &err))
            exit(1);
        double t3 = sl_now_seconds(), c3 = (double)clock() / CLOCKS_PER_SEC;
        sl_irradiance_free(&irr);
        if (!sl_irradiance_brute(&irr, &env, 64, 0, &err))
            exit(1);
        double t4 = sl_now_seconds(), c4 = (double)clock() / CLOCKS_PER_SEC;
        sl_irradiance_free(&irr);
        sl_env_free(&env);
        sl_image_free(&img);
        double w[4] = {t1 - t0, t2 - t1, t3 - t2, t4 - t3}, c[4] = {c1 - c0, c2 - c1, c3 - c2, c4 - c3};
        for (int k = 0; k < 4; k++) {
            wall[k][round] = 1e3 * w[k];
            cpu[k][round] = 1e3 * c[k];
        }
    }
    static const char *names[4] = {"read .hdr", "mip chain", "oct irradiance (default)", "brute lat-long 64x32"};
    printf("\n%s made ready (median of 9, ms):\n", path);
    double total_wall = 0.0, total_cpu = 0.0;
    for (int k = 0; k < 4; k++) {
        qsort(wall[k], 9, sizeof(double), cmp_double);
        qsort(cpu[k], 9, sizeof(double), cmp_double);
        printf("  %-26s wall %7.1f   cpu %7.1f\n", names[k], wall[k][4], cpu[k][4]);
        if (k < 3) {
            total_wall += wall[k][4];
            total_cpu += cpu[k][4];
        }
    }
    printf("  %-26s wall %7.1f   cpu %7.1f\n", "ready (first three)", total_wall, total_cpu);
}

/* A 1024x512 synthetic map: a sky (1 + z above the horizon, 0.2 below) and a sun of radius 0.27
 * degrees and radiance 2e5 at polar angle theta_sun (degrees). */
static bool synth(sl_env *env, double theta_sun, sl_error *err)
{
    sl_image img;
    if (!sl_image_alloc(&img, 1024, 512, 3, err))
        return false;
    double sd[3] = {sin(theta_sun * PI / 180) * cos(0.7), sin(theta_sun * PI / 180) * sin(0.7),
                    cos(theta_sun * PI / 180)};
    double cr = cos(0.27 * PI / 180);
    for (int j = 0; j < 512; j++)
        for (int i = 0; i < 1024; i++) {
            vec3 d = sl_uv_to_dir(vec2((i + 0.5f) / 1024, (j + 0.5f) / 512));
            double L = d.z > 0 ? 1.0 + d.z : 0.2;
            if (d.x * sd[0] + d.y * sd[1] + d.z * sd[2] > cr)
                L = 2e5;
            float *t = &img.data[((size_t)j * 1024 + i) * 3];
            t[0] = (float)L;
            t[1] = (float)(L * 0.9);
            t[2] = (float)(L * 0.8);
        }
    bool ok = sl_env_build(env, &img, 0, err);
    sl_image_free(&img);
    return ok;
}

int main(int argc, char **argv)
{
    static const config all[] = {
        {"sh9", SL_IRRADIANCE_SH9, 0, 0, 0, 0},
        {"brute latlong 64x32", SL_IRRADIANCE_BRUTE, 64, 0, 0, 0},
        {"oct 33", SL_IRRADIANCE_OCT, 33, 0, 0, 0},
        {"oct 65", SL_IRRADIANCE_OCT, 65, 0, 0, 0},
        {"oct 129", SL_IRRADIANCE_OCT, 129, 0, 0, 0},
        {"dp 2x33", SL_IRRADIANCE_DP, 33, 0, 0, 0},
        {"dp 2x47", SL_IRRADIANCE_DP, 47, 0, 0, 0},
        {"dp 2x65", SL_IRRADIANCE_DP, 65, 0, 0, 0},
        {"dp 2x91", SL_IRRADIANCE_DP, 91, 0, 0, 0},
        {"oct 129, groups 64x32", SL_IRRADIANCE_OCT, 129, 4, 0, 0},
        {"oct 129, groups 128x64", SL_IRRADIANCE_OCT, 129, 3, 0, 0},
        {"oct 129, groups 32x16", SL_IRRADIANCE_OCT, 129, 5, 0, 0},
        {"oct 129, 32x16, no bright", SL_IRRADIANCE_OCT, 129, 5, -1, 0},
    };
    static const config quick[] = {
        {"sh9", SL_IRRADIANCE_SH9, 0, 0, 0, 0},
        {"brute latlong 64x32", SL_IRRADIANCE_BRUTE, 64, 0, 0, 0},
        {"oct 129", SL_IRRADIANCE_OCT, 129, 0, 0, 0},
        {"dp 2x91", SL_IRRADIANCE_DP, 91, 0, 0, 0},
    };
    static const config exact[] = {
        {"oct 65", SL_IRRADIANCE_OCT, 65, 0, 0, 0},
        {"oct 65 exact", SL_IRRADIANCE_OCT, 65, 0, 0, 1},
        {"oct 129", SL_IRRADIANCE_OCT, 129, 0, 0, 0},
        {"oct 129 exact", SL_IRRADIANCE_OCT, 129, 0, 0, 1},
        {"dp 2x47", SL_IRRADIANCE_DP, 47, 0, 0, 0},
        {"dp 2x47 exact", SL_IRRADIANCE_DP, 47, 0, 0, 1},
    };
    if (getenv("SL_BENCH_READY")) {
        ready_time(argc > 1 ? argv[1] : "scenes/envmaps/city.hdr");
        return 0;
    }
    bool q = getenv("SL_BENCH_QUICK") != NULL, x = getenv("SL_BENCH_EXACT") != NULL;
    const config *cfg = x ? exact : q ? quick : all;
    int ncfg = x ? (int)(sizeof exact / sizeof *exact)
                 : q ? (int)(sizeof quick / sizeof *quick) : (int)(sizeof all / sizeof *all);
    static const char *defaults[] = {"scenes/envmaps/studio.hdr", "scenes/envmaps/interior.hdr",
                                     "scenes/envmaps/forest.hdr", "scenes/envmaps/city.hdr",
                                     "scenes/envmaps/sunset.hdr"};
    int nmaps = argc > 1 ? argc - 1 : 5;
    sl_error err;
    sl_env env;
    for (int m = 0; m < nmaps; m++) {
        const char *path = argc > 1 ? argv[m + 1] : defaults[m];
        sl_image img;
        if (!sl_image_read_hdr(path, 0, &img, NULL, &err) || !sl_env_build(&env, &img, 0, &err)) {
            fprintf(stderr, "%s: %s\n", path, err.msg);
            return 1;
        }
        sl_image_free(&img);
        run(path, &env, cfg, ncfg);
        if (m == 0)
            lookup_cost(&env, cfg, ncfg < 9 ? ncfg : 9);
        sl_env_free(&env);
    }
    if (argc > 1)
        return 0;
    static const struct {
        const char *name;
        double theta;
    } synths[] = {{"synthetic: sun 3 deg above the horizon", 87.0},
                  {"synthetic: sun at the pole (+Z)", 0.0},
                  {"synthetic: sun 1 deg from the pole", 1.0}};
    for (int s = 0; s < 3; s++) {
        if (!synth(&env, synths[s].theta, &err)) {
            fprintf(stderr, "synthetic: %s\n", err.msg);
            return 1;
        }
        run(synths[s].name, &env, cfg, ncfg);
        sl_env_free(&env);
    }
    return 0;
}
