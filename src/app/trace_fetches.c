/* trace_fetches.c - the texture fetches of one pixel for `softlight trace`: a hook on the textured
 * G-buffer program (sl_scene_textures.trace) records every fetch made at the traced pixel while
 * the frame is rasterized, and the print keeps those of the fragment whose texel the G-buffer
 * holds (its depth, not a helper), since overdraw, occluded fragments and helper lanes fetch
 * there too. A quad runs its lanes in rounds (quad.c) until the derivatives settle, so each
 * fragment fetches once per round: the last round's fetch of each map is the one whose value the
 * G-buffer got. Recording during the one raster of the trace, rather than re-drawing the pixel's
 * quad, means the printed values are the draw's own bits. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "trace_fetches.h"

static const char *const map_names[SL_MAP_COUNT] = {"kd_map",       "ks_map",        "alpha_map",
                                                    "normal_map",   "mask_map",      "metallic_roughness_map",
                                                    "occlusion_map", "emissive_map"};

static void record(void *ctx, const sl_fragment_in *in, int slot, const sl_sampler2D *s, vec2 uv, vec2 dPdx,
                   vec2 dPdy, float lambda, vec4 value)
{
    sl_trace_fetches *t = ctx;
    if (in->x != t->x || in->y != t->y)
        return;
    /* one tile, hence one thread, holds the pixel; the guard is for any future split of a tile */
#pragma omp critical(sl_trace_fetches)
    {
        if (t->count < SL_TRACE_MAX_FETCHES) {
            sl_trace_fetch *f = &t->fetches[t->count++];
            *f = (sl_trace_fetch){.slot = slot, .helper = in->helper, .depth = in->frag_coord.z, .uv = uv,
                                  .dPdx = dPdx, .dPdy = dPdy, .lambda = lambda, .value = value, .sampler = *s};
        } else {
            t->dropped++;
        }
    }
}

void sl_trace_fetches_hook(sl_trace_fetches *t, sl_scene_textures *textures, int x, int y)
{
    memset(t, 0, sizeof *t);
    t->x = x;
    t->y = y;
    textures->trace = record;
    textures->trace_ctx = t;
}

static const char *filter_name(sl_filter f)
{
    static const char *const names[] = {"NEAREST", "LINEAR", "NEAREST_MIPMAP_NEAREST", "LINEAR_MIPMAP_NEAREST",
                                        "NEAREST_MIPMAP_LINEAR", "LINEAR_MIPMAP_LINEAR"};
    return names[f];
}

/* Which level(s) the sample read: sl_texture_sample's choice (GL 4.6 section 8.14), in words. */
static void print_level(FILE *out, const sl_trace_fetch *f)
{
    const sl_texture *tex = f->sampler.texture;
    int last = sl_texture_levels(tex) - 1, w = 0, h = 0;
    sl_filter min = f->sampler.state.min_filter;
    if (!(f->lambda > 0.0f)) {
        sl_texture_level_texels(tex, 0, &w, &h);
        fprintf(out, "level 0 (%dx%d), magnified: %s", w, h, filter_name(f->sampler.state.mag_filter));
        return;
    }
    if (min == SL_NEAREST || min == SL_LINEAR) {
        sl_texture_level_texels(tex, 0, &w, &h);
        fprintf(out, "level 0 (%dx%d), minified: %s", w, h, filter_name(min));
        return;
    }
    if (min == SL_NEAREST_MIPMAP_NEAREST || min == SL_LINEAR_MIPMAP_NEAREST || f->lambda >= (float)last) {
        int l = f->lambda >= (float)last ? last : (int)rintf(f->lambda);
        sl_texture_level_texels(tex, l, &w, &h);
        fprintf(out, "level %d (%dx%d), minified: %s", l, w, h, filter_name(min));
        return;
    }
    int l = (int)floorf(f->lambda);
    sl_texture_level_texels(tex, l, &w, &h);
    fprintf(out, "levels %d (%dx%d) and %d, weight %.6g, minified: %s", l, w, h, l + 1,
            (double)(f->lambda - (float)l), filter_name(min));
}

void sl_trace_fetches_print(FILE *out, const sl_trace_fetches *t, float gbuffer_depth)
{
    int last[SL_MAP_COUNT]; /* per map, the last round's fetch of the fragment the G-buffer kept */
    for (int slot = 0; slot < SL_MAP_COUNT; slot++)
        last[slot] = -1;
    for (int i = 0; i < t->count; i++)
        if (!t->fetches[i].helper && t->fetches[i].depth == gbuffer_depth)
            last[t->fetches[i].slot] = i;
    int shown = 0;
    for (int slot = 0; slot < SL_MAP_COUNT; slot++) {
        if (last[slot] < 0)
            continue;
        const sl_trace_fetch *f = &t->fetches[last[slot]];
        if (shown++ == 0)
            fprintf(out, "texture fetches (G-buffer pass, the fragment that wrote this texel)\n");
        const sl_texture *tex = f->sampler.texture;
        fprintf(out, "  %s (%s, %d levels)\n", map_names[f->slot], sl_texture_format_name(sl_texture_get_format(tex)),
                sl_texture_levels(tex));
        fprintf(out, "    %-10s (%.8g, %.8g)\n", "uv", (double)f->uv.x, (double)f->uv.y);
        fprintf(out, "    %-10s (%.8g, %.8g)\n", "dPdx", (double)f->dPdx.x, (double)f->dPdx.y);
        fprintf(out, "    %-10s (%.8g, %.8g)\n", "dPdy", (double)f->dPdy.x, (double)f->dPdy.y);
        fprintf(out, "    %-10s %.8g (the 2x2 quad's: dPdx = lane 1 - lane 0, dPdy = lane 2 - lane 0)\n", "lambda",
                (double)f->lambda);
        fprintf(out, "    %-10s ", "level");
        print_level(out, f);
        fprintf(out, "\n    %-10s (%.8g, %.8g, %.8g, %.8g)\n", "value", (double)f->value.x, (double)f->value.y,
                (double)f->value.z, (double)f->value.w);
    }
    int others = t->count - shown + t->dropped;
    if (shown == 0)
        fprintf(out, "texture fetches: none by the fragment that wrote this texel (untextured or no geometry)\n");
    if (others > 0)
        fprintf(out, "  (%d more fetches here: earlier quad rounds, helper lanes, overdrawn or discarded fragments)\n",
                others);
}
