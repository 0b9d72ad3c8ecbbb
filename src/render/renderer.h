/* renderer.h - one frame through every stage, and the state that outlives frames.
 *
 * Consumes: a loaded scene (src/scene) and an option record (core/options.h: the command line's
 * or the caller's, over the scene file's, over the defaults), and optionally a per-frame override of the sampling
 * (sl_lighting_frame: the viewer's refinement stages).
 * Produces, per frame: the G-buffer (raster), linear HDR radiance (shading; row 0 = top) and
 * the tone-mapped display image in [0,1] (post), with the time each stage took.
 *
 * Per environment (once, or when the viewer swaps it): the .hdr is loaded, checked and
 * repaired, its mip chain built, its irradiance computed with the chosen method, and, when
 * lighting.env_lights asks for them, its env lights extracted (src/ibl/env_lights.h), and for
 * the octahedral layout the samples' chain resampled into it (src/ibl/env_oct.c), and for
 * --estimator splitsum its prefiltered chains (src/ibl/prefilter.c) and the BRDF's table, for
 * --estimator mis the environment's distribution (src/ibl/env_dist.h).
 * Per scene: the materials' texture maps, each image file decoded once with its mips.
 * Per size: the G-buffer and images are allocated once and reused.
 * Per frame: raster -> lighting -> tone map; nothing else.
 *
 * Does not: load the scene, write files, or open windows (src/app does). */
#ifndef SL_RENDERER_H
#define SL_RENDERER_H

#include <stdbool.h>
#include <stdint.h>

#include <softlight/renderer.h>

#include "core/error.h"
#include "core/image.h"
#include "ibl/ibl.h"
#include "occlusion/gtao.h"
#include "occlusion/reflection.h"
#include "post/tonemap.h"
#include "raster/gbuffer.h"
#include "raster/gbuffer_textured.h"
#include "raster/raster.h"
#include "shadow/shadow.h"
#include "shadow/sky.h"
#include "scene/scene.h"
#include "shading/lighting.h"

/* What a render is asked for, and what each stage is given.
 *
 * The caller fills `options` (each option it gives marked set: the command line's record,
 * sl_option_set_samples, ...), and the band. sl_render_desc_resolve (sl_renderer_init calls it)
 * turns `options` into the resolved record (the caller's, over the scene file's, over the
 * declaration's defaults) and fills the stages' parameters below from it: one resolution, in one
 * place. The stages' fields given by the caller are overwritten. */
typedef struct {
    sl_option_values options;     /* given: the caller's; resolved: what the render uses */
    int irradiance_map_width;     /* brute-force map width; 0 = 64 */
    bool env_lights_worth;        /* the env lights' count is a ceiling (sl_lighting_options); set
                                     by the resolution where it chooses the count itself (the GGX
                                     default), kept when the desc is resolved again */
    bool env_lights_ggx_only;     /* ... and they are the GGX set's alone (a scene of both sets'
                                     default), likewise */
    /* a shard (app/shard.h): only image rows [band[0], band[1]) (row 0 = top) keep their
     * G-buffer texels after the raster, so lighting and ground truth cost only the band */
    bool banded;
    int band[2];
    /* ---- the stages' parameters, from the resolved options ---- */
    int width, height;
    sl_lighting_options lighting; /* every field its value (the viewer's keys change them live) */
    sl_tonemap_options tonemap;
    int threads;                  /* 0 = all cores */
    int tile_size;                /* raster tiles */
    bool plain_raster;            /* the rasterizer's per-pixel reference path (sl_raster_desc.plain) */
    size_t image_budget;          /* bytes one image read from a file may take decoded (the
                                     environment, the irradiance map) */
    const sl_lighting_program *lighting_program; /* the lighting stage's shading; NULL = the built-in */
    const sl_gbuffer_fragment_program *gbuffer_program; /* every object's G-buffer fragment program
                                                           (softlight/gbuffer_program.h); NULL = the
                                                           built-in programs */
    bool any_lobe;                /* the G-buffer's lobes need not be the materials' (a G-buffer
                                     program drawn elsewhere: softlight-gl --gbuffer-shader): the
                                     split sum prefilters both sets, as for gbuffer_program */
} sl_render_desc;

typedef struct {
    double load_ms;     /* environment load + mips (per environment), textures (per scene) */
    double irradiance_ms;
    double env_lights_ms; /* extraction of the env lights and the residual's mips (when asked) */
    double env_oct_ms;    /* the octahedral chain of what the samples read (--env-layout oct) */
    double splitsum_ms;   /* --estimator splitsum: the prefiltered chains (the lobe sets the scene
                             uses) and the BRDF's table */
    double env_dist_ms;   /* --estimator mis: the environment distribution (src/ibl/env_dist.h) */
    double raster_ms, shading_ms, tonemap_ms; /* last frame */
    double ao_ms;       /* last frame's ambient occlusion (--ao-radius; 0 when off) */
    double reflection_ms; /* last frame's reflection occlusion (--reflection-occlusion; 0 when off) */
    int64_t reflection_lone; /* ... its texels that traced their own five rays (sl_reflection_apply) */
    double shadow_ms;   /* the point lights' shadow maps (--shadows or a light's "shadow"): drawn
                           on the first frame that needs them, kept for the renderer's scene */
    double sun_shadow_ms; /* the env lights' maps (--shadows with --env-lights): drawn on the first
                           frame that needs them, again when the env lights or their rotation change */
    double sky_ms;      /* the sky visibility maps (--sky-maps): their cells' weights and their draw, on
                           the first frame that needs them, again when what they depend on changes */
} sl_render_timings;

/* The renderer (opaque in softlight/renderer.h; sl_renderer_create allocates one, sl_renderer_init
 * fills caller storage). */
struct sl_renderer {
    const sl_scene *scene;  /* not owned */
    sl_render_desc desc;    /* resolved */
    sl_env env;
    sl_irradiance irradiance;
    bool have_irradiance;
    sl_env_lights env_lights; /* built on first use for desc.lighting.env_lights > 0 */
    int env_lights_built;     /* the count extracted, in use; 0 = none */
    int env_lights_asked;     /* the request they were extracted for: the count or ceiling K;
                                 0 = none yet */
    bool env_lights_asked_worth; /* ... and whether K was a ceiling (env_lights_worth) */
    sl_env env_oct;           /* --env-layout oct: the octahedral chain of env, or of the env
                                 lights' residual; built on first use */
    int env_oct_built;        /* -1 = none, else the env lights count of what it was built from */
    sl_env splitsum_phong, splitsum_ggx; /* --estimator splitsum: what the samples read, prefiltered
                                 per lobe width (src/ibl/prefilter.c); built on first use */
    int splitsum_built;       /* -1 = none, else the env lights count of what they were built from */
    sl_gterm splitsum_gterm;  /* the --g the Phong chain was built for (its samples' weight) */
    sl_splitsum_lut *splitsum_lut; /* the BRDF's table (heap, 37 KB), built with the chains, once */
    sl_env_dist env_dist;     /* --estimator mis: the distribution of what the samples read; built
                                 on first use */
    int env_dist_built;       /* -1 = none, else the env lights count of what it was built from */
    sl_raster *raster;
    sl_shadow_maps shadows;   /* the point lights' cube maps (src/shadow), drawn on first use */
    int shadows_built;        /* 0 = none; 1 = the lights with "shadow"; 2 = every light (--shadows) */
    sl_shadow_suns suns;      /* the env lights' orthographic maps (src/shadow), drawn on first use */
    int suns_built;           /* 0 = none, else the env lights count they were clustered from */
    float suns_rotation;      /* ... and the environment rotation they were drawn for */
    sl_shadow_sky sky;        /* the sky visibility maps (src/shadow/sky.h), drawn on first use */
    int sky_built;            /* 0 = none, else the count drawn */
    int sky_env_lights;       /* ... the env lights count whose residual weighted them (0: the
                                 whole environment) */
    float sky_rotation;       /* ... and the environment rotation they were drawn for */
    sl_scene_textures textures; /* the materials' images, decoded once per scene */
    sl_gbuffer gbuffer;
    /* the occlusion passes' working planes, kept from frame to frame (src/occlusion) */
    sl_gtao_scratch gtao_scratch;
    sl_reflection_scratch reflection_scratch;
    sl_lighting_uniforms *uniforms; /* ~9 KB, heap */
    sl_lighting_stats lighting_stats;
    sl_image radiance;      /* linear, row 0 = top */
    sl_image display;       /* tone mapped, [0,1], row 0 = top */
    sl_tonemap_table *tonemap_table; /* heap (~22 KB), built on first use and whenever
                                        desc.tonemap no longer matches tonemap_built */
    sl_tonemap_options tonemap_built;
    sl_image_repairs env_repairs;
    sl_render_timings timings;
};

/* Resolve d->options against the scene's (scene->options) and the declaration's defaults, and fill
 * the stages' parameters from the result (the irradiance: the scene's map if it names one and no
 * method was chosen; the environment's rotation: the scene's). False when the resolved options
 * contradict each other. sl_renderer_init calls it; `softlight info` too, to report what the
 * render would take. Resolving a resolved description changes nothing. */
bool sl_render_desc_resolve(sl_render_desc *d, const sl_scene *scene, sl_error *err);
/* Resolve settings against the scene, load the environment, build mips and irradiance. */
bool sl_renderer_init(sl_renderer *r, const sl_scene *scene, const sl_render_desc *desc, sl_error *err);
void sl_renderer_free(sl_renderer *r);

/* sl_renderer_set_environment (softlight/renderer.h): the viewer's drag and drop. */
/* Recompute the irradiance with `method` (the viewer's irradiance key) and set
 * desc.lighting.irradiance to it. On failure the old irradiance and method stay. */
bool sl_renderer_set_irradiance(sl_renderer *r, sl_irradiance_method method, sl_error *err);
/* sl_renderer_resize: softlight/renderer.h. */

/* Rasterize the scene into the G-buffer from `cam` (NULL = the scene's camera); with a band, the
 * texels outside it are cleared (every field 0, depth 1: nothing drawn). */
bool sl_renderer_raster(sl_renderer *r, const sl_camera *cam, sl_error *err);
/* Set r->uniforms for lighting the current G-buffer seen from `cam` (what shade and trace use),
 * with desc.lighting as it is. */
bool sl_renderer_prepare_lighting(sl_renderer *r, const sl_camera *cam, sl_error *err);

/* What one frame draws where it differs from desc.lighting: the viewer's refinement stages light
 * with fewer samples, rotated, numbered frames, yet filtered as the user's N (docs/viewer.md
 * "Refinement"). Passed per call, so desc keeps the user's settings and is never swapped. */
typedef struct {
    int samples;     /* N drawn, 1 .. SL_HAMMERSLEY_MAX */
    int lod_samples; /* the N whose mip levels they read (uLodBase = 1/2 log2(W H / N)); 0 = samples */
    bool rotate;     /* per-pixel rotation of the sample set (uRotate) */
    uint32_t frame;  /* its frame number (uFrame) */
    sl_estimator estimator; /* SL_ESTIMATOR_DEFAULT: desc's; the viewer's moving frames ask for
                               SPLITSUM (its chains are then prefiltered once per environment) */
} sl_lighting_frame;

/* sl_renderer_prepare_lighting with `frame`'s four fields in place of desc.lighting's (NULL: as
 * sl_renderer_prepare_lighting). */
bool sl_renderer_prepare_lighting_frame(sl_renderer *r, const sl_camera *cam, const sl_lighting_frame *frame,
                                        sl_error *err);
/* The lobe sets the split sum prefilters a chain for: those the scene's materials use (Phong
 * when there are none). */
void sl_renderer_splitsum_sets(const sl_scene *scene, bool *phong, bool *ggx);
/* Whether every object of the scene is drawn with a GGX material (imported models): the scene
 * whose default lighting is the microfacet estimator with up to 64 env lights, those worth their
 * cost (sl_render_desc_resolve). */
bool sl_renderer_all_ggx(const sl_scene *scene);
/* The split-sum chain of a lobe set (NULL when none is built). A set no material uses is not
 * prefiltered: the other set's chain stands in for it (no pixel reads it). */
const sl_env *sl_renderer_splitsum_chain(const sl_renderer *r, bool ggx);
/* Light the current G-buffer into r->radiance (same camera as the last raster). */
bool sl_renderer_shade(sl_renderer *r, const sl_camera *cam, sl_error *err);
/* The same for a G-buffer of the renderer's size drawn elsewhere (sl_renderer_light). */
bool sl_renderer_shade_gbuffer(sl_renderer *r, const sl_gbuffer *gb, const sl_camera *cam, sl_error *err);
/* Tone map r->radiance into r->display. */
bool sl_renderer_tonemap(sl_renderer *r, sl_error *err);
/* The tone map's table for r->desc.tonemap (built, or rebuilt when the options changed; owned by
 * r): what sl_renderer_tonemap applies, for callers that tone map into their own format (the
 * viewer's window, sl_tonemap_apply_xrgb8888). NULL and err on bad options or no memory. */
const sl_tonemap_table *sl_renderer_tonemap_table(sl_renderer *r, sl_error *err);
/* sl_renderer_shade_gbuffer and sl_renderer_tonemap in one parallel region: each band of rows
 * is tone mapped by the thread that lit it, as soon as it is lit (sl_lighting_pass_hooked), with
 * the same images as the two calls. timings.tonemap_ms is the tone map's share of the pass (the
 * pass's wall time times the tone map's part of the CPU time it used), timings.shading_ms the rest. */
bool sl_renderer_shade_tonemap(sl_renderer *r, const sl_gbuffer *gb, const sl_camera *cam, sl_error *err);
/* All three: sl_renderer_frame (softlight/renderer.h). */

#endif
