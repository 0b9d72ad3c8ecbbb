/* view_image.c - the images the viewer can show besides the tone-mapped frame: G-buffer
 * channels and the per-pixel mip level of the specular samples, the 8-bit conversion every
 * shown image goes through on its way into the window's texture, and the tone-mapped frame made
 * into `shown` when it went straight into the window (view_shown_make). No SDL here. */
#include "view_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "post/tonemap.h"
#include "shading/lighting_trace.h"

static const char *const mode_names[VIEW_MODE_COUNT] = {
    "final", "position", "normal", "kd", "ks", "alpha", "depth", "mip level",
};

const char *view_mode_name(view_mode mode)
{
    return (unsigned)mode < VIEW_MODE_COUNT ? mode_names[mode] : "?";
}

bool view_mode_needs_shading(view_mode mode) { return mode == VIEW_FINAL; }
bool view_mode_needs_lighting(view_mode mode) { return mode == VIEW_FINAL || mode == VIEW_MIP; }

static bool ensure_rgb(sl_image *img, int width, int height, sl_error *err)
{
    if (img->data && img->width == width && img->height == height && img->channels == 3)
        return true;
    sl_image_free(img);
    return sl_image_alloc(img, width, height, 3, err);
}

bool view_shown_make(viewer *v, sl_error *err)
{
    if (!v->shown_pending)
        return true;
    v->shown_pending = false;
    return sl_renderer_tonemap(&v->r, err) && view_image_take(&v->shown, &v->r.display, err);
}

void view_shown_size(const viewer *v, int *w, int *h)
{
    const sl_image *img = v->shown_pending ? &v->r.radiance : &v->shown;
    *w = img->data ? img->width : 0;
    *h = img->data ? img->height : 0;
}

bool view_image_take(sl_image *dst, sl_image *src, sl_error *err)
{
    if (src->channels != 3)
        return sl_fail(err, SL_ERR_RANGE, "view: expected a 3-channel image, got %d channels", src->channels);
    if (dst->data && dst->width == src->width && dst->height == src->height && dst->channels == 3) {
        /* a swap: a 1280x720 copy is 11 MB of memory traffic a frame */
        sl_image t = *dst;
        *dst = *src;
        *src = t;
        return true;
    }
    if (!ensure_rgb(dst, src->width, src->height, err))
        return false;
    memcpy(dst->data, src->data, (size_t)src->width * (size_t)src->height * 3 * sizeof(float));
    return true;
}

/* Window depth back to the distance along the view axis, for a GL perspective projection:
 * z_ndc = 2 d - 1, z_eye = 2 n f / (f + n - z_ndc (f - n)). */
static float eye_depth(float d, float n, float f)
{
    float z_ndc = 2.0f * d - 1.0f;
    return 2.0f * n * f / (f + n - z_ndc * (f - n));
}

static vec3 encode(vec3 c)
{
    return vec3(sl_linear_to_gamma(c.x), sl_linear_to_gamma(c.y), sl_linear_to_gamma(c.z));
}

bool view_channel_image(const sl_gbuffer *gb, view_mode mode, vec3 lo, vec3 hi, float znear, float zfar,
                        sl_image *out, float depth_range[2], sl_error *err)
{
    if (mode < VIEW_POSITION || mode > VIEW_DEPTH)
        return sl_fail(err, SL_ERR_RANGE, "view: '%s' is not a G-buffer channel", view_mode_name(mode));
    if (!ensure_rgb(out, gb->width, gb->height, err))
        return false;
    /* Depth is shown relative to what is on screen, so the range is found first. */
    float dmin = INFINITY, dmax = -INFINITY;
    if (mode == VIEW_DEPTH) {
        for (int i = 0; i < gb->width * gb->height; i++) {
            const sl_gbuffer_texel *t = &gb->texels[i];
            if (!sl_gbuffer_covered(t))
                continue;
            float z = eye_depth(t->depth, znear, zfar);
            dmin = minf(dmin, z);
            dmax = maxf(dmax, z);
        }
    }
    if (depth_range) {
        depth_range[0] = dmin;
        depth_range[1] = dmax;
    }
    vec3 extent = vmax(sub(hi, lo), vec3s(1e-6f));
    /* log(1 + alpha) / log(1 + 10000): the specification's range of alpha in one grey ramp. */
    const float alpha_norm = 1.0f / log1pf(10000.0f);
    for (int y = 0; y < gb->height; y++) {
        const sl_gbuffer_texel *row = sl_gbuffer_at(gb, 0, gb->height - 1 - y); /* row 0 = top */
        for (int x = 0; x < gb->width; x++) {
            const sl_gbuffer_texel *t = &row[x];
            vec3 c = vec3s(0.0f);
            if (sl_gbuffer_covered(t)) {
                switch (mode) {
                case VIEW_POSITION:
                    c = clamp(mul(sub(t->position, lo), vec3(1.0f / extent.x, 1.0f / extent.y, 1.0f / extent.z)),
                              0.0f, 1.0f);
                    break;
                case VIEW_NORMAL:
                    c = clamp(add(scale(t->normal, 0.5f), vec3s(0.5f)), 0.0f, 1.0f);
                    break;
                case VIEW_KD:
                    c = encode(t->kd);
                    break;
                case VIEW_KS:
                    c = encode(t->ks);
                    break;
                case VIEW_ALPHA:
                    c = vec3s(clampf(log1pf(maxf(t->alpha, 0.0f)) * alpha_norm, 0.0f, 1.0f));
                    break;
                case VIEW_DEPTH: {
                    float z = eye_depth(t->depth, znear, zfar);
                    float range = dmax - dmin;
                    c = vec3s(range > 0.0f ? clampf(1.0f - (z - dmin) / range, 0.0f, 1.0f) : 1.0f);
                    break;
                }
                default:
                    break;
                }
            }
            float *p = sl_image_pixel(out, x, y);
            p[0] = c.x;
            p[1] = c.y;
            p[2] = c.z;
        }
    }
    return true;
}

float view_trace_mean_level(const sl_lighting_trace *trace)
{
    float sum = 0.0f;
    int used = 0;
    for (int k = 0; k < trace->sample_count; k++)
        if (trace->samples[k].wN > 0.0f) {
            sum += trace->samples[k].lod;
            used++;
        }
    return used ? sum / (float)used : NAN;
}

/* Blue (0) -> cyan -> green -> yellow -> red (1): levels stay tellable apart at a glance. */
static vec3 ramp(float t)
{
    static const vec3 stops[5] = {{0, 0, 1}, {0, 1, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
    t = clampf(t, 0.0f, 1.0f) * 4.0f;
    int i = (int)t;
    if (i >= 4)
        return stops[4];
    return mix(stops[i], stops[i + 1], t - (float)i);
}

bool view_mip_image(const sl_lighting_uniforms *u, const sl_gbuffer *gb, sl_image *out, float *max_level_seen,
                    sl_error *err)
{
    if (!ensure_rgb(out, gb->width, gb->height, err))
        return false;
    float max_level = u->uEnvMaxLod > 0.0f ? u->uEnvMaxLod : 1.0f;
    float seen = 0.0f;
    bool ok = true;
    /* The trace is large (every sample of a pixel); one per thread, reused for every pixel.
     * Rows are independent, so the image does not depend on the thread count. */
#pragma omp parallel reduction(max : seen)
    {
        sl_lighting_trace *trace = malloc(sizeof *trace);
        if (!trace) {
#pragma omp atomic write
            ok = false;
        }
#pragma omp for schedule(dynamic, 4)
        for (int y = 0; y < gb->height; y++) {
            if (!trace)
                continue;
            int y_gb = gb->height - 1 - y;
            for (int x = 0; x < gb->width; x++) {
                float *p = sl_image_pixel(out, x, y);
                if (!sl_gbuffer_covered(sl_gbuffer_at(gb, x, y_gb))) {
                    p[0] = p[1] = p[2] = 0.0f;
                    continue;
                }
                trace->sample_count = 0;
                sl_lighting_shade(u, gb, x, y_gb, NULL, trace);
                float mean = view_trace_mean_level(trace);
                /* Covered, but no sample reached the environment (specular off, or all below
                 * the horizon): dark grey, not a level. */
                vec3 c = vec3s(0.15f);
                if (!isnan(mean)) {
                    seen = maxf(seen, mean);
                    c = ramp(mean / max_level);
                }
                p[0] = c.x;
                p[1] = c.y;
                p[2] = c.z;
            }
        }
        free(trace);
    }
    if (!ok)
        return sl_fail(err, SL_ERR_MEMORY, "view: out of memory for the mip-level trace");
    if (max_level_seen)
        *max_level_seen = seen;
    return true;
}

/* One channel's 8-bit code, rounded like the PNG writer; NaN -> 0. */
static inline uint32_t code8(float v)
{
    v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
    return (uint32_t)(v * 255.0f + 0.5f);
}

void view_image_to_xrgb8888(const sl_image *img, uint8_t *pixels, int pitch)
{
    /* rows over the threads: one thread took 1.9-3 ms at 1280x720, most of the upload */
#pragma omp parallel for schedule(static)
    for (int y = 0; y < img->height; y++) {
        const float *src = sl_image_pixel(img, 0, y);
        uint32_t *dst = (uint32_t *)(void *)(pixels + (size_t)y * (size_t)pitch);
        for (int x = 0; x < img->width; x++)
            dst[x] = 0xff000000u | code8(src[3 * x]) << 16 | code8(src[3 * x + 1]) << 8 | code8(src[3 * x + 2]);
    }
}
