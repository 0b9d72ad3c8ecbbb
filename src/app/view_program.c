/* view_program.c - `softlight view --lighting my.c --gbuffer-shader my_gb.c`: the user's lighting
 * program and G-buffer program, live (the contract is in view_internal.h).
 *
 * Each program is loaded as `softlight render` loads it (program_load.c: compiled, cached by
 * content, dlopened), so every frame is drawn by the same code render runs. Each source is polled
 * with the scene's watcher (view_reload.c, every VIEW_POLL_SECONDS); a change starts a compile on
 * a thread of its own, so the window keeps drawing with the last good program. The loop polls the
 * thread once a turn: a program that loaded is swapped in between frames (a lighting program
 * restarts the lighting and the G-buffer stays; a G-buffer program restarts from the raster); a
 * compile error stays in the HUD, and on stderr, until a later save compiles. A changed source
 * loads from a new cached object (the cache is keyed by content), so dlopen never hands back the
 * old one; old objects stay loaded. */
#define _POSIX_C_SOURCE 200809L
#if SL_HAVE_SDL2

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "app/gbuffer_load.h"
#include "app/lighting_load.h"
#include "core/timer.h"
#include "view_internal.h"

enum { MSG_SIZE = 1200 };

struct view_program_state {
    view_program_kind kind;
    char path[SL_PATH_MAX];
    sl_program_load_options opt;
    view_watch watch;
    char error[MSG_SIZE];      /* the last compile's error ("": none), shown until one succeeds */

    /* the compile in flight: the thread writes result, ok and msg, then sets done */
    pthread_t thread;
    bool running;
    atomic_int done;
    const void *result;        /* an sl_lighting_program or an sl_gbuffer_fragment_program */
    bool ok;
    char msg[MSG_SIZE];
    double started;            /* sl_now_seconds */
    double saved_at;           /* the source's mtime (CLOCK_REALTIME seconds) when it started */
    bool again;                /* the source changed while compiling */

    /* from the swap to the first frame lit in full with the new program, presented */
    bool measuring;
    double swap_saved_at, swap_time, compile_s;
};

static double realtime_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double mtime_seconds(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return realtime_now();
    return (double)st.st_mtim.tv_sec + 1e-9 * (double)st.st_mtim.tv_nsec;
}

/* Load p->path as its kind into *out. */
static bool load(const view_program_state *p, const void **out, char *msg, size_t msg_size)
{
    if (p->kind == VIEW_PROGRAM_GBUFFER) {
        const sl_gbuffer_fragment_program *g;
        if (!sl_gbuffer_program_load(p->path, &p->opt, &g, msg, msg_size))
            return false;
        *out = g;
        return true;
    }
    const sl_lighting_program *l;
    if (!sl_lighting_load(p->path, &p->opt, &l, msg, msg_size))
        return false;
    *out = l;
    return true;
}

static void *compile_thread(void *arg)
{
    view_program_state *p = arg;
    p->msg[0] = '\0';
    p->ok = load(p, &p->result, p->msg, sizeof p->msg);
    atomic_store(&p->done, 1);
    return NULL;
}

/* The program into the settings: the command line's (for scenes dropped later) and the renderer's. */
static void set_program(viewer *v, view_program_kind kind, const void *program)
{
    if (kind == VIEW_PROGRAM_GBUFFER) {
        v->cli_desc.gbuffer_program = program;
        if (v->scene)
            v->r.desc.gbuffer_program = program;
    } else {
        v->cli_desc.lighting_program = program;
        if (v->scene)
            v->r.desc.lighting_program = program;
    }
}

static void compile_start(view_program_state *p)
{
    p->saved_at = mtime_seconds(p->path);
    p->started = sl_now_seconds();
    p->again = false;
    atomic_store(&p->done, 0);
    if (pthread_create(&p->thread, NULL, compile_thread, p) != 0) {
        snprintf(p->error, sizeof p->error, "%s: could not start a thread to compile it", p->path);
        fprintf(stderr, "softlight view: %s\n", p->error);
        return;
    }
    p->running = true;
}

bool view_program_open(viewer *v, view_program_kind kind, const char *path, bool debug, bool verbose, char *msg,
                       size_t msg_size)
{
    view_program_state *p = calloc(1, sizeof *p);
    if (!p) {
        snprintf(msg, msg_size, "out of memory");
        return false;
    }
    p->kind = kind;
    snprintf(p->path, sizeof p->path, "%s", path);
    p->opt = (sl_program_load_options){.debug = debug, .verbose = verbose};
    const void *program;
    if (!load(p, &program, msg, msg_size)) {
        free(p);
        return false;
    }
    sl_error err = {0};
    if (!view_watch_file(&p->watch, path, &err))
        fprintf(stderr, "softlight view: %s (%s is not watched)\n", err.msg, path);
    set_program(v, kind, program);
    v->programs[kind] = p;
    return true;
}

static void swap_in(viewer *v, view_program_state *p, const void *program)
{
    set_program(v, p->kind, program);
    if (v->scene) {
        if (p->kind == VIEW_PROGRAM_GBUFFER)
            view_restart_camera(v); /* the G-buffer is drawn again */
        else
            view_restart_lighting(v);
    }
    v->frame_lit = false;
    p->measuring = true;
    p->swap_saved_at = p->saved_at;
    p->swap_time = sl_now_seconds();
}

static void poll_one(viewer *v, view_program_state *p, double now)
{
    if (view_watch_changed(&p->watch, now)) {
        if (p->running)
            p->again = true;
        else
            compile_start(p);
    }
    if (p->running && atomic_load(&p->done)) {
        pthread_join(p->thread, NULL);
        p->running = false;
        p->compile_s = sl_now_seconds() - p->started;
        if (p->ok) {
            p->error[0] = '\0';
            swap_in(v, p, p->result);
            if (p->opt.verbose)
                fprintf(stderr, "softlight view: %s: compiled and loaded in %.0f ms\n", p->path, p->compile_s * 1e3);
        } else {
            snprintf(p->error, sizeof p->error, "%s", p->msg);
            fprintf(stderr, "softlight view: %s (the last good program keeps running)\n", p->error);
        }
        if (p->again)
            compile_start(p);
    }
    /* The frame was presented in the turn that lit it: its present time is v->last_present. */
    if (p->measuring && v->frame_lit && v->last_present >= p->swap_time) {
        p->measuring = false;
        double latency = realtime_now() - (sl_now_seconds() - v->last_present) - p->swap_saved_at;
        fprintf(stderr, "softlight view: %s: on screen %.0f ms after it was saved (compile %.0f ms)\n", p->path,
                latency * 1e3, p->compile_s * 1e3);
    }
}

void view_program_poll(viewer *v, double now)
{
    for (int k = 0; k < VIEW_PROGRAM_KINDS; k++)
        if (v->programs[k])
            poll_one(v, v->programs[k], now);
}

void view_program_hud(const viewer *v, bool compact, char *buf, size_t size)
{
    static const char *const names[VIEW_PROGRAM_KINDS] = {"lighting program", "G-buffer program"};
    buf[0] = '\0';
    size_t n = 0;
    for (int k = 0; k < VIEW_PROGRAM_KINDS; k++) {
        const view_program_state *p = v->programs[k];
        if (!p)
            continue;
        if (n < size && !compact)
            n += (size_t)snprintf(buf + n, size - n, "%s %s%s\n", names[k], p->path, p->running ? " (compiling)" : "");
        if (n < size && p->error[0])
            n += (size_t)snprintf(buf + n, size - n, "compile error: %s (the last good program runs)\n", p->error);
    }
    if (n < size && v->programs[VIEW_PROGRAM_LIGHTING] && v->shown_nonfinite > 0 && v->mode == VIEW_FINAL)
        snprintf(buf + n, size - n, "%lld pixels NaN/Inf (magenta)\n", (long long)v->shown_nonfinite);
}

double view_program_wake(const viewer *v, double now)
{
    double wake = 1e9;
    for (int k = 0; k < VIEW_PROGRAM_KINDS; k++) {
        const view_program_state *p = v->programs[k];
        if (!p)
            continue;
        if (p->running || p->measuring)
            return 0.005;
        if (p->watch.count)
            wake = fmin(wake, p->watch.next_poll - now);
    }
    return wake;
}

void view_program_close(viewer *v)
{
    for (int k = 0; k < VIEW_PROGRAM_KINDS; k++) {
        view_program_state *p = v->programs[k];
        if (!p)
            continue;
        if (p->running)
            pthread_join(p->thread, NULL);
        view_watch_free(&p->watch);
        free(p);
        v->programs[k] = NULL;
    }
}

#else
typedef int view_program_unused; /* this file is only built with SDL2 */
#endif
