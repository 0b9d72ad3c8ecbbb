/* lighting_uniforms.c - the host side of the lighting shader: options resolved to the option
 * table's defaults (core/options.h owns their names and limits), the std140 Hammersley block,
 * and the uniforms derived from a frame's description. softlight-gl's src/gl/lighting_pass.c
 * uploads these same uniforms to shaders/lighting.frag, field by field
 * (docs/architecture.md "Adding a uniform" lists every place a new one goes). */

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "../ibl/texture_lod.h"
#include "lighting.h"

/* Zero means the option table's default (core/options.h). */
sl_lighting_options sl_lighting_options_resolve(const sl_lighting_options *opt)
{
    sl_option_values def; /* the declaration's defaults (core/options.h) */
    sl_option_values_default(&def);
    sl_lighting_options r = opt ? *opt : (sl_lighting_options){0};
    if (r.samples == 0)
        r.samples = def.samples;
    if (r.lod_samples == 0)
        r.lod_samples = r.samples;
    if (r.lod_rule == SL_LOD_DEFAULT)
        r.lod_rule = def.lod;
    if (r.gterm == SL_GTERM_DEFAULT)
        r.gterm = def.gterm;
    if (r.env_layout == SL_ENV_LAYOUT_DEFAULT)
        r.env_layout = def.env_layout;
    if (r.estimator == SL_ESTIMATOR_DEFAULT)
        r.estimator = def.estimator;
    if (r.env_intensity == 0.0f)
        r.env_intensity = def.env_intensity;
    if (r.ggx.estimator == SL_ESTIMATOR_DEFAULT) /* the GGX set samples as the frame does */
        r.ggx = (sl_lobe_sampling){r.estimator, r.lod_rule, r.distortion};
    else if (r.ggx.lod_rule == SL_LOD_DEFAULT)
        r.ggx.lod_rule = def.lod;
    return r;
}

void sl_hammersley_pack_std140(const sl_hammersley *set, sl_hammersley_block *block)
{
    _Static_assert(sizeof(vec4) == 16, "vec4 must be 16 bytes for std140");
    _Static_assert(offsetof(sl_hammersley_block, hammersley) == 16, "std140: the vec4 array starts at 16");
    memset(block, 0, sizeof *block);
    block->N = (float)set->n;
    for (int k = 0; k < set->n; k++) {
        vec4 *h = &block->hammersley[k >> 1];
        if ((k & 1) == 0) {
            h->x = set->points[k].x;
            h->y = set->points[k].y;
        } else {
            h->z = set->points[k].x;
            h->w = set->points[k].y;
        }
    }
}

/* Each env light's visibility slot (envLightVisSlot), the lights grouped by map
 * (envLightGroups), and each map's glow (uEnvGlow): its direction in environment space and the
 * cap its lights spread over (sl_shadow_sun.spread) widened by SL_SHADOW_GLOW_DEG. */
static void group_env_lights(sl_lighting_uniforms *u)
{
    const sl_shadow_suns *m = u->envShadowMaps;
    for (int j = 0; j < SL_ENV_LIGHTS_MAX; j++) {
        int k = j < u->uEnvLightCount ? m->env_light_sun[j] : -2;
        u->envLightVisSlot[j] = (unsigned char)(k >= 0 ? k : k == -1 ? SL_SHADOW_SUN_MAX : SL_SHADOW_SUN_MAX + 1);
    }
    sl_env_light_groups_build(&u->envLightGroups, u->uEnvLightDir, u->uEnvLightRadiance, u->uEnvLightCount,
                              m->env_light_sun, m->count);
    u->uEnvGlowCount = SL_SHADOW_GLOW_DEG >= 0.0f ? m->count : 0;
    for (int k = 0; k < m->count; k++) {
        vec3 d = mat3_mul_vec3(u->uEnvRotation, m->maps[k].dir);
        float cap = fminf(atanf(m->maps[k].spread) + radians(SL_SHADOW_GLOW_DEG), SL_PI);
        u->uEnvGlow[k] = vec4(d.x, d.y, d.z, cosf(cap));
    }
}

bool sl_lighting_uniforms_init(sl_lighting_uniforms *u, const sl_lighting_desc *desc, sl_error *err)
{
    memset(u, 0, sizeof *u);
    sl_lighting_options o = sl_lighting_options_resolve(&desc->options);
    if (!desc->env || desc->env->level_count < 1)
        return sl_fail(err, SL_ERR_RANGE, "lighting: no environment map");
    if (o.samples < 1 || o.samples > SL_HAMMERSLEY_MAX)
        return sl_fail(err, SL_ERR_RANGE, "lighting: samples = %d, expected 1..%d", o.samples, SL_HAMMERSLEY_MAX);
    if (o.lod_samples < 1 || o.lod_samples > SL_HAMMERSLEY_MAX)
        return sl_fail(err, SL_ERR_RANGE, "lighting: lod samples = %d, expected 1..%d", o.lod_samples,
                       SL_HAMMERSLEY_MAX);
    if ((unsigned)o.lod_rule > SL_LOD_PDF || (unsigned)o.estimator > SL_ESTIMATOR_CV_MIS ||
        (unsigned)o.ggx.lod_rule > SL_LOD_PDF || (unsigned)o.ggx.estimator > SL_ESTIMATOR_CV_MIS ||
        (unsigned)o.gterm > SL_GTERM_ONE || (unsigned)o.env_layout > SL_ENV_LAYOUT_OCT)
        return sl_fail(err, SL_ERR_RANGE, "lighting: unknown lod rule, estimator, G term or environment layout");
    /* the two sets share the frame's Hammersley set, which mis and cvmis split into pairs */
    if (sl_estimator_reads_env_dist(o.estimator) != sl_estimator_reads_env_dist(o.ggx.estimator))
        return sl_fail(err, SL_ERR_RANGE, "lighting: the GGX set's estimator %s and the frame's %s draw different sample sets",
                       sl_estimator_name(o.ggx.estimator), sl_estimator_name(o.estimator));
    if (desc->light_count < 0 || desc->light_count > SL_LIGHTING_MAX_LIGHTS)
        return sl_fail(err, SL_ERR_RANGE, "lighting: %d point lights, at most %d", desc->light_count,
                       SL_LIGHTING_MAX_LIGHTS);
    if (desc->light_count > 0 && !desc->lights)
        return sl_fail(err, SL_ERR_RANGE, "lighting: light_count %d with no lights", desc->light_count);
    if (!o.no_diffuse) {
        if (!desc->irradiance)
            return sl_fail(err, SL_ERR_RANGE, "lighting: diffuse is on but no irradiance was given");
        if (desc->irradiance->method != o.irradiance)
            return sl_fail(err, SL_ERR_RANGE, "lighting: options ask for irradiance method %d, the irradiance is %d",
                           (int)o.irradiance, (int)desc->irradiance->method);
    }
    if (!isfinite(o.env_intensity) || o.env_intensity < 0.0f || !isfinite(o.env_rotation_deg))
        return sl_fail(err, SL_ERR_RANGE, "lighting: environment intensity %g / rotation %g not usable",
                       (double)o.env_intensity, (double)o.env_rotation_deg);
    if (desc->width < 1 || desc->height < 1)
        return sl_fail(err, SL_ERR_RANGE, "lighting: viewport %dx%d", desc->width, desc->height);
    if (o.env_lights < 0 || o.env_lights > SL_ENV_LIGHTS_MAX)
        return sl_fail(err, SL_ERR_RANGE, "lighting: %d env lights, expected 0..%d", o.env_lights, SL_ENV_LIGHTS_MAX);
    const sl_env_lights *el = o.env_lights > 0 ? desc->env_lights : NULL;
    if (o.env_lights > 0) {
        const sl_env_level *a = &desc->env->levels[0];
        const sl_env_level *b = el ? &el->residual.levels[0] : NULL;
        if (!el || el->residual.level_count != desc->env->level_count || b->width != a->width ||
            b->height != a->height)
            return sl_fail(err, SL_ERR_RANGE, "lighting: %d env lights asked for, but none extracted from this environment",
                           o.env_lights);
    }
    const bool oct = o.env_layout == SL_ENV_LAYOUT_OCT;
    /* the GGX set's env lights alone: the Phong set's samples read uEnv, the lat-long map itself,
     * and no chain or distribution made from the residual */
    if (o.env_lights_ggx_only &&
        (oct || sl_estimator_reads_splitsum(o.estimator) || sl_estimator_reads_splitsum(o.ggx.estimator) ||
         sl_estimator_reads_env_dist(o.estimator)))
        return sl_fail(err, SL_ERR_RANGE, "lighting: env lights for the GGX set alone need the lat-long layout and "
                                          "estimators that read neither the split sum's chains nor a distribution");
    if (oct && (!desc->env_oct || desc->env_oct->layout != SL_ENV_LAYOUT_OCT || desc->env_oct->level_count < 1))
        return sl_fail(err, SL_ERR_RANGE, "lighting: the octahedral layout asked for, but no octahedral chain given");
    const bool splitsum = sl_estimator_reads_splitsum(o.estimator) || sl_estimator_reads_splitsum(o.ggx.estimator);
    if (splitsum && (!desc->splitsum_phong || !desc->splitsum_ggx || !desc->splitsum_lut ||
                     desc->splitsum_phong->level_count != SL_PREFILTER_LEVELS ||
                     desc->splitsum_ggx->level_count != SL_PREFILTER_LEVELS))
        return sl_fail(err, SL_ERR_RANGE, "lighting: the %s estimator asked for, but no prefiltered chains of %d levels or no table given",
                       sl_estimator_name(sl_estimator_reads_splitsum(o.estimator) ? o.estimator : o.ggx.estimator),
                       SL_PREFILTER_LEVELS);

    const bool mis = sl_estimator_reads_env_dist(o.estimator); /* and so the GGX set's (above) */
    if (mis && oct)
        return sl_fail(err, SL_ERR_RANGE, "lighting: the %s estimator reads the lat-long level 0, not the octahedral layout",
                       sl_estimator_name(o.estimator));
    if (mis) {
        const sl_env *src = el ? &el->residual : desc->env;
        const sl_env_dist *d = desc->env_dist;
        if (!d || d->width < 1 || d->height < 1 || d->src_width != src->levels[0].width ||
            d->src_height != src->levels[0].height || (d->width << d->level) != d->src_width)
            return sl_fail(err, SL_ERR_RANGE, "lighting: the %s estimator asked for, but no environment distribution given",
                           sl_estimator_name(o.estimator));
    }

    /* MIS splits its N samples into pairs: one from the BRDF and one from the environment per
     * point of a set of (N + 1) / 2 (lighting.frag specular_mis) */
    sl_hammersley set;
    if (!sl_hammersley_build(&set, mis ? (o.samples + 1) / 2 : o.samples, err))
        return false;
    sl_hammersley_pack_std140(&set, &u->uHammersley);

    const sl_env_level *l0 = &desc->env->levels[0];
    u->uEnv = desc->env;
    u->uEnvResidual = oct ? desc->env_oct : el ? &el->residual : desc->env;
    u->uEnvLayout = (int)o.env_layout;
    _Static_assert(SL_ENV_LIGHTS_MAX % 16 == 0, "the batched path runs whole groups of 16 env lights");
    u->uEnvLightCount = el ? el->count : 0; /* the arrays stay zero past it (memset above) */
    u->uEnvLightAzimuth = el ? el->azimuth : 0.0f;
    for (int j = 0; j < u->uEnvLightCount; j++) {
        u->uEnvLightDir[j] = vec4(el->dir[j].x, el->dir[j].y, el->dir[j].z, 0.0f);
        u->uEnvLightRadiance[j] = vec4(el->radiance[j].x, el->radiance[j].y, el->radiance[j].z, el->spread[j]);
        u->uEnvLightTexel[j] = vec4(el->box[j].x, el->box[j].y, el->box[j].z, 0.0f);
        u->envLightX[j] = el->dir[j].x;
        u->envLightY[j] = el->dir[j].y;
        u->envLightZ[j] = el->dir[j].z;
        u->envLightR[j] = el->radiance[j].x;
        u->envLightG[j] = el->radiance[j].y;
        u->envLightB[j] = el->radiance[j].z;
    }
    /* The samples' chain sets the lod: the octahedral one has its own size and level count. */
    const sl_env_level *s0 = &u->uEnvResidual->levels[0];
    u->uEnvMaxLod = (float)(u->uEnvResidual->level_count - 1);
    /* In float, as a shader computing it would; log2 of a product of ints <= 2^28 is exact enough. */
    u->uLodBase = 0.5f * log2f((float)s0->width * (float)s0->height / (float)o.lod_samples);
    u->uSinThetaMin = sinf(SL_PI / (2.0f * (float)l0->height));
    u->uEnvLightSide = fmaxf(SL_PI / (float)l0->height, 2.0f * SL_PI / (float)l0->width);
    u->uEnvLightMeridian = SL_PI / (float)l0->height; /* theta1 - theta0 of every texel: the split's grid */
    /* world -> environment: rotate by -rotation about +Z (column-major). */
    float phi = radians(o.env_rotation_deg);
    float c = cosf(phi), s = sinf(phi);
    u->uEnvRotation = (mat3){{{c, -s, 0.0f}, {s, c, 0.0f}, {0.0f, 0.0f, 1.0f}}};
    u->uEnvIntensity = o.env_intensity;
    u->uIrradianceMethod = desc->irradiance ? (int)desc->irradiance->method : 0;
    if (desc->irradiance && !o.no_diffuse) {
        u->uIrradiance = desc->irradiance;
        memcpy(u->uSH, desc->irradiance->sh, sizeof u->uSH);
    }
    u->uEye = desc->eye;
    u->uInvViewProj = desc->inv_view_proj;
    u->uViewport = vec2((float)desc->width, (float)desc->height);
    u->uReflectionDistance = desc->reflection_distance;
    u->uViewForward = desc->view.forward;
    u->uViewRight = desc->view.right;
    u->uViewUp = desc->view.up;
    u->uPixelsPerUnit = desc->view.pixels_per_unit;
    u->uLightCount = desc->light_count;
    for (int i = 0; i < desc->light_count; i++) {
        u->uLightPosition[i] = desc->lights[i].position;
        u->uLightColor[i] = desc->lights[i].color;
        u->uLightIntensity[i] = desc->lights[i].intensity;
    }
    if (splitsum) {
        u->uSplitSumPhong = desc->splitsum_phong;
        u->uSplitSumGGX = desc->splitsum_ggx;
        u->uSplitSumLut = desc->splitsum_lut;
        u->uSplitSumMaxLod = (float)(desc->splitsum_phong->level_count - 1);
        u->uSplitSumExactLevel = sl_prefilter_first_exact(desc->splitsum_phong->level_count);
        sl_env_gather_init(&u->splitSumPhongGather, u->uSplitSumPhong);
        sl_env_gather_init(&u->splitSumGGXGather, u->uSplitSumGGX);
    }
    if (mis) {
        u->uEnvDist = desc->env_dist;
        u->uEnvDistShift = desc->env_dist->level;
    }
    u->uLodRule = (int)o.lod_rule;
    u->uDistortion = o.distortion ? 1 : 0;
    u->uGTerm = (int)o.gterm;
    u->uEstimator = (int)o.estimator;
    u->uLodRuleGGX = (int)o.ggx.lod_rule;
    u->uDistortionGGX = o.ggx.distortion ? 1 : 0;
    u->uEstimatorGGX = (int)o.ggx.estimator;
    for (int k = 0; k < 2; k++) { /* Phong, GGX */
        int e = k ? u->uEstimatorGGX : u->uEstimator;
        u->setSampling[k].estimator = e;
        u->setSampling[k].lod_rule = k ? u->uLodRuleGGX : u->uLodRule;
        u->setSampling[k].distortion = k ? u->uDistortionGGX : u->uDistortion;
        u->setSampling[k].about_n = e == SL_ESTIMATOR_MICROFACET || e == SL_ESTIMATOR_CV;
        const bool lights = u->uEnvLightCount > 0 && (k == 1 || !o.env_lights_ggx_only);
        u->setSampling[k].env_lights = lights;
        u->setSampling[k].whole_map = k == 0 && o.env_lights_ggx_only;
    }
    u->uEnvLightsGGXOnly = o.env_lights_ggx_only ? 1 : 0;
    u->uDiffuse = o.no_diffuse ? 0 : 1;
    u->uSpecular = o.no_specular ? 0 : 1;
    u->uPointLights = (o.no_point_lights || desc->light_count == 0) ? 0 : 1;
    u->uRotate = o.rotate ? 1 : 0;
    u->uFrame = o.frame;
    u->options = o;
    sl_env_gather_init(&u->envGather, u->uEnv);
    sl_env_gather_init(&u->residualGather, u->uEnvResidual);
    u->program = desc->program;
    u->shadowMaps = desc->shadows;
    u->envShadowMaps = u->uEnvLightCount > 0 && desc->env_shadows && desc->env_shadows->count > 0 &&
                               desc->env_shadows->env_light_count == u->uEnvLightCount
                           ? desc->env_shadows
                           : NULL;
    u->envLightShadows = u->envShadowMaps ? 1 : 0;
    if (u->envShadowMaps && o.env_lights_ggx_only)
        return sl_fail(err, SL_ERR_RANGE, "lighting: env lights for the GGX set alone cast no shadows");
    if (u->envShadowMaps)
        group_env_lights(u);
    u->skyMaps = desc->sky && desc->sky->count > 0 ? desc->sky : NULL;
    sl_lighting_frame_uniforms *f = &u->frame;
    f->eye = u->uEye;
    f->inv_view_proj = u->uInvViewProj;
    f->viewport = u->uViewport;
    f->env_rotation = u->uEnvRotation;
    f->env_intensity = u->uEnvIntensity;
    f->env_max_lod = u->uEnvMaxLod;
    f->samples = (int)u->uHammersley.N;
    f->rotate = u->uRotate;
    f->frame = u->uFrame;
    f->diffuse = u->uDiffuse;
    f->specular = u->uSpecular;
    f->point_lights = u->uPointLights;
    f->gterm = u->uGTerm;
    f->light_count = u->uLightCount;
    for (int i = 0; i < u->uLightCount; i++) {
        f->light_position[i] = u->uLightPosition[i];
        f->light_color[i] = u->uLightColor[i];
        f->light_intensity[i] = u->uLightIntensity[i];
    }
    f->env_light_count = u->uEnvLightCount;
    return true;
}

_Static_assert(SL_LIGHTING_MAX_POINT_LIGHTS == SL_LIGHTING_MAX_LIGHTS, "the public light arrays hold every light");

