/* view_probe.c - the pixel under the pointer (the contract is in view_internal.h): its readout
 * for the HUD and the script's `readout`, and its trace (T), the text `softlight trace
 * SCENE --pixel X,Y` prints for the same camera and settings.
 *
 * Why a file of its own: both read what the refinement left (the linear image behind the
 * window, the G-buffer, the uniforms) without changing what is shown; the trace alone
 * re-rasters (with the fetch hook) and re-prepares the exact frame's uniforms, and then tells
 * the refinement to light again if it was using them. */
#if SL_HAVE_SDL2
#include <SDL.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/trace_fetches.h"
#include "shading/lighting_trace.h"
#include "view_internal.h"

bool view_pointer_pixel(const viewer *v, int w, int h, int *x, int *y)
{
    int ww = 0, wh = 0;
    SDL_GetWindowSize(v->window, &ww, &wh);
    if (ww < 1 || wh < 1 || w < 1 || h < 1 || v->pointer_x < 0 || v->pointer_y < 0 || v->pointer_x >= ww ||
        v->pointer_y >= wh)
        return false;
    *x = (int)((long long)v->pointer_x * w / ww);
    *y = (int)((long long)v->pointer_y * h / wh);
    return true;
}

/* Window depth back to the distance along the view axis (as view_image.c's depth view). */
static float eye_depth(float d, float n, float f)
{
    float z_ndc = 2.0f * d - 1.0f;
    return 2.0f * n * f / (f + n - z_ndc * (f - n));
}

/* "NAME x y z (UNITS)" with `digits` significant digits. */
static void vec3_readout(char *o, size_t left, const char *name, vec3 v, const char *units, int digits)
{
    snprintf(o, left, "%s %.*g %.*g %.*g (%s)", name, digits, (double)v.x, digits, (double)v.y, digits, (double)v.z,
             units);
}

/* The mean mip level of the pixel's specular samples above the horizon (the mip view's value). */
static bool mean_level(const viewer *v, int x, int y_gb, float *level)
{
    sl_lighting_trace *trace = malloc(sizeof *trace);
    if (!trace)
        return false;
    trace->sample_count = 0;
    sl_lighting_shade(v->r.uniforms, &v->r.gbuffer, x, y_gb, NULL, trace);
    *level = view_trace_mean_level(trace);
    free(trace);
    return !isnan(*level);
}

bool view_readout(viewer *v, int digits, char *buf, size_t size)
{
    buf[0] = '\0';
    int x, y;
    if (v->mode == VIEW_FINAL) {
        if (v->shown_from == VIEW_SHOWN_GL || v->shown_from == VIEW_SHOWN_DIFF) {
            const sl_image *c = &v->gl.c_radiance, *g = &v->gl.radiance;
            if (!view_pointer_pixel(v, c->width, c->height, &x, &y))
                return false;
            const float *pc = sl_image_pixel(c, x, y), *pg = sl_image_pixel(g, x, y);
            snprintf(buf, size, "pixel %d,%d of %dx%d: C %.*g %.*g %.*g, GL %.*g %.*g %.*g (linear RGB)", x, y,
                     c->width, c->height, digits, (double)pc[0], digits, (double)pc[1], digits, (double)pc[2], digits,
                     (double)pg[0], digits, (double)pg[1], digits, (double)pg[2]);
            return true;
        }
        const sl_image *linear = v->shown_from == VIEW_SHOWN_MEAN       ? &v->mean
                                 : v->shown_from == VIEW_SHOWN_RADIANCE ? &v->r.radiance
                                                                        : NULL;
        if (!linear || !linear->data || !view_pointer_pixel(v, linear->width, linear->height, &x, &y))
            return false;
        const float *p = sl_image_pixel(linear, x, y);
        snprintf(buf, size, "pixel %d,%d of %dx%d: radiance %.*g %.*g %.*g (linear RGB, %s)", x, y, linear->width,
                 linear->height, digits, (double)p[0], digits, (double)p[1], digits, (double)p[2],
                 v->shown_from == VIEW_SHOWN_MEAN ? "the mean so far" : "this frame");
        return true;
    }
    const sl_gbuffer *gb = &v->r.gbuffer;
    if (!gb->texels || !view_pointer_pixel(v, gb->width, gb->height, &x, &y))
        return false;
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, gb->height - 1 - y);
    int n = snprintf(buf, size, "pixel %d,%d of %dx%d: ", x, y, gb->width, gb->height);
    if (n < 0 || (size_t)n >= size)
        return true;
    char *o = buf + n;
    size_t left = size - (size_t)n;
    if (!sl_gbuffer_covered(t)) {
        snprintf(o, left, "no geometry");
        return true;
    }
    switch (v->mode) {
    case VIEW_POSITION: vec3_readout(o, left, "position", t->position, "world units", digits); break;
    case VIEW_NORMAL: vec3_readout(o, left, "normal", t->normal, "unit vector, world space", digits); break;
    case VIEW_KD: vec3_readout(o, left, "kd", t->kd, "diffuse albedo, linear, 0..1", digits); break;
    case VIEW_KS: vec3_readout(o, left, "ks", t->ks, "Fresnel F0, linear, 0..1", digits); break;
    case VIEW_ALPHA:
        if (t->alpha >= 0.0f)
            snprintf(o, left, "alpha %.*g (Phong exponent, 0 rough .. 10000 mirror)", digits, (double)t->alpha);
        else
            snprintf(o, left, "GGX roughness %.*g (perceptual, 0..1)", digits, (double)(-1.0f - t->alpha));
        break;
    case VIEW_DEPTH:
        snprintf(o, left, "depth %.*g (world units along the view axis; window depth %.*g)", digits,
                 (double)eye_depth(t->depth, v->camera.cam.znear, v->camera.cam.zfar), digits, (double)t->depth);
        break;
    case VIEW_MIP: {
        float level;
        if (v->r.uniforms && mean_level(v, x, gb->height - 1 - y, &level))
            snprintf(o, left, "mean mip level %.*g of 0..%.0f (specular samples above the horizon)", digits,
                     (double)level, (double)v->r.uniforms->uEnvMaxLod);
        else
            snprintf(o, left, "no specular sample above the horizon");
        break;
    }
    default:
        break;
    }
    return true;
}

void view_trace_free(viewer *v)
{
    free(v->trace_text);
    v->trace_text = NULL;
    v->trace_lines = 0;
    v->show_trace = false;
}

bool view_trace_pointer(viewer *v, sl_error *err)
{
    int w, h, x, y;
    view_render_size(v, 1, &w, &h);
    if (!view_pointer_pixel(v, w, h, &x, &y))
        return sl_fail(err, SL_ERR_RANGE, "the pointer is not over the image");
    if (!view_shown_make(v, err)) /* r.radiance stays what the window shows */
        return false;
    sl_trace_fetches *fetches = malloc(sizeof *fetches);
    sl_lighting_trace *trace = malloc(sizeof *trace);
    char *text = NULL;
    size_t text_size = 0;
    FILE *out = NULL;
    bool ok = false;
    if (!fetches || !trace) {
        sl_fail(err, SL_ERR_MEMORY, "out of memory for the trace");
        goto done;
    }
    /* As cmd_trace.c: a raster at full size with the fetch hook at the pixel, the uniforms of the
     * exact frame (the user's settings, no per-frame override), the shader's trace. */
    if (v->r.gbuffer.width != w || v->r.gbuffer.height != h) {
        if (!sl_renderer_resize(&v->r, w, h, err))
            goto done;
    }
    int gb_y = h - 1 - y;
    sl_trace_fetches_hook(fetches, &v->r.textures, x, gb_y);
    bool rastered = sl_renderer_raster(&v->r, &v->camera.cam, err);
    v->r.textures.trace = NULL;
    v->r.textures.trace_ctx = NULL;
    v->raster_valid = rastered;
    if (!rastered || !sl_renderer_prepare_lighting(&v->r, &v->camera.cam, err) ||
        !sl_lighting_trace_pixel(v->r.uniforms, &v->r.gbuffer, x, y, trace, err))
        goto done;
    out = open_memstream(&text, &text_size);
    if (!out) {
        sl_fail(err, SL_ERR_MEMORY, "out of memory for the trace's text");
        goto done;
    }
    sl_lighting_trace_print(out, trace);
    const sl_gbuffer_fragment_program *user = v->r.desc.gbuffer_program;
    if (user) /* the fetch hook is the built-in textured program's */
        fprintf(out, "G-buffer program: %s; its texture fetches are not traced\n", user->name ? user->name : "(unnamed)");
    else
        sl_trace_fetches_print(out, fetches, sl_gbuffer_at(&v->r.gbuffer, x, gb_y)->depth);
    if (fclose(out) != 0) {
        out = NULL;
        sl_fail(err, SL_ERR_MEMORY, "out of memory for the trace's text");
        goto done;
    }
    out = NULL;
    printf("softlight view: trace of pixel %d,%d (%dx%d; softlight trace --pixel %d,%d)\n", x, y, w, h, x, y);
    fputs(text, stdout);
    fflush(stdout);
    view_trace_free(v);
    v->trace_text = text;
    text = NULL;
    for (const char *p = v->trace_text; *p; p++)
        v->trace_lines += *p == '\n';
    v->trace_page = 0;
    v->show_trace = true;
    v->present_needed = true;
    ok = true;
done:
    if (out)
        fclose(out);
    free(text);
    free(trace);
    free(fetches);
    /* The G-buffer is now full size and the uniforms the exact frame's: a stage under way, or
     * one that was to light a smaller G-buffer, starts again from there. */
    if (v->job_active || v->stage < VIEW_STAGE_COUNT) {
        if (v->stage == VIEW_STAGE_MOVING || !v->raster_valid)
            view_restart_camera(v);
        else
            view_restart_lighting(v);
    }
    return ok;
}

#else
typedef int view_probe_unused; /* this file is only built with SDL2 */
#endif
