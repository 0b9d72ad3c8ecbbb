/* raster.c - bench_raster: rasterizer throughput at 1920x1080 (not a test).
 *
 * Two workloads, both through the built-in G-buffer pair, each frame = clear + draw:
 *   tris  a UV sphere of about a million small triangles (1000 x 500) filling most of
 *         the frame, both faces drawn: setup- and binning-bound. Reported as triangles
 *         submitted per second.
 *   fill  ten screen-sized quads at different depths drawn in alternating depth order
 *         (overdraw 10, about half the fragments pass the LESS test): tile-bound.
 *         Reported as depth-tested fragments per second.
 * For every tile size of the sweep and every thread count, the median of --frames frames
 * (after one warm-up frame). Then the speed-up of the last thread count over the first,
 * beside the speed-up of a control: a trivially parallel loop with no memory traffic,
 * run before and after. On a shared machine the control says how much parallelism was
 * actually available; the rasterizer's efficiency is its speed-up over the control's.
 *
 * --plain runs the rasterizer's plain per-pixel path (sl_raster_desc.plain) instead of
 * the span path, to compare the two.
 *
 * --boxes N runs a third workload instead: N tiny boxes (the built-in box, 24 vertices and 12
 * triangles, each about 3 pixels wide) on a square grid filling the frame, each its own draw
 * (as N objects of a scene file): the per-draw cost, not setup or fill. Reported as frame
 * time and microseconds per draw.
 *
 * usage: bench_raster [--threads 1,2] [--tiles 16,32,64,128] [--frames 5] [--size 1920x1080]
 *                     [--slices 1000] [--plain] [--boxes N] */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/timer.h"
#include "raster/raster.h"

#define MAX_LIST 8

static int parse_list(const char *s, int *out)
{
    int n = 0;
    while (*s && n < MAX_LIST) {
        char *end;
        long v = strtol(s, &end, 10);
        if (end == s || v <= 0)
            return 0;
        out[n++] = (int)v;
        s = *end == ',' ? end + 1 : end;
    }
    return n;
}

typedef struct {
    double ms;              /* median frame time */
    sl_raster_stats stats;  /* of one frame */
} result;

/* Median frame time of drawing `scene` with `threads` and `tile`. */
static bool run(const sl_scene *scene, const sl_camera *cam, sl_gbuffer *gb, int threads, int tile, int frames,
                bool plain, result *res)
{
    sl_error err = {0};
    sl_raster *r = sl_raster_create(&(sl_raster_desc){.threads = threads, .tile_size = tile, .plain = plain}, &err);
    sl_raster *rs = sl_raster_create(
        &(sl_raster_desc){.threads = threads, .tile_size = tile, .stats = true, .plain = plain}, &err);
    if (!r || !rs) {
        fprintf(stderr, "bench_raster: %s\n", err.msg);
        return false;
    }
    bool ok = sl_raster_scene(rs, scene, cam, gb, &err); /* warm-up, with counters */
    res->stats = sl_raster_get_stats(rs);
    double *t = calloc((size_t)frames, sizeof *t);
    for (int f = 0; ok && t && f < frames; f++) {
        double t0 = sl_now_seconds();
        ok = sl_raster_scene(r, scene, cam, gb, &err);
        t[f] = (sl_now_seconds() - t0) * 1000.0;
    }
    if (!ok || !t)
        fprintf(stderr, "bench_raster: %s\n", t ? err.msg : "out of memory");
    if (ok && t) {
        res->ms = sl_median(t, frames);
    }
    free(t);
    sl_raster_destroy(r);
    sl_raster_destroy(rs);
    return ok && t;
}

/* The control: milliseconds (median of 3) of a compute-only loop on `threads` threads. */
static double control_ms(int threads)
{
    double t[3];
    for (int rep = 0; rep < 3; rep++) {
        double t0 = sl_now_seconds(), sum = 0.0;
#pragma omp parallel for schedule(static) num_threads(threads) reduction(+ : sum)
        for (long i = 0; i < 100000000L; i++)
            sum += (double)(i & 7) * 1e-9;
        t[rep] = (sl_now_seconds() - t0) * 1000.0 + (sum < 0.0 ? 1.0 : 0.0);
    }
    return sl_median(t, 3);
}

/* --boxes: n boxes of side 2 * 0.004 on a square grid over [-4, 4]^2 at z = 0, seen from
 * above (a scene of many tiny objects), one object and one draw each. */
static int bench_boxes(int n, const int *threads, int nthreads, const int *tiles, int ntiles, int frames, int width,
                       int height, bool plain)
{
    sl_mesh box = {0};
    sl_error err = {0};
    sl_material mat = {.name = "grey", .kd = {0.5f, 0.5f, 0.5f}, .ks = {0.04f, 0.04f, 0.04f}, .alpha = 50.0f};
    sl_object *objs = malloc((size_t)n * sizeof *objs);
    sl_gbuffer gb = {0};
    if (!objs || !sl_mesh_box(&box, &err) || !sl_gbuffer_resize(&gb, width, height, &err)) {
        fprintf(stderr, "bench_raster: %s\n", objs ? err.msg : "out of memory");
        free(objs);
        return 1;
    }
    int side = 1;
    while (side * side < n)
        side++;
    for (int i = 0; i < n; i++) {
        vec3 at = vec3((float)(i % side) / (float)side * 8.0f - 4.0f, (float)(i / side) / (float)side * 8.0f - 4.0f, 0);
        objs[i] = (sl_object){"box", 0, 0, mat4_mul(mat4_translate(at), mat4_scale(vec3s(0.004f)))};
    }
    sl_scene scene = {.meshes = &box, .mesh_count = 1, .materials = &mat, .material_count = 1, .objects = objs,
                      .object_count = n};
    sl_camera cam = {.eye = {0, -0.01f, 9}, .target = {0, 0, 0}, .up = {0, 0, 1}, .fovy_deg = 50,
                     .znear = 0.1f, .zfar = 20};
    printf("bench_raster: %dx%d, %d frames (median), %d boxes (one draw each)%s\n", width, height, frames, n,
           plain ? ", plain path" : "");
    printf("%5s %7s | %9s %9s | %12s\n", "tile", "threads", "boxes ms", "us/draw", "fragments");
    int rc = 0;
    for (int ti = 0; ti < ntiles && rc == 0; ti++) {
        for (int hi = 0; hi < nthreads && rc == 0; hi++) {
            result a;
            if (!run(&scene, &cam, &gb, threads[hi], tiles[ti], frames, plain, &a)) {
                rc = 1;
                break;
            }
            printf("%5d %7d | %9.1f %9.2f | %12lld\n", tiles[ti], threads[hi], a.ms, a.ms * 1e3 / (double)n,
                   a.stats.fragments_tested);
            fflush(stdout);
        }
    }
    sl_gbuffer_free(&gb);
    sl_mesh_free(&box);
    free(objs);
    return rc;
}

int main(int argc, char **argv)
{
    int threads[MAX_LIST] = {1, 2}, nthreads = 2;
    int tiles[MAX_LIST] = {16, 32, 64, 128}, ntiles = 4;
    int frames = 5, width = 1920, height = 1080, slices = 1000, boxes = 0;
    bool plain = false;
    /* options come in pairs: --name value, except --plain */
    for (int i = 1; i < argc; i += 2) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        bool ok = v != NULL;
        if (!strcmp(a, "--plain")) {
            plain = true;
            i--;
            continue;
        }
        if (ok && !strcmp(a, "--threads"))
            ok = (nthreads = parse_list(v, threads)) > 0;
        else if (ok && (!strcmp(a, "--tiles") || !strcmp(a, "--tile")))
            ok = (ntiles = parse_list(v, tiles)) > 0;
        else if (ok && !strcmp(a, "--frames"))
            ok = (frames = atoi(v)) > 0;
        else if (ok && !strcmp(a, "--slices"))
            ok = (slices = atoi(v)) >= 8;
        else if (ok && !strcmp(a, "--size"))
            ok = sscanf(v, "%dx%d", &width, &height) == 2;
        else if (ok && !strcmp(a, "--boxes"))
            ok = (boxes = atoi(v)) > 0;
        else
            ok = false;
        if (!ok) {
            fprintf(stderr, "usage: bench_raster [--threads 1,2] [--tiles 16,32,64,128] [--frames 5] "
                            "[--size 1920x1080] [--slices 1000] [--plain] [--boxes N]\n");
            return 2;
        }
    }
    if (boxes > 0)
        return bench_boxes(boxes, threads, nthreads, tiles, ntiles, frames, width, height, plain);

    /* tris: the sphere, 4 units away, filling about 60% of the frame height */
    sl_mesh sphere = {0};
    sl_error mesh_err;
    if (!sl_mesh_sphere(&sphere, slices, slices / 2, &mesh_err)) {
        fprintf(stderr, "bench_raster: %s\n", mesh_err.msg);
        return 1;
    }
    sl_material mat = {.name = "grey", .kd = {0.5f, 0.5f, 0.5f}, .ks = {0.04f, 0.04f, 0.04f}, .alpha = 50.0f};
    sl_object sphere_obj = {"sphere", 0, 0, mat4_identity()};
    sl_scene tris = {.meshes = &sphere, .mesh_count = 1, .materials = &mat, .material_count = 1,
                     .objects = &sphere_obj, .object_count = 1};
    sl_camera cam = {.eye = {0, -3.2f, 0.3f}, .target = {0, 0, 0}, .up = {0, 0, 1}, .fovy_deg = 45,
                     .znear = 0.1f, .zfar = 20};

    /* fill: quads at y = -1 + 0.2 k (k = 0 nearest) facing the camera, wider than the frustum,
     * drawn as k = 9 7 5 3 1 8 6 4 2 0: the odd layers back to front (all pass), then the
     * even ones (only k = 0 passes in front of k = 1): 6 of 10 fragments pass */
    static vec3 qpos[] = {{-3, 0, -3}, {3, 0, -3}, {3, 0, 3}, {-3, 0, 3}};
    static vec3 qnrm[] = {{0, -1, 0}, {0, -1, 0}, {0, -1, 0}, {0, -1, 0}};
    static uint32_t qidx[] = {0, 1, 2, 0, 2, 3};
    sl_mesh quad = {.vertex_count = 4, .triangle_count = 2, .positions = qpos, .normals = qnrm, .indices = qidx};
    sl_object layers[10];
    for (int i = 0; i < 10; i++) {
        static const int order[10] = {9, 7, 5, 3, 1, 8, 6, 4, 2, 0};
        int k = order[i];
        layers[i] = (sl_object){"layer", 0, 0, mat4_translate(vec3(0, -1.0f + 0.2f * (float)k, 0))};
    }
    sl_scene fill = {.meshes = &quad, .mesh_count = 1, .materials = &mat, .material_count = 1, .objects = layers,
                     .object_count = 10};

    sl_gbuffer gb = {0};
    sl_error err = {0};
    if (!sl_gbuffer_resize(&gb, width, height, &err)) {
        fprintf(stderr, "bench_raster: %s\n", err.msg);
        return 1;
    }
    printf("bench_raster: %dx%d, %d frames (median), sphere %d triangles, fill 10 layers%s\n", width, height, frames,
           sphere.triangle_count, plain ? ", plain path" : "");
    int t_first = threads[0], t_last = threads[nthreads - 1];
    double control_before = control_ms(t_first) / control_ms(t_last);
    printf("%5s %7s | %9s %9s | %9s %10s %8s\n", "tile", "threads", "tris ms", "Mtri/s", "fill ms", "Mfrag/s",
           "passed");
    double best_ms[2][MAX_LIST][MAX_LIST];
    for (int ti = 0; ti < ntiles; ti++) {
        for (int hi = 0; hi < nthreads; hi++) {
            result a, b;
            if (!run(&tris, &cam, &gb, threads[hi], tiles[ti], frames, plain, &a) ||
                !run(&fill, &cam, &gb, threads[hi], tiles[ti], frames, plain, &b))
                return 1;
            best_ms[0][ti][hi] = a.ms;
            best_ms[1][ti][hi] = b.ms;
            printf("%5d %7d | %9.1f %9.2f | %9.1f %10.1f %7.0f%%\n", tiles[ti], threads[hi], a.ms,
                   (double)a.stats.triangles_in / (a.ms * 1e3), b.ms,
                   (double)b.stats.fragments_tested / (b.ms * 1e3),
                   100.0 * (double)b.stats.fragments_shaded / (double)b.stats.fragments_tested);
            fflush(stdout);
        }
    }
    if (nthreads > 1) {
        double control_after = control_ms(t_first) / control_ms(t_last);
        printf("speed-up %d -> %d threads (control loop: %.2fx before, %.2fx after):\n", t_first, t_last,
               control_before, control_after);
        for (int ti = 0; ti < ntiles; ti++)
            printf("  tile %3d: tris %.2fx, fill %.2fx\n", tiles[ti], best_ms[0][ti][0] / best_ms[0][ti][nthreads - 1],
                   best_ms[1][ti][0] / best_ms[1][ti][nthreads - 1]);
    }
    sl_gbuffer_free(&gb);
    sl_mesh_free(&sphere);
    return 0;
}
