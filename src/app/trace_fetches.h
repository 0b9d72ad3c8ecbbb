/* trace_fetches.h - the texture fetches of the traced pixel (trace_fetches.c), for cmd_trace. */
#ifndef SL_TRACE_FETCHES_H
#define SL_TRACE_FETCHES_H

#include <stdio.h>

#include "raster/gbuffer_textured.h"

typedef struct {
    int slot;              /* sl_map_slot */
    bool helper;           /* a helper lane: fetched for its neighbours' derivatives only */
    float depth;           /* gl_FragCoord.z: picks the fragment the G-buffer kept */
    vec2 uv, dPdx, dPdy;   /* the transformed coordinate and its quad derivatives */
    float lambda;          /* level of detail, biased and clamped */
    vec4 value;            /* what texture() returned */
    sl_sampler2D sampler;
} sl_trace_fetch;

/* Fetches of every fragment and helper at the pixel during the raster (a few per draw). */
#define SL_TRACE_MAX_FETCHES 64
typedef struct {
    int x, y; /* G-buffer pixel, row 0 = bottom */
    int count, dropped;
    sl_trace_fetch fetches[SL_TRACE_MAX_FETCHES];
} sl_trace_fetches;

/* Start recording the fetches at G-buffer pixel (x, y) of the draws that use `textures`. */
void sl_trace_fetches_hook(sl_trace_fetches *t, sl_scene_textures *textures, int x, int y);
/* Print the fetches of the fragment whose depth the G-buffer holds (gbuffer_depth). */
void sl_trace_fetches_print(FILE *out, const sl_trace_fetches *t, float gbuffer_depth);

#endif
