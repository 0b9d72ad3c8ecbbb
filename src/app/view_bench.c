/* view_bench.c - `softlight view --benchmark FRAMES`: the moving stage under a steady drag,
 * timed from one present to the next (the contract is in view_internal.h).
 *
 * Why a file of its own: it is a measuring instrument beside the viewer, not part of it. It
 * feeds the loop the input a drag would (view_bench_input) and records what the loop presented
 * (view_bench_record); the refinement and the window do not know it runs, except that a running
 * benchmark counts as interacting, so the camera never settles. */
#if SL_HAVE_SDL2
#include <SDL.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/timer.h"
#include "view_internal.h"

#define BENCH_WARMUP 5       /* frames not counted (first raster, texture setup) */
#define BENCH_ORBIT_PIXELS 3 /* a drag of this many pixels a frame */

bool view_bench_init(view_bench *b, int frames, sl_error *err)
{
    *b = (view_bench){0};
    double **arrays[] = {&b->frame_ms, &b->raster_ms, &b->shade_ms, &b->tonemap_ms, &b->present_ms};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
        if (!(*arrays[i] = calloc((size_t)frames, sizeof(double))))
            return sl_fail(err, SL_ERR_MEMORY, "out of memory for %d benchmark frames", frames);
    b->frames = frames;
    return true;
}

void view_bench_free(view_bench *b)
{
    free(b->frame_ms);
    free(b->raster_ms);
    free(b->shade_ms);
    free(b->tonemap_ms);
    free(b->present_ms);
    *b = (view_bench){0};
}

void view_bench_input(viewer *v, double now)
{
    view_camera_orbit(&v->camera, -VIEW_ORBIT_DEG_PER_PIXEL * BENCH_ORBIT_PIXELS, 0.0f);
    v->last_input = now;
    view_restart_camera(v);
}

void view_bench_record(viewer *v, double now)
{
    view_bench *b = &v->bench;
    int i = b->done - BENCH_WARMUP;
    b->done++;
    if (i >= 0) {
        b->frame_ms[i] = (now - b->last_present) * 1e3;
        b->raster_ms[i] = v->raster_ms;
        b->shade_ms[i] = v->shade_ms;
        b->tonemap_ms[i] = v->tonemap_ms;
        b->present_ms[i] = v->present_ms;
        b->div_counts[v->shown_params.div]++;
        view_shown_size(v, &b->last_w, &b->last_h);
    }
    b->last_present = now;
    if (i + 1 < b->frames)
        return;
    int n = b->frames, ow, oh;
    char lit[64];
    view_stage_describe(&v->shown_params, lit, sizeof lit);
    view_output_size(v, &ow, &oh);
    double worst = 0.0;
    for (int k = 0; k < n; k++)
        worst = fmax(worst, b->frame_ms[k]);
    double med = sl_median(b->frame_ms, n), p90 = b->frame_ms[(int)(0.9 * (n - 1))];
    char divs[128] = "";
    for (int d = 1; d <= VIEW_MAX_PREVIEW_DIV; d++)
        if (b->div_counts[d]) {
            size_t len = strlen(divs);
            snprintf(divs + len, sizeof divs - len, "%s1/%d: %d", len ? ", " : "", d, b->div_counts[d]);
        }
    SDL_RendererInfo info = {0};
    const char *presenter = SDL_GetRendererInfo(v->sdl, &info) == 0 && info.name ? info.name : "?";
    printf("softlight view: benchmark: %d moving frames in a %dx%d window (rendered %dx%d at the end; frames at "
           "%s), %s: frame median %.1f ms, p90 %.1f ms, worst %.1f ms (%.1f frames a second at the median); "
           "medians: raster %.1f, lighting %.1f, tone map %.1f, present %.1f ms (SDL renderer %s)\n",
           n, ow, oh, b->last_w, b->last_h, divs, lit, med, p90, worst, 1e3 / med, sl_median(b->raster_ms, n),
           sl_median(b->shade_ms, n), sl_median(b->tonemap_ms, n), sl_median(b->present_ms, n), presenter);
    fflush(stdout);
    v->quit = true;
}

#else
typedef int view_bench_unused; /* this file is only built with SDL2 */
#endif
