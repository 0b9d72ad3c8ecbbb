/* lighting_pass.c - runs the frame's lighting program (softlight/lighting.h) over a G-buffer:
 * the built-in's dispatch between the port (lighting.c, options.plain), the batched path
 * (lighting_batched.c) and the split-sum fast path (lighting_splitsum.c, for --estimator
 * splitsum), another program's forms with its NaN/Inf made loud and counted, the planes the
 * batched paths read from the whole G-buffer (sl_lighting_planes: the sky maps' V), the pass
 * (OpenMP over bands of whole rows, one task per thread), and the accumulation of rotated frames. */

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "lighting_internal.h"

/* The built-in program's dispatch: the port or the batched path, as options.plain says (the
 * split sum's own fast path where it runs); both count into the task. */
vec3 sl_lighting_builtin_texel(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y,
                               sl_lighting_task *task, sl_lighting_trace *trace)
{
    if (u->options.plain)
        return sl_shade_plain(u, gb, x, y, task, trace);
    vec3 c;
    if (sl_shade_splitsum_fast(u) && !gb->cone && !gb->reflection)
        sl_shade_span_splitsum(u, gb, x, y, 1, task, trace, &c);
    else
        sl_shade_span(u, gb, x, y, 1, task, trace, &c);
    return c;
}

void sl_lighting_builtin_row(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                             sl_lighting_task *task, vec3 *out)
{
    /* the split sum's own path has no visibility cone or reflection occlusion: with either, the
     * batched path runs the split sum */
    const bool splitsum = sl_shade_splitsum_fast(u) && !gb->cone && !gb->reflection;
    for (int x = x0; x < x0 + count; x += SPAN) {
        int n = x0 + count - x < SPAN ? x0 + count - x : SPAN;
        if (u->options.plain)
            for (int i = 0; i < n; i++)
                out[x - x0 + i] = sl_shade_plain(u, gb, x + i, y, task, NULL);
        else if (splitsum)
            sl_shade_span_splitsum(u, gb, x, y, n, task, NULL, out + (x - x0));
        else
            sl_shade_span(u, gb, x, y, n, task, NULL, out + (x - x0));
    }
}

/* Another program's NaN or Inf becomes SL_LIGHTING_NONFINITE, counted (the built-in repairs its
 * own to 0 in sl_shade_finish). */
static vec3 guard_nonfinite(vec3 c, sl_lighting_task *task)
{
    if (isfinite(c.x) && isfinite(c.y) && isfinite(c.z))
        return c;
    if (task)
        task->stats.nonfinite++;
    return SL_LIGHTING_NONFINITE;
}

/* The frame's program, per texel (a trace records the texel and the result; the built-in
 * records everything it computes). */
vec3 sl_lighting_shade(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y,
                       sl_lighting_task *task, sl_lighting_trace *trace)
{
    if (!u->program)
        return sl_lighting_builtin_texel(u, gb, x, y, task, trace);
    const sl_lighting_resources res = {u, gb, task, trace};
    const sl_lighting_texel_in in = {sl_gbuffer_at(gb, x, y), shade_extra(gb, x, y), x, y};
    vec3 raw = u->program->shade(&u->frame, &res, &in);
    vec3 c = guard_nonfinite(raw, task);
    if (trace) {
        trace_texel(trace, in.texel, vec2((float)x + 0.5f, (float)y + 0.5f), false);
        trace->program = u->program->name ? u->program->name : "(unnamed)";
        trace->program_result = raw;
        trace->extra_texel = in.extra;
        trace->repaired = !(raw.x == c.x && raw.y == c.y && raw.z == c.z);
        trace->total = c;
    }
    return c;
}

/* The frame's program over a row: its span form, or its per-texel form per texel. */
void sl_lighting_shade_row(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                           sl_lighting_task *task, vec3 *out)
{
    const sl_lighting_program *p = u->program;
    if (!p) {
        sl_lighting_builtin_row(u, gb, x0, y, count, task, out);
        return;
    }
    const sl_lighting_resources res = {u, gb, task, NULL};
    const size_t row = (size_t)y * (size_t)gb->width + (size_t)x0;
    if (p->shade_span) {
        const sl_lighting_span span = {x0, y, count, gb->texels + row, gb->extra ? gb->extra + row : NULL};
        p->shade_span(&u->frame, &res, &span, out);
    } else {
        for (int i = 0; i < count; i++) {
            const sl_lighting_texel_in in = {gb->texels + row + i, shade_extra(gb, x0 + i, y), x0 + i, y};
            out[i] = p->shade(&u->frame, &res, &in);
        }
    }
    for (int i = 0; i < count; i++)
        out[i] = guard_nonfinite(out[i], task);
}

bool sl_lighting_planes_prepare(sl_lighting_planes *planes, const sl_lighting_uniforms *u, const sl_gbuffer *gb,
                                int threads, sl_error *err)
{
    /* the built-in's batched paths only: the port looks V up per pixel, another program as it likes */
    if (u->program || u->options.plain || !u->skyMaps || u->uDiffuse == 0) {
        free(planes->sky);
        *planes = (sl_lighting_planes){0};
        return true;
    }
    size_t need = (size_t)gb->width * (size_t)gb->height;
    if (planes->capacity < need) {
        float *grown = realloc(planes->sky, need * sizeof *grown);
        if (!grown)
            return sl_fail(err, SL_ERR_MEMORY, "lighting: no memory for the sky maps' plane (%dx%d)", gb->width,
                           gb->height);
        planes->sky = grown;
        planes->capacity = need;
    }
    sl_sky_plane_fill(u, gb, planes->sky, SL_SKY_PLANE_AGREE, threads > 0 ? threads : omp_get_max_threads());
    return true;
}

void sl_lighting_planes_free(sl_lighting_planes *planes)
{
    free(planes->sky);
    *planes = (sl_lighting_planes){0};
}

/* A band is BAND_ROWS whole rows: the G-buffer and the image are read and written in address
 * order, which the hardware prefetcher follows (32x32 tiles jumped to a new page every 32
 * texels, and the split sum spent a fifth of its time waiting for its first G-buffer read). */
enum { BAND_ROWS = 4 };

bool sl_lighting_pass(const sl_lighting_uniforms *u, sl_lighting_stats *stats, const sl_gbuffer *gb,
                      sl_image *out, int threads, sl_error *err)
{
    return sl_lighting_pass_hooked(u, stats, gb, out, threads, NULL, err);
}

bool sl_lighting_pass_hooked(const sl_lighting_uniforms *u, sl_lighting_stats *stats, const sl_gbuffer *gb,
                             sl_image *out, int threads, const sl_lighting_band_hook *hook, sl_error *err)
{
    if (!gb || !gb->texels || gb->width < 1 || gb->height < 1)
        return sl_fail(err, SL_ERR_RANGE, "lighting pass: empty G-buffer");
    if ((int)u->uViewport.x != gb->width || (int)u->uViewport.y != gb->height)
        return sl_fail(err, SL_ERR_RANGE, "lighting pass: uniforms are for %dx%d, the G-buffer is %dx%d",
                       (int)u->uViewport.x, (int)u->uViewport.y, gb->width, gb->height);
    if (out->data) {
        if (out->width != gb->width || out->height != gb->height || out->channels != 3)
            return sl_fail(err, SL_ERR_RANGE, "lighting pass: output is %dx%dx%d, expected %dx%dx3", out->width,
                           out->height, out->channels, gb->width, gb->height);
    } else if (!sl_image_alloc(out, gb->width, gb->height, 3, err)) {
        return false;
    }
    int nthreads = threads > 0 ? threads : omp_get_max_threads();
    sl_lighting_task **tasks = calloc((size_t)nthreads, sizeof *tasks);
    if (!tasks)
        return sl_fail(err, SL_ERR_MEMORY, "lighting pass: no memory");
    for (int i = 0; i < nthreads; i++) {
        tasks[i] = sl_lighting_task_create(err);
        if (!tasks[i]) {
            for (int j = 0; j < i; j++)
                sl_lighting_task_destroy(tasks[j]);
            free(tasks);
            return false;
        }
    }
    sl_lighting_planes planes = {0};
    if (!sl_lighting_planes_prepare(&planes, u, gb, nthreads, err)) {
        for (int i = 0; i < nthreads; i++)
            sl_lighting_task_destroy(tasks[i]);
        free(tasks);
        return false;
    }
    for (int i = 0; i < nthreads; i++)
        sl_lighting_task_use_planes(tasks[i], &planes);
    const int band_count = (gb->height + BAND_ROWS - 1) / BAND_ROWS;
    /* Each band writes only its own pixels; each pixel's value depends on nothing but its
     * texel, the read-only uniforms and the planes filled before the bands, so the image does
     * not depend on the thread count. */
#pragma omp parallel num_threads(nthreads)
    {
        sl_lighting_task *task = tasks[omp_get_thread_num()];
#pragma omp for schedule(dynamic)
        for (int band = 0; band < band_count; band++) {
            int y0 = band * BAND_ROWS;
            int y1 = y0 + BAND_ROWS < gb->height ? y0 + BAND_ROWS : gb->height;
            for (int y = y0; y < y1; y++) {
                /* the image's row is the row's vec3s (three floats each): shaded in place */
                vec3 *row = (vec3 *)(void *)sl_image_pixel(out, 0, gb->height - 1 - y); /* row 0 = top */
                sl_lighting_shade_row(u, gb, 0, y, gb->width, task, row);
            }
            task->stats.pixels += (int64_t)gb->width * (y1 - y0);
            if (hook) /* the band's image rows: row 0 = top */
                hook->run(hook->ctx, omp_get_thread_num(), gb->height - y1, gb->height - y0);
        }
    }
    if (stats)
        memset(stats, 0, sizeof *stats);
    for (int i = 0; i < nthreads; i++) {
        if (stats)
            sl_lighting_task_stats(tasks[i], stats);
        sl_lighting_task_destroy(tasks[i]);
    }
    free(tasks);
    sl_lighting_planes_free(&planes);
    return true;
}

bool sl_lighting_accumulate(sl_image *mean, const sl_image *frame, int index, sl_error *err)
{
    if (!frame || !frame->data || index < 0)
        return sl_fail(err, SL_ERR_RANGE, "accumulate: no frame, or frame index %d < 0", index);
    if (index == 0 && !mean->data && !sl_image_alloc(mean, frame->width, frame->height, frame->channels, err))
        return false;
    if (!mean->data || mean->width != frame->width || mean->height != frame->height ||
        mean->channels != frame->channels)
        return sl_fail(err, SL_ERR_RANGE, "accumulate: frame %d is %dx%dx%d, the mean %dx%dx%d", index, frame->width,
                       frame->height, frame->channels, mean->width, mean->height, mean->channels);
    size_t count = (size_t)frame->width * (size_t)frame->height * (size_t)frame->channels;
    float *m = mean->data;
    const float *f = frame->data;
    if (index == 0) {
        memcpy(m, f, count * sizeof *m);
        return true;
    }
    /* The running mean: after frame k it is the mean of frames 0..k to float rounding, and it
     * never needs more than one image of memory. */
    float w = 1.0f / (float)(index + 1);
    for (size_t i = 0; i < count; i++)
        m[i] += (f[i] - m[i]) * w;
    return true;
}

