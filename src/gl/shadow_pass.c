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
 * Each kind of map is its own texture and layer table in slgl_shadows, bound to its own sampler
 * of lighting.frag (uShadowCubes, uShadowCubeLayer), so another kind adds a texture beside the
 * cubes without touching them. */
#include <math.h>
#include <string.h>

#include "shadow/shadow.h"
#include "slgl.h"

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
    memset(s, 0, sizeof *s);
    for (int i = 0; i < SL_LIGHTING_MAX_LIGHTS; i++)
        s->cube_layer[i] = -1;
}

static const float far_away[4] = {INFINITY, INFINITY, INFINITY, INFINITY}; /* nothing drawn */

/* Layer `layer` of the cube texture with view_proj: every object with a triangle. */
static void draw_face(const slgl_shadows *s, const sl_scene *scene, const slgl_mesh *meshes, GLint mvp_loc,
                      int layer, mat4 view_proj)
{
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, s->cubes, 0, layer);
    glClearBufferfv(GL_COLOR, 0, far_away);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    for (int o = 0; o < scene->object_count; o++) {
        const sl_object *obj = &scene->objects[o];
        const slgl_mesh *mesh = &meshes[obj->mesh];
        if (scene->meshes[obj->mesh].triangle_count == 0)
            continue;
        mat4 mvp = mat4_mul(view_proj, obj->model);
        glUniformMatrix4fv(mvp_loc, 1, GL_FALSE, &mvp.c[0].x);
        glBindVertexArray(mesh->vao);
        glDrawElements(GL_TRIANGLES, mesh->index_count, GL_UNSIGNED_INT, NULL);
    }
}

bool slgl_shadows_draw(slgl_shadows *s, const sl_scene *scene, const slgl_mesh *meshes, bool all, sl_error *err)
{
    slgl_shadows_destroy(s);
    int casting = 0;
    for (int i = 0; i < scene->light_count && i < SL_LIGHTING_MAX_LIGHTS; i++)
        if (all || scene->lights[i].shadow)
            s->cube_layer[i] = 6 * casting++;
    if (casting == 0)
        return true;
    s->cube_count = casting;
    s->side = SL_SHADOW_CUBE_SIZE + 2 * SL_SHADOW_GUARD;
    if (!slgl_program_from_files("shadow_depth.vert", "shadow_depth.frag", &s->program, err))
        return false;
    glGenTextures(1, &s->cubes);
    glBindTexture(GL_TEXTURE_2D_ARRAY, s->cubes);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_R32F, s->side, s->side, 6 * casting, 0, GL_RED, GL_FLOAT, NULL);
    /* read with texelFetch only, but complete without mipmaps */
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glGenRenderbuffers(1, &s->depth);
    glBindRenderbuffer(GL_RENDERBUFFER, s->depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, s->side, s->side);
    glGenFramebuffers(1, &s->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, s->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, s->depth);
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, s->cubes, 0, 0);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return sl_fail(err, SL_ERR_GL, "shadow maps: framebuffer incomplete (0x%04x)", (unsigned)status);
    glDrawBuffer(GL_COLOR_ATTACHMENT0);
    glViewport(0, 0, s->side, s->side);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glUseProgram(s->program);
    GLint mvp_loc = glGetUniformLocation(s->program, "uModelViewProj");
    for (int i = 0; i < scene->light_count && i < SL_LIGHTING_MAX_LIGHTS; i++) {
        if (s->cube_layer[i] < 0)
            continue;
        for (int f = 0; f < 6; f++) {
            mat4 view_proj;
            if (sl_shadow_face_view_proj(scene, scene->lights[i].position, f, &view_proj)) {
                draw_face(s, scene, meshes, mvp_loc, s->cube_layer[i] + f, view_proj);
            } else { /* no geometry: every depth stays +inf */
                glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, s->cubes, 0, s->cube_layer[i] + f);
                glClearBufferfv(GL_COLOR, 0, far_away);
            }
        }
    }
    glBindVertexArray(0);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return slgl_check("drawing the shadow maps", err);
}
