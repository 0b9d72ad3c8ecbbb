/* renderer.c - one frame through raster, shading and post (see renderer.h). */
#include "renderer.h"

#include <stdlib.h>
#include <string.h>

#include "core/threads.h"
#include "core/timer.h"
#include "occlusion/gtao.h"
#include "occlusion/reflection.h"
#include "shadow/shadow.h"
#include "scene/camera.h"

static bool build_irradiance(sl_renderer *r, sl_error *err)
{
    const sl_scene *scene = r->scene;
    sl_irradiance_method method = r->desc.lighting.irradiance;
    if (r->have_irradiance) {
        sl_irradiance_free(&r->irradiance);
        r->have_irradiance = false;
    }
    double t0 = sl_now_seconds();
    bool ok;
    switch (method) {
    case SL_IRRADIANCE_MAP: {
        if (!scene->environment.irradiance_path[0])
            return sl_fail(err, SL_ERR_RANGE, "irradiance method 'map' needs environment.irradiance in %s",
                           scene->path);
        sl_image map;
        if (!sl_image_read_radiance(scene->environment.irradiance_path, r->desc.image_budget, &map, NULL, err))
            return false;
        ok = sl_irradiance_from_image(&r->irradiance, &map, err);
        sl_image_free(&map);
        break;
    }
    case SL_IRRADIANCE_BRUTE:
        ok = sl_irradiance_brute(&r->irradiance, &r->env, r->desc.irradiance_map_width, r->desc.threads, err);
        break;
    case SL_IRRADIANCE_OCT:
    case SL_IRRADIANCE_DP:
        ok = sl_irradiance_map(&r->irradiance, &r->env, &(sl_irradiance_map_desc){.method = method, .threads = r->desc.threads}, err);
        break;
    case SL_IRRADIANCE_SH9:
    default:
        ok = sl_irradiance_sh9(&r->irradiance, &r->env, err);
        break;
    }
    r->timings.irradiance_ms = (sl_now_seconds() - t0) * 1e3;
    r->have_irradiance = ok;
    return ok;
}

/* The env lights for the requested count (or ceiling), extracted once per environment and
 * request. A ceiling can leave none (env_lights_built 0): the frame then reads the environment as
 * without env lights. */
static bool update_env_lights(sl_renderer *r, sl_error *err)
{
    const sl_lighting_options *o = &r->desc.lighting;
    if (o->env_lights <= 0 ||
        (o->env_lights == r->env_lights_asked && o->env_lights_worth == r->env_lights_asked_worth))
        return true;
    double t0 = sl_now_seconds();
    sl_env_lights_free(&r->env_lights);
    r->env_lights_built = 0;
    r->env_lights_asked = 0;
    sl_env_free(&r->env_oct); /* resampled from the old residual */
    r->env_oct_built = -1;
    if (!(o->env_lights_worth ? sl_env_lights_extract_worth : sl_env_lights_extract)(&r->env_lights, &r->env,
                                                                                    o->env_lights, r->desc.threads, err))
        return false;
    r->env_lights_built = r->env_lights.count;
    r->env_lights_asked = o->env_lights;
    r->env_lights_asked_worth = o->env_lights_worth;
    r->timings.env_lights_ms = (sl_now_seconds() - t0) * 1e3;
    return true;
}

/* The octahedral chain of what the samples read (the residual when there are env lights),
 * when the layout asks for it; rebuilt when the environment or the env lights change. */
static bool update_env_oct(sl_renderer *r, sl_error *err)
{
    sl_lighting_options o = sl_lighting_options_resolve(&r->desc.lighting);
    int lights = o.env_lights > 0 ? r->env_lights_built : 0;
    if (o.env_layout != SL_ENV_LAYOUT_OCT || r->env_oct_built == lights)
        return true;
    double t0 = sl_now_seconds();
    sl_env_free(&r->env_oct);
    r->env_oct_built = -1;
    if (!sl_env_build_oct(&r->env_oct, lights > 0 ? &r->env_lights.residual : &r->env, 0, r->desc.threads, err))
        return false;
    r->env_oct_built = lights;
    r->timings.env_oct_ms = (sl_now_seconds() - t0) * 1e3;
    return true;
}

/* The MIS estimator's distribution of what the samples read (the residual when there are env
 * lights), when the estimator asks for it (`estimator` as update_splitsum's); rebuilt when the
 * environment or the env lights change, never per frame. */
static bool update_env_dist(sl_renderer *r, sl_estimator estimator, sl_error *err)
{
    sl_lighting_options o = sl_lighting_options_resolve(&r->desc.lighting);
    if (estimator != SL_ESTIMATOR_DEFAULT)
        o.estimator = o.ggx.estimator = estimator;
    int lights = o.env_lights > 0 ? r->env_lights_built : 0;
    if (!(sl_estimator_reads_env_dist(o.estimator) || sl_estimator_reads_env_dist(o.ggx.estimator)) ||
        r->env_dist_built == lights)
        return true;
    double t0 = sl_now_seconds();
    sl_env_dist_free(&r->env_dist);
    r->env_dist_built = -1;
    if (!sl_env_dist_build(&r->env_dist, lights > 0 ? &r->env_lights.residual : &r->env, err))
        return false;
    r->env_dist_built = lights;
    r->timings.env_dist_ms = (sl_now_seconds() - t0) * 1e3;
    return true;
}

bool sl_renderer_all_ggx(const sl_scene *scene)
{
    for (int i = 0; i < scene->object_count; i++)
        if (scene->materials[scene->objects[i].material].brdf != SL_BRDF_GGX)
            return false;
    return scene->object_count > 0;
}

/* Whether some object of the scene is drawn with a GGX material */
static bool any_ggx(const sl_scene *scene)
{
    for (int i = 0; i < scene->object_count; i++)
        if (scene->materials[scene->objects[i].material].brdf == SL_BRDF_GGX)
            return true;
    return false;
}

void sl_renderer_splitsum_sets(const sl_scene *scene, bool *phong, bool *ggx)
{
    *phong = *ggx = false;
    for (int m = 0; m < scene->material_count; m++) {
        *ggx |= scene->materials[m].brdf == SL_BRDF_GGX;
        *phong |= scene->materials[m].brdf != SL_BRDF_GGX;
    }
    *phong |= !*ggx;
}

/* The split-sum method's prefiltered chains of what the samples read, for both lobe sets, and
 * the BRDF's table (once), when the estimator asks for them (splitsum, and cv, its control variate) (`estimator`: the frame's, which the
 * viewer's moving frames set; SL_ESTIMATOR_DEFAULT: desc's); rebuilt when the environment or
 * the env lights change, never per frame. A scene and a viewer that never use the estimator pay
 * nothing. */
static bool update_splitsum(sl_renderer *r, sl_estimator estimator, sl_error *err)
{
    sl_lighting_options o = sl_lighting_options_resolve(&r->desc.lighting);
    if (estimator != SL_ESTIMATOR_DEFAULT)
        o.estimator = o.ggx.estimator = estimator;
    int lights = o.env_lights > 0 ? r->env_lights_built : 0;
    if (!(sl_estimator_reads_splitsum(o.estimator) || sl_estimator_reads_splitsum(o.ggx.estimator)) ||
        (r->splitsum_built == lights && r->splitsum_gterm == o.gterm))
        return true;
    double t0 = sl_now_seconds();
    sl_env_free(&r->splitsum_phong);
    sl_env_free(&r->splitsum_ggx);
    r->splitsum_built = -1;
    const sl_env *src = lights > 0 ? &r->env_lights.residual : &r->env;
    if (!r->splitsum_lut) {
        r->splitsum_lut = malloc(sizeof *r->splitsum_lut);
        if (!r->splitsum_lut)
            return sl_fail(err, SL_ERR_MEMORY, "no memory for the split-sum table");
        sl_splitsum_lut_build(r->splitsum_lut, r->desc.threads);
    }
    bool phong, ggx;
    sl_renderer_splitsum_sets(r->scene, &phong, &ggx);
    if (r->desc.gbuffer_program || r->desc.any_lobe) /* a user's G-buffer program writes either lobe */
        phong = ggx = true;
    /* the Phong chain weights its samples with the G term (prefilter.c), so --g picks the chain */
    sl_prefilter_desc pd = {.ggx = false, .g_one = o.gterm == SL_GTERM_ONE, .threads = r->desc.threads};
    if ((phong && !sl_env_prefilter(&r->splitsum_phong, src, &pd, err)) ||
        (ggx && !sl_env_prefilter(&r->splitsum_ggx, src, &(sl_prefilter_desc){.ggx = true, .threads = r->desc.threads}, err))) {
        sl_env_free(&r->splitsum_phong);
        return false;
    }
    r->splitsum_built = lights;
    r->splitsum_gterm = o.gterm;
    r->timings.splitsum_ms = (sl_now_seconds() - t0) * 1e3;
    return true;
}

/* A scene without an environment is lit by black: a 1x1 black map keeps the shader's
 * one code path (and the GL path's) instead of a special case per pixel. */
static bool load_env(sl_env *env, const char *path, size_t budget, int threads, sl_image_repairs *repairs,
                     sl_error *err)
{
    sl_image img;
    if (path[0]) {
        if (!sl_image_read_radiance(path, budget, &img, repairs, err))
            return false;
        if (img.channels != 3) {
            sl_image_free(&img);
            return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: environment must be RGB", path);
        }
    } else if (!sl_image_alloc(&img, 1, 1, 3, err)) {
        return false;
    }
    bool ok = sl_env_build(env, &img, threads, err);
    sl_image_free(&img);
    return ok;
}

bool sl_render_desc_resolve(sl_render_desc *d, const sl_scene *scene, sl_error *err)
{
    sl_option_values o = scene->options;
    sl_option_values_merge(&o, &d->options);
    /* the irradiance's default: the scene's precomputed map when it names one */
    if (!sl_option_is_set(&o, SL_OPT_IRRADIANCE) && scene->environment.irradiance_path[0])
        sl_option_set_irradiance(&o, SL_IRRADIANCE_MAP);
    /* the estimator's default: the specification's recipe for its Phong set; for a scene whose
     * objects are all GGX (imported models) the most accurate setting at the recipe's cost as
     * measured (docs/accuracy.md "Defaults"): the microfacet estimator, the pdf mip rule with the
     * distortion, and the most env lights, each where neither the scene nor the command line
     * sets it. In a scene of both sets the GGX objects sample that way, with the env lights as
     * theirs alone, and the Phong ones keep the recipe (the lat-long layout and no --shadows: the
     * Phong samples read the lat-long map itself, and env lights for one set cast no shadow). */
    const bool estimator_unset = !sl_option_is_set(&o, SL_OPT_ESTIMATOR) || o.estimator == SL_ESTIMATOR_DEFAULT;
    sl_lobe_sampling ggx = {SL_ESTIMATOR_DEFAULT, SL_LOD_DEFAULT, false}; /* the frame's */
    if (estimator_unset && !sl_renderer_all_ggx(scene) && any_ggx(scene)) {
        ggx = (sl_lobe_sampling){
            .estimator = SL_ESTIMATOR_MICROFACET,
            .lod_rule = sl_option_is_set(&o, SL_OPT_LOD) && o.lod != SL_LOD_DEFAULT ? o.lod : SL_LOD_PDF,
            .distortion = sl_option_is_set(&o, SL_OPT_DISTORTION) ? o.distortion : true,
        };
        if (!sl_option_is_set(&o, SL_OPT_ENV_LIGHTS) && o.env_layout != SL_ENV_LAYOUT_OCT && !o.shadows) {
            sl_option_set_env_lights(&o, SL_ENV_LIGHTS_MAX);
            d->env_lights_worth = d->env_lights_ggx_only = true;
        }
    }
    if (estimator_unset && sl_renderer_all_ggx(scene)) {
        sl_option_set_estimator(&o, SL_ESTIMATOR_MICROFACET);
        if (!sl_option_is_set(&o, SL_OPT_LOD) || o.lod == SL_LOD_DEFAULT)
            sl_option_set_lod(&o, SL_LOD_PDF);
        if (!sl_option_is_set(&o, SL_OPT_DISTORTION))
            sl_option_set_distortion(&o, true);
        if (!sl_option_is_set(&o, SL_OPT_ENV_LIGHTS)) {
            sl_option_set_env_lights(&o, SL_ENV_LIGHTS_MAX);
            d->env_lights_worth = true; /* a ceiling: only the lights worth their cost */
        }
        if (!sl_option_is_set(&o, SL_OPT_SAMPLES)) /* the recipe's cost at its N */
            sl_option_set_samples(&o, SL_GGX_DEFAULT_SAMPLES);
    }
    if (!sl_option_values_check(&o, scene->path, err))
        return false;
    d->options = o;
    d->width = o.size[0];
    d->height = o.size[1];
    d->threads = o.threads; /* -j: every parallel region of the library takes it from here */
    d->tile_size = o.tile;
    d->plain_raster = o.plain;
    d->image_budget = (size_t)o.image_memory << 20;
    if (!d->irradiance_map_width)
        d->irradiance_map_width = 64;
    d->tonemap = (sl_tonemap_options){.exposure = o.exposure, .contrast = o.contrast, .exact_srgb = o.srgb};
    /* the lighting stage's switches: diffuse-only turns its specular term off, and either turns
     * the point lights off */
    d->lighting = (sl_lighting_options){
        .samples = o.samples,
        .lod_rule = o.lod,
        .distortion = o.distortion,
        .gterm = o.gterm,
        .estimator = o.estimator,
        .env_layout = o.env_layout,
        .irradiance = o.irradiance,
        .no_diffuse = o.specular_only,
        .no_specular = o.diffuse_only,
        .no_point_lights = o.no_lights || o.diffuse_only || o.specular_only,
        .env_intensity = o.env_intensity,
        .env_rotation_deg = scene->environment.rotation_deg,
        .rotate = o.rotate,
        .frame = (uint32_t)o.frame,
        .plain = o.plain,
        .env_lights = o.env_lights,
        .env_lights_worth = d->env_lights_worth,
        .ggx = ggx,
        .env_lights_ggx_only = d->env_lights_ggx_only,
    };
    return true;
}

bool sl_renderer_init(sl_renderer *r, const sl_scene *scene, const sl_render_desc *desc, sl_error *err)
{
    memset(r, 0, sizeof *r);
    r->scene = scene;
    r->desc = *desc;
    r->env_oct_built = -1;
    r->splitsum_built = -1;
    r->env_dist_built = -1;
    sl_render_desc *d = &r->desc;
    if (!sl_render_desc_resolve(d, scene, err))
        return false;

    double t0 = sl_now_seconds();
    if (!load_env(&r->env, scene->environment.hdr_path, d->image_budget, d->threads, &r->env_repairs, err))
        return false;
    /* The materials' textures, each image once, with its mips (raster/gbuffer_textured.h). */
    if (!sl_scene_textures_load(scene, d->image_budget, &r->textures, err))
        goto fail;
    r->timings.load_ms = (sl_now_seconds() - t0) * 1e3;
    if (!d->lighting.no_diffuse && !build_irradiance(r, err))
        goto fail;
    /* per environment: not in a frame's time */
    if (!update_env_lights(r, err) || !update_env_oct(r, err) || !update_splitsum(r, SL_ESTIMATOR_DEFAULT, err) ||
        !update_env_dist(r, SL_ESTIMATOR_DEFAULT, err))
        goto fail;
    r->uniforms = calloc(1, sizeof *r->uniforms);
    if (!r->uniforms) {
        sl_fail(err, SL_ERR_MEMORY, "out of memory for the lighting uniforms");
        goto fail;
    }
    r->raster = sl_raster_create(
        &(sl_raster_desc){.threads = d->threads, .tile_size = d->tile_size, .plain = d->plain_raster}, err);
    if (!r->raster || !sl_renderer_resize(r, d->width, d->height, err))
        goto fail;
    return true;
fail:
    sl_renderer_free(r);
    return false;
}

void sl_renderer_free(sl_renderer *r)
{
    sl_env_free(&r->env);
    sl_env_lights_free(&r->env_lights);
    sl_env_free(&r->env_oct);
    sl_env_free(&r->splitsum_phong);
    sl_env_free(&r->splitsum_ggx);
    free(r->splitsum_lut);
    sl_env_dist_free(&r->env_dist);
    if (r->have_irradiance)
        sl_irradiance_free(&r->irradiance);
    sl_shadow_free(&r->shadows);
    sl_shadow_suns_free(&r->suns);
    sl_shadow_sky_free(&r->sky);
    sl_raster_destroy(r->raster);
    sl_scene_textures_free(&r->textures);
    sl_gbuffer_free(&r->gbuffer);
    sl_gtao_scratch_free(&r->gtao_scratch);
    sl_reflection_scratch_free(&r->reflection_scratch);
    free(r->uniforms);
    sl_image_free(&r->radiance);
    sl_image_free(&r->display);
    free(r->tonemap_table);
    memset(r, 0, sizeof *r);
}

bool sl_renderer_set_environment(sl_renderer *r, const char *hdr_path, sl_error *err)
{
    sl_env env;
    sl_image_repairs repairs = {0};
    if (!load_env(&env, hdr_path, r->desc.image_budget, r->desc.threads, &repairs, err))
        return false;
    sl_env old = r->env;
    r->env = env;
    if (r->desc.lighting.no_diffuse) {
        /* Irradiance of the old environment is stale; it is rebuilt when diffuse comes back on. */
        if (r->have_irradiance)
            sl_irradiance_free(&r->irradiance);
        r->have_irradiance = false;
    } else {
        /* A loaded irradiance map belongs to the old environment: the new one gets the default. */
        sl_irradiance_method method = r->desc.lighting.irradiance;
        if (method == SL_IRRADIANCE_MAP)
            method = sl_irradiance_default();
        if (!sl_renderer_set_irradiance(r, method, err)) { /* keeps the old irradiance */
            sl_env_free(&r->env);
            r->env = old;
            return false;
        }
    }
    sl_env_free(&old);
    sl_env_lights_free(&r->env_lights); /* extracted from the old one: rebuilt on the next frame */
    r->env_lights_built = 0;
    r->env_lights_asked = 0;
    r->suns_built = 0; /* the old lights' directions: redrawn with them */
    r->sky_built = 0;  /* weighted by the old environment: likewise */
    sl_env_free(&r->env_oct); /* resampled from the old one: rebuilt on the next frame */
    r->env_oct_built = -1;
    sl_env_free(&r->splitsum_phong); /* prefiltered from the old one: likewise */
    sl_env_free(&r->splitsum_ggx);
    r->splitsum_built = -1;
    sl_env_dist_free(&r->env_dist); /* the old one's: likewise */
    r->env_dist_built = -1;
    r->env_repairs = repairs;
    return true;
}

bool sl_renderer_set_irradiance(sl_renderer *r, sl_irradiance_method method, sl_error *err)
{
    sl_irradiance_method old_method = r->desc.lighting.irradiance;
    sl_irradiance old = r->irradiance;
    bool had = r->have_irradiance;
    r->have_irradiance = false; /* build_irradiance must not free the old one yet */
    r->desc.lighting.irradiance = method;
    if (!build_irradiance(r, err)) {
        r->desc.lighting.irradiance = old_method;
        r->irradiance = old;
        r->have_irradiance = had;
        return false;
    }
    if (had)
        sl_irradiance_free(&old);
    return true;
}

bool sl_renderer_resize(sl_renderer *r, int width, int height, sl_error *err)
{
    if (r->gbuffer.texels && r->gbuffer.width == width && r->gbuffer.height == height)
        return true;
    sl_image_free(&r->radiance);
    sl_image_free(&r->display);
    if (!sl_gbuffer_resize(&r->gbuffer, width, height, err))
        return false;
    if (!sl_image_alloc(&r->radiance, width, height, 3, err) || !sl_image_alloc(&r->display, width, height, 3, err))
        return false;
    r->desc.width = width;
    r->desc.height = height;
    return true;
}

/* A shard's band: the whole frame is rasterized (so every texel in the band is what the unsharded
 * frame has), then the rows outside are emptied, all but the one beside each edge of the band,
 * which the lighting's sky plane fills the band's edge rows from (sl_lighting_planes); per-pixel
 * stages skip empty texels. */
static void keep_band(sl_gbuffer *gb, const int band[2])
{
    const sl_gbuffer_texel empty = {.depth = 1.0f};
    for (int y = 0; y < gb->height; y++) {
        int row = gb->height - 1 - y; /* image row 0 = top = G-buffer row height - 1 */
        if (row >= band[0] - 1 && row < band[1] + 1)
            continue;
        for (int x = 0; x < gb->width; x++)
            *sl_gbuffer_at(gb, x, y) = empty;
    }
}

/* The point lights' shadow maps, drawn once for the lights that cast (every light with
 * --shadows, else those whose "shadow" key is set): they depend on the scene's geometry and
 * lights alone, which a renderer's scene never changes. A scene where none casts draws none. */
static bool update_shadows(sl_renderer *r, sl_error *err)
{
    bool all = r->desc.options.shadows;
    int want = !sl_shadow_any(r->scene, all) ? 0 : all ? 2 : 1;
    if (want == 0 || want == r->shadows_built)
        return true;
    double t0 = sl_now_seconds();
    r->shadows_built = 0;
    if (!sl_shadow_build(&r->shadows, r->raster, r->scene, &r->textures, all, err))
        return false;
    r->shadows_built = want;
    r->timings.shadow_ms = (sl_now_seconds() - t0) * 1e3;
    return true;
}

/* The env lights' maps, with --shadows and env lights: drawn once per set of env lights and
 * environment rotation (the scene's geometry never changes). Without either, none is drawn and
 * the frame pays nothing. */
static bool sun_shadows_wanted(const sl_renderer *r)
{
    return r->desc.options.shadows && r->desc.lighting.env_lights > 0 && r->env_lights_built > 0 &&
           !r->desc.lighting.env_lights_ggx_only; /* one set's lights cast none */
}

static bool update_sun_shadows(sl_renderer *r, sl_error *err)
{
    float rotation = r->desc.lighting.env_rotation_deg;
    if (!sun_shadows_wanted(r) || (r->suns_built == r->env_lights_built && r->suns_rotation == rotation))
        return true;
    double t0 = sl_now_seconds();
    r->suns_built = 0;
    if (!sl_shadow_suns_build(&r->suns, r->raster, r->scene, &r->textures, &r->env_lights, rotation, err))
        return false;
    r->suns_built = r->env_lights_built;
    r->suns_rotation = rotation;
    r->timings.sun_shadow_ms = (sl_now_seconds() - t0) * 1e3;
    return true;
}

static const sl_shadow_suns *current_suns(const sl_renderer *r)
{
    bool current = sun_shadows_wanted(r) && r->suns_built == r->env_lights_built &&
                   r->suns_rotation == r->desc.lighting.env_rotation_deg;
    return current && r->suns.count > 0 ? &r->suns : NULL;
}

/* The sky visibility maps, with --sky-maps K: weighted by what the diffuse irradiance holds of
 * the environment (the residual when the env lights' maps take the lights out of it, else the
 * whole environment), drawn once per count, environment and rotation. */
static int sky_env_lights(const sl_renderer *r)
{
    return current_suns(r) ? r->env_lights_built : 0;
}

static bool update_sky(sl_renderer *r, sl_error *err)
{
    int want = r->desc.options.sky_maps;
    float rotation = r->desc.lighting.env_rotation_deg;
    if (want <= 0 || (r->sky_built == want && r->sky_env_lights == sky_env_lights(r) && r->sky_rotation == rotation))
        return true;
    double t0 = sl_now_seconds();
    r->sky_built = 0;
    int lights = sky_env_lights(r);
    const sl_env *env = lights > 0 ? &r->env_lights.residual : &r->env;
    if (!sl_shadow_sky_build(&r->sky, want, env, rotation, r->raster, r->scene, &r->textures, err))
        return false;
    r->sky_built = want;
    r->sky_env_lights = lights;
    r->sky_rotation = rotation;
    r->timings.sky_ms = (sl_now_seconds() - t0) * 1e3;
    return true;
}

static const sl_shadow_sky *current_sky(const sl_renderer *r)
{
    int want = r->desc.options.sky_maps;
    bool current = want > 0 && r->sky_built == want && r->sky_env_lights == sky_env_lights(r) &&
                   r->sky_rotation == r->desc.lighting.env_rotation_deg;
    return current ? &r->sky : NULL;
}

/* The maps the lighting reads: those of the options as they stand (NULL when no light casts). */
static const sl_shadow_maps *current_shadows(const sl_renderer *r)
{
    bool all = r->desc.options.shadows;
    int want = !sl_shadow_any(r->scene, all) ? 0 : all ? 2 : 1;
    return want != 0 && want == r->shadows_built ? &r->shadows : NULL;
}

bool sl_renderer_raster(sl_renderer *r, const sl_camera *cam, sl_error *err)
{
    double t0 = sl_now_seconds();
    if (!cam)
        cam = &r->scene->camera;
    float ao_radius = r->desc.options.ao_radius, reflection = r->desc.options.reflection_occlusion;
    sl_raster_keep_extra(r->raster, ao_radius > 0.0f);
    /* the reflection occlusion's rays test the drawn triangles' planes (reflection.h) */
    bool ok = sl_gbuffer_use_facet(&r->gbuffer, reflection > 0.0f, err) &&
              sl_raster_scene_program(r->raster, r->scene, &r->textures, r->desc.gbuffer_program, cam, &r->gbuffer,
                                      err);
    r->timings.raster_ms = (sl_now_seconds() - t0) * 1e3;
    /* occlusion reads the neighbours of every texel: before a shard drops the rows outside its band */
    double t1 = sl_now_seconds();
    if (ok && ao_radius > 0.0f) {
        ok = sl_gtao_apply(&r->gbuffer, cam, ao_radius, r->desc.threads, &r->gtao_scratch, err);
    } else { /* occlusion turned off (the viewer's O): the lighting reads no cone, the pass's planes go */
        free(r->gbuffer.cone);
        r->gbuffer.cone = NULL;
        sl_gtao_scratch_free(&r->gtao_scratch);
    }
    double t2 = sl_now_seconds();
    r->timings.ao_ms = (t2 - t1) * 1e3;
    if (ok && reflection > 0.0f) {
        ok = sl_reflection_apply(&r->gbuffer, cam, reflection, r->desc.threads, &r->reflection_scratch,
                                 &r->timings.reflection_lone, err);
    } else { /* turned off: the lighting reads no plane, the pass's planes go */
        free(r->gbuffer.reflection);
        r->gbuffer.reflection = NULL;
        sl_reflection_scratch_free(&r->reflection_scratch);
    }
    r->timings.reflection_ms = (sl_now_seconds() - t2) * 1e3;
    if (ok && r->desc.banded)
        keep_band(&r->gbuffer, r->desc.band);
    return ok;
}

bool sl_renderer_prepare_lighting(sl_renderer *r, const sl_camera *cam, sl_error *err)
{
    return sl_renderer_prepare_lighting_frame(r, cam, NULL, err);
}

bool sl_renderer_prepare_lighting_frame(sl_renderer *r, const sl_camera *cam, const sl_lighting_frame *frame,
                                        sl_error *err)
{
    if (!cam)
        cam = &r->scene->camera;
    sl_estimator estimator = frame ? frame->estimator : SL_ESTIMATOR_DEFAULT;
    /* the shadow maps here, after the raster and before the lighting, so that a G-buffer drawn
     * elsewhere (sl_renderer_light, --gbuffer) is lit with them too */
    if (!update_env_lights(r, err) || !update_env_oct(r, err) || !update_splitsum(r, estimator, err) ||
        !update_env_dist(r, estimator, err) || !update_shadows(r, err) || !update_sun_shadows(r, err) ||
        !update_sky(r, err))
        return false;
    sl_lighting_options options = r->desc.lighting; /* a copy: r->desc stays the caller's settings */
    if (r->env_lights_built == 0)
        options.env_lights = 0; /* a ceiling that left none worth their cost */
    if (frame) {
        options.samples = frame->samples;
        options.lod_samples = frame->lod_samples;
        options.rotate = frame->rotate;
        options.frame = frame->frame;
        if (frame->estimator != SL_ESTIMATOR_DEFAULT) { /* every pixel's (the viewer's moving frames) */
            options.estimator = frame->estimator;
            options.ggx.estimator = SL_ESTIMATOR_DEFAULT;
            options.env_lights_ggx_only = false;
        }
    }
    mat4 view_proj = sl_camera_view_proj(cam, r->gbuffer.width, r->gbuffer.height);
    sl_lighting_desc desc = {
        .options = options,
        .env = &r->env,
        .irradiance = r->have_irradiance ? &r->irradiance : NULL,
        .eye = cam->eye,
        .inv_view_proj = inverse(view_proj),
        .width = r->gbuffer.width,
        .height = r->gbuffer.height,
        .lights = r->scene->lights,
        .light_count = r->scene->light_count,
        .env_lights = r->env_lights_built > 0 ? &r->env_lights : NULL,
        .env_oct = r->env_oct_built >= 0 ? &r->env_oct : NULL,
        .splitsum_phong = sl_renderer_splitsum_chain(r, false),
        .splitsum_ggx = sl_renderer_splitsum_chain(r, true),
        .splitsum_lut = r->splitsum_lut,
        .env_dist = r->env_dist_built >= 0 ? &r->env_dist : NULL,
        .program = r->desc.lighting_program,
        .shadows = current_shadows(r),
        .env_shadows = current_suns(r),
        .sky = current_sky(r),
        .reflection_distance = r->desc.options.reflection_occlusion,
        .view = sl_gtao_view_of(cam, r->gbuffer.height),
    };
    return sl_lighting_uniforms_init(r->uniforms, &desc, err);
}

const sl_env *sl_renderer_splitsum_chain(const sl_renderer *r, bool ggx)
{
    if (r->splitsum_built < 0)
        return NULL;
    const sl_env *want = ggx ? &r->splitsum_ggx : &r->splitsum_phong;
    return want->level_count > 0 ? want : ggx ? &r->splitsum_phong : &r->splitsum_ggx;
}

bool sl_renderer_shade(sl_renderer *r, const sl_camera *cam, sl_error *err)
{
    return sl_renderer_shade_gbuffer(r, &r->gbuffer, cam, err);
}

/* Whether gb is one the renderer can light: filled, and of its size. */
static bool fits(const sl_renderer *r, const sl_gbuffer *gb, sl_error *err)
{
    if (!gb->texels || gb->width != r->gbuffer.width || gb->height != r->gbuffer.height)
        return sl_fail(err, SL_ERR_RANGE, "renderer: a %dx%d G-buffer to light, the renderer is %dx%d", gb->width,
                       gb->height, r->gbuffer.width, r->gbuffer.height);
    return true;
}

bool sl_renderer_shade_gbuffer(sl_renderer *r, const sl_gbuffer *gb, const sl_camera *cam, sl_error *err)
{
    if (!fits(r, gb, err))
        return false;
    double t0 = sl_now_seconds();
    if (!sl_renderer_prepare_lighting(r, cam, err))
        return false;
    memset(&r->lighting_stats, 0, sizeof r->lighting_stats);
    bool ok = sl_lighting_pass(r->uniforms, &r->lighting_stats, gb, &r->radiance, r->desc.threads, err);
    r->timings.shading_ms = (sl_now_seconds() - t0) * 1e3;
    return ok;
}

const sl_tonemap_table *sl_renderer_tonemap_table(sl_renderer *r, sl_error *err)
{
    /* the table costs about 0.2 ms to build: kept while the options stay (the viewer's keys
     * change them between frames) */
    const sl_tonemap_options *o = &r->desc.tonemap, *b = &r->tonemap_built;
    bool stale = !r->tonemap_table || o->exposure != b->exposure || o->contrast != b->contrast ||
                 o->exact_srgb != b->exact_srgb;
    if (!r->tonemap_table && !(r->tonemap_table = malloc(sizeof *r->tonemap_table))) {
        sl_fail(err, SL_ERR_MEMORY, "tone map: out of memory for its table");
        return NULL;
    }
    if (stale) {
        if (!sl_tonemap_prepare(o, r->tonemap_table, err)) {
            free(r->tonemap_table); /* not built: the next call starts again */
            r->tonemap_table = NULL;
            return NULL;
        }
        r->tonemap_built = *o;
    }
    return r->tonemap_table;
}

bool sl_renderer_tonemap(sl_renderer *r, sl_error *err)
{
    double t0 = sl_now_seconds();
    const sl_tonemap_table *tab = sl_renderer_tonemap_table(r, err);
    bool ok = tab && sl_tonemap_apply(tab, &r->radiance, &r->display, r->desc.threads, err);
    r->timings.tonemap_ms = (sl_now_seconds() - t0) * 1e3;
    return ok;
}

/* The tone map of the rows the lighting pass has just lit, on the thread that lit them. */
typedef struct band_tonemap {
    const sl_tonemap_table *table;
    const sl_image *radiance;
    sl_image *display;
    double *thread_ms; /* each thread's CPU time in the tone map */
} band_tonemap;

static void tonemap_band(void *ctx, int thread, int row0, int row1)
{
    band_tonemap *b = ctx;
    double t0 = sl_thread_cpu_seconds();
    sl_tonemap_rows(b->table, b->radiance, b->display, row0, row1);
    b->thread_ms[thread] += (sl_thread_cpu_seconds() - t0) * 1e3;
}

bool sl_renderer_shade_tonemap(sl_renderer *r, const sl_gbuffer *gb, const sl_camera *cam, sl_error *err)
{
    if (!fits(r, gb, err))
        return false;
    double t0 = sl_now_seconds();
    const sl_tonemap_table *table = sl_renderer_tonemap_table(r, err);
    if (!table || !sl_renderer_prepare_lighting(r, cam, err))
        return false;
    if (!r->radiance.data && !sl_image_alloc(&r->radiance, gb->width, gb->height, 3, err))
        return false;
    if (!sl_tonemap_target(&r->radiance, &r->display, err))
        return false;
    const int threads = sl_threads(r->desc.threads);
    band_tonemap band = {table, &r->radiance, &r->display, calloc((size_t)threads, sizeof(double))};
    if (!band.thread_ms)
        return sl_fail(err, SL_ERR_MEMORY, "renderer: no memory");
    memset(&r->lighting_stats, 0, sizeof r->lighting_stats);
    const sl_lighting_band_hook hook = {tonemap_band, &band};
    double cpu0 = sl_process_cpu_seconds(), pass0 = sl_now_seconds();
    bool ok = sl_lighting_pass_hooked(r->uniforms, &r->lighting_stats, gb, &r->radiance, threads, &hook, err);
    double pass_ms = (sl_now_seconds() - pass0) * 1e3, cpu_ms = (sl_process_cpu_seconds() - cpu0) * 1e3;
    /* The pass's wall time split between the two stages by the CPU time each used: a thread
     * descheduled in the middle of a band (another process on the machine) counts against
     * both in proportion, and the two still add up to the pass. */
    double tonemap_cpu_ms = 0.0;
    for (int i = 0; i < threads; i++)
        tonemap_cpu_ms += band.thread_ms[i];
    free(band.thread_ms);
    double share = cpu_ms > 0.0 ? tonemap_cpu_ms / cpu_ms : 0.0;
    r->timings.tonemap_ms = pass_ms * (share < 1.0 ? share : 1.0);
    r->timings.shading_ms = (sl_now_seconds() - t0) * 1e3 - r->timings.tonemap_ms;
    return ok;
}

bool sl_renderer_frame(sl_renderer *r, const sl_camera *cam, sl_error *err)
{
    return sl_renderer_raster(r, cam, err) && sl_renderer_shade_tonemap(r, &r->gbuffer, cam, err);
}
