/* gbuffer.c - bench_gbuffer: the G-buffer pass of scene files alone, in wall and CPU time (not a test).
 *
 * softlight render reports the raster stage's wall time; on a shared machine that moves 2-5x
 * with the load, because a thread that waits for a core is counted. The process's CPU time per
 * frame moves much less (it still feels other jobs through the caches), so this bench reports
 * both: per scene the median and the minimum over --frames frames (after one warm-up frame, which
 * also faults the G-buffer's pages in) of sl_raster_scene_textured, the call softlight render
 * times as "raster". Several builds' benches run alternately give comparable CPU figures.
 *
 * usage: bench_gbuffer [--size 1280x720] [--frames 15] [--threads 1] [--tile S] SCENE.json ...
 * (--tile: the raster's tile size, a power of two in [SL_TILE_MIN, SL_TILE_MAX]; 0 or none: the default)
 * SL_BENCH_STATS=1 in the environment also prints one frame's raster counters (triangles, bin
 * entries, fragments shaded, quads, helper lanes), with the counting on. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/timer.h"
#include "raster/gbuffer_textured.h"
#include "scene/scene.h"

#define MAX_FRAMES 1000

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double min_of(const double *v, int n)
{
    double m = v[0];
    for (int i = 1; i < n; i++)
        m = v[i] < m ? v[i] : m;
    return m;
}

/* One scene: load it and its textures, then frames of the G-buffer pass. */
static int bench_scene(const char *path, int width, int height, int frames, int threads, int tile)
{
    sl_scene scene;
    sl_scene_textures tex;
    sl_gbuffer gb = {0};
    sl_error err = {0};
    if (!sl_scene_load(path, &scene, &err)) {
        fprintf(stderr, "bench_gbuffer: %s\n", err.msg);
        return 1;
    }
    sl_raster *r = NULL;
    int status = 1;
    const bool stats = getenv("SL_BENCH_STATS") != NULL; /* counters cost a little: off unless asked */
    static double wall[MAX_FRAMES], cpu[MAX_FRAMES];
    if (!sl_scene_textures_load(&scene, 0, &tex, &err))
        goto fail_scene;
    if (!(r = sl_raster_create(&(sl_raster_desc){.threads = threads, .tile_size = tile, .stats = stats}, &err)) ||
        !sl_gbuffer_resize(&gb, width, height, &err))
        goto fail;
    for (int f = -1; f < frames; f++) {
        double w0 = sl_now_seconds(), c0 = cpu_seconds();
        if (!sl_raster_scene_textured(r, &scene, &tex, &scene.camera, &gb, &err))
            goto fail;
        if (f >= 0) {
            wall[f] = 1e3 * (sl_now_seconds() - w0);
            cpu[f] = 1e3 * (cpu_seconds() - c0);
        }
    }
    printf("%s %dx%d, %d thread(s), %d frames: wall median %.2f min %.2f ms, cpu median %.2f min %.2f ms\n", path,
           width, height, threads, frames, sl_median(wall, frames), min_of(wall, frames), sl_median(cpu, frames),
           min_of(cpu, frames));
    if (stats) { /* one frame's counts: what the pass does, for per-item costs */
        sl_raster_stats st = sl_raster_get_stats(r);
        for (long long *c = &st.triangles_in; c <= &st.parallel_regions; c++)
            *c /= frames + 1;
        printf("  triangles %lld (binned %lld, bin entries %lld), fragments shaded %lld, quads %lld, helpers %lld\n",
               st.triangles_in, st.triangles_binned, st.bin_entries, st.fragments_shaded, st.quads,
               st.helper_invocations);
    }
    status = 0;
fail:
    sl_raster_destroy(r);
    sl_gbuffer_free(&gb);
    sl_scene_textures_free(&tex);
fail_scene:
    if (status)
        fprintf(stderr, "bench_gbuffer: %s\n", err.msg);
    sl_scene_free(&scene);
    return status;
}

int main(int argc, char **argv)
{
    int width = 1280, height = 720, frames = 15, threads = 1, tile = 0, first = argc;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--size") && i + 1 < argc) {
            if (sscanf(argv[++i], "%dx%d", &width, &height) != 2)
                width = 0;
        } else if (!strcmp(argv[i], "--frames") && i + 1 < argc) {
            frames = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            threads = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--tile") && i + 1 < argc) {
            tile = atoi(argv[++i]);
        } else if (argv[i][0] != '-') {
            first = i;
            break;
        } else {
            first = argc;
            break;
        }
    }
    if (first == argc || width < 1 || height < 1 || frames < 1 || frames > MAX_FRAMES || threads < 1) {
        fprintf(stderr,
                "usage: bench_gbuffer [--size 1280x720] [--frames 15 (1..%d)] [--threads 1] [--tile 0 (the default)] "
                "SCENE.json ...\n",
                MAX_FRAMES);
        return 2;
    }
    int status = 0;
    for (int i = first; i < argc; i++)
        status |= bench_scene(argv[i], width, height, frames, threads, tile);
    return status;
}
