/* render_options.h - the options every rendering command shares (render, trace, view, and
 * softlight-gl), parsed from one table so the C and GL programs accept the same words: the
 * option table of core/options.h, one argument per row, with the help text written here. */
#ifndef SL_RENDER_OPTIONS_H
#define SL_RENDER_OPTIONS_H

#include <stdbool.h>

#include "args.h"
#include "render/renderer.h"

typedef struct {
    int size[2];
    int samples;
    float exposure, contrast;
    int lod, gterm, estimator, irradiance, env_layout; /* choice index, -1 = not given */
    bool distortion, srgb;
    bool diffuse_only, specular_only, no_lights;
    int threads, tile;
    bool rotate; /* per-pixel rotation of the Hammersley set (lighting options.rotate) */
    bool plain;  /* the reference paths: per-pixel raster, the line-by-line port of lighting.frag */
    int frame;   /* the rotation's frame number (options.frame) */
    int env_lights; /* K brightest texels summed exactly (options.env_lights); 0 = off */
    int image_memory; /* the image memory budget in MiB (desc.image_budget); 0 = the default */
    char choices[SL_OPT_CLI_COUNT][64]; /* a choice argument's words, "none|spec|...", from its row */
} sl_render_options;

#define SL_RENDER_OPTION_COUNT 21 /* = SL_OPT_CLI_COUNT, the table's rows with a spelling */

/* Fill `table` (SL_RENDER_OPTION_COUNT entries) to parse into `o`, which is reset to "not given". */
void sl_render_options_table(sl_render_options *o, sl_arg *table);
/* Turn parsed options into a renderer description (zero fields keep the scene's values).
 * False when they contradict each other (--diffuse-only with --specular-only). */
bool sl_render_options_desc(const sl_render_options *o, sl_render_desc *desc, sl_error *err);

#endif
