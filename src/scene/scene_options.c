/* scene_options.c - the options a scene file may set (docs/scene-format.md "render"): every row of
 * the option declaration (core/options.h) with a scene key, read by its type and held to the range
 * the declaration gives scene files, into the scene's option record (scene->options) with its bit
 * set. The "render" object's keys are the declaration's; nothing here names an option. */
#include "scene_read.h"

#include <string.h>

/* The option `id` at its key(s) in `section`, the object its JSON path ("render.samples") starts
 * with, held to the range the declaration gives scene files, into its field of `options`, marked
 * as given; absent leaves the field as it is. A choice is read by name ("default" where 0 means
 * the default), a flag as true or false. */
bool sl_scene_read_option(scene_parser *p, const cJSON *section, sl_option_id id, sl_option_values *options)
{
    const sl_option *opt = &sl_options[id];
    void *field = sl_option_field(options, id);
    double lo = sl_option_file_min(opt), hi = sl_option_file_max(opt);
    for (int which = 0; which < 2 && opt->scene[which]; which++) {
        const char *path = opt->scene[which];
        const cJSON *v = sl_scene_member(section, strchr(path, '.') + 1);
        if (!v)
            continue;
        switch (opt->type) {
        case SL_OPTION_FLAG:
            if (!cJSON_IsBool(v))
                return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected true or false");
            *(bool *)field = cJSON_IsTrue(v);
            break;
        case SL_OPTION_INT:
        case SL_OPTION_SIZE:
            if (!sl_scene_read_int(p, v, path, (int)lo, (int)hi, (int *)field + which))
                return false;
            break;
        case SL_OPTION_FLOAT: {
            float *f = field;
            if (!sl_scene_read_float(p, v, path, lo, hi, f))
                return false;
            if (opt->file_min_open && !(*f > (float)lo))
                return sl_scene_fail(p, path, SL_ERR_RANGE, "%g must be greater than %g (%g < %s <= %g)", (double)*f, lo,
                               lo, opt->name, hi);
            break;
        }
        case SL_OPTION_CHOICE: {
            char name[32], shown[MASKED_MAX + 4], words[96];
            if (!sl_scene_read_string(p, v, path, name, sizeof name))
                return false;
            if (!sl_option_parse(opt, name, (int *)field)) {
                sl_option_choices(opt, words, sizeof words);
                return sl_scene_fail(p, path, SL_ERR_RANGE, "unknown %s \"%s\" (expected %s)", opt->name,
                               sl_scene_masked(name, 32, shown), words);
            }
            break;
        }
        }
        options->set |= SL_OPT_BIT(id);
    }
    return true;
}

/* The "render" object: a key per row of the option declaration whose scene key starts with
 * "render." (core/options.h), each read by read_option. */
bool sl_scene_parse_render(scene_parser *p, const cJSON *item, sl_option_values *options)
{
    const char *keys[SL_OPT_COUNT + 2];
    int n = 0;
    for (int id = 0; id < SL_OPT_COUNT; id++)
        for (int which = 0; which < 2; which++) {
            const char *path = sl_options[id].scene[which];
            if (path && !strncmp(path, "render.", 7))
                keys[n++] = path + 7;
        }
    keys[n] = NULL;
    if (!item)
        return true;
    if (!sl_scene_check_keys(p, item, "render", keys))
        return false;
    for (int id = 0; id < SL_OPT_COUNT; id++)
        if (sl_options[id].scene[0] && !strncmp(sl_options[id].scene[0], "render.", 7) &&
            !sl_scene_read_option(p, item, (sl_option_id)id, options))
            return false;
    return sl_option_values_check(options, p->name, p->err);
}
