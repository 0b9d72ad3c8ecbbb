/* view_refine.c - the viewer's progressive refinement: which stage renders next and rendering it
 * (docs/viewer.md "Refinement"; the contract is in view_internal.h).
 *
 *     moving    1/preview_div of the window per axis (starting at full size), lit with the
 *               split-sum estimator (no samples: the sweep's best error for the time, and a
 *               few ns a pixel; its chains are prefiltered once per environment); with
 *               --move-estimator user, or in the mip view, the user's estimator with
 *               N = min(N, --move-samples), rotated per pixel, a new frame number each frame; whole frames
 *     accumulate full size, frames of min(N, VIEW_ACC_SAMPLES) rotated samples, frame = 0, 1,
 *               2, ..., filtered with the mip levels of N, averaged (sl_lighting_accumulate)
 *               until they hold at least N samples a pixel
 *     exact     full size, the chosen N, the user's options: the frame `softlight render` makes
 *
 * A camera move restarts at the moving stage and stays there while input continues (the preview
 * divisor adapts so a frame, present included, takes at most about TARGET_FRAME_MS); a lighting
 * change keeps the G-buffer and restarts the accumulation; exposure and contrast only re-run the
 * tone map. The accumulation and exact stages are lit in row slices (view_shade.c) so the loop
 * can handle input between them.
 *
 * Why a file of its own: this is the viewer's one state machine, and everything else only asks
 * it questions (converged? interacting?) or tells it to restart. It renders into the viewer's
 * images and never touches the window beyond asking its size; errors go back to the caller,
 * which shows them (cmd_view.c). A stage lights with the user's settings (r.desc) except for N,
 * rotation and frame, which it passes per frame (sl_lighting_frame), so r.desc is never swapped. */
#if SL_HAVE_SDL2
#include <SDL.h>

#include <math.h>

#include "core/timer.h"
#include "view_internal.h"

#define MAX_ACC_FRAMES 64        /* at most this many accumulation frames (N > 512) */
#define TARGET_FRAME_MS 30.0     /* a moving frame, present included: 33 ms is 30 per second */
#define SLICE_SECONDS 0.04       /* one lighting slice between two looks at the input */

static int min_int(int a, int b) { return a < b ? a : b; }

/* ------------------------------------------------------------------ the stages */

/* Accumulation frames the still camera gets before the exact frame: enough for N samples a
 * pixel (ceil(N / VIEW_ACC_SAMPLES)), none when one frame of N is no dearer than one
 * accumulation frame (N <= VIEW_ACC_SAMPLES), and none outside the final view (the others do not
 * light, or, the mip view, show the samples' levels, which averaging would blur). */
int view_acc_target(const viewer *v)
{
    int n = v->r.desc.lighting.samples;
    if (v->mode != VIEW_FINAL || n <= VIEW_ACC_SAMPLES)
        return 0;
    int k = (n + VIEW_ACC_SAMPLES - 1) / VIEW_ACC_SAMPLES;
    return k < MAX_ACC_FRAMES ? k : MAX_ACC_FRAMES;
}

static view_stage_params params_of(const viewer *v, int stage)
{
    const sl_lighting_options *user = &v->r.desc.lighting;
    bool final = v->mode == VIEW_FINAL;
    switch (stage) {
    case VIEW_STAGE_MOVING:
        if (final && !v->move_user) /* N, rotation and frame stay the user's: the split sum ignores them */
            return (view_stage_params){v->preview_div, user->samples, user->rotate, user->frame,
                                       SL_ESTIMATOR_SPLITSUM};
        return (view_stage_params){v->preview_div, min_int(user->samples, v->move_samples), final || user->rotate,
                                   final ? v->move_frame : user->frame, SL_ESTIMATOR_DEFAULT};
    case VIEW_STAGE_ACCUMULATE:
        return (view_stage_params){1, min_int(user->samples, VIEW_ACC_SAMPLES), true, (uint32_t)v->acc_count,
                                   SL_ESTIMATOR_DEFAULT};
    default:
        return (view_stage_params){1, user->samples, user->rotate, user->frame, SL_ESTIMATOR_DEFAULT};
    }
}

/* The estimator a stage lights with, resolved (DEFAULT: the user's). */
static sl_estimator stage_estimator(const viewer *v, view_stage_params p)
{
    if (p.estimator != SL_ESTIMATOR_DEFAULT)
        return p.estimator;
    return sl_lighting_options_resolve(&v->r.desc.lighting).estimator;
}

/* Stages that would render the same image as the one before them are skipped (N, the rotation
 * and the estimator only matter to views that light the G-buffer; a split-sum moving frame at
 * full size is the exact frame when the user's estimator is the split sum). */
static bool same_params(const viewer *v, view_stage_params a, view_stage_params b)
{
    if (a.div != b.div)
        return false;
    if (!view_mode_needs_lighting(v->mode))
        return true;
    return a.samples == b.samples && a.rotate == b.rotate && (!a.rotate || a.frame == b.frame) &&
           stage_estimator(v, a) == stage_estimator(v, b);
}

static bool stage_needed(const viewer *v, int stage)
{
    return stage != VIEW_STAGE_ACCUMULATE || view_acc_target(v) > 0;
}

static int next_stage(const viewer *v, int stage)
{
    view_stage_params p = params_of(v, stage);
    int next = stage + 1;
    while (next < VIEW_STAGE_COUNT && (!stage_needed(v, next) || same_params(v, params_of(v, next), p)))
        next++;
    return next;
}

/* The stage that follows a finished one: another accumulation frame until there are enough. */
static int stage_after(const viewer *v, int stage)
{
    if (stage == VIEW_STAGE_ACCUMULATE && v->acc_count < view_acc_target(v))
        return VIEW_STAGE_ACCUMULATE;
    return next_stage(v, stage);
}

void view_restart_camera(viewer *v)
{
    v->gl.frame_changed = true;
    v->stage = VIEW_STAGE_MOVING;
    v->urgent = true;
    v->raster_valid = false;
    v->radiance_exact = false;
    v->job_active = false;
    v->acc_count = 0;
}

void view_restart_lighting(viewer *v)
{
    v->gl.frame_changed = true;
    if (v->stage > VIEW_STAGE_ACCUMULATE)
        v->stage = VIEW_STAGE_ACCUMULATE;
    if (v->stage == VIEW_STAGE_ACCUMULATE && !stage_needed(v, VIEW_STAGE_ACCUMULATE))
        v->stage = VIEW_STAGE_EXACT;
    v->urgent = true;
    v->radiance_exact = false;
    v->job_active = false;
    v->acc_count = 0;
}

bool view_converged(const viewer *v) { return v->stage >= VIEW_STAGE_COUNT && !v->urgent && !v->job_active; }

bool view_interacting(const viewer *v, double now)
{
    if (v->drag_button || now - v->last_input < VIEW_QUIET_SECONDS || v->bench.frames > 0)
        return true;
    for (int i = 0; i < VIEW_NAV_COUNT; i++)
        if (v->held[i])
            return true;
    return false;
}

/* ------------------------------------------------------------------ sizes */

void view_output_size(const viewer *v, int *w, int *h)
{
    *w = *h = 0;
    if (SDL_GetRendererOutputSize(v->sdl, w, h) != 0 || *w < 1 || *h < 1)
        SDL_GetWindowSize(v->window, w, h);
    if (*w < 1)
        *w = 1;
    if (*h < 1)
        *h = 1;
}

static int scaled(int size, float scale, int div)
{
    int s = (int)lroundf((float)size * scale / (float)div);
    return s < 1 ? 1 : (s > SL_RASTER_MAX_SIZE ? SL_RASTER_MAX_SIZE : s);
}

void view_render_size(const viewer *v, int div, int *w, int *h)
{
    int ow, oh;
    view_output_size(v, &ow, &oh);
    *w = scaled(ow, v->scale, div);
    *h = scaled(oh, v->scale, div);
}

/* ------------------------------------------------------------------ rendering a stage */

static void stage_finished(viewer *v)
{
    v->job_active = false;
    v->shown_params = v->job_params;
    v->shown_stage = v->job_stage;
    v->texture_stale = true;
    v->present_needed = true;
    /* Whatever stage made it, a frame lit with the exact stage's settings is the exact frame. */
    if (v->shown_from == VIEW_SHOWN_RADIANCE && v->job_params.div == 1 &&
        same_params(v, v->job_params, params_of(v, VIEW_STAGE_EXACT)))
        v->radiance_exact = true;
}

/* Tone map a linear image into `shown` (re-allocated when the size changed). */
static bool tonemap_shown(viewer *v, const sl_image *linear, sl_error *err)
{
    if (v->shown.data && (v->shown.width != linear->width || v->shown.height != linear->height))
        sl_image_free(&v->shown);
    v->shown_pending = false;
    double t0 = sl_now_seconds();
    if (!sl_tonemap_image(linear, &v->shown, &v->r.desc.tonemap, v->r.desc.threads, err))
        return false;
    v->tonemap_ms = (sl_now_seconds() - t0) * 1e3;
    v->texture_stale = true;
    return true;
}

/* Where a stage's lighting pass writes: its own frame for the accumulation, else the renderer's
 * radiance (what `softlight render` tone maps and writes). */
static sl_image *job_target(viewer *v)
{
    return v->job_stage == VIEW_STAGE_ACCUMULATE ? &v->acc_frame : &v->r.radiance;
}

/* The lit frame in r.radiance goes to the window: its tone map is made in one pass into the
 * window's texture at the next present (view_present.c), `shown` only when a reader needs it. The
 * table is built here, so bad tone map settings fail here as sl_renderer_tonemap would. (A
 * moving frame's rows went into the texture as they were lit: stage_continue.) */
static bool show_radiance(viewer *v, sl_error *err)
{
    if (!sl_renderer_tonemap_table(&v->r, err))
        return false;
    v->shown_pending = true;
    v->texture_stale = true;
    v->tonemap_ms = 0.0; /* the present measures the tone map */
    v->shown_from = VIEW_SHOWN_RADIANCE;
    return true;
}

/* Start a refinement stage: size, raster, then either the whole image (G-buffer views and the
 * mip view) or the first step of a sliced lighting pass (the final image). */
static bool stage_begin(viewer *v, int stage, sl_error *err)
{
    view_stage_params p = params_of(v, stage);
    /* What the window shows must not lose r.radiance behind it: a moving frame replaces it whole
     * (its radiance is of no use to anyone then); the other stages make it first (once a
     * settle: the exact stage tone maps its rows over it, and all may resize r.radiance). */
    if (stage == VIEW_STAGE_MOVING)
        v->shown_pending = false;
    else if (!view_shown_make(v, err))
        return false;
    int w, h;
    view_render_size(v, p.div, &w, &h);
    v->job_active = false;
    v->job_stage = stage;
    v->job_params = p;
    if (v->r.gbuffer.width != w || v->r.gbuffer.height != h) {
        if (!sl_renderer_resize(&v->r, w, h, err))
            return false;
        v->raster_valid = false;
    }
    const sl_camera *cam = &v->camera.cam;
    if (stage != VIEW_STAGE_ACCUMULATE || v->acc_count == 0)
        v->shade_ms = v->tonemap_ms = 0.0; /* between accumulation frames the HUD keeps the last one's */
    if (!v->raster_valid) {
        if (!sl_renderer_raster(&v->r, cam, err))
            return false;
        v->raster_valid = true;
        v->raster_ms = v->r.timings.raster_ms;
    }
    /* The stage's N, rotation and frame go into the uniforms through a per-frame override;
     * r.desc keeps the user's settings. An accumulation frame reads the mip levels of the user's
     * N (lod_samples: uLodBase = 1/2 log2(W H / N), the only place N enters the level), so that
     * the mean converges to the exact frame's filtering rather than to that of 8 samples
     * (docs/viewer.md "Refinement"). */
    if (v->mode == VIEW_FINAL || v->mode == VIEW_MIP) {
        sl_lighting_frame f = {.samples = p.samples, .rotate = p.rotate, .frame = p.frame, .estimator = p.estimator};
        if (stage == VIEW_STAGE_ACCUMULATE && v->acc_total_lod)
            f.lod_samples = sl_lighting_options_resolve(&v->r.desc.lighting).lod_samples;
        if (!sl_renderer_prepare_lighting_frame(&v->r, cam, &f, err))
            return false;
    }
    double t0 = sl_now_seconds();
    switch (v->mode) {
    case VIEW_FINAL:
        if (stage == VIEW_STAGE_ACCUMULATE && (v->acc_frame.width != w || v->acc_frame.height != h)) {
            sl_image_free(&v->acc_frame);
            if (!sl_image_alloc(&v->acc_frame, w, h, 3, err))
                return false;
        }
        if (stage == VIEW_STAGE_ACCUMULATE && v->acc_count == 0)
            v->acc_ms = 0.0;
        if (!view_shade_begin(&v->shade, v->r.uniforms, &v->r.gbuffer, v->r.desc.threads,
                              stage == VIEW_STAGE_ACCUMULATE && v->acc_count > 0, err))
            return false;
        v->job_active = true;
        return true;
    case VIEW_MIP:
        if (!view_mip_image(v->r.uniforms, &v->r.gbuffer, &v->shown, &v->mip_max_seen, err))
            return false;
        break;
    default:
        if (!view_channel_image(&v->r.gbuffer, v->mode, v->bounds_lo, v->bounds_hi, cam->znear, cam->zfar, &v->shown,
                                v->depth_range, err))
            return false;
        break;
    }
    v->shade_ms = (sl_now_seconds() - t0) * 1e3;
    v->shown_from = VIEW_SHOWN_NONE;
    stage_finished(v);
    return true;
}

/* One slice of the active stage's lighting pass. The exact stage's rows replace the old ones on
 * screen as they come (tone mapped like the whole image will be) while the image on screen has
 * its size; an accumulation frame is folded into the mean and shown when it is complete. */
static bool stage_continue(viewer *v, double budget_s, sl_error *err)
{
    int first;
    sl_image *target = job_target(v);
    /* A moving frame of the final view is lit whole: each row is tone mapped into the window's
     * texture right after it is lit, while it is in cache (a pass of its own read the 11 MB
     * frame back from memory), and the present only copies the texture. Where the texture
     * cannot be locked, the present tone maps the frame instead. */
    bool direct = false;
    if (v->job_stage == VIEW_STAGE_MOVING && v->mode == VIEW_FINAL && isinf(budget_s)) {
        const sl_tonemap_table *tab = sl_renderer_tonemap_table(&v->r, err);
        if (!tab)
            return false;
        sl_error lock_err = {0}; /* no texture: the present tone maps the frame, and reports why */
        direct = view_texture_lock(v, target->width, target->height, &v->shade.display, &v->shade.display_pitch,
                                   &lock_err);
        v->shade.display_tab = tab;
    }
    bool done = view_shade_slice(&v->shade, v->r.uniforms, &v->r.gbuffer, target, budget_s, &first);
    if (direct) {
        view_texture_unlock(v);
        v->shade.display = NULL;
    }
    if (v->job_stage != VIEW_STAGE_ACCUMULATE || done || v->acc_count == 0)
        v->shade_ms = v->shade.seconds * 1e3;
    if (!done) {
        if (v->job_stage == VIEW_STAGE_EXACT && v->shown.data && v->shown.width == target->width &&
            v->shown.height == target->height) {
            const sl_tonemap_options *t = &v->r.desc.tonemap;
            for (int y = first; y < v->shade.next_row; y++) {
                const float *src = sl_image_pixel(target, 0, y);
                float *dst = sl_image_pixel(&v->shown, 0, y);
                for (int i = 0; i < target->width * 3; i++)
                    dst[i] = sl_tonemap_value(src[i], t->exposure, t->contrast, t->exact_srgb);
            }
            v->texture_stale = true;
            v->present_needed = true;
        }
        return true;
    }
    v->job_active = false;
    v->shown_nonfinite = view_shade_nonfinite(&v->shade);
    v->frame_lit = true;
    if (v->job_stage == VIEW_STAGE_ACCUMULATE) {
        if (v->acc_count == 0 && v->mean.data &&
            (v->mean.width != target->width || v->mean.height != target->height))
            sl_image_free(&v->mean);
        if (!sl_lighting_accumulate(&v->mean, target, v->acc_count, err) || !tonemap_shown(v, &v->mean, err))
            return false;
        v->acc_count++;
        v->acc_ms += v->shade_ms;
        v->shown_from = VIEW_SHOWN_MEAN;
    } else if (!show_radiance(v, err)) {
        return false;
    }
    v->retonemap = false; /* the tone map just ran with the current settings */
    stage_finished(v);
    if (direct)
        v->texture_stale = false; /* the rows are in the texture already */
    return true;
}

/* A whole stage at once (the moving stage, and screenshots). */
static bool render_stage(viewer *v, int stage, sl_error *err)
{
    if (!stage_begin(v, stage, err))
        return false;
    while (v->job_active)
        if (!stage_continue(v, (double)INFINITY, err))
            return false;
    return true;
}

/* ------------------------------------------------------------------ what the loop calls */

bool view_refine_wanted(const viewer *v, double now)
{
    bool minimized = (SDL_GetWindowFlags(v->window) & SDL_WINDOW_MINIMIZED) != 0;
    return !minimized && !v->job_active && v->stage < VIEW_STAGE_COUNT && (v->urgent || !view_interacting(v, now));
}

bool view_refine_start(viewer *v, sl_error *err)
{
    int stage = v->stage;
    v->urgent = false;
    /* A moving frame is small by design and always finishes; later stages are sliced. */
    bool ok = stage == VIEW_STAGE_MOVING ? render_stage(v, stage, err) : stage_begin(v, stage, err);
    if (ok && !v->job_active)
        v->stage = stage_after(v, stage);
    return ok;
}

bool view_refine_continue(viewer *v, sl_error *err)
{
    int stage = v->job_stage;
    if (!stage_continue(v, SLICE_SECONDS, err))
        return false;
    if (!v->job_active)
        v->stage = stage_after(v, stage);
    return true;
}

/* The moving stage's divisor follows the cost of a whole moving frame (raster, lighting, tone
 * map, present), smoothed over frames so that one slow frame on a loaded machine does not halve
 * the resolution: above TARGET_FRAME_MS by a quarter the divisor doubles; it halves when four
 * times the cost (the pixels of half the divisor) would still be well inside the target. */
void view_refine_moved(viewer *v, double frame_ms)
{
    v->move_frame++;
    if (v->preview_ms <= 0.0) {
        v->preview_ms = frame_ms; /* the first frame also sets up buffers: only a starting point */
        return;
    }
    v->preview_ms = 0.7 * v->preview_ms + 0.3 * frame_ms;
    if (v->fixed_div)
        return;
    if (v->preview_ms > TARGET_FRAME_MS * 1.25 && v->preview_div < VIEW_MAX_PREVIEW_DIV) {
        v->preview_div *= 2;
        v->preview_ms /= 4.0;
    } else if (v->preview_ms * 4.0 < TARGET_FRAME_MS * 0.75 && v->preview_div > 1) {
        v->preview_div /= 2;
        v->preview_ms *= 4.0;
    }
}

void view_refine_stop(viewer *v)
{
    v->job_active = false;
    v->stage = VIEW_STAGE_COUNT; /* nothing to gain from retrying the same failure */
    v->urgent = false;
}

bool view_refine_finish(viewer *v, sl_error *err)
{
    /* Straight to the exact frame: the accumulation is a preview of it. */
    if (!render_stage(v, VIEW_STAGE_EXACT, err))
        return false;
    v->stage = VIEW_STAGE_COUNT;
    v->urgent = false;
    return true;
}

bool view_refine_retonemap(viewer *v, sl_error *err)
{
    v->retonemap = false;
    if (v->mode == VIEW_FINAL && v->shown_from == VIEW_SHOWN_RADIANCE) {
        return show_radiance(v, err);
    } else if (v->mode == VIEW_FINAL && v->shown_from == VIEW_SHOWN_MEAN) {
        return tonemap_shown(v, &v->mean, err);
    }
    return true;
}

#else
typedef int view_refine_unused; /* this file is only built with SDL2 */
#endif
