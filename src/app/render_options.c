/* render_options.c - the command line's words for the rendering options (see render_options.h).
 * Each option's spelling, default and limits come from the option table (core/options.h); what
 * is written here is only how --help describes it and where its value goes. */
#include "render_options.h"

#include <string.h>

/* Metavar and help per option, in the table's order (which is --help's). A range or default in
 * a help line is checked against the table by tests/unit/test_options.c. */
static const struct {
    const char *metavar, *help;
} words[SL_OPT_CLI_COUNT] = {
    [SL_OPT_SIZE] = {"WxH", "render size (default: the scene's)"},
    [SL_OPT_SAMPLES] = {"N", "specular samples N per pixel (1..1024)"},
    [SL_OPT_EXPOSURE] = {"E", "tone-map exposure e"},
    [SL_OPT_CONTRAST] = {"C", "tone-map contrast c (exponent c/2.2)"},
    [SL_OPT_SRGB] = {NULL, "encode with the exact sRGB curve instead of the 1/2.2 power"},
    [SL_OPT_LOD] = {NULL, "mip-level rule for specular samples (default spec-d4; pdf: gems without its +1)"},
    [SL_OPT_DISTORTION] = {NULL, "include the lat-long distortion in the mip level"},
    [SL_OPT_GTERM] = {NULL, "G/(L.N V.N): 1/(L.H)^2 (default) or 1"},
    [SL_OPT_ESTIMATOR] = {NULL,
                          "specular estimator: the specification's eq. (3) (default), consistent, microfacet sampling, or the split-sum lookup (prefiltered environment, no samples)"},
    [SL_OPT_IRRADIANCE] = {NULL, "diffuse irradiance (default: the scene's map if any, else oct, the pole-free octahedral map)"},
    [SL_OPT_ENV_LAYOUT] = {NULL, "the specular samples' mip chain: latlong (default; the specification's, as GL builds it) "
                                 "or oct, an octahedral chain without pole or seam"},
    [SL_OPT_DIFFUSE_ONLY] = {NULL, "image-based diffuse term only"},
    [SL_OPT_SPECULAR_ONLY] = {NULL, "image-based specular term only"},
    [SL_OPT_NO_LIGHTS] = {NULL, "ignore the scene's point lights"},
    [SL_OPT_THREADS] = {"N", "worker threads (default: all cores)"},
    [SL_OPT_TILE] = {"S", "raster tile size in pixels (power of two)"},
    [SL_OPT_ROTATE] = {NULL, "rotate the specular sample set per pixel (Cranley-Patterson): noise instead of banding"},
    [SL_OPT_FRAME] = {"N", "frame number of the rotation (--rotate): average frames 0..K-1 to converge"},
    [SL_OPT_PLAIN] = {NULL, "run the plain reference paths (per-pixel raster, the line-by-line port of lighting.frag) "
                            "to compare with the fast ones or to step through in a debugger"},
    [SL_OPT_ENV_LIGHTS] = {"K", "sum the environment's K brightest texels exactly, sample the rest (0..64; default 0: off)"},
    [SL_OPT_IMAGE_MEMORY] = {"MIB", "the most memory one image read from a file may take decoded, in MiB (1..4096; default 1024); "
                                    "an environment needs 2.4 (maps over 2048x1024) to 4.4 times that at its peak (softlight info)"},
};

void sl_render_options_table(sl_render_options *o, sl_arg *t)
{
    _Static_assert(SL_RENDER_OPTION_COUNT == SL_OPT_CLI_COUNT, "one command-line option per row of the table");
    memset(o, 0, sizeof *o);
    o->lod = o->gterm = o->estimator = o->irradiance = o->env_layout = -1;
    void *const value[SL_OPT_CLI_COUNT] = {
        [SL_OPT_SIZE] = o->size,
        [SL_OPT_SAMPLES] = &o->samples,
        [SL_OPT_EXPOSURE] = &o->exposure,
        [SL_OPT_CONTRAST] = &o->contrast,
        [SL_OPT_SRGB] = &o->srgb,
        [SL_OPT_LOD] = &o->lod,
        [SL_OPT_DISTORTION] = &o->distortion,
        [SL_OPT_GTERM] = &o->gterm,
        [SL_OPT_ESTIMATOR] = &o->estimator,
        [SL_OPT_IRRADIANCE] = &o->irradiance,
        [SL_OPT_ENV_LAYOUT] = &o->env_layout,
        [SL_OPT_DIFFUSE_ONLY] = &o->diffuse_only,
        [SL_OPT_SPECULAR_ONLY] = &o->specular_only,
        [SL_OPT_NO_LIGHTS] = &o->no_lights,
        [SL_OPT_THREADS] = &o->threads,
        [SL_OPT_TILE] = &o->tile,
        [SL_OPT_ROTATE] = &o->rotate,
        [SL_OPT_FRAME] = &o->frame,
        [SL_OPT_PLAIN] = &o->plain,
        [SL_OPT_ENV_LIGHTS] = &o->env_lights,
        [SL_OPT_IMAGE_MEMORY] = &o->image_memory,
    };
    static const sl_arg_type types[] = {[SL_OPTION_FLAG] = SL_ARG_FLAG, [SL_OPTION_INT] = SL_ARG_INT,
                                        [SL_OPTION_FLOAT] = SL_ARG_FLOAT, [SL_OPTION_SIZE] = SL_ARG_SIZE,
                                        [SL_OPTION_CHOICE] = SL_ARG_CHOICE};
    for (int id = 0; id < SL_OPT_CLI_COUNT; id++) {
        const sl_option *opt = &sl_options[id];
        const char *choices = NULL;
        double min = opt->min, max = opt->max;
        if (opt->type == SL_OPTION_CHOICE) {
            /* the words in the table's order: argument k is value min + k (sl_render_options_desc) */
            sl_option_choices(opt, o->choices[id], sizeof o->choices[id]);
            choices = o->choices[id];
            min = max = 0;
        } else if (opt->type == SL_OPTION_FLAG) {
            min = max = 0;
        }
        t[id] = (sl_arg){opt->cli, opt->alias, types[opt->type], value[id], min, max, choices, words[id].metavar,
                         words[id].help, NULL};
    }
}

/* The value a choice argument stands for: its index counts from the row's first value. */
static int choice_value(sl_option_id id, int index) { return (int)sl_options[id].min + index; }

bool sl_render_options_desc(const sl_render_options *o, sl_render_desc *d, sl_error *err)
{
    memset(d, 0, sizeof *d);
    if (o->diffuse_only && o->specular_only)
        return sl_fail(err, SL_ERR_RANGE, "--diffuse-only and --specular-only exclude each other");
    if (o->tile && (o->tile & (o->tile - 1)))
        return sl_fail(err, SL_ERR_RANGE, "--tile: %d is not a power of two", o->tile);
    d->width = o->size[0];
    d->height = o->size[1];
    d->threads = o->threads; /* -j: every parallel region of the library takes it from here */
    d->tile_size = o->tile;
    d->tonemap.exposure = o->exposure;
    d->tonemap.contrast = o->contrast;
    d->tonemap.exact_srgb = o->srgb;
    sl_lighting_options *l = &d->lighting;
    l->samples = o->samples;
    if (o->lod >= 0)
        l->lod_rule = (sl_lod_rule)choice_value(SL_OPT_LOD, o->lod);
    l->distortion = o->distortion;
    if (o->gterm >= 0)
        l->gterm = (sl_gterm)choice_value(SL_OPT_GTERM, o->gterm);
    if (o->estimator >= 0)
        l->estimator = (sl_estimator)choice_value(SL_OPT_ESTIMATOR, o->estimator);
    if (o->irradiance >= 0) {
        l->irradiance = (sl_irradiance_method)choice_value(SL_OPT_IRRADIANCE, o->irradiance);
        d->irradiance_set = true;
    }
    if (o->env_layout >= 0)
        l->env_layout = (sl_env_layout)choice_value(SL_OPT_ENV_LAYOUT, o->env_layout);
    l->plain = o->plain;
    d->plain_raster = o->plain;
    l->no_specular = o->diffuse_only;
    l->no_diffuse = o->specular_only;
    l->no_point_lights = o->no_lights || o->diffuse_only || o->specular_only;
    l->rotate = o->rotate;
    l->frame = (uint32_t)o->frame;
    l->env_lights = o->env_lights;
    d->image_budget = (size_t)o->image_memory << 20;
    return true;
}
