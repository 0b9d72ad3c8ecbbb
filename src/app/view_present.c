/* view_present.c - what reaches the window: the shown image as a texture, the heads-up display,
 * the help overlay and the message line (the contract is in view_internal.h).
 *
 * Why a file of its own: presenting only reads the viewer's state (it never renders or changes
 * what is refined), so every other part can ask for a present or a message without knowing how
 * the window is drawn. The HUD describes the refinement through view_refine.c's questions. */
#if SL_HAVE_SDL2
#include <SDL.h>

#include <stdarg.h>
#include <stdio.h>

#include "core/timer.h"
#include "view_internal.h"

#define MESSAGE_SECONDS 6.0
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

/* ------------------------------------------------------------------ the HUD and help */

const char *view_irradiance_name(sl_irradiance_method m)
{
    return sl_irradiance_name(m);
}

void view_stage_describe(const view_stage_params *s, char *buf, size_t size)
{
    if (s->estimator == SL_ESTIMATOR_SPLITSUM)
        snprintf(buf, size, "split sum");
    else
        snprintf(buf, size, "N %d%s", s->samples, s->rotate ? " rotated" : "");
}

/* The refinement line of the HUD: what the image on screen is and what comes next. */
static void state_line(const viewer *v, double now, char *buf, size_t size)
{
    const view_stage_params *s = &v->shown_params;
    char what[96];
    char lit[64];
    view_stage_describe(s, lit, sizeof lit);
    if (s->div == 1)
        snprintf(what, sizeof what, "full size, %s", lit);
    else
        snprintf(what, sizeof what, "1/%d size, %s", s->div, lit);
    int n = v->r.desc.lighting.samples, acc_n = n < VIEW_ACC_SAMPLES ? n : VIEW_ACC_SAMPLES;
    int target = view_acc_target(v), total = target * acc_n;
    if (v->job_active && v->job_stage == VIEW_STAGE_EXACT)
        snprintf(buf, size, "refining: the exact frame, N %d, row %d of %d (over %s)", n, v->shade.next_row,
                 v->r.radiance.height, v->shown_from == VIEW_SHOWN_MEAN ? "the mean" : what);
    else if (v->shown_stage == VIEW_STAGE_ACCUMULATE && v->acc_count > 0 && !view_converged(v))
        snprintf(buf, size, "refining: mean of %d/%d frames, %d of %d samples a pixel (%.0f ms), then exact N %d",
                 v->acc_count, target, v->acc_count * acc_n, total, v->acc_ms, n);
    else if (view_converged(v))
        snprintf(buf, size, "done: %s%s", what, v->radiance_exact ? " (= softlight render)" : "");
    else if (view_interacting(v, now) && v->shown_stage == VIEW_STAGE_MOVING && !v->job_active)
        snprintf(buf, size, "moving: %s (%.0f ms a frame)", what, v->preview_ms);
    else if (v->stage == VIEW_STAGE_ACCUMULATE || (v->job_active && v->job_stage == VIEW_STAGE_ACCUMULATE))
        snprintf(buf, size, "refining: %s; accumulating %d frames of N %d", what, target, acc_n);
    else
        snprintf(buf, size, "refining: %s", what);
}

/* The HUD's lines into `buf` (VIEW_HUD_MAX_LINES of 160 characters), pointed to by `lines`. */
static void hud_lines(viewer *v, double now, const char **lines, char (*buf)[160], int *count)
{
    int n = 0;
    const sl_render_desc *d = &v->r.desc;
    const sl_lighting_options *l = &d->lighting;
    int ow, oh, sw, sh;
    view_output_size(v, &ow, &oh);
    view_shown_size(v, &sw, &sh);
    snprintf(buf[n++], 160, "%s  %dx%d (window %dx%d)  N %d  exposure %.3g  contrast %.2f", view_mode_name(v->mode),
             sw, sh, ow, oh, l->samples, (double)d->tonemap.exposure,
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

/* The help overlay (F1 or ?); docs/viewer.md lists the same keys. */
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
    "I             irradiance: oct, dp, sh9, brute, map (when the scene has one)",
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

/* ------------------------------------------------------------------ the window */

/* What the window shows into the streaming texture (recreated when the size changed), only when
 * it changed since the last upload (texture_stale): a present with nothing new costs nothing.
 * A lit frame (shown_pending) is tone mapped straight into the texture, one pass over the frame
 * (its time is the tone map's, `tone_ms`); other images are converted from `shown`. */
static bool upload(viewer *v, double *tone_ms)
{
    int w, h;
    view_shown_size(v, &w, &h);
    if (w < 1 || h < 1)
        return false;
    if (!v->texture || v->texture_w != w || v->texture_h != h)
        v->texture_stale = true;
    if (v->texture_stale) {
        uint8_t *pixels;
        int pitch;
        sl_error err = {0};
        if (!view_texture_lock(v, w, h, &pixels, &pitch, &err)) {
            view_message(v, true, "%s", err.msg);
            return false;
        }
        if (v->shown_pending) {
            double t0 = sl_now_seconds();
            const sl_tonemap_table *tab = sl_renderer_tonemap_table(&v->r, &err);
            if (!tab) {
                view_texture_unlock(v);
                view_message(v, true, "%s", err.msg);
                return false;
            }
            sl_tonemap_apply_xrgb8888(tab, &v->r.radiance, pixels, pitch, v->r.desc.threads);
            *tone_ms = (sl_now_seconds() - t0) * 1e3;
        } else {
            view_image_to_xrgb8888(&v->shown, pixels, pitch);
        }
        view_texture_unlock(v);
        v->texture_stale = false;
    }
    return true;
}

void view_present(viewer *v)
{
    double t0 = sl_now_seconds(), tone_ms = -1.0;
    /* the image covers the whole window: a clear only when there is none */
    if (upload(v, &tone_ms)) {
        SDL_RenderCopy(v->sdl, v->texture, NULL, NULL);
    } else {
        SDL_SetRenderDrawColor(v->sdl, 0, 0, 0, 255);
        SDL_RenderClear(v->sdl);
    }
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
    if (tone_ms >= 0.0) { /* the tone map ran in the upload: its time is the tone map's, not the present's */
        v->tonemap_ms = tone_ms;
        v->present_ms -= tone_ms;
    }
    v->present_needed = false;
    v->frames++;
    if (v->max_frames > 0 && v->frames >= v->max_frames)
        v->quit = true;
}

#else
typedef int view_present_unused; /* this file is only built with SDL2 */
#endif
