/* view_shade.c - the viewer's lighting pass, in slices (see view_internal.h).
 *
 * Why not sl_lighting_pass: a full-size frame at the scene's N takes a good part of a second on
 * a small machine, and one call would freeze the window for that long. Slicing by rows keeps
 * each call near a time budget; the loop handles input in between and shows the rows already
 * refined. Each row goes through sl_lighting_shade_row, the pass's own unit of work (same bits;
 * it vectorizes the per-pixel part over the row: 1.1-1.4x faster than a call of
 * sl_lighting_shade per pixel, docs/performance.md "Viewer"). Inside a slice the
 * rows are shared between threads (OpenMP, dynamic schedule) in bands of 4, as the library's pass
 * shares them;
 * each pixel depends only on its texel, the read-only uniforms and the planes the job fills when
 * it begins (sl_lighting_planes, as the pass fills its own), so the result is identical for any
 * thread count and slicing. */
#include "view_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>

#include "core/timer.h"

enum { BAND_ROWS = 4 }; /* rows a chunk of the parallel loop, as sl_lighting_pass's bands */

bool view_shade_begin(view_shade_job *job, const sl_lighting_uniforms *u, const sl_gbuffer *gb, int threads,
                      bool same_cost, sl_error *err)
{
    int n = threads > 0 ? threads : omp_get_max_threads();
    if (job->tasks && job->thread_count != n)
        view_shade_free(job);
    if (!job->tasks) {
        job->tasks = calloc((size_t)n, sizeof *job->tasks);
        if (!job->tasks)
            return sl_fail(err, SL_ERR_MEMORY, "view: out of memory for lighting tasks");
        job->thread_count = n;
        for (int i = 0; i < n; i++)
            if (!(job->tasks[i] = sl_lighting_task_create(err))) {
                view_shade_free(job);
                return false;
            }
    }
    /* The uniforms were re-initialised in place: cached sample tables are stale. */
    for (int i = 0; i < n; i++)
        sl_lighting_task_reset(job->tasks[i]);
    if (!sl_lighting_planes_prepare(&job->planes, u, gb, n, err))
        return false;
    for (int i = 0; i < n; i++)
        sl_lighting_task_use_planes(job->tasks[i], &job->planes);
    job->next_row = 0;
    job->seconds = 0.0;
    job->nonfinite_base = 0;
    job->nonfinite_base = view_shade_nonfinite(job);
    if (!same_cost) {
        job->row_seconds = 0.0; /* N and the size may differ from the last job: measure again */
        job->last_rows = 0;
    }
    return true;
}

bool view_shade_slice(view_shade_job *job, const sl_lighting_uniforms *u, const sl_gbuffer *gb, sl_image *out,
                      double budget_s, int *first_row)
{
    const int height = gb->height, width = gb->width;
    int y0 = job->next_row;
    /* Rows differ a lot in cost (sky rows are cheap, glossy ones are not): the slice grows at
     * most twofold from one call to the next, so a run of cheap rows cannot promise a long
     * expensive slice. */
    const int least = 2 * job->thread_count; /* fewer rows would leave threads idle */
    int rows = least;
    if (isinf(budget_s)) { /* no budget (a whole stage at once): one parallel region, no slices */
        rows = height - y0;
    } else if (job->row_seconds > 0.0) {
        double fit = budget_s / job->row_seconds;
        rows = fit < 2.0 * job->last_rows ? (int)fit : 2 * job->last_rows;
    }
    if (rows < least)
        rows = least;
    if (rows > height - y0)
        rows = height - y0;
    const int y1 = y0 + rows;
    /* The slice's rows in bands of BAND_ROWS in the G-buffer's address order (its row 0 is the
     * image's bottom), as sl_lighting_pass takes them: image rows top first, one a chunk, cost
     * about 5% more CPU time on pbr.json's split sum (docs/performance.md "Viewer"). */
    const int g0 = height - y1, g1 = height - y0; /* the slice's G-buffer rows [g0, g1) */
    const int bands = (g1 - g0 + BAND_ROWS - 1) / BAND_ROWS;
    double t0 = sl_now_seconds();
#pragma omp parallel num_threads(job->thread_count)
    {
        int t = omp_get_thread_num();
        sl_lighting_task *task = job->tasks[t];
#pragma omp for schedule(dynamic)
        for (int band = 0; band < bands; band++) {
            const int ga = g0 + band * BAND_ROWS, gz = ga + BAND_ROWS < g1 ? ga + BAND_ROWS : g1;
            for (int gy = ga; gy < gz; gy++) {
                const int y = height - 1 - gy; /* the image's row */
                /* the image's row is the row's vec3s (three floats each): shaded in place, as the
                 * library's pass does */
                vec3 *row = (vec3 *)(void *)sl_image_pixel(out, 0, y);
                sl_lighting_shade_row(u, gb, 0, gy, width, task, row);
                if (job->display) /* the moving frame: its row into the window's texture */
                    sl_tonemap_row_xrgb8888(job->display_tab, &row[0].x, width,
                                            (uint32_t *)(void *)(job->display + (size_t)y * job->display_pitch));
            }
        }
    }
    double dt = sl_now_seconds() - t0;
    job->seconds += dt;
    job->row_seconds = dt / rows;
    job->last_rows = rows;
    job->next_row = y1;
    if (first_row)
        *first_row = y0;
    return y1 >= height;
}

int64_t view_shade_nonfinite(const view_shade_job *job)
{
    sl_lighting_stats stats = {0};
    for (int i = 0; job->tasks && i < job->thread_count; i++)
        sl_lighting_task_stats(job->tasks[i], &stats);
    return stats.nonfinite - job->nonfinite_base;
}

void view_shade_free(view_shade_job *job)
{
    for (int i = 0; job->tasks && i < job->thread_count; i++)
        sl_lighting_task_destroy(job->tasks[i]);
    free(job->tasks);
    job->tasks = NULL;
    job->thread_count = 0;
    sl_lighting_planes_free(&job->planes);
}
