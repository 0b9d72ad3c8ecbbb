/* renderer_api.c - the public renderer (softlight/renderer.h) on top of sl_renderer_init: a heap
 * renderer made from the few options a caller sets, the lighting of a caller's G-buffer, and read
 * access to its frame. */
#include <stdlib.h>

#include "renderer.h"

sl_renderer *sl_renderer_create(const sl_scene *scene, const sl_renderer_options *opt, sl_error *err)
{
    sl_render_desc desc = {0};
    sl_option_values *o = &desc.options;
    if (opt) { /* zero: the scene's */
        if (opt->width && opt->height)
            sl_option_set_size(o, opt->width, opt->height);
        if (opt->samples)
            sl_option_set_samples(o, opt->samples);
        if (opt->exposure != 0.0f)
            sl_option_set_exposure(o, opt->exposure);
        if (opt->contrast != 0.0f)
            sl_option_set_contrast(o, opt->contrast);
        sl_option_set_threads(o, opt->threads);
    }
    sl_renderer *r = malloc(sizeof *r);
    if (!r) {
        sl_fail(err, SL_ERR_MEMORY, "out of memory for the renderer");
        return NULL;
    }
    if (!sl_renderer_init(r, scene, &desc, err)) {
        free(r);
        return NULL;
    }
    return r;
}

void sl_renderer_destroy(sl_renderer *r)
{
    if (!r)
        return;
    sl_renderer_free(r);
    free(r);
}

bool sl_renderer_light(sl_renderer *r, const sl_gbuffer *gb, const sl_camera *cam, sl_error *err)
{
    return sl_renderer_shade_tonemap(r, gb, cam, err);
}

const sl_image *sl_renderer_radiance(const sl_renderer *r) { return &r->radiance; }
const sl_image *sl_renderer_display(const sl_renderer *r) { return &r->display; }
const sl_gbuffer *sl_renderer_gbuffer(const sl_renderer *r) { return &r->gbuffer; }
