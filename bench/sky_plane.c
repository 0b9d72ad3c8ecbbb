/* sky_plane.c - bench_sky_plane: the sky maps' V over a whole G-buffer, filled between anchors
 * (src/shading/sky_plane.c, what the batched lighting paths read) against a lookup at every
 * texel, and that lookup made 16 texels at a time (sl_shadow_sky_visibility_points, a lane a
 * texel: the plane's) against one texel at a time (sl_shadow_sky_visibility, a lane a map: what
 * the port does), on scene files (not a test).
 *
 *   bench_sky_plane [--size 1280x720] [--rounds 7] [--maps 32] [--agree A] SCENE.json ...
 *
 * --agree: the fill's agreement of the anchors' V (default SL_SKY_PLANE_AGREE, the lighting
 * pass's). Per scene, after one warm-up round, ROUNDS rounds of the fill, the every-texel lookup
 * 16 texels at a time and the every-texel lookup one texel at a time, in turn on one thread, each
 * timed in process CPU time: the median of each and of the per-round ratios, fill to every texel
 * and 16 at a time to one at a time (a change of load falls on both), the lookups the fill makes
 * per covered texel, and how far its V is from the lookup's: the largest difference, the 99.9th
 * percentile and the share of covered texels more than 1/255 apart; a markdown table, a row a
 * scene. The maps weigh the whole environment (--sky-maps K alone) and are drawn once, before
 * the rounds. docs/lighting.md "Sky visibility maps" quotes it. The two every-texel lookups' V
 * must be equal bit for bit (else the bench fails). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "core/timer.h"
#include "render/renderer.h"
#include "shading/lighting_internal.h"

enum { MAX_ROUNDS = 64 };

static int bench_scene(const char *path, int w, int h, int rounds, int maps, float agree)
{
    sl_error err;
    sl_scene scene;
    if (!sl_scene_load(path, &scene, &err)) {
        fprintf(stderr, "bench_sky_plane: %s\n", err.msg);
        return 1;
    }
    sl_render_desc desc = {0};
    sl_option_set_size(&desc.options, w, h);
    sl_option_set_threads(&desc.options, 1);
    sl_option_set_sky_maps(&desc.options, maps);
    static sl_renderer r;
    int status = 1;
    float *filled = malloc((size_t)w * (size_t)h * sizeof *filled);
    float *every = malloc((size_t)w * (size_t)h * sizeof *every);
    float *single = malloc((size_t)w * (size_t)h * sizeof *single);
    double *diff = malloc((size_t)w * (size_t)h * sizeof *diff);
    if (!filled || !every || !single || !diff) {
        fprintf(stderr, "bench_sky_plane: no memory\n");
        goto done;
    }
    if (!sl_renderer_init(&r, &scene, &desc, &err) || !sl_renderer_raster(&r, NULL, &err) ||
        !sl_renderer_prepare_lighting(&r, NULL, &err)) {
        fprintf(stderr, "bench_sky_plane: %s: %s\n", path, err.msg);
        goto done;
    }
    const sl_lighting_uniforms *u = r.uniforms;
    const sl_gbuffer *gb = &r.gbuffer;
    double t_fill[MAX_ROUNDS], t_every[MAX_ROUNDS], ratio[MAX_ROUNDS], t_single[MAX_ROUNDS], gain[MAX_ROUNDS];
    const vec3 rows[3] = {u->uEnvRotation.c[0], u->uEnvRotation.c[1], u->uEnvRotation.c[2]};
    int64_t lookups = 0;
    for (int k = -1; k < rounds; k++) {
        double c0 = sl_process_cpu_seconds();
        lookups = sl_sky_plane_fill(u, gb, filled, agree, 1);
        double c1 = sl_process_cpu_seconds();
        sl_sky_plane_fill(u, gb, every, -1.0f, 1);
        double c2 = sl_process_cpu_seconds();
        for (int i = 0; i < w * h; i++) {
            const sl_gbuffer_texel *t = &gb->texels[i];
            single[i] = 1.0f;
            if (!(t->depth >= 1.0f)) {
                shade_view_frame f = shade_view_frame_at(u->uEye, t->position, t->normal, rows);
                single[i] = sl_shadow_sky_visibility(u->skyMaps, t->position, f.N, NULL);
            }
        }
        double c3 = sl_process_cpu_seconds();
        if (k >= 0) {
            t_fill[k] = 1e3 * (c1 - c0);
            t_every[k] = 1e3 * (c2 - c1);
            t_single[k] = 1e3 * (c3 - c2);
            ratio[k] = (c1 - c0) / (c2 - c1);
            gain[k] = (c2 - c1) / (c3 - c2);
        }
    }
    if (memcmp(every, single, (size_t)w * (size_t)h * sizeof *every) != 0) {
        fprintf(stderr, "bench_sky_plane: %s: the lookups 16 texels at a time differ from one at a time\n", path);
        goto done;
    }
    int covered = 0, over = 0;
    double worst = 0.0;
    for (int i = 0; i < w * h; i++) {
        if (gb->texels[i].depth >= 1.0f)
            continue;
        double d = fabs((double)filled[i] - (double)every[i]);
        diff[covered++] = d;
        worst = d > worst ? d : worst;
        over += d > 1.0 / 255.0;
    }
    qsort(diff, (size_t)covered, sizeof *diff, bench_ascending);
    double p999 = covered > 0 ? diff[(size_t)(0.999 * (covered - 1))] : 0.0;
    printf("| %s | %dx%d | %d | %.3f | %.1f | %.1f | %.2f | %.4f | %.5f | %.3f%% | %.1f | %.2f |\n", path, w, h,
           covered, covered > 0 ? (double)lookups / covered : 0.0, sl_median(t_fill, rounds), sl_median(t_every, rounds),
           sl_median(ratio, rounds), worst, p999, covered > 0 ? 100.0 * over / covered : 0.0,
           sl_median(t_single, rounds), sl_median(gain, rounds));
    status = 0;
done:
    sl_renderer_free(&r);
    sl_scene_free(&scene);
    free(filled);
    free(every);
    free(single);
    free(diff);
    return status;
}

int main(int argc, char **argv)
{
    int w = 1280, h = 720, rounds = 7, maps = 32, status = 0, scenes = 0;
    float agree = SL_SKY_PLANE_AGREE;
    for (int i = 1; i < argc; i++) {
        if (bench_size_arg(argc, argv, &i, &w, &h) || bench_rounds_arg(argc, argv, &i, &rounds, MAX_ROUNDS))
            continue;
        if (!strcmp(argv[i], "--maps") && i + 1 < argc && (maps = atoi(argv[i + 1])) > 0 &&
            maps <= SL_SKY_MAPS_MAX)
            i++;
        else if (!strcmp(argv[i], "--agree") && i + 1 < argc && (agree = strtof(argv[i + 1], NULL)) >= 0.0f)
            i++;
        else if (argv[i][0] == '-') {
            fprintf(stderr, "usage: bench_sky_plane [--size 1280x720] [--rounds 7] [--maps 32] [--agree A] SCENE.json ...\n");
            return 2;
        } else {
            if (scenes == 0)
                printf("%d maps, agree %g, %d rounds on one thread:\n\n"
                       "| scene | size | covered texels | lookups a covered texel | fill ms | every texel ms | ratio "
                       "| max abs dV | p99.9 abs dV | share > 1/255 | every texel one at a time ms | 16 at a time / one "
                       "at a time |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
                       maps, agree, rounds);
            status |= bench_scene(argv[i], w, h, rounds, maps, agree);
            scenes++;
        }
    }
    if (scenes == 0) {
        fprintf(stderr, "usage: bench_sky_plane [--size 1280x720] [--rounds 7] [--maps 32] [--agree A] SCENE.json ...\n");
        return 2;
    }
    return status;
}
