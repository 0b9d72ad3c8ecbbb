/* shadow_pass.c - the shadow maps in OpenGL, the twin of src/shadow/shadow.c: the same maps drawn
 * by GL's rasterizer with shaders/shadow_depth.vert/.frag, for lighting.frag to read.
 *
 * Point lights: each light that casts (every one with --shadows, else those whose "shadow" key
 * is set, as sl_shadow_build chooses) gets six faces, +X, -X, +Y, -Y, +Z, -Z, drawn with the
 * view-projections softlight draws its own with (sl_shadow_face_view_proj: the guard band, the
 * face frames and the depth range are shadow.c's), into consecutive layers of one R32F
 * 2D-array texture, SL_SHADOW_CUBE_SIZE + 2 SL_SHADOW_GUARD texels a side, row 0 at the bottom
 * as in shadow.c, cleared to +inf (nothing drawn). The state is softlight's raster stage's:
 * depth test LESS against a 32-bit float depth cleared to 1, no culling (the maps see both faces
 * of every triangle), no blending.
 *
 * Env lights (with --shadows): the clusters, each map's frame, box and view-projection are
 * src/shadow's (sl_shadow_suns_frames, sl_shadow_sun_view_proj), so GL draws exactly the maps
 * softlight draws, one layer of an R32F 2D-array texture SL_SHADOW_SUN_SIZE texels a side per
 * cluster, with shadow_sun.frag keeping the depth along the map's axis as shadow.c does; the
 * same state, its own depth buffer.
 *
 * Sky visibility maps (with --sky-maps K): the directions, the cells' weights m_k and each map's
 * frame and box are src/shadow/sky.c's (sl_shadow_sky_frames, from the environment the renderer
 * weighted C's maps with), drawn as the env lights' are (shadow_sun.frag, sl_shadow_sun_view_proj)
 * into K layers of an R32F 2D-array texture SL_SKY_MAP_SIZE texels a side.
 *
 * Each kind of map is its own texture and table in slgl_shadows, bound to its own sampler of
 * lighting.frag (uShadowCubes with uShadowCubeLayer; uShadowSuns with uEnvLightSun and the
 * frames; uSkyMaps with the frames and weights), so one kind is drawn and read without touching
 * the others.
 *
 * A masked caster (src/raster/coverage.h, as softlight chooses it from the same textures) is drawn
 * with its coverage map on texture unit 0, through a sampler object in the map's state, and the
 * shaders discard where the mask cuts it away. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raster/coverage.h"
#include "shadow/shadow.h"
#include "shadow/sky.h"
#include "slgl.h"

/* An object's mask, found once for every map (raster/coverage.h, from the renderer's textures). */
typedef struct {
    bool masked;
    sl_coverage coverage;
} caster_mask;

/* What a map's draw reads: the scene, its meshes and, for the masked casters, each object's mask,
 * the textures' GL names and a sampler object. */
typedef struct {
    const sl_scene *scene;
    const slgl_mesh *meshes;
    const caster_mask *masks; /* one per object */
    const slgl_textures *textures;
    GLuint sampler;
} casters;

/* A depth program's uniform locations. */
typedef struct {
    GLint mvp, masked, coverage_st, coverage_channel, alpha_cutoff;
} depth_uniforms;

static depth_uniforms depth_uniforms_of(GLuint program)
{
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "uCoverageMap"), 0); /* texture unit 0 */
    return (depth_uniforms){glGetUniformLocation(program, "uModelViewProj"), glGetUniformLocation(program, "uMasked"),
                            glGetUniformLocation(program, "uCoverageST"),
                            glGetUniformLocation(program, "uCoverageChannel"),
                            glGetUniformLocation(program, "uAlphaCutoff")};
}

/* Object o's mask for a draw: its coverage map bound on unit 0 and the uniforms set, or
 * uMasked 0 for an opaque caster. */
static void bind_mask(const casters *c, const depth_uniforms *u, int o)
{
    const caster_mask *m = &c->masks[o];
    glUniform1i(u->masked, m->masked);
    if (!m->masked)
        return;
    const sl_coverage *cov = &m->coverage;
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, c->textures->names[cov->image]);
    slgl_sampler_set(c->sampler, &cov->map.state);
    glBindSampler(0, c->sampler);
    glUniform4f(u->coverage_st, cov->st.x, cov->st.y, cov->st.z, cov->st.w);
    glUniform1i(u->coverage_channel, cov->channel);
    glUniform1f(u->alpha_cutoff, cov->cutoff);
}

void slgl_shadows_destroy(slgl_shadows *s)
{
    if (s->cubes)
        glDeleteTextures(1, &s->cubes);
    if (s->depth)
        glDeleteRenderbuffers(1, &s->depth);
    if (s->fbo)
        glDeleteFramebuffers(1, &s->fbo);
    if (s->program)
        glDeleteProgram(s->program);
    if (s->suns)
        glDeleteTextures(1, &s->suns);
    if (s->sun_depth)
        glDeleteRenderbuffers(1, &s->sun_depth);
    if (s->sun_fbo)
        glDeleteFramebuffers(1, &s->sun_fbo);
    if (s->sun_program)
        glDeleteProgram(s->sun_program);
    if (s->sky)
        glDeleteTextures(1, &s->sky);
    if (s->sky_depth)
        glDeleteRenderbuffers(1, &s->sky_depth);
    if (s->sky_fbo)
        glDeleteFramebuffers(1, &s->sky_fbo);
    if (s->sky_program)
        glDeleteProgram(s->sky_program);
    if (s->mask_sampler)
        glDeleteSamplers(1, &s->mask_sampler);
    memset(s, 0, sizeof *s);
    for (int i = 0; i < SL_LIGHTING_MAX_LIGHTS; i++)
        s->cube_layer[i] = -1;
}

static const float far_away[4] = {INFINITY, INFINITY, INFINITY, INFINITY}; /* nothing drawn */

/* Layer `layer` of `texture` with view_proj: every object with a triangle. */
static void draw_face(GLuint texture, const casters *c, const depth_uniforms *u, int layer, mat4 view_proj)
{
    const sl_scene *scene = c->scene;
    const slgl_mesh *meshes = c->meshes;
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, texture, 0, layer);
    glClearBufferfv(GL_COLOR, 0, far_away);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    for (int o = 0; o < scene->object_count; o++) {
        const sl_object *obj = &scene->objects[o];
        const slgl_mesh *mesh = &meshes[obj->mesh];
        if (scene->meshes[obj->mesh].triangle_count == 0)
            continue;
        mat4 mvp = mat4_mul(view_proj, obj->model);
        glUniformMatrix4fv(u->mvp, 1, GL_FALSE, &mvp.c[0].x);
        bind_mask(c, u, o);
        glBindVertexArray(mesh->vao);
        glDrawElements(GL_TRIANGLES, mesh->index_count, GL_UNSIGNED_INT, NULL);
    }
}

/* An R32F 2D array of `layers` layers, side x side, and a framebuffer with a depth buffer of that
 * size drawing into its layer 0, in the raster stage's state; false when incomplete. */
static bool make_target(GLuint *texture, GLuint *fbo, GLuint *depth, int side, int layers, sl_error *err)
{
    glGenTextures(1, texture);
    glBindTexture(GL_TEXTURE_2D_ARRAY, *texture);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_R32F, side, side, layers, 0, GL_RED, GL_FLOAT, NULL);
    /* read with texelFetch only, but complete without mipmaps */
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glGenRenderbuffers(1, depth);
    glBindRenderbuffer(GL_RENDERBUFFER, *depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, side, side);
    glGenFramebuffers(1, fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, *depth);
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, *texture, 0, 0);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return sl_fail(err, SL_ERR_GL, "shadow maps: framebuffer incomplete (0x%04x)", (unsigned)status);
    glDrawBuffer(GL_COLOR_ATTACHMENT0);
    glViewport(0, 0, side, side);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    return true;
}

/* The point lights' cube maps. */
static bool draw_cubes(slgl_shadows *s, const casters *c, bool all, sl_error *err)
{
    const sl_scene *scene = c->scene;
    int casting = 0;
    for (int i = 0; i < scene->light_count && i < SL_LIGHTING_MAX_LIGHTS; i++)
        if (all || scene->lights[i].shadow)
            s->cube_layer[i] = 6 * casting++;
    if (casting == 0)
        return true;
    s->cube_count = casting;
    s->side = SL_SHADOW_CUBE_SIZE + 2 * SL_SHADOW_GUARD;
    if (!slgl_program_from_files("shadow_depth.vert", "shadow_depth.frag", &s->program, err) ||
        !make_target(&s->cubes, &s->fbo, &s->depth, s->side, 6 * casting, err))
        return false;
    depth_uniforms u = depth_uniforms_of(s->program);
    for (int i = 0; i < scene->light_count && i < SL_LIGHTING_MAX_LIGHTS; i++) {
        if (s->cube_layer[i] < 0)
            continue;
        for (int f = 0; f < 6; f++) {
            mat4 view_proj;
            if (sl_shadow_face_view_proj(scene, scene->lights[i].position, f, &view_proj)) {
                draw_face(s->cubes, c, &u, s->cube_layer[i] + f, view_proj);
            } else { /* no geometry: every depth stays +inf */
                glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, s->cubes, 0, s->cube_layer[i] + f);
                glClearBufferfv(GL_COLOR, 0, far_away);
            }
        }
    }
    return true;
}

/* Orthographic maps[0 .. count - 1] (their frames set; `geometry`: the scene has some), one layer
 * each of a fresh R32F 2D array `size` texels a side, with shadow_sun.frag keeping the depth
 * along each map's axis. */
static bool draw_ortho(GLuint *program, GLuint *texture, GLuint *fbo, GLuint *depth, const sl_shadow_sun *maps,
                       int count, int size, bool geometry, const casters *c, sl_error *err)
{
    if (!slgl_program_from_files("shadow_depth.vert", "shadow_sun.frag", program, err) ||
        !make_target(texture, fbo, depth, size, count, err))
        return false;
    depth_uniforms u = depth_uniforms_of(*program);
    GLint origin_loc = glGetUniformLocation(*program, "uDepthOrigin");
    GLint extent_loc = glGetUniformLocation(*program, "uDepthExtent");
    for (int k = 0; k < count; k++) {
        const sl_shadow_sun *map = &maps[k];
        if (geometry) {
            glUniform1f(origin_loc, map->z0);
            glUniform1f(extent_loc, map->sz);
            draw_face(*texture, c, &u, k, sl_shadow_sun_view_proj(map));
        } else { /* no geometry: every depth stays +inf */
            glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, *texture, 0, k);
            glClearBufferfv(GL_COLOR, 0, far_away);
        }
    }
    return true;
}

/* The env lights' orthographic maps, one layer per cluster. */
static bool draw_suns(slgl_shadows *s, const casters *c, const sl_env_lights *env_lights, float env_rotation_deg,
                      sl_error *err)
{
    sl_shadow_suns *m = &s->sun_frames;
    bool geometry = sl_shadow_suns_frames(m, c->scene, env_lights, env_rotation_deg);
    if (m->count == 0)
        return true;
    return draw_ortho(&s->sun_program, &s->suns, &s->sun_fbo, &s->sun_depth, m->maps, m->count, SL_SHADOW_SUN_SIZE,
                      geometry, c, err);
}

/* The sky visibility maps, one layer per direction. */
static bool draw_sky(slgl_shadows *s, const casters *c, int count, const sl_env *env, float env_rotation_deg,
                     sl_error *err)
{
    if (count < 1 || count > SL_SKY_MAPS_MAX)
        return sl_fail(err, SL_ERR_RANGE, "sky maps: %d directions (1..%d)", count, SL_SKY_MAPS_MAX);
    sl_shadow_sky *m = &s->sky_frames;
    bool geometry = sl_shadow_sky_frames(m, count, env, env_rotation_deg, c->scene);
    return draw_ortho(&s->sky_program, &s->sky, &s->sky_fbo, &s->sky_depth, m->maps, m->count, SL_SKY_MAP_SIZE,
                      geometry, c, err);
}

bool slgl_shadows_draw(slgl_shadows *s, const sl_scene *scene, const slgl_mesh *meshes,
                       const sl_scene_textures *sl_textures, const slgl_textures *textures, bool all,
                       const sl_env_lights *env_lights, float env_rotation_deg, int sky_maps, const sl_env *sky_env,
                       sl_error *err)
{
    slgl_shadows_destroy(s);
    caster_mask *masks = calloc(scene->object_count > 0 ? (size_t)scene->object_count : 1, sizeof *masks);
    if (!masks)
        return sl_fail(err, SL_ERR_MEMORY, "shadow maps: out of memory for %d objects", scene->object_count);
    for (int o = 0; o < scene->object_count; o++) {
        caster_mask *m = &masks[o];
        m->masked = textures &&
                    sl_coverage_of(&scene->materials[scene->objects[o].material], sl_textures, &m->coverage) &&
                    m->coverage.image < textures->count;
    }
    glGenSamplers(1, &s->mask_sampler);
    const casters c = {scene, meshes, masks, textures, s->mask_sampler};
    bool ok = draw_cubes(s, &c, all, err) &&
              (!all || !env_lights || draw_suns(s, &c, env_lights, env_rotation_deg, err)) &&
              (sky_maps <= 0 || draw_sky(s, &c, sky_maps, sky_env, env_rotation_deg, err));
    free(masks);
    glBindSampler(0, 0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindVertexArray(0);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return ok && slgl_check("drawing the shadow maps", err);
}
