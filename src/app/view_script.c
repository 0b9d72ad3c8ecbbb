/* view_script.c - `softlight view --script FILE`: reading the script, and running it a turn of
 * the loop at a time (view_script_step) (the contract is in view_internal.h).
 *
 * Why a script instead of xdotool: under Xvfb with no window manager, synthetic X input races
 * the window's mapping and focus; events pushed onto SDL's own queue go through exactly the
 * handlers a user's mouse and keyboard reach, in order, with no timing luck. One command a line:
 *
 *     # comment
 *     wait 500                    let 500 ms pass (frames keep running)
 *     settle                      wait until refinement has finished (and the GL comparison, M)
 *     drag 100 100 200 100        left-button drag (add right|middle, and a step count)
 *     move 10 20                  pointer motion, no button
 *     wheel 3                     three wheel clicks away from the user (zoom in)
 *     key r   key shift+e   key F1   key Up      press and release (SDL key names)
 *     keydown Left / keyup Left   hold and release
 *     resize 1 1                  set the window size
 *     drop scenes/envmaps/city.hdr    a file dropped on the window
 *     screenshot out/shot         out/shot.png and out/shot.hdr (no name: softlight-<n>)
 *     quit                        as closing the window
 *     accumulated 4               wait until the still camera's mean holds 4 frames
 *     snapshot out/acc4           out/acc4.png and out/acc4.pfm of what is on screen now
 *     readout                     print the readout of the pixel under the pointer (9 digits)
 *
 * Everything is checked when the file is read, so a typo fails before a window opens. Running
 * it, input commands become SDL events and go through view_input.c like a user's; the others
 * ask the refinement (settle, accumulated) or write files (view_screenshot.c). */
#if SL_HAVE_SDL2

#include <SDL.h>

#include "view_internal.h"

#include <ctype.h>
#include <stdio.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#define SCRIPT_MAX_BYTES ((size_t)1 << 24)
#define MAX_WAIT_MS 600000

static const struct {
    const char *name;
    view_cmd_kind kind;
} commands[] = {
    {"wait", VIEW_CMD_WAIT},       {"settle", VIEW_CMD_SETTLE},   {"drag", VIEW_CMD_DRAG},
    {"move", VIEW_CMD_MOVE},       {"wheel", VIEW_CMD_WHEEL},     {"key", VIEW_CMD_KEY},
    {"keydown", VIEW_CMD_KEYDOWN}, {"keyup", VIEW_CMD_KEYUP},     {"resize", VIEW_CMD_RESIZE},
    {"drop", VIEW_CMD_DROP},       {"screenshot", VIEW_CMD_SCREENSHOT}, {"quit", VIEW_CMD_QUIT},
    {"accumulated", VIEW_CMD_ACCUMULATED}, {"snapshot", VIEW_CMD_SNAPSHOT}, {"readout", VIEW_CMD_READOUT},
};

/* ------------------------------------------------------------------ reading */

static bool parse_int(const char *s, long min, long max, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < min || v > max)
        return false;
    *out = (int)v;
    return true;
}

/* "shift+ctrl+e" -> key 'e' with modifiers. */
static bool parse_key(const char *word, int *key, int *mod)
{
    *mod = KMOD_NONE;
    for (;;) {
        const char *plus = strchr(word, '+');
        if (!plus || plus == word || plus[1] == '\0')
            break;
        size_t n = (size_t)(plus - word);
        if (n == 5 && !SDL_strncasecmp(word, "shift", 5))
            *mod |= KMOD_LSHIFT;
        else if (n == 4 && !SDL_strncasecmp(word, "ctrl", 4))
            *mod |= KMOD_LCTRL;
        else if (n == 3 && !SDL_strncasecmp(word, "alt", 3))
            *mod |= KMOD_LALT;
        else
            return false;
        word = plus + 1;
    }
    *key = (int)SDL_GetKeyFromName(word);
    return *key != SDLK_UNKNOWN;
}

/* Split `line` into at most 8 words in place; returns the count. */
static int split(char *line, char **words)
{
    int n = 0;
    char *p = line;
    while (*p && n < 8) {
        while (*p && isspace((unsigned char)*p))
            p++;
        if (!*p)
            break;
        words[n++] = p;
        while (*p && !isspace((unsigned char)*p))
            p++;
        if (*p)
            *p++ = '\0';
    }
    return n;
}

static bool parse_line(char *line, const char *path, int lineno, view_cmd *cmd, sl_error *err)
{
    char rest_copy[SL_PATH_MAX];
    char *words[8];
    /* Keep the untouched tail for DROP and SCREENSHOT before split() cuts it into words. */
    {
        const char *p = line;
        while (*p && isspace((unsigned char)*p))
            p++;
        while (*p && !isspace((unsigned char)*p))
            p++;
        while (*p && isspace((unsigned char)*p))
            p++;
        size_t n = strlen(p);
        while (n && isspace((unsigned char)p[n - 1]))
            n--;
        if (n >= sizeof rest_copy)
            return sl_fail(err, SL_ERR_RANGE, "%s:%d: argument longer than %zu bytes", path, lineno, sizeof rest_copy - 1);
        memcpy(rest_copy, p, n);
        rest_copy[n] = '\0';
    }
    int n = split(line, words);
    memset(cmd, 0, sizeof *cmd);
    cmd->line = lineno;
    int k = 0, count = (int)(sizeof commands / sizeof commands[0]);
    while (k < count && strcmp(commands[k].name, words[0]))
        k++;
    if (k == count)
        return sl_fail(err, SL_ERR_FORMAT, "%s:%d: unknown command '%s'", path, lineno, words[0]);
    cmd->kind = commands[k].kind;
    int argc = n - 1;
    char **argv = words + 1;
    switch (cmd->kind) {
    case VIEW_CMD_WAIT:
        if (argc != 1 || !parse_int(argv[0], 0, MAX_WAIT_MS, &cmd->args[0]))
            return sl_fail(err, SL_ERR_FORMAT, "%s:%d: expected 'wait MS' with MS in 0..%d", path, lineno,
                           MAX_WAIT_MS);
        return true;
    case VIEW_CMD_SETTLE:
    case VIEW_CMD_QUIT:
    case VIEW_CMD_READOUT:
        if (argc != 0)
            return sl_fail(err, SL_ERR_FORMAT, "%s:%d: '%s' takes no arguments", path, lineno, words[0]);
        return true;
    case VIEW_CMD_DRAG: {
        bool ok = argc >= 4 && argc <= 6;
        for (int i = 0; ok && i < 4; i++)
            ok = parse_int(argv[i], -100000, 100000, &cmd->args[i]);
        cmd->args[4] = SDL_BUTTON_LEFT;
        cmd->args[5] = 10;
        for (int i = 4; ok && i < argc; i++) {
            if (!strcmp(argv[i], "left"))
                cmd->args[4] = SDL_BUTTON_LEFT;
            else if (!strcmp(argv[i], "right"))
                cmd->args[4] = SDL_BUTTON_RIGHT;
            else if (!strcmp(argv[i], "middle"))
                cmd->args[4] = SDL_BUTTON_MIDDLE;
            else
                ok = parse_int(argv[i], 1, 10000, &cmd->args[5]);
        }
        if (!ok)
            return sl_fail(err, SL_ERR_FORMAT, "%s:%d: expected 'drag X0 Y0 X1 Y1 [left|right|middle] [STEPS]'", path,
                           lineno);
        return true;
    }
    case VIEW_CMD_MOVE:
        if (argc != 2 || !parse_int(argv[0], -100000, 100000, &cmd->args[0]) ||
            !parse_int(argv[1], -100000, 100000, &cmd->args[1]))
            return sl_fail(err, SL_ERR_FORMAT, "%s:%d: expected 'move X Y'", path, lineno);
        return true;
    case VIEW_CMD_WHEEL:
        if (argc != 1 || !parse_int(argv[0], -1000, 1000, &cmd->args[0]))
            return sl_fail(err, SL_ERR_FORMAT, "%s:%d: expected 'wheel N' with N in -1000..1000", path, lineno);
        return true;
    case VIEW_CMD_KEY:
    case VIEW_CMD_KEYDOWN:
    case VIEW_CMD_KEYUP:
        if (argc != 1 || !parse_key(argv[0], &cmd->key, &cmd->mod))
            return sl_fail(err, SL_ERR_FORMAT, "%s:%d: expected '%s NAME' with an SDL key name (r, F1, Up, shift+e), got '%s'",
                           path, lineno, words[0], argc ? argv[0] : "");
        return true;
    case VIEW_CMD_RESIZE:
        if (argc != 2 || !parse_int(argv[0], 1, SL_RASTER_MAX_SIZE, &cmd->args[0]) ||
            !parse_int(argv[1], 1, SL_RASTER_MAX_SIZE, &cmd->args[1]))
            return sl_fail(err, SL_ERR_FORMAT, "%s:%d: expected 'resize W H' with each in 1..%d", path, lineno,
                           SL_RASTER_MAX_SIZE);
        return true;
    case VIEW_CMD_DROP:
        if (!rest_copy[0])
            return sl_fail(err, SL_ERR_FORMAT, "%s:%d: expected 'drop PATH'", path, lineno);
        memcpy(cmd->text, rest_copy, sizeof rest_copy);
        return true;
    case VIEW_CMD_SCREENSHOT:
        memcpy(cmd->text, rest_copy, sizeof rest_copy);
        return true;
    case VIEW_CMD_ACCUMULATED:
        if (argc != 1 || !parse_int(argv[0], 1, 1000, &cmd->args[0]))
            return sl_fail(err, SL_ERR_FORMAT, "%s:%d: expected 'accumulated K' with K in 1..1000", path, lineno);
        return true;
    case VIEW_CMD_SNAPSHOT:
        if (!rest_copy[0])
            return sl_fail(err, SL_ERR_FORMAT, "%s:%d: expected 'snapshot NAME'", path, lineno);
        memcpy(cmd->text, rest_copy, sizeof rest_copy);
        return true;
    }
    return sl_fail(err, SL_ERR_FORMAT, "%s:%d: internal: unhandled command", path, lineno);
}

bool view_script_load(const char *path, view_script *s, sl_error *err)
{
    memset(s, 0, sizeof *s);
    unsigned char *bytes;
    size_t size;
    if (!sl_read_file(path, SCRIPT_MAX_BYTES, &bytes, &size, err))
        return false;
    int capacity = 0;
    bool ok = true;
    int lineno = 0;
    for (size_t pos = 0; ok && pos < size;) {
        size_t end = pos;
        while (end < size && bytes[end] != '\n')
            end++;
        lineno++;
        char line[SL_PATH_MAX + 64];
        size_t len = end - pos;
        if (len >= sizeof line) {
            ok = sl_fail(err, SL_ERR_FORMAT, "%s:%d: line longer than %zu bytes", path, lineno, sizeof line - 1);
            break;
        }
        memcpy(line, bytes + pos, len);
        line[len] = '\0';
        pos = end + 1;
        for (size_t i = 0; i < len; i++)
            if (line[i] == '\0' || line[i] == '\r')
                line[i] = ' ';
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        const char *p = line;
        while (*p && isspace((unsigned char)*p))
            p++;
        if (!*p)
            continue;
        if (s->count == capacity) {
            int grown = capacity ? capacity * 2 : 64;
            view_cmd *cmds = realloc(s->cmds, (size_t)grown * sizeof *cmds);
            if (!cmds) {
                ok = sl_fail(err, SL_ERR_MEMORY, "%s: out of memory at line %d", path, lineno);
                break;
            }
            s->cmds = cmds;
            capacity = grown;
        }
        ok = parse_line(line, path, lineno, &s->cmds[s->count], err);
        if (ok)
            s->count++;
    }
    free(bytes);
    if (!ok)
        view_script_free(s);
    return ok;
}

void view_script_free(view_script *s)
{
    free(s->cmds);
    memset(s, 0, sizeof *s);
}

/* ------------------------------------------------------------------ input as SDL events */

static bool push(SDL_Event *e, sl_error *err)
{
    if (SDL_PushEvent(e) < 0)
        return sl_fail(err, SL_ERR_RANGE, "script: SDL event queue: %s", SDL_GetError());
    return true;
}

static bool push_motion(Uint32 window_id, int x, int y, int xrel, int yrel, Uint32 state, sl_error *err)
{
    SDL_Event e = {0};
    e.motion.type = SDL_MOUSEMOTION;
    e.motion.windowID = window_id;
    e.motion.x = x;
    e.motion.y = y;
    e.motion.xrel = xrel;
    e.motion.yrel = yrel;
    e.motion.state = state;
    return push(&e, err);
}

static bool push_button(Uint32 window_id, Uint32 type, int button, int x, int y, sl_error *err)
{
    SDL_Event e = {0};
    e.button.type = type;
    e.button.windowID = window_id;
    e.button.button = (Uint8)button;
    e.button.state = type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
    e.button.clicks = 1;
    e.button.x = x;
    e.button.y = y;
    return push(&e, err);
}

static bool push_key(Uint32 window_id, Uint32 type, int key, int mod, sl_error *err)
{
    SDL_Event e = {0};
    e.key.type = type;
    e.key.windowID = window_id;
    e.key.state = type == SDL_KEYDOWN ? SDL_PRESSED : SDL_RELEASED;
    e.key.keysym.sym = (SDL_Keycode)key;
    e.key.keysym.scancode = SDL_GetScancodeFromKey((SDL_Keycode)key);
    e.key.keysym.mod = (Uint16)mod;
    return push(&e, err);
}

/* The SDL events of an input command (DRAG, MOVE, WHEEL, KEY, KEYDOWN, KEYUP, DROP), exactly as a
 * user's input would arrive. False when the queue is full. */
static bool push_command(view_script *s, const view_cmd *cmd, SDL_Window *window, sl_error *err)
{
    Uint32 id = SDL_GetWindowID(window);
    switch (cmd->kind) {
    case VIEW_CMD_DRAG: {
        int x0 = cmd->args[0], y0 = cmd->args[1], x1 = cmd->args[2], y1 = cmd->args[3];
        int button = cmd->args[4], steps = cmd->args[5];
        Uint32 state = SDL_BUTTON(button);
        if (!push_motion(id, x0, y0, x0 - s->mouse_x, y0 - s->mouse_y, 0, err) ||
            !push_button(id, SDL_MOUSEBUTTONDOWN, button, x0, y0, err))
            return false;
        int px = x0, py = y0;
        for (int i = 1; i <= steps; i++) {
            int x = x0 + (int)((long long)(x1 - x0) * i / steps);
            int y = y0 + (int)((long long)(y1 - y0) * i / steps);
            if (!push_motion(id, x, y, x - px, y - py, state, err))
                return false;
            px = x;
            py = y;
        }
        s->mouse_x = x1;
        s->mouse_y = y1;
        return push_button(id, SDL_MOUSEBUTTONUP, button, x1, y1, err);
    }
    case VIEW_CMD_MOVE: {
        int x = cmd->args[0], y = cmd->args[1];
        bool ok = push_motion(id, x, y, x - s->mouse_x, y - s->mouse_y, 0, err);
        s->mouse_x = x;
        s->mouse_y = y;
        return ok;
    }
    case VIEW_CMD_WHEEL: {
        SDL_Event e = {0};
        e.wheel.type = SDL_MOUSEWHEEL;
        e.wheel.windowID = id;
        e.wheel.y = cmd->args[0];
        e.wheel.direction = SDL_MOUSEWHEEL_NORMAL;
        return push(&e, err);
    }
    case VIEW_CMD_KEY:
        return push_key(id, SDL_KEYDOWN, cmd->key, cmd->mod, err) && push_key(id, SDL_KEYUP, cmd->key, cmd->mod, err);
    case VIEW_CMD_KEYDOWN:
        return push_key(id, SDL_KEYDOWN, cmd->key, cmd->mod, err);
    case VIEW_CMD_KEYUP:
        return push_key(id, SDL_KEYUP, cmd->key, cmd->mod, err);
    case VIEW_CMD_DROP: {
        SDL_Event e = {0};
        e.drop.type = SDL_DROPFILE;
        e.drop.windowID = id;
        e.drop.file = SDL_strdup(cmd->text); /* the handler SDL_free()s it, as for a real drop */
        if (!e.drop.file)
            return sl_fail(err, SL_ERR_MEMORY, "script: out of memory");
        if (!push(&e, err)) {
            SDL_free(e.drop.file);
            return false;
        }
        return true;
    }
    default:
        return sl_fail(err, SL_ERR_RANGE, "script line %d: not an input command", cmd->line);
    }
}

/* ------------------------------------------------------------------ running */

/* Input commands in a row are pushed together (that is how a burst of real input arrives); a
 * command that depends on their effect (settle, screenshot, resize) waits for the next turn,
 * after the loop has handled the events. */
void view_script_step(viewer *v, double now)
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
            if (pushed || !view_converged(v) || view_interacting(v, now) || v->retonemap || view_gl_wanted(v))
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
            if (c->args[0] > view_acc_target(v) || v->acc_count > c->args[0]) {
                fprintf(stderr,
                        "softlight view: script line %d: accumulated %d: this view accumulates %d frames "
                        "and holds %d\n",
                        c->line, c->args[0], view_acc_target(v), v->acc_count);
                v->exit_status = 2;
                break;
            }
            if (v->acc_count < c->args[0])
                return;
            break;
        case VIEW_CMD_SNAPSHOT:
            if (pushed)
                return;
            if (!view_snapshot(v, c->text, &err)) {
                fprintf(stderr, "softlight view: script line %d: %s\n", c->line, err.msg);
                v->exit_status = 2;
            }
            break;
        case VIEW_CMD_READOUT: {
            if (pushed)
                return;
            char text[1024];
            if (view_readout(v, 9, text, sizeof text))
                printf("softlight view: readout %s\n", text);
            else
                printf("softlight view: readout: the pointer is not over the image\n");
            fflush(stdout);
            break;
        }
        case VIEW_CMD_QUIT: {
            SDL_Event e = {0};
            e.type = SDL_QUIT;
            SDL_PushEvent(&e);
            s->next++;
            return;
        }
        default:
            if (!push_command(s, c, v->window, &err)) {
                /* The queue is full: let the loop drain it and try again. */
                return;
            }
            pushed = true;
            break;
        }
        s->next++;
    }
}


#else
typedef int view_script_unused; /* this file is only built with SDL2 */
#endif
