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
#include <string.h>

#include "core/timer.h"
#include "view_internal.h"

#define MESSAGE_SECONDS 6.0
#define HUD_SLOTS 0
#define HELP_SLOTS VIEW_HUD_MAX_LINES
#define TRACE_SLOTS (2 * VIEW_HUD_MAX_LINES)

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

#define LINE 160 /* characters a HUD line holds (view_hud.c's slots) */
#define HUD_PAD 6

typedef struct {
    const char *lines[VIEW_HUD_MAX_LINES];
    char buf[VIEW_HUD_MAX_LINES][LINE];
    int count;
} text_block;

/* Append `text` to the block, wrapped at spaces to `width` pixels (0: no limit) so a long line
 * (an error naming a path) is not clipped at the window's edge. */
static void add_wrapped(const viewer *v, text_block *t, const char *text, int width)
{
    const char *s = text;
    do {
        if (t->count >= VIEW_HUD_MAX_LINES)
            return;
        char *line = t->buf[t->count];
        size_t len = strlen(s);
        if (len >= LINE)
            len = LINE - 1;
        snprintf(line, LINE, "%.*s", (int)len, s);
        /* shorten to the last space that fits (or to the characters that fit, for one long word) */
        while (width > 0 && v->hud && len > 1 && view_hud_text_width(v->hud, line) > width) {
            size_t cut = len - 1;
            while (cut > 0 && line[cut] != ' ')
                cut--;
            if (cut == 0) {
                cut = len - 1;
                while (cut > 1 && view_hud_text_width(v->hud, line) > width)
                    line[cut--] = '\0';
                break;
            }
            line[cut] = '\0';
            len = cut;
        }
        len = strlen(line);
        t->lines[t->count] = line;
        t->count++;
        s += len;
        while (*s == ' ')
            s++;
    } while (*s);
}

static void addf(const viewer *v, text_block *t, int width, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static void addf(const viewer *v, text_block *t, int width, const char *fmt, ...)
{
    char text[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    add_wrapped(v, t, text, width);
}

/* What the view shows, in words and units (every view has one). */
static void legend(const viewer *v, char *buf, size_t size)
{
    vec3 lo = v->bounds_lo, hi = v->bounds_hi;
    switch (v->mode) {
    case VIEW_FINAL:
        snprintf(buf, size, "final: radiance x exposure, tone mapped (contrast c/2.2), sRGB");
        break;
    case VIEW_POSITION:
        snprintf(buf, size,
                 "position: R = x %.3g..%.3g, G = y %.3g..%.3g, B = z %.3g..%.3g (the scene's bounds, world units)",
                 (double)lo.x, (double)hi.x, (double)lo.y, (double)hi.y, (double)lo.z, (double)hi.z);
        break;
    case VIEW_NORMAL:
        snprintf(buf, size, "normal: RGB = n x 0.5 + 0.5 (world space: red +X, green +Y, blue +Z)");
        break;
    case VIEW_KD:
    case VIEW_KS:
        snprintf(buf, size, "%s: RGB = value^(1/2.2), black 0 .. white 1 (%s)", view_mode_name(v->mode),
                 v->mode == VIEW_KD ? "diffuse albedo" : "Fresnel F0");
        break;
    case VIEW_ALPHA:
        snprintf(buf, size, "alpha: grey = log(1 + alpha) / log(1 + 10000): black 0 (rough) .. white 10000 (mirror)");
        break;
    case VIEW_DEPTH:
        snprintf(buf, size, "depth: white %.4g .. black %.4g (world units along the view axis, what is on screen)",
                 (double)v->depth_range[0], (double)v->depth_range[1]);
        break;
    case VIEW_MIP:
        snprintf(buf, size, "mean mip level: 0 blue, cyan, green, yellow, %.0f red (largest here %.2f); grey: no sample",
                 (double)v->r.uniforms->uEnvMaxLod, (double)v->mip_max_seen);
        break;
    default:
        buf[0] = '\0';
        break;
    }
}

/* Which estimator lit the frame on screen, and why a moving frame and the still one differ. */
static void estimator_line(const viewer *v, char *buf, size_t size)
{
    buf[0] = '\0';
    if (v->mode != VIEW_FINAL)
        return;
    sl_estimator user = sl_lighting_options_resolve(&v->r.desc.lighting).estimator;
    if (v->move_user || user == SL_ESTIMATOR_SPLITSUM)
        return;
    bool split = v->shown_params.estimator == SL_ESTIMATOR_SPLITSUM;
    snprintf(buf, size,
             "on screen: %s. Moving frames use the split sum (prefiltered, no samples), the still frame %s with "
             "N %d: two estimators, so the image changes when the camera stops",
             split ? "split sum (moving)" : sl_estimator_name(user), sl_estimator_name(user),
             v->r.desc.lighting.samples);
}

/* The HUD's lines: full (settings, times, state, estimator, legend, readout, message) or
 * compact (the view and state in one line, the readout, the message). */
static void hud_lines(viewer *v, double now, int width, text_block *t)
{
    const sl_render_desc *d = &v->r.desc;
    const sl_lighting_options *l = &d->lighting;
    int ow, oh, sw, sh;
    char line[1024], state[256];
    view_output_size(v, &ow, &oh);
    view_shown_size(v, &sw, &sh);
    state_line(v, now, state, sizeof state);
    bool compact = v->hud_chosen ? v->hud_compact : oh < 400; /* a small window keeps its image */
    if (compact) {
        addf(v, t, width, "%s %dx%d N %d exp %.3g | %s", view_mode_name(v->mode), sw, sh, l->samples,
             (double)d->tonemap.exposure, state);
    } else {
        addf(v, t, width, "%s  %dx%d (window %dx%d)  N %d  exposure %.3g  contrast %.2f", view_mode_name(v->mode), sw,
             sh, ow, oh, l->samples, (double)d->tonemap.exposure, (double)d->tonemap.contrast);
        if (view_mode_needs_shading(v->mode))
            addf(v, t, width, "raster %.1f ms  shading %.1f ms  tone map %.1f ms  present %.1f ms", v->raster_ms,
                 v->shade_ms, v->tonemap_ms, v->present_ms);
        else
            addf(v, t, width, "raster %.1f ms  %s %.1f ms  present %.1f ms", v->raster_ms,
                 v->mode == VIEW_MIP ? "mip levels" : "channel", v->shade_ms, v->present_ms);
        sl_lighting_options resolved = sl_lighting_options_resolve(l);
        addf(v, t, width, "lod %s  estimator %s  G %s  irradiance %s  env rotation %+.0f",
             sl_lod_rule_name(resolved.lod_rule), sl_estimator_name(resolved.estimator), sl_gterm_name(resolved.gterm),
             view_irradiance_name(l->irradiance), (double)l->env_rotation_deg);
        addf(v, t, width, "diffuse %s  specular %s  point lights %s (%d)", l->no_diffuse ? "off" : "on",
             l->no_specular ? "off" : "on", l->no_point_lights ? "off" : "on", v->scene->light_count);
        add_wrapped(v, t, state, width);
        estimator_line(v, line, sizeof line);
        if (line[0])
            add_wrapped(v, t, line, width);
        legend(v, line, sizeof line);
        add_wrapped(v, t, line, width);
    }
    if (view_readout(v, 4, line, sizeof line))
        add_wrapped(v, t, line, width);
    view_gl_hud(v, line, sizeof line);
    if (line[0])
        add_wrapped(v, t, line, width);
    view_program_hud(v, compact, line, sizeof line);
    for (char *s = line, *end; *s; s = end + 1) {
        end = strchr(s, '\n');
        if (!end)
            break;
        *end = '\0';
        add_wrapped(v, t, s, width);
    }
    if (now < v->message_until)
        add_wrapped(v, t, v->message, width);
    if (!compact)
        add_wrapped(v, t, "F1 or ? for keys, H for a smaller HUD", width);
}

/* The help overlay (F1 or ?): the key table (view_keys.c), as docs/viewer.md has it. */
static void help_lines(const viewer *v, int width, text_block *t)
{
    for (int i = 0; i < view_keys_count(); i++) {
        char action[1024];
        view_keys_action(i, action, sizeof action);
        addf(v, t, width, "%-19s %s", view_keys_input(i), action);
    }
}

/* The trace (T), a page at a time: as many lines as the window holds under a header. */
static void trace_lines(viewer *v, int height, text_block *t)
{
    int per_page = v->hud ? (height - 2 * HUD_PAD) / view_hud_line_height(v->hud) - 1 : 1;
    if (per_page < 1)
        per_page = 1;
    if (per_page > VIEW_HUD_MAX_LINES - 1)
        per_page = VIEW_HUD_MAX_LINES - 1;
    int pages = (v->trace_lines + per_page - 1) / per_page;
    if (pages < 1)
        pages = 1;
    if (v->trace_page >= pages)
        v->trace_page = pages - 1;
    snprintf(t->buf[0], LINE, "trace, page %d of %d (PageUp / PageDown or the wheel; Esc closes; also on stdout)",
             v->trace_page + 1, pages);
    t->lines[0] = t->buf[0];
    t->count = 1;
    const char *p = v->trace_text;
    for (int skip = v->trace_page * per_page; skip > 0 && p && *p; skip--) {
        p = strchr(p, '\n');
        p = p ? p + 1 : NULL;
    }
    while (p && *p && t->count <= per_page) {
        size_t len = strcspn(p, "\n");
        snprintf(t->buf[t->count], LINE, "%.*s", (int)(len < LINE ? len : LINE - 1), p);
        t->lines[t->count] = t->buf[t->count];
        t->count++;
        p += len;
        if (*p == '\n')
            p++;
    }
}

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
    if (v->hud) {
        int ow, oh;
        view_output_size(v, &ow, &oh);
        int width = ow - 2 * HUD_PAD;
        static text_block t; /* 10 KB: off the stack; one loop thread */
        t.count = 0;
        if (v->show_trace && v->trace_text) {
            trace_lines(v, oh, &t);
            view_hud_draw(v->hud, v->sdl, TRACE_SLOTS, t.lines, t.count, 0, 0, false);
        } else if (v->show_help) {
            help_lines(v, width, &t);
            view_hud_draw(v->hud, v->sdl, HELP_SLOTS, t.lines, t.count, 0, 0, true);
        } else if (v->show_hud) {
            hud_lines(v, now, width, &t);
            view_hud_draw(v->hud, v->sdl, HUD_SLOTS, t.lines, t.count, 0, 0, false);
        }
    }
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
