/* render_options.h - the options every rendering command shares (render, trace, info, view, and
 * softlight-gl), parsed from one table so the C and GL programs accept the same words: one
 * argument per row of the option declaration (core/options.h) that has a command-line spelling,
 * its help text the row's, parsed straight into an sl_option_values record. */
#ifndef SL_RENDER_OPTIONS_H
#define SL_RENDER_OPTIONS_H

#include <stdbool.h>

#include "args.h"
#include "render/renderer.h"

/* Where the command line's options go: `values` is the record (the defaults, and each option
 * given marked in values.set); `choices` the words of each choice argument, "none|spec|...". */
typedef struct {
    sl_option_values values;
    char choices[SL_OPT_COUNT][64];
    sl_arg_mark marks[SL_OPT_COUNT];
} sl_render_options;

/* The most arguments sl_render_options_table fills. */
#define SL_RENDER_OPTION_COUNT SL_OPT_COUNT

/* Fill `table` (at most SL_RENDER_OPTION_COUNT entries) to parse into `o`, which is reset to
 * the defaults with nothing given; returns how many it filled. */
int sl_render_options_table(sl_render_options *o, sl_arg *table);
/* The renderer's description for the parsed options: desc->options is the command line's record,
 * the rest zero (sl_renderer_init resolves it against the scene). False when they contradict each
 * other (--diffuse-only with --specular-only, a tile not a power of two). */
bool sl_render_options_desc(const sl_render_options *o, sl_render_desc *desc, sl_error *err);

#endif
