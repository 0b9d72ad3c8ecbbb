/* view_input.c - what the viewer's input does: keys, mouse, window events and dropped files turn
 * into changes of the viewer's state (camera, lighting options, view, scene, environment) and an
 * answer, the view_action the loop then takes: which restart of the refinement the change needs,
 * or a screenshot (the contract is in view_internal.h).
 *
 * Why actions and not calls: input only edits state and says what follows from it; the loop
 * (cmd_view.c), which calls view_handle_event for every SDL event, real or pushed by a
 * --script, acts on the answer before the next event. So this file calls nothing above it (the
 * refinement, screenshots), only the camera, the renderer and the message line. */
#if SL_HAVE_SDL2
#include <SDL.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/timer.h"
#include "view_internal.h"

#define ORBIT_KEY_DEG 5.0f
#define PAN_KEY_FRACTION 0.05f
#define ZOOM_STEP 0.9f
#define ENV_ROTATION_STEP 15.0f
#define EXPOSURE_STEP 1.189207115f /* 2^(1/4): a quarter stop */
#define CONTRAST_STEP 0.1f

/* ------------------------------------------------------------------ scenes and drops */

static bool has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && !strcasecmp(s + n - k, suffix);
}

void view_adopt_scene(viewer *v, sl_scene *scene, const sl_renderer *r)
{
    sl_error err = {0};
    if (!view_shown_make(v, &err)) { /* r.radiance goes with the old renderer */
        view_message(v, true, "%s", err.msg);
        sl_image_free(&v->shown);
    }
    if (v->scene) {
        sl_renderer_free(&v->r);
        sl_scene_free(v->scene);
        free(v->scene);
    }
    v->scene = scene;
    v->r = *r;
    if (!sl_scene_bounds(scene, &v->bounds_lo, &v->bounds_hi)) {
        v->bounds_lo = vec3s(-1.0f);
        v->bounds_hi = vec3s(1.0f);
    }
    view_camera_init(&v->camera, &scene->camera);
    view_camera_set_bounds(&v->camera, v->bounds_lo, v->bounds_hi);
    v->home_lighting = r->desc.lighting;
    v->home_tonemap = r->desc.tonemap;
    v->home_ao_radius = r->desc.options.ao_radius;
    v->home_shadows = r->desc.options.shadows;
    v->home_sky_maps = r->desc.options.sky_maps;
    /* Y's count: the scene's or the command line's, else the one docs/lighting.md recommends */
    v->sky_maps_on = r->desc.options.sky_maps > 0 ? r->desc.options.sky_maps : 32;
    v->home_reflection = r->desc.options.reflection_occlusion;
    /* J's distance: the scene's or the command line's, else half the scene's bounding diagonal */
    v->reflection_on = r->desc.options.reflection_occlusion > 0.0f ? r->desc.options.reflection_occlusion
                                                                  : 0.5f * length(sub(v->bounds_hi, v->bounds_lo));
    /* O's radius: the scene's or the command line's, else a tenth of the scene's bounding radius */
    v->ao_radius_on = r->desc.options.ao_radius > 0.0f ? r->desc.options.ao_radius
                                                       : 0.05f * length(sub(v->bounds_hi, v->bounds_lo));
    v->irradiance_stale = false;
    v->env_replaced = false;
    char title[SL_PATH_MAX + 32];
    snprintf(title, sizeof title, "softlight view - %s", scene->path);
    if (v->window)
        SDL_SetWindowTitle(v->window, title);
}

bool view_is_environment(const char *path)
{
    return has_suffix(path, ".hdr") || has_suffix(path, ".exr") || has_suffix(path, ".pfm");
}

bool view_read_scene(const char *path, const char *env, const sl_option_values *given, sl_scene **out, sl_error *err)
{
    sl_scene *scene = calloc(1, sizeof *scene);
    if (!scene)
        return sl_fail(err, SL_ERR_MEMORY, "out of memory for a scene");
    if (!sl_scene_load_with(path, given, scene, err)) {
        free(scene);
        return false;
    }
    fputs(scene->warnings, stderr); /* what the scene loads but does not draw */
    if (env) { /* as render's --env: relative to here, and no irradiance map */
        if (strlen(env) >= sizeof scene->environment.hdr_path) {
            sl_scene_free(scene);
            free(scene);
            return sl_fail(err, SL_ERR_RANGE, "--env: path too long");
        }
        snprintf(scene->environment.hdr_path, sizeof scene->environment.hdr_path, "%s", env);
        scene->environment.irradiance_path[0] = '\0';
    }
    *out = scene;
    return true;
}

/* Load a scene and build its renderer at the current size; on failure nothing changes. */
static bool load_scene(viewer *v, const char *path, const char *env, int width, int height, sl_error *err)
{
    sl_scene *scene;
    if (!view_read_scene(path, env, &v->cli_desc.options, &scene, err))
        return false;
    sl_render_desc desc = v->cli_desc;
    sl_option_set_size(&desc.options, width, height);
    sl_renderer r;
    if (!sl_renderer_init(&r, scene, &desc, err)) {
        sl_scene_free(scene);
        free(scene);
        return false;
    }
    view_adopt_scene(v, scene, &r);
    sl_error werr = {0};
    if (!view_watch_scene(&v->watch, scene, env, &werr))
        view_message(v, true, "%s (no reloading)", werr.msg);
    return true;
}

bool view_load_scene(viewer *v, const char *path, sl_error *err)
{
    int w, h;
    view_render_size(v, 1, &w, &h);
    return load_scene(v, path, v->env_override[0] ? v->env_override : NULL, w, h, err);
}

static view_action handle_drop(viewer *v, const char *path)
{
    sl_error err = {0};
    if (has_suffix(path, ".hdr")) {
        if (!sl_renderer_set_environment(&v->r, path, &err)) {
            view_message(v, true, "%s (the environment stays)", err.msg);
            return VIEW_ACT_NONE;
        }
        /* The renderer rebuilds the irradiance only while the diffuse term is on. */
        v->irradiance_stale = v->r.desc.lighting.no_diffuse;
        v->env_replaced = true;
        sl_error werr = {0};
        snprintf(v->env_override, sizeof v->env_override, "%s", path); /* a reload keeps it */
        if (!view_watch_scene(&v->watch, v->scene, path, &werr))
            view_message(v, true, "%s (no reloading)", werr.msg);
        view_message(v, false, "environment %s", path);
        return VIEW_ACT_RESTART_LIGHTING;
    }
    /* A .json scene, or any other file as a model in the default scene (`softlight view
     * model.glb`); what is neither fails there with its reason ("unknown model format"). */
    if (!load_scene(v, path, NULL, v->r.desc.width, v->r.desc.height, &err)) {
        view_message(v, true, "%s (the scene stays)", err.msg);
        return VIEW_ACT_NONE;
    }
    v->env_override[0] = '\0'; /* the dropped scene brings its own environment */
    view_message(v, false, "%s %s", has_suffix(path, ".json") ? "scene" : "model", path);
    return VIEW_ACT_RESTART_CAMERA;
}

/* ------------------------------------------------------------------ input */

static int nav_index(SDL_Keycode key)
{
    switch (key) {
    case SDLK_LEFT: return VIEW_NAV_LEFT;
    case SDLK_RIGHT: return VIEW_NAV_RIGHT;
    case SDLK_UP: return VIEW_NAV_UP;
    case SDLK_DOWN: return VIEW_NAV_DOWN;
    case SDLK_w: return VIEW_NAV_W;
    case SDLK_a: return VIEW_NAV_A;
    case SDLK_s: return VIEW_NAV_S;
    case SDLK_d: return VIEW_NAV_D;
    case SDLK_EQUALS: case SDLK_PLUS: case SDLK_KP_PLUS: return VIEW_NAV_IN;
    case SDLK_MINUS: case SDLK_KP_MINUS: return VIEW_NAV_OUT;
    default: return -1;
    }
}

/* One step of a navigation key (a press or an auto-repeat). */
static view_action navigate(viewer *v, int nav, bool fine)
{
    float step = fine ? 0.2f : 1.0f;
    switch (nav) {
    case VIEW_NAV_LEFT: view_camera_orbit(&v->camera, -ORBIT_KEY_DEG * step, 0.0f); break;
    case VIEW_NAV_RIGHT: view_camera_orbit(&v->camera, ORBIT_KEY_DEG * step, 0.0f); break;
    case VIEW_NAV_UP: view_camera_orbit(&v->camera, 0.0f, ORBIT_KEY_DEG * step); break;
    case VIEW_NAV_DOWN: view_camera_orbit(&v->camera, 0.0f, -ORBIT_KEY_DEG * step); break;
    /* The keys move the camera, arrows and WASD alike: Left and A to the left, Up and W up (a
     * pan moves the scene the other way: view_camera_pan's dx > 0 moves it right). */
    case VIEW_NAV_W: view_camera_pan(&v->camera, 0.0f, PAN_KEY_FRACTION * step); break;
    case VIEW_NAV_S: view_camera_pan(&v->camera, 0.0f, -PAN_KEY_FRACTION * step); break;
    case VIEW_NAV_A: view_camera_pan(&v->camera, PAN_KEY_FRACTION * step, 0.0f); break;
    case VIEW_NAV_D: view_camera_pan(&v->camera, -PAN_KEY_FRACTION * step, 0.0f); break;
    case VIEW_NAV_IN: view_camera_zoom(&v->camera, powf(ZOOM_STEP, step)); break;
    case VIEW_NAV_OUT: view_camera_zoom(&v->camera, 1.0f / powf(ZOOM_STEP, step)); break;
    default: return VIEW_ACT_NONE;
    }
    return VIEW_ACT_RESTART_CAMERA;
}

/* N's next step up or down among the powers of two 1 .. SL_HAMMERSLEY_MAX and the scene's N
 * (so N = 40 is on the way from 32 to 64 and back). */
static int samples_step(int n, int home, bool up)
{
    int p = 1;
    if (up) {
        while (p <= n && p < SL_HAMMERSLEY_MAX)
            p *= 2;
        if (p <= n)
            return n;
        return home > n && home < p ? home : p;
    }
    if (n <= 1)
        return 1;
    while (p * 2 < n)
        p *= 2;
    return home < n && home > p ? home : p;
}

static view_action cycle_irradiance(viewer *v)
{
    sl_lighting_options *l = &v->r.desc.lighting;
    bool has_map = v->scene->environment.irradiance_path[0] != '\0' && !v->env_replaced;
    /* view_irradiance_cycle's order (the help spells it from the same array), the map only
     * when the scene names one */
    int at = 0;
    while (at < VIEW_IRRADIANCE_CYCLE && view_irradiance_cycle[at] != l->irradiance)
        at++;
    sl_irradiance_method next = view_irradiance_cycle[(at + 1) % VIEW_IRRADIANCE_CYCLE];
    if (next == SL_IRRADIANCE_MAP && !has_map)
        next = view_irradiance_cycle[(at + 2) % VIEW_IRRADIANCE_CYCLE];
    if (l->no_diffuse) {
        /* Built when the diffuse term comes back on. */
        l->irradiance = next;
        v->irradiance_stale = true;
        view_message(v, false, "irradiance %s (diffuse is off)", view_irradiance_name(next));
        return VIEW_ACT_NONE;
    }
    sl_error err = {0};
    if (!sl_renderer_set_irradiance(&v->r, next, &err)) {
        view_message(v, true, "%s", err.msg);
        return VIEW_ACT_NONE;
    }
    view_message(v, false, "irradiance %s (%.0f ms)", view_irradiance_name(next), v->r.timings.irradiance_ms);
    return VIEW_ACT_RESTART_LIGHTING;
}

static view_action toggle_diffuse(viewer *v)
{
    sl_lighting_options *l = &v->r.desc.lighting;
    if (l->no_diffuse && (v->irradiance_stale || !v->r.have_irradiance)) {
        sl_error err = {0};
        sl_irradiance_method method = l->irradiance;
        if (method == SL_IRRADIANCE_MAP && v->env_replaced)
            method = sl_irradiance_default(); /* the scene's map belongs to the scene's environment */
        if (!sl_renderer_set_irradiance(&v->r, method, &err)) {
            view_message(v, true, "%s", err.msg);
            return VIEW_ACT_NONE;
        }
        v->irradiance_stale = false;
    }
    l->no_diffuse = !l->no_diffuse;
    return VIEW_ACT_RESTART_LIGHTING;
}

void view_reset_all(viewer *v)
{
    sl_lighting_options *l = &v->r.desc.lighting;
    sl_lighting_options home = v->home_lighting;
    if (home.irradiance == SL_IRRADIANCE_MAP && v->env_replaced)
        home.irradiance = sl_irradiance_default(); /* the scene's map belongs to the scene's environment */
    l->no_diffuse = home.no_diffuse; /* the renderer builds the irradiance while the diffuse term is on */
    if (home.no_diffuse) {
        if (l->irradiance != home.irradiance)
            v->irradiance_stale = true; /* built when the diffuse term comes back on */
    } else if (l->irradiance != home.irradiance || v->irradiance_stale || !v->r.have_irradiance) {
        sl_error err = {0};
        if (sl_renderer_set_irradiance(&v->r, home.irradiance, &err)) {
            v->irradiance_stale = false;
        } else {
            view_message(v, true, "%s", err.msg);
            home.irradiance = l->irradiance;
        }
    }
    *l = home;
    v->r.desc.tonemap = v->home_tonemap;
    v->r.desc.options.ao_radius = v->home_ao_radius;
    v->r.desc.options.shadows = v->home_shadows;
    v->r.desc.options.sky_maps = v->home_sky_maps;
    v->r.desc.options.reflection_occlusion = v->home_reflection;
    v->mode = VIEW_FINAL;
    view_camera_reset(&v->camera);
}

static view_action handle_key(viewer *v, const SDL_KeyboardEvent *e)
{
    SDL_Keycode key = e->keysym.sym;
    bool shift = (e->keysym.mod & KMOD_SHIFT) != 0;
    sl_lighting_options *l = &v->r.desc.lighting;
    sl_tonemap_options *t = &v->r.desc.tonemap;
    int nav = nav_index(key);
    if (nav >= 0) {
        v->held[nav] = true;
        return navigate(v, nav, shift && nav != VIEW_NAV_IN); /* shift: fine steps ('+' is shift+= on most layouts) */
    }
    /* Adjustments: auto-repeat applies. Exposure stays in the option table's range, contrast in
     * steps within a scene file's (0 < c <= 10). */
    switch (key) {
    case SDLK_e:
        t->exposure = fminf(t->exposure * EXPOSURE_STEP, (float)sl_options[SL_OPT_EXPOSURE].max);
        v->retonemap = true;
        return VIEW_ACT_NONE;
    case SDLK_q:
        t->exposure = fmaxf(t->exposure / EXPOSURE_STEP, (float)sl_options[SL_OPT_EXPOSURE].min);
        v->retonemap = true;
        return VIEW_ACT_NONE;
    case SDLK_c:
        t->contrast = fminf(t->contrast + CONTRAST_STEP, (float)sl_option_file_max(&sl_options[SL_OPT_CONTRAST]));
        v->retonemap = true;
        return VIEW_ACT_NONE;
    case SDLK_x:
        t->contrast = fmaxf(t->contrast - CONTRAST_STEP, CONTRAST_STEP);
        v->retonemap = true;
        return VIEW_ACT_NONE;
    case SDLK_RIGHTBRACKET:
    case SDLK_LEFTBRACKET: {
        float r = l->env_rotation_deg + (key == SDLK_RIGHTBRACKET ? ENV_ROTATION_STEP : -ENV_ROTATION_STEP);
        r = fmodf(r, 360.0f);
        if (r > 180.0f)
            r -= 360.0f;
        if (r <= -180.0f)
            r += 360.0f;
        l->env_rotation_deg = r;
        return VIEW_ACT_RESTART_LIGHTING;
    }
    default:
        break;
    }
    if (e->repeat)
        return VIEW_ACT_NONE;
    view_action act = VIEW_ACT_NONE;
    switch (key) { /* toggles and one-shot actions: a held key acts once */
    case SDLK_ESCAPE:
        if (v->show_trace)
            v->show_trace = false;
        else if (v->show_help)
            v->show_help = false;
        else
            v->quit = true;
        break;
    case SDLK_f: {
        int ow, oh;
        view_output_size(v, &ow, &oh);
        view_camera_frame(&v->camera, (float)ow / (float)oh);
        act = VIEW_ACT_RESTART_CAMERA;
        break;
    }
    case SDLK_m: {
        char what[160];
        view_gl_cycle(v, what, sizeof what);
        view_message(v, false, "%s", what);
        break;
    }
    case SDLK_t: {
        sl_error err = {0};
        if (!view_trace_pointer(v, &err))
            view_message(v, true, "trace: %s", err.msg);
        break;
    }
    case SDLK_PAGEUP:
    case SDLK_PAGEDOWN:
        if (v->show_trace) {
            v->trace_page += key == SDLK_PAGEDOWN ? 1 : -1;
            if (v->trace_page < 0)
                v->trace_page = 0;
        }
        break;
    case SDLK_F1:
    case SDLK_QUESTION:
        v->show_help = !v->show_help;
        break;
    case SDLK_SLASH:
        if (shift)
            v->show_help = !v->show_help;
        break;
    case SDLK_h: /* full -> compact -> off -> full */
        if (!v->show_hud) {
            v->show_hud = true;
            v->hud_compact = false;
        } else if (!v->hud_compact) {
            v->hud_compact = true;
        } else {
            v->show_hud = false;
        }
        v->hud_chosen = true;
        break;
    case SDLK_r:
        view_reset_all(v);
        act = VIEW_ACT_RESTART_CAMERA;
        break;
    case SDLK_n:
    case SDLK_b:
        l->samples = samples_step(l->samples, v->home_lighting.samples, key == SDLK_n);
        act = VIEW_ACT_RESTART_LIGHTING;
        break;
    case SDLK_1:
        act = toggle_diffuse(v);
        break;
    case SDLK_2:
        l->no_specular = !l->no_specular;
        act = VIEW_ACT_RESTART_LIGHTING;
        break;
    case SDLK_3:
        l->no_point_lights = !l->no_point_lights;
        act = VIEW_ACT_RESTART_LIGHTING;
        break;
    case SDLK_i:
        act = cycle_irradiance(v);
        break;
    case SDLK_o: /* occlusion is drawn into the G-buffer: the frame is rasterized again */
        v->r.desc.options.ao_radius = v->r.desc.options.ao_radius > 0.0f ? 0.0f : v->ao_radius_on;
        view_message(v, false, "ambient occlusion %s", v->r.desc.options.ao_radius > 0.0f ? "on" : "off");
        act = VIEW_ACT_RESTART_CAMERA;
        break;
    case SDLK_u: /* the maps are drawn before the lighting, once (src/render/renderer.c update_shadows) */
        v->r.desc.options.shadows = !v->r.desc.options.shadows;
        view_message(v, false, "shadows of every point light %s", v->r.desc.options.shadows ? "on" : "off");
        act = VIEW_ACT_RESTART_LIGHTING;
        break;
    case SDLK_j: /* traced into the G-buffer's plane: the frame is rasterized again */
        v->r.desc.options.reflection_occlusion =
            v->r.desc.options.reflection_occlusion > 0.0f ? 0.0f : v->reflection_on;
        view_message(v, false, "reflection occlusion %s",
                     v->r.desc.options.reflection_occlusion > 0.0f ? "on" : "off");
        act = VIEW_ACT_RESTART_CAMERA;
        break;
    case SDLK_y: /* drawn before the lighting, once per scene and environment (renderer.c update_sky) */
        v->r.desc.options.sky_maps = v->r.desc.options.sky_maps > 0 ? 0 : v->sky_maps_on;
        view_message(v, false, "sky visibility maps %s", v->r.desc.options.sky_maps > 0 ? "on" : "off");
        act = VIEW_ACT_RESTART_LIGHTING;
        break;
    case SDLK_l: {
        l->lod_rule =
            (sl_lod_rule)sl_option_next(&sl_options[SL_OPT_LOD], (int)sl_lighting_options_resolve(l).lod_rule);
        l->ggx.lod_rule = l->lod_rule; /* a GGX set of its own (a scene of both sets) takes it too */
        act = VIEW_ACT_RESTART_LIGHTING;
        break;
    }
    case SDLK_k: {
        l->estimator =
            (sl_estimator)sl_option_next(&sl_options[SL_OPT_ESTIMATOR], (int)sl_lighting_options_resolve(l).estimator);
        l->ggx.estimator = SL_ESTIMATOR_DEFAULT; /* the one asked for, for every pixel */
        l->env_lights_ggx_only = false;
        act = VIEW_ACT_RESTART_LIGHTING;
        break;
    }
    case SDLK_g: {
        l->gterm = (sl_gterm)sl_option_next(&sl_options[SL_OPT_GTERM], (int)sl_lighting_options_resolve(l).gterm);
        act = VIEW_ACT_RESTART_LIGHTING;
        break;
    }
    case SDLK_v:
        v->mode = (view_mode)((v->mode + (shift ? VIEW_MODE_COUNT - 1 : 1)) % VIEW_MODE_COUNT);
        act = VIEW_ACT_RESTART_LIGHTING;
        break;
    case SDLK_F12:
    case SDLK_p:
        act = VIEW_ACT_SCREENSHOT;
        break;
    default:
        return VIEW_ACT_NONE;
    }
    v->present_needed = true;
    return act;
}

view_action view_handle_event(viewer *v, SDL_Event *e)
{
    double now = sl_now_seconds();
    view_action act = VIEW_ACT_NONE;
    switch (e->type) {
    case SDL_QUIT:
        v->quit = true;
        break;
    case SDL_WINDOWEVENT:
        switch (e->window.event) {
        case SDL_WINDOWEVENT_SIZE_CHANGED:
        case SDL_WINDOWEVENT_RESIZED:
            v->last_input = now;
            act = VIEW_ACT_RESTART_CAMERA;
            break;
        case SDL_WINDOWEVENT_CLOSE:
            v->quit = true;
            break;
        case SDL_WINDOWEVENT_EXPOSED:
            v->present_needed = true;
            break;
        case SDL_WINDOWEVENT_LEAVE:
            v->pointer_x = v->pointer_y = -1;
            v->present_needed = true;
            break;
        default:
            break;
        }
        break;
    case SDL_KEYDOWN:
        v->last_input = now;
        act = handle_key(v, &e->key);
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
        v->pointer_x = e->motion.x;
        v->pointer_y = e->motion.y;
        if (!v->drag_button)
            v->present_needed = v->hud && v->show_hud; /* the readout follows the pointer */
        if (!v->drag_button || (e->motion.xrel == 0 && e->motion.yrel == 0))
            break;
        int ow, oh;
        SDL_GetWindowSize(v->window, &ow, &oh);
        if (oh < 1)
            oh = 1;
        if (v->drag_button == SDL_BUTTON_LEFT)
            view_camera_orbit(&v->camera, -VIEW_ORBIT_DEG_PER_PIXEL * (float)e->motion.xrel,
                              VIEW_ORBIT_DEG_PER_PIXEL * (float)e->motion.yrel);
        else
            view_camera_pan(&v->camera, (float)e->motion.xrel / (float)oh, (float)e->motion.yrel / (float)oh);
        v->last_input = now;
        act = VIEW_ACT_RESTART_CAMERA;
        break;
    }
    case SDL_MOUSEWHEEL: {
        int clicks = e->wheel.direction == SDL_MOUSEWHEEL_FLIPPED ? -e->wheel.y : e->wheel.y;
        if (clicks && v->show_trace) { /* over the trace the wheel pages it */
            v->trace_page = clicks > 0 ? (v->trace_page > 0 ? v->trace_page - 1 : 0) : v->trace_page + 1;
            v->present_needed = true;
        } else if (clicks) {
            view_camera_zoom(&v->camera, powf(ZOOM_STEP, (float)clicks));
            v->last_input = now;
            act = VIEW_ACT_RESTART_CAMERA;
        }
        break;
    }
    case SDL_DROPFILE:
        if (e->drop.file) {
            act = handle_drop(v, e->drop.file);
            SDL_free(e->drop.file);
        }
        break;
    default:
        break;
    }
    return act;
}

#else
typedef int view_input_unused; /* this file is only built with SDL2 */
#endif
