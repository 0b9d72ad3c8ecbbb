/* reflection.c - reflection occlusion (reflection.h): the lobe's rays traced against the G-buffer.
 *
 * The pass first reduces every texel to what a ray's test reads of it, its tangent plane as the
 * camera sees it (the facing normal and its offset) and its view depth, 20 bytes in one array;
 * then traces each texel's rays, rows over threads. A ray's point is linear in t, so its view
 * coordinates are too: each step is three multiply-adds and one division. */
#include "reflection.h"

#include <math.h>
#include <stdlib.h>

#include <softlight/lighting.h>

#include "core/threads.h"
#include "occlusion/gtao.h"
#include "occlusion/specular_occlusion.h"

/* What a ray reads of a texel: its view depth z (+inf for an empty texel: nothing there blocks),
 * in a plane of its own since every step reads it and few read more, and its tangent plane
 * dot(n, X) = d with n facing the eye and its position (for the cross's test of "the same
 * surface"). */
typedef struct {
    float nx, ny, nz, d;
    float px, py, pz, z;
} surface_plane;

typedef struct {
    sl_gtao_view view;
    float half_width, half_height;
    float distance;
    int width, height;
    const float *depth;           /* each texel's z */
    const surface_plane *planes;
} reflection_frame;

/* GLSL: reflection_surface */
static surface_plane plane_of(const sl_gbuffer_texel *t, const sl_gtao_view *view)
{
    surface_plane s = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, INFINITY};
    if (!sl_gbuffer_covered(t))
        return s;
    vec3 N = sl_lighting_facing_normal(t->normal, normalize(sub(view->eye, t->position)));
    s.nx = N.x;
    s.ny = N.y;
    s.nz = N.z;
    s.d = dot(N, t->position);
    s.z = dot(sub(t->position, view->eye), view->forward);
    s.px = t->position.x;
    s.py = t->position.y;
    s.pz = t->position.z;
    return s;
}

static void planes_of_rows(const sl_gbuffer *gb, const sl_gtao_view *view, surface_plane *planes, float *depth,
                           int y0, int y1)
{
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < gb->width; x++) {
            size_t i = (size_t)y * (size_t)gb->width + (size_t)x;
            planes[i] = plane_of(&gb->texels[i], view);
            depth[i] = planes[i].z;
        }
}

/* 1 when the ray from P along the unit R leaves the image, the camera's front or its length
 * unblocked; 0 at its first blocked point (reflection.h). */
/* GLSL: reflection_trace_ray */
static float trace_ray(const reflection_frame *f, vec3 P, vec3 R)
{
    const sl_gtao_view *v = &f->view;
    vec3 d0 = sub(P, v->eye);
    float z0 = dot(d0, v->forward), zr = dot(R, v->forward);
    float x0 = dot(d0, v->right), xr = dot(R, v->right);
    float y0 = dot(d0, v->up), yr = dot(R, v->up);
    float prev_t = 0.0f;
    for (int k = 1; k <= SL_REFLECTION_STEPS; k++) {
        float s = (float)k / (float)SL_REFLECTION_STEPS;
        float t = f->distance * s * s;
        float z = z0 + zr * t;
        if (!(z > 1e-4f))
            return 1.0f; /* behind the camera */
        float scale_px = v->pixels_per_unit / z;
        float px = f->half_width + (x0 + xr * t) * scale_px;
        float py = f->half_height + (y0 + yr * t) * scale_px;
        if (!(px >= 0.0f && py >= 0.0f && px < (float)f->width && py < (float)f->height))
            return 1.0f; /* off the image */
        size_t i = (size_t)(int)py * (size_t)f->width + (size_t)(int)px;
        float zc = f->depth[i];
        float thickness = fmaxf(t - prev_t, SL_REFLECTION_THICKNESS * zc);
        prev_t = t;
        if (!(z > zc && z < zc + thickness)) /* in front of it, too far behind it, or empty */
            continue;
        const surface_plane *c = &f->planes[i];
        float Qx = P.x + R.x * t, Qy = P.y + R.y * t, Qz = P.z + R.z * t;
        float behind = c->nx * Qx + c->ny * Qy + c->nz * Qz - c->d;
        if (behind < -SL_REFLECTION_PLANE_EPS * c->z)
            return 0.0f;
    }
    return 1.0f;
}

/* The ray texel (x, y) traces: (x + 2 y) mod SL_REFLECTION_RAYS, so that a texel and its four
 * neighbours trace all five (reflection.h). */
static int ray_index(int x, int y) { return (x + 2 * y) % SL_REFLECTION_RAYS; }

/* Whether ray k of the covered texel t is open (1) or blocked (0): k = 0 along R, else on the
 * ring at turn k - 1 (reflection.h). */
/* GLSL: reflection_ray */
static float texel_ray(const reflection_frame *f, const sl_gbuffer_texel *t, int k)
{
    const sl_gtao_view *v = &f->view;
    vec3 V = normalize(sub(v->eye, t->position));
    vec3 N = sl_lighting_facing_normal(t->normal, V);
    vec3 R = sub(scale(N, 2.0f * dot(N, V)), V);
    float depth = dot(sub(t->position, v->eye), v->forward);
    vec3 P = add(t->position, scale(N, SL_REFLECTION_OFFSET * depth));
    if (k == 0)
        return trace_ray(f, P, R);
    /* the ring about R at SL_REFLECTION_RING of the lobe's cone angle */
    float ring = SL_REFLECTION_RING * sl_so_lobe_cone(sl_lighting_lobe_param(t->alpha)).ts;
    vec3 helper = fabsf(R.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f);
    vec3 T = normalize(cross(R, helper)), B = cross(R, T);
    float phase = 2.0f * SL_PI * (float)(k - 1) / (float)(SL_REFLECTION_RAYS - 1);
    vec3 side = add(scale(T, cosf(phase)), scale(B, sinf(phase)));
    vec3 Rk = add(scale(R, cosf(ring)), scale(side, sinf(ring)));
    return dot(Rk, N) > 0.0f ? trace_ray(f, P, Rk) : 1.0f; /* below the surface: open */
}

/* Whether neighbour q is the same surface as texel p: covered, within SL_REFLECTION_SAME_DEPTH of
 * p's view depth from p's tangent plane, normals within SL_REFLECTION_SAME_NORMAL. */
static bool same_surface(const surface_plane *p, const surface_plane *q)
{
    if (!(q->z < INFINITY))
        return false;
    float off = p->nx * q->px + p->ny * q->py + p->nz * q->pz - p->d;
    float cosn = p->nx * q->nx + p->ny * q->ny + p->nz * q->nz;
    return fabsf(off) < SL_REFLECTION_SAME_DEPTH * p->z && cosn > SL_REFLECTION_SAME_NORMAL;
}

/* The visibility of covered texel (x, y) from the rays of its cross (itself and the four
 * neighbours that are the same surface), each given by `ray_of` (the frame's plane of them, or
 * traced here); each member's ray and whether it counted go to `rays` and `used` when not NULL,
 * in the order centre, +x, -x, +y, -y. */
/* GLSL: reflection_visibility */
static float cross_visibility(const reflection_frame *f, const sl_gbuffer *gb, const float *ray_plane, int x, int y,
                              float *rays, int *used)
{
    static const int dx[SL_REFLECTION_RAYS] = {0, 1, -1, 0, 0}, dy[SL_REFLECTION_RAYS] = {0, 0, 0, 1, -1};
    const surface_plane *p = &f->planes[(size_t)y * (size_t)f->width + (size_t)x];
    float sum = 0.0f;
    int count = 0;
    for (int m = 0; m < SL_REFLECTION_RAYS; m++) {
        int qx = x + dx[m], qy = y + dy[m];
        bool inside = qx >= 0 && qy >= 0 && qx < f->width && qy < f->height;
        size_t q = inside ? (size_t)qy * (size_t)f->width + (size_t)qx : 0;
        bool take = inside && (m == 0 || same_surface(p, &f->planes[q]));
        float ray = !take ? 1.0f : ray_plane ? ray_plane[q] : texel_ray(f, &gb->texels[q], ray_index(qx, qy));
        if (rays)
            rays[m] = ray;
        if (used)
            used[m] = take;
        sum += take ? ray : 0.0f;
        count += take;
    }
    return sum / (float)count;
}

static reflection_frame frame_of(const sl_gbuffer *gb, const sl_camera *cam, float distance,
                                 const surface_plane *planes, const float *depth)
{
    reflection_frame f;
    f.view = sl_gtao_view_of(cam, gb->height);
    f.half_width = 0.5f * (float)gb->width;
    f.half_height = 0.5f * (float)gb->height;
    f.distance = distance;
    f.width = gb->width;
    f.height = gb->height;
    f.planes = planes;
    f.depth = depth;
    return f;
}

bool sl_reflection_apply(sl_gbuffer *gb, const sl_camera *cam, float distance, int threads, sl_error *err)
{
    if (!(distance > 0.0f) || !isfinite(distance))
        return sl_fail(err, SL_ERR_RANGE, "reflection occlusion: distance %g, expected a positive number",
                       (double)distance);
    const int width = gb->width, height = gb->height;
    size_t n = (size_t)width * (size_t)height;
    surface_plane *planes = malloc((n ? n : 1) * sizeof *planes);
    float *ray_plane = malloc((n ? n : 1) * sizeof *ray_plane); /* each texel's own ray */
    float *depth = malloc((n ? n : 1) * sizeof *depth);
    if (!gb->reflection) /* the G-buffer frees it (sl_gbuffer_free, or a resize) */
        gb->reflection = malloc((n ? n : 1) * sizeof *gb->reflection);
    if (!planes || !ray_plane || !depth || !gb->reflection) {
        free(planes);
        free(ray_plane);
        free(depth);
        return sl_fail(err, SL_ERR_MEMORY, "reflection occlusion: out of memory for %dx%d", width, height);
    }
    reflection_frame f = frame_of(gb, cam, distance, planes, depth);
    /* dynamic chunks: a row's cost follows what it covers, and a descheduled thread holds up
     * the barrier for one chunk at most */
#pragma omp parallel num_threads(sl_threads(threads))
    {
#pragma omp for schedule(dynamic, 8)
        for (int y = 0; y < height; y++)
            planes_of_rows(gb, &f.view, planes, depth, y, y + 1);
#pragma omp for schedule(dynamic, 2)
        for (int y = 0; y < height; y++)
            for (int x = 0; x < width; x++) {
                size_t i = (size_t)y * (size_t)width + (size_t)x;
                const sl_gbuffer_texel *t = &gb->texels[i];
                ray_plane[i] = sl_gbuffer_covered(t) ? texel_ray(&f, t, ray_index(x, y)) : 1.0f;
            }
#pragma omp for schedule(dynamic, 8)
        for (int y = 0; y < height; y++)
            for (int x = 0; x < width; x++) {
                size_t i = (size_t)y * (size_t)width + (size_t)x;
                bool covered = sl_gbuffer_covered(&gb->texels[i]);
                gb->reflection[i] = covered ? cross_visibility(&f, gb, ray_plane, x, y, NULL, NULL) : 1.0f;
            }
    }
    free(planes);
    free(ray_plane);
    free(depth);
    return true;
}

float sl_reflection_texel(const sl_gbuffer *gb, const sl_camera *cam, float distance, int x, int y, float *rays,
                          int *used)
{
    size_t n = (size_t)gb->width * (size_t)gb->height;
    surface_plane *planes = malloc((n ? n : 1) * sizeof *planes);
    float *depth = malloc((n ? n : 1) * sizeof *depth);
    if (!planes || !depth) { /* trace and the tests only: an empty answer beats a crash */
        free(planes);
        free(depth);
        return NAN;
    }
    reflection_frame f = frame_of(gb, cam, distance, planes, depth);
    planes_of_rows(gb, &f.view, planes, depth, 0, gb->height);
    float v = 1.0f;
    if (sl_gbuffer_covered(sl_gbuffer_at(gb, x, y))) {
        v = cross_visibility(&f, gb, NULL, x, y, rays, used);
    } else {
        for (int m = 0; m < SL_REFLECTION_RAYS; m++) {
            if (rays)
                rays[m] = 1.0f;
            if (used)
                used[m] = 0;
        }
    }
    free(planes);
    free(depth);
    return v;
}
