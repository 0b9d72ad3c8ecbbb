/* view_gl.c - M in the viewer: the exact frame beside the GL version of it, or their difference.
 *
 * The comparison is `softlight check`'s, made for the view on screen: softlight-gl lights the exact
 * frame's G-buffer (gl_twin.h) from the viewer's camera and environment rotation, with the exact
 * frame's settings as its options and the user's GLSL twin (--glsl) where the C side runs a
 * lighting program, so that what differs is only how the two shaders evaluate. It runs once the
 * refinement has converged, never while the camera moves: a run costs seconds on llvmpipe
 * (a new process, a GL context, the environment's upload), which the viewer says on screen before
 * it blocks. The HUD keeps the comparison's figures; the pointer's readout reads the image shown. */
#if SL_HAVE_SDL2

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/gl_twin.h"
#include "core/timer.h"
#include "post/compare.h"
#include "post/tonemap.h"
#include "view_internal.h"

#define WORDS_MAX 24 /* option words of one run */

static const char *const mode_names[VIEW_GL_MODES] = {"C", "GL", "C - GL difference"};

static view_shown_source source_of(view_gl_mode mode)
{
    return mode == VIEW_GL_IMAGE ? VIEW_SHOWN_GL : mode == VIEW_GL_DIFF ? VIEW_SHOWN_DIFF : VIEW_SHOWN_RADIANCE;
}

static bool showing_gl(const viewer *v) { return v->shown_from == VIEW_SHOWN_GL || v->shown_from == VIEW_SHOWN_DIFF; }

void view_gl_cycle(viewer *v, char *what, size_t size)
{
    view_gl *g = &v->gl;
    g->mode = (view_gl_mode)((g->mode + 1) % VIEW_GL_MODES);
    if (g->mode == VIEW_GL_OFF)
        snprintf(what, size, "compare: C (softlight's frame)");
    else if (v->mode != VIEW_FINAL)
        snprintf(what, size, "compare: %s, in the final view only (V)", mode_names[g->mode]);
    else
        snprintf(what, size, "compare: %s%s", mode_names[g->mode],
                 g->valid && !g->frame_changed ? "" : ", once the frame is exact (softlight-gl runs then)");
    v->present_needed = true;
}

bool view_gl_wanted(const viewer *v)
{
    const view_gl *g = &v->gl;
    if (v->mode != VIEW_FINAL || !view_converged(v) || v->retonemap)
        return false;
    if (g->mode == VIEW_GL_OFF)
        return showing_gl(v); /* back to C */
    if (g->frame_changed || !g->valid)
        return g->frame_changed || !g->failed;
    const sl_tonemap_options *t = &v->r.desc.tonemap, *s = &g->shown_tonemap;
    return v->shown_from != source_of(g->mode) || t->exposure != s->exposure || t->contrast != s->contrast ||
           t->exact_srgb != s->exact_srgb;
}

bool view_gl_will_run(const viewer *v)
{
    return v->gl.mode != VIEW_GL_OFF && view_gl_wanted(v) && (v->gl.frame_changed || !v->gl.valid);
}

/* The exact frame's settings as softlight-gl's options (the uniforms it was lit with). False with
 * err where the frame has no command-line spelling. */
static bool option_words(const viewer *v, char words[WORDS_MAX][32], const char **argv, int *count, sl_error *err)
{
    const sl_lighting_options *l = &v->r.uniforms->options;
    int n = 0;
#define WORD(...) (snprintf(words[n], sizeof words[n], __VA_ARGS__), argv[n] = words[n], n++)
    WORD("--samples");
    WORD("%d", l->samples);
    /* a scene of both sets that samples each its own way: no estimator named, so that
     * softlight-gl resolves the same per-set default (and, where they are the GGX set's alone, the
     * same env lights) */
    const bool own = v->r.desc.lighting.ggx.estimator != SL_ESTIMATOR_DEFAULT;
    if (!own) {
        WORD("--estimator");
        WORD("%s", sl_estimator_name(l->estimator));
    }
    if (!own || l->lod_rule == l->ggx.lod_rule) { /* the GGX set's own pdf rule stays unnamed */
        WORD("--lod");
        WORD("%s", sl_lod_rule_name(l->lod_rule));
    }
    WORD("--g");
    WORD("%s", sl_gterm_name(l->gterm));
    WORD("--irradiance");
    WORD("%s", sl_irradiance_name(l->irradiance));
    WORD("--env-layout");
    WORD("%s", sl_env_layout_name(l->env_layout));
    if (!l->env_lights_ggx_only) {
        WORD("--env-lights");
        WORD("%d", l->env_lights);
    }
    if (l->distortion)
        WORD("--distortion");
    if (v->r.desc.options.shadows) /* U; a light's own "shadow" key is in the scene file */
        WORD("--shadows");
    if (l->rotate) {
        WORD("--rotate");
        WORD("--frame");
        WORD("%u", (unsigned)l->frame);
    }
    /* the terms: render's three switches (render_options: --diffuse-only and --specular-only
     * turn the point lights off too) */
    if (!l->no_diffuse && !l->no_specular) {
        if (l->no_point_lights)
            WORD("--no-lights");
    } else if (l->no_specular && !l->no_diffuse && l->no_point_lights) {
        WORD("--diffuse-only");
    } else if (l->no_diffuse && !l->no_specular && l->no_point_lights) {
        WORD("--specular-only");
    } else {
        return sl_fail(err, SL_ERR_RANGE,
                       "softlight-gl has no option for these terms (1 2 3): diffuse %s, specular %s, point lights %s",
                       l->no_diffuse ? "off" : "on", l->no_specular ? "off" : "on", l->no_point_lights ? "off" : "on");
    }
#undef WORD
    *count = n;
    return true;
}

/* softlight-gl on the exact frame; its figures against r.radiance. */
static bool run(viewer *v, sl_error *err)
{
    view_gl *g = &v->gl;
    if (v->env_override[0])
        return sl_fail(err, SL_ERR_RANGE, "softlight-gl lights with the scene's environment, not %s",
                       v->env_override);
    if (v->programs[VIEW_PROGRAM_LIGHTING] && !g->glsl)
        return sl_fail(err, SL_ERR_RANGE, "a --lighting program needs its GLSL twin: view ... --glsl FILE.frag");
    if (!v->radiance_exact && !view_refine_finish(v, err))
        return false;
    char words[WORDS_MAX][32];
    const char *options[WORDS_MAX];
    int count = 0;
    if (!option_words(v, words, options, &count, err))
        return false;
    const sl_gl_twin_request q = {.scene = v->scene->path,
                                  .gbuffer = &v->r.gbuffer,
                                  .camera = &v->camera.cam,
                                  .env_rotation_deg = &v->r.desc.lighting.env_rotation_deg,
                                  .glsl = g->glsl,
                                  .options = options,
                                  .option_count = count,
                                  .who = "softlight view"};
    double t0 = sl_now_seconds();
    sl_image_repairs repairs;
    sl_image_free(&g->radiance);
    if (!sl_gl_twin_light(&q, &g->radiance, &repairs, g->renderer, sizeof g->renderer, err))
        return false;
    g->ms = (sl_now_seconds() - t0) * 1e3;
    /* a copy: the next refinement writes over r.radiance while the figures stay on the HUD */
    const sl_image *c = &v->r.radiance;
    if (!g->c_radiance.data || g->c_radiance.width != c->width || g->c_radiance.height != c->height) {
        sl_image_free(&g->c_radiance);
        sl_image_free(&g->difference);
        if (!sl_image_alloc(&g->c_radiance, c->width, c->height, 3, err) ||
            !sl_image_alloc(&g->difference, c->width, c->height, 3, err))
            return false;
    }
    size_t values = (size_t)c->width * (size_t)c->height * 3;
    memcpy(g->c_radiance.data, c->data, values * sizeof(float));
    for (size_t i = 0; i < values; i++)
        g->difference.data[i] = fabsf(c->data[i] - g->radiance.data[i]);
    sl_compare_desc cd = {.exposure = v->r.desc.tonemap.exposure, .contrast = v->r.desc.tonemap.contrast};
    sl_compare_stats *s = malloc(sizeof *s);
    if (!s)
        return sl_fail(err, SL_ERR_MEMORY, "no memory for the comparison");
    bool ok = sl_compare_images(&g->c_radiance, &g->radiance, &cd, s, err);
    if (ok) {
        g->p99_rel = s->p99_rel;
        g->max_abs = s->max_abs;
        g->over1 = s->share_over_1;
        g->over8 = s->share_over_8;
        printf("softlight view: compare: softlight-gl (%s) lit the %dx%d frame in %.2f s: p99 rel %.4g, max abs %.4g, "
               "> 1/255 %.3f%%, > 8/255 %.3f%%\n",
               g->renderer, c->width, c->height, g->ms / 1e3, g->p99_rel, g->max_abs, 100.0 * g->over1,
               100.0 * g->over8);
        fflush(stdout);
    }
    free(s);
    return ok;
}

/* The mode's image into `shown`. */
static bool show(viewer *v, sl_error *err)
{
    view_gl *g = &v->gl;
    sl_image_free(&v->shown); /* both writers allocate it */
    v->shown_pending = false;
    bool ok;
    if (g->mode == VIEW_GL_IMAGE) {
        ok = sl_tonemap_image(&g->radiance, &v->shown, &v->r.desc.tonemap, v->r.desc.threads, err);
    } else {
        sl_compare_desc cd = {.exposure = v->r.desc.tonemap.exposure, .contrast = v->r.desc.tonemap.contrast};
        ok = sl_compare_diff_image(&g->c_radiance, &g->radiance, &cd, &v->shown, err);
    }
    v->shown_from = ok ? source_of(g->mode) : VIEW_SHOWN_NONE;
    g->shown_tonemap = v->r.desc.tonemap;
    v->texture_stale = true;
    v->present_needed = true;
    return ok;
}

bool view_gl_step(viewer *v, sl_error *err)
{
    view_gl *g = &v->gl;
    if (g->frame_changed) {
        g->frame_changed = false;
        g->valid = g->failed = false;
    }
    if (g->mode == VIEW_GL_OFF) {
        /* r.radiance still holds the exact frame: the tone map's path shows it again */
        v->shown_from = VIEW_SHOWN_RADIANCE;
        v->retonemap = true;
        return true;
    }
    if (!g->valid) {
        if (!run(v, err)) {
            g->failed = true;
            return false;
        }
        g->valid = true;
    }
    return show(v, err);
}

void view_gl_hud(const viewer *v, char *buf, size_t size)
{
    const view_gl *g = &v->gl;
    buf[0] = '\0';
    if (g->mode == VIEW_GL_OFF)
        return;
    if (g->valid && !g->frame_changed)
        snprintf(buf, size,
                 "compare (M): %s | GL %s, %.1f s | p99 rel %.3g, max |C-GL| %.3g, > 1/255 %.2f%%, > 8/255 %.2f%%",
                 mode_names[g->mode], g->renderer, g->ms / 1e3, g->p99_rel, g->max_abs, 100.0 * g->over1,
                 100.0 * g->over8);
    else
        snprintf(buf, size, "compare (M): %s | %s", mode_names[g->mode],
                 g->failed ? "softlight-gl failed (the message line said why)" : "once the frame is exact");
}

void view_gl_free(viewer *v)
{
    sl_image_free(&v->gl.c_radiance);
    sl_image_free(&v->gl.radiance);
    sl_image_free(&v->gl.difference);
}

#else
typedef int view_gl_unused; /* this file is only built with SDL2 */
#endif
