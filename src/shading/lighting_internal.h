/* lighting_internal.h - what the lighting shader (lighting.c) and the code that runs it
 * (lighting_pass.c: uniforms, tasks, the pass, the trace) share: the per-thread scratch. */
#ifndef SL_LIGHTING_INTERNAL_H
#define SL_LIGHTING_INTERNAL_H

#include "lighting.h"

/* The batched path shades a row of up to SPAN pixels at a time; the pass's tiles are SPAN wide. */
enum { SPAN = 32 };

/* ---- per-thread scratch ---- */

enum { SLOTS = 8 };

/* The loop-invariant part of specular_ibl for one alpha: (xi, L, pdf) of every sample,
 * structure of arrays so the batched path's loops read them with vector loads. For the
 * microfacet estimator (specular_microfacet) the same arrays hold (xi, H about +Z, D(H)). */
typedef struct {
    bool valid;
    bool microfacet; /* built by microfacet_sample / microfacet_D */
    float alpha;
    int n;
    float xi1[SL_HAMMERSLEY_MAX], xi2[SL_HAMMERSLEY_MAX];
    /* the skewed direction about +Z: L of eq. (4) (spec, consistent) or H (microfacet) */
    float Lx[SL_HAMMERSLEY_MAX], Ly[SL_HAMMERSLEY_MAX], Lz[SL_HAMMERSLEY_MAX];
    /* sample_pdf, p(L) (spec, consistent); or microfacet_D, D(H) (microfacet), whose p(w)
     * still needs the pixel's V.H */
    float pdf[SL_HAMMERSLEY_MAX];
} lobe_table;

/* For rotation on: the unrotated pairs and cos/sin of their azimuth phi = 2 pi (1/2 - xi1). */
typedef struct {
    int n; /* 0 = not built */
    float xi1[SL_HAMMERSLEY_MAX], xi2[SL_HAMMERSLEY_MAX];
    float cphi[SL_HAMMERSLEY_MAX], sphi[SL_HAMMERSLEY_MAX];
} azimuth_table;

struct sl_lighting_task {
    const sl_lighting_uniforms *owner; /* the uniforms the tables were built from */
    int next;                          /* round-robin victim */
    lobe_table slots[SLOTS];
    azimuth_table azimuth;
    sl_lighting_stats stats;
};

#endif
