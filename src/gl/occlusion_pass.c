/* occlusion_pass.c - ambient occlusion in OpenGL, the twin of src/occlusion/gtao.c: after the
 * G-buffer pass, shaders/gtao.frag draws the raw samples over the half-resolution grid (an R32F
 * target), then shaders/gtao_blur.frag draws each texel's blurred AO times the material's
 * occlusion, with the emission, into an RGBA32F target that is copied over the G-buffer's extra
 * target, and each texel's visibility cone (bent normal, AO) into a second one the lighting reads
 * (uCone). The two shaders get softlight's constants (slices, steps, the blur's tests) as
 * #defines and the camera's frame from sl_gtao_view_of, as gtao.c does, so the two
 * differ only in how they evaluate the same code. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "occlusion/gtao.h"
#include "slgl.h"

static GLuint make_target(GLenum internal, GLenum format, int width, int height, GLuint *fbo)
{
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, width, height, 0, format, GL_FLOAT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glGenFramebuffers(1, fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    return tex;
}

bool slgl_occlusion_create(slgl_occlusion *o, int width, int height, sl_error *err)
{
    memset(o, 0, sizeof *o);
    o->width = width;
    o->height = height;
    o->grid_width = (width + 1) / 2;
    o->grid_height = (height + 1) / 2;
    char defines[200];
    snprintf(defines, sizeof defines, "#define SLICES %d\n#define STEPS %d", SL_GTAO_SLICES, SL_GTAO_STEPS);
    char blur_defines[200];
    snprintf(blur_defines, sizeof blur_defines, "#define BLUR_DEPTH %.9g\n#define BLUR_NORMAL %.9g",
             (double)SL_GTAO_BLUR_DEPTH, (double)SL_GTAO_BLUR_NORMAL);
    if (!slgl_program_from_sources("full-screen triangle", slgl_fullscreen_vert, "gtao.frag", defines, &o->program,
                                   err) ||
        !slgl_program_from_sources("full-screen triangle", slgl_fullscreen_vert, "gtao_blur.frag", blur_defines,
                                   &o->blur_program, err)) {
        slgl_occlusion_destroy(o);
        return false;
    }
    glGenVertexArrays(1, &o->vao);
    o->half = make_target(GL_RGBA32F, GL_RGBA, o->grid_width, o->grid_height, &o->half_fbo);
    o->out = make_target(GL_RGBA32F, GL_RGBA, width, height, &o->out_fbo);
    glGenTextures(1, &o->cone); /* the blur's second output, beside out */
    glBindTexture(GL_TEXTURE_2D, o->cone);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, o->cone, 0);
    return slgl_check("creating the occlusion targets", err);
}

void slgl_occlusion_destroy(slgl_occlusion *o)
{
    GLuint textures[3] = {o->half, o->out, o->cone}, fbos[2] = {o->half_fbo, o->out_fbo};
    glDeleteTextures(3, textures);
    glDeleteFramebuffers(2, fbos);
    if (o->vao)
        glDeleteVertexArrays(1, &o->vao);
    if (o->program)
        glDeleteProgram(o->program);
    if (o->blur_program)
        glDeleteProgram(o->blur_program);
    memset(o, 0, sizeof *o);
}

static void bind_texture(int unit, GLuint tex)
{
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(GL_TEXTURE_2D, tex);
}

bool slgl_occlusion_draw(slgl_occlusion *o, slgl_gbuffer *g, const sl_camera *cam, float radius, sl_error *err)
{
    if (!g->extra)
        return sl_fail(err, SL_ERR_RANGE, "ambient occlusion: the GL G-buffer has no extra target");
    if (g->width != o->width || g->height != o->height)
        return sl_fail(err, SL_ERR_RANGE, "ambient occlusion: the G-buffer is %dx%d, the targets %dx%d", g->width,
                       g->height, o->width, o->height);
    const sl_gtao_view v = sl_gtao_view_of(cam, g->height);
    const vec3 forward = v.forward, right = v.right, up = v.up;
    const float pixels_per_unit = v.pixels_per_unit;
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glBindVertexArray(o->vao);

    GLuint p = o->program;
    glUseProgram(p);
    bind_texture(0, g->position);
    bind_texture(1, g->normal);
    glUniform1i(glGetUniformLocation(p, "uPosition"), 0);
    glUniform1i(glGetUniformLocation(p, "uNormal"), 1);
    glUniform3f(glGetUniformLocation(p, "uEye"), cam->eye.x, cam->eye.y, cam->eye.z);
    glUniform3f(glGetUniformLocation(p, "uForward"), forward.x, forward.y, forward.z);
    glUniform3f(glGetUniformLocation(p, "uRight"), right.x, right.y, right.z);
    glUniform3f(glGetUniformLocation(p, "uUp"), up.x, up.y, up.z);
    glUniform1f(glGetUniformLocation(p, "uPixelsPerUnit"), pixels_per_unit);
    glUniform2f(glGetUniformLocation(p, "uHalfSize"), 0.5f * (float)g->width, 0.5f * (float)g->height);
    glUniform1f(glGetUniformLocation(p, "uRadius"), radius);
    glUniform1f(glGetUniformLocation(p, "uMaxPixels"), SL_GTAO_MAX_SCREEN * (float)g->height);
    glUniform2i(glGetUniformLocation(p, "uGrid"), o->grid_width, o->grid_height);
    glBindFramebuffer(GL_FRAMEBUFFER, o->half_fbo);
    glViewport(0, 0, o->grid_width, o->grid_height);
    glDrawArrays(GL_TRIANGLES, 0, 3);

    p = o->blur_program;
    glUseProgram(p);
    bind_texture(2, g->extra);
    bind_texture(3, o->half);
    glUniform1i(glGetUniformLocation(p, "uPosition"), 0);
    glUniform1i(glGetUniformLocation(p, "uNormal"), 1);
    glUniform1i(glGetUniformLocation(p, "uExtra"), 2);
    glUniform1i(glGetUniformLocation(p, "uHalf"), 3);
    glUniform3f(glGetUniformLocation(p, "uEye"), cam->eye.x, cam->eye.y, cam->eye.z);
    glUniform3f(glGetUniformLocation(p, "uForward"), forward.x, forward.y, forward.z);
    glUniform2i(glGetUniformLocation(p, "uGrid"), o->grid_width, o->grid_height);
    glBindFramebuffer(GL_FRAMEBUFFER, o->out_fbo);
    static const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, both);
    glViewport(0, 0, o->width, o->height);
    glDrawArrays(GL_TRIANGLES, 0, 3);

    /* the result over the extra target: read from the output, copy into the bound texture */
    bind_texture(2, g->extra);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, o->out_fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 0, 0, o->width, o->height);
    g->cone = o->cone;
    glBindVertexArray(0);
    glActiveTexture(GL_TEXTURE0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return slgl_check("the occlusion pass", err);
}
