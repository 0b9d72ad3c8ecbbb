/* view_screenshot.c - the viewer's files: screenshots (F12 / P, the script's `screenshot`) and
 * the script's snapshots (the contract is in view_internal.h).
 *
 * Why a file of its own: a screenshot is a promise that the files mean what `softlight render`
 * means (full size, the user's N, whatever the window showed), so it completes the refinement
 * first (view_refine_finish); a snapshot is the opposite, the stage on screen as it is, for the
 * tests of the stages. Both only read the images the refinement left. */
#if SL_HAVE_SDL2
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "core/output_set.h"
#include "view_internal.h"

static bool file_exists(const char *path) { return access(path, F_OK) == 0; }

/* A PNG and its linear image, replaced together or not at all (one output set). */
static bool write_pair(const char *png, const sl_image *shown, const char *linear_path, sl_image_encoder encode,
                       const sl_image *linear, sl_error *err)
{
    sl_output_set out = {0};
    bool ok = sl_output_set_image(&out, png, sl_image_encode_png, shown, err) &&
              sl_output_set_image(&out, linear_path, encode, linear, err) && sl_output_set_commit(&out, err);
    sl_output_set_free(&out);
    return ok;
}

bool view_screenshot(viewer *v, const char *name, sl_error *err)
{
    if (!view_converged(v)) {
        if (!view_refine_finish(v, err))
            return false;
        view_present(v);
    }
    if (!view_shown_make(v, err)) /* the PNG is `shown`; the shading below replaces r.radiance */
        return false;
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
    /* the linear image behind what is shown: the comparison's (view_gl.c), else the frame's */
    const sl_image *linear = v->shown_from == VIEW_SHOWN_GL     ? &v->gl.radiance
                             : v->shown_from == VIEW_SHOWN_DIFF ? &v->gl.difference
                                                                : &v->r.radiance;
    if (!write_pair(png, &v->shown, hdr, sl_image_encode_hdr, linear, err))
        return false;
    const sl_camera *c = &v->camera.cam;
    printf("softlight view: wrote %s and %s (%dx%d, %s, N %d; camera eye %g,%g,%g target %g,%g,%g up %g,%g,%g "
           "fovy %g)\n",
           png, hdr, v->shown.width, v->shown.height, view_mode_name(v->mode), v->r.desc.lighting.samples,
           (double)c->eye.x, (double)c->eye.y, (double)c->eye.z, (double)c->target.x, (double)c->target.y,
           (double)c->target.z, (double)c->up.x, (double)c->up.y, (double)c->up.z, (double)c->fovy_deg);
    fflush(stdout);
    view_message(v, false, "wrote %s and %s", png, hdr);
    return true;
}

bool view_snapshot(viewer *v, const char *base, sl_error *err)
{
    if (!view_shown_make(v, err))
        return false;
    const sl_image *linear = v->shown_from == VIEW_SHOWN_MEAN       ? &v->mean
                             : v->shown_from == VIEW_SHOWN_RADIANCE ? &v->r.radiance
                             : v->shown_from == VIEW_SHOWN_GL       ? &v->gl.radiance
                             : v->shown_from == VIEW_SHOWN_DIFF     ? &v->gl.difference
                                                                    : NULL;
    if (!linear || !v->shown.data)
        return sl_fail(err, SL_ERR_RANGE, "snapshot: no lit image on screen (view %s)", view_mode_name(v->mode));
    char png[SL_PATH_MAX + 8], pfm[SL_PATH_MAX + 8];
    snprintf(png, sizeof png, "%s.png", base);
    snprintf(pfm, sizeof pfm, "%s.pfm", base);
    if (!write_pair(png, &v->shown, pfm, sl_image_encode_pfm, linear, err))
        return false;
    const view_stage_params *s = &v->shown_params;
    const char *stage = v->shown_stage == VIEW_STAGE_MOVING       ? "moving"
                        : v->shown_stage == VIEW_STAGE_ACCUMULATE ? "accumulating"
                                                                  : "exact";
    char lit[64];
    view_stage_describe(s, lit, sizeof lit);
    printf("softlight view: snapshot %s and %s (%dx%d, %s, %s, frame %u, %d frames averaged%s)\n", png, pfm,
           linear->width, linear->height, stage, lit, (unsigned)s->frame,
           v->shown_from == VIEW_SHOWN_MEAN ? v->acc_count : 1,
           v->radiance_exact && v->shown_from == VIEW_SHOWN_RADIANCE ? ", exact" : "");
    fflush(stdout);
    return true;
}

#else
typedef int view_screenshot_unused; /* this file is only built with SDL2 */
#endif
