/* lighting_pass.c - the lighting pass in OpenGL: shaders/lighting.frag over a full-screen triangle,
 * reading the G-buffer textures, into an RGBA32F target read back as linear radiance.
 *
 * Every uniform comes from softlight's own sl_lighting_uniforms (src/shading/lighting.h), which
 * names its fields after the GLSL uniforms: the same Hammersley block bytes, the same SH9
 * coefficients, lod base, rotation and inverse view-projection. So the C port and the GLSL differ
 * only in how they evaluate the shader -- float ordering, transcendental precision, and the
 * sampler's own filtering arithmetic -- which is what the GL comparison measures.
 *
 * The environment goes up as GL_RGB32F with the image's top row (v = 0) as the texture's first row,
 * so t = v as in the C textureLod, and glGenerateMipmap builds the chain (2x2 box averages for the
 * power-of-two maps softlight ships, the same as sl_env_build). An octahedral chain (--env-layout
 * oct, src/ibl/env_oct.c) goes up level by level as softlight built it (its filter weighs by solid
 * angle, which glGenerateMipmap does not), and the GLSL filters it with texelFetch.
 *
 * One program per combination of options and scene features (lighting.frag "Specialization"),
 * compiled the first time a draw asks for it: the C pass runs only the code a scene needs, and
 * llvmpipe, which runs every branch some lane of a SIMD batch might take, must not pay for the
 * rest either, or the comparison flatters softlight. $SL_GL_GENERAL (any value) compiles the file
 * without defines instead: the general shader, every option a uniform (measurements, docs/gl.md).
 *
 * The shadow maps are GL's own (shadow_pass.c), bound beside the G-buffer; the uniforms'
 * shadowMaps and envShadowMaps (softlight's) only say which lights must have one, and a draw
 * where the two disagree fails rather than compare a shadowed C frame with an unshadowed GL
 * one. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "slgl.h"

/* Texture units of the samplers. */
enum {
    UNIT_POSITION,
    UNIT_NORMAL,
    UNIT_KD,
    UNIT_KS_ALPHA,
    UNIT_DEPTH,
    UNIT_ENV,
    UNIT_IRRADIANCE,
    UNIT_ENV_RESIDUAL,
    UNIT_EXTRA, /* the G-buffer's occlusion + emission target, when it has one */
    UNIT_SPLITSUM_PHONG,
    UNIT_SPLITSUM_GGX,
    UNIT_SPLITSUM_LUT,
    UNIT_ENV_DIST,
    UNIT_ENV_DIST_MARGINAL,
    UNIT_CONE, /* the occlusion pass's visibility cone, when it ran */
    UNIT_COUNT,
    UNIT_SHADOW_CUBES = UNIT_COUNT, /* 2D arrays (the shadow maps), each bound on its own */
    UNIT_SHADOW_SUNS,
    UNIT_SHADOW_SKY, /* 17: unit numbers run to GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS - 1 (48 or more
                        in OpenGL 3.3; checked in slgl_lighting_create); what is bounded by 16 there
                        is the fragment stage's active samplers, which a specialized program with
                        every kind of map keeps under (the general shader has 18: llvmpipe allows 32) */
    UNIT_END
};
#define HAMMERSLEY_BINDING 1

static GLuint upload_latlong(const sl_env_level *level, bool mipmaps)
{
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    /* row 0 of the level (top, v = 0) is the first row GL reads: t = v */
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, level->width, level->height, 0, GL_RGB, GL_FLOAT, level->texels);
    if (mipmaps) {
        glGenerateMipmap(GL_TEXTURE_2D);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    } else {
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return tex;
}

/* Every level of an octahedral chain as built (texelFetch reads it; no GL filtering). */
static GLuint upload_levels(const sl_env *env)
{
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (int l = 0; l < env->level_count; l++)
        glTexImage2D(GL_TEXTURE_2D, l, GL_RGB32F, env->levels[l].width, env->levels[l].height, 0, GL_RGB, GL_FLOAT,
                     env->levels[l].texels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, env->level_count - 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return tex;
}

/* A split-sum chain as softlight prefiltered it: every level, filtered by GL (trilinear, as the
 * C textureLod), REPEAT in s and CLAMP in t like the environment. */
static GLuint upload_prefiltered(const sl_env *env)
{
    GLuint tex = upload_levels(env);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    return tex;
}

bool slgl_lighting_set_splitsum(slgl_lighting *l, const sl_env *phong, const sl_env *ggx, const sl_splitsum_lut *lut,
                                sl_error *err)
{
    GLuint old[3] = {l->splitsum_phong, l->splitsum_ggx, l->splitsum_lut};
    glDeleteTextures(3, old);
    l->splitsum_phong = l->splitsum_ggx = l->splitsum_lut = 0;
    l->splitsum_levels = 0;
    if (!phong || !ggx || !lut)
        return true;
    l->splitsum_phong = upload_prefiltered(phong);
    l->splitsum_ggx = upload_prefiltered(ggx);
    l->splitsum_levels = phong->level_count;
    /* the table's A, B, t with the control variate's beta as .w */
    enum { TEXELS = SL_SPLITSUM_SETS * SL_SPLITSUM_LUT_SIZE * SL_SPLITSUM_LUT_SIZE };
    float *rgba = malloc(sizeof(float) * 4 * TEXELS);
    if (!rgba)
        return sl_fail(err, SL_ERR_MEMORY, "gl: no memory for the split-sum table");
    for (int i = 0; i < TEXELS; i++) {
        rgba[4 * i] = lut->texels[i].x;
        rgba[4 * i + 1] = lut->texels[i].y;
        rgba[4 * i + 2] = lut->texels[i].z;
        rgba[4 * i + 3] = lut->beta[i];
    }
    glGenTextures(1, &l->splitsum_lut);
    glBindTexture(GL_TEXTURE_2D, l->splitsum_lut);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, SL_SPLITSUM_LUT_SIZE, SL_SPLITSUM_SETS * SL_SPLITSUM_LUT_SIZE, 0, GL_RGBA,
                 GL_FLOAT, rgba);
    free(rgba);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return slgl_check("uploading the split-sum chains and table", err);
}

/* One float image for texelFetch: NEAREST, CLAMP, no mips. */
static GLuint upload_float(GLenum internal, GLenum format, int width, int height, const float *data)
{
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, width, height, 0, format, GL_FLOAT, data);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return tex;
}

/* The MIS estimator's distribution (src/ibl/env_dist.h) as lighting.frag reads it: uEnvDist, RG32F
 * W x H of (conditional CDF, density), and uEnvDistMarginal, R32F H x 1. Uploaded once per
 * distribution. */
static bool upload_env_dist(slgl_lighting *l, const sl_env_dist *d, sl_error *err)
{
    GLuint old[2] = {l->env_dist, l->env_dist_marginal};
    glDeleteTextures(2, old);
    l->env_dist = l->env_dist_marginal = 0;
    l->env_dist_source = NULL;
    size_t n = (size_t)d->width * (size_t)d->height;
    float *rg = malloc(2 * n * sizeof *rg);
    if (!rg)
        return sl_fail(err, SL_ERR_MEMORY, "no memory to upload the environment distribution");
    for (size_t k = 0; k < n; k++) {
        rg[2 * k] = d->cdf[k];
        rg[2 * k + 1] = d->density[k];
    }
    l->env_dist = upload_float(GL_RG32F, GL_RG, d->width, d->height, rg);
    free(rg);
    l->env_dist_marginal = upload_float(GL_R32F, GL_RED, d->height, 1, d->marginal);
    l->env_dist_source = d;
    l->env_dist_cdf = d->cdf;
    return slgl_check("uploading the environment distribution", err);
}

/* The key of the program for these uniforms on this G-buffer. */
static slgl_lighting_key program_key(const slgl_lighting *l, const slgl_gbuffer *g, const sl_lighting_uniforms *u)
{
    slgl_lighting_key k;
    memset(&k, 0, sizeof k);
    k.lod_rule = u->uLodRule;
    k.distortion = u->uDistortion;
    k.gterm = u->uGTerm;
    k.estimator = u->uEstimator;
    k.lod_rule_ggx = u->uLodRuleGGX;
    k.distortion_ggx = u->uDistortionGGX;
    k.estimator_ggx = u->uEstimatorGGX;
    k.env_lights_ggx_only = u->uEnvLightsGGXOnly;
    k.diffuse = u->uDiffuse;
    k.specular = u->uSpecular;
    k.rotate = u->uRotate;
    k.env_layout = u->uEnvLayout;
    k.irradiance_method = u->uIrradianceMethod;
    k.point_lights = u->uPointLights != 0 && u->uLightCount > 0;
    k.has_extra = g->extra != 0;
    k.env_lights = u->uEnvLightCount > 0;
    k.phong = l->phong;
    k.ggx = l->ggx;
    k.shadow_cubes = k.point_lights && l->shadows && l->shadows->cube_count > 0;
    k.shadow_suns = k.env_lights && l->shadows && l->shadows->sun_frames.count > 0;
    k.sky_maps = l->shadows && l->shadows->sky_frames.count > 0;
    return k;
}

/* Compile lighting.frag for `k` (or the general shader) and bind its uniform block. */
static bool build_program(const slgl_lighting *l, const slgl_lighting_key *k, GLuint *program, sl_error *err)
{
    char defines[768];
    snprintf(defines, sizeof defines,
             "#define SL_SPECIALIZED 1\n#define SL_LOD_RULE %d\n#define SL_DISTORTION %d\n#define SL_GTERM %d\n"
             "#define SL_ESTIMATOR %d\n#define SL_LOD_RULE_GGX %d\n#define SL_DISTORTION_GGX %d\n"
             "#define SL_ESTIMATOR_GGX %d\n#define SL_ENV_LIGHTS_GGX_ONLY %d\n#define SL_DIFFUSE %d\n"
             "#define SL_SPECULAR %d\n#define SL_ROTATE %d\n"
             "#define SL_ENV_LAYOUT %d\n#define SL_IRRADIANCE_METHOD %d\n#define SL_POINT_LIGHTS %d\n"
             "#define SL_HAS_EXTRA %d\n#define SL_ENV_LIGHTS %d\n#define SL_PHONG %d\n#define SL_GGX %d\n"
             "#define SL_SHADOW_CUBES %d\n#define SL_SHADOW_SUNS %d\n#define SL_SKY_MAPS %d",
             k->lod_rule, k->distortion, k->gterm, k->estimator, k->lod_rule_ggx, k->distortion_ggx, k->estimator_ggx,
             k->env_lights_ggx_only, k->diffuse, k->specular, k->rotate, k->env_layout,
             k->irradiance_method, k->point_lights, k->has_extra, k->env_lights, k->phong, k->ggx, k->shadow_cubes,
             k->shadow_suns, k->sky_maps);
    if (l->user_frag ? !slgl_program_user_lighting("full-screen triangle", slgl_fullscreen_vert, l->user_frag,
                                                   l->general ? NULL : defines, program, err)
                     : !slgl_program_from_sources("full-screen triangle", slgl_fullscreen_vert, "lighting.frag",
                                                  l->general ? NULL : defines, program, err))
        return false;
    /* The specification's recipe: bind the buffer to a binding point, then the block to it. */
    GLuint block = glGetUniformBlockIndex(*program, "HammersleyBlock");
    GLint block_size = 0;
    if (block != GL_INVALID_INDEX)
        glGetActiveUniformBlockiv(*program, block, GL_UNIFORM_BLOCK_DATA_SIZE, &block_size);
    /* a program without samples (split sum, or no specular term) may have no block at all */
    if (block_size > (GLint)sizeof(sl_hammersley_block)) {
        glDeleteProgram(*program);
        *program = 0;
        return sl_fail(err, SL_ERR_GL, "lighting.frag: HammersleyBlock is %d bytes, the C block %zu", block_size,
                       sizeof(sl_hammersley_block));
    }
    if (block != GL_INVALID_INDEX)
        glUniformBlockBinding(*program, block, HAMMERSLEY_BINDING);
    return slgl_check("building a lighting program", err);
}

/* The program for `k`: one already built, or a new one in the next slot (the oldest goes). */
static bool program_for(slgl_lighting *l, const slgl_lighting_key *k, GLuint *program, sl_error *err)
{
    for (int i = 0; i < l->program_count; i++)
        if (l->general || !memcmp(&l->keys[i], k, sizeof *k)) {
            *program = l->programs[i];
            return true;
        }
    int slot = l->program_next;
    if (l->programs[slot])
        glDeleteProgram(l->programs[slot]);
    l->programs[slot] = 0;
    if (!build_program(l, k, &l->programs[slot], err))
        return false;
    l->keys[slot] = *k;
    l->program_next = (slot + 1) % SLGL_LIGHTING_PROGRAMS;
    if (l->program_count < SLGL_LIGHTING_PROGRAMS)
        l->program_count++;
    *program = l->programs[slot];
    return true;
}

void slgl_lighting_set_shadows(slgl_lighting *l, const slgl_shadows *s) { l->shadows = s; }

void slgl_lighting_set_lobes(slgl_lighting *l, bool phong, bool ggx)
{
    l->phong = phong || !ggx; /* a program for no set at all would be GGX's (lighting.frag sl_lobe_is_ggx) */
    l->ggx = ggx;
}

bool slgl_lighting_create(slgl_lighting *l, int width, int height, sl_error *err)
{
    memset(l, 0, sizeof *l);
    l->width = width;
    l->height = height;
    l->phong = l->ggx = true;
    const char *general = getenv("SL_GL_GENERAL");
    l->general = general != NULL && general[0] != '\0';
    glGenVertexArrays(1, &l->vao); /* core profile draws need a bound VAO, even an empty one */
    glGenTextures(1, &l->color);
    glBindTexture(GL_TEXTURE_2D, l->color);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glGenFramebuffers(1, &l->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, l->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, l->color, 0);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        slgl_lighting_destroy(l);
        return sl_fail(err, SL_ERR_GL, "lighting framebuffer incomplete (0x%04x)", (unsigned)status);
    }
    glGenBuffers(1, &l->ubo);
    GLint units = 0;
    glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &units);
    if (units < UNIT_END) {
        slgl_lighting_destroy(l);
        return sl_fail(err, SL_ERR_GL, "lighting: %d texture units, lighting.frag's samplers need %d", (int)units,
                       (int)UNIT_END);
    }
    return slgl_check("creating the lighting pass", err);
}

void slgl_lighting_destroy(slgl_lighting *l)
{
    GLuint textures[9] = {l->color,          l->env,          l->irradiance_map, l->env_residual,
                          l->splitsum_phong, l->splitsum_ggx, l->splitsum_lut,   l->env_dist,
                          l->env_dist_marginal};
    glDeleteTextures(9, textures);
    if (l->ubo)
        glDeleteBuffers(1, &l->ubo);
    if (l->fbo)
        glDeleteFramebuffers(1, &l->fbo);
    if (l->vao)
        glDeleteVertexArrays(1, &l->vao);
    for (int i = 0; i < SLGL_LIGHTING_PROGRAMS; i++)
        if (l->programs[i])
            glDeleteProgram(l->programs[i]);
    memset(l, 0, sizeof *l);
}

bool slgl_lighting_set_environment(slgl_lighting *l, const sl_env *env, const sl_env *residual,
                                   const sl_irradiance *irr, sl_error *err)
{
    if (l->env)
        glDeleteTextures(1, &l->env);
    if (l->env_residual)
        glDeleteTextures(1, &l->env_residual);
    l->env_dist_source = NULL; /* the next MIS draw uploads the new environment's */
    l->residual_oct = residual && residual->layout == SL_ENV_LAYOUT_OCT;
    l->env_residual = !residual ? 0 : l->residual_oct ? upload_levels(residual) : upload_latlong(&residual->levels[0], true);
    l->residual_levels = residual ? residual->level_count : 0;
    if (l->irradiance_map)
        glDeleteTextures(1, &l->irradiance_map);
    l->env = upload_latlong(&env->levels[0], true);
    GLint levels = 0;
    for (int w = env->levels[0].width, h = env->levels[0].height; w > 0 || h > 0; w /= 2, h /= 2)
        levels++;
    l->env_levels = levels;
    if (!residual)
        l->residual_levels = levels;
    l->irradiance_map = 0;
    if (irr && irr->method != SL_IRRADIANCE_SH9 && irr->map.level_count > 0) {
        l->irradiance_map = upload_latlong(&irr->map.levels[0], false);
        /* the pole-free layouts clamp their coordinates to the outer texel centres (REPEAT
         * would not be read either); CLAMP_TO_EDGE says so */
        if (irr->method == SL_IRRADIANCE_OCT || irr->method == SL_IRRADIANCE_DP)
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    }
    return slgl_check("uploading the environment", err);
}

static GLint loc(GLuint program, const char *name) { return glGetUniformLocation(program, name); }

/* The uniforms of one kind of orthographic map: its frames' axis, right, up, box and depth. */
typedef struct {
    const char *axis, *right, *up, *box, *depth;
} ortho_uniforms;

/* Orthographic maps[0 .. count - 1]'s frames and boxes, as src/shadow has them (the lookup's
 * arithmetic starts from the C lookup's numbers): the env lights' and the sky maps'. */
static void upload_ortho_frames(GLuint p, ortho_uniforms names, const sl_shadow_sun *maps, int count)
{
    enum { MAX = SL_SKY_MAPS_MAX > SL_SHADOW_SUN_MAX ? SL_SKY_MAPS_MAX : SL_SHADOW_SUN_MAX };
    if (count <= 0)
        return;
    vec3 axis[MAX], right[MAX], up[MAX];
    vec4 box[MAX];
    vec2 depth[MAX];
    for (int k = 0; k < count; k++) {
        axis[k] = maps[k].axis;
        right[k] = maps[k].right;
        up[k] = maps[k].up;
        box[k] = vec4(maps[k].x0, maps[k].y0, maps[k].sx, maps[k].sy);
        depth[k] = vec2(maps[k].sz, maps[k].texel);
    }
    glUniform3fv(loc(p, names.axis), count, &axis[0].x);
    glUniform3fv(loc(p, names.right), count, &right[0].x);
    glUniform3fv(loc(p, names.up), count, &up[0].x);
    glUniform4fv(loc(p, names.box), count, &box[0].x);
    glUniform2fv(loc(p, names.depth), count, &depth[0].x);
}

/* Copy sl_lighting_uniforms into the program, field by field, name by name; the shadow maps'
 * samplers and layer tables from GL's own maps (uniforms' shadowMaps are softlight's). */
static void set_uniforms(GLuint p, const sl_lighting_uniforms *u, const slgl_shadows *shadows)
{
    /* a name the program's specialization made a constant, or left unused, has location -1,
     * which glUniform ignores */
    glUniform1i(loc(p, "uPosition"), UNIT_POSITION);
    glUniform1i(loc(p, "uNormal"), UNIT_NORMAL);
    glUniform1i(loc(p, "uKd"), UNIT_KD);
    glUniform1i(loc(p, "uKsAlpha"), UNIT_KS_ALPHA);
    glUniform1i(loc(p, "uDepth"), UNIT_DEPTH);
    glUniform1i(loc(p, "uExtra"), UNIT_EXTRA);
    glUniform1i(loc(p, "uCone"), UNIT_CONE);
    glUniform1i(loc(p, "uEnv"), UNIT_ENV);
    glUniform1i(loc(p, "uIrradianceMap"), UNIT_IRRADIANCE);
    glUniform1i(loc(p, "uEnvResidual"), UNIT_ENV_RESIDUAL);
    glUniform1i(loc(p, "uSplitSumPhong"), UNIT_SPLITSUM_PHONG);
    glUniform1i(loc(p, "uSplitSumGGX"), UNIT_SPLITSUM_GGX);
    glUniform1i(loc(p, "uSplitSumLut"), UNIT_SPLITSUM_LUT);
    glUniform1f(loc(p, "uSplitSumMaxLod"), u->uSplitSumMaxLod);
    glUniform1i(loc(p, "uSplitSumExactLevel"), u->uSplitSumExactLevel);
    if (u->uSplitSumLut) { /* each chain level's kernel 1 / Z, set s level k at s SL_PREFILTER_LEVELS + k */
        float norm[SL_SPLITSUM_SETS * SL_PREFILTER_LEVELS];
        for (int set = 0; set < SL_SPLITSUM_SETS; set++)
            for (int k = 0; k < SL_PREFILTER_LEVELS; k++)
                norm[set * SL_PREFILTER_LEVELS + k] = u->uSplitSumLut->kernels[set][k].inv_norm;
        glUniform1fv(loc(p, "uSplitSumKernelNorm"), SL_SPLITSUM_SETS * SL_PREFILTER_LEVELS, norm);
    }
    glUniform1i(loc(p, "uEnvDist"), UNIT_ENV_DIST);
    glUniform1i(loc(p, "uEnvDistMarginal"), UNIT_ENV_DIST_MARGINAL);
    glUniform1i(loc(p, "uEnvDistShift"), u->uEnvDistShift);
    glUniform1i(loc(p, "uEnvLightCount"), u->uEnvLightCount);
    if (u->uEnvLightCount > 0) {
        glUniform4fv(loc(p, "uEnvLightDir"), u->uEnvLightCount, &u->uEnvLightDir[0].x);
        glUniform4fv(loc(p, "uEnvLightRadiance"), u->uEnvLightCount, &u->uEnvLightRadiance[0].x);
        glUniform4fv(loc(p, "uEnvLightTexel"), u->uEnvLightCount, &u->uEnvLightTexel[0].x);
    }
    glUniform1f(loc(p, "uEnvLightSide"), u->uEnvLightSide);
    glUniform1f(loc(p, "uEnvLightMeridian"), u->uEnvLightMeridian);
    glUniform1f(loc(p, "uEnvLightAzimuth"), u->uEnvLightAzimuth);
    glUniform1f(loc(p, "uEnvMaxLod"), u->uEnvMaxLod);
    glUniform1i(loc(p, "uEnvLayout"), u->uEnvLayout);
    glUniform1f(loc(p, "uLodBase"), u->uLodBase);
    glUniform1f(loc(p, "uSinThetaMin"), u->uSinThetaMin);
    glUniformMatrix3fv(loc(p, "uEnvRotation"), 1, GL_FALSE, &u->uEnvRotation.c[0].x);
    glUniform1f(loc(p, "uEnvIntensity"), u->uEnvIntensity);
    glUniform1i(loc(p, "uIrradianceMethod"), u->uIrradianceMethod);
    glUniform3fv(loc(p, "uSH"), 9, &u->uSH[0].x);
    glUniform3f(loc(p, "uEye"), u->uEye.x, u->uEye.y, u->uEye.z);
    glUniformMatrix4fv(loc(p, "uInvViewProj"), 1, GL_FALSE, &u->uInvViewProj.c[0].x);
    glUniform2f(loc(p, "uViewport"), u->uViewport.x, u->uViewport.y);
    glUniform1f(loc(p, "uReflectionDistance"), u->uReflectionDistance);
    glUniform3f(loc(p, "uViewForward"), u->uViewForward.x, u->uViewForward.y, u->uViewForward.z);
    glUniform3f(loc(p, "uViewRight"), u->uViewRight.x, u->uViewRight.y, u->uViewRight.z);
    glUniform3f(loc(p, "uViewUp"), u->uViewUp.x, u->uViewUp.y, u->uViewUp.z);
    glUniform1f(loc(p, "uPixelsPerUnit"), u->uPixelsPerUnit);
    glUniform1i(loc(p, "uLightCount"), u->uLightCount);
    if (u->uLightCount > 0) {
        glUniform3fv(loc(p, "uLightPosition"), u->uLightCount, &u->uLightPosition[0].x);
        glUniform3fv(loc(p, "uLightColor"), u->uLightCount, &u->uLightColor[0].x);
        glUniform1fv(loc(p, "uLightIntensity"), u->uLightCount, u->uLightIntensity);
    }
    glUniform1i(loc(p, "uLodRule"), u->uLodRule);
    glUniform1i(loc(p, "uDistortion"), u->uDistortion);
    glUniform1i(loc(p, "uGTerm"), u->uGTerm);
    glUniform1i(loc(p, "uEstimator"), u->uEstimator);
    glUniform1i(loc(p, "uLodRuleGGX"), u->uLodRuleGGX);
    glUniform1i(loc(p, "uDistortionGGX"), u->uDistortionGGX);
    glUniform1i(loc(p, "uEstimatorGGX"), u->uEstimatorGGX);
    glUniform1i(loc(p, "uEnvLightsGGXOnly"), u->uEnvLightsGGXOnly);
    glUniform1i(loc(p, "uDiffuse"), u->uDiffuse);
    glUniform1i(loc(p, "uSpecular"), u->uSpecular);
    glUniform1i(loc(p, "uPointLights"), u->uPointLights);
    glUniform1i(loc(p, "uRotate"), u->uRotate);
    glUniform1ui(loc(p, "uFrame"), u->uFrame);
    int none[SL_LIGHTING_MAX_LIGHTS];
    for (int i = 0; i < SL_LIGHTING_MAX_LIGHTS; i++)
        none[i] = -1;
    glUniform1i(loc(p, "uShadowCubes"), UNIT_SHADOW_CUBES);
    glUniform1iv(loc(p, "uShadowCubeLayer"), SL_LIGHTING_MAX_LIGHTS, shadows ? shadows->cube_layer : none);
    /* the env lights' maps: src/shadow's frames as they are, so the lookup's arithmetic starts
     * from the C lookup's numbers */
    const sl_shadow_suns *suns = shadows && u->uEnvLightCount > 0 ? &shadows->sun_frames : NULL;
    int count = suns ? suns->count : 0;
    glUniform1i(loc(p, "uShadowSuns"), UNIT_SHADOW_SUNS);
    glUniform1i(loc(p, "uShadowSunCount"), count);
    upload_ortho_frames(p,
                        (ortho_uniforms){"uShadowSunAxis", "uShadowSunRight", "uShadowSunUp", "uShadowSunBox",
                                         "uShadowSunDepth"},
                        suns ? suns->maps : NULL, count);
    int sun_of[SL_ENV_LIGHTS_MAX];
    for (int j = 0; j < SL_ENV_LIGHTS_MAX; j++)
        sun_of[j] = suns && j < suns->env_light_count ? suns->env_light_sun[j] : -1;
    glUniform1iv(loc(p, "uEnvLightSun"), SL_ENV_LIGHTS_MAX, sun_of);
    /* the maps' glows: the C uniforms' (a GL draw shadows the lights where and only where the C
     * side has maps: shadows_agree) */
    glUniform1i(loc(p, "uEnvGlowCount"), count > 0 ? u->uEnvGlowCount : 0);
    glUniform4fv(loc(p, "uEnvGlow"), SL_SHADOW_SUN_MAX, &u->uEnvGlow[0].x);
    /* the sky visibility maps: src/shadow/sky.c's frames, weights and cells' sites as they are */
    const sl_shadow_sky *sky = shadows && u->skyMaps ? &shadows->sky_frames : NULL;
    int sky_count = sky ? sky->count : 0;
    glUniform1i(loc(p, "uSkyMaps"), UNIT_SHADOW_SKY);
    glUniform1i(loc(p, "uSkyMapCount"), sky_count);
    upload_ortho_frames(p, (ortho_uniforms){"uSkyMapAxis", "uSkyMapRight", "uSkyMapUp", "uSkyMapBox", "uSkyMapDepth"},
                        sky ? sky->maps : NULL, sky_count);
    if (sky_count > 0) {
        glUniform3fv(loc(p, "uSkyMapWeight"), sky_count, &sky->weight[0].x);
        glUniform3fv(loc(p, "uSkyCellSite"), sky_count, &sky->site[0].x);
        glUniform1i(loc(p, "uSkyCellSkySites"), sky->sky_sites);
        glUniform1f(loc(p, "uSkyCellAngle"), sky->cell_angle);
    }
}

/* The uniforms' lights read maps (softlight's, sl_lighting_uniforms.shadowMaps) where and only
 * where GL drew some: a draw never leaves out a shadow the C side has. */
static bool shadows_agree(const slgl_lighting *l, const sl_lighting_uniforms *u, sl_error *err)
{
    for (int i = 0; i < u->uLightCount; i++) {
        const sl_shadow_maps *c = u->shadowMaps;
        bool c_casts = c && i < c->count && c->cubes[i].casts;
        bool gl_casts = l->shadows && l->shadows->cube_count > 0 && l->shadows->cube_layer[i] >= 0;
        if (c_casts != gl_casts)
            return sl_fail(err, SL_ERR_RANGE, "lighting: light %d casts shadows in softlight's uniforms%s, in GL's "
                           "maps%s", i, c_casts ? "" : " not", gl_casts ? "" : " not");
    }
    /* the env lights: the same clusters (both from sl_shadow_suns_frames' clustering) */
    const sl_shadow_suns *c = u->envLightShadows != 0 ? u->envShadowMaps : NULL;
    const sl_shadow_suns *gl = l->shadows && u->uEnvLightCount > 0 && l->shadows->sun_frames.count > 0
                                   ? &l->shadows->sun_frames
                                   : NULL;
    if (!c != !gl)
        return sl_fail(err, SL_ERR_RANGE, "lighting: the env lights cast shadows in softlight's uniforms%s, in GL's "
                       "maps%s", c ? "" : " not", gl ? "" : " not");
    if (c && (c->count != gl->count || c->env_light_count != gl->env_light_count ||
              memcmp(c->env_light_sun, gl->env_light_sun, (size_t)c->env_light_count) != 0))
        return sl_fail(err, SL_ERR_RANGE, "lighting: softlight's env lights make %d shadow maps, GL's %d, or in "
                       "other clusters", c->count, gl->count);
    /* the sky maps: as many, with the same weights (both from sl_shadow_sky_frames, of the same
     * environment) */
    const sl_shadow_sky *csky = u->skyMaps;
    const sl_shadow_sky *glsky = l->shadows && l->shadows->sky_frames.count > 0 ? &l->shadows->sky_frames : NULL;
    int ccount = csky ? csky->count : 0, glcount = glsky ? glsky->count : 0;
    if (ccount != glcount || (ccount > 0 && memcmp(csky->weight, glsky->weight, (size_t)ccount * sizeof *csky->weight)))
        return sl_fail(err, SL_ERR_RANGE, "lighting: softlight's uniforms have %d sky visibility maps, GL's %d, or "
                       "with other weights", ccount, glcount);
    return true;
}

bool slgl_lighting_draw(slgl_lighting *l, const slgl_gbuffer *g, const sl_lighting_uniforms *u, sl_error *err)
{
    if (g->width != l->width || g->height != l->height)
        return sl_fail(err, SL_ERR_RANGE, "lighting: the G-buffer is %dx%d, the target %dx%d", g->width, g->height,
                       l->width, l->height);
    if (!l->env)
        return sl_fail(err, SL_ERR_RANGE, "lighting: no environment uploaded");
    /* The GL chain must be the one the uniforms clamp the lod to. */
    if ((int)u->uEnvMaxLod != l->residual_levels - 1)
        return sl_fail(err, SL_ERR_RANGE, "lighting: softlight's chain has %d levels, GL's %d",
                       (int)u->uEnvMaxLod + 1, l->residual_levels);
    if ((u->uEnvLayout == SL_ENV_LAYOUT_OCT) != l->residual_oct)
        return sl_fail(err, SL_ERR_RANGE, "lighting: the uniforms ask for the %s layout, GL holds the other",
                       sl_env_layout_name((sl_env_layout)u->uEnvLayout));
    glBindBuffer(GL_UNIFORM_BUFFER, l->ubo);
    glBufferData(GL_UNIFORM_BUFFER, (GLsizeiptr)sizeof u->uHammersley, &u->uHammersley, GL_STATIC_DRAW);
    glBindBufferBase(GL_UNIFORM_BUFFER, HAMMERSLEY_BINDING, l->ubo);

    /* Without env lights or the octahedral layout the samples read the environment itself. */
    if ((u->uEnvLightCount > 0 || l->residual_oct) != (l->env_residual != 0))
        return sl_fail(err, SL_ERR_RANGE, "lighting: %d env lights but %s residual environment uploaded",
                       u->uEnvLightCount, l->env_residual ? "a" : "no");
    GLuint residual = l->env_residual ? l->env_residual : l->env;
    if ((sl_estimator_reads_splitsum((sl_estimator)u->uEstimator) ||
         sl_estimator_reads_splitsum((sl_estimator)u->uEstimatorGGX)) &&
        (!l->splitsum_lut || (int)u->uSplitSumMaxLod != l->splitsum_levels - 1))
        return sl_fail(err, SL_ERR_RANGE, "lighting: split sum asked for, but its chains of %d levels are not uploaded",
                       (int)u->uSplitSumMaxLod + 1);
    if (!shadows_agree(l, u, err))
        return false;
    if (sl_estimator_reads_env_dist((sl_estimator)u->uEstimator) &&
        (u->uEnvDist != l->env_dist_source || u->uEnvDist->cdf != l->env_dist_cdf) &&
        !upload_env_dist(l, u->uEnvDist, err))
        return false;
    GLuint units[UNIT_COUNT] = {g->position,       g->normal,        g->kd,          g->ks_alpha,
                                g->depth,          l->env,           l->irradiance_map, residual,
                                g->extra,          l->splitsum_phong, l->splitsum_ggx, l->splitsum_lut,
                                l->env_dist,       l->env_dist_marginal, g->cone};
    slgl_lighting_key key = program_key(l, g, u);
    GLuint program;
    if (!program_for(l, &key, &program, err))
        return false;
    glUseProgram(program);
    glUniform1i(loc(program, "uHasExtra"), g->extra != 0);
    glUniform1i(loc(program, "uHasCone"), g->cone != 0);
    glUniform1i(loc(program, "uHasFacet"), g->facet);
    for (int i = 0; i < UNIT_COUNT; i++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)i);
        glBindTexture(GL_TEXTURE_2D, units[i]);
    }
    glActiveTexture(GL_TEXTURE0 + UNIT_SHADOW_CUBES);
    glBindTexture(GL_TEXTURE_2D_ARRAY, l->shadows ? l->shadows->cubes : 0);
    glActiveTexture(GL_TEXTURE0 + UNIT_SHADOW_SUNS);
    glBindTexture(GL_TEXTURE_2D_ARRAY, l->shadows ? l->shadows->suns : 0);
    glActiveTexture(GL_TEXTURE0 + UNIT_SHADOW_SKY);
    glBindTexture(GL_TEXTURE_2D_ARRAY, l->shadows ? l->shadows->sky : 0);
    /* The depth texture is sampled as a value, not compared. */
    glActiveTexture(GL_TEXTURE0 + UNIT_DEPTH);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    glActiveTexture(GL_TEXTURE0);

    glBindFramebuffer(GL_FRAMEBUFFER, l->fbo);
    glViewport(0, 0, l->width, l->height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    set_uniforms(program, u, l->shadows);
    glBindVertexArray(l->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    return slgl_check("the lighting pass", err);
}

bool slgl_lighting_read(const slgl_lighting *l, sl_image *radiance, long *repaired, sl_error *err)
{
    size_t n = (size_t)l->width * (size_t)l->height;
    float *rgba = malloc(n * 4 * sizeof *rgba);
    if (!rgba)
        return sl_fail(err, SL_ERR_MEMORY, "no memory to read back %dx%d radiance", l->width, l->height);
    if (!radiance->data && !sl_image_alloc(radiance, l->width, l->height, 3, err)) {
        free(rgba);
        return false;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, l->fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, l->width, l->height, GL_RGBA, GL_FLOAT, rgba);
    /* glReadPixels' row 0 is the bottom; sl_image's row 0 is the top. a = 0 marks a pixel the
     * built-in found non-finite and wrote as 0 (lighting.frag, "Output"); a user's shader owns its
     * alpha, so its non-finite pixels are found here and written as magenta, as softlight's pass
     * writes a C program's (docs/lighting-programs.md). */
    long bad = 0;
    for (int y = 0; y < l->height; y++) {
        const float *src = rgba + (size_t)(l->height - 1 - y) * (size_t)l->width * 4;
        for (int x = 0; x < l->width; x++) {
            float *dst = sl_image_pixel(radiance, x, y);
            memcpy(dst, src + 4 * x, 3 * sizeof *dst);
            if (!l->user_frag) {
                bad += src[4 * x + 3] == 0.0f;
            } else if (!isfinite(dst[0]) || !isfinite(dst[1]) || !isfinite(dst[2])) {
                dst[0] = dst[2] = 1.0f;
                dst[1] = 0.0f;
                bad++;
            }
        }
    }
    free(rgba);
    if (repaired)
        *repaired = bad;
    return slgl_check("reading the radiance back", err);
}
