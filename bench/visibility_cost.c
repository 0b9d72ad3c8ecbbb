/* visibility_cost.c - bench_visibility_cost: what the whole set of visibility methods costs a
 * frame, measured in one process on scene files (not a test).
 *
 *   bench_visibility_cost [--size 1280x720] [--rounds 9] SCENE.json ...
 *
 * Per scene two renderers on one thread, the scene's own settings with --env-lights 32 (the
 * estimator the set goes with: docs/accuracy.md "Visibility"), the second also with the set:
 * the env lights' and point lights' shadow maps (--shadows), the ambient occlusion
 * (--ao-radius 1), the sky visibility maps (--sky-maps 32) and the reflection occlusion
 * (--reflection-occlusion 5). One frame of each first (the maps are drawn then, once per scene
 * and environment), then ROUNDS rounds of a frame of each, back to back, the order turned each
 * round, each frame timed in process CPU time: a change of load falls on both frames of a round.
 * Prints a markdown row per scene: the median frame of each, the set's share of the frame with it
 * (the median of the rounds' own shares, 1 - without / with) and the lowest and highest of those.
 * docs/lighting.md "What the whole set costs" quotes it (bench/visibility-cost.sh). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/timer.h"
#include "render/renderer.h"

enum { MAX_ROUNDS = 64 };

/* The renderer of `scene` at w x h on one thread with --env-lights 32, and the set when `set`. */
static bool renderer_for(sl_renderer *r, const sl_scene *scene, int w, int h, bool set, sl_error *err)
{
    sl_render_desc desc = {0};
    sl_option_set_size(&desc.options, w, h);
    sl_option_set_threads(&desc.options, 1);
    sl_option_set_env_lights(&desc.options, 32);
    if (set) {
        sl_option_set_shadows(&desc.options, true);
        sl_option_set_ao_radius(&desc.options, 1.0f);
        sl_option_set_sky_maps(&desc.options, 32);
        sl_option_set_reflection_occlusion(&desc.options, 5.0f);
    }
    return sl_renderer_init(r, scene, &desc, err);
}

/* One frame's process CPU seconds. */
static bool timed_frame(sl_renderer *r, double *seconds, sl_error *err)
{
    double c0 = sl_process_cpu_seconds();
    bool ok = sl_renderer_frame(r, NULL, err);
    *seconds = sl_process_cpu_seconds() - c0;
    return ok;
}

static int ascending(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static int bench_scene(const char *path, int w, int h, int rounds)
{
    sl_error err = {0};
    sl_scene scene;
    if (!sl_scene_load(path, &scene, &err)) {
        fprintf(stderr, "bench_visibility_cost: %s\n", err.msg);
        return 1;
    }
    static sl_renderer without, with;
    memset(&without, 0, sizeof without);
    memset(&with, 0, sizeof with);
    int status = 1;
    double off[MAX_ROUNDS], on[MAX_ROUNDS], share[MAX_ROUNDS], first;
    if (!renderer_for(&without, &scene, w, h, false, &err) || !renderer_for(&with, &scene, w, h, true, &err) ||
        !timed_frame(&without, &first, &err) || !timed_frame(&with, &first, &err))
        goto failed;
    for (int k = 0; k < rounds; k++) {
        bool turned = k % 2 == 1;
        if (!timed_frame(turned ? &with : &without, turned ? &on[k] : &off[k], &err) ||
            !timed_frame(turned ? &without : &with, turned ? &off[k] : &on[k], &err))
            goto failed;
        share[k] = on[k] > 0.0 ? 100.0 * (1.0 - off[k] / on[k]) : 0.0;
    }
    double median_share = sl_median(share, rounds);
    qsort(share, (size_t)rounds, sizeof *share, ascending);
    printf("| %s | %.3f | %.3f | %.0f%% | %.0f%% to %.0f%% |\n", path, sl_median(off, rounds), sl_median(on, rounds),
           median_share, share[0], share[rounds - 1]);
    fflush(stdout);
    status = 0;
    goto done;
failed:
    fprintf(stderr, "bench_visibility_cost: %s: %s\n", path, err.msg);
done:
    sl_renderer_free(&without);
    sl_renderer_free(&with);
    sl_scene_free(&scene);
    return status;
}

int main(int argc, char **argv)
{
    int w = 1280, h = 720, rounds = 9, status = 0, scenes = 0;
    const char *usage = "usage: bench_visibility_cost [--size 1280x720] [--rounds 9] SCENE.json ...\n";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--size") && i + 1 < argc && sscanf(argv[i + 1], "%dx%d", &w, &h) == 2 && w > 0 && h > 0)
            i++;
        else if (!strcmp(argv[i], "--rounds") && i + 1 < argc && (rounds = atoi(argv[i + 1])) > 0 &&
                 rounds <= MAX_ROUNDS)
            i++;
        else if (argv[i][0] == '-') {
            fputs(usage, stderr);
            return 2;
        } else {
            if (scenes == 0)
                printf("| scene, %dx%d | CPU s a frame, --env-lights 32 | with --shadows --ao-radius 1 --sky-maps 32 "
                       "--reflection-occlusion 5 | the set's share of the frame | the rounds' shares, lowest to highest "
                       "|\n|---|---:|---:|---:|---:|\n",
                       w, h);
            status |= bench_scene(argv[i], w, h, rounds);
            scenes++;
        }
    }
    if (scenes == 0) {
        fputs(usage, stderr);
        return 2;
    }
    return status;
}
