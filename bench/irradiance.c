/* bench/irradiance.c - the figures in docs/ibl.md: SH9 against brute-force irradiance on the
 * shipped environments, the error of brute force over coarser mip levels, and the speed of
 * textureLod, the precomputations and the ground truth.
 *
 *   bench_irradiance [map.hdr ...]     (default: the five maps in scenes/envmaps/)
 *
 * Reference irradiance: the brute-force quadrature over level 0 (every texel), evaluated at
 * the centres of a 64x32 map. Errors are on luminance (Rec. 709 weights), relative to the
 * reference at the same normal; "of mean" divides by the map's mean irradiance instead, which
 * does not blow up in the dark directions. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "core/timer.h"
#include "ibl/ground_truth.h"
#include "ibl/ibl.h"

#define PI 3.14159265358979323846
#define MAP_W 64

/* CPU time of the calling thread: single-thread figures on a shared machine are less
 * disturbed by other processes than wall time (cache sharing still shows). */
static double thread_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double luminance(vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

static vec3 map_centre_dir(int w, int h, int i, int j)
{
    double phi = 2.0 * PI * (0.5 - (i + 0.5) / w), theta = PI * (j + 0.5) / h;
    return vec3(cos(phi) * sin(theta), sin(phi) * sin(theta), cos(theta));
}

typedef struct {
    double rms, max, rms_of_mean, max_of_mean;
} errors;

/* Compare an irradiance (by eval at the reference map's texel centres) with the reference. */
static errors compare(const sl_irradiance *irr, const sl_irradiance *ref, double *min_raw_sh)
{
    const sl_env_level *m = &ref->map.levels[0];
    double mean = 0;
    for (int k = 0; k < m->width * m->height; k++)
        mean += luminance(m->texels[k]);
    mean /= m->width * m->height;
    errors e = {0};
    double s2 = 0, s2m = 0, min_sh = INFINITY;
    for (int j = 0; j < m->height; j++)
        for (int i = 0; i < m->width; i++) {
            vec3 n = map_centre_dir(m->width, m->height, i, j);
            double a = luminance(sl_irradiance_eval(irr, n)), b = luminance(m->texels[j * m->width + i]);
            if (irr->method == SL_IRRADIANCE_SH9) {
                /* the unclamped value, to see how far SH9 rings below 0 */
                const double k0 = 0.282095, k1 = 0.488603, k2 = 1.092548, k3 = 0.315392, k4 = 0.546274;
                double x = n.x, y = n.y, z = n.z;
                double yb[9] = {k0, k1 * y, k1 * z, k1 * x, k2 * x * y, k2 * y * z, k3 * (3 * z * z - 1),
                                k2 * x * z, k4 * (x * x - y * y)};
                vec3 raw = vec3s(0.0f);
                for (int c = 0; c < 9; c++)
                    raw = add3(raw, scale3(irr->sh[c], (float)yb[c]));
                min_sh = fmin(min_sh, luminance(raw) / mean);
            }
            double rel = fabs(a - b) / b, relm = fabs(a - b) / mean;
            s2 += rel * rel;
            s2m += relm * relm;
            e.max = fmax(e.max, rel);
            e.max_of_mean = fmax(e.max_of_mean, relm);
        }
    e.rms = sqrt(s2 / (m->width * m->height));
    e.rms_of_mean = sqrt(s2m / (m->width * m->height));
    if (min_raw_sh)
        *min_raw_sh = min_sh;
    return e;
}

static void bench_map(const char *path)
{
    sl_image img;
    sl_error err = {0};
    if (!sl_image_read_hdr(path, 0, &img, NULL, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    sl_env env;
    double t0 = sl_now_seconds();
    if (!sl_env_build(&env, &img, 0, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    double t_env = sl_now_seconds() - t0;

    sl_irradiance ref, sh;
    t0 = sl_now_seconds();
    sl_irradiance_brute_level(&ref, &env, MAP_W, 0, 0, &err);
    double t_ref = sl_now_seconds() - t0;
    t0 = sl_now_seconds();
    sl_irradiance_sh9(&sh, &env, &err);
    double t_sh = sl_now_seconds() - t0;
    double min_sh;
    errors e = compare(&sh, &ref, &min_sh);
    printf("%s (%dx%d): mip chain %.1f ms, SH9 %.1f ms, brute level 0 (%dx%d map) %.0f ms\n", path, img.width,
           img.height, 1e3 * t_env, 1e3 * t_sh, MAP_W, MAP_W / 2, 1e3 * t_ref);
    printf("  SH9 vs brute level 0: RMS %.2f%%  max %.1f%%  | of mean E: RMS %.2f%%  max %.1f%% | "
           "lowest unclamped SH9 %.3f of mean\n",
           100 * e.rms, 100 * e.max, 100 * e.rms_of_mean, 100 * e.max_of_mean, min_sh);
    for (int level = 1; level <= 5 && level < env.level_count; level++) {
        sl_irradiance b;
        t0 = sl_now_seconds();
        sl_irradiance_brute_level(&b, &env, MAP_W, level, 0, &err);
        double t = sl_now_seconds() - t0;
        errors eb = compare(&b, &ref, NULL);
        printf("  brute level %d (%dx%d): %7.1f ms  RMS %.4f%%  max %.4f%%%s\n", level, env.levels[level].width,
               env.levels[level].height, 1e3 * t, 100 * eb.rms, 100 * eb.max,
               level == sl_irradiance_brute_default_level(&env) ? "   <- default" : "");
        sl_irradiance_free(&b);
    }
    sl_irradiance_free(&ref);
    sl_irradiance_free(&sh);
    sl_env_free(&env);
    sl_image_free(&img);
}

static void bench_texture_lod(const char *path)
{
    sl_image img;
    sl_error err = {0};
    sl_env env;
    if (!sl_image_read_hdr(path, 0, &img, NULL, &err) || !sl_env_build(&env, &img, 0, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    enum { N = 1 << 16, REPS = 200 };
    vec2 *uv = malloc(N * sizeof *uv);
    float *lod = malloc(N * sizeof *lod);
    unsigned s = 1;
    for (int k = 0; k < N; k++) {
        s = s * 1664525u + 1013904223u;
        float a = (float)(s >> 8) / 16777216.0f;
        s = s * 1664525u + 1013904223u;
        float b = (float)(s >> 8) / 16777216.0f;
        s = s * 1664525u + 1013904223u;
        uv[k] = vec2(a, b);
        lod[k] = 10.0f * (float)(s >> 8) / 16777216.0f;
    }
    /* Random uv misses the cache on the large levels; the coherent walk (neighbouring calls
     * read neighbouring texels, as neighbouring pixels' samples do) shows the arithmetic. */
    const char *what[3] = {"random uv, lod in [0, 10]", "random uv, lod in [0, 2]",
                           "coherent walk, lod in [0, 10]"};
    vec2 *walk = malloc(N * sizeof *walk);
    for (int k = 0; k < N; k++)
        walk[k] = vec2(fmod(k * 3e-4, 1.0), 0.5 + 0.4 * sin(k * 1e-4));
    for (int mode = 0; mode < 3; mode++) {
        float acc = 0;
        const vec2 *at = mode == 2 ? walk : uv;
        double t0 = thread_seconds();
        for (int r = 0; r < REPS; r++)
            for (int k = 0; k < N; k++)
                acc += textureLod(&env, at[k], mode == 1 ? 0.2f * lod[k] : lod[k]).x;
        double t = thread_seconds() - t0;
        printf("textureLod (%s, one thread, CPU time): %.1f ns/call (checksum %g)\n", what[mode], 1e9 * t / ((double)N * REPS),
               (double)acc);
    }
    free(uv);
    free(lod);
    free(walk);
    sl_env_free(&env);
    sl_image_free(&img);
}

static void bench_ground_truth(const char *path)
{
    sl_image img;
    sl_error err = {0};
    sl_env env;
    if (!sl_image_read_hdr(path, 0, &img, NULL, &err) || !sl_env_build(&env, &img, 0, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    sl_ground_truth gt;
    double t0 = sl_now_seconds();
    sl_ground_truth_init(&gt, &env, &err);
    double t_init = sl_now_seconds() - t0;
    enum { PIXELS = 24 };
    double acc = 0;
    t0 = thread_seconds();
    for (int p = 0; p < PIXELS; p++) {
        double a = 2.0 * PI * p / PIXELS;
        sl_gt_query q = {.n = vec3(cos(a) * 0.6, sin(a) * 0.6, 0.8), .v = vec3(0.3, 0.1, 1.0),
                         .kd = vec3(0.5, 0.5, 0.5), .ks = vec3(0.04, 0.04, 0.04), .alpha = p % 2 ? 10.0 : 1000.0,
                         .g = p % 3 ? SL_GT_G_INV_LH2 : SL_GT_G_ONE, .rotation = 0.0, .intensity = 1.0};
        sl_gt_result r;
        sl_ground_truth_shade(&gt, &q, &r, &err);
        acc += r.diffuse[0] + r.specular[1];
    }
    double t = thread_seconds() - t0;
    printf("ground truth (%s, %zu texels): init %.1f ms, %.2f ms/pixel (one thread, CPU time; checksum %g)\n", path, gt.count,
           1e3 * t_init, 1e3 * t / PIXELS, acc);
    sl_ground_truth_free(&gt);
    sl_env_free(&env);
    sl_image_free(&img);
}

int main(int argc, char **argv)
{
    const char *defaults[] = {"scenes/envmaps/studio.hdr", "scenes/envmaps/interior.hdr",
                              "scenes/envmaps/forest.hdr", "scenes/envmaps/city.hdr",
                              "scenes/envmaps/sunset.hdr"};
    const char **maps = argc > 1 ? (const char **)(argv + 1) : defaults;
    int count = argc > 1 ? argc - 1 : 5;
    printf("threads: %d\n", omp_get_max_threads());
    bench_texture_lod(maps[0]);
    bench_ground_truth(maps[0]);
    if (getenv("SL_BENCH_QUICK"))
        return 0;
    for (int m = 0; m < count; m++)
        bench_map(maps[m]);
    return 0;
}
