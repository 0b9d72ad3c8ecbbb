/* render_options.c - the command line's arguments for the rendering options (see
 * render_options.h): each row of the option declaration with a spelling becomes one argument
 * writing into its field of the record. */
#include "render_options.h"

#include <string.h>

int sl_render_options_table(sl_render_options *o, sl_arg *t)
{
    memset(o, 0, sizeof *o);
    sl_option_values_default(&o->values);
    static const sl_arg_type types[] = {[SL_OPTION_FLAG] = SL_ARG_FLAG, [SL_OPTION_INT] = SL_ARG_INT,
                                        [SL_OPTION_FLOAT] = SL_ARG_FLOAT, [SL_OPTION_SIZE] = SL_ARG_SIZE,
                                        [SL_OPTION_CHOICE] = SL_ARG_CHOICE};
    int n = 0;
    for (int id = 0; id < SL_OPT_COUNT; id++) {
        const sl_option *opt = &sl_options[id];
        if (!opt->cli)
            continue;
        const char *choices = NULL;
        double min = opt->min, max = opt->max;
        if (opt->type == SL_OPTION_CHOICE) {
            /* the words in the row's order: argument k is value min + k */
            sl_option_choices(opt, o->choices[id], sizeof o->choices[id]);
            choices = o->choices[id];
        } else if (opt->type == SL_OPTION_FLAG) {
            min = max = 0;
        }
        o->marks[id] = (sl_arg_mark){&o->values.set, SL_OPT_BIT(id)};
        t[n++] = (sl_arg){opt->cli, opt->alias, types[opt->type], sl_option_field(&o->values, (sl_option_id)id),
                          min, max, choices, opt->metavar, opt->help, &o->marks[id]};
    }
    return n;
}

bool sl_render_options_desc(const sl_render_options *o, sl_render_desc *d, sl_error *err)
{
    memset(d, 0, sizeof *d);
    if (!sl_option_values_check(&o->values, NULL, err))
        return false;
    d->options = o->values;
    return true;
}
