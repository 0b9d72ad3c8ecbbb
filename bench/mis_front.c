/* mis_front.c - the MIS estimator's speed against error front, the timing half: for one scene at
 * one size, the lighting stage's process CPU time of each variant (median of 7 frames, the
 * variants interleaved, after a warm-up round; point lights off) and its radiance as PFM, which
 * bench/mis-front.sh compares with the ground truth (`softlight truth --compare`).
 *
 *   bench_mis_front SCENE.json WxH OUTDIR THREADS NAME|ESTIMATOR|LOD|DISTORTION|N[|ENV_LIGHTS] ...
 *
 * ENV_LIGHTS: a count K, or auto: those of the brightest 64 worth their cost, as the GGX default
 * takes them (src/ibl/env_lights.h sl_env_lights_extract_worth). ESTIMATOR `default`: the
 * scene's own sampling as sl_render_desc_resolve gives it (LOD and DISTORTION unread; a scene of
 * both lobe sets samples each its way); any other estimator sets every pixel's. N 0: the scene's
 * own N as resolved (a scene of GGX objects alone that sets none: SL_GGX_DEFAULT_SAMPLES).
 *
 * Why a program of its own: the sweep of bench/speed_vs_error.c runs every variant on fixed
 * scenes; this one takes any scene file (the environments bench/mis-front.sh writes into a
 * temporary directory) and only the variants asked for. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "render/renderer.h"
#include <softlight/image.h>

enum { FRAMES = 7, MAX_VARIANTS = 32 };

static double cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return 1e3 * (double)ts.tv_sec + 1e-6 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static int fail(const char *what, const sl_error *err)
{
    fprintf(stderr, "bench_mis_front: %s: %s\n", what, err->msg);
    return 1;
}

int main(int argc, char **argv)
{
    int w, h;
    if (argc < 6 || sscanf(argv[2], "%dx%d", &w, &h) != 2 || argc - 5 > MAX_VARIANTS) {
        fprintf(stderr, "usage: bench_mis_front SCENE.json WxH OUTDIR THREADS NAME|ESTIMATOR|LOD|DISTORTION|N[|ENV_LIGHTS] ...\n");
        return 2;
    }
    sl_error err;
    sl_scene scene;
    if (!sl_scene_load(argv[1], &scene, &err))
        return fail(argv[1], &err);
    sl_render_desc desc = {0};
    sl_option_set_size(&desc.options, w, h);
    sl_option_set_threads(&desc.options, atoi(argv[4]));
    sl_option_set_no_lights(&desc.options, true);
    const int nv = argc - 5;
    static double t[MAX_VARIANTS][FRAMES];
    sl_lighting_options opts[MAX_VARIANTS];
    sl_renderer *pool[MAX_VARIANTS], *of[MAX_VARIANTS];
    int pool_lights[MAX_VARIANTS], renderers = 0; /* each pool renderer's request: K, a ceiling or not */
    bool pool_worth[MAX_VARIANTS];
    char names[MAX_VARIANTS][64];
    for (int i = 0; i < nv; i++) {
        char est[32], lod[32], lights[32] = "0";
        int dist, n, env_lights = 0;
        if (sscanf(argv[5 + i], "%63[^|]|%31[^|]|%31[^|]|%d|%d|%31s", names[i], est, lod, &dist, &n, lights) < 5 ||
            n < 0 ||
            (strcmp(lights, "auto") != 0 && sscanf(lights, "%d", &env_lights) != 1)) {
            fprintf(stderr, "bench_mis_front: %s: expected NAME|ESTIMATOR|LOD|DISTORTION|N[|ENV_LIGHTS or auto]\n", argv[5 + i]);
            return 2;
        }
        /* auto: the GGX default's ceiling, those of the brightest SL_ENV_LIGHTS_MAX worth their cost */
        bool worth = strcmp(lights, "auto") == 0;
        if (worth)
            env_lights = SL_ENV_LIGHTS_MAX;
        sl_estimator estimator = SL_ESTIMATOR_DEFAULT;
        sl_lod_rule lod_rule = SL_LOD_DEFAULT;
        const bool scene_default = strcmp(est, "default") == 0;
        if (!scene_default && (!sl_estimator_parse(est, &estimator) || !sl_lod_rule_parse(lod, &lod_rule))) {
            fprintf(stderr, "bench_mis_front: %s: unknown estimator or lod rule\n", argv[5 + i]);
            return 2;
        }
        /* a renderer per env-light request, each extracted once: a shared one would extract
         * again before each frame of a variant whose request differs from the last one's, and
         * that frame would start with the caches the extraction left */
        int slot = 0;
        while (slot < renderers && !(pool_lights[slot] == env_lights && pool_worth[slot] == worth))
            slot++;
        if (slot == renderers) {
            pool[slot] = calloc(1, sizeof *pool[slot]);
            if (!pool[slot] || !sl_renderer_init(pool[slot], &scene, &desc, &err) ||
                !sl_renderer_raster(pool[slot], NULL, &err))
                return fail(argv[1], &err);
            pool_lights[slot] = env_lights;
            pool_worth[slot] = worth;
            renderers++;
        }
        sl_renderer *renderer = pool[slot];
        of[i] = renderer;
        opts[i] = renderer->desc.lighting;
        if (!scene_default) { /* every pixel's, both lobe sets */
            opts[i].estimator = estimator;
            opts[i].lod_rule = lod_rule;
            opts[i].distortion = dist != 0;
            opts[i].ggx = (sl_lobe_sampling){0};
            opts[i].env_lights_ggx_only = false;
        }
        if (n > 0) /* 0: the scene's N as resolved */
            opts[i].samples = n;
        opts[i].env_lights = env_lights; /* extracted once per count, outside the timed frames */
        opts[i].env_lights_worth = worth;
        opts[i].no_point_lights = true;
    }
    for (int f = -1; f < FRAMES; f++)
        for (int i = 0; i < nv; i++) {
            sl_renderer *r = of[i];
            r->desc.lighting = opts[i];
            if (!sl_renderer_prepare_lighting(r, NULL, &err))
                return fail(names[i], &err);
            double c0 = cpu_ms();
            if (!sl_renderer_shade(r, NULL, &err))
                return fail(names[i], &err);
            double c1 = cpu_ms();
            if (f >= 0)
                t[i][f] = c1 - c0;
            if (f == FRAMES - 1) {
                char path[1024];
                snprintf(path, sizeof path, "%s/%s.pfm", argv[3], names[i]);
                if (!sl_image_write_pfm(path, &r->radiance, &err))
                    return fail(path, &err);
            }
        }
    for (int i = 0; i < nv; i++) {
        qsort(t[i], FRAMES, sizeof t[i][0], cmp_double);
        printf("%s %.2f\n", names[i], t[i][FRAMES / 2]);
    }
    for (int k = 0; k < renderers; k++) {
        sl_renderer_free(pool[k]);
        free(pool[k]);
    }
    sl_scene_free(&scene);
    return 0;
}
