/* render_options.c - see render_options.h. */
#include "render_options.h"

#include <string.h>

void sl_render_options_table(sl_render_options *o, sl_arg *t)
{
    memset(o, 0, sizeof *o);
    o->lod = o->gterm = o->estimator = o->irradiance = -1;
    const sl_arg table[SL_RENDER_OPTION_COUNT] = {
        {"--size", NULL, SL_ARG_SIZE, o->size, 1, SL_RASTER_MAX_SIZE, NULL, "WxH", "render size (default: the scene's)", NULL},
        {"--samples", "-n", SL_ARG_INT, &o->samples, 1, SL_HAMMERSLEY_MAX, NULL, "N", "specular samples N per pixel (1..1024)", NULL},
        {"--exposure", "-e", SL_ARG_FLOAT, &o->exposure, 0.001, 1e6, NULL, "E", "tone-map exposure e", NULL},
        {"--contrast", "-c", SL_ARG_FLOAT, &o->contrast, 0.01, 100, NULL, "C", "tone-map contrast c (exponent c/2.2)", NULL},
        {"--srgb", NULL, SL_ARG_FLAG, &o->srgb, 0, 0, NULL, NULL, "encode with the exact sRGB curve instead of the 1/2.2 power", NULL},
        {"--lod", NULL, SL_ARG_CHOICE, &o->lod, 0, 0, "none|spec|spec-d4|gems|pdf", NULL,
         "mip-level rule for specular samples (default spec-d4; pdf: gems without its +1)", NULL},
        {"--distortion", NULL, SL_ARG_FLAG, &o->distortion, 0, 0, NULL, NULL, "include the lat-long distortion in the mip level", NULL},
        {"--g", NULL, SL_ARG_CHOICE, &o->gterm, 0, 0, "inv-lh2|one", NULL, "G/(L.N V.N): 1/(L.H)^2 (default) or 1", NULL},
        {"--estimator", NULL, SL_ARG_CHOICE, &o->estimator, 0, 0, "spec|consistent|mf", NULL,
         "specular estimator: the specification's eq. (3) (default), consistent, or microfacet sampling", NULL},
        {"--irradiance", NULL, SL_ARG_CHOICE, &o->irradiance, 0, 0, "sh9|brute|map|oct|dp", NULL,
         "diffuse irradiance (default: the scene's map if any, else oct, the pole-free octahedral map)", NULL},
        {"--diffuse-only", NULL, SL_ARG_FLAG, &o->diffuse_only, 0, 0, NULL, NULL, "image-based diffuse term only", NULL},
        {"--specular-only", NULL, SL_ARG_FLAG, &o->specular_only, 0, 0, NULL, NULL, "image-based specular term only", NULL},
        {"--no-lights", NULL, SL_ARG_FLAG, &o->no_lights, 0, 0, NULL, NULL, "ignore the scene's point lights", NULL},
        {"--threads", "-j", SL_ARG_INT, &o->threads, 1, 256, NULL, "N", "worker threads (default: all cores)", NULL},
        {"--tile", NULL, SL_ARG_INT, &o->tile, SL_TILE_MIN, SL_TILE_MAX, NULL, "S", "raster tile size in pixels (power of two)", NULL},
        {"--rotate", NULL, SL_ARG_FLAG, &o->rotate, 0, 0, NULL, NULL,
         "rotate the specular sample set per pixel (Cranley-Patterson): noise instead of banding", NULL},
        {"--frame", NULL, SL_ARG_INT, &o->frame, 0, 1e9, NULL, "N",
         "frame number of the rotation (--rotate): average frames 0..K-1 to converge", NULL},
        {"--plain", NULL, SL_ARG_FLAG, &o->plain, 0, 0, NULL, NULL,
         "run the plain reference paths (per-pixel raster, the line-by-line port of lighting.frag) "
         "to compare with the fast ones or to step through in a debugger", NULL},
        {"--env-lights", NULL, SL_ARG_INT, &o->env_lights, 0, SL_ENV_LIGHTS_MAX, NULL, "K",
         "sum the environment's K brightest texels exactly, sample the rest (0..64; default 0: off)", NULL},
    };
    memcpy(t, table, sizeof table);
}

bool sl_render_options_desc(const sl_render_options *o, sl_render_desc *d, sl_error *err)
{
    memset(d, 0, sizeof *d);
    if (o->diffuse_only && o->specular_only)
        return sl_fail(err, SL_ERR_RANGE, "--diffuse-only and --specular-only exclude each other");
    if (o->tile && (o->tile & (o->tile - 1)))
        return sl_fail(err, SL_ERR_RANGE, "--tile: %d is not a power of two", o->tile);
    d->width = o->size[0];
    d->height = o->size[1];
    d->threads = o->threads;
    d->tile_size = o->tile;
    d->tonemap.exposure = o->exposure;
    d->tonemap.contrast = o->contrast;
    d->tonemap.exact_srgb = o->srgb;
    sl_lighting_options *l = &d->lighting;
    l->samples = o->samples;
    if (o->lod >= 0)
        l->lod_rule = (sl_lod_rule)(SL_LOD_NONE + o->lod);
    l->distortion = o->distortion;
    if (o->gterm >= 0)
        l->gterm = (sl_gterm)(SL_GTERM_INV_LH2 + o->gterm);
    if (o->estimator >= 0)
        l->estimator = (sl_estimator)(SL_ESTIMATOR_SPEC + o->estimator);
    if (o->irradiance >= 0) {
        static const sl_irradiance_method methods[] = {SL_IRRADIANCE_SH9, SL_IRRADIANCE_BRUTE, SL_IRRADIANCE_MAP,
                                                        SL_IRRADIANCE_OCT, SL_IRRADIANCE_DP};
        l->irradiance = methods[o->irradiance];
        d->irradiance_set = true;
    }
    l->plain = o->plain;
    d->plain_raster = o->plain;
    l->no_specular = o->diffuse_only;
    l->no_diffuse = o->specular_only;
    l->no_point_lights = o->no_lights || o->diffuse_only || o->specular_only;
    l->rotate = o->rotate;
    l->frame = (uint32_t)o->frame;
    l->env_lights = o->env_lights;
    return true;
}
