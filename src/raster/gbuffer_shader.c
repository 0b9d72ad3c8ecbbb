/* gbuffer_shader.c - the built-in shader pair that fills the G-buffer, and the
 * scene convenience that draws a whole scene with it.
 *
 * The GLSL twin (shaders/gbuffer.vert, shaders/gbuffer.frag) is a translation of
 * these two functions and keeps their names: uModel, uViewProj, uNormalMatrix,
 * uKd, uKs, uAlpha; varyings vWorldPos, vNormal. */
#include <stddef.h>

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

const sl_program sl_gbuffer_program = {
    .vertex = sl_gbuffer_vert,
    .fragment = sl_gbuffer_frag,
    .varying_count = SL_GBUFFER_VARYINGS,
};

void sl_gbuffer_uniforms_init(sl_gbuffer_uniforms *u, mat4 model, mat4 view_proj, const sl_material *m)
{
    u->uModel = model;
    u->uViewProj = view_proj;
    u->uNormalMatrix = transpose(inverse(mat3_from_mat4(model)));
    u->uKd = m->kd;
    u->uKs = m->ks;
    u->uAlpha = m->alpha;
}

sl_target sl_gbuffer_target(sl_gbuffer *gb)
{
    return (sl_target){
        .width = gb->width,
        .height = gb->height,
        .texel_size = sizeof(sl_gbuffer_texel),
        .texels = gb->texels,
        .depth_offset = (long)offsetof(sl_gbuffer_texel, depth),
    };
}

mat4 sl_camera_view_proj(const sl_camera *cam, int width, int height)
{
    mat4 view = lookAt(cam->eye, cam->target, cam->up);
    mat4 proj = perspective(radians(cam->fovy_deg), (float)width / (float)height, cam->znear, cam->zfar);
    return mat4_mul(proj, view);
}

bool sl_raster_scene(sl_raster *r, const sl_scene *scene, const sl_camera *cam, sl_gbuffer *gb, sl_error *err)
{
    if (!gb->texels)
        return sl_fail(err, SL_ERR_RANGE, "raster: G-buffer not allocated (call sl_gbuffer_resize)");
    if (!(cam->znear > 0.0f) || !(cam->zfar > cam->znear) || !(cam->fovy_deg > 0.0f && cam->fovy_deg < 180.0f))
        return sl_fail(err, SL_ERR_RANGE, "raster: camera near %g, far %g, fovy %g: need 0 < near < far, 0 < fovy < 180",
                       (double)cam->znear, (double)cam->zfar, (double)cam->fovy_deg);
    sl_gbuffer_clear(gb);
    mat4 view_proj = sl_camera_view_proj(cam, gb->width, gb->height);
    sl_target target = sl_gbuffer_target(gb);
    for (int i = 0; i < scene->object_count; i++) {
        const sl_object *o = &scene->objects[i];
        if (o->mesh < 0 || o->mesh >= scene->mesh_count || o->material < 0 || o->material >= scene->material_count)
            return sl_fail(err, SL_ERR_RANGE, "raster: object %d (%s) names mesh %d / material %d out of range", i,
                           o->name, o->mesh, o->material);
        sl_gbuffer_uniforms u;
        sl_gbuffer_uniforms_init(&u, o->model, view_proj, &scene->materials[o->material]);
        sl_draw draw = {
            .program = &sl_gbuffer_program,
            .vs_uniforms = &u,
            .fs_uniforms = &u,
            .mesh = &scene->meshes[o->mesh],
            .cull = SL_CULL_NONE,
        };
        if (!sl_raster_draw(r, &target, &draw, err)) {
            sl_error_prefix(err, "object %d (%s): ", i, o->name);
            return false;
        }
    }
    return true;
}
