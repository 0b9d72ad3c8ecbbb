/* shadow.c - the point lights' cube shadow maps and the env lights' orthographic ones: drawn
 * with the tiled rasterizer and a depth-only program (its masked twin for a masked material,
 * which discards where the mask cuts the surface away: raster/coverage.h), read with a
 * slope-scaled, normal-offset, percentage-closer lookup (shadow.h says what and why). */
#include "shadow.h"

#include "ibl/ibl.h"
#include "raster/coverage.h"

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
#define SHADOW_NORMAL_OFFSET 1.0f /* the receiver moved along its normal by up to this many texels */

/* The target's texel: the window depth the rasterizer tests, and the view depth kept. */
typedef struct {
    float depth;
    float view;
} shadow_texel;

/* An object's uniforms in a depth pass: its model-view-projection (first: shadow_vert reads the
 * uniforms as one), set per draw, and whether it is a masked caster with its coverage lookup,
 * which depend on its material alone (casters_new). */
typedef struct {
    mat4 mvp;
    bool masked;
    sl_coverage coverage;
} caster_uniforms;

/* One caster_uniforms per object of the scene, its mask found once for every map a build draws
 * (raster/coverage.h; tex NULL: every caster opaque). NULL when out of memory. */
static caster_uniforms *casters_new(const sl_scene *scene, const sl_scene_textures *tex)
{
    int objects = scene->object_count > 0 ? scene->object_count : 1;
    caster_uniforms *casters = calloc((size_t)objects, sizeof *casters);
    for (int o = 0; casters && o < scene->object_count; o++)
        casters[o].masked = sl_coverage_of(&scene->materials[scene->objects[o].material], tex, &casters[o].coverage);
    return casters;
}

/* The opaque casters' vertex shader (shaders/shadow_depth.vert's position). */
static void shadow_vert(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    (void)varyings;
    *clip = mat4_mul_vec4(*(const mat4 *)uniforms, vec4_from3(in->position, 1.0f));
}

/* The masked casters' vertex shader: the same position, and the texture coordinate (GLSL:
 * shadow_depth.vert's vTexCoord). */
static void masked_vert(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    *clip = mat4_mul_vec4(((const caster_uniforms *)uniforms)->mvp, vec4_from3(in->position, 1.0f));
    varyings[0] = in->texcoord.x;
    varyings[1] = in->texcoord.y;
}

/* Whether a masked caster's fragment is cut away (GLSL: shadow_depth.frag's discard). */
static bool masked_away(const void *uniforms, const sl_fragment_in *in)
{
    const caster_uniforms *u = uniforms;
    if (sl_coverage_keeps(&u->coverage, vec2(in->varyings[0], in->varyings[1])))
        return false;
    discard(in);
    return true;
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

static void shadow_masked_frag(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    if (!masked_away(uniforms, in))
        shadow_frag(uniforms, in, texel);
}

static const sl_program shadow_masked_program = {
    .vertex = masked_vert,
    .fragment = shadow_masked_frag,
    .varying_count = 2,
    .discards = true,
    .writes_depth = true,
};

/* The orthographic maps' program: the window depth, linear in the depth along the map's axis
 * (an orthographic projection), kept in both fields. */
static void sun_frag(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    (void)uniforms;
    shadow_texel *t = texel;
    t->depth = t->view = in->frag_coord.z;
}

static void sun_frag_span(const void *uniforms, const sl_fragment_span *span)
{
    (void)uniforms;
    for (int j = 0; j < span->n; j++) {
        shadow_texel *t = (shadow_texel *)(void *)(span->row + (size_t)span->x[j] * span->texel_size);
        t->depth = t->view = span->frag_z[j];
    }
}

static const sl_program sun_program = {
    .vertex = shadow_vert,
    .fragment = sun_frag,
    .varying_count = 0,
    .fragment_span = sun_frag_span,
    .writes_depth = true,
};

static void sun_masked_frag(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    if (!masked_away(uniforms, in))
        sun_frag(uniforms, in, texel);
}

static const sl_program sun_masked_program = {
    .vertex = masked_vert,
    .fragment = sun_masked_frag,
    .varying_count = 2,
    .discards = true,
    .writes_depth = true,
};

/* A kind of map's two programs: for opaque casters and for masked ones. */
typedef struct {
    const sl_program *opaque, *masked;
} depth_programs;

static const depth_programs cube_programs = {&shadow_program, &shadow_masked_program};
static const depth_programs ortho_programs = {&sun_program, &sun_masked_program};

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

/* Draw every mesh of the scene through vp into a side x side target of shadow texels with a
 * depth-only program (the masked one for a masked caster: casters_new), the first draw clearing
 * it to "nothing" (+inf). The draw's count: 0 when no mesh has triangles (texels untouched), -1
 * on error (err set). draws and casters hold one per object. */
static int draw_depth(sl_raster *r, const sl_scene *scene, depth_programs programs, mat4 vp, int side,
                      shadow_texel *texels, sl_draw *draws, caster_uniforms *casters, sl_error *err)
{
    static const shadow_texel clear = {1.0f, INFINITY};
    sl_target target = {.width = side, .height = side, .texel_size = sizeof(shadow_texel), .texels = texels,
                        .depth_offset = (long)offsetof(shadow_texel, depth)};
    int count = 0;
    for (int o = 0; o < scene->object_count; o++) {
        const sl_object *obj = &scene->objects[o];
        const sl_mesh *mesh = &scene->meshes[obj->mesh];
        if (mesh->triangle_count == 0)
            continue;
        caster_uniforms *u = &casters[o];
        u->mvp = mat4_mul(vp, obj->model);
        draws[count] = (sl_draw){.program = u->masked ? programs.masked : programs.opaque, .vs_uniforms = u,
                                 .fs_uniforms = u, .mesh = mesh, .cull = SL_CULL_NONE,
                                 .clear = count == 0 ? &clear : NULL};
        count++;
    }
    if (count > 0 && !sl_raster_draw_list(r, &target, draws, count, err))
        return -1;
    return count;
}

static bool draw_cube(sl_shadow_maps *m, sl_shadow_cube *c, sl_raster *r, const sl_scene *scene, sl_draw *draws,
                      caster_uniforms *casters, shadow_texel *texels, sl_error *err)
{
    float znear, zfar;
    if (!cube_range(scene, c->position, &znear, &zfar))
        return true; /* no geometry: nothing casts, every depth stays +inf */
    size_t n = (size_t)m->side * (size_t)m->side;
    for (int f = 0; f < 6; f++) {
        mat4 vp = face_view_proj(m, f, c->position, znear, zfar);
        int count = draw_depth(r, scene, cube_programs, vp, m->side, texels, draws, casters, err);
        if (count < 0)
            return false;
        for (size_t k = 0; k < n; k++)
            c->depth[f][k] = count > 0 ? texels[k].view : INFINITY;
    }
    return true;
}

bool sl_shadow_build(sl_shadow_maps *m, sl_raster *r, const sl_scene *scene, const sl_scene_textures *tex, bool all,
                     sl_error *err)
{
    face_frames(m);
    size_t n = (size_t)m->side * (size_t)m->side;
    int objects = scene->object_count > 0 ? scene->object_count : 1;
    sl_draw *draws = malloc((size_t)objects * sizeof *draws);
    caster_uniforms *casters = casters_new(scene, tex);
    shadow_texel *texels = malloc(n * sizeof *texels);
    bool ok = draws && casters && texels;
    if (!ok)
        sl_fail(err, SL_ERR_MEMORY, "shadow maps: out of memory for a %dx%d face", m->side, m->side);
    m->count = scene->light_count;
    for (int i = 0; ok && i < scene->light_count; i++) {
        sl_shadow_cube *c = &m->cubes[i];
        c->casts = all || scene->lights[i].shadow;
        c->position = scene->lights[i].position;
        if (!c->casts)
            continue;
        if (!c->block && !(c->block = malloc(6 * n * sizeof(float)))) {
            sl_fail(err, SL_ERR_MEMORY, "shadow maps: out of memory for light %d's cube (%d texels a side)", i,
                    m->side);
            ok = false;
            break;
        }
        for (int f = 0; f < 6; f++)
            c->depth[f] = c->block + (size_t)f * n;
        ok = ok && draw_cube(m, c, r, scene, draws, casters, texels, err);
    }
    free(draws);
    free(casters);
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
        free(m->cubes[i].block);

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
    vec3 q = add(d, scale(N, texel * SHADOW_NORMAL_OFFSET * sl_shadow_offset_share(dot(N, d) / dist)));
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
    const int last = m->side - 1;
    const float *depth = c->depth[f];
    /* each column's and row's clamped index and share of N.(ray) once (the guard band keeps the
     * block inside the face, so the clamp bites only at the very edge of a face's frustum) */
    int xs[4], ys[4];
    float nx[4], ny[4];
    for (int a = 0; a < 4; a++) {
        xs[a] = x0 + a < 0 ? 0 : x0 + a > last ? last : x0 + a;
        ys[a] = y0 + a < 0 ? 0 : y0 + a > last ? last : y0 + a;
        nx[a] = nr * (cx0 + (float)a * step);
        ny[a] = na + nu * (cy0 + (float)a * step);
    }
    const float scale_rel = 1.0f + SHADOW_DEPTH_REL;
    float vis = 0.0f;
    for (int b = 0; b < 4; b++) {
        const float *row = depth + (size_t)ys[b] * (size_t)m->side;
        float rv = 0.0f;
        for (int a = 0; a < 4; a++) {
            float nd = ny[b] + nx[a];
            /* open when the stored depth, less the bias, is beyond the receiver plane's depth
             * nq / nd along the tap's ray, multiplied out by nd < 0 (no division; an empty
             * texel's +inf gives -inf); a ray that never meets the plane (its horizon) is open */
            int open = (nd > -1e-6f) | ((row[xs[a]] * scale_rel + bias) * nd <= nq);
            rv += open ? wx[a] : 0.0f;
        }
        vis += rv * wy[b];
    }
    return fminf(vis, 1.0f);
}

/* ---- the env lights' orthographic maps ---- */

/* Greedy clusters, brightest light first (env_lights.h keeps them sorted): a light joins the
 * first cluster whose seed is within SL_SHADOW_SUN_CLUSTER_DEG, else seeds one while there is
 * room, else stays unmapped. Directions in world space. */
static void cluster_lights(sl_shadow_suns *m, const vec3 *world, const sl_env_lights *lights)
{
    const float cos_max = cosf(radians(SL_SHADOW_SUN_CLUSTER_DEG));
    int seed[SL_SHADOW_SUN_MAX];
    vec3 sum[SL_SHADOW_SUN_MAX];
    m->count = 0;
    m->env_light_count = lights->count;
    for (int j = 0; j < lights->count; j++) {
        int c = -1;
        m->env_light_sun[j] = -1;
        if (!(sl_luminance(lights->radiance[j]) > 0.0f))
            continue; /* a black light (more asked than lit texels) adds nothing: no map */
        for (int k = 0; k < m->count && c < 0; k++)
            if (dot(world[seed[k]], world[j]) >= cos_max)
                c = k;
        if (c < 0 && m->count < SL_SHADOW_SUN_MAX) {
            c = m->count++;
            seed[c] = j;
            sum[c] = vec3s(0.0f);
            m->maps[c].lights = 0;
        }
        m->env_light_sun[j] = (signed char)c;
        if (c < 0)
            continue;
        sum[c] = add(sum[c], scale(world[j], sl_luminance(lights->radiance[j])));
        m->maps[c].lights++;
    }
    /* a cluster with too small a share of the environment's light gets no map: its lights stay
     * unshadowed (lights->share is the share of all the lights, spread in proportion to their
     * luminous power, radiance times node weight) */
    double power[SL_SHADOW_SUN_MAX] = {0.0}, all = 0.0;
    for (int j = 0; j < lights->count; j++) {
        double p = (double)sl_luminance(lights->radiance[j]);
        all += p > 0.0 ? p : 0.0;
        if (m->env_light_sun[j] >= 0)
            power[m->env_light_sun[j]] += p;
    }
    int kept = 0, to[SL_SHADOW_SUN_MAX];
    for (int c = 0; c < m->count; c++) {
        bool keep = all > 0.0 && lights->share * power[c] / all >= SL_SHADOW_SUN_MIN_SHARE;
        to[c] = keep ? kept : -1;
        if (keep) {
            seed[kept] = seed[c];
            sum[kept] = sum[c];
            m->maps[kept].lights = m->maps[c].lights;
            kept++;
        }
    }
    m->count = kept;
    for (int j = 0; j < lights->count; j++)
        if (m->env_light_sun[j] >= 0)
            m->env_light_sun[j] = (signed char)to[m->env_light_sun[j]];
    for (int c = 0; c < m->count; c++) {
        sl_shadow_sun *sun = &m->maps[c];
        float len = length(sum[c]);
        sun->dir = len > 0.0f ? scale(sum[c], 1.0f / len) : world[seed[c]];
        float cos_min = 1.0f;
        for (int j = 0; j < lights->count; j++)
            if (m->env_light_sun[j] == c)
                cos_min = fminf(cos_min, dot(world[j], sun->dir));
        cos_min = clamp(cos_min, -1.0f, 1.0f);
        sun->spread = sqrtf(fmaxf(1.0f - cos_min * cos_min, 0.0f)) / fmaxf(cos_min, 1e-6f);
    }
}

/* The map's frame and box: the scene's bounds in light space, a texel wider on each side so the
 * filter's taps at the edge read drawn texels, and a share deeper so nothing meets near or far. */
static void sun_frame(sl_shadow_sun *sun, vec3 lo, vec3 hi, int side)
{
    sun->size = side;
    vec3 a = scale(sun->dir, -1.0f);
    vec3 up0 = fabsf(a.z) > 0.99f ? vec3(0, 1, 0) : vec3(0, 0, 1);
    sun->axis = a;
    sun->right = normalize(cross(a, up0));
    sun->up = cross(sun->right, a);
    float mn[3] = {INFINITY, INFINITY, INFINITY}, mx[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int k = 0; k < 8; k++) {
        vec3 corner = vec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
        float v[3] = {dot(corner, sun->right), dot(corner, sun->up), dot(corner, a)};
        for (int i = 0; i < 3; i++) {
            mn[i] = fminf(mn[i], v[i]);
            mx[i] = fmaxf(mx[i], v[i]);
        }
    }
    float size = (float)side;
    float ex = fmaxf(mx[0] - mn[0], 1e-4f), ey = fmaxf(mx[1] - mn[1], 1e-4f), ez = fmaxf(mx[2] - mn[2], 1e-4f);
    float px = 2.0f * ex / size, py = 2.0f * ey / size, pz = 0.01f * ez + 1e-4f;
    sun->x0 = mn[0] - px;
    sun->y0 = mn[1] - py;
    sun->z0 = mn[2] - pz;
    sun->sx = ex + 2.0f * px;
    sun->sy = ey + 2.0f * py;
    sun->sz = ez + 2.0f * pz;
    sun->texel = fmaxf(sun->sx, sun->sy) / size;
    sun->stepx = sun->sx / size;
    sun->stepy = sun->sy / size;
}

/* world -> clip: x, y and the depth along the axis mapped linearly onto [-1, 1] (column-major) */
static mat4 sun_view_proj(const sl_shadow_sun *sun)
{
    float kx = 2.0f / sun->sx, ky = 2.0f / sun->sy, kz = 2.0f / sun->sz;
    vec3 r = scale(sun->right, kx), u = scale(sun->up, ky), a = scale(sun->axis, kz);
    return (mat4){{{r.x, u.x, a.x, 0}, {r.y, u.y, a.y, 0}, {r.z, u.z, a.z, 0},
                   {-sun->x0 * kx - 1.0f, -sun->y0 * ky - 1.0f, -sun->z0 * kz - 1.0f, 1}}};
}

bool sl_shadow_suns_frames(sl_shadow_suns *m, const sl_scene *scene, const sl_env_lights *lights,
                           float env_rotation_deg)
{
    m->count = 0;
    m->env_light_count = 0;
    if (!lights || lights->count < 1)
        return false;
    /* environment -> world: the transpose of the lighting's world -> environment rotation
     * (lighting_uniforms.c uEnvRotation), a turn by +rotation about +Z */
    float phi = radians(env_rotation_deg), c = cosf(phi), s = sinf(phi);
    vec3 world[SL_ENV_LIGHTS_MAX];
    for (int j = 0; j < lights->count; j++) {
        vec3 e = lights->dir[j];
        world[j] = vec3(c * e.x - s * e.y, s * e.x + c * e.y, e.z);
    }
    cluster_lights(m, world, lights);
    vec3 lo, hi;
    bool geometry = sl_scene_bounds(scene, &lo, &hi);
    for (int k = 0; k < m->count; k++)
        sun_frame(&m->maps[k], geometry ? lo : vec3s(0.0f), geometry ? hi : vec3s(0.0f), SL_SHADOW_SUN_SIZE);
    return geometry;
}

mat4 sl_shadow_sun_view_proj(const sl_shadow_sun *sun) { return sun_view_proj(sun); }

bool sl_shadow_ortho_frames(sl_shadow_sun *maps, int count, int size, const sl_scene *scene)
{
    vec3 lo, hi;
    bool geometry = sl_scene_bounds(scene, &lo, &hi);
    for (int k = 0; k < count; k++)
        sun_frame(&maps[k], geometry ? lo : vec3s(0.0f), geometry ? hi : vec3s(0.0f), size);
    return geometry;
}

bool sl_shadow_ortho_build(sl_shadow_sun *maps, int count, int size, sl_raster *r, const sl_scene *scene,
                           const sl_scene_textures *tex, sl_error *err)
{
    if (size < SL_SHADOW_TILE || size % SL_SHADOW_TILE != 0)
        return sl_fail(err, SL_ERR_RANGE, "shadow maps: an orthographic map of %d texels a side, not a multiple of %d",
                       size, SL_SHADOW_TILE);
    bool geometry = sl_shadow_ortho_frames(maps, count, size, scene);
    const size_t n = (size_t)size * (size_t)size;
    int objects = scene->object_count > 0 ? scene->object_count : 1;
    sl_draw *draws = malloc((size_t)objects * sizeof *draws);
    caster_uniforms *casters = casters_new(scene, tex);
    shadow_texel *texels = geometry ? malloc(n * sizeof *texels) : NULL;
    bool ok = draws && casters && (texels || !geometry);
    if (!ok)
        sl_fail(err, SL_ERR_MEMORY, "shadow maps: out of memory for a %dx%d orthographic map", size, size);
    for (int k = 0; ok && k < count; k++) {
        sl_shadow_sun *sun = &maps[k];
        if (!sun->depth && !(sun->depth = malloc(n * sizeof(float)))) {
            ok = sl_fail(err, SL_ERR_MEMORY, "shadow maps: out of memory for orthographic map %d", k);
            break;
        }
        if (!geometry) { /* nothing casts */
            for (size_t t = 0; t < n; t++)
                sun->depth[t] = INFINITY;
            continue;
        }
        int drawn = draw_depth(r, scene, ortho_programs, sun_view_proj(sun), size, texels, draws, casters, err);
        if (drawn < 0) {
            ok = false;
            break;
        }
        /* window depth -> depth along the axis, into tiles (sl_shadow_tile_index); the clear's
         * +inf stays */
        for (int y = 0; y < size; y++)
            for (int x = 0; x < size; x++) {
                const shadow_texel *t = &texels[(size_t)y * (size_t)size + (size_t)x];
                sun->depth[sl_shadow_tile_index(x, y, size)] = drawn > 0 ? sun->z0 + t->view * sun->sz : INFINITY;
            }
    }
    free(draws);
    free(casters);
    free(texels);
    return ok;
}

bool sl_shadow_suns_build(sl_shadow_suns *m, sl_raster *r, const sl_scene *scene, const sl_scene_textures *tex,
                          const sl_env_lights *lights, float env_rotation_deg, sl_error *err)
{
    sl_shadow_suns_frames(m, scene, lights, env_rotation_deg);
    if (m->count == 0)
        return true;
    bool ok = sl_shadow_ortho_build(m->maps, m->count, SL_SHADOW_SUN_SIZE, r, scene, tex, err);
    if (!ok)
        m->count = 0;
    return ok;
}

void sl_shadow_suns_free(sl_shadow_suns *m)
{
    for (int k = 0; k < SL_SHADOW_SUN_MAX; k++)
        free(m->maps[k].depth);
    memset(m, 0, sizeof *m);
}

/* GLSL: shadow_sun_visibility (softlight-gl's maps, read with texelFetch) */
float sl_shadow_sun_visibility(const sl_shadow_suns *m, int s, vec3 P, vec3 N)
{
    if (s < 0 || s >= m->count)
        return 1.0f;
    const sl_shadow_sun *sun = &m->maps[s];
    sl_shadow_ortho_at at;
    if (!sl_shadow_ortho_locate(sun, P, N, sun->texel * SHADOW_NORMAL_OFFSET, &at))
        return 1.0f; /* facing away from the lights, or off the map: nothing there casts */
    const float xq = at.xq, yq = at.yq, zq = at.zq, fx = at.fx, fy = at.fy, tx = at.tx, ty = at.ty;
    const float stepx = at.stepx, stepy = at.stepy, gx = at.gx, gy = at.gy;
    int x0 = (int)fx - 1, y0 = (int)fy - 1;
    float bias = sun->texel * SHADOW_BIAS_CONST + sun->sz * 1e-6f;
    const float wx[4] = {(1.0f - tx) / 3.0f, 1.0f / 3.0f, 1.0f / 3.0f, tx / 3.0f};
    const float wy[4] = {(1.0f - ty) / 3.0f, 1.0f / 3.0f, 1.0f / 3.0f, ty / 3.0f};
    const int last = sun->size - 1;
    /* each column's and row's offset from q and clamped index once: ((float)(x0 + a) + 0.5f) is
     * fx + (a - 1) + 0.5, formed in float (exact: |fx| < 1e6) rather than converted per tap */
    float dxs[4], dys[4];
    int xs[4];
    for (int a = 0; a < 4; a++) {
        xs[a] = x0 + a < 0 ? 0 : x0 + a > last ? last : x0 + a;
        dxs[a] = (fx + (float)(a - 1) + 0.5f) * stepx + sun->x0 - xq;
        dys[a] = (fy + (float)(a - 1) + 0.5f) * stepy + sun->y0 - yq;
    }
    float vis = 0.0f;
    for (int b = 0; b < 4; b++) {
        int y = y0 + b < 0 ? 0 : y0 + b > last ? last : y0 + b;
        float rv = 0.0f;
        for (int a = 0; a < 4; a++) {
            float receiver = zq + gx * dxs[a] + gy * dys[b];
            /* open when the stored depth, less the bias, is beyond the receiver's (+inf: empty) */
            rv += sun->depth[sl_shadow_tile_index(xs[a], y, sun->size)] + bias >= receiver ? wx[a] : 0.0f;
        }
        vis += rv * wy[b];
    }
    return fminf(vis, 1.0f);
}

/* One row of a lane's 4x4 taps (sl_shadow_sun_visibility's inner loop, written out: GCC does not
 * vectorize the loop over the points with loops inside): the sum of the columns' weights wx0 ..
 * wx3 whose stored depth d0 .. d3 (0 where not read), less the bias, lies beyond the receiver's
 * plane at (dx0 .. dx3, dy). */
__attribute__((always_inline)) static inline float sun_row(float d0, float d1, float d2, float d3, float bias,
                                                           float zq, float gx, float dx0, float dx1, float dx2,
                                                           float dx3, float gy, float dy, float wx0, float wx12,
                                                           float wx3)
{
    float rv = 0.0f;
    rv += d0 + bias >= zq + gx * dx0 + gy * dy ? wx0 : 0.0f;
    rv += d1 + bias >= zq + gx * dx1 + gy * dy ? wx12 : 0.0f;
    rv += d2 + bias >= zq + gx * dx2 + gy * dy ? wx12 : 0.0f;
    rv += d3 + bias >= zq + gx * dx3 + gy * dy ? wx3 : 0.0f;
    return rv;
}

/* A lane's texel cell along one axis: floorf(u) by truncation (exact below 2^24; it vectorizes
 * where floorf does not), as an index and as a float. */
__attribute__((always_inline)) static inline void lane_cell(float u, int *i, float *f)
{
    const int t = (int)u;
    const float ft = (float)t;
    const bool down = ft > u;
    *i = down ? t - 1 : t;
    *f = down ? ft - 1.0f : ft;
}

/* The 4x4 taps of SL_SHADOW_LANES lanes: where each reads (a vector loop), what it reads (taps_read,
 * plain loads), then the test (a vector loop). The reads are plain loads rather than the vector
 * loop's gathers, as the reflection occlusion's march: on cores whose gathers issue slowly they
 * cost less, and the bits are the same. */
typedef struct {
    int at[16][SL_SHADOW_LANES];   /* tap a + 4 b: column a, row b */
    float depth[16][SL_SHADOW_LANES];
} lane_taps;

static void taps_read(const float *texels, int count, lane_taps *t)
{
    for (int k = 0; k < 16; k++)
        for (int i = 0; i < count; i++)
            t->depth[k][i] = texels[t->at[k][i]];
}

/* sl_shadow_sun_visibility for `count` points (at most SL_SHADOW_LANES), a lane a point: its
 * operations in its order, its early returns as a `read` mask and floorf by truncation, so each
 * value is its bits. A lane not read (facing away from the lights, off the map) is 1 and takes
 * its taps as 0 (it reads texel 0); its indices are clamped onto the map all the same, from
 * coordinates held within 1e7 (NaN too), so nothing undefined is computed. */
__attribute__((noinline)) /* inlined into its caller's loop, clang does not vectorize it */
static void sun_visibility_run(const sl_shadow_suns *m, int s, int count, const float *px, const float *py,
                               const float *pz, const float *nx, const float *ny, const float *nz, float *vis)
{
    if (s < 0 || s >= m->count) {
        for (int i = 0; i < count; i++)
            vis[i] = 1.0f;
        return;
    }
    const sl_shadow_sun *sun = &m->maps[s];
    const float offset = sun->texel * SHADOW_NORMAL_OFFSET;
    const float bias = sun->texel * SHADOW_BIAS_CONST + sun->sz * 1e-6f;
    const float ax = sun->axis.x, ay = sun->axis.y, az = sun->axis.z;
    const float rx = sun->right.x, ry = sun->right.y, rz = sun->right.z;
    const float upx = sun->up.x, upy = sun->up.y, upz = sun->up.z;
    const float x0 = sun->x0, y0 = sun->y0, stepx = sun->stepx, stepy = sun->stepy;
    const int size = sun->size, last = sun->size - 1;
    /* the place, then the cells and taps, then the test: separate loops (with the place's
     * holding select and the cells' truncation in one loop, GCC moves the truncation into the
     * select's branch and does not vectorize) */
    float nas[SL_SHADOW_LANES], xqs[SL_SHADOW_LANES], yqs[SL_SHADOW_LANES], zqs[SL_SHADOW_LANES];
    float uxs[SL_SHADOW_LANES], uys[SL_SHADOW_LANES], fxs[SL_SHADOW_LANES], fys[SL_SHADOW_LANES];
    int reads[SL_SHADOW_LANES];
    lane_taps taps;
#pragma omp simd
    for (int i = 0; i < count; i++) {
        /* sl_shadow_ortho_locate */
        const float na = nx[i] * ax + ny[i] * ay + nz[i] * az;
        const float off = offset * sl_shadow_offset_share(na);
        const float qx = px[i] + nx[i] * off, qy = py[i] + ny[i] * off, qz = pz[i] + nz[i] * off;
        const float xq = qx * rx + qy * ry + qz * rz;
        const float yq = qx * upx + qy * upy + qz * upz;
        const float ux = (xq - x0) / stepx - 0.5f, uy = (yq - y0) / stepy - 0.5f;
        nas[i] = na;
        xqs[i] = xq;
        yqs[i] = yq;
        zqs[i] = qx * ax + qy * ay + qz * az;
        uxs[i] = fabsf(ux) < 1e7f ? ux : 1e7f;
        uys[i] = fabsf(uy) < 1e7f ? uy : 1e7f;
    }
#pragma omp simd
    for (int i = 0; i < count; i++) {
        int ix, iy;
        float fx, fy;
        lane_cell(uxs[i], &ix, &fx);
        lane_cell(uys[i], &iy, &fy);
        const bool read = (nas[i] < -1e-6f) & (fabsf(fx) < 1e6f) & (fabsf(fy) < 1e6f);
        /* the columns and rows ix - 1 .. ix + 2 and iy - 1 .. iy + 2 */
#pragma GCC unroll 4
        for (int b = 0; b < 4; b++) {
            const int r = sl_shadow_clamp_index(iy - 1 + b, last);
#pragma GCC unroll 4
            for (int a = 0; a < 4; a++)
                taps.at[a + 4 * b][i] = read ? sl_shadow_tile_index(sl_shadow_clamp_index(ix - 1 + a, last), r, size) : 0;
        }
        fxs[i] = fx;
        fys[i] = fy;
        reads[i] = read;
    }
    taps_read(sun->depth, count, &taps);
    float out[SL_SHADOW_LANES];
#pragma omp simd
    for (int i = 0; i < count; i++) {
        const float na = nas[i], xq = xqs[i], yq = yqs[i], zq = zqs[i], fx = fxs[i], fy = fys[i];
        const bool read = reads[i] != 0;
        const float tx = uxs[i] - fx, ty = uys[i] - fy;
        const float gx = -(nx[i] * rx + ny[i] * ry + nz[i] * rz) / na;
        const float gy = -(nx[i] * upx + ny[i] * upy + nz[i] * upz) / na;
        /* sl_shadow_sun_visibility's taps: each column's and row's offset from q, and the
         * box-tent weights */
        const float wx0 = (1.0f - tx) / 3.0f, wx3 = tx / 3.0f, wy0 = (1.0f - ty) / 3.0f, wy3 = ty / 3.0f;
        const float w12 = 1.0f / 3.0f;
        const float dx0 = (fx + -1.0f + 0.5f) * stepx + x0 - xq, dx1 = (fx + 0.0f + 0.5f) * stepx + x0 - xq;
        const float dx2 = (fx + 1.0f + 0.5f) * stepx + x0 - xq, dx3 = (fx + 2.0f + 0.5f) * stepx + x0 - xq;
        const float dy0 = (fy + -1.0f + 0.5f) * stepy + y0 - yq, dy1 = (fy + 0.0f + 0.5f) * stepy + y0 - yq;
        const float dy2 = (fy + 1.0f + 0.5f) * stepy + y0 - yq, dy3 = (fy + 2.0f + 0.5f) * stepy + y0 - yq;
#define SUN_TAP(k) (read ? taps.depth[k][i] : 0.0f)
#define SUN_ROW(b, dy)                                                                                            \
    sun_row(SUN_TAP(4 * (b)), SUN_TAP(4 * (b) + 1), SUN_TAP(4 * (b) + 2), SUN_TAP(4 * (b) + 3), bias, zq, gx, dx0, \
            dx1, dx2, dx3, gy, dy, wx0, w12, wx3)
        float v = 0.0f;
        v += SUN_ROW(0, dy0) * wy0;
        v += SUN_ROW(1, dy1) * w12;
        v += SUN_ROW(2, dy2) * w12;
        v += SUN_ROW(3, dy3) * wy3;
#undef SUN_ROW
#undef SUN_TAP
        v = v < 1.0f ? v : 1.0f; /* fminf: v is finite where read */
        out[i] = read ? v : 1.0f;
    }
    for (int i = 0; i < count; i++) /* through a local array: clang does not vectorize the loop
                                       storing through a pointer beside the maps' reads */
        vis[i] = out[i];
}

/* One row of a lane's 4x4 cube-map taps (sl_shadow_point_visibility's inner loop, written out):
 * the sum of the columns' weights wx0 .. wx3 whose tap is open, of stored depths d0 .. d3 (0
 * where not read), with N.(ray) ny + nx0 .. ny + nx3. */
__attribute__((always_inline)) static inline float cube_row(float d0, float d1, float d2, float d3, float scale_rel,
                                                            float bias, float nq, float ny, float nx0, float nx1,
                                                            float nx2, float nx3, float wx0, float wx12, float wx3)
{
    const float nd0 = ny + nx0, nd1 = ny + nx1, nd2 = ny + nx2, nd3 = ny + nx3;
    float rv = 0.0f;
    rv += ((nd0 > -1e-6f) | ((d0 * scale_rel + bias) * nd0 <= nq)) ? wx0 : 0.0f;
    rv += ((nd1 > -1e-6f) | ((d1 * scale_rel + bias) * nd1 <= nq)) ? wx12 : 0.0f;
    rv += ((nd2 > -1e-6f) | ((d2 * scale_rel + bias) * nd2 <= nq)) ? wx12 : 0.0f;
    rv += ((nd3 > -1e-6f) | ((d3 * scale_rel + bias) * nd3 <= nq)) ? wx3 : 0.0f;
    return rv;
}

/* sl_shadow_point_visibility for `count` points (at most SL_SHADOW_LANES), a lane a point, as
 * sun_visibility_run does it: its operations in its order (major_face as selects, the face's
 * frame from a table), its early returns as a `read` mask, floorf by truncation, the six faces
 * read through the cube's block by plain loads (lane_taps); each value its bits. A lane not read
 * is 1 and takes its taps as 0; its coordinates are held within 1e7 (NaN too) and its indices
 * clamped onto the face. */
__attribute__((noinline)) /* as sun_visibility_run */
static void point_visibility_run(const sl_shadow_maps *m, int light, int count, const float *px, const float *py,
                                 const float *pz, const float *nx, const float *ny, const float *nz, float *vis)
{
    if (light < 0 || light >= m->count || !m->cubes[light].casts) {
        for (int i = 0; i < count; i++)
            vis[i] = 1.0f;
        return;
    }
    const sl_shadow_cube *c = &m->cubes[light];
    const float lx = c->position.x, ly = c->position.y, lz = c->position.z;
    float fax[6], fay[6], faz[6], frx[6], fry[6], frz[6], fux[6], fuy[6], fuz[6];
    for (int f = 0; f < 6; f++) {
        fax[f] = m->axis[f].x, fay[f] = m->axis[f].y, faz[f] = m->axis[f].z;
        frx[f] = m->right[f].x, fry[f] = m->right[f].y, frz[f] = m->right[f].z;
        fux[f] = m->up[f].x, fuy[f] = m->up[f].y, fuz[f] = m->up[f].z;
    }
    const int side = m->side, last = m->side - 1, face_texels = m->side * m->side;
    const float sidef = (float)m->side, proj = m->proj;
    const float step = 2.0f / (sidef * proj), edge = 1.0f / proj;
    const float scale_rel = 1.0f + SHADOW_DEPTH_REL;
    /* the place (q, its face, depth and texel coordinates), the cells and taps, then the test:
     * separate loops, as in sun_visibility_run */
    float qxs[SL_SHADOW_LANES], qys[SL_SHADOW_LANES], qzs[SL_SHADOW_LANES];
    float texels[SL_SHADOW_LANES], uxs[SL_SHADOW_LANES], uys[SL_SHADOW_LANES];
    float fxs[SL_SHADOW_LANES], fys[SL_SHADOW_LANES];
    int faces[SL_SHADOW_LANES], seen[SL_SHADOW_LANES], xs[SL_SHADOW_LANES], ys[SL_SHADOW_LANES];
    lane_taps taps;
#pragma omp simd
    for (int i = 0; i < count; i++) {
        const float dx = px[i] - lx, dy = py[i] - ly, dz = pz[i] - lz;
        const float dist2 = dx * dx + dy * dy + dz * dz;
        const float dist = sqrtf(dist2 > 0.0f ? dist2 : 1.0f); /* where dist2 <= 0, not read */
        const float texel = 2.0f * dist / (float)SL_SHADOW_CUBE_SIZE;
        const float off = texel * SHADOW_NORMAL_OFFSET *
                          sl_shadow_offset_share((nx[i] * dx + ny[i] * dy + nz[i] * dz) / dist);
        const float qx = dx + nx[i] * off, qy = dy + ny[i] * off, qz = dz + nz[i] * off;
        /* major_face */
        const float ax = fabsf(qx), ay = fabsf(qy), az = fabsf(qz);
        const bool on_x = (ax >= ay) & (ax >= az), on_y = !on_x & (ay >= az);
        const int f = on_x ? (qx >= 0.0f ? 0 : 1) : on_y ? (qy >= 0.0f ? 2 : 3) : (qz >= 0.0f ? 4 : 5);
        const float z = qx * fax[f] + qy * fay[f] + qz * faz[f];
        const float ux = (proj * (qx * frx[f] + qy * fry[f] + qz * frz[f]) / z + 1.0f) * 0.5f * sidef - 0.5f;
        const float uy = (proj * (qx * fux[f] + qy * fuy[f] + qz * fuz[f]) / z + 1.0f) * 0.5f * sidef - 0.5f;
        qxs[i] = qx, qys[i] = qy, qzs[i] = qz, texels[i] = texel, faces[i] = f;
        seen[i] = (dist2 > 0.0f) & (z > 0.0f);
        uxs[i] = fabsf(ux) < 1e7f ? ux : 1e7f;
        uys[i] = fabsf(uy) < 1e7f ? uy : 1e7f;
    }
#pragma omp simd
    for (int i = 0; i < count; i++) {
        int ix, iy;
        float fx, fy;
        lane_cell(uxs[i], &ix, &fx);
        lane_cell(uys[i], &iy, &fy);
        const int x0 = ix - 1, y0 = iy - 1, base = faces[i] * face_texels;
#pragma GCC unroll 4
        for (int b = 0; b < 4; b++) {
            const int r = base + sl_shadow_clamp_index(y0 + b, last) * side;
#pragma GCC unroll 4
            for (int a = 0; a < 4; a++)
                taps.at[a + 4 * b][i] = seen[i] ? r + sl_shadow_clamp_index(x0 + a, last) : 0;
        }
        fxs[i] = fx, fys[i] = fy, xs[i] = x0, ys[i] = y0;
    }
    taps_read(c->block, count, &taps);
    float out[SL_SHADOW_LANES];
#pragma omp simd
    for (int i = 0; i < count; i++) {
        const int f = faces[i];
        const float qx = qxs[i], qy = qys[i], qz = qzs[i], fx = fxs[i], fy = fys[i];
        const bool read = seen[i] != 0;
        const float tx = uxs[i] - fx, ty = uys[i] - fy;
        const int x0 = xs[i], y0 = ys[i];
        const float nq = nx[i] * qx + ny[i] * qy + nz[i] * qz;
        const float na = nx[i] * fax[f] + ny[i] * fay[f] + nz[i] * faz[f];
        const float nr = nx[i] * frx[f] + ny[i] * fry[f] + nz[i] * frz[f];
        const float nu = nx[i] * fux[f] + ny[i] * fuy[f] + nz[i] * fuz[f];
        const float cx0 = ((float)x0 + 0.5f) * step - edge, cy0 = ((float)y0 + 0.5f) * step - edge;
        const float bias = texels[i] * SHADOW_BIAS_CONST;
        const float wx0 = (1.0f - tx) / 3.0f, wx3 = tx / 3.0f, wy0 = (1.0f - ty) / 3.0f, wy3 = ty / 3.0f;
        const float w12 = 1.0f / 3.0f;
        const float nx0 = nr * (cx0 + 0.0f * step), nx1 = nr * (cx0 + 1.0f * step);
        const float nx2 = nr * (cx0 + 2.0f * step), nx3 = nr * (cx0 + 3.0f * step);
        const float ny0 = na + nu * (cy0 + 0.0f * step), ny1 = na + nu * (cy0 + 1.0f * step);
        const float ny2 = na + nu * (cy0 + 2.0f * step), ny3 = na + nu * (cy0 + 3.0f * step);
#define CUBE_TAP(k) (read ? taps.depth[k][i] : 0.0f)
#define CUBE_ROW(b, ny)                                                                                         \
    cube_row(CUBE_TAP(4 * (b)), CUBE_TAP(4 * (b) + 1), CUBE_TAP(4 * (b) + 2), CUBE_TAP(4 * (b) + 3), scale_rel, \
             bias, nq, ny, nx0, nx1, nx2, nx3, wx0, w12, wx3)
        float v = 0.0f;
        v += CUBE_ROW(0, ny0) * wy0;
        v += CUBE_ROW(1, ny1) * w12;
        v += CUBE_ROW(2, ny2) * w12;
        v += CUBE_ROW(3, ny3) * wy3;
#undef CUBE_ROW
#undef CUBE_TAP
        v = v < 1.0f ? v : 1.0f; /* fminf: v is finite where read */
        out[i] = read ? v : 1.0f;
    }
    for (int i = 0; i < count; i++) /* through a local array: clang does not vectorize the loop
                                       storing through a pointer beside the maps' reads */
        vis[i] = out[i];
}

/* The lanes lookups of any number of points: runs of at most SL_SHADOW_LANES, each in one loop. */
void sl_shadow_sun_visibility_lanes(const sl_shadow_suns *m, int s, int count, const float *px, const float *py,
                                    const float *pz, const float *nx, const float *ny, const float *nz, float *vis)
{
    for (int i = 0; i < count; i += SL_SHADOW_LANES)
        sun_visibility_run(m, s, count - i < SL_SHADOW_LANES ? count - i : SL_SHADOW_LANES, px + i, py + i, pz + i,
                           nx + i, ny + i, nz + i, vis + i);
}

void sl_shadow_point_visibility_lanes(const sl_shadow_maps *m, int light, int count, const float *px,
                                      const float *py, const float *pz, const float *nx, const float *ny,
                                      const float *nz, float *vis)
{
    for (int i = 0; i < count; i += SL_SHADOW_LANES)
        point_visibility_run(m, light, count - i < SL_SHADOW_LANES ? count - i : SL_SHADOW_LANES, px + i, py + i,
                             pz + i, nx + i, ny + i, nz + i, vis + i);
}
