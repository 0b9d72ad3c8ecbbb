/* visibility_cost.c - bench_visibility_cost: what the whole set of visibility methods costs a
 * frame, measured in one process on scene files (not a test).
 *
 *   bench_visibility_cost [--size 1280x720] [--rounds 9] [--each] SCENE.json ...
 *
 * Per scene two renderers on one thread, the scene's own settings with --env-lights 32 (the
 * estimator the set goes with: docs/accuracy.md "Visibility"), the second also with the set:
 * the env lights' and point lights' shadow maps (--shadows), the ambient occlusion
 * (--ao-radius 1), the sky visibility maps (--sky-maps 32) and the reflection occlusion
 * (--reflection-occlusion 7). One frame of each first (the maps are drawn then, once per scene
 * and environment), then ROUNDS rounds of a frame of each, back to back, the order turned each
 * round, each frame timed in process CPU time: a change of load falls on both frames of a round.
 * Prints a markdown row per scene: the median frame of each, the set's share of the frame with it
 * (the median of the rounds' own shares, 1 - without / with) and the lowest and highest of those.
 * --each: also a renderer per method with that method alone, each round's frames in turn, and a
 * second table: per scene each method's CPU ms a frame over the frame without the set (the
 * median of the rounds' differences) and the set's. docs/lighting.md "What the whole set costs"
 * quotes both (bench/visibility-cost.sh). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "core/timer.h"
#include "render/renderer.h"

enum { MAX_ROUNDS = 64 };

/* The settings a scene is rendered with: without the set, each method alone, the whole set. */
enum { WITHOUT, SHADOWS, AO, SKY_MAPS, REFLECTION, WITH, SETTINGS };
#define SETTING_BIT(s) (1u << (s))
/* The set's values, each declared once: the methods' names and renderer_for read them. */
#define SET_AO_RADIUS 1
#define SET_SKY_MAPS 32
#define SET_REFLECTION_LENGTH 7
#define STRINGIFY_(x) #x
#define STRINGIFY(x) STRINGIFY_(x)
static const char *const method_names[SETTINGS] = {
    [SHADOWS] = "--shadows", [AO] = "--ao-radius " STRINGIFY(SET_AO_RADIUS),
    [SKY_MAPS] = "--sky-maps " STRINGIFY(SET_SKY_MAPS),
    [REFLECTION] = "--reflection-occlusion " STRINGIFY(SET_REFLECTION_LENGTH)};

/* The renderer of `scene` at w x h on one thread with --env-lights 32 and the methods of setting s
 * (WITH: all of them). */
static bool renderer_for(sl_renderer *r, const sl_scene *scene, int w, int h, int s, sl_error *err)
{
    sl_render_desc desc = {0};
    sl_option_set_size(&desc.options, w, h);
    sl_option_set_threads(&desc.options, 1);
    sl_option_set_env_lights(&desc.options, 32);
    if (s == SHADOWS || s == WITH)
        sl_option_set_shadows(&desc.options, true);
    if (s == AO || s == WITH)
        sl_option_set_ao_radius(&desc.options, (float)SET_AO_RADIUS);
    if (s == SKY_MAPS || s == WITH)
        sl_option_set_sky_maps(&desc.options, SET_SKY_MAPS);
    if (s == REFLECTION || s == WITH)
        sl_option_set_reflection_occlusion(&desc.options, (float)SET_REFLECTION_LENGTH);
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

/* Scene at `path`: a row of the first table, and with `each` a row of the second into `*each_row`. */
static int bench_scene(const char *path, int w, int h, int rounds, bool each, char *each_row, size_t row_size)
{
    sl_error err = {0};
    sl_scene scene;
    if (!sl_scene_load(path, &scene, &err)) {
        fprintf(stderr, "bench_visibility_cost: %s\n", err.msg);
        return 1;
    }
    static sl_renderer r[SETTINGS];
    memset(r, 0, sizeof r);
    const unsigned used = each ? (1u << SETTINGS) - 1u : SETTING_BIT(WITHOUT) | SETTING_BIT(WITH);
    int status = 1;
    static double t[SETTINGS][MAX_ROUNDS];
    double share[MAX_ROUNDS], extra[MAX_ROUNDS], first;
    for (int s = 0; s < SETTINGS; s++)
        if ((used & SETTING_BIT(s)) && (!renderer_for(&r[s], &scene, w, h, s, &err) || !timed_frame(&r[s], &first, &err)))
            goto failed;
    /* a round: every setting's frame, back to back, starting one further each round */
    for (int k = 0; k < rounds; k++)
        for (int n = 0; n < SETTINGS; n++) {
            const int s = (n + k) % SETTINGS;
            if ((used & SETTING_BIT(s)) && !timed_frame(&r[s], &t[s][k], &err))
                goto failed;
        }
    for (int k = 0; k < rounds; k++)
        share[k] = t[WITH][k] > 0.0 ? 100.0 * (1.0 - t[WITHOUT][k] / t[WITH][k]) : 0.0;
    double median_share = sl_median(share, rounds);
    qsort(share, (size_t)rounds, sizeof *share, bench_ascending);
    printf("| %s | %.3f | %.3f | %.0f%% | %.0f%% to %.0f%% |\n", path, sl_median(t[WITHOUT], rounds),
           sl_median(t[WITH], rounds), median_share, share[0], share[rounds - 1]);
    fflush(stdout);
    if (each) {
        int used_chars = snprintf(each_row, row_size, "| %s | %.0f |", path, 1e3 * sl_median(t[WITHOUT], rounds));
        for (int s = SHADOWS; s <= WITH && used_chars > 0 && (size_t)used_chars < row_size; s++) {
            for (int k = 0; k < rounds; k++)
                extra[k] = 1e3 * (t[s][k] - t[WITHOUT][k]);
            used_chars += snprintf(each_row + used_chars, row_size - (size_t)used_chars, " %.0f |",
                                   sl_median(extra, rounds));
        }
    }
    status = 0;
    goto done;
failed:
    fprintf(stderr, "bench_visibility_cost: %s: %s\n", path, err.msg);
done:
    for (int s = 0; s < SETTINGS; s++)
        sl_renderer_free(&r[s]);
    sl_scene_free(&scene);
    return status;
}

int main(int argc, char **argv)
{
    int w = 1280, h = 720, rounds = 9, status = 0, scenes = 0;
    bool each = false;
    const char *usage = "usage: bench_visibility_cost [--size 1280x720] [--rounds 9] [--each] SCENE.json ...\n";
    enum { ROW = 512, MAX_SCENES = 64 };
    static char rows[MAX_SCENES][ROW];
    for (int i = 1; i < argc; i++) {
        if (bench_size_arg(argc, argv, &i, &w, &h) || bench_rounds_arg(argc, argv, &i, &rounds, MAX_ROUNDS))
            continue;
        if (!strcmp(argv[i], "--each"))
            each = true;
        else if (argv[i][0] == '-' || scenes == MAX_SCENES) {
            fputs(usage, stderr);
            return 2;
        } else {
            if (scenes == 0) {
                printf("| scene, %dx%d | CPU s a frame, --env-lights 32 | with", w, h);
                for (int s = SHADOWS; s < WITH; s++)
                    printf(" %s", method_names[s]);
                printf(" | the set's share of the frame | the rounds' shares, lowest to highest |\n"
                       "|---|---:|---:|---:|---:|\n");
            }
            rows[scenes][0] = '\0';
            status |= bench_scene(argv[i], w, h, rounds, each, rows[scenes], ROW);
            scenes++;
        }
    }
    if (scenes == 0) {
        fputs(usage, stderr);
        return 2;
    }
    if (each) {
        printf("\n| scene, %dx%d | CPU ms a frame, --env-lights 32 |", w, h);
        for (int s = SHADOWS; s < WITH; s++)
            printf(" + %s alone |", method_names[s]);
        printf(" + the set |\n|---|---:|---:|---:|---:|---:|---:|\n");
        for (int k = 0; k < scenes; k++)
            if (rows[k][0])
                printf("%s\n", rows[k]);
    }
    return status;
}
