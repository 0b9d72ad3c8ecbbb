/* cmd_view.c - `softlight view scene.json`: the interactive SDL2 viewer.
 *
 * One thread runs the loop: script commands -> SDL events -> at most one render step ->
 * present. The pipeline itself is parallel (OpenMP inside raster and shading), so the loop
 * stays simple and every finished frame is the one `softlight render` would make for that camera.
 *
 * Refinement (docs/viewer.md "Refinement"):
 *     moving    1/preview_div of the window per axis, N = min(N, --move-samples), the sample
 *               set rotated per pixel with a new frame number each frame; whole frames
 *     accumulate full size, frames of min(N, ACC_SAMPLES) rotated samples, frame = 0, 1, 2, ...,
 *               filtered with the mip levels of N, averaged (sl_lighting_accumulate) until they
 *               hold at least N samples a pixel
 *     exact     full size, the chosen N, the user's options: the frame `softlight render` makes
 * A camera move restarts at the moving stage and stays there while input continues (the preview
 * divisor adapts so a frame, present included, takes at most about TARGET_FRAME_MS); a lighting
 * change keeps the G-buffer and restarts the accumulation; exposure and contrast only re-run the
 * tone map. The accumulation and exact stages are lit in row slices so input stays live.
 *
 * Files: view_input.c (keys, mouse, drops), view_camera.c (orbit camera), view_image.c
 * (G-buffer and mip views), view_shade.c (sliced lighting), view_script.c (--script),
 * view_hud.c (text); the state they share is in view_internal.h. Without SDL2 the command
 * prints one line and exits 2. */
#if SL_HAVE_SDL2
#include <SDL.h>
#endif

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "app/args.h"
#include "app/commands.h"
#include "app/render_options.h"
#include "core/timer.h"
#include "view_internal.h"

#if !SL_HAVE_SDL2

int cmd_view(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "softlight view: built without SDL2 (install libsdl2-dev and libsdl2-ttf-dev and rebuild); "
                    "use softlight render scene.json -o out.png\n");
    return 2;
}

#else

#define DEFAULT_FONT "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf"
#define FONT_POINTS 12
enum { STAGE_MOVING, STAGE_ACCUMULATE, STAGE_EXACT, STAGE_COUNT };
#define MOVE_SAMPLES 8          /* default N while moving (docs/viewer.md "Moving": measured) */
#define ACC_SAMPLES 8           /* N of one accumulation frame */
#define MAX_ACC_FRAMES 64       /* at most this many accumulation frames (N > 512) */
#define QUIET_SECONDS 0.15      /* input this recent still counts as "moving" */
#define TARGET_FRAME_MS 30.0    /* a moving frame, present included: 33 ms is 30 per second */
#define BENCH_WARMUP 5          /* --benchmark: frames not counted (first raster, texture setup) */
#define BENCH_ORBIT_PIXELS 3    /* --benchmark: a drag of this many pixels a frame */
#define MESSAGE_SECONDS 6.0
#define SLICE_SECONDS 0.04      /* one lighting slice between two looks at the input */
#define PRESENT_IDLE_SECONDS 0.1 /* between slices that changed no pixel, present this often */
#define VIEW_OPTION_COUNT 9      /* options of `view` beside render's */
#define HUD_SLOTS 0
#define HELP_SLOTS VIEW_HUD_MAX_LINES

/* ------------------------------------------------------------------ messages */

void view_message(viewer *v, bool error, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(v->message, sizeof v->message, fmt, ap);
    va_end(ap);
    if (error)
        fprintf(stderr, "softlight view: %s\n", v->message);
    v->message_until = sl_now_seconds() + MESSAGE_SECONDS;
    v->present_needed = true;
}

/* ------------------------------------------------------------------ refinement */

static int min_int(int a, int b) { return a < b ? a : b; }

/* Accumulation frames the still camera gets before the exact frame: enough for N samples a
 * pixel (ceil(N / ACC_SAMPLES)), none when one frame of N is no dearer than one accumulation
 * frame (N <= ACC_SAMPLES), and none outside the final view (the others do not light, or, the
 * mip view, show the samples' levels, which averaging would blur). */
static int acc_target(const viewer *v)
{
    if (v->mode != VIEW_FINAL || v->samples <= ACC_SAMPLES)
        return 0;
    int k = (v->samples + ACC_SAMPLES - 1) / ACC_SAMPLES;
    return k < MAX_ACC_FRAMES ? k : MAX_ACC_FRAMES;
}

static view_stage_params params_of(const viewer *v, int stage)
{
    bool final = v->mode == VIEW_FINAL;
    switch (stage) {
    case STAGE_MOVING:
        return (view_stage_params){v->preview_div, min_int(v->samples, v->move_samples), final || v->rotate,
                                   final ? v->move_frame : v->frame};
    case STAGE_ACCUMULATE:
        return (view_stage_params){1, min_int(v->samples, ACC_SAMPLES), true, (uint32_t)v->acc_count};
    default:
        return (view_stage_params){1, v->samples, v->rotate, v->frame};
    }
}

/* Stages that would render the same image as the one before them are skipped (N and the
 * rotation only matter to views that light the G-buffer). */
static bool same_params(const viewer *v, view_stage_params a, view_stage_params b)
{
    if (a.div != b.div)
        return false;
    if (!view_mode_needs_lighting(v->mode))
        return true;
    return a.samples == b.samples && a.rotate == b.rotate && (!a.rotate || a.frame == b.frame);
}

static bool stage_needed(const viewer *v, int stage) { return stage != STAGE_ACCUMULATE || acc_target(v) > 0; }

static int next_stage(const viewer *v, int stage)
{
    view_stage_params p = params_of(v, stage);
    int next = stage + 1;
    while (next < STAGE_COUNT && (!stage_needed(v, next) || same_params(v, params_of(v, next), p)))
        next++;
    return next;
}

void view_restart_camera(viewer *v)
{
    v->stage = STAGE_MOVING;
    v->urgent = true;
    v->raster_valid = false;
    v->radiance_exact = false;
    v->job_active = false;
    v->acc_count = 0;
}

void view_restart_lighting(viewer *v)
{
    if (v->stage > STAGE_ACCUMULATE)
        v->stage = STAGE_ACCUMULATE;
    if (v->stage == STAGE_ACCUMULATE && !stage_needed(v, STAGE_ACCUMULATE))
        v->stage = STAGE_EXACT;
    v->urgent = true;
    v->radiance_exact = false;
    v->job_active = false;
    v->acc_count = 0;
}

static bool converged(const viewer *v) { return v->stage >= STAGE_COUNT && !v->urgent && !v->job_active; }

static bool interacting(const viewer *v, double now)
{
    if (v->drag_button || now - v->last_input < QUIET_SECONDS || v->bench.frames > 0)
        return true;
    for (int i = 0; i < VIEW_NAV_COUNT; i++)
        if (v->held[i])
            return true;
    return false;
}

static void output_size(const viewer *v, int *w, int *h)
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

static void stage_finished(viewer *v)
{
    v->job_active = false;
    v->shown_params = v->job_params;
    v->shown_stage = v->job_stage;
    v->texture_stale = true;
    v->present_needed = true;
    /* Whatever stage made it, a frame lit with the exact stage's settings is the exact frame. */
    if (v->shown_from == VIEW_SHOWN_RADIANCE && v->job_params.div == 1 &&
        same_params(v, v->job_params, params_of(v, STAGE_EXACT)))
        v->radiance_exact = true;
}

/* Tone map a linear image into `shown` (re-allocated when the size changed). */
static bool tonemap_shown(viewer *v, const sl_image *linear, sl_error *err)
{
    if (v->shown.data && (v->shown.width != linear->width || v->shown.height != linear->height))
        sl_image_free(&v->shown);
    double t0 = sl_now_seconds();
    if (!sl_tonemap_image(linear, &v->shown, &v->r.desc.tonemap, err))
        return false;
    v->tonemap_ms = (sl_now_seconds() - t0) * 1e3;
    v->texture_stale = true;
    return true;
}

/* Where a stage's lighting pass writes: its own frame for the accumulation, else the renderer's
 * radiance (what `softlight render` tone maps and writes). */
static sl_image *job_target(viewer *v) { return v->job_stage == STAGE_ACCUMULATE ? &v->acc_frame : &v->r.radiance; }

/* Start a refinement stage: size, raster, then either the whole image (G-buffer views and the
 * mip view) or the first step of a sliced lighting pass (the final image). */
static bool stage_begin(viewer *v, int stage, sl_error *err)
{
    view_stage_params p = params_of(v, stage);
    int ow, oh;
    output_size(v, &ow, &oh);
    int w = scaled(ow, v->scale, p.div), h = scaled(oh, v->scale, p.div);
    v->job_active = false;
    v->job_stage = stage;
    v->job_params = p;
    if (v->r.gbuffer.width != w || v->r.gbuffer.height != h) {
        if (!sl_renderer_resize(&v->r, w, h, err))
            return false;
        v->raster_valid = false;
    }
    const sl_camera *cam = &v->camera.cam;
    if (stage != STAGE_ACCUMULATE || v->acc_count == 0)
        v->shade_ms = v->tonemap_ms = 0.0; /* between accumulation frames the HUD keeps the last one's */
    if (!v->raster_valid) {
        if (!sl_renderer_raster(&v->r, cam, err))
            return false;
        v->raster_valid = true;
        v->raster_ms = v->r.timings.raster_ms;
    }
    /* The stage's N and rotation go into the uniforms; desc keeps the user's settings. An
     * accumulation frame reads the mip levels of the user's N (uLodBase = 1/2 log2(W H / N), the
     * only place N enters the level), taken from the uniforms of N, so that the mean converges to
     * the exact frame's filtering rather than to that of 8 samples (docs/viewer.md). */
    sl_lighting_options *l = &v->r.desc.lighting;
    bool lights = v->mode == VIEW_FINAL || v->mode == VIEW_MIP, ok = true;
    float lod_base = 0.0f;
    bool total_lod = stage == STAGE_ACCUMULATE && v->acc_total_lod;
    if (lights && total_lod && (ok = sl_renderer_prepare_lighting(&v->r, cam, err)))
        lod_base = v->r.uniforms->uLodBase;
    l->samples = p.samples;
    l->rotate = p.rotate;
    l->frame = p.frame;
    if (lights && ok)
        ok = sl_renderer_prepare_lighting(&v->r, cam, err);
    if (ok && lights && total_lod)
        v->r.uniforms->uLodBase = lod_base;
    l->samples = v->samples;
    l->rotate = v->rotate;
    l->frame = v->frame;
    if (!ok)
        return false;
    double t0 = sl_now_seconds();
    switch (v->mode) {
    case VIEW_FINAL:
        if (stage == STAGE_ACCUMULATE && (v->acc_frame.width != w || v->acc_frame.height != h)) {
            sl_image_free(&v->acc_frame);
            if (!sl_image_alloc(&v->acc_frame, w, h, 3, err))
                return false;
        }
        if (stage == STAGE_ACCUMULATE && v->acc_count == 0)
            v->acc_ms = 0.0;
        if (!view_shade_begin(&v->shade, v->r.desc.threads, w, stage == STAGE_ACCUMULATE && v->acc_count > 0, err))
            return false;
        v->job_active = true;
        return true;
    case VIEW_MIP:
        if (!view_mip_image(v->r.uniforms, &v->r.gbuffer, &v->shown, &v->mip_max_seen, err))
            return false;
        break;
    default:
        if (!view_channel_image(&v->r.gbuffer, v->mode, v->bounds_lo, v->bounds_hi, cam->znear, cam->zfar, &v->shown,
                                err))
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
    bool done = view_shade_slice(&v->shade, v->r.uniforms, &v->r.gbuffer, target, budget_s, &first);
    if (v->job_stage != STAGE_ACCUMULATE || done || v->acc_count == 0)
        v->shade_ms = v->shade.seconds * 1e3;
    if (!done) {
        if (v->job_stage == STAGE_EXACT && v->shown.data && v->shown.width == target->width &&
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
    if (v->job_stage == STAGE_ACCUMULATE) {
        if (v->acc_count == 0 && v->mean.data &&
            (v->mean.width != target->width || v->mean.height != target->height))
            sl_image_free(&v->mean);
        if (!sl_lighting_accumulate(&v->mean, target, v->acc_count, err) || !tonemap_shown(v, &v->mean, err))
            return false;
        v->acc_count++;
        v->acc_ms += v->shade_ms;
        v->shown_from = VIEW_SHOWN_MEAN;
    } else {
        if (!sl_renderer_tonemap(&v->r, err) || !view_image_copy(&v->shown, &v->r.display, err))
            return false;
        v->tonemap_ms = v->r.timings.tonemap_ms;
        v->shown_from = VIEW_SHOWN_RADIANCE;
    }
    v->retonemap = false; /* the tone map just ran with the current settings */
    stage_finished(v);
    return true;
}

/* A whole stage at once (the moving stage, and screenshots). */
static bool render_stage(viewer *v, int stage, sl_error *err)
{
    if (!stage_begin(v, stage, err))
        return false;
    while (v->job_active)
        if (!stage_continue(v, 1e30, err))
            return false;
    return true;
}

/* The stage that follows a finished one: another accumulation frame until there are enough. */
static int stage_after(const viewer *v, int stage)
{
    if (stage == STAGE_ACCUMULATE && v->acc_count < acc_target(v))
        return STAGE_ACCUMULATE;
    return next_stage(v, stage);
}

/* ------------------------------------------------------------------ presenting */

const char *view_irradiance_name(sl_irradiance_method m)
{
    return sl_irradiance_name(m);
}

/* The refinement line of the HUD: what the image on screen is and what comes next. */
static void state_line(const viewer *v, double now, char *buf, size_t size)
{
    const view_stage_params *s = &v->shown_params;
    char what[96];
    if (s->div == 1)
        snprintf(what, sizeof what, "full size, N %d%s", s->samples, s->rotate ? " rotated" : "");
    else
        snprintf(what, sizeof what, "1/%d size, N %d%s", s->div, s->samples, s->rotate ? " rotated" : "");
    int target = acc_target(v), total = target * min_int(v->samples, ACC_SAMPLES);
    if (v->job_active && v->job_stage == STAGE_EXACT)
        snprintf(buf, size, "refining: the exact frame, N %d, row %d of %d (over %s)", v->samples, v->shade.next_row,
                 v->r.radiance.height, v->shown_from == VIEW_SHOWN_MEAN ? "the mean" : what);
    else if (v->shown_stage == STAGE_ACCUMULATE && v->acc_count > 0 && !converged(v))
        snprintf(buf, size, "refining: mean of %d/%d frames, %d of %d samples a pixel (%.0f ms), then exact N %d",
                 v->acc_count, target, v->acc_count * min_int(v->samples, ACC_SAMPLES), total, v->acc_ms, v->samples);
    else if (converged(v))
        snprintf(buf, size, "done: %s%s", what, v->radiance_exact ? " (= softlight render)" : "");
    else if (interacting(v, now) && v->shown_stage == STAGE_MOVING && !v->job_active)
        snprintf(buf, size, "moving: %s (%.0f ms a frame)", what, v->preview_ms);
    else if (v->stage == STAGE_ACCUMULATE || (v->job_active && v->job_stage == STAGE_ACCUMULATE))
        snprintf(buf, size, "refining: %s; accumulating %d frames of N %d", what, target,
                 min_int(v->samples, ACC_SAMPLES));
    else
        snprintf(buf, size, "refining: %s", what);
}

static void hud_lines(viewer *v, double now, const char **lines, char (*buf)[160], int *count)
{
    int n = 0;
    const sl_render_desc *d = &v->r.desc;
    const sl_lighting_options *l = &d->lighting;
    int ow, oh;
    output_size(v, &ow, &oh);
    snprintf(buf[n++], 160, "%s  %dx%d (window %dx%d)  N %d  exposure %.3g  contrast %.2f", view_mode_name(v->mode),
             v->shown.width, v->shown.height, ow, oh, v->samples, (double)d->tonemap.exposure,
             (double)d->tonemap.contrast);
    if (view_mode_needs_shading(v->mode))
        snprintf(buf[n++], 160, "raster %.1f ms  shading %.1f ms  tone map %.1f ms  present %.1f ms", v->raster_ms,
                 v->shade_ms, v->tonemap_ms, v->present_ms);
    else
        snprintf(buf[n++], 160, "raster %.1f ms  %s %.1f ms  present %.1f ms", v->raster_ms,
                 v->mode == VIEW_MIP ? "mip levels" : "channel", v->shade_ms, v->present_ms);
    sl_lighting_options resolved = sl_lighting_options_resolve(l);
    snprintf(buf[n++], 160, "lod %s  estimator %s  G %s  irradiance %s  env rotation %+.0f",
             sl_lod_rule_name(resolved.lod_rule), sl_estimator_name(resolved.estimator), sl_gterm_name(resolved.gterm),
             view_irradiance_name(l->irradiance), (double)l->env_rotation_deg);
    snprintf(buf[n++], 160, "diffuse %s  specular %s  point lights %s (%d)", l->no_diffuse ? "off" : "on",
             l->no_specular ? "off" : "on", l->no_point_lights ? "off" : "on", v->scene->light_count);
    state_line(v, now, buf[n++], 160);
    if (v->mode == VIEW_MIP)
        snprintf(buf[n++], 160, "mean mip level: 0 blue .. %.0f red (largest here %.2f)",
                 (double)v->r.uniforms->uEnvMaxLod, (double)v->mip_max_seen);
    if (now < v->message_until)
        snprintf(buf[n++], 160, "%.159s", v->message);
    snprintf(buf[n++], 160, "F1 or ? for keys");
    for (int i = 0; i < n; i++)
        lines[i] = buf[i];
    *count = n;
}

static const char *const help_text[] = {
    "mouse: left drag orbit, right/middle drag pan, wheel zoom",
    "arrows        orbit about +Z / tilt",
    "W A S D       pan",
    "+ / -         zoom in / out",
    "R             reset the camera to the scene's",
    "E / Q         exposure up / down (quarter stop)",
    "C / X         contrast up / down",
    "N / B         samples N x2 / /2 (1..1024)",
    "] / [         rotate the environment +15 / -15 degrees",
    "1 2 3         toggle diffuse, specular, point lights",
    "I             irradiance: sh9, brute, map (when the scene has one)",
    "L             mip-level rule: none, spec, spec-d4, gems, pdf",
    "K             estimator: spec, consistent, mf",
    "G             G term: inv-lh2, one",
    "V / shift+V   view: final, position, normal, kd, ks, alpha, depth, mip level",
    "H             heads-up display on / off",
    "F12 or P      screenshot: softlight-<n>.png and .hdr",
    "F1 or ?       this help",
    "Esc           close the help, else quit",
    "drop a file   .hdr: new environment; .json: new scene",
};

static bool upload(viewer *v)
{
    const sl_image *img = &v->shown;
    if (!img->data)
        return false;
    if (!v->texture || v->texture_w != img->width || v->texture_h != img->height) {
        if (v->texture)
            SDL_DestroyTexture(v->texture);
        v->texture = SDL_CreateTexture(v->sdl, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, img->width,
                                       img->height);
        if (!v->texture) {
            view_message(v, true, "SDL texture %dx%d: %s", img->width, img->height, SDL_GetError());
            return false;
        }
        v->texture_w = img->width;
        v->texture_h = img->height;
        v->texture_stale = true;
    }
    if (v->texture_stale) {
        void *pixels;
        int pitch;
        if (SDL_LockTexture(v->texture, NULL, &pixels, &pitch) != 0)
            return false;
        view_image_to_rgb8(img, pixels, pitch);
        SDL_UnlockTexture(v->texture);
        v->texture_stale = false;
    }
    return true;
}

static void present(viewer *v)
{
    double t0 = sl_now_seconds();
    SDL_SetRenderDrawColor(v->sdl, 0, 0, 0, 255);
    SDL_RenderClear(v->sdl);
    if (upload(v))
        SDL_RenderCopy(v->sdl, v->texture, NULL, NULL);
    double now = sl_now_seconds();
    if (v->hud && v->show_hud && !v->show_help) {
        const char *lines[VIEW_HUD_MAX_LINES];
        char buf[VIEW_HUD_MAX_LINES][160];
        int n;
        hud_lines(v, now, lines, buf, &n);
        view_hud_draw(v->hud, v->sdl, HUD_SLOTS, lines, n, 0, 0, false);
    }
    if (v->hud && v->show_help)
        view_hud_draw(v->hud, v->sdl, HELP_SLOTS, help_text, (int)(sizeof help_text / sizeof help_text[0]), 0, 0, true);
    SDL_RenderPresent(v->sdl);
    v->message_shown = now < v->message_until;
    v->last_present = sl_now_seconds();
    v->present_ms = (v->last_present - t0) * 1e3;
    v->present_needed = false;
    v->frames++;
    if (v->max_frames > 0 && v->frames >= v->max_frames)
        v->quit = true;
}

/* ------------------------------------------------------------------ screenshots */

static bool file_exists(const char *path) { return access(path, F_OK) == 0; }

/* The finished frame of the current view as <base>.png (what is shown, without the HUD) and
 * <base>.hdr (linear radiance). Refinement is completed first, so the files are full size, full
 * N whatever the window showed at the moment. */
bool view_screenshot(viewer *v, const char *name, sl_error *err)
{
    if (!converged(v)) {
        /* Straight to the exact frame: the accumulation is a preview of it. */
        if (!render_stage(v, STAGE_EXACT, err))
            return false;
        v->stage = STAGE_COUNT;
        v->urgent = false;
        present(v);
    }
    if (!v->radiance_exact) {
        /* A G-buffer view: light the (current, full-size) G-buffer for the .hdr, as render does. */
        if (!sl_renderer_shade(&v->r, &v->camera.cam, err))
            return false;
        v->radiance_exact = true;
    }
    char base[SL_PATH_MAX], png[SL_PATH_MAX + 8], hdr[SL_PATH_MAX + 8];
    if (name && name[0]) {
        snprintf(base, sizeof base, "%s", name);
        size_t n = strlen(base);
        if (n > 4 && (!strcasecmp(base + n - 4, ".png") || !strcasecmp(base + n - 4, ".hdr")))
            base[n - 4] = '\0';
    } else {
        do {
            snprintf(base, sizeof base, "softlight-%d", ++v->shot_counter);
            snprintf(png, sizeof png, "%s.png", base);
            snprintf(hdr, sizeof hdr, "%s.hdr", base);
        } while (file_exists(png) || file_exists(hdr));
    }
    snprintf(png, sizeof png, "%s.png", base);
    snprintf(hdr, sizeof hdr, "%s.hdr", base);
    if (!sl_image_write_png(png, &v->shown, err) || !sl_image_write_hdr(hdr, &v->r.radiance, err))
        return false;
    const sl_camera *c = &v->camera.cam;
    printf("softlight view: wrote %s and %s (%dx%d, %s, N %d; camera eye %g,%g,%g target %g,%g,%g up %g,%g,%g "
           "fovy %g)\n",
           png, hdr, v->shown.width, v->shown.height, view_mode_name(v->mode), v->samples, (double)c->eye.x,
           (double)c->eye.y, (double)c->eye.z, (double)c->target.x, (double)c->target.y, (double)c->target.z,
           (double)c->up.x, (double)c->up.y, (double)c->up.z, (double)c->fovy_deg);
    fflush(stdout);
    view_message(v, false, "wrote %s and %s", png, hdr);
    return true;
}

/* What is on screen now, without completing the refinement (the script's `snapshot`, for tests
 * of the stages themselves): <base>.png as shown and <base>.pfm, the linear image behind it (the
 * accumulated mean, or the moving or exact frame). */
static bool snapshot(viewer *v, const char *base, sl_error *err)
{
    const sl_image *linear = v->shown_from == VIEW_SHOWN_MEAN       ? &v->mean
                             : v->shown_from == VIEW_SHOWN_RADIANCE ? &v->r.radiance
                                                               : NULL;
    if (!linear || !v->shown.data)
        return sl_fail(err, SL_ERR_RANGE, "snapshot: no lit image on screen (view %s)", view_mode_name(v->mode));
    char png[SL_PATH_MAX + 8], pfm[SL_PATH_MAX + 8];
    snprintf(png, sizeof png, "%s.png", base);
    snprintf(pfm, sizeof pfm, "%s.pfm", base);
    if (!sl_image_write_png(png, &v->shown, err) || !sl_image_write_pfm(pfm, linear, err))
        return false;
    const view_stage_params *s = &v->shown_params;
    printf("softlight view: snapshot %s and %s (%dx%d, %s, N %d%s, frame %u, %d frames averaged%s)\n", png, pfm,
           linear->width, linear->height,
           v->shown_stage == STAGE_MOVING ? "moving" : v->shown_stage == STAGE_ACCUMULATE ? "accumulating" : "exact",
           s->samples, s->rotate ? " rotated" : "", (unsigned)s->frame,
           v->shown_from == VIEW_SHOWN_MEAN ? v->acc_count : 1,
           v->radiance_exact && v->shown_from == VIEW_SHOWN_RADIANCE ? ", exact" : "");
    fflush(stdout);
    return true;
}

/* ------------------------------------------------------------------ the script */

/* Run script commands that are due. Input commands in a row are pushed together (that is how
 * a burst of real input arrives); a command that depends on their effect (settle, screenshot,
 * resize) waits for the next turn, after the events have been handled. */
static void script_step(viewer *v, double now)
{
    view_script *s = &v->script;
    bool pushed = false;
    while (s->next < s->count && !v->quit) {
        const view_cmd *c = &s->cmds[s->next];
        sl_error err = {0};
        switch (c->kind) {
        case VIEW_CMD_WAIT:
            if (!s->waiting) {
                s->waiting = true;
                s->wait_until = now + c->args[0] / 1000.0;
            }
            if (now < s->wait_until)
                return;
            s->waiting = false;
            break;
        case VIEW_CMD_SETTLE:
            if (pushed || !converged(v) || interacting(v, now) || v->retonemap)
                return;
            break;
        case VIEW_CMD_RESIZE:
            if (pushed)
                return;
            if (!s->waiting) {
                SDL_SetWindowSize(v->window, c->args[0], c->args[1]);
                s->waiting = true;
                s->wait_until = now + 2.0;
                return;
            } else {
                int w, h;
                SDL_GetWindowSize(v->window, &w, &h);
                if ((w != c->args[0] || h != c->args[1]) && now < s->wait_until)
                    return;
                s->waiting = false;
                v->last_input = now;
                view_restart_camera(v);
            }
            break;
        case VIEW_CMD_SCREENSHOT:
            if (pushed)
                return;
            if (!view_screenshot(v, c->text, &err)) {
                fprintf(stderr, "softlight view: script line %d: screenshot: %s\n", c->line, err.msg);
                v->exit_status = 2;
            }
            break;
        case VIEW_CMD_ACCUMULATED:
            /* Runs in the first turn after the K-th accumulation frame, before the next begins. */
            if (pushed)
                return;
            if (c->args[0] > acc_target(v) || v->acc_count > c->args[0]) {
                fprintf(stderr,
                        "softlight view: script line %d: accumulated %d: this view accumulates %d frames "
                        "and holds %d\n",
                        c->line, c->args[0], acc_target(v), v->acc_count);
                v->exit_status = 2;
                break;
            }
            if (v->acc_count < c->args[0])
                return;
            break;
        case VIEW_CMD_SNAPSHOT:
            if (pushed)
                return;
            if (!snapshot(v, c->text, &err)) {
                fprintf(stderr, "softlight view: script line %d: %s\n", c->line, err.msg);
                v->exit_status = 2;
            }
            break;
        case VIEW_CMD_QUIT: {
            SDL_Event e = {0};
            e.type = SDL_QUIT;
            SDL_PushEvent(&e);
            s->next++;
            return;
        }
        default:
            if (!view_script_push(s, c, v->window, &err)) {
                /* The queue is full: let the loop drain it and try again. */
                return;
            }
            pushed = true;
            break;
        }
        s->next++;
    }
}

/* ------------------------------------------------------------------ the loop */

/* The moving stage's divisor follows the cost of a whole moving frame (raster, lighting, tone
 * map, present), smoothed over frames so that one slow frame on a loaded machine does not halve
 * the resolution: above TARGET_FRAME_MS by a quarter the divisor doubles; it halves when four
 * times the cost (the pixels of half the divisor) would still be well inside the target. */
static void adapt_preview(viewer *v, double frame_ms)
{
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

static bool want_stage(const viewer *v, double now)
{
    bool minimized = (SDL_GetWindowFlags(v->window) & SDL_WINDOW_MINIMIZED) != 0;
    return !minimized && !v->job_active && v->stage < STAGE_COUNT && (v->urgent || !interacting(v, now));
}

static void render_failed(viewer *v, const sl_error *err)
{
    view_message(v, true, "render: %s", err->msg);
    v->job_active = false;
    v->stage = STAGE_COUNT; /* nothing to gain from retrying the same failure */
    v->urgent = false;
}

/* ---- --benchmark: the moving stage under a steady drag, timed from present to present */

static bool bench_init(view_bench *b, int frames, sl_error *err)
{
    *b = (view_bench){0};
    double **arrays[] = {&b->frame_ms, &b->raster_ms, &b->shade_ms, &b->tonemap_ms, &b->present_ms};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
        if (!(*arrays[i] = calloc((size_t)frames, sizeof(double))))
            return sl_fail(err, SL_ERR_MEMORY, "out of memory for %d benchmark frames", frames);
    b->frames = frames;
    return true;
}

static void bench_free(view_bench *b)
{
    free(b->frame_ms);
    free(b->raster_ms);
    free(b->shade_ms);
    free(b->tonemap_ms);
    free(b->present_ms);
    *b = (view_bench){0};
}

/* Input for the next benchmark frame: what a mouse drag of BENCH_ORBIT_PIXELS does. */
static void bench_input(viewer *v, double now)
{
    view_camera_orbit(&v->camera, -VIEW_ORBIT_DEG_PER_PIXEL * BENCH_ORBIT_PIXELS, 0.0f);
    v->last_input = now;
    view_restart_camera(v);
}

/* A moving frame was presented: record it, and report and quit after the last one. */
static void bench_record(viewer *v, double now)
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
        b->last_w = v->shown.width;
        b->last_h = v->shown.height;
    }
    b->last_present = now;
    if (i + 1 < b->frames)
        return;
    int n = b->frames, ow, oh;
    output_size(v, &ow, &oh);
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
    printf("softlight view: benchmark: %d moving frames in a %dx%d window (rendered %dx%d at the end; frames at "
           "%s), N %d rotated: frame median %.1f ms, p90 %.1f ms, worst %.1f ms (%.1f frames a second at the median); "
           "medians: raster %.1f, lighting %.1f, tone map %.1f, present %.1f ms\n",
           n, ow, oh, b->last_w, b->last_h, divs, min_int(v->samples, v->move_samples), med, p90, worst, 1e3 / med,
           sl_median(b->raster_ms, n), sl_median(b->shade_ms, n), sl_median(b->tonemap_ms, n), sl_median(b->present_ms, n));
    fflush(stdout);
    v->quit = true;
}

static void run(viewer *v)
{
    v->bench.last_present = sl_now_seconds();
    while (!v->quit) {
        double now = sl_now_seconds();
        if (v->have_script)
            script_step(v, now);
        if (v->bench.frames > 0)
            bench_input(v, now);
        bool message_expired = v->message_shown && now >= v->message_until;
        bool busy = v->job_active || want_stage(v, now) || v->retonemap || v->present_needed || message_expired;
        SDL_Event e;
        if (!busy) {
            /* Idle: sleep until input, but wake for the script, the end of a quiet period and the
             * message's expiry. */
            double wake = 0.25;
            if (v->have_script && v->script.next < v->script.count)
                wake = v->script.waiting ? fmax(0.001, v->script.wait_until - now) : 0.005;
            if (v->stage < STAGE_COUNT)
                wake = fmin(wake, fmax(0.005, v->last_input + QUIET_SECONDS - now));
            if (v->message_shown)
                wake = fmin(wake, fmax(0.005, v->message_until - now));
            if (SDL_WaitEventTimeout(&e, (int)(wake * 1000.0) + 1))
                view_handle_event(v, &e);
        }
        while (!v->quit && SDL_PollEvent(&e))
            view_handle_event(v, &e);
        if (v->quit)
            break;
        now = sl_now_seconds();
        sl_error err = {0};
        if (v->job_active) {
            int stage = v->job_stage;
            if (!stage_continue(v, SLICE_SECONDS, &err))
                render_failed(v, &err);
            else if (!v->job_active)
                v->stage = stage_after(v, stage);
            /* Between slices that changed nothing on screen, the HUD's progress needs no more
             * than a present every PRESENT_IDLE_SECONDS (a present costs milliseconds). */
            if (v->texture_stale || v->present_needed || !v->job_active ||
                sl_now_seconds() - v->last_present >= PRESENT_IDLE_SECONDS)
                present(v);
        } else if (want_stage(v, now)) {
            int stage = v->stage;
            double t0 = sl_now_seconds();
            v->urgent = false;
            /* A moving frame is small by design and always finishes; later stages are sliced. */
            bool ok = stage == STAGE_MOVING ? render_stage(v, stage, &err) : stage_begin(v, stage, &err);
            if (!ok)
                render_failed(v, &err);
            else if (!v->job_active)
                v->stage = stage_after(v, stage);
            present(v);
            if (ok && stage == STAGE_MOVING) {
                double t1 = sl_now_seconds();
                v->move_frame++;
                adapt_preview(v, (t1 - t0) * 1e3);
                if (v->bench.frames > 0)
                    bench_record(v, t1);
            }
        } else if (v->retonemap && !v->job_active) {
            v->retonemap = false;
            if (v->mode == VIEW_FINAL && v->shown_from == VIEW_SHOWN_RADIANCE) {
                if (sl_renderer_tonemap(&v->r, &err) && view_image_copy(&v->shown, &v->r.display, &err)) {
                    v->tonemap_ms = v->r.timings.tonemap_ms;
                    v->texture_stale = true;
                } else {
                    view_message(v, true, "tone map: %s", err.msg);
                }
            } else if (v->mode == VIEW_FINAL && v->shown_from == VIEW_SHOWN_MEAN && !tonemap_shown(v, &v->mean, &err)) {
                view_message(v, true, "tone map: %s", err.msg);
            }
            present(v);
        } else if (v->present_needed || (v->message_shown && now >= v->message_until)) {
            present(v);
        }
    }
}

/* ------------------------------------------------------------------ setup */

static bool display_available(char *why, size_t size)
{
    const char *display = getenv("DISPLAY"), *wayland = getenv("WAYLAND_DISPLAY"), *driver = getenv("SDL_VIDEODRIVER");
    /* SDL_VIDEODRIVER names a driver explicitly (offscreen, dummy, kmsdrm): let SDL decide. */
    if ((display && display[0]) || (wayland && wayland[0]) || (driver && driver[0]))
        return true;
    snprintf(why, size, "neither DISPLAY nor WAYLAND_DISPLAY is set");
    return false;
}

/* The window starts at --size, else the scene's size, shrunk (aspect kept) to fit the screen. */
static void initial_window_size(const sl_render_options *o, const sl_scene *scene, float scale, int *w, int *h)
{
    if (o->size[0] > 0) {
        *w = o->size[0];
        *h = o->size[1];
        return;
    }
    *w = (int)lroundf((float)scene->settings.width / scale);
    *h = (int)lroundf((float)scene->settings.height / scale);
    SDL_Rect usable;
    if (SDL_GetDisplayUsableBounds(0, &usable) == 0 && usable.w > 0 && usable.h > 0) {
        float fit = fminf(0.9f * (float)usable.w / (float)*w, 0.9f * (float)usable.h / (float)*h);
        if (fit < 1.0f) {
            *w = (int)lroundf((float)*w * fit);
            *h = (int)lroundf((float)*h * fit);
        }
    }
    if (*w < 1)
        *w = 1;
    if (*h < 1)
        *h = 1;
}

static void viewer_free(viewer *v)
{
    view_script_free(&v->script);
    view_shade_free(&v->shade);
    view_hud_destroy(v->hud);
    if (v->scene) {
        sl_renderer_free(&v->r);
        sl_scene_free(v->scene);
        free(v->scene);
    }
    sl_image_free(&v->shown);
    sl_image_free(&v->acc_frame);
    sl_image_free(&v->mean);
    bench_free(&v->bench);
    if (v->texture)
        SDL_DestroyTexture(v->texture);
    if (v->sdl)
        SDL_DestroyRenderer(v->sdl);
    if (v->window)
        SDL_DestroyWindow(v->window);
}

int cmd_view(int argc, char **argv)
{
    sl_render_options opts;
    sl_arg table[SL_RENDER_OPTION_COUNT + VIEW_OPTION_COUNT];
    sl_render_options_table(&opts, table);
    float scale = 1.0f;
    const char *script_path = NULL, *font_path = DEFAULT_FONT;
    int frames = 0, move_samples = MOVE_SAMPLES, move_div = 0, bench_frames = 0;
    int acc_lod = 0; /* index in "total|frame" */
    bool no_hud = false;
    const sl_arg extra[] = {
        {"--scale", NULL, SL_ARG_FLOAT, &scale, 0.05, 1.0, NULL, "S", "render at S times the window size (default 1)",
         NULL},
        {"--script", NULL, SL_ARG_STRING, &script_path, 0, 0, NULL, "FILE",
         "scripted input, one command a line (docs/viewer.md)", NULL},
        {"--frames", NULL, SL_ARG_INT, &frames, 1, 1000000, NULL, "N", "quit after N frames", NULL},
        {"--font", NULL, SL_ARG_STRING, &font_path, 0, 0, NULL, "TTF", "HUD font (default DejaVu Sans Mono)", NULL},
        {"--no-hud", NULL, SL_ARG_FLAG, &no_hud, 0, 0, NULL, NULL, "start with the heads-up display hidden", NULL},
        {"--move-samples", NULL, SL_ARG_INT, &move_samples, 1, SL_HAMMERSLEY_MAX, NULL, "N",
         "samples N while the camera moves (default 8, rotated per frame)", NULL},
        {"--move-div", NULL, SL_ARG_INT, &move_div, 1, VIEW_MAX_PREVIEW_DIV, NULL, "D",
         "while moving, render at 1/D of the window per axis (default: adapts, starting at 2)", NULL},
        {"--benchmark", NULL, SL_ARG_INT, &bench_frames, 1, 100000, NULL, "FRAMES",
         "orbit for FRAMES moving frames, print the frame times and quit", NULL},
        {"--accumulate-lod", NULL, SL_ARG_CHOICE, &acc_lod, 0, 0, "total|frame", NULL,
         "mip levels of accumulation frames: as for the total N (default) or for the frame's own N", NULL},
    };
    _Static_assert(sizeof extra / sizeof extra[0] == VIEW_OPTION_COUNT, "VIEW_OPTION_COUNT is the size of extra[]");
    memcpy(table + SL_RENDER_OPTION_COUNT, extra, sizeof extra);
    const int count = SL_RENDER_OPTION_COUNT + (int)(sizeof extra / sizeof extra[0]);
    const char *usage = "softlight view scene.json [options]   (--size: the window's size)";
    const char *scene_path[1];
    int npos = 0;
    bool help = false;
    sl_error err = {0};
    sl_render_desc desc;
    if (!sl_args_parse(argc, argv, 2, table, count, scene_path, 1, &npos, &help, &err)) {
        fprintf(stderr, "softlight view: %s\n", err.msg);
        return 2;
    }
    if (help) {
        sl_args_print_help(stdout, usage, table, count);
        printf("\nkeys: press F1 or ? in the window; docs/viewer.md lists keys, script commands and refinement\n");
        return 0;
    }
    if (npos != 1) {
        fprintf(stderr, "softlight view: expected one scene file (see --help)\n");
        return 2;
    }
    if (!sl_render_options_desc(&opts, &desc, &err)) {
        fprintf(stderr, "softlight view: %s\n", err.msg);
        return 2;
    }
    viewer v = {0};
    v.cli_desc = desc;
    v.scale = scale;
    v.max_frames = frames;
    v.show_hud = !no_hud;
    v.acc_total_lod = acc_lod == 0;
    v.move_samples = move_samples;
    v.fixed_div = move_div;
    v.preview_div = move_div ? move_div : 2;
    v.shown_stage = -1;
    if (script_path) {
        if (!view_script_load(script_path, &v.script, &err)) {
            fprintf(stderr, "softlight view: %s\n", err.msg);
            return 2;
        }
        v.have_script = true;
    }
    if (bench_frames > 0 && !bench_init(&v.bench, bench_frames, &err)) {
        fprintf(stderr, "softlight view: %s\n", err.msg);
        view_script_free(&v.script);
        bench_free(&v.bench);
        return 2;
    }

    char why[256];
    bool display = display_available(why, sizeof why);
    if (!display || SDL_Init(SDL_INIT_VIDEO) != 0) {
        if (display)
            snprintf(why, sizeof why, "SDL: %s", SDL_GetError());
        fprintf(stderr, "softlight view: no display (%s); use softlight render %s -o out.png\n", why, scene_path[0]);
        view_script_free(&v.script);
        bench_free(&v.bench);
        return 2;
    }
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "1");
    SDL_StopTextInput();

    int status = 2;
    sl_scene *scene = calloc(1, sizeof *scene);
    if (!scene || !sl_scene_load(scene_path[0], scene, &err)) {
        fprintf(stderr, "softlight view: %s\n", scene ? err.msg : "out of memory");
        free(scene);
        goto done;
    }
    int ww, wh;
    initial_window_size(&opts, scene, scale, &ww, &wh);
    v.window = SDL_CreateWindow("softlight view", SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, ww, wh,
                                SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI);
    if (v.window) {
        v.sdl = SDL_CreateRenderer(v.window, -1, SDL_RENDERER_ACCELERATED);
        if (!v.sdl)
            v.sdl = SDL_CreateRenderer(v.window, -1, SDL_RENDERER_SOFTWARE);
    }
    if (!v.window || !v.sdl) {
        fprintf(stderr, "softlight view: no display (SDL: %s); use softlight render %s -o out.png\n", SDL_GetError(),
               scene_path[0]);
        sl_scene_free(scene);
        free(scene);
        goto done;
    }
    int ow, oh;
    output_size(&v, &ow, &oh);
    sl_renderer r;
    sl_render_desc first = desc;
    first.width = scaled(ow, scale, 1);
    first.height = scaled(oh, scale, 1);
    if (!sl_renderer_init(&r, scene, &first, &err)) {
        fprintf(stderr, "softlight view: %s\n", err.msg);
        sl_scene_free(scene);
        free(scene);
        goto done;
    }
    view_adopt_scene(&v, scene, &r);
    if (r.env_repairs.nan_count || r.env_repairs.inf_count || r.env_repairs.negative_count)
        view_message(&v, true, "%s: %ld NaN, %ld Inf, %ld negative texels read as 0", scene->environment.hdr_path,
                r.env_repairs.nan_count, r.env_repairs.inf_count, r.env_repairs.negative_count);

    v.hud = view_hud_create(font_path, FONT_POINTS, &err);
    if (!v.hud)
        fprintf(stderr, "softlight view: font %s; running without HUD text\n", err.msg);

    v.exit_status = 0;
    run(&v);
    status = v.exit_status;
done:
    viewer_free(&v);
    SDL_Quit();
    return status;
}

#endif
