/* cmd_view.c - `softlight view scene.json`: the interactive SDL2 viewer.
 *
 * One thread runs the loop: script commands -> SDL events -> at most one render step ->
 * present. The pipeline itself is parallel (OpenMP inside raster and shading), so the loop
 * stays simple and every frame is the one `softlight render` would make for that camera.
 *
 * Refinement. A frame at full size and full N can take a good part of a second, so the image
 * is built in stages (docs/viewer.md):
 *     stage 0  preview: 1/preview_div of the window per axis, N = min(N, 4)
 *     stage 1  full size, N = min(N, 8)
 *     stage 2  full size, the chosen N (the result `softlight render` gives)
 * A camera move restarts at stage 0 and stays there while input continues (the preview divisor
 * adapts so a preview takes about TARGET_PREVIEW_MS); a lighting change restarts at stage 1;
 * exposure and contrast only re-run the tone map. Stages with the same size and N as the one
 * before are skipped. A true progressive accumulation would need the lighting API to take a
 * per-frame rotation of the Hammersley set (docs/viewer.md says what exactly).
 *
 * Files: view_camera.c (orbit camera), view_image.c (G-buffer and mip views), view_script.c
 * (--script), view_hud.c (text). Without SDL2 the command prints one line and exits 2. */
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
#define STAGE_COUNT 3
#define PREVIEW_SAMPLES 4
#define MID_SAMPLES 8
#define QUIET_SECONDS 0.15      /* input this recent still counts as "moving" */
#define TARGET_PREVIEW_MS 40.0  /* preview frames aim at about 25 per second */
#define MAX_PREVIEW_DIV 8
#define MESSAGE_SECONDS 6.0
#define ORBIT_DEG_PER_PIXEL 0.4f
#define ORBIT_KEY_DEG 5.0f
#define PAN_KEY_FRACTION 0.05f
#define ZOOM_STEP 0.9f
#define ENV_ROTATION_STEP 15.0f
#define EXPOSURE_STEP 1.189207115f /* 2^(1/4): a quarter stop */
#define CONTRAST_STEP 0.1f
#define SLICE_SECONDS 0.04      /* one lighting slice between two looks at the input */
#define HUD_SLOTS 0
#define HELP_SLOTS VIEW_HUD_MAX_LINES

typedef struct {
    int div;     /* the render size is the window's (times --scale) divided by this */
    int samples; /* N */
} stage_params;

/* Navigation keys, tracked from events so a held key keeps the preview going (SDL's own keyboard
 * state does not see scripted events). */
enum { NAV_LEFT, NAV_RIGHT, NAV_UP, NAV_DOWN, NAV_W, NAV_A, NAV_S, NAV_D, NAV_IN, NAV_OUT, NAV_COUNT };

typedef struct {
    /* window */
    SDL_Window *window;
    SDL_Renderer *sdl;
    SDL_Texture *texture;
    int texture_w, texture_h;
    bool texture_stale; /* `shown` changed since the last upload */
    view_hud *hud;      /* NULL: no font, no text */
    bool show_hud, show_help;

    /* what is rendered */
    sl_scene *scene;
    sl_renderer r;
    sl_render_desc cli_desc; /* the command line's settings, for scenes dropped later */
    vec3 bounds_lo, bounds_hi;
    view_camera camera;
    view_mode mode;
    int samples;     /* the user's N; stages may use fewer */
    float scale;     /* --scale */
    bool irradiance_stale; /* the environment changed while the diffuse term was off */
    bool env_replaced;     /* a dropped .hdr replaced the scene's environment (its map no longer fits) */

    /* refinement */
    int stage;       /* next stage to render; STAGE_COUNT: done */
    bool urgent;     /* something changed: render `stage` now, even during input */
    bool retonemap;  /* exposure/contrast changed: tone map and present only */
    int preview_div;
    bool raster_valid; /* the G-buffer holds the current camera at its current size */
    view_shade_job shade; /* the lighting pass of the stage in progress */
    bool job_active;   /* a stage's lighting pass is under way */
    int job_stage;
    stage_params job_params;
    int radiance_stage; /* the stage r.radiance belongs to; -1 = stale */
    stage_params shown_params;
    int shown_stage;
    sl_image shown;  /* what the window shows, [0,1], row 0 = top */
    float mip_max_seen;
    double raster_ms, shade_ms, tonemap_ms, present_ms;
    bool present_needed;

    /* input */
    double last_input;
    int drag_button;
    bool held[NAV_COUNT];

    /* messages, script, counters */
    char message[256];
    double message_until;
    bool message_shown;
    view_script script;
    bool have_script;
    long frames, max_frames;
    int shot_counter;
    int exit_status;
    bool quit;
} viewer;

/* ------------------------------------------------------------------ messages */

/* One line in the HUD for a few seconds; errors also go to stderr (the window may be hidden). */
static void message(viewer *v, bool error, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void message(viewer *v, bool error, const char *fmt, ...)
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

static stage_params params_of(const viewer *v, int stage)
{
    switch (stage) {
    case 0:
        return (stage_params){v->preview_div, v->samples < PREVIEW_SAMPLES ? v->samples : PREVIEW_SAMPLES};
    case 1:
        return (stage_params){1, v->samples < MID_SAMPLES ? v->samples : MID_SAMPLES};
    default:
        return (stage_params){1, v->samples};
    }
}

/* Stages that would render the same image as the one before them are skipped (N only matters
 * to views that light the G-buffer). */
static bool same_params(const viewer *v, stage_params a, stage_params b)
{
    return a.div == b.div && (a.samples == b.samples || !view_mode_needs_lighting(v->mode));
}

static int next_stage(const viewer *v, int stage)
{
    stage_params p = params_of(v, stage);
    int next = stage + 1;
    while (next < STAGE_COUNT && same_params(v, params_of(v, next), p))
        next++;
    return next;
}

/* The camera, the scene or the window size changed: start again from the preview. */
static void restart_view(viewer *v)
{
    v->stage = 0;
    v->urgent = true;
    v->raster_valid = false;
    v->radiance_stage = -1;
    v->job_active = false;
}

/* Lighting settings or the view mode changed: the G-buffer stays, the preview is skipped. */
static void restart_lighting(viewer *v)
{
    if (v->stage > 1)
        v->stage = 1;
    v->urgent = true;
    v->radiance_stage = -1;
    v->job_active = false;
}

static bool converged(const viewer *v) { return v->stage >= STAGE_COUNT && !v->urgent && !v->job_active; }

static bool interacting(const viewer *v, double now)
{
    if (v->drag_button || now - v->last_input < QUIET_SECONDS)
        return true;
    for (int i = 0; i < NAV_COUNT; i++)
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
}

/* Start a refinement stage: size, raster, then either the whole image (G-buffer views and the
 * mip view) or the first step of a sliced lighting pass (the final image). */
static bool stage_begin(viewer *v, int stage, sl_error *err)
{
    stage_params p = params_of(v, stage);
    int ow, oh;
    output_size(v, &ow, &oh);
    int w = scaled(ow, v->scale, p.div), h = scaled(oh, v->scale, p.div);
    v->job_active = false;
    v->job_stage = stage;
    v->job_params = p;
    v->radiance_stage = -1;
    if (v->r.gbuffer.width != w || v->r.gbuffer.height != h) {
        if (!sl_renderer_resize(&v->r, w, h, err))
            return false;
        v->raster_valid = false;
    }
    const sl_camera *cam = &v->camera.cam;
    v->r.desc.lighting.samples = p.samples;
    v->shade_ms = v->tonemap_ms = 0.0;
    if (!v->raster_valid) {
        if (!sl_renderer_raster(&v->r, cam, err))
            return false;
        v->raster_valid = true;
        v->raster_ms = v->r.timings.raster_ms;
    }
    double t0 = sl_now_seconds();
    switch (v->mode) {
    case VIEW_FINAL:
        if (!sl_renderer_prepare_lighting(&v->r, cam, err) || !view_shade_begin(&v->shade, v->r.desc.threads, err))
            return false;
        v->job_active = true;
        return true;
    case VIEW_MIP:
        if (!sl_renderer_prepare_lighting(&v->r, cam, err) ||
            !view_mip_image(v->r.uniforms, &v->r.gbuffer, &v->shown, &v->mip_max_seen, err))
            return false;
        break;
    default:
        if (!view_channel_image(&v->r.gbuffer, v->mode, v->bounds_lo, v->bounds_hi, cam->znear, cam->zfar, &v->shown,
                                err))
            return false;
        break;
    }
    v->shade_ms = (sl_now_seconds() - t0) * 1e3;
    stage_finished(v);
    return true;
}

/* One slice of the active stage's lighting pass. While the stage has the size of the image on
 * screen, the rows done so far replace the old ones there (tone mapped like the whole image will
 * be); a stage of another size shows up when it is complete. */
static bool stage_continue(viewer *v, double budget_s, sl_error *err)
{
    int first;
    bool done = view_shade_slice(&v->shade, v->r.uniforms, &v->r.gbuffer, &v->r.radiance, budget_s, &first);
    v->shade_ms = v->shade.seconds * 1e3;
    if (!done) {
        const sl_image *rad = &v->r.radiance;
        if (v->shown.data && v->shown.width == rad->width && v->shown.height == rad->height) {
            const sl_tonemap_options *t = &v->r.desc.tonemap;
            for (int y = first; y < v->shade.next_row; y++) {
                const float *src = sl_image_pixel(rad, 0, y);
                float *dst = sl_image_pixel(&v->shown, 0, y);
                for (int i = 0; i < rad->width * 3; i++)
                    dst[i] = sl_tonemap_value(src[i], t->exposure, t->contrast, t->exact_srgb);
            }
            v->texture_stale = true;
            v->present_needed = true;
        }
        return true;
    }
    if (!sl_renderer_tonemap(&v->r, err) || !view_image_copy(&v->shown, &v->r.display, err)) {
        v->job_active = false;
        return false;
    }
    v->tonemap_ms = v->r.timings.tonemap_ms;
    v->radiance_stage = v->job_stage;
    v->retonemap = false; /* the tone map just ran with the current settings */
    stage_finished(v);
    return true;
}

/* A whole stage at once (the preview, and screenshots). */
static bool render_stage(viewer *v, int stage, sl_error *err)
{
    if (!stage_begin(v, stage, err))
        return false;
    while (v->job_active)
        if (!stage_continue(v, 1e30, err))
            return false;
    return true;
}

/* ------------------------------------------------------------------ presenting */

static const char *irradiance_name(sl_irradiance_method m)
{
    return m == SL_IRRADIANCE_MAP ? "map" : m == SL_IRRADIANCE_BRUTE ? "brute" : "sh9";
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
             irradiance_name(l->irradiance), (double)l->env_rotation_deg);
    snprintf(buf[n++], 160, "diffuse %s  specular %s  point lights %s (%d)", l->no_diffuse ? "off" : "on",
             l->no_specular ? "off" : "on", l->no_point_lights ? "off" : "on", v->scene->light_count);
    char res[32];
    if (v->shown_params.div == 1)
        snprintf(res, sizeof res, "full size");
    else
        snprintf(res, sizeof res, "1/%d size", v->shown_params.div);
    if (v->job_active && v->shown.width == v->r.radiance.width && v->shown.height == v->r.radiance.height)
        snprintf(buf[n++], 160, "refining %d/%d: %s, N %d, row %d of %d", v->job_stage + 1, STAGE_COUNT, res,
                 v->job_params.samples, v->shade.next_row, v->r.radiance.height);
    else if (v->job_active)
        snprintf(buf[n++], 160, "refining %d/%d: %s, N %d (next: full size, N %d)", v->shown_stage + 1, STAGE_COUNT,
                 res, v->shown_params.samples, v->job_params.samples);
    else if (converged(v))
        snprintf(buf[n++], 160, "done: %s, N %d", res, v->shown_params.samples);
    else if (interacting(v, now) && v->stage <= 1)
        snprintf(buf[n++], 160, "moving: %s, N %d", res, v->shown_params.samples);
    else
        snprintf(buf[n++], 160, "refining %d/%d: %s, N %d", v->shown_stage + 1, STAGE_COUNT, res,
                 v->shown_params.samples);
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
    "L             mip-level rule: none, spec, spec-d4, gems",
    "K             estimator: spec, consistent",
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
            message(v, true, "SDL texture %dx%d: %s", img->width, img->height, SDL_GetError());
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
    v->present_ms = (sl_now_seconds() - t0) * 1e3;
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
static bool screenshot(viewer *v, const char *name, sl_error *err)
{
    if (!converged(v)) {
        if (!render_stage(v, STAGE_COUNT - 1, err))
            return false;
        v->stage = STAGE_COUNT;
        v->urgent = false;
        present(v);
    }
    if (v->radiance_stage < 0) {
        /* A G-buffer view: light the (current, full-size) G-buffer for the .hdr. */
        v->r.desc.lighting.samples = v->samples;
        if (!sl_renderer_shade(&v->r, &v->camera.cam, err))
            return false;
        v->radiance_stage = STAGE_COUNT - 1;
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
    message(v, false, "wrote %s and %s", png, hdr);
    return true;
}

/* ------------------------------------------------------------------ scenes and drops */

static bool has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && !strcasecmp(s + n - k, suffix);
}

/* Take over a loaded scene and its renderer (the old ones are freed). */
static void adopt_scene(viewer *v, sl_scene *scene, const sl_renderer *r)
{
    if (v->scene) {
        sl_renderer_free(&v->r);
        sl_scene_free(v->scene);
        free(v->scene);
    }
    v->scene = scene;
    v->r = *r;
    v->samples = v->r.desc.lighting.samples;
    if (!sl_scene_bounds(scene, &v->bounds_lo, &v->bounds_hi)) {
        v->bounds_lo = vec3s(-1.0f);
        v->bounds_hi = vec3s(1.0f);
    }
    view_camera_init(&v->camera, &scene->camera);
    v->irradiance_stale = false;
    v->env_replaced = false;
    char title[SL_PATH_MAX + 32];
    snprintf(title, sizeof title, "softlight view - %s", scene->path);
    if (v->window)
        SDL_SetWindowTitle(v->window, title);
    restart_view(v);
}

/* Load a scene and build its renderer at the current size; on failure nothing changes. */
static bool load_scene(viewer *v, const char *path, int width, int height, sl_error *err)
{
    sl_scene *scene = calloc(1, sizeof *scene);
    if (!scene)
        return sl_fail(err, SL_ERR_MEMORY, "out of memory for a scene");
    if (!sl_scene_load(path, scene, err)) {
        free(scene);
        return false;
    }
    sl_render_desc desc = v->cli_desc;
    desc.width = width;
    desc.height = height;
    sl_renderer r;
    if (!sl_renderer_init(&r, scene, &desc, err)) {
        sl_scene_free(scene);
        free(scene);
        return false;
    }
    adopt_scene(v, scene, &r);
    return true;
}

static void handle_drop(viewer *v, const char *path)
{
    sl_error err = {0};
    if (has_suffix(path, ".hdr")) {
        if (!sl_renderer_set_environment(&v->r, path, &err)) {
            message(v, true, "%s (the environment stays)", err.msg);
            return;
        }
        /* The renderer rebuilds the irradiance only while the diffuse term is on. */
        v->irradiance_stale = v->r.desc.lighting.no_diffuse;
        v->env_replaced = true;
        message(v, false, "environment %s", path);
        restart_lighting(v);
    } else if (has_suffix(path, ".json")) {
        if (!load_scene(v, path, v->r.desc.width, v->r.desc.height, &err)) {
            message(v, true, "%s (the scene stays)", err.msg);
            return;
        }
        message(v, false, "scene %s", path);
    } else {
        message(v, true, "%s: drop an .hdr environment or a .json scene", path);
    }
}

/* ------------------------------------------------------------------ input */

static int nav_index(SDL_Keycode key)
{
    switch (key) {
    case SDLK_LEFT: return NAV_LEFT;
    case SDLK_RIGHT: return NAV_RIGHT;
    case SDLK_UP: return NAV_UP;
    case SDLK_DOWN: return NAV_DOWN;
    case SDLK_w: return NAV_W;
    case SDLK_a: return NAV_A;
    case SDLK_s: return NAV_S;
    case SDLK_d: return NAV_D;
    case SDLK_EQUALS: case SDLK_PLUS: case SDLK_KP_PLUS: return NAV_IN;
    case SDLK_MINUS: case SDLK_KP_MINUS: return NAV_OUT;
    default: return -1;
    }
}

/* One step of a navigation key (a press or an auto-repeat). */
static void navigate(viewer *v, int nav, bool fine)
{
    float step = fine ? 0.2f : 1.0f;
    switch (nav) {
    case NAV_LEFT: view_camera_orbit(&v->camera, -ORBIT_KEY_DEG * step, 0.0f); break;
    case NAV_RIGHT: view_camera_orbit(&v->camera, ORBIT_KEY_DEG * step, 0.0f); break;
    case NAV_UP: view_camera_orbit(&v->camera, 0.0f, ORBIT_KEY_DEG * step); break;
    case NAV_DOWN: view_camera_orbit(&v->camera, 0.0f, -ORBIT_KEY_DEG * step); break;
    case NAV_W: view_camera_pan(&v->camera, 0.0f, -PAN_KEY_FRACTION * step); break;
    case NAV_S: view_camera_pan(&v->camera, 0.0f, PAN_KEY_FRACTION * step); break;
    case NAV_A: view_camera_pan(&v->camera, -PAN_KEY_FRACTION * step, 0.0f); break;
    case NAV_D: view_camera_pan(&v->camera, PAN_KEY_FRACTION * step, 0.0f); break;
    case NAV_IN: view_camera_zoom(&v->camera, powf(ZOOM_STEP, step)); break;
    case NAV_OUT: view_camera_zoom(&v->camera, 1.0f / powf(ZOOM_STEP, step)); break;
    default: return;
    }
    restart_view(v);
}

static int power_of_two_step(int n, bool up)
{
    int p = 1;
    while (p < n)
        p *= 2;
    if (up)
        return p == n ? (n < SL_HAMMERSLEY_MAX ? n * 2 : n) : p;
    return p == n ? (n > 1 ? n / 2 : 1) : p / 2;
}

static void cycle_irradiance(viewer *v)
{
    sl_lighting_options *l = &v->r.desc.lighting;
    bool has_map = v->scene->environment.irradiance_path[0] != '\0' && !v->env_replaced;
    sl_irradiance_method next = l->irradiance == SL_IRRADIANCE_SH9     ? SL_IRRADIANCE_BRUTE
                                : l->irradiance == SL_IRRADIANCE_BRUTE ? (has_map ? SL_IRRADIANCE_MAP : SL_IRRADIANCE_SH9)
                                                                       : SL_IRRADIANCE_SH9;
    if (l->no_diffuse) {
        /* Built when the diffuse term comes back on. */
        l->irradiance = next;
        v->irradiance_stale = true;
        message(v, false, "irradiance %s (diffuse is off)", irradiance_name(next));
        return;
    }
    sl_error err = {0};
    if (!sl_renderer_set_irradiance(&v->r, next, &err)) {
        message(v, true, "%s", err.msg);
        return;
    }
    message(v, false, "irradiance %s (%.0f ms)", irradiance_name(next), v->r.timings.irradiance_ms);
    restart_lighting(v);
}

static void toggle_diffuse(viewer *v)
{
    sl_lighting_options *l = &v->r.desc.lighting;
    if (l->no_diffuse && (v->irradiance_stale || !v->r.have_irradiance)) {
        sl_error err = {0};
        sl_irradiance_method method = l->irradiance;
        if (method == SL_IRRADIANCE_MAP && v->env_replaced)
            method = SL_IRRADIANCE_SH9; /* the scene's map belongs to the scene's environment */
        if (!sl_renderer_set_irradiance(&v->r, method, &err)) {
            message(v, true, "%s", err.msg);
            return;
        }
        v->irradiance_stale = false;
    }
    l->no_diffuse = !l->no_diffuse;
    restart_lighting(v);
}

static void handle_key(viewer *v, const SDL_KeyboardEvent *e)
{
    SDL_Keycode key = e->keysym.sym;
    bool shift = (e->keysym.mod & KMOD_SHIFT) != 0;
    sl_lighting_options *l = &v->r.desc.lighting;
    sl_tonemap_options *t = &v->r.desc.tonemap;
    int nav = nav_index(key);
    if (nav >= 0) {
        v->held[nav] = true;
        navigate(v, nav, shift && nav != NAV_IN); /* shift: fine steps ('+' is shift+= on most layouts) */
        return;
    }
    switch (key) { /* adjustments: auto-repeat applies */
    case SDLK_e:
        t->exposure = fminf(t->exposure * EXPOSURE_STEP, 1e6f);
        v->retonemap = true;
        return;
    case SDLK_q:
        t->exposure = fmaxf(t->exposure / EXPOSURE_STEP, 1e-3f);
        v->retonemap = true;
        return;
    case SDLK_c:
        t->contrast = fminf(t->contrast + CONTRAST_STEP, 10.0f);
        v->retonemap = true;
        return;
    case SDLK_x:
        t->contrast = fmaxf(t->contrast - CONTRAST_STEP, 0.1f);
        v->retonemap = true;
        return;
    case SDLK_RIGHTBRACKET:
    case SDLK_LEFTBRACKET: {
        float r = l->env_rotation_deg + (key == SDLK_RIGHTBRACKET ? ENV_ROTATION_STEP : -ENV_ROTATION_STEP);
        r = fmodf(r, 360.0f);
        if (r > 180.0f)
            r -= 360.0f;
        if (r <= -180.0f)
            r += 360.0f;
        l->env_rotation_deg = r;
        restart_lighting(v);
        return;
    }
    default:
        break;
    }
    if (e->repeat)
        return;
    switch (key) { /* toggles and one-shot actions: a held key acts once */
    case SDLK_ESCAPE:
        if (v->show_help)
            v->show_help = false;
        else
            v->quit = true;
        break;
    case SDLK_F1:
    case SDLK_QUESTION:
        v->show_help = !v->show_help;
        break;
    case SDLK_SLASH:
        if (shift)
            v->show_help = !v->show_help;
        break;
    case SDLK_h:
        v->show_hud = !v->show_hud;
        break;
    case SDLK_r:
        view_camera_reset(&v->camera);
        restart_view(v);
        break;
    case SDLK_n:
    case SDLK_b:
        v->samples = power_of_two_step(v->samples, key == SDLK_n);
        restart_lighting(v);
        break;
    case SDLK_1:
        toggle_diffuse(v);
        break;
    case SDLK_2:
        l->no_specular = !l->no_specular;
        restart_lighting(v);
        break;
    case SDLK_3:
        l->no_point_lights = !l->no_point_lights;
        restart_lighting(v);
        break;
    case SDLK_i:
        cycle_irradiance(v);
        break;
    case SDLK_l: {
        sl_lod_rule rule = sl_lighting_options_resolve(l).lod_rule;
        l->lod_rule = rule >= SL_LOD_GEMS ? SL_LOD_NONE : (sl_lod_rule)(rule + 1);
        restart_lighting(v);
        break;
    }
    case SDLK_k: {
        sl_estimator est = sl_lighting_options_resolve(l).estimator;
        l->estimator = est == SL_ESTIMATOR_SPEC ? SL_ESTIMATOR_CONSISTENT : SL_ESTIMATOR_SPEC;
        restart_lighting(v);
        break;
    }
    case SDLK_g: {
        sl_gterm g = sl_lighting_options_resolve(l).gterm;
        l->gterm = g == SL_GTERM_INV_LH2 ? SL_GTERM_ONE : SL_GTERM_INV_LH2;
        restart_lighting(v);
        break;
    }
    case SDLK_v:
        v->mode = (view_mode)((v->mode + (shift ? VIEW_MODE_COUNT - 1 : 1)) % VIEW_MODE_COUNT);
        restart_lighting(v);
        break;
    case SDLK_F12:
    case SDLK_p: {
        sl_error err = {0};
        if (!screenshot(v, NULL, &err))
            message(v, true, "screenshot: %s", err.msg);
        break;
    }
    default:
        return;
    }
    v->present_needed = true;
}

static void handle_event(viewer *v, SDL_Event *e)
{
    double now = sl_now_seconds();
    switch (e->type) {
    case SDL_QUIT:
        v->quit = true;
        break;
    case SDL_WINDOWEVENT:
        switch (e->window.event) {
        case SDL_WINDOWEVENT_SIZE_CHANGED:
        case SDL_WINDOWEVENT_RESIZED:
            v->last_input = now;
            restart_view(v);
            break;
        case SDL_WINDOWEVENT_CLOSE:
            v->quit = true;
            break;
        case SDL_WINDOWEVENT_EXPOSED:
            v->present_needed = true;
            break;
        default:
            break;
        }
        break;
    case SDL_KEYDOWN:
        v->last_input = now;
        handle_key(v, &e->key);
        break;
    case SDL_KEYUP: {
        int nav = nav_index(e->key.keysym.sym);
        if (nav >= 0)
            v->held[nav] = false;
        break;
    }
    case SDL_MOUSEBUTTONDOWN:
        if (e->button.button == SDL_BUTTON_LEFT || e->button.button == SDL_BUTTON_RIGHT ||
            e->button.button == SDL_BUTTON_MIDDLE) {
            v->drag_button = e->button.button;
            v->last_input = now;
        }
        break;
    case SDL_MOUSEBUTTONUP:
        if (e->button.button == v->drag_button) {
            v->drag_button = 0;
            v->last_input = now;
        }
        break;
    case SDL_MOUSEMOTION: {
        if (!v->drag_button || (e->motion.xrel == 0 && e->motion.yrel == 0))
            break;
        int ow, oh;
        SDL_GetWindowSize(v->window, &ow, &oh);
        if (oh < 1)
            oh = 1;
        if (v->drag_button == SDL_BUTTON_LEFT)
            view_camera_orbit(&v->camera, -ORBIT_DEG_PER_PIXEL * (float)e->motion.xrel,
                              ORBIT_DEG_PER_PIXEL * (float)e->motion.yrel);
        else
            view_camera_pan(&v->camera, (float)e->motion.xrel / (float)oh, (float)e->motion.yrel / (float)oh);
        v->last_input = now;
        restart_view(v);
        break;
    }
    case SDL_MOUSEWHEEL: {
        int clicks = e->wheel.direction == SDL_MOUSEWHEEL_FLIPPED ? -e->wheel.y : e->wheel.y;
        if (clicks) {
            view_camera_zoom(&v->camera, powf(ZOOM_STEP, (float)clicks));
            v->last_input = now;
            restart_view(v);
        }
        break;
    }
    case SDL_DROPFILE:
        if (e->drop.file) {
            handle_drop(v, e->drop.file);
            SDL_free(e->drop.file);
        }
        break;
    default:
        break;
    }
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
                restart_view(v);
            }
            break;
        case VIEW_CMD_SCREENSHOT:
            if (pushed)
                return;
            if (!screenshot(v, c->text, &err)) {
                fprintf(stderr, "softlight view: script line %d: screenshot: %s\n", c->line, err.msg);
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

static void adapt_preview(viewer *v, double frame_ms)
{
    if (frame_ms > TARGET_PREVIEW_MS * 1.5 && v->preview_div < MAX_PREVIEW_DIV)
        v->preview_div *= 2;
    else if (frame_ms < TARGET_PREVIEW_MS / 4.0 && v->preview_div > 1)
        v->preview_div /= 2;
}

static bool want_stage(const viewer *v, double now)
{
    bool minimized = (SDL_GetWindowFlags(v->window) & SDL_WINDOW_MINIMIZED) != 0;
    return !minimized && !v->job_active && v->stage < STAGE_COUNT && (v->urgent || !interacting(v, now));
}

static void render_failed(viewer *v, const sl_error *err)
{
    message(v, true, "render: %s", err->msg);
    v->job_active = false;
    v->stage = STAGE_COUNT; /* nothing to gain from retrying the same failure */
    v->urgent = false;
}

static void run(viewer *v)
{
    while (!v->quit) {
        double now = sl_now_seconds();
        if (v->have_script)
            script_step(v, now);
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
                handle_event(v, &e);
        }
        while (!v->quit && SDL_PollEvent(&e))
            handle_event(v, &e);
        if (v->quit)
            break;
        now = sl_now_seconds();
        sl_error err = {0};
        if (v->job_active) {
            if (!stage_continue(v, SLICE_SECONDS, &err))
                render_failed(v, &err);
            else if (!v->job_active)
                v->stage = next_stage(v, v->job_stage);
            present(v);
        } else if (want_stage(v, now)) {
            int stage = v->stage;
            double t0 = sl_now_seconds();
            v->urgent = false;
            /* The preview is small by design and always finishes; later stages are sliced. */
            bool ok = stage == 0 ? render_stage(v, stage, &err) : stage_begin(v, stage, &err);
            if (!ok)
                render_failed(v, &err);
            else if (!v->job_active)
                v->stage = next_stage(v, stage);
            if (ok && stage == 0)
                adapt_preview(v, (sl_now_seconds() - t0) * 1e3);
            present(v);
        } else if (v->retonemap && !v->job_active) {
            v->retonemap = false;
            if (v->mode == VIEW_FINAL && v->radiance_stage >= 0) {
                if (sl_renderer_tonemap(&v->r, &err) && view_image_copy(&v->shown, &v->r.display, &err)) {
                    v->tonemap_ms = v->r.timings.tonemap_ms;
                    v->texture_stale = true;
                } else {
                    message(v, true, "tone map: %s", err.msg);
                }
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
    sl_arg table[SL_RENDER_OPTION_COUNT + 5];
    sl_render_options_table(&opts, table);
    float scale = 1.0f;
    const char *script_path = NULL, *font_path = DEFAULT_FONT;
    int frames = 0;
    bool no_hud = false;
    const sl_arg extra[] = {
        {"--scale", NULL, SL_ARG_FLOAT, &scale, 0.05, 1.0, NULL, "S", "render at S times the window size (default 1)",
         NULL},
        {"--script", NULL, SL_ARG_STRING, &script_path, 0, 0, NULL, "FILE",
         "scripted input, one command a line (docs/viewer.md)", NULL},
        {"--frames", NULL, SL_ARG_INT, &frames, 1, 1000000, NULL, "N", "quit after N frames", NULL},
        {"--font", NULL, SL_ARG_STRING, &font_path, 0, 0, NULL, "TTF", "HUD font (default DejaVu Sans Mono)", NULL},
        {"--no-hud", NULL, SL_ARG_FLAG, &no_hud, 0, 0, NULL, NULL, "start with the heads-up display hidden", NULL},
    };
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
    v.preview_div = 2;
    v.radiance_stage = -1;
    v.shown_stage = -1;
    if (script_path) {
        if (!view_script_load(script_path, &v.script, &err)) {
            fprintf(stderr, "softlight view: %s\n", err.msg);
            return 2;
        }
        v.have_script = true;
    }

    char why[256];
    bool display = display_available(why, sizeof why);
    if (!display || SDL_Init(SDL_INIT_VIDEO) != 0) {
        if (display)
            snprintf(why, sizeof why, "SDL: %s", SDL_GetError());
        fprintf(stderr, "softlight view: no display (%s); use softlight render %s -o out.png\n", why, scene_path[0]);
        view_script_free(&v.script);
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
    adopt_scene(&v, scene, &r);
    if (r.env_repairs.nan_count || r.env_repairs.inf_count || r.env_repairs.negative_count)
        message(&v, true, "%s: %ld NaN, %ld Inf, %ld negative texels read as 0", scene->environment.hdr_path,
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
