/* cmd_view.c - `softlight view scene.json`: the interactive SDL2 viewer's command and loop.
 *
 * One thread runs the loop: script commands -> SDL events -> at most one render step ->
 * present. The pipeline itself is parallel (OpenMP inside raster and shading), so the loop
 * stays simple and every finished frame is the one `softlight render` would make for that camera.
 *
 * This file owns the order of a turn and nothing else: what the stages are and how they render
 * is view_refine.c (docs/viewer.md "Refinement"), what the window shows is view_present.c, and
 * input (view_input.c) only changes state and answers a view_action, which act() below takes
 * before the next event. Every file of the viewer and the state they share are listed in
 * view_internal.h. Without SDL2 the command prints one line and exits 2. */
#if SL_HAVE_SDL2
#include <SDL.h>
#endif

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "app/args.h"
#include "app/commands.h"
#include "app/render_options.h"
#include "core/timer.h"
#include "softlight/data.h"
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
#define MOVE_SAMPLES 8           /* default N while moving (docs/viewer.md "Refinement": measured) */
#define PRESENT_IDLE_SECONDS 0.1 /* between slices that changed no pixel, present this often */
#define VIEW_OPTION_COUNT 17     /* options of `view` beside render's */
#define DEFAULT_SCENE "scenes/default.json" /* what `softlight view ENV.hdr` lights */

/* ------------------------------------------------------------------ the loop */

/* Take what an event asks for, before the next event is handled (so a key sequence acts in
 * order, as it did when input restarted the refinement itself). */
static void act(viewer *v, view_action a)
{
    sl_error err = {0};
    switch (a) {
    case VIEW_ACT_RESTART_CAMERA:
        view_restart_camera(v);
        break;
    case VIEW_ACT_RESTART_LIGHTING:
        view_restart_lighting(v);
        break;
    case VIEW_ACT_SCREENSHOT:
        if (!view_screenshot(v, NULL, &err))
            view_message(v, true, "screenshot: %s", err.msg);
        break;
    case VIEW_ACT_NONE:
        break;
    }
}

static void render_failed(viewer *v, const sl_error *err)
{
    view_message(v, true, "render: %s", err->msg);
    view_refine_stop(v);
}

/* A watched file changed: load the scene again, keeping the camera (unless it is the scene's
 * own, which then follows the file) and the view. On failure the old scene stays. */
static void reload(viewer *v)
{
    view_camera old = v->camera;
    view_mode mode = v->mode;
    char path[SL_PATH_MAX];
    snprintf(path, sizeof path, "%s", v->scene->path);
    sl_error err = {0};
    if (!view_load_scene(v, path, &err)) {
        view_message(v, true, "reload: %s (the scene stays)", err.msg);
        return;
    }
    if (!old.at_home)
        view_camera_carry(&v->camera, &old);
    v->mode = mode;
    view_trace_free(v);
    view_message(v, false, "reloaded %s", path);
    view_restart_camera(v);
}

static void run(viewer *v)
{
    v->bench.last_present = sl_now_seconds();
    while (!v->quit) {
        double now = sl_now_seconds();
        if (v->have_script)
            view_script_step(v, now);
        if (v->bench.frames > 0)
            view_bench_input(v, now);
        if (view_watch_changed(&v->watch, now))
            reload(v);
        view_program_poll(v, now);
        bool message_expired = v->message_shown && now >= v->message_until;
        bool busy = v->job_active || view_refine_wanted(v, now) || v->retonemap || v->present_needed ||
                    message_expired || view_gl_wanted(v);
        SDL_Event e;
        if (!busy) {
            /* Idle: sleep until input, but wake for the script, the end of a quiet period and the
             * message's expiry. */
            double wake = 0.25;
            if (v->have_script && v->script.next < v->script.count)
                wake = v->script.waiting ? fmax(0.001, v->script.wait_until - now) : 0.005;
            if (v->stage < VIEW_STAGE_COUNT)
                wake = fmin(wake, fmax(0.005, v->last_input + VIEW_QUIET_SECONDS - now));
            if (v->message_shown)
                wake = fmin(wake, fmax(0.005, v->message_until - now));
            if (v->watch.count)
                wake = fmin(wake, fmax(0.005, v->watch.next_poll - now));
            wake = fmin(wake, fmax(0.005, view_program_wake(v, now)));
            if (SDL_WaitEventTimeout(&e, (int)(wake * 1000.0) + 1))
                act(v, view_handle_event(v, &e));
        }
        while (!v->quit && SDL_PollEvent(&e))
            act(v, view_handle_event(v, &e));
        if (v->quit)
            break;
        now = sl_now_seconds();
        sl_error err = {0};
        if (v->job_active) {
            if (!view_refine_continue(v, &err))
                render_failed(v, &err);
            /* Between slices that changed nothing on screen, the HUD's progress needs no more
             * than a present every PRESENT_IDLE_SECONDS (a present costs milliseconds). */
            if (v->texture_stale || v->present_needed || !v->job_active ||
                sl_now_seconds() - v->last_present >= PRESENT_IDLE_SECONDS)
                view_present(v);
        } else if (view_refine_wanted(v, now)) {
            bool moving = v->stage == VIEW_STAGE_MOVING;
            double t0 = sl_now_seconds();
            bool ok = view_refine_start(v, &err);
            if (!ok)
                render_failed(v, &err);
            view_present(v);
            if (ok && moving) {
                double t1 = sl_now_seconds();
                view_refine_moved(v, (t1 - t0) * 1e3);
                if (v->bench.frames > 0)
                    view_bench_record(v, t1);
            }
        } else if (view_gl_wanted(v)) {
            if (view_gl_will_run(v)) { /* it blocks for about a second: say so first */
                view_message(v, false, "compare: softlight-gl is lighting this frame");
                view_present(v);
            }
            if (!view_gl_step(v, &err))
                view_message(v, true, "compare: %s", err.msg);
            view_present(v);
        } else if (v->retonemap && !v->job_active) {
            if (!view_refine_retonemap(v, &err))
                view_message(v, true, "tone map: %s", err.msg);
            view_present(v);
        } else if (v->present_needed || (v->message_shown && now >= v->message_until)) {
            view_present(v);
        }
    }
}

/* ------------------------------------------------------------------ setup */

static bool env_set(const char *name)
{
    const char *s = getenv(name);
    return s && s[0];
}

/* Whether a display can be asked for, and which drivers SDL may try. SDL_VIDEODRIVER names a
 * driver explicitly (offscreen, dummy, kmsdrm): SDL decides. Otherwise only the drivers whose
 * display variable is set are tried, so a DISPLAY with no server behind it fails here instead
 * of falling through to SDL's offscreen driver (a window nobody sees, forever). */
static bool display_available(char *why, size_t size)
{
    bool display = env_set("DISPLAY"), wayland = env_set("WAYLAND_DISPLAY");
    if (env_set("SDL_VIDEODRIVER"))
        return true;
    if (!display && !wayland) {
        snprintf(why, size, "neither DISPLAY nor WAYLAND_DISPLAY is set");
        return false;
    }
    SDL_SetHint("SDL_VIDEODRIVER", display && wayland ? "x11,wayland" : display ? "x11" : "wayland");
    return true;
}

/* After SDL_Init: false when SDL opened no real video driver (offscreen, dummy) that the user
 * did not ask for. */
static bool real_driver(char *why, size_t size)
{
    const char *name = SDL_GetCurrentVideoDriver();
    if (env_set("SDL_VIDEODRIVER") && name)
        return true;
    if (name && strcmp(name, "offscreen") && strcmp(name, "dummy") && strcmp(name, "evdev"))
        return true;
    const char *display = getenv("DISPLAY"), *wayland = getenv("WAYLAND_DISPLAY");
    snprintf(why, size, "no X server at DISPLAY=%s%s%s; SDL found only %s", display ? display : "",
             wayland && wayland[0] ? " and no compositor at WAYLAND_DISPLAY=" : "", wayland && wayland[0] ? wayland : "",
             name ? name : "no video driver");
    return false;
}

/* The window starts at --size, else the scene's size, shrunk (aspect kept) to fit the screen. */
static void initial_window_size(const sl_render_options *o, const sl_scene *scene, float scale, int *w, int *h)
{
    if (sl_option_is_set(&o->values, SL_OPT_SIZE)) {
        *w = o->values.size[0];
        *h = o->values.size[1];
        return;
    }
    *w = (int)lroundf((float)scene->options.size[0] / scale);
    *h = (int)lroundf((float)scene->options.size[1] / scale);
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
    view_watch_free(&v->watch);
    view_program_close(v);
    view_gl_free(v);
    view_trace_free(v);
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
    view_bench_free(&v->bench);
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
    const int n = sl_render_options_table(&opts, table);
    float scale = 1.0f;
    const char *script_path = NULL, *font_path = DEFAULT_FONT;
    int frames = 0, move_samples = MOVE_SAMPLES, move_div = 0, bench_frames = 0;
    int acc_lod = 0;  /* index in "total|frame" */
    int move_est = 0; /* index in "splitsum|user" */
    bool no_hud = false, keys = false, debug_shader = false, verbose = false;
    const char *env = NULL, *lighting = NULL, *gbuffer_shader = NULL, *glsl = NULL;
    const sl_arg extra[] = {
        {"--env", NULL, SL_ARG_STRING, &env, 0, 0, NULL, "FILE",
         "environment image (.exr, .hdr or .pfm) in place of the scene's, and no irradiance map", NULL},
        {"--keys", NULL, SL_ARG_FLAG, &keys, 0, 0, NULL, NULL, "print the key table (markdown, as docs/viewer.md) and exit",
         NULL},
        {"--scale", NULL, SL_ARG_FLOAT, &scale, 0.05, 1.0, NULL, "S", "render at S times the window size (default 1)",
         NULL},
        {"--script", NULL, SL_ARG_STRING, &script_path, 0, 0, NULL, "FILE",
         "scripted input, one command a line (docs/viewer.md)", NULL},
        {"--frames", NULL, SL_ARG_INT, &frames, 1, 1000000, NULL, "N", "quit after N frames", NULL},
        {"--font", NULL, SL_ARG_STRING, &font_path, 0, 0, NULL, "TTF", "HUD font (default DejaVu Sans Mono)", NULL},
        {"--no-hud", NULL, SL_ARG_FLAG, &no_hud, 0, 0, NULL, NULL, "start with the heads-up display hidden", NULL},
        {"--move-estimator", NULL, SL_ARG_CHOICE, &move_est, 0, 0, "splitsum|user", NULL,
         "while moving, light with the split sum (default) or the user's estimator with --move-samples", NULL},
        {"--move-samples", NULL, SL_ARG_INT, &move_samples, 1, SL_HAMMERSLEY_MAX, NULL, "N",
         "with --move-estimator user: samples N while the camera moves (default 8, rotated per frame)", NULL},
        {"--move-div", NULL, SL_ARG_INT, &move_div, 1, VIEW_MAX_PREVIEW_DIV, NULL, "D",
         "while moving, render at 1/D of the window per axis (default: adapts, starting at 1; 2 with "
         "--move-estimator user)",
         NULL},
        {"--benchmark", NULL, SL_ARG_INT, &bench_frames, 1, 100000, NULL, "FRAMES",
         "orbit for FRAMES moving frames, print the frame times and quit", NULL},
        {"--accumulate-lod", NULL, SL_ARG_CHOICE, &acc_lod, 0, 0, "total|frame", NULL,
         "mip levels of accumulation frames: as for the total N (default) or for the frame's own N", NULL},
        {"--lighting", NULL, SL_ARG_STRING, &lighting, 0, 0, NULL, "FILE",
         "shade with this lighting program, as render does; a C source is recompiled when it is saved "
         "(docs/lighting-programs.md)", NULL},
        {"--glsl", NULL, SL_ARG_STRING, &glsl, 0, 0, NULL, "FILE.frag",
         "the GLSL twin of --lighting, which the comparison with the GL version (M) runs in softlight-gl", NULL},
        {"--gbuffer-shader", NULL, SL_ARG_STRING, &gbuffer_shader, 0, 0, NULL, "FILE",
         "fill the G-buffer with this fragment program, as render does; a C source is recompiled when it is "
         "saved (docs/gbuffer-programs.md)", NULL},
        {"--debug-shader", NULL, SL_ARG_FLAG, &debug_shader, 0, 0, NULL, NULL,
         "compile the --lighting and --gbuffer-shader sources with -g -O0, for a debugger", NULL},
        {"--verbose", "-v", SL_ARG_FLAG, &verbose, 0, 0, NULL, NULL,
         "print the --lighting and --gbuffer-shader compiler commands and each recompile's time", NULL},
    };
    _Static_assert(sizeof extra / sizeof extra[0] == VIEW_OPTION_COUNT, "VIEW_OPTION_COUNT is the size of extra[]");
    memcpy(table + n, extra, sizeof extra);
    const int count = n + (int)(sizeof extra / sizeof extra[0]);
    const char *usage = "softlight view SCENE.json|MODEL|ENV.hdr [options]   (--size: the window's size)";
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
    if (keys) {
        view_keys_markdown(stdout);
        return 0;
    }
    if (npos != 1) {
        fprintf(stderr, "softlight view: expected one scene file (see --help)\n");
        return 2;
    }
    /* An environment alone: the default scene under it. */
    char default_scene[SL_PATH_MAX];
    if (view_is_environment(scene_path[0])) {
        if (env) {
            fprintf(stderr, "softlight view: %s is an environment and --env names another\n", scene_path[0]);
            return 2;
        }
        if (!sl_data_path(DEFAULT_SCENE, default_scene, sizeof default_scene)) {
            fprintf(stderr,
                    "softlight view: %s: no default scene: softlight's data directory (shaders/, scenes/) was not "
                    "found; set SOFTLIGHT_DATA_DIR\n",
                    scene_path[0]);
            return 2;
        }
        env = scene_path[0];
        scene_path[0] = default_scene;
    }
    if (!sl_render_options_desc(&opts, &desc, &err)) {
        fprintf(stderr, "softlight view: %s\n", err.msg);
        return 2;
    }
    viewer v = {0};
    v.cli_desc = desc;
    snprintf(v.env_override, sizeof v.env_override, "%s", env ? env : "");
    v.pointer_x = v.pointer_y = -1;
    v.scale = scale;
    v.max_frames = frames;
    v.show_hud = !no_hud;
    v.acc_total_lod = acc_lod == 0;
    v.move_samples = move_samples;
    v.move_user = move_est == 1;
    v.fixed_div = move_div;
    /* the split sum lights a full-size frame within the budget on the shipped scenes; the
     * adaptive divisor (view_refine_moved) still halves it for a heavy mesh */
    v.preview_div = move_div ? move_div : v.move_user ? 2 : 1;
    v.shown_stage = -1;
    if (script_path) {
        if (!view_script_load(script_path, &v.script, &err)) {
            fprintf(stderr, "softlight view: %s\n", err.msg);
            return 2;
        }
        v.have_script = true;
    }
    struct stat glsl_stat;
    if (glsl && (!lighting || stat(glsl, &glsl_stat) != 0 || !S_ISREG(glsl_stat.st_mode))) {
        fprintf(stderr, "softlight view: --glsl %s: %s\n", glsl,
                !lighting ? "the GLSL twin of a --lighting program, which is not given" : "not a readable file");
        view_script_free(&v.script);
        return 2;
    }
    v.gl.glsl = glsl;
    /* only the command line names code to run; a scene never does */
    const char *programs[VIEW_PROGRAM_KINDS] = {[VIEW_PROGRAM_LIGHTING] = lighting,
                                                [VIEW_PROGRAM_GBUFFER] = gbuffer_shader};
    for (int k = 0; k < VIEW_PROGRAM_KINDS; k++) {
        char msg[1200];
        if (programs[k] &&
            !view_program_open(&v, (view_program_kind)k, programs[k], debug_shader, verbose, msg, sizeof msg)) {
            fprintf(stderr, "softlight view: %s\n", msg);
            view_script_free(&v.script);
            view_program_close(&v);
            return 2;
        }
    }
    if (bench_frames > 0 && !view_bench_init(&v.bench, bench_frames, &err)) {
        fprintf(stderr, "softlight view: %s\n", err.msg);
        view_script_free(&v.script);
        view_bench_free(&v.bench);
        view_program_close(&v);
        return 2;
    }

    char why[256];
    bool display = display_available(why, sizeof why);
    bool sdl_up = false;
    if (display) {
        sdl_up = SDL_Init(SDL_INIT_VIDEO) == 0;
        if (!sdl_up) {
            const char *d = getenv("DISPLAY");
            snprintf(why, sizeof why, "%s%s%sSDL: %s", d && d[0] ? "DISPLAY=" : "", d && d[0] ? d : "",
                     d && d[0] ? ": " : "", SDL_GetError());
        }
        display = sdl_up && real_driver(why, sizeof why);
    }
    if (!display) {
        if (sdl_up)
            SDL_Quit();
        fprintf(stderr, "softlight view: no display (%s); use softlight render %s -o out.png\n", why, scene_path[0]);
        view_script_free(&v.script);
        view_bench_free(&v.bench);
        view_program_close(&v);
        return 2;
    }
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "1");
    /* SDL's software renderer draws into the window's own surface and presents it with
     * SDL_UpdateWindowSurface; with framebuffer acceleration off that surface is shared memory
     * put to the X server (XShmPutImage), no GL at all (else SDL backs it with a GL texture
     * again). Under Xvfb, where GL is Mesa's software GL, this presents a 1280x720 frame several
     * times faster (docs/viewer.md "Presenting"). A user's SDL_RENDER_DRIVER or
     * SDL_FRAMEBUFFER_ACCELERATION still wins (SDL: the environment beats a hint set at normal
     * priority), e.g. SDL_RENDER_DRIVER=opengl on a machine with a GPU. */
    SDL_SetHint(SDL_HINT_RENDER_DRIVER, "software");
    SDL_SetHint(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0");
    SDL_StopTextInput();

    int status = 2;
    sl_scene *scene;
    if (!view_read_scene(scene_path[0], env, &desc.options, &scene, &err)) {
        fprintf(stderr, "softlight view: %s\n", err.msg);
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
    sl_renderer r;
    sl_render_desc first = v.cli_desc;
    int first_w, first_h;
    view_render_size(&v, 1, &first_w, &first_h);
    sl_option_set_size(&first.options, first_w, first_h);
    if (!sl_renderer_init(&r, scene, &first, &err)) {
        fprintf(stderr, "softlight view: %s\n", err.msg);
        sl_scene_free(scene);
        free(scene);
        goto done;
    }
    view_adopt_scene(&v, scene, &r);
    view_restart_camera(&v);
    if (!view_watch_scene(&v.watch, scene, env, &err))
        fprintf(stderr, "softlight view: %s (no reloading)\n", err.msg);
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
