/* lighting_internal.h - what the files of the lighting stage share, and which way they call:
 *
 *     lighting_pass.c ──> lighting.c (the port)          lighting_uniforms.c (host side)
 *            ├──────────> lighting_task.c (per-thread scratch)
 *            ├──────────> lighting_batched.c ──> lighting_task.c ──> lighting.c
 *            │                   └──────────> lighting.c (the pixel's sum, its rotation, split sum)
 *            └──────────> lighting_splitsum.c (split sum) ──> lighting.c (shade_finish)
 *                                └──────────> lighting_batched.c (shade_background_span)
 *     splitsum_lut.c ──> lighting.c (the table is integrated with the port's samples; the
 *                                    port reads the table's lobe width from brdf.h)
 *     lighting_trace.c ─> the pass's dispatch (sl_lighting_shade)
 *     ground_truth_image.c ─> lighting.c (facing_normal: the exact pass bends normals as the shader does)
 *
 * No two files call each other.
 * The port exports the GLSL functions the others reuse (shade_*: the sample generators for the
 * per-alpha tables, pixel_rotation, the covered pixel's sum); the trace hooks below are the few
 * named points where either path records a pixel; the per-thread task holds the sample tables. */
#ifndef SL_LIGHTING_INTERNAL_H
#define SL_LIGHTING_INTERNAL_H

#include "lighting.h"
#include "lighting_trace.h"
#include "bent_irradiance.h"
#include "occlusion/reflection.h"
#include "occlusion/specular_occlusion.h"

/* The batched path shades a row of up to SPAN pixels at a time (sl_lighting_shade_row cuts rows into spans). */
enum { SPAN = 32 };

/* GLSL constants that more than one file needs (lighting.frag has them with these values). */
#define SHADE_MIN_NDOTV 0.01f /* normals facing away from the eye are bent to N.V = 0.01 */
#define SHADE_POLE_EPS 1e-6f  /* |R.xy|^2 below this: Z x R vanishes, use X x R instead */
#define SHADE_MAX_ALPHA 1e7f  /* alpha beyond this is a mirror to float precision */

/* How a pixel samples the environment, by its lobe set: a GGX lobe takes the GGX set's own
 * (uEstimatorGGX ...: a scene of both sets gives its GGX objects the accurate default and keeps
 * the recipe for the specification's Phong set), which are the frame's where it has none; read
 * from the uniforms' setSampling, a table by the lobe's sign (selects of the two sets' uniforms
 * cost the batched path's direction loops their vectorization in some inlined copies). */
/* GLSL: estimator_of */
static inline int shade_estimator_of(const sl_lighting_uniforms *u, float alpha)
{
    return u->setSampling[sl_lobe_is_ggx(alpha)].estimator;
}
/* GLSL: lod_rule_of */
static inline int shade_lod_rule_of(const sl_lighting_uniforms *u, float alpha)
{
    return u->setSampling[sl_lobe_is_ggx(alpha)].lod_rule;
}
/* GLSL: distortion_of */
static inline int shade_distortion_of(const sl_lighting_uniforms *u, float alpha)
{
    return u->setSampling[sl_lobe_is_ggx(alpha)].distortion;
}
/* GLSL: env_lights_of - whether a lobe sums the env lights, its samples then reading the
 * residual (uEnvLightsGGXOnly: the GGX set's alone, the Phong set's samples reading uEnv) */
static inline bool shade_env_lights_of(const sl_lighting_uniforms *u, float alpha)
{
    return u->setSampling[sl_lobe_is_ggx(alpha)].env_lights;
}
/* The chain a lobe's samples read (uEnvResidual, or uEnv: setSampling's whole_map), and as a block */
static inline const sl_env *shade_samples_chain(const sl_lighting_uniforms *u, float alpha)
{
    return u->setSampling[sl_lobe_is_ggx(alpha)].whole_map ? u->uEnv : u->uEnvResidual;
}
static inline const sl_env_gather *shade_samples_gather(const sl_lighting_uniforms *u, float alpha)
{
    return u->setSampling[sl_lobe_is_ggx(alpha)].whole_map ? &u->envGather : &u->residualGather;
}
/* Whether a lobe's samples are drawn about N (the microfacet estimator's, and cv's) */
static inline bool shade_microfacet_samples(const sl_lighting_uniforms *u, float alpha)
{
    return u->setSampling[sl_lobe_is_ggx(alpha)].about_n;
}

/* GLSL lobe_param: the G-buffer alpha clamped, Phong's to [0, SHADE_MAX_ALPHA], GGX's (alpha
 * <= -1) to [-2, -1]. Inline, as every path reads it per pixel (a call into lighting.c was 2-3%
 * of the split sum's samples). */
/* GLSL: lobe_param */
static inline float shade_lobe_param(float a)
{
    return a <= -1.0f ? maxf(a, -2.0f) : clamp(a, 0.0f, SHADE_MAX_ALPHA);
}

/* ---- the port's functions that the other files call (lighting.c) ---- */

vec2 sl_shade_hammersley_point(const sl_lighting_uniforms *u, int k);     /* GLSL hammersley_point */
vec2 sl_shade_pixel_rotation(const sl_lighting_uniforms *u, int x, int y); /* GLSL pixel_rotation */
vec3 sl_shade_skewed_sample(vec2 xi, float alpha);                         /* GLSL skewed_sample */
float sl_shade_sample_pdf(vec2 xi, float alpha);                           /* GLSL sample_pdf */
vec3 sl_shade_microfacet_sample(vec2 xi, float alpha);                     /* GLSL microfacet_sample */
float sl_shade_microfacet_D(vec2 xi, float alpha);                         /* GLSL microfacet_D */
vec3 sl_shade_ggx_stretched_view(vec3 Vl, float a);                        /* GLSL ggx_stretched_view */
vec3 sl_shade_facing_normal(vec3 N, vec3 V);                               /* GLSL facing_normal */

/* The specular's part from across the horizon, with the sky visibility maps (uniforms' skyMaps;
 * docs/lighting.md "Sky visibility maps"). A lobe about R that reaches the other side of the
 * horizon (z >= 0 is the sky's, where the maps' cells are cut) is cut there the way a floor cuts
 * the environment: one side hidden, the other open. The pixel's specular factor (the cone's, the
 * reflection occlusion's) speaks for the lobe about R, so every estimator sums the samples that
 * lie across apart, and that part takes the visibility of the sky map whose cell holds its
 * luminous direction (sl_shade_horizon_visible). Without the maps `on` is false and every sample
 * stays in the estimate.
 * It also carries what the env lights' maps say of a sample's direction (shade_glow): a sample
 * in a map's glow is times that map's visibility before it is summed; and the pixel's facet
 * (shade_facet_hides), under which a sample's direction is hidden by the surface itself. */
typedef struct {
    bool on;    /* the maps are drawn: split */
    bool sky;   /* R on the sky's side */
    vec3 facet; /* the facet normal in environment space (shade_facet_env), 0: none */
    vec3 sum;   /* the samples' contributions from across, over the estimate's count */
    vec3 dir;   /* their directions, each times its contribution's |luminance| (environment space) */
    int glows;                        /* the env lights' maps whose glow applies (0: none) */
    const vec4 *glow;                 /* their glows' caps (uniforms' uEnvGlow) */
    float glow_vis[SL_SHADOW_SUN_MAX]; /* each map's visibility from the pixel's point */
} shade_horizon;

/* GLSL: horizon_on - whether the specular is split at the horizon: the maps are drawn (and the
 * build has the split) */
static inline bool shade_horizon_on(const sl_lighting_uniforms *u)
{
    return SL_SKY_MAPS_HORIZON && u->skyMaps != NULL;
}

/* GLSL: horizon_for */
static inline shade_horizon shade_horizon_for(const sl_lighting_uniforms *u, vec3 Nenv, vec3 Venv, vec3 Fenv)
{
    vec3 R = sub(scale(Nenv, 2.0f * dot(Nenv, Venv)), Venv);
    return (shade_horizon){.on = shade_horizon_on(u), .sky = R.z >= 0.0f, .facet = Fenv, .sum = vec3s(0.0f),
                           .dir = vec3s(0.0f), .glows = 0, .glow = u->uEnvGlow};
}

/* GLSL: facet_hides - whether direction w (environment space) lies under the pixel's facet: the
 * drawn triangle's plane (src/raster/gbuffer.h sl_gbuffer.facet), which a smooth or normal-mapped
 * N leans across at a silhouette's rim. The surface itself hides such a direction, as the
 * visibility truth's rays, which leave from the triangle, find: every estimator leaves it out as
 * it leaves out one below N's horizon (the BRDF's part; the control variate's kernel reaches
 * there still), and so do the env lights. A zero facet (none) hides nothing: w.0 is never < 0. */
static inline bool shade_facet_hides(const shade_horizon *h, vec3 w)
{
    return dot(w, h->facet) < 0.0f;
}

/* The facet normal of pixel (x, y) in environment space, under which the estimators leave a
 * direction out (shade_facet_hides): with reflection occlusion on and the G-buffer's facet plane
 * (0 where the triangle spanned no plane), else 0. The visibility methods go together: the
 * reflection occlusion's rays then count only the directions above the facet (reflection.c). */
/* GLSL: facet_env */
static inline vec3 shade_facet_env(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y)
{
    if (!(u->uReflectionDistance > 0.0f) || !gb->facet)
        return vec3s(0.0f);
    return mat3_mul_vec3(u->uEnvRotation, gb->facet[(size_t)y * (size_t)gb->width + (size_t)x]);
}

/* GLSL: horizon_across - whether direction w (environment space) lies across the horizon from R */
static inline bool shade_horizon_across(const shade_horizon *h, vec3 w)
{
    return h->on && (w.z >= 0.0f) != h->sky;
}

/* GLSL: horizon_add - a sample's contribution c from direction w into the part across */
static inline void shade_horizon_add(shade_horizon *h, vec3 w, vec3 c)
{
    h->sum = add(h->sum, c);
    h->dir = add(h->dir, scale(w, fabsf(sl_luminance(c))));
}

/* GLSL: glow_for - with the env lights' shadow maps, each map's visibility from the pixel's point
 * (map_vis[k], SL_SHADOW_SUN_MAX of them, those past the count unread) for shade_glow. Where
 * every map sees the point (most of a frame) no glow applies: times 1 leaves every contribution's
 * bits as they are, so the estimators skip the tests (lighting.frag makes them and multiplies
 * by 1). */
static inline void shade_horizon_glow(shade_horizon *h, const sl_lighting_uniforms *u, const float *map_vis)
{
    bool shadowed = false;
    for (int k = 0; k < SL_SHADOW_SUN_MAX; k++) {
        h->glow_vis[k] = map_vis[k];
        shadowed |= k < u->uEnvGlowCount && map_vis[k] < 1.0f;
    }
    h->glows = shadowed ? u->uEnvGlowCount : 0;
}

/* GLSL: glow - a sample's contribution c from direction w (environment space) times the
 * visibility of the map whose direction is nearest w where w lies in that map's glow, else c as
 * it is (the nearest map's, not the first whose glow holds w: two clusters of one sun's texels,
 * each with its own shadow, have glows that overlap). The env lights take a sun's brightest
 * texels out of the environment; the texels about them that the samples still read (the disc's
 * rim, the sky's glare around it) lie behind what hides the sun, which the map sees along their
 * own direction, where the pixel's specular factor (the cone, the reflection occlusion's rays,
 * the sky map of R's cell) speaks for the lobe about R. A glossy ball behind a bunny's ear, its
 * lobe's core open beside the ear and the sun's glare behind it, keeps the glare without it
 * (docs/lighting.md "Shadow maps", the glow). */
static inline int shade_glow_map(const shade_horizon *h, vec3 w) /* the map, or -1: none */
{
    float nearest = -2.0f;
    int map = -1;
    for (int k = 0; k < h->glows; k++) {
        float d = dot(w, xyz(h->glow[k]));
        if (d > nearest) {
            nearest = d;
            map = k;
        }
    }
    return map >= 0 && nearest >= h->glow[map].w ? map : -1;
}
static inline vec3 shade_glow(const shade_horizon *h, vec3 w, vec3 c, int *map) /* *map: the trace's */
{
    *map = shade_glow_map(h, w);
    return *map >= 0 ? scale(c, h->glow_vis[*map]) : c;
}

/* The part across the horizon times its visibility from world point P with world normal N: that
 * of the sky map whose cell holds normalize(h->dir) (sl_shadow_sky_cell); 0 with nothing
 * across, and so without the split (h->on false). Recorded in the trace. */
/* normalize(h->dir) into *d, or false with nothing across (its sum 0): the map's direction (the
 * batched path looks a span's maps up at once, sl_shadow_sky_cell_visibility_lanes) */
bool sl_shade_horizon_dir(const shade_horizon *h, vec3 *d);
vec3 sl_shade_horizon_visible(const sl_lighting_uniforms *u, const shade_horizon *h, vec3 P, vec3 N,
                              sl_lighting_trace *trace);
/* GLSL specular_mis, and specular_cv with mis for cvmis, each with the part across the horizon
 * to h (the batched path runs them per pixel where it does not batch: lighting_batched.c says
 * when) */
vec3 sl_shade_specular_mis(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation,
                           shade_horizon *h, sl_lighting_task *task, sl_lighting_trace *trace);
vec3 sl_shade_specular_cvmis(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation,
                             shade_horizon *h, sl_lighting_task *task, sl_lighting_trace *trace);

/* specular_mis's pieces: env_dist_sample, env_texel, env_dist_pdf, mis_power, and texelFetch of
 * level 0 */
vec4 sl_shade_env_dist_sample(const sl_lighting_uniforms *u, vec2 xi, ivec2 *texel);
ivec2 sl_shade_env_texel(const sl_lighting_uniforms *u, vec3 w);
float sl_shade_env_dist_pdf(const sl_lighting_uniforms *u, ivec2 t);
float sl_shade_mis_power(float p, float q);
vec3 sl_shade_env_texel_fetch(const sl_lighting_uniforms *u, ivec2 t);
/* The control variate's kernel for one pixel (lighting.c specular_cv; GLSL CvKernel): each
 * sample's radiance is subtracted times scale K(w) / p(w), K = ca k_a + cb k_b about dir. */
typedef struct {
    vec3 R;     /* the reflection direction */
    float r, lod; /* the lobe width and its chain level r (levels - 1) */
    vec3 ab;    /* the table's A, B, t */
    vec3 dir;   /* the lookup direction normalize(mix(N, R, t)), the kernels' axis */
    int set;    /* the chain's set (splitsum_lut.h) */
    sl_cv_levels levels;
    float beta; /* the table's coefficient */
    vec3 E;     /* the albedo Ks A + B */
    vec3 scale; /* beta E */
} sl_cv_kernel;
/* GLSL: no_cv - the microfacet estimator's: no kernel, nothing subtracted */
#define NO_CV ((const sl_cv_kernel *)NULL)

/* GLSL: cv_kernel_level - level `level`'s kernel of set `set` at c = w.d (ibl.h) */
static inline float sl_cv_kernel_level(const sl_lighting_uniforms *u, int set, int level, float c)
{
    return sl_prefilter_kernel_eval(&u->uSplitSumLut->kernels[set][level], c);
}

/* GLSL: cv_kernel */
static inline float sl_cv_kernel_eval(const sl_lighting_uniforms *u, const sl_cv_kernel *cv, float c)
{
    float K = 0.0f;
    if (cv->levels.ca > 0.0f)
        K += cv->levels.ca * sl_cv_kernel_level(u, cv->set, cv->levels.la, c);
    if (cv->levels.cb > 0.0f)
        K += cv->levels.cb * sl_cv_kernel_level(u, cv->set, cv->levels.lb, c);
    return K;
}

/* lighting.c cv_setup: the control variate's kernel for a pixel (the batched path's cv_samples
 * reads the chain itself) */
sl_cv_kernel sl_shade_cv_setup(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha);
/* GLSL specular_splitsum: the whole specular term of --estimator splitsum (both paths run it) */
vec3 sl_shade_specular_splitsum(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha,
                             sl_lighting_trace *trace);

/* The toolbox's pieces of the port (softlight/lighting.h, lighting_program.c): GLSL env_lod,
 * irradiance, specular_env_lights, point_light, background. */
vec3 sl_shade_env_lod(const sl_lighting_uniforms *u, vec3 w, float lod);
vec3 sl_shade_irradiance(const sl_lighting_uniforms *u, vec3 N);
vec3 sl_shade_env_lights(const sl_lighting_uniforms *u, vec3 N, vec3 V, vec3 Ks, float alpha);
/* The env lights the batched loops run over: the count rounded up to whole vectors of 16. The
 * uniforms' light arrays are zero past the count (a zero direction and radiance add exactly 0),
 * and a small K stays off the scalar remainder loop, which made K = 8 cost as much as K = 24. */
static inline int shade_env_light_lanes(const sl_lighting_uniforms *u) { return (u->uEnvLightCount + 15) & ~15; }
/* GLSL EnvLightSplit, env_light_split, env_light_near, env_light_grid: which env lights a
 * pixel's lobe reads over cells of their texel (those near R, when cells > 1), and into how many
 * rows and columns of cells light j's texel is split (lighting.c says why). R, T, B: the mirror
 * direction and the lobe's unit axes across it; across, along: the cells' widths along T and B
 * (radians), reach: the lobe's own along B (the near test's); side: the level-0 texel's longest
 * side. */
typedef struct {
    int cells;
    float cos_near;
    vec3 R, T, B;
    float across, along, reach, side;
} shade_env_light_split;
shade_env_light_split sl_shade_env_light_split(const sl_lighting_uniforms *u, vec3 N, vec3 V, float alpha);
bool sl_shade_env_light_near(const shade_env_light_split *split, vec3 l);
void sl_shade_env_light_grid(const sl_lighting_uniforms *u, int j, const shade_env_light_split *split, int *rows,
                             int *cols);
/* C only: each env light's shadow-map visibility at a point (shade_env_shadow.vis, as the port's
 * env_light_visibility gives it) from each map's there (map_vis[k]: sl_shadow_sun_visibility of
 * map k, SL_SHADOW_SUN_MAX of them, those past the maps' count read and not used) */
void sl_shade_env_light_visibility_of(const sl_lighting_uniforms *u, const float *map_vis, float *vis);
/* point_light times the light's shadow-map visibility (1 without maps) */
vec3 sl_shade_point_light(const sl_lighting_uniforms *u, int i, vec3 P, vec3 N, vec3 V, vec3 Kd, vec3 Ks, float alpha);
/* point_light alone: the batched path looks the visibility up for a span's pixels that it lights
 * at once, and scales as sl_shade_point_light does */
vec3 sl_shade_point_light_unshadowed(const sl_lighting_uniforms *u, int i, vec3 P, vec3 N, vec3 V, vec3 Kd, vec3 Ks,
                                     float alpha);
vec3 sl_shade_background(const sl_lighting_uniforms *u, vec2 fragCoord);

/* What a lighting program's toolbox reads (softlight/lighting.h: opaque there): the frame's
 * uniforms and G-buffer, the calling thread's task and the trace (both may be NULL). */
struct sl_lighting_resources {
    const sl_lighting_uniforms *u;
    const sl_gbuffer *gb;
    sl_lighting_task *task;
    sl_lighting_trace *trace;
};

/* The built-in program's two forms (lighting_program.c): the pass's dispatch between the port,
 * the batched path and the split sum, per texel and per span. */
vec3 sl_lighting_builtin_texel(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y,
                               sl_lighting_task *task, sl_lighting_trace *trace);
void sl_lighting_builtin_row(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                             sl_lighting_task *task, vec3 *out);

/* A covered pixel as main() has it once its frame is known. */
typedef struct {
    vec3 P, Kd, Ks;
    float alpha;     /* the lobe parameter (lobe_param): [0, MAX_ALPHA] Phong, [-2, -1] GGX */
    vec3 V, N;       /* world space, N after facing_normal */
    vec3 Nenv, Venv; /* environment space */
    vec2 rotation;   /* the pixel's Hammersley offset, 0 with rotation off */
    float occlusion; /* the G-buffer's extra plane (gbuffer.h): 1 and 0 when it has none */
    vec3 emissive;
    const vec2 *reflection; /* the G-buffer's reflection occlusion of the pixel (visibility, rays), or
                               NULL without it */
    const sl_vec4 *cone; /* the G-buffer's visibility cone (bent normal, AO) of the pixel, or NULL
                            without ambient occlusion */
    vec3 Fenv;           /* the facet normal in environment space (shade_facet_env), 0: none */
} shade_surface;

/* The env lights' shadows at a covered pixel (uniforms' envLightShadows): each light's
 * visibility (sl_shade_env_light_visibility_of; 0 past the count as far as the batched loops read,
 * shade_env_light_lanes, and unset beyond), and the batched path's specular
 * sum over the lights, each times its visibility; with `diffuse_given` the batched path has also
 * taken the lights' part out of the E it passes and summed their diffuse times the visibility
 * (`diffuse`), which sl_shade_surface_color then adds instead of summing it again. */
typedef struct {
    float vis[SL_ENV_LIGHTS_MAX];
    float map_vis[SL_SHADOW_SUN_MAX]; /* each map's visibility (unset past the maps' count): the glow's */
    vec3 specular;
    bool diffuse_given;
    vec3 diffuse;
} shade_env_shadow;

/* The reflection occlusion of pixel (x, y): NULL without the plane (sl_gbuffer.reflection). */
static inline const vec2 *shade_reflection(const sl_gbuffer *gb, int x, int y)
{
    return gb->reflection ? gb->reflection + (size_t)y * (size_t)gb->width + (size_t)x : NULL;
}

/* The visibility cone of pixel (x, y): NULL without the plane (sl_gbuffer.cone). */
static inline const sl_vec4 *shade_cone(const sl_gbuffer *gb, int x, int y)
{
    return gb->cone ? gb->cone + (size_t)y * (size_t)gb->width + (size_t)x : NULL;
}

/* The extra channels of pixel (x, y): "none" (occlusion 1, emission 0) without the plane. */
static inline sl_gbuffer_extra shade_extra(const sl_gbuffer *gb, int x, int y)
{
    const sl_gbuffer_extra none = {.occlusion = 1.0f};
    return gb->extra ? gb->extra[(size_t)y * (size_t)gb->width + (size_t)x] : none;
}

/* The specular term's occlusion with the visibility cone, in two steps both paths share (so
 * both have the same bits): shade_cone_cosines, B.R and N.V of the lobe about R =
 * reflect(-Venv, Nenv) with B the cone's axis in environment space, and the share of the cone's
 * occlusion across the horizon from R (shade_cone_across); shade_spec_occlusion, the material's
 * `occlusion` times its share of the AO `ao` (the cone's w) and the specular occlusion
 * (sl_specular_occlusion_lobe) of the cone opened by that share. The second has no branch: the
 * batched path runs it over a span in one vector loop. GLSL main's uHasCone branch has both
 * inline. */

/* GLSL: cone_across
 * With the sky maps' part across the horizon (shade_horizon_on; 0 without it), the
 * share of the cone's occlusion that lies across the horizon from R, in [0, 1]. The maps take
 * the lobe's part across, so the cone's factor, which the rest of the lobe keeps, should count
 * only the occluders on R's side; the cone does not say where its occluders are, but its axis
 * leans away from them: the share of the lean B - N that points across the horizon from R (its
 * z over its length, signed by R's side) is taken as their share across. A pedestal's side face
 * beside the floor (the bent normal leans up, R just above the horizon) keeps its reflection of
 * the sky, as the visibility truth does, where the whole cone closed over it. */
static inline float shade_cone_across(const sl_lighting_uniforms *u, vec3 B, vec3 Nenv, vec3 R)
{
    vec3 lean = sub(B, Nenv);
    float len = sqrtf(dot(lean, lean));
    float up = len > 1e-6f ? lean.z / len : 0.0f; /* > 0: the occluders lie below */
    float across = R.z >= 0.0f ? up : -up;
    return shade_horizon_on(u) ? clampf(across, 0.0f, 1.0f) : 0.0f;
}

static inline void shade_cone_cosines(const sl_lighting_uniforms *u, const sl_vec4 *cone, vec3 Nenv, vec3 Venv,
                                      float *b_dot_r, float *n_dot_v, float *across)
{
    vec3 B = mat3_mul_vec3(u->uEnvRotation, vec3(cone->x, cone->y, cone->z));
    vec3 R = sub(scale(Nenv, 2.0f * dot(Nenv, Venv)), Venv);
    *b_dot_r = dot(B, R);
    *n_dot_v = dot(Nenv, Venv);
    *across = shade_cone_across(u, B, Nenv, R);
}

static inline float shade_spec_occlusion(float ao, float occlusion, float b_dot_r, float n_dot_v, sl_so_lobe lobe,
                                         float across)
{
    float so = sl_specular_occlusion_lobe(ao + (1.0f - ao) * across, b_dot_r, n_dot_v, lobe);
    /* the occlusion is the material's times the AO: the material's share stays */
    float share = occlusion * (so / ao);
    return ao > 0.0f ? share : 0.0f;
}

/* The share of a cell's angle from which a lobe takes its map (GLSL LOBE_MAP_SHARE,
 * tests/cli/uniforms_in_sync.sh). A build defining another (1e9f: no lobe takes a map)
 * is for bench/visibility-variants.sh's comparison; the GLSL twin does not follow it. */
#ifndef SL_LOBE_MAP_SHARE
#define SL_LOBE_MAP_SHARE 0.5f
#endif
/* 1: every lobe whose R lies under the horizon takes its map too, however narrow (docs/lighting.md
 * "Sky visibility maps", why not; for that comparison, the GLSL twin does not follow it). */
#ifndef SL_LOBE_MAP_GROUND
#define SL_LOBE_MAP_GROUND 0
#endif

/* GLSL: lobe_map_factor
 * With the sky maps, a lobe at least half a cell wide (its cone's angle ts, sl_so_lobe_cone, at
 * least half the angle of a cap of 4 pi / K steradians) also takes the visibility of the one map
 * whose cell holds R, times the material's occlusion: the specular's factor is the smaller of
 * `capped` and that. The reflection occlusion's rays see only what the G-buffer holds: a floor
 * beside a pedestal, whose lobe the model on the pedestal hides from behind, keeps its rays open
 * where the truth loses nearly all of it; the map sees the whole scene. A cell is wide for a
 * narrower lobe (a sharp reflection of a sphere in a glossy floor, which the rays see), which
 * keeps `capped`. R in environment space (unit, as the batched path's p->R), P and N in the
 * world. */
/* whether the lobe (cone angle ts, R's environment z) takes its cell's map: wide enough, or, in a
 * SL_LOBE_MAP_GROUND build, R under the horizon */
static inline bool shade_lobe_takes_map(const sl_lighting_uniforms *u, float ts, float Rz)
{
    return u->skyMaps && (!(ts < SL_LOBE_MAP_SHARE * u->skyMaps->cell_angle) || (SL_LOBE_MAP_GROUND && Rz < 0.0f));
}
/* the factor with the map's visibility v (the batched path looks a span's up at once) */
static inline float shade_lobe_map_with(float capped, float material, float v) { return minf(capped, material * v); }
static inline float shade_lobe_map(const sl_lighting_uniforms *u, float capped, float material, vec3 P, vec3 N,
                                   vec3 R, float ts)
{
    if (!shade_lobe_takes_map(u, ts, R.z))
        return capped;
    float v = sl_shadow_sky_map_visibility(u->skyMaps, sl_shadow_sky_cell(u->skyMaps, R), P, N);
    return shade_lobe_map_with(capped, material, v);
}

/* The material's share of the occlusion `occlusion` (the extra plane's: the material's times the
 * AO `ao`), 0 where the AO is 0, as shade_spec_occlusion takes it; the reflection occlusion's
 * rays scale it (sl_reflection_specular_factor). */
static inline float shade_material_occlusion(float ao, float occlusion)
{
    float share = occlusion / ao;
    return ao > 0.0f ? share : 0.0f;
}

/* The diffuse term's lookup direction with the visibility cone (bent_irradiance.h), in
 * environment space: both paths call this one, so the port's irradiance(D) and the batched
 * path's span lookup read the same direction. */
static inline vec3 shade_diffuse_dir(const sl_lighting_uniforms *u, const sl_vec4 *cone, vec3 Nenv)
{
    if (u->skyMaps)
        return Nenv; /* the sky maps take the diffuse's occlusion: the irradiance about N */
    vec3 B = mat3_mul_vec3(u->uEnvRotation, vec3(cone->x, cone->y, cone->z));
    return sl_bent_irradiance_dir(Nenv, B, cone->w);
}

/* The diffuse term's occlusion with the visibility cone: the extra plane's (the material's times
 * GTAO's AO), or with the sky visibility maps the material's alone (that over the AO, cone.w):
 * the maps replace the AO on the diffuse, which counted together would see near occluders twice
 * (docs/lighting.md "Sky visibility maps"); the AO keeps the specular occlusion. */
static inline float shade_diffuse_occlusion(const sl_lighting_uniforms *u, const sl_vec4 *cone, float occlusion)
{
    if (!u->skyMaps)
        return occlusion;
    return cone->w > 1e-3f ? fminf(occlusion / cone->w, 1.0f) : 1.0f;
}

/* Part of GLSL main, from `if (uDiffuse != 0)` on: diffuse, specular (+ env lights), times the occlusion,
 * point lights, emission.
 * `E` NULL runs the port's irradiance(Nenv), with the cone irradiance(shade_diffuse_dir); the batched path passes the value it looked up for
 * the whole span (sl_irradiance_eval_span: the same bits).
 * `specular` NULL runs the port's specular_ibl / specular_microfacet and specular_env_lights;
 * the batched path passes the value of that whole term, computed by its own loops, the env
 * lights left out of it when their shadow maps are on (env_shadow then holds them).
 * `across` (with `specular` given): the part of it across the horizon times its visibility
 * (sl_shade_horizon_visible), which `specular` leaves out; NULL: none.
 * `env_shadow` (uniforms' envLightShadows only; NULL: the port looks the visibilities up). */
vec3 sl_shade_surface_color(const sl_lighting_uniforms *u, const shade_surface *s, const vec3 *E, const vec3 *specular,
                            const vec3 *across, const shade_env_shadow *env_shadow, sl_lighting_task *task,
                            sl_lighting_trace *trace);

/* The end of main(): a NaN or Inf becomes 0 (counted, and traced). */
vec3 sl_shade_finish(vec3 color, sl_lighting_task *task, sl_lighting_trace *trace);

/* The view ray of background(), for both paths: m = uInvViewProj, r = uEnvRotation, passed by
 * column so a vectorized caller keeps them in registers. mat4_mul_vec4's operations. */
__attribute__((always_inline)) static inline vec3 shade_background_dir(const vec4 m[4], const vec3 r[3], vec2 viewport,
                                                                       vec2 fragCoord)
{
    vec2 ndc = sub(scale(vec2(fragCoord.x / viewport.x, fragCoord.y / viewport.y), 2.0f), vec2s(1.0f));
    vec4 nearP = add(add(scale(m[0], ndc.x), scale(m[1], ndc.y)), add(scale(m[2], -1.0f), scale(m[3], 1.0f)));
    vec4 farP = add(add(scale(m[0], ndc.x), scale(m[1], ndc.y)), add(scale(m[2], 1.0f), scale(m[3], 1.0f)));
    vec3 d = normalize(sub(scale(xyz(farP), 1.0f / farP.w), scale(xyz(nearP), 1.0f / nearP.w)));
    return add(add(scale(r[0], d.x), scale(r[1], d.y)), scale(r[2], d.z));
}

/* background() over a span, both fast paths (lighting_batched.c): the view ray, the fast
 * lat-long map and level 0 alone, gathered from the block when there is one; times the
 * intensity, into bg_r/g/b[0 .. count). */
void sl_shade_background_span(const sl_lighting_uniforms *u, int x0, int y, int count, float *bg_r, float *bg_g,
                           float *bg_b);

/* The pixel's view frame for both fast paths' vectorized loops: V from P to the eye,
 * facing_normal (its two branches as selects of values computed by the port's operations, so
 * the same bits), the environment frame NE, VE (r = uEnvRotation by column: mat3_mul_vec3's
 * operations), NE.VE, R = reflect(-VE, NE), and whether facing_normal bent n. Returned by
 * value: GCC vectorizes a loop around it then, not when it writes through a pointer. */
typedef struct {
    vec3 V, N, NE, VE, R;
    float NdotV;
    int bent;
} shade_view_frame;

__attribute__((always_inline)) static inline shade_view_frame shade_view_frame_at(vec3 eye, vec3 P, vec3 n,
                                                                                  const vec3 r[3])
{
    shade_view_frame f;
    vec3 V = normalize(sub(eye, P));
    float len2 = dot(n, n);
    vec3 Nn = scale(n, 1.0f / sqrtf(len2));
    float NdotV0 = dot(Nn, V);
    vec3 Nb = normalize(add(Nn, scale(V, SHADE_MIN_NDOTV - NdotV0)));
    bool keep = len2 > SL_BRDF_TINY, bend = NdotV0 < SHADE_MIN_NDOTV;
    /* per component: GCC if-converts scalar selects, not whole-struct ones */
    vec3 N = vec3(keep ? (bend ? Nb.x : Nn.x) : V.x, keep ? (bend ? Nb.y : Nn.y) : V.y,
                  keep ? (bend ? Nb.z : Nn.z) : V.z);
    f.V = V;
    f.N = N;
    f.NE = add(add(scale(r[0], N.x), scale(r[1], N.y)), scale(r[2], N.z));
    f.VE = add(add(scale(r[0], V.x), scale(r[1], V.y)), scale(r[2], V.z));
    f.NdotV = dot(f.NE, f.VE);
    f.R = normalize(sub(scale(f.NE, 2.0f * f.NdotV), f.VE));
    f.bent = dot(n, V) < SHADE_MIN_NDOTV * length(n);
    return f;
}

/* ---- per-thread scratch (lighting_task.c) ---- */

enum { SLOTS = 8 };

/* The batched path's per-sample loops run over whole vectors of 8: a block of m samples is
 * processed as sl_samples_padded(m), the samples past m copies of the last one (valid numbers,
 * so every fetch stays in range), their contributions dropped before the sum (the same bits).
 * Unpadded, a tail of m mod 8 runs through the loops' scalar remainders, which makes N = 12
 * take 1.5 times and N = 20 1.36 times as long (the recipe on ggx.json at 320x180, one thread),
 * longer than N = 16 and N = 40. 8, not 16: N = 40 stays 40. The tables below hold their padded
 * tail (sl_shade_lobe_for, sl_shade_azimuth_for). */
enum { SL_SAMPLE_LANES = 8 };
static inline int sl_samples_padded(int m) { return (m + SL_SAMPLE_LANES - 1) / SL_SAMPLE_LANES * SL_SAMPLE_LANES; }
_Static_assert(SL_HAMMERSLEY_MAX % SL_SAMPLE_LANES == 0, "a padded N fits the tables");

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

/* The MIS estimator's environment samples with rotation off: the same N directions in every
 * pixel (env_dist_sample of each shifted pair, the port's bits), their level-0 radiance times
 * the intensity and their density. Structure of arrays for the batched path's vector loads. */
typedef struct {
    int n; /* 0 = not built */
    float wx[SL_HAMMERSLEY_MAX], wy[SL_HAMMERSLEY_MAX], wz[SL_HAMMERSLEY_MAX];
    float lr[SL_HAMMERSLEY_MAX], lg[SL_HAMMERSLEY_MAX], lb[SL_HAMMERSLEY_MAX];
    float pe[SL_HAMMERSLEY_MAX];
    float xe1[SL_HAMMERSLEY_MAX], xe2[SL_HAMMERSLEY_MAX]; /* the shifted pairs, for a trace */
} env_sample_table;

struct sl_lighting_task {
    const sl_lighting_uniforms *owner; /* the uniforms the tables were built from */
    int next;                          /* round-robin victim */
    lobe_table slots[SLOTS];
    azimuth_table azimuth;
    env_sample_table env_samples;
    sl_lighting_stats stats;
    /* the sky maps' V per texel of the G-buffer being lit (sl_lighting_planes, sky_plane.c), for
     * the batched paths; NULL: each pixel looks its V up */
    const float *sky_plane;
};

/* ---- the sky maps' V over a whole G-buffer (sky_plane.c) ---- */

/* The task's plane of V from texel (x0, y) of gb on, or NULL: the span looks V up itself. */
static inline const float *shade_sky_row(const sl_lighting_task *task, const sl_gbuffer *gb, int x0, int y)
{
    return task && task->sky_plane ? task->sky_plane + (size_t)y * (size_t)gb->width + (size_t)x0 : NULL;
}

/* The fill's tests: an anchor stands for a texel where it lies within SL_SKY_PLANE_SAME_DEPTH of
 * the texel's view distance from its tangent plane, within SL_SKY_PLANE_REACH texels of the
 * finest map from it, with its normal within SL_SKY_PLANE_SAME_NORMAL (a cosine: 18 degrees),
 * and the anchors' V are within SL_SKY_PLANE_AGREE of each other (the lighting pass's;
 * bench_sky_plane and the tests pass others). */
#define SL_SKY_PLANE_SAME_DEPTH 0.002f
#define SL_SKY_PLANE_REACH 6.0f
#define SL_SKY_PLANE_SAME_NORMAL 0.95f
#define SL_SKY_PLANE_AGREE 0.005f
/* The anchors' spacing, in texels each way (a power of two): the grids between are filled a
 * level at a time, each from the one of twice its spacing. */
#ifndef SL_SKY_PLANE_SPACING
#define SL_SKY_PLANE_SPACING 4
#endif
_Static_assert(SL_SKY_PLANE_SPACING >= 2 && (SL_SKY_PLANE_SPACING & (SL_SKY_PLANE_SPACING - 1)) == 0,
               "the anchors' spacing is a power of two");

/* V (sl_shadow_sky_visibility at each covered texel's P and lighting normal) into plane, w x h
 * floats in the G-buffer's order (1 at an empty texel): looked up at the anchors (every
 * SL_SKY_PLANE_SPACING-th texel each way) and filled between them a level at a time where the
 * surface allows and the texels filled from agree within `agree` (agree < 0: every covered texel
 * looked up), with `threads` OpenMP threads (> 0).
 * u->skyMaps must be set. Returns the lookups made. */
int64_t sl_sky_plane_fill(const sl_lighting_uniforms *u, const sl_gbuffer *gb, float *plane, float agree,
                          int threads);

/* ---- trace hooks and counters: the named points where a path records what a pixel computed.
 * trace and task may be NULL (the pass has no trace); a hook then does nothing. ---- */

static inline void trace_texel(sl_lighting_trace *t, const sl_gbuffer_texel *texel, vec2 fragCoord, bool plain)
{
    if (!t)
        return;
    t->frag_coord = fragCoord;
    t->texel = *texel;
    t->covered = !(texel->depth >= 1.0f);
    t->plain = plain;
}

static inline void trace_background(sl_lighting_task *task, sl_lighting_trace *t, vec3 color)
{
    if (task)
        task->stats.background++;
    if (t)
        t->background = color;
}

/* A covered pixel whose normal was bent toward the eye (facing_normal), counted. */
static inline void count_bent(sl_lighting_task *task, bool bent)
{
    if (task)
        task->stats.bent_normals += bent;
}

/* The covered pixel's frame and how its lobe set samples; bent: its normal was bent toward the
 * eye (facing_normal). */
static inline void trace_surface(const sl_lighting_uniforms *u, sl_lighting_task *task, sl_lighting_trace *t,
                                 const shade_surface *s, bool bent)
{
    count_bent(task, bent);
    if (!t)
        return;
    t->estimator = shade_estimator_of(u, s->alpha);
    t->lod_rule = shade_lod_rule_of(u, s->alpha);
    t->distortion = shade_distortion_of(u, s->alpha) != 0;
    t->set_own = sl_lobe_is_ggx(s->alpha) && sl_lighting_sets_differ(&u->options);
    t->V = s->V;
    t->N = s->N;
    t->bent = bent;
    t->Nenv = s->Nenv;
    t->Venv = s->Venv;
    t->rotation = s->rotation;
    t->alpha = s->alpha;
}

/* The frame the samples are drawn in: A, B about R (specular_ibl) or about N (microfacet).
 * R is recorded for both, as specular_ibl computes it. */
static inline void trace_sample_frame(sl_lighting_trace *t, vec3 N, vec3 V, vec3 A, vec3 B, bool pole, int n,
                                      bool microfacet)
{
    if (!t)
        return;
    float NdotV = dot(N, V);
    t->NdotV = NdotV;
    t->R = normalize(sub(scale(N, 2.0f * NdotV), V));
    t->A = A;
    t->B = B;
    t->pole_frame = pole;
    t->sample_count = n;
    t->microfacet = microfacet;
}

/* The split-sum lookup (specular_splitsum): its frame, lobe width, level, lookup direction,
 * prefiltered radiance and the table's scale, bias and direction factor. */
static inline void trace_splitsum(sl_lighting_trace *t, vec3 N, vec3 V, vec3 R, float r, float lod, vec3 dir, vec3 P,
                                  vec3 ab)
{
    if (!t)
        return;
    t->NdotV = dot(N, V);
    t->R = R;
    t->sample_count = 0;
    t->splitsum = true;
    t->splitsum_width = r;
    t->splitsum_lod = lod;
    t->splitsum_dir = dir;
    t->splitsum_prefiltered = P;
    t->splitsum_ab = ab;
}

/* The control variate's terms (specular_cv): beta, the levels, E, the closed part and the
 * samples' mean correction. */
static inline void trace_cv(sl_lighting_trace *t, const sl_cv_kernel *cv, vec3 closed, vec3 correction)
{
    if (!t)
        return;
    t->cv = true;
    t->cv_beta = cv->beta;
    t->cv_levels = cv->levels;
    t->cv_E = cv->E;
    t->cv_closed = closed;
    t->cv_correction = correction;
}

static inline void trace_sample(sl_lighting_trace *t, int k, const sl_lighting_trace_sample *s)
{
    if (t)
        t->samples[k] = *s;
}

/* The MIS estimator ran: samples[k] is pair k's BRDF sample, env_samples[k] its environment one. */
static inline void trace_mis(sl_lighting_trace *t)
{
    if (t)
        t->mis = true;
}

static inline void trace_env_sample(sl_lighting_trace *t, int k, const sl_lighting_trace_sample *s)
{
    if (t)
        t->env_samples[k] = *s;
}

/* The terms of main()'s sum: diffuse (with its irradiance), env lights (their exact part, inside
 * the specular), specular, point light i. */
static inline void trace_diffuse(sl_lighting_trace *t, vec3 E, vec3 diffuse)
{
    if (t) {
        t->irradiance = E;
        t->diffuse = diffuse;
    }
}

/* N, V: environment space, as specular_env_lights takes them */
static inline void trace_env_lights(sl_lighting_trace *t, const sl_lighting_uniforms *u, vec3 N, vec3 V, float alpha,
                                    vec3 exact)
{
    if (!t)
        return;
    t->env_light_count = u->uEnvLightCount;
    t->env_lights = exact;
    t->env_lights_split = t->env_light_cells = 0;
    const shade_env_light_split split = sl_shade_env_light_split(u, N, V, alpha);
    for (int j = 0; j < u->uEnvLightCount; j++) {
        vec3 w = xyz(u->uEnvLightDir[j]);
        int rows, cols;
        if (dot(w, N) <= 0.0f || !sl_shade_env_light_near(&split, w))
            continue;
        sl_shade_env_light_grid(u, j, &split, &rows, &cols);
        if (rows * cols > 1) {
            t->env_lights_split++;
            t->env_light_cells = rows * cols > t->env_light_cells ? rows * cols : t->env_light_cells;
        }
    }
}

static inline void trace_specular(sl_lighting_trace *t, vec3 specular)
{
    if (t)
        t->specular = specular;
}

static inline void trace_horizon(sl_lighting_trace *t, const shade_horizon *h, vec3 dir, int cell, float v,
                                 vec3 visible)
{
    if (t) {
        t->horizon = true;
        t->horizon_part = h->sum;
        t->horizon_dir = dir;
        t->horizon_cell = cell;
        t->horizon_visibility = v;
        t->horizon_visible = visible;
    }
}

static inline void trace_light(sl_lighting_trace *t, int i, vec3 light)
{
    if (t) {
        t->light[i] = light;
        t->lights = add(t->lights, light);
    }
}

static inline void trace_extra(sl_lighting_trace *t, float occlusion, vec3 emissive)
{
    if (t) {
        t->occlusion = occlusion;
        t->emissive = emissive;
    }
}

/* The pixel's visibility cone and what the lighting made of it: the bent normal (world space),
 * the AO, the diffuse and specular factors applied, the share of the cone's occlusion across the
 * horizon (shade_cone_across). */
static inline void trace_cone(sl_lighting_trace *t, const sl_vec4 *cone, float diffuse_occlusion,
                              float specular_occlusion, float cone_across, float lobe_map)
{
    if (t && cone) {
        t->cone_across = cone_across;
        t->lobe_map = lobe_map;
        t->cone = true;
        t->cone_axis = vec3(cone->x, cone->y, cone->z);
        t->ao = cone->w;
        t->diffuse_occlusion = diffuse_occlusion;
        t->specular_occlusion = specular_occlusion;
    }
}

/* After a pixel's samples: n drawn, `below` of them contributed 0, pole = the X x axis frame. */
static inline void count_samples(sl_lighting_task *task, int n, int below, bool pole)
{
    if (!task)
        return;
    task->stats.samples += n;
    task->stats.below_horizon += below;
    task->stats.pole_frames += pole;
}

/* Samples k0 .. k0 + m - 1 of the lobe for alpha, by the port's own generators (so their bits):
 * a table's contents, or a block's when there is no task (tests, traces). */
void sl_shade_lobe_fill(const sl_lighting_uniforms *u, float alpha, bool microfacet, int k0, int m, float *xi1, float *xi2,
                     float *Lx, float *Ly, float *Lz, float *pdf);
/* The table for alpha in the task's cache, built on a miss (the tables of the last SLOTS
 * distinct alphas are kept: scenes have few materials). */
const lobe_table *sl_shade_lobe_for(const sl_lighting_uniforms *u, sl_lighting_task *task, float alpha, bool microfacet);
/* Entries [m, padded) of each column set to its entry m - 1 (m >= 1). */
void sl_shade_pad_samples(float *const *columns, int count, int m, int padded);
/* The MIS environment samples, rotation off: the task's (built once per uniforms), or `local`
 * filled when task is NULL. */
const env_sample_table *sl_shade_env_samples_for(const sl_lighting_uniforms *u, sl_lighting_task *task,
                                                 env_sample_table *local);
/* The azimuth table: the task's (built once per uniforms), or `local` filled when task is NULL. */
const azimuth_table *sl_shade_azimuth_for(const sl_lighting_uniforms *u, sl_lighting_task *task, azimuth_table *local);

/* ---- the batched path (lighting_batched.c) ---- */

/* main(), batched: pixels x0 .. x0 + count - 1 (count <= SPAN) of G-buffer row y into out[].
 * A trace (count 1) records what the pixel computed. */
void sl_shade_span(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                sl_lighting_task *task, sl_lighting_trace *trace, vec3 *out);

/* ---- the split-sum fast path (lighting_splitsum.c) ---- */

/* Whether it runs for these uniforms: estimator SPLITSUM, not plain, no env lights, both
 * prefiltered chains as blocks of the same size. */
bool sl_shade_splitsum_fast(const sl_lighting_uniforms *u);
/* main() with specular_splitsum, vectorized over pixels x0 .. x0 + count - 1 (count <= SPAN) of
 * G-buffer row y into out[]; a trace (count 1) records what the pixel computed. */
void sl_shade_span_splitsum(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x0, int y, int count,
                         sl_lighting_task *task, sl_lighting_trace *trace, vec3 *out);

/* main(), the port: G-buffer texel (x, y) (lighting.c). */
vec3 sl_shade_plain(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y, sl_lighting_task *task,
                 sl_lighting_trace *trace);

#endif
