/* gbuffer_io.c - the G-buffer as image files (AOVs) and as a debug view.
 *
 * Rows: the G-buffer's row 0 is the bottom (GL window coordinates), an sl_image's
 * row 0 is the top, and a PFM file stores the bottom row first. So G-buffer row y
 * becomes image row height-1-y, and sl_image_write_pfm puts it back at the start
 * of the file: a PFM viewer shows the frame upright, as GL's glReadPixels would
 * write it. Reading undoes the same two steps.
 *
 * Reading uses sl_image_read_pfm_signed, not sl_image_read_pfm: that reader repairs
 * negative texels to 0, as input radiance should be, but positions, normals and view
 * vectors are signed.
 *
 * The same channels go into one multi-layer .exr with the radiance (sl_gbuffer_add_exr): layer
 * names are the AOV names, channel suffixes the components (normal.X, kd.R), a one-channel AOV a
 * channel of its own name; 32-bit float, so each holds the PFM's numbers (half would round
 * positions and depth, and overflow past 65504 radiance, which a sun reaches).
 *
 * A G-buffer with the extra plane (gbuffer.h: occlusion, emission) adds occlusion.pfm and
 * emissive.pfm (layers `occlusion`, `emissive.R/G/B`); one without it writes neither, and reading
 * takes the plane when both files are there. One with the ambient occlusion's cone plane
 * (sl_gbuffer.cone) adds bent.pfm and ao.pfm the same way (layers `bent.X/Y/Z`, `ao`), and one with
 * the facet plane (sl_gbuffer.facet) facet.pfm (layer `facet.X/Y/Z`). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/exr.h"
#include "gbuffer.h"
#include "raster.h"

/* OCCLUSION and EMISSIVE are the extra plane's (gbuffer.h), BENT and AO the cone plane's, FACET
 * the facet plane's, each written only by a G-buffer that has the plane. */
enum {
    AOV_POSITION,
    AOV_NORMAL,
    AOV_VIEW,
    AOV_KD,
    AOV_KS,
    AOV_ALPHA,
    AOV_DEPTH,
    AOV_MASK,
    AOV_OCCLUSION,
    AOV_EMISSIVE,
    AOV_BENT,
    AOV_AO,
    AOV_FACET,
    AOV_COUNT
};
static const char *const aov_names[AOV_COUNT] = {"position", "normal", "view", "kd", "ks", "alpha", "depth", "mask",
                                                 "occlusion", "emissive", "bent", "ao", "facet"};
static const int aov_channels[AOV_COUNT] = {3, 3, 3, 3, 3, 1, 1, 1, 1, 3, 3, 1, 3};
static const char *const aov_suffixes[AOV_COUNT] = {"XYZ", "XYZ", "XYZ", "RGB", "RGB", "", "",
                                                    "",    "",    "RGB", "XYZ", "",  "XYZ"};

/* Whether a G-buffer has the AOV: the extra plane's two only with it, the cone's and the facet's
 * only with theirs. */
static bool aov_present(const sl_gbuffer *gb, int aov)
{
    if (aov == AOV_FACET)
        return gb->facet != NULL;
    return aov < AOV_OCCLUSION || (aov < AOV_BENT ? gb->extra != NULL : gb->cone != NULL);
}

static bool aov_path(char *path, size_t size, const char *dir, int aov, sl_error *err)
{
    int n = snprintf(path, size, "%s/%s.pfm", dir, aov_names[aov]);
    if (n < 0 || (size_t)n >= size)
        return sl_fail(err, SL_ERR_RANGE, "%s: directory name too long", dir);
    return true;
}

/* The AOV value of texel (x, y), in `out` (1 or 3 floats). */
static void aov_get(const sl_gbuffer *gb, int x, int y, vec3 eye, int aov, float *out)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
    const sl_gbuffer_extra *e = gb->extra ? gb->extra + (t - gb->texels) : NULL;
    bool covered = sl_gbuffer_covered(t);
    vec3 v = vec3s(0.0f);
    switch (aov) {
    case AOV_POSITION: v = t->position; break;
    case AOV_NORMAL: v = t->normal; break;
    case AOV_VIEW:
        if (covered) {
            vec3 d = sub(eye, t->position);
            v = dot(d, d) > 0.0f ? normalize(d) : vec3s(0.0f);
        }
        break;
    case AOV_KD: v = t->kd; break;
    case AOV_KS: v = t->ks; break;
    case AOV_ALPHA: out[0] = t->alpha; return;
    case AOV_DEPTH: out[0] = t->depth; return;
    case AOV_MASK: out[0] = covered ? 1.0f : 0.0f; return;
    case AOV_OCCLUSION: out[0] = e ? e->occlusion : 1.0f; return;
    case AOV_BENT: v = gb->cone ? xyz(gb->cone[t - gb->texels]) : t->normal; break;
    case AOV_AO: out[0] = gb->cone ? gb->cone[t - gb->texels].w : 1.0f; return;
    case AOV_FACET: v = gb->facet ? gb->facet[t - gb->texels] : vec3s(0.0f); break;
    default: v = e ? e->emissive : vec3s(0.0f); break;
    }
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
}

static void aov_set(sl_gbuffer *gb, int x, int y, int aov, const float *in)
{
    sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
    sl_gbuffer_extra *e = gb->extra ? gb->extra + (t - gb->texels) : NULL;
    vec3 v = aov_channels[aov] == 3 ? vec3(in[0], in[1], in[2]) : vec3s(in[0]);
    if (e) /* tagged as the resolve leaves the plane (gbuffer.h) */
        e->depth = t->depth;
    switch (aov) {
    case AOV_OCCLUSION: if (e) e->occlusion = in[0]; break;
    case AOV_EMISSIVE: if (e) e->emissive = v; break;
    case AOV_BENT: if (gb->cone) gb->cone[t - gb->texels] = vec4(v.x, v.y, v.z, gb->cone[t - gb->texels].w); break;
    case AOV_AO: if (gb->cone) gb->cone[t - gb->texels].w = in[0]; break;
    case AOV_FACET: if (gb->facet) gb->facet[t - gb->texels] = v; break;
    case AOV_POSITION: t->position = v; break;
    case AOV_NORMAL: t->normal = v; break;
    case AOV_KD: t->kd = v; break;
    case AOV_KS: t->ks = v; break;
    case AOV_ALPHA: t->alpha = in[0]; break;
    case AOV_DEPTH: t->depth = in[0]; break;
    default: break;
    }
}

bool sl_gbuffer_read_aov_image(const char *path, sl_image *img, sl_error *err)
{
    return sl_image_read_pfm_signed(path, 0, img, err);
}

bool sl_gbuffer_write_aovs(const sl_gbuffer *gb, vec3 eye, const char *dir, sl_error *err)
{
    sl_output_set out = {0};
    bool ok = sl_gbuffer_add_aovs(gb, eye, dir, &out, err) && sl_output_set_commit(&out, err);
    sl_output_set_free(&out);
    return ok;
}

bool sl_gbuffer_add_aovs(const sl_gbuffer *gb, vec3 eye, const char *dir, sl_output_set *out, sl_error *err)
{
    if (!gb->texels)
        return sl_fail(err, SL_ERR_RANGE, "%s: empty G-buffer", dir);
    sl_image img[2] = {{0}, {0}};
    if (!sl_image_alloc(&img[0], gb->width, gb->height, 1, err) ||
        !sl_image_alloc(&img[1], gb->width, gb->height, 3, err)) {
        sl_image_free(&img[0]);
        return false;
    }
    bool ok = true;
    for (int aov = 0; ok && aov < AOV_COUNT; aov++) {
        if (!aov_present(gb, aov))
            continue;
        sl_image *im = &img[aov_channels[aov] == 3];
        for (int y = 0; y < gb->height; y++)
            for (int x = 0; x < gb->width; x++)
                aov_get(gb, x, y, eye, aov, sl_image_pixel(im, x, gb->height - 1 - y));
        char path[4096];
        ok = aov_path(path, sizeof path, dir, aov, err) && sl_output_set_image(out, path, sl_image_encode_pfm, im, err);
    }
    sl_image_free(&img[0]);
    sl_image_free(&img[1]);
    return ok;
}

/* One AOV as an image, row 0 = top (allocates img). */
static bool aov_image(const sl_gbuffer *gb, vec3 eye, int aov, sl_image *img, sl_error *err)
{
    if (!sl_image_alloc(img, gb->width, gb->height, aov_channels[aov], err))
        return false;
    for (int y = 0; y < gb->height; y++)
        for (int x = 0; x < gb->width; x++)
            aov_get(gb, x, y, eye, aov, sl_image_pixel(img, x, gb->height - 1 - y));
    return true;
}

bool sl_gbuffer_add_exr(const sl_gbuffer *gb, vec3 eye, const sl_image *radiance, const char *path,
                        sl_output_set *out, sl_error *err)
{
    if (!gb->texels)
        return sl_fail(err, SL_ERR_RANGE, "%s: empty G-buffer", path);
    if (radiance->width != gb->width || radiance->height != gb->height || radiance->channels != 3)
        return sl_fail(err, SL_ERR_RANGE, "%s: radiance %dx%dx%d does not match the G-buffer %dx%d", path,
                       radiance->width, radiance->height, radiance->channels, gb->width, gb->height);
    sl_image img[AOV_COUNT] = {{0}};
    sl_exr_layer layers[AOV_COUNT + 1] = {{"", "RGB", radiance}};
    bool ok = true;
    int count = 0;
    for (int aov = 0; ok && aov < AOV_COUNT; aov++) {
        if (!aov_present(gb, aov))
            continue;
        ok = aov_image(gb, eye, aov, &img[aov], err);
        layers[++count] = (sl_exr_layer){aov_names[aov], aov_suffixes[aov], &img[aov]};
    }
    unsigned char *bytes = NULL;
    size_t size = 0;
    ok = ok && sl_exr_encode(layers, count + 1, &(sl_exr_options){.compression = SL_EXR_ZIP}, &bytes, &size, err);
    if (!ok)
        sl_error_prefix(err, "%s: ", path);
    ok = ok && sl_output_set_bytes(out, path, bytes, size, err);
    free(bytes);
    for (int aov = 0; aov < AOV_COUNT; aov++)
        sl_image_free(&img[aov]);
    return ok;
}

bool sl_gbuffer_read_aovs(const char *dir, sl_gbuffer *gb, sl_error *err)
{
    sl_image img = {0};
    bool ok = true;
    int width = 0, height = 0;
    /* the extra plane's files come as a pair, or not at all */
    char extra_path[2][4096];
    if (!aov_path(extra_path[0], sizeof extra_path[0], dir, AOV_OCCLUSION, err) ||
        !aov_path(extra_path[1], sizeof extra_path[1], dir, AOV_EMISSIVE, err))
        return false;
    FILE *f[2] = {fopen(extra_path[0], "rb"), fopen(extra_path[1], "rb")};
    bool extra = f[0] && f[1], half = !extra && (f[0] || f[1]);
    for (int i = 0; i < 2; i++)
        if (f[i])
            fclose(f[i]);
    if (half)
        return sl_fail(err, SL_ERR_FORMAT, "%s: occlusion.pfm and emissive.pfm come together (the G-buffer's extra "
                       "channels); only %s is there", dir, f[0] ? "occlusion.pfm" : "emissive.pfm");
    /* and so do the cone plane's */
    char cone_path[2][4096];
    if (!aov_path(cone_path[0], sizeof cone_path[0], dir, AOV_BENT, err) ||
        !aov_path(cone_path[1], sizeof cone_path[1], dir, AOV_AO, err))
        return false;
    FILE *g[2] = {fopen(cone_path[0], "rb"), fopen(cone_path[1], "rb")};
    bool cone = g[0] && g[1], cone_half = !cone && (g[0] || g[1]);
    for (int i = 0; i < 2; i++)
        if (g[i])
            fclose(g[i]);
    if (cone_half)
        return sl_fail(err, SL_ERR_FORMAT, "%s: bent.pfm and ao.pfm come together (the ambient occlusion's cone); "
                       "only %s is there", dir, g[0] ? "bent.pfm" : "ao.pfm");
    /* the facet plane's file is read where it is there */
    char facet_path[4096];
    if (!aov_path(facet_path, sizeof facet_path, dir, AOV_FACET, err))
        return false;
    FILE *h = fopen(facet_path, "rb");
    bool facet = h != NULL;
    if (h)
        fclose(h);
    for (int aov = 0; ok && aov < AOV_COUNT; aov++) {
        if (aov == AOV_VIEW || (!extra && (aov == AOV_OCCLUSION || aov == AOV_EMISSIVE)) ||
            (!cone && (aov == AOV_BENT || aov == AOV_AO)) || (!facet && aov == AOV_FACET))
            continue;
        char path[4096];
        if (!aov_path(path, sizeof path, dir, aov, err) || !sl_gbuffer_read_aov_image(path, &img, err))
            return false;
        if (aov == AOV_POSITION) {
            width = img.width;
            height = img.height;
            ok = sl_gbuffer_resize(gb, width, height, err) && sl_gbuffer_use_extra(gb, extra, 0, err) &&
                 sl_gbuffer_use_facet(gb, facet, err);
            free(gb->cone);
            gb->cone = NULL;
            if (ok && cone && !(gb->cone = calloc((size_t)width * (size_t)height, sizeof *gb->cone)))
                ok = sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for the cone plane", dir);
            if (ok)
                sl_gbuffer_clear(gb, 0);
        } else if (img.width != width || img.height != height) {
            ok = sl_fail(err, SL_ERR_FORMAT, "%s: %dx%d, but position.pfm is %dx%d", path, img.width, img.height,
                         width, height);
        }
        if (ok && img.channels != aov_channels[aov])
            ok = sl_fail(err, SL_ERR_FORMAT, "%s: %d channels, expected %d", path, img.channels, aov_channels[aov]);
        for (int y = 0; ok && y < height; y++) {
            for (int x = 0; x < width; x++) {
                sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
                const float *p = sl_image_pixel(&img, x, height - 1 - y);
                if (aov != AOV_MASK) {
                    aov_set(gb, x, y, aov, p);
                } else if ((p[0] != 0.0f) != sl_gbuffer_covered(t)) {
                    ok = sl_fail(err, SL_ERR_FORMAT, "%s: pixel (%d, %d) from the bottom: mask %g but depth %g", path,
                                 x, y, (double)p[0], (double)t->depth);
                    break;
                }
            }
        }
        sl_image_free(&img);
    }
    return ok;
}

bool sl_gbuffer_normal_image(const sl_gbuffer *gb, sl_image *img, sl_error *err)
{
    if (!gb->texels)
        return sl_fail(err, SL_ERR_RANGE, "normal view: empty G-buffer");
    if (!sl_image_alloc(img, gb->width, gb->height, 3, err))
        return false;
    for (int y = 0; y < gb->height; y++) {
        for (int x = 0; x < gb->width; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
            if (!sl_gbuffer_covered(t))
                continue;
            float *p = sl_image_pixel(img, x, gb->height - 1 - y);
            vec3 c = add(scale(t->normal, 0.5f), vec3s(0.5f));
            p[0] = c.x;
            p[1] = c.y;
            p[2] = c.z;
        }
    }
    return true;
}
