/* options.c - the option table, expanded from the declaration (SL_OPTION_LIST, options.h), and
 * the record's defaults, merge and checks. A new option is a row of SL_OPTION_LIST and, where a
 * stage reads it, one line in sl_render_desc_resolve (src/render/renderer.c); the command line
 * (src/app/render_options.c) and the scene file (src/scene/scene_options.c) read every row as it
 * is, and tests/unit/test_options.c checks --help, README.md and docs/scene-format.md against
 * the rows. */
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
    [SL_ESTIMATOR_MIS] = "mis", [SL_ESTIMATOR_CV] = "cv", [SL_ESTIMATOR_CV_MIS] = "cvmis",
};
static const char *const irradiance_names[] = {
    [SL_IRRADIANCE_SH9] = "sh9", [SL_IRRADIANCE_BRUTE] = "brute", [SL_IRRADIANCE_MAP] = "map",
    [SL_IRRADIANCE_OCT] = "oct", [SL_IRRADIANCE_DP] = "dp",
};
static const char *const missing_textures_names[] = {
    [SL_MISSING_TEXTURES_FAIL] = "fail", [SL_MISSING_TEXTURES_SKIP] = "skip",
};
static const char *const env_layout_names[] = {
    [SL_ENV_LAYOUT_DEFAULT] = "default", [SL_ENV_LAYOUT_LATLONG] = "latlong", [SL_ENV_LAYOUT_OCT] = "oct",
};

#define SL_OPT_UNPAREN_(...) __VA_ARGS__
#define SL_OPT_ROW_(ID, field_, TYPE, ctype, name_, cli_, alias_, metavar_, help_, row)                                \
    [SL_OPT_##ID] = {.name = name_, .cli = cli_, .alias = alias_, .metavar = metavar_, .help = help_,                \
                     .type = SL_OPTION_##TYPE, .offset = offsetof(sl_option_values, field_), SL_OPT_UNPAREN_ row},

const sl_option sl_options[SL_OPT_COUNT] = {SL_OPTION_LIST(SL_OPT_ROW_)};

/* The generic readers below write a choice as an int and a flag as a bool. */
#define SL_OPT_SIZEOF_FLAG(ctype) (sizeof(ctype) == sizeof(bool))
#define SL_OPT_SIZEOF_INT(ctype) (sizeof(ctype) == sizeof(int))
#define SL_OPT_SIZEOF_FLOAT(ctype) (sizeof(ctype) == sizeof(float))
#define SL_OPT_SIZEOF_CHOICE(ctype) (sizeof(ctype) == sizeof(int))
#define SL_OPT_SIZEOF_SIZE(ctype) (sizeof(ctype) == sizeof(int))
#define SL_OPT_ASSERT_(ID, field, TYPE, ctype, ...)                                                                 \
    _Static_assert(SL_OPT_SIZEOF_##TYPE(ctype), #field ": its C type has the size its kind is written with");
SL_OPTION_LIST(SL_OPT_ASSERT_)

void *sl_option_field(sl_option_values *v, sl_option_id id) { return (char *)v + sl_options[id].offset; }

void sl_option_values_default(sl_option_values *v)
{
    memset(v, 0, sizeof *v);
    for (int id = 0; id < SL_OPT_COUNT; id++) {
        const sl_option *o = &sl_options[id];
        void *f = sl_option_field(v, (sl_option_id)id);
        switch (o->type) {
        case SL_OPTION_FLAG: *(bool *)f = o->def[0] != 0.0; break;
        case SL_OPTION_INT:
        case SL_OPTION_CHOICE: *(int *)f = (int)o->def[0]; break;
        case SL_OPTION_FLOAT: *(float *)f = (float)o->def[0]; break;
        case SL_OPTION_SIZE:
            ((int *)f)[0] = (int)o->def[0];
            ((int *)f)[1] = (int)o->def[1];
            break;
        }
    }
}

static size_t field_size(const sl_option *o)
{
    switch (o->type) {
    case SL_OPTION_FLAG: return sizeof(bool);
    case SL_OPTION_FLOAT: return sizeof(float);
    case SL_OPTION_SIZE: return 2 * sizeof(int);
    case SL_OPTION_INT:
    case SL_OPTION_CHOICE: break;
    }
    return sizeof(int);
}

void sl_option_values_merge(sl_option_values *v, const sl_option_values *over)
{
    for (int id = 0; id < SL_OPT_COUNT; id++)
        if (sl_option_is_set(over, (sl_option_id)id)) {
            memcpy(sl_option_field(v, (sl_option_id)id), (const char *)over + sl_options[id].offset,
                   field_size(&sl_options[id]));
            v->set |= SL_OPT_BIT(id);
        }
}

bool sl_option_values_check(const sl_option_values *v, const char *scene, sl_error *err)
{
    const sl_option *d = &sl_options[SL_OPT_DIFFUSE_ONLY], *s = &sl_options[SL_OPT_SPECULAR_ONLY];
    if (v->diffuse_only && v->specular_only)
        return scene ? sl_fail(err, SL_ERR_RANGE, "%s: %s and %s exclude each other", scene, d->scene[0], s->scene[0])
                     : sl_fail(err, SL_ERR_RANGE, "%s and %s exclude each other", d->cli, s->cli);
    if (v->tile & (v->tile - 1))
        return sl_fail(err, SL_ERR_RANGE, "%s: %d is not a power of two", sl_options[SL_OPT_TILE].cli, v->tile);
    return true;
}

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
