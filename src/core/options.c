/* options.c - the option table (options.h): each option's spelling, default and limits, written
 * once. A new option is a row here, a field where it is used (sl_lighting_options, the
 * renderer's description), its words in src/app/render_options.c and, if a scene file may set
 * it, a key in src/scene/scene.c; tests/unit/test_options.c fails until the four agree. */
#include "options.h"

#include <stdio.h>
#include <string.h>

static const char *const lod_names[] = {
    [SL_LOD_DEFAULT] = "default", [SL_LOD_NONE] = "none", [SL_LOD_SPEC] = "spec",
    [SL_LOD_SPEC_D4] = "spec-d4", [SL_LOD_GEMS] = "gems", [SL_LOD_PDF] = "pdf",
};
static const char *const gterm_names[] = {
    [SL_GTERM_DEFAULT] = "default", [SL_GTERM_INV_LH2] = "inv-lh2", [SL_GTERM_ONE] = "one",
};
static const char *const estimator_names[] = {
    [SL_ESTIMATOR_DEFAULT] = "default", [SL_ESTIMATOR_SPEC] = "spec", [SL_ESTIMATOR_CONSISTENT] = "consistent",
    [SL_ESTIMATOR_MICROFACET] = "mf", [SL_ESTIMATOR_SPLITSUM] = "splitsum",
};
static const char *const irradiance_names[] = {
    [SL_IRRADIANCE_SH9] = "sh9", [SL_IRRADIANCE_BRUTE] = "brute", [SL_IRRADIANCE_MAP] = "map",
    [SL_IRRADIANCE_OCT] = "oct", [SL_IRRADIANCE_DP] = "dp",
};
static const char *const env_layout_names[] = {
    [SL_ENV_LAYOUT_DEFAULT] = "default", [SL_ENV_LAYOUT_LATLONG] = "latlong", [SL_ENV_LAYOUT_OCT] = "oct",
};

#define FLAG(id, spelling) [id] = {.name = spelling, .cli = "--" spelling, .type = SL_OPTION_FLAG}

const sl_option sl_options[SL_OPT_COUNT] = {
    [SL_OPT_SIZE] = {.name = "size", .cli = "--size", .scene = {"render.width", "render.height"},
                     .type = SL_OPTION_SIZE, .def = {1280, 720}, .min = 1, .max = SL_RASTER_MAX_SIZE},
    /* N: the specification suggests 20 to 40 */
    [SL_OPT_SAMPLES] = {.name = "samples", .cli = "--samples", .alias = "-n", .scene = {"render.samples"},
                        .type = SL_OPTION_INT, .def = {40}, .min = 1, .max = SL_HAMMERSLEY_MAX},
    /* e of the tone map: a scene file keeps to the specification's range for its environments,
     * the command line and the viewer's keys go beyond it (src/post/tonemap.h) */
    [SL_OPT_EXPOSURE] = {.name = "exposure", .cli = "--exposure", .alias = "-e", .scene = {"render.exposure"},
                         .type = SL_OPTION_FLOAT, .def = {1}, .min = 0.001, .max = 1e6, .file_min = 0.1,
                         .file_max = 10000.0},
    /* c of the tone map's exponent c/2.2 */
    [SL_OPT_CONTRAST] = {.name = "contrast", .cli = "--contrast", .alias = "-c", .scene = {"render.contrast"},
                         .type = SL_OPTION_FLOAT, .def = {1}, .min = 0.01, .max = 100, .file_min = 0.0,
                         .file_max = 10.0, .file_min_open = true},
    FLAG(SL_OPT_SRGB, "srgb"),
    [SL_OPT_LOD] = {.name = "lod", .cli = "--lod", .scene = {"render.lod"}, .type = SL_OPTION_CHOICE, .def = {SL_LOD_SPEC_D4},
                    .min = SL_LOD_NONE, .max = SL_LOD_PDF, .names = lod_names},
    [SL_OPT_DISTORTION] = {.name = "distortion", .cli = "--distortion", .scene = {"render.distortion"},
                           .type = SL_OPTION_FLAG},
    [SL_OPT_GTERM] = {.name = "gterm", .cli = "--g", .scene = {"render.gterm"}, .type = SL_OPTION_CHOICE, .def = {SL_GTERM_INV_LH2},
                      .min = SL_GTERM_INV_LH2, .max = SL_GTERM_ONE, .names = gterm_names},
    [SL_OPT_ESTIMATOR] = {.name = "estimator", .cli = "--estimator", .scene = {"render.estimator"}, .type = SL_OPTION_CHOICE,
                          .def = {SL_ESTIMATOR_SPEC}, .min = SL_ESTIMATOR_SPEC, .max = SL_ESTIMATOR_SPLITSUM,
                          .names = estimator_names},
    /* default: the scene's map if it names one, else this, the pole-free octahedral map
     * (src/render/renderer.c; docs/ibl.md says why) */
    [SL_OPT_IRRADIANCE] = {.name = "irradiance", .cli = "--irradiance", .scene = {"render.irradiance"},
                           .type = SL_OPTION_CHOICE,
                           .def = {SL_IRRADIANCE_OCT}, .min = SL_IRRADIANCE_SH9, .max = SL_IRRADIANCE_DP,
                           .names = irradiance_names},
    /* the specular samples' mip chain; docs/ibl.md "Specular layouts" says why the default */
    [SL_OPT_ENV_LAYOUT] = {.name = "env-layout", .cli = "--env-layout", .scene = {"render.env_layout"},
                           .type = SL_OPTION_CHOICE, .def = {SL_ENV_LAYOUT_LATLONG}, .min = SL_ENV_LAYOUT_LATLONG,
                           .max = SL_ENV_LAYOUT_OCT, .names = env_layout_names},
    FLAG(SL_OPT_DIFFUSE_ONLY, "diffuse-only"),
    FLAG(SL_OPT_SPECULAR_ONLY, "specular-only"),
    FLAG(SL_OPT_NO_LIGHTS, "no-lights"),
    /* default 0: all cores */
    [SL_OPT_THREADS] = {.name = "threads", .cli = "--threads", .alias = "-j", .type = SL_OPTION_INT, .min = 1,
                        .max = 256},
    /* a power of two (the rasterizer checks) */
    [SL_OPT_TILE] = {.name = "tile", .cli = "--tile", .type = SL_OPTION_INT, .def = {SL_TILE_DEFAULT},
                     .min = SL_TILE_MIN, .max = SL_TILE_MAX},
    [SL_OPT_ROTATE] = {.name = "rotate", .cli = "--rotate", .scene = {"render.rotate"}, .type = SL_OPTION_FLAG},
    [SL_OPT_FRAME] = {.name = "frame", .cli = "--frame", .type = SL_OPTION_INT, .min = 0, .max = 1e9},
    FLAG(SL_OPT_PLAIN, "plain"),
    [SL_OPT_ENV_LIGHTS] = {.name = "env-lights", .cli = "--env-lights", .type = SL_OPTION_INT, .min = 0,
                           .max = SL_ENV_LIGHTS_MAX},
    /* not in a scene file: a file must not raise the budget that guards against it */
    [SL_OPT_IMAGE_MEMORY] = {.name = "image-memory", .cli = "--image-memory", .type = SL_OPTION_INT,
                             .def = {SL_IMAGE_MEMORY_DEFAULT_MIB}, .min = 1, .max = SL_IMAGE_MEMORY_MAX_MIB},
    [SL_OPT_ENV_INTENSITY] = {.name = "env-intensity", .scene = {"environment.intensity"},
                              .type = SL_OPTION_FLOAT, .def = {1}, .min = 0, .max = 1e6},
};

const char *sl_option_name(const sl_option *opt, int value)
{
    if (opt->type != SL_OPTION_CHOICE || value < 0 || value > (int)opt->max || !opt->names[value])
        return "?";
    return opt->names[value];
}

bool sl_option_parse(const sl_option *opt, const char *name, int *value)
{
    for (int v = 0; name && opt->type == SL_OPTION_CHOICE && v <= (int)opt->max; v++)
        if (opt->names[v] && !strcmp(name, opt->names[v])) {
            *value = v;
            return true;
        }
    return false;
}

int sl_option_next(const sl_option *opt, int value)
{
    return value >= (int)opt->max || value < (int)opt->min ? (int)opt->min : value + 1;
}

bool sl_option_choices(const sl_option *opt, char *out, size_t size)
{
    size_t n = 0;
    if (size)
        out[0] = '\0';
    for (int v = (int)opt->min; opt->type == SL_OPTION_CHOICE && v <= (int)opt->max; v++) {
        int k = snprintf(out + n, size - n, "%s%s", v > (int)opt->min ? "|" : "", opt->names[v]);
        if (k < 0 || (size_t)k >= size - n)
            return false;
        n += (size_t)k;
    }
    return size > 0;
}

double sl_option_file_min(const sl_option *opt)
{
    return opt->file_min != 0.0 || opt->file_max != 0.0 ? opt->file_min : opt->min;
}
double sl_option_file_max(const sl_option *opt)
{
    return opt->file_min != 0.0 || opt->file_max != 0.0 ? opt->file_max : opt->max;
}

const char *sl_lod_rule_name(sl_lod_rule rule) { return sl_option_name(&sl_options[SL_OPT_LOD], (int)rule); }
const char *sl_estimator_name(sl_estimator estimator)
{
    return sl_option_name(&sl_options[SL_OPT_ESTIMATOR], (int)estimator);
}
const char *sl_gterm_name(sl_gterm gterm) { return sl_option_name(&sl_options[SL_OPT_GTERM], (int)gterm); }
const char *sl_irradiance_name(sl_irradiance_method method)
{
    return sl_option_name(&sl_options[SL_OPT_IRRADIANCE], (int)method);
}
const char *sl_env_layout_name(sl_env_layout layout)
{
    return sl_option_name(&sl_options[SL_OPT_ENV_LAYOUT], (int)layout);
}
bool sl_lod_rule_parse(const char *name, sl_lod_rule *rule)
{
    int v;
    if (!sl_option_parse(&sl_options[SL_OPT_LOD], name, &v))
        return false;
    *rule = (sl_lod_rule)v;
    return true;
}
bool sl_estimator_parse(const char *name, sl_estimator *estimator)
{
    int v;
    if (!sl_option_parse(&sl_options[SL_OPT_ESTIMATOR], name, &v))
        return false;
    *estimator = (sl_estimator)v;
    return true;
}
bool sl_gterm_parse(const char *name, sl_gterm *gterm)
{
    int v;
    if (!sl_option_parse(&sl_options[SL_OPT_GTERM], name, &v))
        return false;
    *gterm = (sl_gterm)v;
    return true;
}

sl_irradiance_method sl_irradiance_default(void)
{
    return (sl_irradiance_method)sl_options[SL_OPT_IRRADIANCE].def[0];
}
