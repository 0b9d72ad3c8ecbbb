/* gbuffer_pass.c - the G-buffer pass in OpenGL: every object drawn with shaders/gbuffer.vert/.frag
 * (or, when its material has texture maps, shaders/gbuffer_textured.vert/.frag) into four RGBA32F
 * colour targets and a 32-bit float depth target.
 *
 * It reproduces softlight's raster stage state for state, so that coverage and depth can be compared
 * bit for bit: the uniforms come from the same C function (sl_gbuffer_uniforms_init) with the same
 * view-projection (sl_camera_view_proj), the viewport is the whole target, depth test LESS against
 * a clear depth of 1, no culling (softlight's sl_raster_scene draws both faces), no blending, no
 * multisampling. Targets: 0 position (w = 1 where drawn), 1 normal, 2 kd, 3 ks + alpha, the .w of
 * 1 and 2 the facet normal (octahedral: facet_code; softlight's sl_gbuffer.facet); cleared to
 * 0 like sl_gbuffer_clear; for a scene with occlusion or emission, 4 the extra channels (cleared to
 * "none", written by both programs: gbuffer.frag writes "none" where the C program leaves its plane
 * to the depth-tag resolve, src/raster/gbuffer.h). Row 0 is the bottom row in both.
 *
 * Textured materials: the uniforms come from sl_gbuffer_tex_uniforms_init, map i's texture is
 * bound to unit i with a sampler object set from sl_gbuffer_map_sampler, and the mesh's texture
 * coordinates and tangents are attributes 2 and 3. One GL program serves masked and unmasked
 * materials (uMaps says whether to discard); softlight picks its early- or late-depth variant
 * by the same bit, and the results agree since only a discard tells the two apart.
 *
 * --gbuffer-shader: the user's fragment shader, linked with gbuffer_textured.vert, draws every
 * object with the textured program's uniforms (the C side: src/raster/gbuffer_user.c). A shader
 * without oExtra leaves the extra target as cleared ("none"), as the C side's default; its .w
 * channels are its own, so the lighting rebuilds the geometric normal from the positions there
 * (uHasFacet 0), where softlight's rasterizer writes the facet plane for any program. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raster/raster.h"
#include "slgl.h"

static GLuint make_target(GLenum internal, GLenum format, int width, int height)
{
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, width, height, 0, format, GL_FLOAT, NULL);
    /* read with texelFetch, but a complete texture needs a filter that does not want mipmaps */
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return tex;
}

bool slgl_gbuffer_create(slgl_gbuffer *g, int width, int height, bool extra, sl_error *err)
{
    memset(g, 0, sizeof *g);
    g->width = width;
    g->height = height;
    if (!slgl_program_from_files("gbuffer.vert", "gbuffer.frag", &g->program, err))
        return false;
    if (!slgl_program_from_files("gbuffer_textured.vert", "gbuffer_textured.frag", &g->tex_program, err)) {
        slgl_gbuffer_destroy(g);
        return false;
    }
    glGenSamplers(SL_MAP_COUNT, g->samplers);
    int count = extra ? 5 : 4;
    GLuint targets[5] = {0};
    for (int i = 0; i < count; i++)
        targets[i] = make_target(GL_RGBA32F, GL_RGBA, width, height);
    g->position = targets[0];
    g->normal = targets[1];
    g->kd = targets[2];
    g->ks_alpha = targets[3];
    g->extra = targets[4];
    g->depth = make_target(GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, width, height);
    glGenFramebuffers(1, &g->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    for (int i = 0; i < count; i++)
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i, GL_TEXTURE_2D, targets[i], 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, g->depth, 0);
    static const GLenum draw_buffers[5] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                           GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4};
    glDrawBuffers(count, draw_buffers);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        slgl_gbuffer_destroy(g);
        return sl_fail(err, SL_ERR_GL, "G-buffer framebuffer incomplete (0x%04x): RGBA32F or DEPTH32F unsupported?",
                       (unsigned)status);
    }
    return slgl_check("creating the G-buffer", err);
}

void slgl_gbuffer_destroy(slgl_gbuffer *g)
{
    GLuint textures[7] = {g->position, g->normal, g->kd, g->ks_alpha, g->depth, g->extra, g->cone_files};
    glDeleteTextures(7, textures);
    if (g->fbo)
        glDeleteFramebuffers(1, &g->fbo);
    if (g->program)
        glDeleteProgram(g->program);
    if (g->tex_program)
        glDeleteProgram(g->tex_program);
    if (g->samplers[0])
        glDeleteSamplers(SL_MAP_COUNT, g->samplers);
    if (g->user_program)
        glDeleteProgram(g->user_program);
    memset(g, 0, sizeof *g);
}

bool slgl_gbuffer_use_fragment(slgl_gbuffer *g, const char *frag_path, sl_error *err)
{
    if (!slgl_program_with_fragment_file("gbuffer_textured.vert", frag_path, &g->user_program, err))
        return false;
    g->user_extra = glGetFragDataLocation(g->user_program, "oExtra") == 4;
    return slgl_check("linking the --gbuffer-shader program", err);
}

bool slgl_meshes_upload(const sl_scene *scene, slgl_mesh *meshes, sl_error *err)
{
    for (int i = 0; i < scene->mesh_count; i++) {
        const sl_mesh *m = &scene->meshes[i];
        slgl_mesh *out = &meshes[i];
        memset(out, 0, sizeof *out);
        glGenVertexArrays(1, &out->vao);
        glBindVertexArray(out->vao);
        /* vec3 is three packed floats, so the arrays go up as they are */
        glGenBuffers(1, &out->vbo_position);
        glBindBuffer(GL_ARRAY_BUFFER, out->vbo_position);
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)m->vertex_count * sizeof(vec3)), m->positions,
                     GL_STATIC_DRAW);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(vec3), NULL);
        glEnableVertexAttribArray(0);
        glGenBuffers(1, &out->vbo_normal);
        glBindBuffer(GL_ARRAY_BUFFER, out->vbo_normal);
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)m->vertex_count * sizeof(vec3)), m->normals,
                     GL_STATIC_DRAW);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(vec3), NULL);
        glEnableVertexAttribArray(1);
        if (m->texcoords) { /* tangents come with them (scene.h) */
            glGenBuffers(1, &out->vbo_texcoord);
            glBindBuffer(GL_ARRAY_BUFFER, out->vbo_texcoord);
            glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)m->vertex_count * sizeof(vec2)), m->texcoords,
                         GL_STATIC_DRAW);
            glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(vec2), NULL);
            glEnableVertexAttribArray(2);
        }
        if (m->tangents) {
            glGenBuffers(1, &out->vbo_tangent);
            glBindBuffer(GL_ARRAY_BUFFER, out->vbo_tangent);
            glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)m->vertex_count * sizeof(vec4)), m->tangents,
                         GL_STATIC_DRAW);
            glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, sizeof(vec4), NULL);
            glEnableVertexAttribArray(3);
        }
        glGenBuffers(1, &out->ibo);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, out->ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)((size_t)m->triangle_count * 3 * sizeof(uint32_t)),
                     m->indices, GL_STATIC_DRAW);
        out->index_count = m->triangle_count * 3;
        glBindVertexArray(0);
    }
    return slgl_check("uploading meshes", err);
}

void slgl_meshes_destroy(slgl_mesh *meshes, int count)
{
    for (int i = 0; i < count; i++) {
        slgl_mesh *m = &meshes[i];
        GLuint buffers[5] = {m->vbo_position, m->vbo_normal, m->vbo_texcoord, m->vbo_tangent, m->ibo};
        glDeleteBuffers(5, buffers);
        if (m->vao)
            glDeleteVertexArrays(1, &m->vao);
        memset(m, 0, sizeof *m);
    }
}

/* Uniform locations of gbuffer.vert/.frag. */
typedef struct {
    GLint model, view_proj, normal, kd, ks, alpha;
} plain_locations;

/* Uniform locations of gbuffer_textured.vert/.frag; the samplers are set to their units once. */
typedef struct {
    GLint model, view_proj, normal, model3, kd, ks, alpha, roughness, maps, cutoff, metallic, occlusion, emissive,
        st[SL_MAP_COUNT];
} tex_locations;

static tex_locations tex_locations_get(GLuint p)
{
    static const char *const samplers[SL_MAP_COUNT] = {"uKdMap",   "uKsMap",   "uAlphaMap",
                                                       "uNormalMap", "uMaskMap", "uMetallicRoughnessMap",
                                                       "uOcclusionMap", "uEmissiveMap"};
    static const char *const st[SL_MAP_COUNT] = {"uKdMapST",   "uKsMapST",   "uAlphaMapST",
                                                 "uNormalMapST", "uMaskMapST", "uMetallicRoughnessMapST",
                                                 "uOcclusionMapST", "uEmissiveMapST"};
    tex_locations l = {
        .model = glGetUniformLocation(p, "uModel"),
        .view_proj = glGetUniformLocation(p, "uViewProj"),
        .normal = glGetUniformLocation(p, "uNormalMatrix"),
        .model3 = glGetUniformLocation(p, "uModel3"),
        .kd = glGetUniformLocation(p, "uKd"),
        .ks = glGetUniformLocation(p, "uKs"),
        .alpha = glGetUniformLocation(p, "uAlpha"),
        .roughness = glGetUniformLocation(p, "uRoughness"),
        .maps = glGetUniformLocation(p, "uMaps"),
        .cutoff = glGetUniformLocation(p, "uAlphaCutoff"),
        .metallic = glGetUniformLocation(p, "uMetallic"),
        .occlusion = glGetUniformLocation(p, "uOcclusionStrength"),
        .emissive = glGetUniformLocation(p, "uEmissive"),
    };
    glUseProgram(p);
    for (int slot = 0; slot < SL_MAP_COUNT; slot++) {
        l.st[slot] = glGetUniformLocation(p, st[slot]);
        glUniform1i(glGetUniformLocation(p, samplers[slot]), slot); /* map slot i on texture unit i */
    }
    return l;
}

/* One textured object: softlight's uniform struct (sl_gbuffer_tex_uniforms_init, so both draws see
 * the same matrices, constants and map bits), each bound map's texture and sampler state. */
static void draw_textured(const slgl_gbuffer *g, const tex_locations *l, const sl_object *o, const sl_material *m,
                          const sl_scene_textures *sl_textures, const slgl_textures *textures, mat4 view_proj)
{
    sl_gbuffer_tex_uniforms u;
    sl_gbuffer_tex_uniforms_init(&u, o->model, view_proj, m, sl_textures);
    const vec4 st[SL_MAP_COUNT] = {u.uKdMapST,   u.uKsMapST,   u.uAlphaMapST,
                                   u.uNormalMapST, u.uMaskMapST, u.uMetallicRoughnessMapST,
                                   u.uOcclusionMapST, u.uEmissiveMapST};
    glUniformMatrix4fv(l->model, 1, GL_FALSE, &u.uModel.c[0].x);
    glUniformMatrix4fv(l->view_proj, 1, GL_FALSE, &u.uViewProj.c[0].x);
    glUniformMatrix3fv(l->normal, 1, GL_FALSE, &u.uNormalMatrix.c[0].x);
    glUniformMatrix3fv(l->model3, 1, GL_FALSE, &u.uModel3.c[0].x);
    glUniform3f(l->kd, u.uKd.x, u.uKd.y, u.uKd.z);
    glUniform3f(l->ks, u.uKs.x, u.uKs.y, u.uKs.z);
    glUniform1f(l->alpha, u.uAlpha);
    glUniform1f(l->roughness, u.uRoughness);
    glUniform1i(l->maps, u.uMaps);
    glUniform1f(l->cutoff, u.uAlphaCutoff);
    glUniform1f(l->metallic, u.uMetallic);
    glUniform1f(l->occlusion, u.uOcclusionStrength);
    glUniform3f(l->emissive, u.uEmissive.x, u.uEmissive.y, u.uEmissive.z);
    for (int slot = 0; slot < SL_MAP_COUNT; slot++) {
        glUniform4f(l->st[slot], st[slot].x, st[slot].y, st[slot].z, st[slot].w);
        glActiveTexture(GL_TEXTURE0 + (GLenum)slot);
        if (!(u.uMaps & (1 << slot))) { /* unbound: the shader does not sample it */
            glBindTexture(GL_TEXTURE_2D, 0);
            continue;
        }
        const sl_material_map *map = &m->maps[slot];
        glBindTexture(GL_TEXTURE_2D, textures->names[map->image]);
        sl_sampler_state s = sl_gbuffer_map_sampler(map);
        slgl_sampler_set(g->samplers[slot], &s);
        glBindSampler((GLuint)slot, g->samplers[slot]);
    }
    glActiveTexture(GL_TEXTURE0);
}

bool slgl_gbuffer_draw(slgl_gbuffer *g, const sl_scene *scene, const slgl_mesh *meshes,
                       const sl_scene_textures *sl_textures, const slgl_textures *textures, mat4 view_proj,
                       sl_error *err)
{
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glViewport(0, 0, g->width, g->height);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_MULTISAMPLE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDepthRange(0.0, 1.0);
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (g->extra) {
        static const GLfloat none[4] = {1.0f, 0.0f, 0.0f, 0.0f};
        glClearBufferfv(GL_COLOR, 4, none);
    }
    /* attributes a mesh lacks read as 0, as softlight's sl_vertex_in has them (GL's default w is 1) */
    glVertexAttrib2f(2, 0.0f, 0.0f);
    glVertexAttrib4f(3, 0.0f, 0.0f, 0.0f, 0.0f);
    static const GLenum no_extra[5] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                       GL_COLOR_ATTACHMENT3, GL_NONE};
    if (g->user_program && g->extra && !g->user_extra) /* after the clear: the target stays "none" */
        glDrawBuffers(5, no_extra);
    tex_locations ul = g->user_program ? tex_locations_get(g->user_program) : (tex_locations){0};
    tex_locations tl = tex_locations_get(g->tex_program);
    GLuint p = g->program;
    plain_locations pl = {
        .model = glGetUniformLocation(p, "uModel"),
        .view_proj = glGetUniformLocation(p, "uViewProj"),
        .normal = glGetUniformLocation(p, "uNormalMatrix"),
        .kd = glGetUniformLocation(p, "uKd"),
        .ks = glGetUniformLocation(p, "uKs"),
        .alpha = glGetUniformLocation(p, "uAlpha"),
    };
    for (int i = 0; i < scene->object_count; i++) {
        const sl_object *o = &scene->objects[i];
        const sl_material *m = &scene->materials[o->material];
        if (m->textured || g->user_program) {
            if (m->textured && (!sl_textures || !textures || textures->count != scene->image_count))
                return sl_fail(err, SL_ERR_RANGE, "object %d (%s): material \"%s\" has texture maps but the scene's "
                               "textures are not uploaded", i, o->name, m->name);
            glUseProgram(g->user_program ? g->user_program : g->tex_program);
            draw_textured(g, g->user_program ? &ul : &tl, o, m, sl_textures, textures, view_proj);
        } else {
            /* softlight's own uniform set, so both draws see bitwise the same matrices */
            sl_gbuffer_uniforms u;
            sl_gbuffer_uniforms_init(&u, o->model, view_proj, m);
            glUseProgram(g->program);
            glUniformMatrix4fv(pl.model, 1, GL_FALSE, &u.uModel.c[0].x);
            glUniformMatrix4fv(pl.view_proj, 1, GL_FALSE, &u.uViewProj.c[0].x);
            glUniformMatrix3fv(pl.normal, 1, GL_FALSE, &u.uNormalMatrix.c[0].x);
            glUniform3f(pl.kd, u.uKd.x, u.uKd.y, u.uKd.z);
            glUniform3f(pl.ks, u.uKs.x, u.uKs.y, u.uKs.z);
            glUniform1f(pl.alpha, u.uAlpha);
        }
        const slgl_mesh *mesh = &meshes[o->mesh];
        glBindVertexArray(mesh->vao);
        glDrawElements(GL_TRIANGLES, mesh->index_count, GL_UNSIGNED_INT, NULL);
    }
    glBindVertexArray(0);
    for (int slot = 0; slot < SL_MAP_COUNT; slot++)
        glBindSampler((GLuint)slot, 0);
    if (g->user_program && g->extra && !g->user_extra) {
        static const GLenum all[5] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                      GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4};
        glDrawBuffers(5, all);
    }
    g->facet = !g->user_program; /* a user's shader writes its own .w channels */
    return slgl_check("the G-buffer pass", err);
}

/* gbuffer.frag's facet_code of a unit normal (0 for none: the code (2, 2)), and lighting.frag's
 * facet_normal back: the facet plane in the normal's and Kd's spare .w channels. */
static vec2 facet_code(vec3 f)
{
    float l1 = fabsf(f.x) + fabsf(f.y) + fabsf(f.z);
    if (!(l1 > 0.0f))
        return vec2(2.0f, 2.0f);
    vec2 p = vec2(f.x / l1, f.y / l1);
    if (f.z < 0.0f)
        p = vec2((1.0f - fabsf(p.y)) * (p.x >= 0.0f ? 1.0f : -1.0f),
                 (1.0f - fabsf(p.x)) * (p.y >= 0.0f ? 1.0f : -1.0f));
    return p;
}

static vec3 facet_decode(float a, float b)
{
    if (fabsf(a) > 1.5f)
        return vec3s(0.0f);
    vec3 n = vec3(a, b, 1.0f - fabsf(a) - fabsf(b));
    if (n.z < 0.0f)
        n = vec3((1.0f - fabsf(b)) * (a >= 0.0f ? 1.0f : -1.0f), (1.0f - fabsf(a)) * (b >= 0.0f ? 1.0f : -1.0f),
                 n.z);
    return normalize(n);
}

/* Read one RGBA32F attachment, row 0 = bottom. */
static void read_rgba(GLenum attachment, int width, int height, float *rgba)
{
    glReadBuffer(attachment);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, rgba);
}

bool slgl_gbuffer_read(const slgl_gbuffer *g, sl_gbuffer *out, sl_error *err)
{
    if (!sl_gbuffer_resize(out, g->width, g->height, err))
        return false;
    size_t n = (size_t)g->width * (size_t)g->height;
    float *buf = malloc(n * 4 * sizeof *buf);
    float *depth = malloc(n * sizeof *depth);
    if (!buf || !depth) {
        free(buf);
        free(depth);
        return sl_fail(err, SL_ERR_MEMORY, "no memory to read back a %dx%d G-buffer", g->width, g->height);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    read_rgba(GL_COLOR_ATTACHMENT0, g->width, g->height, buf);
    for (size_t i = 0; i < n; i++)
        out->texels[i].position = vec3(buf[4 * i], buf[4 * i + 1], buf[4 * i + 2]);
    bool ok = sl_gbuffer_use_facet(out, g->facet, err);
    read_rgba(GL_COLOR_ATTACHMENT1, g->width, g->height, buf);
    for (size_t i = 0; i < n; i++) {
        out->texels[i].normal = vec3(buf[4 * i], buf[4 * i + 1], buf[4 * i + 2]);
        if (out->facet) /* its first code, the second below */
            out->facet[i].x = buf[4 * i + 3];
    }
    read_rgba(GL_COLOR_ATTACHMENT2, g->width, g->height, buf);
    for (size_t i = 0; i < n; i++) {
        out->texels[i].kd = vec3(buf[4 * i], buf[4 * i + 1], buf[4 * i + 2]);
        if (out->facet)
            out->facet[i] = facet_decode(out->facet[i].x, buf[4 * i + 3]);
    }
    read_rgba(GL_COLOR_ATTACHMENT3, g->width, g->height, buf);
    for (size_t i = 0; i < n; i++) {
        out->texels[i].ks = vec3(buf[4 * i], buf[4 * i + 1], buf[4 * i + 2]);
        out->texels[i].alpha = buf[4 * i + 3];
    }
    glReadPixels(0, 0, g->width, g->height, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    for (size_t i = 0; i < n; i++) {
        out->texels[i].depth = depth[i];
        if (out->facet && !sl_gbuffer_covered(&out->texels[i])) /* 0 where empty, as softlight's clear */
            out->facet[i] = vec3s(0.0f);
    }
    ok = ok && sl_gbuffer_use_extra(out, g->extra != 0, 0, err);
    if (ok && g->extra) { /* tagged with the texel's depth, as softlight's resolve leaves them */
        read_rgba(GL_COLOR_ATTACHMENT4, g->width, g->height, buf);
        for (size_t i = 0; i < n; i++)
            out->extra[i] = (sl_gbuffer_extra){buf[4 * i], vec3(buf[4 * i + 1], buf[4 * i + 2], buf[4 * i + 3]),
                                               depth[i]};
    }
    free(buf);
    free(depth);
    return ok && slgl_check("reading the G-buffer back", err);
}

bool slgl_gbuffer_upload(slgl_gbuffer *g, const sl_gbuffer *in, sl_error *err)
{
    if (in->width != g->width || in->height != g->height)
        return sl_fail(err, SL_ERR_RANGE, "G-buffer files are %dx%d, the frame is %dx%d", in->width, in->height,
                       g->width, g->height);
    size_t n = (size_t)g->width * (size_t)g->height;
    float *buf = malloc(n * 4 * sizeof *buf);
    if (!buf)
        return sl_fail(err, SL_ERR_MEMORY, "no memory to upload a %dx%d G-buffer", g->width, g->height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if ((in->extra != NULL) != (g->extra != 0)) {
        free(buf);
        return sl_fail(err, SL_ERR_RANGE, "G-buffer files %s extra channels, the GL G-buffer %s",
                       in->extra ? "have" : "have no", g->extra ? "has" : "has none");
    }
    for (int target = 0; target < (g->extra ? 6 : 5); target++) {
        for (size_t i = 0; i < n; i++) {
            const sl_gbuffer_texel *t = &in->texels[i];
            float covered = sl_gbuffer_covered(t) ? 1.0f : 0.0f;
            vec2 facet = in->facet ? facet_code(in->facet[i]) : vec2(2.0f, 2.0f);
            vec4 v = target == 0   ? vec4_from3(t->position, covered)
                     : target == 1 ? vec4_from3(t->normal, facet.x)
                     : target == 2 ? vec4_from3(t->kd, facet.y)
                     : target == 3 ? vec4_from3(t->ks, t->alpha)
                     : target == 5 ? vec4(in->extra[i].occlusion, in->extra[i].emissive.x, in->extra[i].emissive.y,
                                          in->extra[i].emissive.z)
                                   : vec4(t->depth, 0, 0, 0);
            if (target == 4)
                buf[i] = v.x;
            else
                memcpy(&buf[4 * i], &v, sizeof v);
        }
        GLuint tex[6] = {g->position, g->normal, g->kd, g->ks_alpha, g->depth, g->extra};
        glBindTexture(GL_TEXTURE_2D, tex[target]);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, g->width, g->height, target == 4 ? GL_DEPTH_COMPONENT : GL_RGBA,
                        GL_FLOAT, buf);
    }
    if (in->cone) { /* the occlusion pass's cone from the files: a texture of the G-buffer's own */
        if (!g->cone_files)
            glGenTextures(1, &g->cone_files);
        glBindTexture(GL_TEXTURE_2D, g->cone_files);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, g->width, g->height, 0, GL_RGBA, GL_FLOAT, in->cone);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        g->cone = g->cone_files;
    }
    g->facet = in->facet != NULL;
    free(buf);
    return slgl_check("uploading the G-buffer", err);
}
