/* visibility.c - the scene's world-space triangles in Embree 3 and the ground truth's occlusion
 * queries (the contract is in visibility.h). Without SL_HAVE_EMBREE every entry point that
 * would trace fails with one message, so the library builds and the truth without visibility is
 * unchanged. */
#include "visibility.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/hash.h"
#include "../raster/coverage.h"

/* World positions as add_object gives them to Embree: model * p in float, as the vertex shader;
 * and each masked caster's mask (raster/coverage.h). */
uint64_t sl_visibility_scene_hash(const sl_scene *scene, const sl_scene_textures *tex)
{
    uint64_t h = SL_FNV1A_START;
    for (int o = 0; o < scene->object_count; o++) {
        const sl_object *obj = &scene->objects[o];
        if (!scene->meshes || obj->mesh < 0 || obj->mesh >= scene->mesh_count)
            continue;
        const sl_mesh *m = &scene->meshes[obj->mesh];
        h = sl_fnv1a(h, &o, sizeof o);
        for (int i = 0; i < m->vertex_count; i++) {
            vec4 w = mat4_mul_vec4(obj->model, vec4_from3(m->positions[i], 1.0f));
            const float xyz[3] = {w.x, w.y, w.z};
            h = sl_fnv1a(h, xyz, sizeof xyz);
        }
        if (m->triangle_count > 0 && m->indices)
            h = sl_fnv1a(h, m->indices, 3 * sizeof *m->indices * (size_t)m->triangle_count);
        sl_coverage c;
        if (obj->material >= 0 && obj->material < scene->material_count &&
            sl_coverage_of(&scene->materials[obj->material], tex, &c)) {
            h = sl_coverage_hash(h, &c);
            if (m->texcoords)
                h = sl_fnv1a(h, m->texcoords, sizeof *m->texcoords * (size_t)m->vertex_count);
        }
    }
    return h;
}

#ifdef SL_HAVE_EMBREE
#include <embree3/rtcore.h>

/* Embree reports errors through a callback: the first one is kept here, per structure. */
typedef struct {
    bool failed;
    char msg[200];
} vis_errors;

/* A masked caster's geometry: what its filter reads to find the hit's texture coordinate. */
typedef struct {
    sl_coverage coverage;
    const sl_vec2 *texcoords; /* the mesh's, per vertex; NULL: (0, 0) everywhere, as the raster has it */
    const uint32_t *indices;  /* the mesh's, 3 a triangle (Embree's primID indexes them) */
} masked_caster;

struct sl_visibility {
    RTCDevice device;
    RTCScene scene;
    vis_errors errors;
    long triangles;
    double extent; /* the largest absolute coordinate of any vertex */
    masked_caster *masked; /* one per object, used by the masked ones' filters */
};

/* Embree's filter for a masked caster, on both kinds of query: a hit where the mask cuts the
 * surface away is no hit (the ray goes on through the cut-out). The N hits come as structure of
 * arrays, each field N values (rtcore_ray.h's RTCHitN_* accessors, which are C++ only): Ng_x,
 * Ng_y, Ng_z, u, v, primID, ... */
static void masked_filter(const struct RTCFilterFunctionNArguments *args)
{
    const masked_caster *g = args->geometryUserPtr;
    const unsigned n = args->N;
    const float *hit = (const float *)(const void *)args->hit;
    const unsigned *prims = (const unsigned *)(const void *)args->hit + 5 * n;
    for (unsigned i = 0; i < n; i++) {
        if (args->valid[i] != -1)
            continue;
        unsigned prim = prims[i];
        float u = hit[3 * n + i], v = hit[4 * n + i];
        vec2 uv = vec2(0.0f, 0.0f);
        if (g->texcoords) {
            const uint32_t *t = g->indices + 3 * (size_t)prim;
            vec2 a = g->texcoords[t[0]], b = g->texcoords[t[1]], c = g->texcoords[t[2]];
            float w = 1.0f - u - v;
            uv = vec2(w * a.x + u * b.x + v * c.x, w * a.y + u * b.y + v * c.y);
        }
        if (!sl_coverage_keeps(&g->coverage, uv))
            args->valid[i] = 0;
    }
}

static void on_embree_error(void *user, enum RTCError code, const char *str)
{
    vis_errors *e = user;
    if (e->failed)
        return;
    e->failed = true;
    snprintf(e->msg, sizeof e->msg, "Embree error %d: %s", (int)code, str ? str : "(no message)");
}

bool sl_visibility_available(void) { return true; }

/* One object's triangles, transformed as the vertex shader places them, as one Embree geometry;
 * `masked` not NULL: a masked caster, filtered by its mask. */
static bool add_object(sl_visibility *v, const sl_mesh *m, mat4 model, const masked_caster *masked, double *extent,
                       sl_error *err)
{
    if (m->triangle_count <= 0 || m->vertex_count <= 0)
        return true;
    RTCGeometry g = rtcNewGeometry(v->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!g)
        return sl_fail(err, SL_ERR_MEMORY, "visibility: %s", v->errors.failed ? v->errors.msg : "no geometry");
    float *pos = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                         (size_t)m->vertex_count);
    unsigned *idx = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                            (size_t)m->triangle_count);
    if (!pos || !idx) {
        rtcReleaseGeometry(g);
        return sl_fail(err, SL_ERR_MEMORY, "visibility: no memory for %d vertices", m->vertex_count);
    }
    for (int i = 0; i < m->vertex_count; i++) {
        vec4 w = mat4_mul_vec4(model, vec4_from3(m->positions[i], 1.0f));
        pos[3 * i + 0] = w.x;
        pos[3 * i + 1] = w.y;
        pos[3 * i + 2] = w.z;
        for (int c = 0; c < 3; c++) {
            double a = fabs((double)pos[3 * i + c]);
            *extent = a > *extent ? a : *extent;
        }
    }
    for (size_t i = 0; i < 3 * (size_t)m->triangle_count; i++) {
        if (m->indices[i] >= (uint32_t)m->vertex_count) {
            rtcReleaseGeometry(g);
            return sl_fail(err, SL_ERR_RANGE, "visibility: index %u out of range (%d vertices)",
                           (unsigned)m->indices[i], m->vertex_count);
        }
        idx[i] = m->indices[i];
    }
    v->triangles += m->triangle_count;
    if (masked) {
        rtcSetGeometryUserData(g, (void *)masked);
        rtcSetGeometryIntersectFilterFunction(g, masked_filter);
        rtcSetGeometryOccludedFilterFunction(g, masked_filter);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(v->scene, g);
    rtcReleaseGeometry(g); /* the scene holds it */
    return true;
}

sl_visibility *sl_visibility_create(const sl_scene *scene, const sl_scene_textures *tex, int threads, sl_error *err)
{
    sl_visibility *v = calloc(1, sizeof *v);
    if (v)
        v->masked = calloc(scene->object_count > 0 ? (size_t)scene->object_count : 1, sizeof *v->masked);
    if (!v || !v->masked) {
        free(v);
        sl_fail(err, SL_ERR_MEMORY, "visibility: no memory");
        return NULL;
    }
    char config[64];
    snprintf(config, sizeof config, "threads=%d,set_affinity=0", threads > 0 ? threads : 1);
    v->device = rtcNewDevice(config);
    if (!v->device) {
        sl_fail(err, SL_ERR_RANGE, "visibility: Embree cannot create a device (error %d)", (int)rtcGetDeviceError(NULL));
        free(v);
        return NULL;
    }
    rtcSetDeviceErrorFunction(v->device, on_embree_error, &v->errors);
    v->scene = rtcNewScene(v->device);
    double extent = 0.0;
    bool ok = v->scene != NULL;
    if (ok) {
        rtcSetSceneBuildQuality(v->scene, RTC_BUILD_QUALITY_HIGH);
        rtcSetSceneFlags(v->scene, RTC_SCENE_FLAG_ROBUST); /* no cracks between a mesh's triangles */
    } else {
        sl_fail(err, SL_ERR_MEMORY, "visibility: %s", v->errors.failed ? v->errors.msg : "no scene");
    }
    for (int o = 0; ok && o < scene->object_count; o++) {
        const sl_object *obj = &scene->objects[o];
        if (obj->mesh < 0 || obj->mesh >= scene->mesh_count) {
            ok = sl_fail(err, SL_ERR_RANGE, "visibility: object %d (%s) names mesh %d out of range", o, obj->name,
                         obj->mesh);
            break;
        }
        const sl_mesh *mesh = &scene->meshes[obj->mesh];
        masked_caster *masked = &v->masked[o];
        bool cut = obj->material >= 0 && obj->material < scene->material_count &&
                   sl_coverage_of(&scene->materials[obj->material], tex, &masked->coverage);
        masked->texcoords = mesh->texcoords;
        masked->indices = mesh->indices;
        ok = add_object(v, mesh, obj->model, cut ? masked : NULL, &extent, err);
        if (!ok)
            sl_error_prefix(err, "object %d (%s): ", o, obj->name);
    }
    if (ok) {
        rtcCommitScene(v->scene);
        if (v->errors.failed)
            ok = sl_fail(err, SL_ERR_RANGE, "visibility: %s", v->errors.msg);
    }
    if (!ok) {
        sl_visibility_free(v);
        return NULL;
    }
    v->extent = extent;
    return v;
}

void sl_visibility_free(sl_visibility *v)
{
    if (!v)
        return;
    if (v->scene)
        rtcReleaseScene(v->scene);
    if (v->device)
        rtcReleaseDevice(v->device);
    free(v->masked);
    free(v);
}

long sl_visibility_triangle_count(const sl_visibility *v) { return v->triangles; }
double sl_visibility_offset(const sl_visibility *v, vec3 p)
{
    /* A G-buffer position's float error grows with its own coordinates and with those of the
     * triangle it was interpolated from (up to the extent), so the offset is relative to both.
     * Its floor near the origin, 1e-4 world units, shrinks with a scene under 10 units across to a
     * tenth of its extent: a scene modelled in millimetres gets the truth it has in metres. */
    double m = fmax(fabs((double)p.x), fmax(fabs((double)p.y), fabs((double)p.z)));
    return 1e-4 * fmax(fmin(1.0, 0.1 * v->extent), m) + 1e-6 * v->extent;
}

bool sl_visibility_surface(const sl_visibility *v, vec3 eye, vec3 p, double ng[3])
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    memset(&rh, 0, sizeof rh);
    rh.ray.org_x = eye.x;
    rh.ray.org_y = eye.y;
    rh.ray.org_z = eye.z;
    rh.ray.dir_x = p.x - eye.x; /* t = 1 at P */
    rh.ray.dir_y = p.y - eye.y;
    rh.ray.dir_z = p.z - eye.z;
    /* only what lies within 0.1% of P's distance: a triangle nearer the eye that the ray grazes
     * at a silhouette is not P's */
    rh.ray.tnear = 0.999f;
    rh.ray.tfar = 1.001f;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(v->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return false;
    double n[3] = {(double)rh.hit.Ng_x, (double)rh.hit.Ng_y, (double)rh.hit.Ng_z};
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0.0) || !isfinite(len))
        return false;
    double toward = n[0] * (double)rh.ray.dir_x + n[1] * (double)rh.ray.dir_y + n[2] * (double)rh.ray.dir_z;
    double s = toward > 0.0 ? -1.0 / len : 1.0 / len; /* the side the eye is on */
    for (int c = 0; c < 3; c++)
        ng[c] = n[c] * s;
    return true;
}

bool sl_visibility_occluded(const sl_visibility *v, const double org[3], const double dir[3], double tmax)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay ray;
    memset(&ray, 0, sizeof ray);
    ray.org_x = (float)org[0];
    ray.org_y = (float)org[1];
    ray.org_z = (float)org[2];
    ray.dir_x = (float)dir[0];
    ray.dir_y = (float)dir[1];
    ray.dir_z = (float)dir[2];
    ray.tnear = 0.0f;
    ray.tfar = isinf(tmax) ? INFINITY : (float)tmax;
    ray.mask = 0xffffffffu;
    rtcOccluded1(v->scene, &ctx, &ray);
    return ray.tfar < 0.0f; /* Embree sets tfar to -inf on a hit */
}

#else /* no Embree */

struct sl_visibility {
    int unused;
};

bool sl_visibility_available(void) { return false; }

sl_visibility *sl_visibility_create(const sl_scene *scene, const sl_scene_textures *tex, int threads, sl_error *err)
{
    (void)scene;
    (void)tex;
    (void)threads;
    sl_fail(err, SL_ERR_RANGE, "visibility needs Embree 3: this build has none (install libembree-dev and rebuild)");
    return NULL;
}

void sl_visibility_free(sl_visibility *v) { free(v); }
long sl_visibility_triangle_count(const sl_visibility *v) { (void)v; return 0; }
double sl_visibility_offset(const sl_visibility *v, vec3 p)
{
    (void)v;
    (void)p;
    return 0.0;
}

bool sl_visibility_surface(const sl_visibility *v, vec3 eye, vec3 p, double ng[3])
{
    (void)v;
    (void)eye;
    (void)p;
    (void)ng;
    return false;
}

bool sl_visibility_occluded(const sl_visibility *v, const double org[3], const double dir[3], double tmax)
{
    (void)v;
    (void)org;
    (void)dir;
    (void)tmax;
    return false;
}

#endif
