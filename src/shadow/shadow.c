/* shadow.c - the point lights' cube shadow maps: drawn with the tiled rasterizer and a
 * depth-only program, read with a slope-scaled, normal-offset, percentage-closer lookup
 * (shadow.h says what and why). */
#include "shadow.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The bias, in texel footprints at the receiver's depth, beyond the receiver plane's own depth
 * per tap: what separates the shaded normal's plane from the drawn triangles (a sphere's facets
 * under its interpolated normals, a normal map); and a share of the depth for the rasterizer's
 * interpolation of 1/w. */
#define SHADOW_BIAS_CONST 1.0f
#define SHADOW_DEPTH_REL 2e-4f
#define SHADOW_NORMAL_OFFSET 1.0f /* the receiver moved along its normal by this many texels */

/* The target's texel: the window depth the rasterizer tests, and the view depth kept. */
typedef struct {
    float depth;
    float view;
} shadow_texel;

static void shadow_vert(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    (void)varyings;
    *clip = mat4_mul_vec4(*(const mat4 *)uniforms, vec4_from3(in->position, 1.0f));
}

static void shadow_frag(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    (void)uniforms;
    shadow_texel *t = texel;
    t->depth = in->frag_coord.z;
    t->view = 1.0f / in->frag_coord.w; /* w_clip = the view depth along the face's axis */
}

static void shadow_frag_span(const void *uniforms, const sl_fragment_span *span)
{
    (void)uniforms;
    for (int j = 0; j < span->n; j++) {
        shadow_texel *t = (shadow_texel *)(void *)(span->row + (size_t)span->x[j] * span->texel_size);
        t->depth = span->frag_z[j];
        t->view = 1.0f / span->frag_w[j];
    }
}

static const sl_program shadow_program = {
    .vertex = shadow_vert,
    .fragment = shadow_frag,
    .varying_count = 0,
    .fragment_span = shadow_frag_span,
    .writes_depth = true,
};

bool sl_shadow_any(const sl_scene *scene, bool all)
{
    for (int i = 0; i < scene->light_count; i++)
        if (all || scene->lights[i].shadow)
            return true;
    return false;
}

/* GLSL: shadow_face_frame (one face's there). The six faces' frames: axis, then an up that is
 * not parallel to it; right = axis x up. */
static void face_frames(sl_shadow_maps *m)
{
    static const float axes[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int f = 0; f < 6; f++) {
        vec3 a = vec3(axes[f][0], axes[f][1], axes[f][2]);
        vec3 up0 = f >= 4 ? vec3(0, 1, 0) : vec3(0, 0, 1);
        vec3 right = normalize(cross(a, up0));
        m->axis[f] = a;
        m->right[f] = right;
        m->up[f] = cross(right, a);
    }
    m->side = SL_SHADOW_CUBE_SIZE + 2 * SL_SHADOW_GUARD;
    m->proj = (float)SL_SHADOW_CUBE_SIZE / (float)m->side;
}

/* view * projection of face f from light position L: view rows right, up, -axis (GL's camera
 * looks down -z), projection as sl_mat4_perspective's with x and y scaled by proj. */
static mat4 face_view_proj(const sl_shadow_maps *m, int f, vec3 L, float znear, float zfar)
{
    vec3 r = m->right[f], u = m->up[f], a = m->axis[f];
    mat4 view = {{{r.x, u.x, -a.x, 0}, {r.y, u.y, -a.y, 0}, {r.z, u.z, -a.z, 0}, {-dot(r, L), -dot(u, L), dot(a, L), 1}}};
    float fovy = 2.0f * atanf(1.0f / m->proj);
    return mat4_mul(sl_mat4_perspective(fovy, 1.0f, znear, zfar), view);
}

/* The depth range of a cube at L from the scene's box: far past its farthest corner, near a small
 * share of that (the window depth keeps ~1e-6 of far apart at the far end). False without
 * geometry. */
static bool cube_range(const sl_scene *scene, vec3 L, float *znear, float *zfar)
{
    vec3 lo, hi;
    if (!sl_scene_bounds(scene, &lo, &hi))
        return false;
    float far2 = 0.0f;
    for (int k = 0; k < 8; k++) {
        vec3 corner = vec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
        vec3 d = sub(corner, L);
        far2 = fmaxf(far2, dot(d, d));
    }
    *zfar = sqrtf(far2) * 1.01f + 1e-3f;
    *znear = *zfar * 1e-3f;
    return true;
}

static bool draw_cube(sl_shadow_maps *m, sl_shadow_cube *c, sl_raster *r, const sl_scene *scene, sl_draw *draws,
                      mat4 *mvp, shadow_texel *texels, sl_error *err)
{
    float znear, zfar;
    if (!cube_range(scene, c->position, &znear, &zfar))
        return true; /* no geometry: nothing casts, every depth stays +inf */
    const shadow_texel clear = {1.0f, INFINITY};
    size_t n = (size_t)m->side * (size_t)m->side;
    sl_target target = {.width = m->side, .height = m->side, .texel_size = sizeof(shadow_texel), .texels = texels,
                        .depth_offset = (long)offsetof(shadow_texel, depth)};
    for (int f = 0; f < 6; f++) {
        mat4 vp = face_view_proj(m, f, c->position, znear, zfar);
        int count = 0;
        for (int o = 0; o < scene->object_count; o++) {
            const sl_object *obj = &scene->objects[o];
            const sl_mesh *mesh = &scene->meshes[obj->mesh];
            if (mesh->triangle_count == 0)
                continue;
            mvp[count] = mat4_mul(vp, obj->model);
            draws[count] = (sl_draw){.program = &shadow_program, .vs_uniforms = &mvp[count], .mesh = mesh,
                                     .cull = SL_CULL_NONE, .clear = count == 0 ? &clear : NULL};
            count++;
        }
        if (count == 0) {
            for (size_t k = 0; k < n; k++)
                c->depth[f][k] = INFINITY;
            continue;
        }
        if (!sl_raster_draw_list(r, &target, draws, count, err))
            return false;
        for (size_t k = 0; k < n; k++)
            c->depth[f][k] = texels[k].view;
    }
    return true;
}

bool sl_shadow_build(sl_shadow_maps *m, sl_raster *r, const sl_scene *scene, bool all, sl_error *err)
{
    face_frames(m);
    size_t n = (size_t)m->side * (size_t)m->side;
    int objects = scene->object_count > 0 ? scene->object_count : 1;
    sl_draw *draws = malloc((size_t)objects * sizeof *draws);
    mat4 *mvp = malloc((size_t)objects * sizeof *mvp);
    shadow_texel *texels = malloc(n * sizeof *texels);
    bool ok = draws && mvp && texels;
    if (!ok)
        sl_fail(err, SL_ERR_MEMORY, "shadow maps: out of memory for a %dx%d face", m->side, m->side);
    m->count = scene->light_count;
    for (int i = 0; ok && i < scene->light_count; i++) {
        sl_shadow_cube *c = &m->cubes[i];
        c->casts = all || scene->lights[i].shadow;
        c->position = scene->lights[i].position;
        if (!c->casts)
            continue;
        for (int f = 0; f < 6 && ok; f++)
            if (!c->depth[f] && !(c->depth[f] = malloc(n * sizeof(float)))) {
                sl_fail(err, SL_ERR_MEMORY, "shadow maps: out of memory for light %d's cube (%d texels a side)", i,
                        m->side);
                ok = false;
            }
        ok = ok && draw_cube(m, c, r, scene, draws, mvp, texels, err);
    }
    free(draws);
    free(mvp);
    free(texels);
    return ok;
}

bool sl_shadow_face_view_proj(const sl_scene *scene, vec3 L, int f, mat4 *vp)
{
    sl_shadow_maps frames;
    face_frames(&frames);
    float znear, zfar;
    if (f < 0 || f >= 6 || !cube_range(scene, L, &znear, &zfar))
        return false;
    *vp = face_view_proj(&frames, f, L, znear, zfar);
    return true;
}

void sl_shadow_free(sl_shadow_maps *m)
{
    for (int i = 0; i < SL_LIGHTING_MAX_LIGHTS; i++)
        for (int f = 0; f < 6; f++)
            free(m->cubes[i].depth[f]);
    memset(m, 0, sizeof *m);
}

/* GLSL: shadow_major_face. The face whose axis is d's major axis (ties to the earlier face, as long as the lookup and
 * the guard band agree: either face holds the texels around the edge). */
static int major_face(vec3 d)
{
    float ax = fabsf(d.x), ay = fabsf(d.y), az = fabsf(d.z);
    if (ax >= ay && ax >= az)
        return d.x >= 0.0f ? 0 : 1;
    if (ay >= az)
        return d.y >= 0.0f ? 2 : 3;
    return d.z >= 0.0f ? 4 : 5;
}

/* GLSL: shadow_point_visibility (softlight-gl's maps, read with texelFetch) */
float sl_shadow_point_visibility(const sl_shadow_maps *m, int i, vec3 P, vec3 N)
{
    if (i < 0 || i >= m->count || !m->cubes[i].casts)
        return 1.0f;
    const sl_shadow_cube *c = &m->cubes[i];
    vec3 d = sub(P, c->position);
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0f))
        return 1.0f;
    float dist = sqrtf(dist2);
    /* one texel's footprint at the receiver: a face spans tan 2 / SIZE per texel, at view depth
     * up to dist */
    float texel = 2.0f * dist / (float)SL_SHADOW_CUBE_SIZE;
    vec3 q = add(d, scale(N, texel * SHADOW_NORMAL_OFFSET));
    int f = major_face(q);
    vec3 ax = m->axis[f], rt = m->right[f], up = m->up[f];
    float z = dot(q, ax);
    if (!(z > 0.0f))
        return 1.0f;
    float side = (float)m->side;
    /* texel coordinates, texel centres at integers */
    float ux = (m->proj * dot(q, rt) / z + 1.0f) * 0.5f * side - 0.5f;
    float uy = (m->proj * dot(q, up) / z + 1.0f) * 0.5f * side - 0.5f;
    float fx = floorf(ux), fy = floorf(uy);
    float tx = ux - fx, ty = uy - fy;
    int x0 = (int)fx - 1, y0 = (int)fy - 1;
    /* the receiver's plane (through q, normal N) along each tap's ray t (axis + cx right + cy up)
     * meets it at view depth N.q / N.(ray): each tap is compared with the receiver's own depth
     * along its ray, not with the centre's, so a tilted plane needs no slope-sized bias */
    float nq = dot(N, q), na = dot(N, ax), nr = dot(N, rt), nu = dot(N, up);
    float step = 2.0f / (side * m->proj); /* tangent units per texel */
    float cx0 = ((float)x0 + 0.5f) * step - 1.0f / m->proj, cy0 = ((float)y0 + 0.5f) * step - 1.0f / m->proj;
    float bias = texel * SHADOW_BIAS_CONST;
    /* a 3-texel box of bilinear comparisons: texels fx-1 .. fx+2 weighted (1-t, 1, 1, t) / 3 */
    const float wx[4] = {(1.0f - tx) / 3.0f, 1.0f / 3.0f, 1.0f / 3.0f, tx / 3.0f};
    const float wy[4] = {(1.0f - ty) / 3.0f, 1.0f / 3.0f, 1.0f / 3.0f, ty / 3.0f};
    int last = m->side - 1;
    const float *depth = c->depth[f];
    /* the guard band keeps the block inside the face but at the very edge of a face's frustum */
    bool inside = x0 >= 0 && y0 >= 0 && x0 + 3 <= last && y0 + 3 <= last;
    float vis = 0.0f;
    for (int b = 0; b < 4; b++) {
        int y = inside ? y0 + b : y0 + b < 0 ? 0 : y0 + b > last ? last : y0 + b;
        const float *row = depth + (size_t)y * (size_t)m->side;
        float ny = na + nu * (cy0 + (float)b * step);
        float rv = 0.0f;
        for (int a = 0; a < 4; a++) {
            int x = inside ? x0 + a : x0 + a < 0 ? 0 : x0 + a > last ? last : x0 + a;
            float nd = ny + nr * (cx0 + (float)a * step);
            /* open when the stored depth, less the bias, is beyond the receiver plane's depth
             * nq / nd along the tap's ray, multiplied out by nd < 0 (no division; an empty
             * texel's +inf gives -inf); a ray that never meets the plane (its horizon) is open */
            bool open = nd > -1e-6f || (row[x] * (1.0f + SHADOW_DEPTH_REL) + bias) * nd <= nq;
            rv += open ? wx[a] : 0.0f;
        }
        vis += rv * wy[b];
    }
    return fminf(vis, 1.0f);
}
