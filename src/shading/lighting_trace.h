/* lighting_trace.h - the trace of one pixel's shading, for `softlight trace` and the tests:
 * every intermediate value of main(), specular_ibl / specular_microfacet and their samples.
 *
 * Either path fills it (the port with options.plain, else the batched path), at a few named
 * points (the trace_* hooks in lighting_internal.h), so the shader's lines still read as the
 * GLSL's; the trace is NULL in the pass and every hook is then a no-op. The values are the
 * path's own, so a traced pixel has the bits the pass writes. */
#ifndef SL_LIGHTING_TRACE_H
#define SL_LIGHTING_TRACE_H

#include <stdio.h>

#include "lighting.h"
#include "occlusion/reflection.h"
#include "splitsum_lut.h"

/* Everything sl_lighting_shade computes for one pixel, for `softlight trace`. With the microfacet
 * estimator (trace.microfacet) L is the drawn H about +Z, w = reflect(-V, H), LdotH = V.H, and a
 * sample with V.H <= 0 or w.N <= 0 contributes 0. */
typedef struct {
    vec2 xi;           /* Hammersley pair (rotated when rotation is on) */
    vec3 L;            /* skewed direction about +Z (eq. (4)); microfacet: H about +Z */
    float pdf;         /* p(w), the density of w (MIS: of the strategy that drew it) */
    float pdf_other;   /* MIS: the other strategy's density at w */
    float mis;         /* MIS: the power heuristic's weight pdf^2 / (pdf^2 + pdf_other^2) */
    vec3 w;            /* rotated to R (environment space); microfacet: reflect(-V, H) */
    float wN;          /* w.N; <= 0: below the horizon, nothing below was computed */
    vec3 H;
    float NdotH, LdotH, D; /* microfacet: N.H is H's drawn cos(theta_h), D = D(H) */
    vec3 F;
    float G;           /* G / (L.N V.N) */
    float lod;
    vec3 Li;           /* fetched radiance times intensity */
    vec3 c;            /* contribution */
    float cv_kp;       /* cv: the kernel mix over the density, K(w) / p(w) */
    bool hidden;       /* w lies under the pixel's facet (lighting_internal.h shade_facet_hides): the
                          BRDF's part left out, as below the horizon */
    bool across;       /* w lies across the horizon from R (sky maps): c went to the part across */
    int glow;          /* 1 + the env-light map whose glow holds w (c is times its visibility:
                          lighting_internal.h shade_glow), 0: none, or every map sees the point */
    vec3 sum;          /* running sum (of the samples not across) */
} sl_lighting_trace_sample;

struct sl_lighting_trace {
    int x, y;                /* image pixel, row 0 = top */
    vec2 frag_coord;         /* gl_FragCoord.xy (G-buffer row y_gb = height - 1 - y) */
    sl_gbuffer_texel texel;  /* as read */
    bool covered;
    vec3 V, N;               /* world space; N after facing_normal */
    bool bent;               /* N was bent toward V */
    vec3 Nenv, Venv;         /* environment space */
    vec2 rotation;           /* the pixel's Hammersley offset (0, 0 when rotation is off) */
    bool plain;              /* traced through the plain port (else the batched path) */
    float NdotV;
    vec3 R, A, B;            /* environment space; A, B span the frame about R, or about N for
                                the microfacet estimator */
    bool pole_frame;
    bool microfacet;         /* the microfacet estimator ran (specular_microfacet) */
    bool splitsum;           /* the split-sum estimator ran (specular_splitsum): no samples, */
    float splitsum_width;    /* ... the lobe width r, */
    float splitsum_lod;      /* ... the prefiltered chain's level r (levels - 1), */
    vec3 splitsum_dir;       /* ... the lookup direction normalize(mix(N, R, t)), */
    vec3 splitsum_prefiltered; /* ... what it read along it (before the intensity), */
    vec3 splitsum_ab;        /* ... and the table's A (times Ks), B and direction factor t */
    bool cv;                 /* the control variate ran (specular_cv): the split sum's lookup above
                                (prefiltered: ca C_a + cb C_b, the exact levels' part), */
    float cv_beta;           /* ... the table's coefficient beta, */
    sl_cv_levels cv_levels;  /* ... the levels read and their shares ca, cb, */
    vec3 cv_E;               /* ... the albedo E = Ks A + B, */
    vec3 cv_closed;          /* ... the closed part beta E (ca C_a + cb C_b) (times the intensity), */
    vec3 cv_correction;      /* ... and the samples' mean of (F W - beta E K / p) Li, each sample's c
                                its term and cv_kp its K(w) / p(w) */
    float alpha;
    int estimator, lod_rule; /* how the lobe's set samples (sl_estimator, sl_lod_rule) */
    bool distortion;
    bool set_own;            /* ... the GGX set's own, not the frame's (a scene of both sets) */
    int sample_count;
    sl_lighting_trace_sample samples[SL_HAMMERSLEY_MAX];
    bool mis;                /* the MIS estimator ran (specular_mis): samples[k] is pair k's BRDF
                                sample (drawn as the microfacet estimator's), env_samples[k] its
                                environment sample (src/ibl/env_dist.h) */
    sl_lighting_trace_sample env_samples[SL_HAMMERSLEY_MAX];
    int env_light_count;     /* uEnvLightCount */
    vec3 env_lights;         /* their exact part of the specular (included in specular) */
    int env_lights_split;    /* ... how many were read over cells of their texel, near a lobe
                                narrower than a few texels (lighting.frag env_light_split), */
    int env_light_cells;     /* ... and the most cells one of them was read over */
    vec3 irradiance, diffuse, specular, lights, background;
    vec3 light[SL_LIGHTING_MAX_LIGHTS];
    int shadow_lights;       /* with shadow maps (uniforms' shadowMaps): uLightCount, else 0 */
    float light_visibility[SL_LIGHTING_MAX_LIGHTS]; /* ... each light's visibility from the point
                                (src/shadow), which light[i] includes */
    int env_shadow_lights;   /* with the env lights' maps (uniforms' envLightShadows): uEnvLightCount */
    signed char env_light_map[SL_ENV_LIGHTS_MAX];  /* ... each env light's map (-1: none, open) */
    float env_light_visibility[SL_ENV_LIGHTS_MAX]; /* ... and its visibility from the point, which
                                the env lights' specular and their part of the diffuse include */
    int sky_maps;            /* with the sky visibility maps (uniforms' skyMaps): their count, else 0 */
    float sky_visibility;    /* ... V, which the irradiance includes */
    float sky_map_visibility[SL_SKY_MAPS_MAX]; /* ... each map's v_k (-1: not read, weight 0) */
    bool horizon;            /* ... samples across the horizon from R were summed apart: */
    vec3 horizon_part;       /* ... their part of the specular, */
    vec3 horizon_dir;        /* ... its luminous direction (environment space), */
    int horizon_cell;        /* ... the map whose cell holds that direction, */
    float horizon_visibility; /* ... the map's visibility from the point, */
    vec3 horizon_visible;    /* ... and the part times it, which specular includes (added after the
                                specular's occlusion) */
    float occlusion;         /* the G-buffer's extra plane: scales irradiance..specular, not lights */
    vec3 emissive;           /* added last */
    bool cone;               /* the G-buffer has the ambient occlusion's cone (--ao-radius): */
    vec3 cone_axis;          /* ... its bent normal (world space; the irradiance is looked up along it) */
    float ao;                /* ... its AO (the cone's cosine-weighted share of the hemisphere) */
    float diffuse_occlusion, specular_occlusion; /* ... the factors on the diffuse and the specular */
    float cone_across;       /* ... the share of its occlusion across the horizon from R, which the
                                specular's factor leaves to the sky maps (0 without them) */
    float lobe_map;          /* ... the factor before the sky map of R's cell (shade_lobe_map),
                                when that map lowered it; -1 when it did not */
    bool reflection;         /* the G-buffer has the reflection occlusion (--reflection-occlusion): */
    float reflection_visibility; /* ... the texel's, which joins or scales the specular's factor */
    int reflection_count;        /* ... the rays it is over (1 .. SL_REFLECTION_MEMBERS) */
    float reflection_rays[SL_REFLECTION_MEMBERS]; /* ... its block's rays (the texel, x + 1, x - 1,
                                y + 1, y - 1, then the corners), then its own others (where the
                                block counts fewer than SL_REFLECTION_LONE): 1 open, 0 blocked,
                                SL_REFLECTION_INTO into its own surface, SL_REFLECTION_BELOW below
                                it (src/occlusion/reflection.h) */
    float reflection_weights[SL_REFLECTION_MEMBERS]; /* ... each counted ray's weight, its cosine */
    int reflection_used[SL_REFLECTION_MEMBERS]; /* ... whether each counted (the same surface, or
                                an own ray traced) */
    bool facet;              /* ... and the G-buffer has the facet plane: */
    vec3 facet_normal;       /* ... the texel's, whose horizon its rays must be above */
    bool extra;              /* the G-buffer has the extra plane (the two lines are printed) */
    vec3 total;              /* what the pass writes */
    bool repaired;           /* the final NaN/Inf guard fired */
    const char *program;     /* another lighting program than the built-in: its name (NULL: the
                                built-in, whose every step the fields above record) */
    sl_gbuffer_extra extra_texel; /* ... the extra plane's texel it saw */
    vec3 program_result;     /* ... and what it returned, before the guard */
};

/* Trace image pixel (x, y) (row 0 = top, as in the written image): runs sl_lighting_shade with
 * a trace. `trace` is large (about 400 KB): allocate it. */
bool sl_lighting_trace_pixel(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y,
                             sl_lighting_trace *trace, sl_error *err);
void sl_lighting_trace_print(FILE *f, const sl_lighting_trace *trace);

#endif
