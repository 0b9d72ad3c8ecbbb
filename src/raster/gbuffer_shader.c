/* gbuffer_shader.c - the built-in shader pair that fills the G-buffer, and the
 * scene convenience that draws a whole scene with it (textured materials with the textured
 * program, gbuffer_textured.c; or every object with a user's G-buffer program, gbuffer_user.c).
 *
 * The GLSL twin (shaders/gbuffer.vert, shaders/gbuffer.frag) is a translation of
 * these two functions and keeps their names: uModel, uViewProj, uNormalMatrix,
 * uKd, uKs, uAlpha; varyings vWorldPos, vNormal. sl_gbuffer_frag_span is the same
 * fragment shader over a row span (the rasterizer's fast path): one vectorized loop
 * normalizes the span's normals, a second writes the texels; it gives the texels
 * sl_gbuffer_frag gives, bit for bit (tests/unit/test_raster_span.c). */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../scene/camera.h"
#include "gbuffer_textured.h"
#include "raster.h"

/* gbuffer.vert: main() */
void sl_gbuffer_vert(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    const sl_gbuffer_uniforms *u = uniforms;
    vec4 world = mat4_mul_vec4(u->uModel, vec4_from3(in->position, 1.0f));
    vec3 vWorldPos = xyz(world);
    vec3 vNormal = mat3_mul_vec3(u->uNormalMatrix, in->normal);
    *clip = mat4_mul_vec4(u->uViewProj, world);
    varyings[0] = vWorldPos.x;
    varyings[1] = vWorldPos.y;
    varyings[2] = vWorldPos.z;
    varyings[3] = vNormal.x;
    varyings[4] = vNormal.y;
    varyings[5] = vNormal.z;
}

/* gbuffer.frag: main(). An interpolated normal of zero length (opposite vertex
 * normals) would make normalize() NaN; the C side writes +Z there instead. */
void sl_gbuffer_frag(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    const sl_gbuffer_uniforms *u = uniforms;
    const float *v = in->varyings;
    vec3 vWorldPos = vec3(v[0], v[1], v[2]);
    vec3 vNormal = vec3(v[3], v[4], v[5]);
    sl_gbuffer_texel *g = texel;
    g->position = vWorldPos;
    g->normal = dot(vNormal, vNormal) > 1e-30f ? normalize(vNormal) : vec3(0, 0, 1);
    g->kd = u->uKd;
    g->ks = u->uKs;
    g->alpha = u->uAlpha;
    g->depth = in->frag_coord.z;
}

/* gbuffer.frag: main(), for the n fragments of a span. The normalisation is
 * sl_gbuffer_frag's, operation for operation (dot, 1/sqrt, scale), written with
 * selects instead of a branch so that it vectorizes: a zero-length normal divides
 * by sqrt(1) and is then replaced by +Z, as in the scalar shader. */
void sl_gbuffer_frag_span(const void *uniforms, const sl_fragment_span *span)
{
    const sl_gbuffer_uniforms *u = uniforms;
    const float *px = span->varyings[0], *py = span->varyings[1], *pz = span->varyings[2];
    const float *vx = span->varyings[3], *vy = span->varyings[4], *vz = span->varyings[5];
    float nx[SL_SPAN_MAX], ny[SL_SPAN_MAX], nz[SL_SPAN_MAX];
    int n = span->n;
#pragma omp simd
    for (int j = 0; j < n; j++) {
        sl_gbuffer_normal_lane(vx[j], vy[j], vz[j], &nx[j], &ny[j], &nz[j]);
    }
    /* Field by field into the texel, as sl_gbuffer_frag writes it. Not a texel assembled on the
     * stack and copied: its copy loaded 32 bytes over the depth just stored there, a store
     * forward that cannot succeed, and that stall was half the shader's time (perf annotate). */
    const vec3 kd = u->uKd, ks = u->uKs;
    const float alpha = u->uAlpha;
    for (int j = 0; j < n; j++) {
        sl_gbuffer_texel *g = (sl_gbuffer_texel *)(void *)(span->row + (size_t)span->x[j] * span->texel_size);
        g->position = vec3(px[j], py[j], pz[j]);
        g->normal = vec3(nx[j], ny[j], nz[j]);
        g->kd = kd;
        g->ks = ks;
        g->alpha = alpha;
        g->depth = span->frag_z[j];
    }
}

const sl_program sl_gbuffer_program = {
    .vertex = sl_gbuffer_vert,
    .fragment = sl_gbuffer_frag,
    .varying_count = SL_GBUFFER_VARYINGS,
    .fragment_span = sl_gbuffer_frag_span,
    .writes_depth = true, /* g->depth = frag_coord.z in both forms */
};

void sl_gbuffer_uniforms_init(sl_gbuffer_uniforms *u, mat4 model, mat4 view_proj, const sl_material *m)
{
    u->uModel = model;
    u->uViewProj = view_proj;
    u->uNormalMatrix = transpose(inverse(mat3_from_mat4(model)));
    u->uKd = m->kd;
    u->uKs = m->ks;
    u->uAlpha = m->brdf == SL_BRDF_GGX ? sl_gbuffer_ggx_alpha(m->roughness) : m->alpha; /* gbuffer.h */
}

bool sl_raster_scene(sl_raster *r, const sl_scene *scene, const sl_camera *cam, sl_gbuffer *gb, sl_error *err)
{
    return sl_raster_scene_textured(r, scene, NULL, cam, gb, err);
}

bool sl_raster_scene_textured(sl_raster *r, const sl_scene *scene, const sl_scene_textures *textures,
                              const sl_camera *cam, sl_gbuffer *gb, sl_error *err)
{
    return sl_raster_scene_program(r, scene, textures, NULL, cam, gb, err);
}

bool sl_raster_scene_program(sl_raster *r, const sl_scene *scene, const sl_scene_textures *textures,
                             const sl_gbuffer_fragment_program *user, const sl_camera *cam, sl_gbuffer *gb,
                             sl_error *err)
{
    if (!gb->texels)
        return sl_fail(err, SL_ERR_RANGE, "raster: G-buffer not allocated (call sl_gbuffer_resize)");
    if (!(cam->znear > 0.0f) || !(cam->zfar > cam->znear) || !(cam->fovy_deg > 0.0f && cam->fovy_deg < 180.0f))
        return sl_fail(err, SL_ERR_RANGE, "raster: camera near %g, far %g, fovy %g: need 0 < near < far, 0 < fovy < 180",
                       (double)cam->znear, (double)cam->zfar, (double)cam->fovy_deg);
    for (int i = 0; i < scene->object_count; i++) {
        const sl_object *o = &scene->objects[i];
        if (o->mesh < 0 || o->mesh >= scene->mesh_count || o->material < 0 || o->material >= scene->material_count)
            return sl_fail(err, SL_ERR_RANGE, "raster: object %d (%s) names mesh %d / material %d out of range", i,
                           o->name, o->mesh, o->material);
        const sl_material *m = &scene->materials[o->material];
        if (sl_material_has_maps(m) && (!textures || textures->count != scene->image_count))
            return sl_fail(err, SL_ERR_RANGE,
                           "raster: object %d (%s): material \"%s\" has texture maps but the scene's textures are not "
                           "loaded (sl_scene_textures_load)", i, o->name, m->name);
        if (sl_material_has_maps(m) && !scene->meshes[o->mesh].texcoords && scene->meshes[o->mesh].vertex_count > 0)
            return sl_fail(err, SL_ERR_RANGE, "raster: object %d (%s): material \"%s\" has texture maps but its mesh "
                           "has no texture coordinates", i, o->name, m->name);
    }
    /* The extra plane only for a scene that draws a material writing it (gbuffer.h). */
    bool extra = false;
    for (int i = 0; i < scene->object_count; i++)
        extra |= sl_material_extra(&scene->materials[scene->objects[i].material]);
    extra |= sl_raster_keeps_extra(r);
    if (!sl_gbuffer_use_extra(gb, extra, sl_raster_threads(r), err))
        return false;
    if (scene->object_count == 0) {
        sl_gbuffer_clear(gb, sl_raster_threads(r));
        return true;
    }
    size_t n = (size_t)scene->object_count;
    size_t textured = 0;
    for (size_t i = 0; i < n; i++)
        textured += scene->materials[scene->objects[i].material].textured;
    sl_gbuffer_uniforms *u = malloc(n * sizeof *u);
    sl_gbuffer_tex_uniforms *tu = textured ? malloc(textured * sizeof *tu) : NULL;
    sl_gbuffer_user_uniforms *uu = user ? malloc(n * sizeof *uu) : NULL; /* a user's program: every object */
    sl_draw *draws = malloc(n * sizeof *draws);
    if (!u || !draws || (textured && !tu) || (user && !uu)) {
        free(u);
        free(tu);
        free(uu);
        free(draws);
        return sl_fail(err, SL_ERR_MEMORY, "raster: out of memory for %zu objects", n);
    }
    const sl_program user_program = user ? sl_gbuffer_user_program(user, gb->extra != NULL) : (sl_program){0};
    /* The clear (every field 0, depth 1, as sl_gbuffer_clear) rides on the list's tile
     * pass: each tile is cleared where it is drawn (tile.c), and so is the extra plane's clear
     * and resolve (the target's tile hooks, sl_gbuffer_target). */
    static const sl_gbuffer_texel empty = {.depth = 1.0f};
    mat4 view_proj = sl_camera_view_proj(cam, gb->width, gb->height);
    for (size_t i = 0, t = 0; i < n; i++) {
        const sl_object *o = &scene->objects[i];
        const sl_material *m = &scene->materials[o->material];
        const sl_program *program = &sl_gbuffer_program;
        const void *uniforms = &u[i];
        if (user) { /* the user's fragment program behind the textured vertex shader */
            sl_gbuffer_tex_uniforms_init(&uu[i].tex, o->model, view_proj, m, textures);
            sl_gbuffer_material_from(&uu[i].material, &uu[i].tex);
            uu[i].program = user;
            uu[i].extra = gb->extra;
            uu[i].extra_width = gb->width;
            program = &user_program;
            uniforms = &uu[i];
        } else if (m->textured) { /* the textured program only where a material has maps */
            sl_gbuffer_tex_uniforms_init(&tu[t], o->model, view_proj, m, textures);
            tu[t].trace = textures ? textures->trace : NULL;
            tu[t].trace_ctx = textures ? textures->trace_ctx : NULL;
            if (sl_material_extra(m)) {
                tu[t].extra = gb->extra;
                tu[t].extra_width = gb->width;
            }
            program = m->masked ? &sl_gbuffer_tex_masked_program : &sl_gbuffer_tex_program;
            uniforms = &tu[t++];
        } else {
            sl_gbuffer_uniforms_init(&u[i], o->model, view_proj, m);
        }
        draws[i] = (sl_draw){
            .program = program,
            .vs_uniforms = uniforms,
            .fs_uniforms = uniforms,
            .mesh = &scene->meshes[o->mesh],
            .cull = SL_CULL_NONE,
            .clear = i == 0 ? &empty : NULL,
        };
    }
    sl_target target = sl_gbuffer_target(gb);
    target.facet_view_proj = view_proj;
    bool ok = sl_raster_draw_list(r, &target, draws, scene->object_count, err);
    if (!ok) { /* name the object: the list's errors say "draw i" */
        int i = 0;
        if (sscanf(err->msg, "draw %d:", &i) == 1 && i >= 0 && i < scene->object_count)
            sl_error_prefix(err, "object %d (%s): ", i, scene->objects[i].name);
    }
    free(u);
    free(tu);
    free(uu);
    free(draws);
    return ok;
}
