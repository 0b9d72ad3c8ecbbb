/* gbuffer_pass.c - the G-buffer pass in OpenGL: every object drawn with shaders/gbuffer.vert/.frag
 * into four RGBA32F colour targets and a 32-bit float depth target.
 *
 * It reproduces softlight's raster stage state for state, so that coverage and depth can be compared
 * bit for bit: the uniforms come from the same C function (sl_gbuffer_uniforms_init) with the same
 * view-projection (sl_camera_view_proj), the viewport is the whole target, depth test LESS against
 * a clear depth of 1, no culling (softlight's sl_raster_scene draws both faces), no blending, no
 * multisampling. Targets: 0 position (w = 1 where drawn), 1 normal, 2 kd, 3 ks + alpha; cleared to
 * 0 like sl_gbuffer_clear. Row 0 is the bottom row in both. */
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

bool slgl_gbuffer_create(slgl_gbuffer *g, int width, int height, sl_error *err)
{
    memset(g, 0, sizeof *g);
    g->width = width;
    g->height = height;
    if (!slgl_program_from_files("gbuffer.vert", "gbuffer.frag", &g->program, err))
        return false;
    GLuint targets[4];
    for (int i = 0; i < 4; i++)
        targets[i] = make_target(GL_RGBA32F, GL_RGBA, width, height);
    g->position = targets[0];
    g->normal = targets[1];
    g->kd = targets[2];
    g->ks_alpha = targets[3];
    g->depth = make_target(GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, width, height);
    glGenFramebuffers(1, &g->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    for (int i = 0; i < 4; i++)
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i, GL_TEXTURE_2D, targets[i], 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, g->depth, 0);
    static const GLenum draw_buffers[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                           GL_COLOR_ATTACHMENT3};
    glDrawBuffers(4, draw_buffers);
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
    GLuint textures[5] = {g->position, g->normal, g->kd, g->ks_alpha, g->depth};
    glDeleteTextures(5, textures);
    if (g->fbo)
        glDeleteFramebuffers(1, &g->fbo);
    if (g->program)
        glDeleteProgram(g->program);
    memset(g, 0, sizeof *g);
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
        GLuint buffers[3] = {m->vbo_position, m->vbo_normal, m->ibo};
        glDeleteBuffers(3, buffers);
        if (m->vao)
            glDeleteVertexArrays(1, &m->vao);
        memset(m, 0, sizeof *m);
    }
}

bool slgl_gbuffer_draw(slgl_gbuffer *g, const sl_scene *scene, const slgl_mesh *meshes, mat4 view_proj,
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
    glUseProgram(g->program);
    GLint loc_model = glGetUniformLocation(g->program, "uModel");
    GLint loc_view_proj = glGetUniformLocation(g->program, "uViewProj");
    GLint loc_normal = glGetUniformLocation(g->program, "uNormalMatrix");
    GLint loc_kd = glGetUniformLocation(g->program, "uKd");
    GLint loc_ks = glGetUniformLocation(g->program, "uKs");
    GLint loc_alpha = glGetUniformLocation(g->program, "uAlpha");
    for (int i = 0; i < scene->object_count; i++) {
        const sl_object *o = &scene->objects[i];
        /* softlight's own uniform set, so both draws see bitwise the same matrices */
        sl_gbuffer_uniforms u;
        sl_gbuffer_uniforms_init(&u, o->model, view_proj, &scene->materials[o->material]);
        glUniformMatrix4fv(loc_model, 1, GL_FALSE, &u.uModel.c[0].x);
        glUniformMatrix4fv(loc_view_proj, 1, GL_FALSE, &u.uViewProj.c[0].x);
        glUniformMatrix3fv(loc_normal, 1, GL_FALSE, &u.uNormalMatrix.c[0].x);
        glUniform3f(loc_kd, u.uKd.x, u.uKd.y, u.uKd.z);
        glUniform3f(loc_ks, u.uKs.x, u.uKs.y, u.uKs.z);
        glUniform1f(loc_alpha, u.uAlpha);
        const slgl_mesh *m = &meshes[o->mesh];
        glBindVertexArray(m->vao);
        glDrawElements(GL_TRIANGLES, m->index_count, GL_UNSIGNED_INT, NULL);
    }
    glBindVertexArray(0);
    return slgl_check("the G-buffer pass", err);
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
    read_rgba(GL_COLOR_ATTACHMENT1, g->width, g->height, buf);
    for (size_t i = 0; i < n; i++)
        out->texels[i].normal = vec3(buf[4 * i], buf[4 * i + 1], buf[4 * i + 2]);
    read_rgba(GL_COLOR_ATTACHMENT2, g->width, g->height, buf);
    for (size_t i = 0; i < n; i++)
        out->texels[i].kd = vec3(buf[4 * i], buf[4 * i + 1], buf[4 * i + 2]);
    read_rgba(GL_COLOR_ATTACHMENT3, g->width, g->height, buf);
    for (size_t i = 0; i < n; i++) {
        out->texels[i].ks = vec3(buf[4 * i], buf[4 * i + 1], buf[4 * i + 2]);
        out->texels[i].alpha = buf[4 * i + 3];
    }
    glReadPixels(0, 0, g->width, g->height, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    for (size_t i = 0; i < n; i++)
        out->texels[i].depth = depth[i];
    free(buf);
    free(depth);
    return slgl_check("reading the G-buffer back", err);
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
    for (int target = 0; target < 5; target++) {
        for (size_t i = 0; i < n; i++) {
            const sl_gbuffer_texel *t = &in->texels[i];
            float covered = sl_gbuffer_covered(t) ? 1.0f : 0.0f;
            vec4 v = target == 0   ? vec4_from3(t->position, covered)
                     : target == 1 ? vec4_from3(t->normal, 0.0f)
                     : target == 2 ? vec4_from3(t->kd, 0.0f)
                     : target == 3 ? vec4_from3(t->ks, t->alpha)
                                   : vec4(t->depth, 0, 0, 0);
            if (target == 4)
                buf[i] = v.x;
            else
                memcpy(&buf[4 * i], &v, sizeof v);
        }
        GLuint tex[5] = {g->position, g->normal, g->kd, g->ks_alpha, g->depth};
        glBindTexture(GL_TEXTURE_2D, tex[target]);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, g->width, g->height, target == 4 ? GL_DEPTH_COMPONENT : GL_RGBA,
                        GL_FLOAT, buf);
    }
    free(buf);
    return slgl_check("uploading the G-buffer", err);
}
