/* reflection.c - reflection occlusion (reflection.h): the lobe's rays traced against the G-buffer.
 *
 * The pass first reduces every texel to what a ray's test reads of it: its view depth, in a
 * plane of its own (every step reads it), beside it its tangent plane as the camera sees it (the
 * facing normal and its offset, 16 bytes) and its position, a plane a coordinate (the block's
 * test of the same surface reads them); then traces each texel's ray, rows over threads, into a
 * plane of one float a texel, its weight into another; then averages each texel's block, the
 * weights' sum in a plane of its own, and where the block counts fewer than SL_REFLECTION_LONE
 * rays adds the texel's own other rays (lone_rays), traced into a row of each thread's. 44 bytes
 * a texel in all, allocated for the frame. A ray's point is linear in t, so its view coordinates
 * are too: each step is three multiply-adds and one division. Each ray weighs its cosine to the
 * normal in the block's share, in a plane beside the rays'. Tracing and the block each have two
 * forms with the same bits: a reference for one texel (trace_ray, one ray at a time, and
 * block_visibility, which sl_reflection_texel runs; tests/unit/test_reflection.c holds the frame
 * to them), and the frame's. march_lanes steps up to MARCH_SPAN rays together, a lane a ray (a
 * run of a row's texels' own rays, or a row's lone texels' others): a ray's cost is the latency
 * of its reads of the depth plane at points strewn over the image, one after the other, and the
 * lanes issue theirs side by side, so the reads overlap. block_row tests one block member for a
 * whole row at a time, a vector loop. The reference builds each ray with ray_of, the frame a run
 * of a row's at a time with rays_of_span (ray_of's expressions in one vector loop; the lone
 * texels' few with ray_of); both test a candidate point with blocked_at. */
#include "reflection.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <softlight/lighting.h>

#include "core/threads.h"
#include "occlusion/gtao.h"
#include "occlusion/specular_occlusion.h"

/* clang honours `omp simd` too but does not vectorize rays_of_span's loop (its selects of vec3
 * values); that is a missed optimisation, not an error in a -Werror build. */
#ifdef __clang__
#pragma clang diagnostic ignored "-Wpass-failed"
#endif

/* A texel's tangent plane as the camera sees it: dot(n, X) = d with n facing the eye (all zero
 * for an empty texel). blocked_at and the block's test of "the same surface" read it. Its view
 * depth lies in a plane of its own, since every step reads that and few read more; the position
 * the block's test takes of a neighbour is the G-buffer texel's own. */
typedef struct sl_reflection_plane {
    float nx, ny, nz, d;
} surface_plane;

typedef struct {
    sl_gtao_view view;
    float half_width, half_height;
    float distance;
    int width, height;
    const float *depth;           /* each texel's view depth, +inf for an empty one (nothing there blocks) */
    const surface_plane *planes;  /* each texel's tangent plane */
    const float *px, *py, *pz;    /* each texel's position (the frame's block pass; NULL in the reference) */
    const sl_vec3 *facet;         /* the G-buffer's facet plane, or NULL: the normal rebuilt from positions */
    /* the ring's turns: the cosine and sine of ring ray k's phase about R, k = 1 .. 4 */
    float turn_cos[SL_REFLECTION_RAYS], turn_sin[SL_REFLECTION_RAYS];
} reflection_frame;

/* The covered texel t's tangent plane and, in *depth, its view depth. */
/* GLSL: reflection_surface */
static surface_plane plane_of(const sl_gbuffer_texel *t, const sl_gtao_view *view, float *depth)
{
    vec3 N = sl_lighting_facing_normal(t->normal, normalize(sub(view->eye, t->position)));
    *depth = dot(sub(t->position, view->eye), view->forward);
    return (surface_plane){N.x, N.y, N.z, dot(N, t->position)};
}

/* Each texel's tangent plane and view depth, rows y0 .. y1 - 1; with `position` not NULL its
 * position too, one plane a coordinate (position[0 .. 2]). */
static void planes_of_rows(const sl_gbuffer *gb, const sl_gtao_view *view, surface_plane *planes, float *depth,
                           float *const *position, int y0, int y1)
{
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < gb->width; x++) {
            size_t i = (size_t)y * (size_t)gb->width + (size_t)x;
            const sl_gbuffer_texel *t = &gb->texels[i];
            if (sl_gbuffer_covered(t)) {
                planes[i] = plane_of(t, view, &depth[i]);
            } else {
                planes[i] = (surface_plane){0.0f, 0.0f, 0.0f, 0.0f};
                depth[i] = INFINITY;
            }
            if (position) {
                position[0][i] = t->position.x;
                position[1][i] = t->position.y;
                position[2][i] = t->position.z;
            }
        }
}

/* A ray in the camera's frame: its start's view depth and screen-plane coordinates (z0, x0, y0)
 * and their rates along the ray (zr, xr, yr). */
typedef struct {
    float z0, zr, x0, xr, y0, yr;
} view_ray;

static view_ray view_ray_of(const sl_gtao_view *v, vec3 P, vec3 R)
{
    vec3 d0 = sub(P, v->eye);
    return (view_ray){dot(d0, v->forward), dot(R, v->forward), dot(d0, v->right),
                      dot(R, v->right),    dot(d0, v->up),      dot(R, v->up)};
}

/* The ray's length at step k (k = 1 .. SL_REFLECTION_STEPS), dense near its start. */
static float step_length(const reflection_frame *f, int k)
{
    float s = (float)k / (float)SL_REFLECTION_STEPS;
    return f->distance * s * s;
}

/* Whether the point at t along the ray from P along R, found within the thickness behind the
 * depth zc of texel c, is behind c's tangent plane: the ray is blocked there. */
static bool blocked_at(const surface_plane *c, float zc, vec3 P, vec3 R, float t)
{
    float Qx = P.x + R.x * t, Qy = P.y + R.y * t, Qz = P.z + R.z * t;
    float behind = c->nx * Qx + c->ny * Qy + c->nz * Qz - c->d;
    return behind < -SL_REFLECTION_PLANE_EPS * zc;
}

/* 1 when the ray from P along the unit R leaves the image, the camera's front or its length
 * unblocked; 0 at its first blocked point (reflection.h). The reference; march_lanes is the
 * frame's form. */
/* GLSL: reflection_trace_ray */
static float trace_ray(const reflection_frame *f, vec3 P, vec3 R)
{
    const sl_gtao_view *v = &f->view;
    view_ray r = view_ray_of(v, P, R);
    float prev_t = 0.0f;
    for (int k = 1; k <= SL_REFLECTION_STEPS; k++) {
        float t = step_length(f, k);
        float z = r.z0 + r.zr * t;
        if (!(z > 1e-4f))
            return 1.0f; /* behind the camera */
        float scale_px = v->pixels_per_unit / z;
        float px = f->half_width + (r.x0 + r.xr * t) * scale_px;
        float py = f->half_height + (r.y0 + r.yr * t) * scale_px;
        if (!(px >= 0.0f && py >= 0.0f && px < (float)f->width && py < (float)f->height))
            return 1.0f; /* off the image */
        size_t i = (size_t)(int)py * (size_t)f->width + (size_t)(int)px;
        float zc = f->depth[i];
        float thickness = fmaxf(t - prev_t, SL_REFLECTION_THICKNESS * zc);
        prev_t = t;
        if (!(z > zc && z < zc + thickness)) /* in front of it, too far behind it, or empty */
            continue;
        if (blocked_at(&f->planes[i], zc, P, R, t))
            return 0.0f;
    }
    return 1.0f;
}

/* The ray texel (x, y) traces: (x + 2 y) mod SL_REFLECTION_RAYS, so that a texel and its four
 * neighbours trace all five (reflection.h). */
static int ray_index(int x, int y) { return (x + 2 * y) % SL_REFLECTION_RAYS; }

/* The ring's angle about R for a lobe of roughness alpha (SL_REFLECTION_RING of the lobe's cone
 * angle), as its cosine and sine: all a ring ray takes of alpha. */
typedef struct {
    float cos, sin;
} ring_angle;

static ring_angle ring_angle_of(float alpha)
{
    float ring = SL_REFLECTION_RING * sl_so_lobe_cone(sl_lighting_lobe_param(alpha)).ts;
    return (ring_angle){cosf(ring), sinf(ring)};
}

/* ring_angle_of for the last alpha asked (its bits: -0 and 0 are two keys), recomputed when
 * alpha changes: a run of one material's texels pays for the power, arc cosine, cosine and sine
 * once. */
typedef struct {
    uint32_t alpha_bits;
    bool valid;
    ring_angle angle;
} ring_cache;

static ring_angle cached_ring_angle(ring_cache *c, float alpha)
{
    uint32_t bits;
    memcpy(&bits, &alpha, sizeof bits);
    if (!c->valid || bits != c->alpha_bits) {
        c->angle = ring_angle_of(alpha);
        c->alpha_bits = bits;
        c->valid = true;
    }
    return c->angle;
}

/* Along one image axis (dx, dy) from covered texel i at (x, y): the step across it, between its
 * two neighbours on the axis (a central difference) or between i and the one neighbour there is,
 * counting a neighbour that is covered and within the thickness in view depth
 * (SL_REFLECTION_THICKNESS of i's; farther, it is another surface, as the surface behind at a
 * silhouette). False where neither is. */
/* GLSL: reflection_axis_step */
static bool axis_step(const reflection_frame *f, const sl_gbuffer *gb, size_t i, int x, int y, int dx, int dy,
                      vec3 *step)
{
    const float z = f->depth[i], near = SL_REFLECTION_THICKNESS * z;
    vec3 ends[2] = {gb->texels[i].position, gb->texels[i].position};
    bool found = false;
    for (int side = 0; side < 2; side++) {
        int qx = x + (2 * side - 1) * dx, qy = y + (2 * side - 1) * dy;
        if (qx < 0 || qy < 0 || qx >= f->width || qy >= f->height)
            continue;
        size_t q = (size_t)qy * (size_t)f->width + (size_t)qx;
        if (fabsf(f->depth[q] - z) < near) { /* +inf for an empty neighbour */
            ends[side] = gb->texels[q].position;
            found = true;
        }
    }
    *step = sub(ends[1], ends[0]);
    return found;
}

/* Texel i's facet (the G-buffer's facet plane: 0 where the triangle spanned no plane). The GLSL
 * decodes it from the two channels GL packs it into. */
/* GLSL: facet_normal */
static inline vec3 facet_normal(const reflection_frame *f, size_t i) { return f->facet[i]; }

/* The geometric normal of covered texel i, facing the eye V: the surface the rasterizer drew,
 * which a smooth or normal-mapped N leans away from. The G-buffer's facet where it has the plane
 * (the triangle's own); else the normal of the plane its steps along x and y span (axis_step),
 * N where an axis has no step or the two span no plane. */
/* GLSL: reflection_geometric_normal */
static vec3 geometric_normal(const reflection_frame *f, const sl_gbuffer *gb, size_t i, vec3 V, vec3 N)
{
    if (f->facet) {
        const vec3 n = facet_normal(f, i);
        if (!(dot(n, n) > 0.0f))
            return N;
        return dot(n, V) < 0.0f ? scale(n, -1.0f) : n;
    }
    const int x = (int)(i % (size_t)f->width), y = (int)(i / (size_t)f->width);
    vec3 along_x, along_y;
    if (!axis_step(f, gb, i, x, y, 1, 0, &along_x) || !axis_step(f, gb, i, x, y, 0, 1, &along_y))
        return N;
    vec3 n = cross(along_x, along_y);
    float len = length(n);
    if (!(len > 0.0f))
        return N;
    n = scale(n, 1.0f / len);
    return dot(n, V) < 0.0f ? scale(n, -1.0f) : n;
}

/* Ring ray direction: R turned at the phase whose cosine and sine are turn_cos and turn_sin, in
 * the lobe's frame: T in the plane of incidence, from R towards N, and B = R x T across it. The
 * cone's angle ts (specular_occlusion.h) comes from the set's exponent about the half vector; the
 * reflection turns a half vector's small turn within the plane of incidence by twice it and one
 * across the plane by 2 (N.V) times it. So the lobe about R is an
 * ellipse, twice the cone in the plane and 2 N.V times it across (at a grazing view a floor's
 * lobe is a long, narrow streak), and the ring is that ellipse at the ring's angle:
 * normalize(R cos(ring) + (2 cos(phase) T + 2 N.V sin(phase) B) sin(ring)). At N.V = 1 (R on N:
 * no plane of incidence) the lobe is round and the helper axis's frame stands in. A build with
 * SL_REFLECTION_ELLIPSE 0 turns R on the round ring of the ring's angle instead. No branch: the
 * vector loop of rays_of_span runs it. */
/* GLSL: reflection_ring_direction */
__attribute__((always_inline)) static inline vec3 ring_direction(vec3 N, vec3 R, float n_dot_v, float turn_cos,
                                                                 float turn_sin, ring_angle ring)
{
    const vec3 toward_n = sub(N, scale(R, n_dot_v));
    const float len2 = dot(toward_n, toward_n);
    const vec3 helper = fabsf(R.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f);
    const vec3 T = len2 > SL_REFLECTION_PLANE_MIN ? scale(toward_n, 1.0f / sqrtf(len2)) : normalize(cross(R, helper));
    const vec3 B = cross(R, T);
    const float along = SL_REFLECTION_ELLIPSE ? 2.0f : 1.0f;
    const float across = SL_REFLECTION_ELLIPSE ? 2.0f * maxf(n_dot_v, 0.0f) : 1.0f;
    const vec3 side = add(scale(T, along * turn_cos), scale(B, across * turn_sin));
    return normalize(add(scale(R, ring.cos), scale(side, ring.sin)));
}

/* How far below the geometric normal's horizon a ray must point to enter the surface: none with
 * the facet plane (the triangle the visibility truth intersects), SL_REFLECTION_INTO_MARGIN with
 * the normal rebuilt from the positions, which is off by up to half the turn across the texels
 * it spans. */
static inline float into_margin(const reflection_frame *f) { return f->facet ? 0.0f : SL_REFLECTION_INTO_MARGIN; }

/* What ray_of found of a ray before any march: below the shading normal's horizon (not traced,
 * not counted), into the texel's own surface (below the geometric normal's horizon by more than
 * SL_REFLECTION_INTO_MARGIN, while above the shading normal's: blocked by it, not traced), or to
 * be traced. */
typedef enum { RAY_BELOW, RAY_INTO_SURFACE, RAY_TRACE } ray_start;

/* What a ray below the geometric normal's horizon is. With the facet plane the lighting leaves
 * every direction under the facet out of the lobe (src/shading/lighting_internal.h
 * shade_facet_hides), so the rays speak for the lobe's part above it: such a ray is not counted,
 * as one below the shading normal's horizon. With the normal rebuilt from positions the lighting
 * has no facet: the ray is blocked by the surface it enters. */
static inline ray_start under_surface(const reflection_frame *f) { return f->facet ? RAY_BELOW : RAY_INTO_SURFACE; }

/* Ray k of covered texel i (k = 0 along R, else on the ring at turn k - 1, `ring` the ring's
 * angle for the texel's alpha; reflection.h): its start P, unit direction and weight in the
 * block's share (its cosine to the normal, at least SL_REFLECTION_MIN_COSINE), and whether it is
 * traced (ray_start). A ray above the shading normal's horizon and below the geometric normal's
 * (geometric_normal; by more than SL_REFLECTION_INTO_MARGIN) enters the surface that the
 * rasterizer drew: blocked, as the visibility truth has it (a normal-mapped or smooth sphere's
 * rim, where N leans past the silhouette). The facing normal and the view depth are the texel's
 * plane's (plane_of), not formed again. */
/* GLSL: reflection_ray */
static ray_start ray_of(const reflection_frame *f, const sl_gbuffer *gb, size_t i, int k, ring_angle ring,
                        vec3 *P, vec3 *direction, float *weight)
{
    const sl_gbuffer_texel *t = &gb->texels[i];
    const surface_plane *plane = &f->planes[i];
    vec3 V = normalize(sub(f->view.eye, t->position));
    vec3 N = vec3(plane->nx, plane->ny, plane->nz);
    const float n_dot_v = dot(N, V);
    vec3 R = sub(scale(N, 2.0f * n_dot_v), V);
    vec3 Ng = geometric_normal(f, gb, i, V, N);
    const float margin = into_margin(f);
    *P = add(t->position, scale(N, SL_REFLECTION_OFFSET * f->depth[i]));
    if (k == 0) {
        *direction = R;
        *weight = maxf(dot(R, N), SL_REFLECTION_MIN_COSINE);
        return dot(R, Ng) < -margin ? under_surface(f) : RAY_TRACE;
    }
    vec3 Rk = ring_direction(N, R, n_dot_v, f->turn_cos[k], f->turn_sin[k], ring);
    float cosine = dot(Rk, N);
    *direction = Rk;
    *weight = maxf(cosine, SL_REFLECTION_MIN_COSINE);
    if (!(cosine > 0.0f))
        return RAY_BELOW;
    return dot(Rk, Ng) < -margin ? under_surface(f) : RAY_TRACE;
}

/* Whether ray k of covered texel i is open (1), blocked (0) or into its own surface
 * (SL_REFLECTION_INTO, blocked), or SL_REFLECTION_BELOW, traced alone, and its weight: the
 * reference. */
static float texel_ray(const reflection_frame *f, const sl_gbuffer *gb, size_t i, int k, float *weight)
{
    vec3 P, R;
    switch (ray_of(f, gb, i, k, ring_angle_of(gb->texels[i].alpha), &P, &R, weight)) {
    case RAY_BELOW: return SL_REFLECTION_BELOW;
    case RAY_INTO_SURFACE: return SL_REFLECTION_INTO;
    case RAY_TRACE: break;
    }
    return trace_ray(f, P, R);
}

/* Rays marched together, a lane a ray, structure-of-arrays: each lane's start and direction, its
 * view_ray, and where its outcome goes (1 set by whoever adds it; 0 written when it is blocked).
 * march_lanes runs trace_ray's steps for all of them with the same bits: a vector loop over the
 * lanes projects each one's point to the texel under it (trace_ray's expressions term by term;
 * the early exits as flags: a lane off the image or behind the camera reads texel 0 and leaves),
 * a plain loop reads the depths there, with no branch on what it read, so the reads of all lanes
 * are in flight at once, and a vector loop tests each point against its depth; a last loop
 * settles each lane still marching: it leaves open, or, when the point is within the thickness
 * behind the depth it read, blocked_at decides. The steps stop when no lane marches. A ray's cost
 * is the latency of its reads, one after the other; side by side, they overlap. The reads are
 * plain loads, not the vector loop's gather: as many loads, and on cores whose gathers issue
 * slowly the pass takes 0.89 of the time (pbr.json at 1280x720, medians of 5 alternated runs;
 * the same bits). */
enum { MARCH_SPAN = 128 };
typedef struct {
    float *out[MARCH_SPAN];
    vec3 start[MARCH_SPAN], dir[MARCH_SPAN];
    float z0[MARCH_SPAN], zr[MARCH_SPAN], sx0[MARCH_SPAN], sxr[MARCH_SPAN], sy0[MARCH_SPAN], syr[MARCH_SPAN];
    int lanes;
} ray_lanes;

static void march_lanes(const reflection_frame *f, ray_lanes *l)
{
    enum { S = MARCH_SPAN };
    /* per lane: whether it still marches; this step's outcome: it leaves (open), it is near a
     * surface, the texel it read, its point's view depth and the depth read there */
    int marching[S], leaves[S], near[S], read_at[S];
    float z_at[S], z_read[S];
    const int lanes = l->lanes;
    for (int m = 0; m < lanes; m++)
        marching[m] = 1;
    const sl_gtao_view *v = &f->view;
    const float ppu = v->pixels_per_unit, half_w = f->half_width, half_h = f->half_height;
    const float width = (float)f->width, height = (float)f->height;
    const int stride = f->width;
    const float *depth = f->depth;
    float prev_t = 0.0f;
    for (int k = 1, still = lanes; k <= SL_REFLECTION_STEPS && still > 0; k++) {
        const float t = step_length(f, k), step = t - prev_t;
        prev_t = t;
#pragma omp simd
        for (int m = 0; m < lanes; m++) {
            const float z = l->z0[m] + l->zr[m] * t;
            const float scale_px = ppu / z;
            const float px = half_w + (l->sx0[m] + l->sxr[m] * t) * scale_px;
            const float py = half_h + (l->sy0[m] + l->syr[m] * t) * scale_px;
            const int inside = (z > 1e-4f) & (px >= 0.0f) & (py >= 0.0f) & (px < width) & (py < height);
            /* the coordinates only where they are inside: no conversion of one that is not; an
             * int (at most SL_RASTER_MAX_SIZE^2 texels) */
            const int c = (int)(inside ? py : 0.0f) * stride + (int)(inside ? px : 0.0f);
            leaves[m] = !inside;
            read_at[m] = c;
            z_at[m] = z;
        }
        for (int m = 0; m < lanes; m++)
            z_read[m] = depth[read_at[m]];
#pragma omp simd
        for (int m = 0; m < lanes; m++) {
            const float z = z_at[m], zc = z_read[m];
            /* maxf, not trace_ray's fmaxf (which GCC does not vectorize): they differ only for a
             * NaN zc, where both tests below fail whatever the thickness, and in a zero's sign,
             * which zc + thickness does not carry into the test */
            const float thickness = maxf(step, SL_REFLECTION_THICKNESS * zc);
            near[m] = (z > zc) & (z < zc + thickness);
        }
        for (int m = 0; m < lanes; m++) {
            if (!marching[m])
                continue;
            if (leaves[m]) {
                marching[m] = 0;
                still--;
            } else if (near[m] && blocked_at(&f->planes[read_at[m]], depth[read_at[m]], l->start[m], l->dir[m], t)) {
                *l->out[m] = 0.0f;
                marching[m] = 0;
                still--;
            }
        }
    }
    l->lanes = 0;
}

/* A lane for the ray from P along R into l, its outcome to *out (set to 1 here); the lanes
 * marched first when they are full. */
static void march_add(const reflection_frame *f, ray_lanes *l, vec3 P, vec3 R, float *out)
{
    if (l->lanes == MARCH_SPAN)
        march_lanes(f, l);
    view_ray r = view_ray_of(&f->view, P, R);
    const int m = l->lanes++;
    *out = 1.0f;
    l->out[m] = out;
    l->start[m] = P;
    l->dir[m] = R;
    l->z0[m] = r.z0;
    l->zr[m] = r.zr;
    l->sx0[m] = r.x0;
    l->sxr[m] = r.xr;
    l->sy0[m] = r.y0;
    l->syr[m] = r.yr;
}

/* A ray as ray_of found it (`start_as`, from P along R, its weight in *weight) into *ray as
 * texel_ray finds it, with the same bits: SL_REFLECTION_BELOW (and weight 0) or 0 into its surface
 * at once, else a lane of l whose march writes it (1 open, 0 blocked). */
static void ray_into_lanes(const reflection_frame *f, ray_lanes *l, ray_start start_as, vec3 P, vec3 R, float *ray,
                           float *weight)
{
    switch (start_as) {
    case RAY_BELOW:
        *ray = SL_REFLECTION_BELOW;
        *weight = 0.0f;
        return;
    case RAY_INTO_SURFACE: *ray = 0.0f; return;
    case RAY_TRACE: march_add(f, l, P, R, ray); return;
    }
}

/* Ray k of covered texel i (ray_of, `ring` its ring angle) into *ray and *weight (ray_into_lanes). */
static void ray_to_lanes(const reflection_frame *f, const sl_gbuffer *gb, ray_lanes *l, size_t i, int k,
                         ring_angle ring, float *ray, float *weight)
{
    vec3 P, R;
    ray_start start_as = ray_of(f, gb, i, k, ring, &P, &R, weight);
    ray_into_lanes(f, l, start_as, P, R, ray, weight);
}

/* ray_of for the texels x0 .. x0 + n - 1 of row y (n at most MARCH_SPAN), each its own ray
 * (ray_index) at its ring angle (`ring_cos`, `ring_sin`), into structure-of-arrays: the start,
 * the direction, the weight and ray_start. ray_of's expressions term by term, with its branches
 * (an axis without a step, a plane that is none, the helper axis, ray 0 against the ring) as
 * selects of both results, so that one vector loop forms a run of rays with ray_of's bits; an
 * empty texel's lane holds what its zero plane gives and is not read. */
typedef struct {
    float px[MARCH_SPAN], py[MARCH_SPAN], pz[MARCH_SPAN], dx[MARCH_SPAN], dy[MARCH_SPAN], dz[MARCH_SPAN];
    float weight[MARCH_SPAN];
    int start[MARCH_SPAN];
} ray_starts;

static void rays_of_span(const reflection_frame *f, int y, int x0, int n, const int *k_of,
                         const float *ring_cos, const float *ring_sin, ray_starts *out)
{
    const int w = f->width, h = f->height;
    const int row = y * w; /* an int: at most SL_RASTER_MAX_SIZE^2 texels */
    const bool below = y > 0, above = y + 1 < h;
    const vec3 eye = f->view.eye;
    const float *depth = f->depth, *px = f->px, *py = f->py, *pz = f->pz;
    const sl_vec3 *facet = f->facet;
    const float margin = into_margin(f);
    const int under = under_surface(f);
#pragma omp simd
    for (int m = 0; m < n; m++) {
        const int x = x0 + m, k = k_of[m];
        const int i = row + x;
        const vec3 P = vec3(px[i], py[i], pz[i]); /* the G-buffer texel's position */
        const surface_plane *plane = &f->planes[i];
        const float z = depth[i], near = SL_REFLECTION_THICKNESS * z;
        vec3 V = normalize(sub(eye, P));
        vec3 N = vec3(plane->nx, plane->ny, plane->nz);
        const float n_dot_v = dot(N, V);
        vec3 R = sub(scale(N, 2.0f * n_dot_v), V);
        /* geometric_normal: the facet, or axis_step along x, then along y */
        /* the neighbours' texels read whether they are there or not (contiguous reads, not a
         * gather's): the planes' margins hold the rows above the first and below the last */
        const int ql = i - 1, qr = i + 1, qb = i - w, qa = i + w;
        const bool l = x > 0 && fabsf(depth[ql] - z) < near, r = x + 1 < w && fabsf(depth[qr] - z) < near;
        const bool b = below && fabsf(depth[qb] - z) < near, a = above && fabsf(depth[qa] - z) < near;
        const vec3 along_x = sub(r ? vec3(px[qr], py[qr], pz[qr]) : P, l ? vec3(px[ql], py[ql], pz[ql]) : P);
        const vec3 along_y = sub(a ? vec3(px[qa], py[qa], pz[qa]) : P, b ? vec3(px[qb], py[qb], pz[qb]) : P);
        vec3 g = cross(along_x, along_y);
        const float len = length(g);
        g = scale(g, 1.0f / len);
        g = dot(g, V) < 0.0f ? scale(g, -1.0f) : g;
        const vec3 rebuilt = (l || r) && (b || a) && len > 0.0f ? g : N;
        const vec3 fn = facet ? facet_normal(f, (size_t)i) : N;
        const vec3 facing = dot(fn, V) < 0.0f ? scale(fn, -1.0f) : fn;
        const vec3 Ng = !facet ? rebuilt : dot(fn, fn) > 0.0f ? facing : N;
        const vec3 start = add(P, scale(N, SL_REFLECTION_OFFSET * z));
        /* ray 0 along R; ray k on the ring */
        const float weight0 = maxf(dot(R, N), SL_REFLECTION_MIN_COSINE);
        const int start0 = dot(R, Ng) < -margin ? under : RAY_TRACE;
        const vec3 Rk = ring_direction(N, R, n_dot_v, f->turn_cos[k], f->turn_sin[k],
                                       (ring_angle){ring_cos[m], ring_sin[m]});
        const float cosine = dot(Rk, N);
        const float weightk = maxf(cosine, SL_REFLECTION_MIN_COSINE);
        const int startk = !(cosine > 0.0f)                               ? RAY_BELOW
                           : dot(Rk, Ng) < -margin ? under
                                                   : RAY_TRACE;
        const vec3 dir = k == 0 ? R : Rk;
        out->px[m] = start.x, out->py[m] = start.y, out->pz[m] = start.z;
        out->dx[m] = dir.x, out->dy[m] = dir.y, out->dz[m] = dir.z;
        out->weight[m] = k == 0 ? weight0 : weightk;
        out->start[m] = k == 0 ? start0 : startk;
    }
}

/* trace_ray for the rays of row y's texels (each its own, ray_index), written into ray_plane (1
 * for an empty texel, SL_REFLECTION_BELOW for a ray below its surface), with the same bits, and
 * each ray's weight into weight_plane (0 where none is traced): the rays formed a run at a time
 * (rays_of_span), and each that has something to trace takes a lane (march_lanes). */
static void march_row(const reflection_frame *f, const sl_gbuffer *gb, ring_cache *ring, float *ray_plane,
                      float *weight_plane, int y)
{
    ray_lanes l;
    l.lanes = 0;
    ray_starts rs;
    int k_of[MARCH_SPAN];
    float ring_cos[MARCH_SPAN], ring_sin[MARCH_SPAN];
    for (int x0 = 0; x0 < f->width; x0 += MARCH_SPAN) {
        const int n = f->width - x0 < MARCH_SPAN ? f->width - x0 : MARCH_SPAN;
        for (int m = 0; m < n; m++) {
            const sl_gbuffer_texel *t = &gb->texels[(size_t)y * (size_t)f->width + (size_t)(x0 + m)];
            k_of[m] = ray_index(x0 + m, y);
            ring_angle angle = k_of[m] != 0 && sl_gbuffer_covered(t) ? cached_ring_angle(ring, t->alpha)
                                                                      : (ring_angle){1.0f, 0.0f};
            ring_cos[m] = angle.cos;
            ring_sin[m] = angle.sin;
        }
        rays_of_span(f, y, x0, n, k_of, ring_cos, ring_sin, &rs);
        for (int m = 0; m < n; m++) {
            size_t i = (size_t)y * (size_t)f->width + (size_t)(x0 + m);
            ray_plane[i] = 1.0f;
            weight_plane[i] = 0.0f;
            if (!sl_gbuffer_covered(&gb->texels[i]))
                continue;
            weight_plane[i] = rs.weight[m];
            ray_into_lanes(f, &l, (ray_start)rs.start[m], vec3(rs.px[m], rs.py[m], rs.pz[m]),
                           vec3(rs.dx[m], rs.dy[m], rs.dz[m]), &ray_plane[i], &weight_plane[i]);
        }
    }
    march_lanes(f, &l);
}

/* Whether neighbour q is the same surface as texel p (indices into the image): covered, within
 * SL_REFLECTION_SAME_DEPTH of p's view depth from p's tangent plane, normals within
 * SL_REFLECTION_SAME_NORMAL. */
static bool same_surface(const reflection_frame *f, const sl_gbuffer *gb, size_t p, size_t q)
{
    if (!(f->depth[q] < INFINITY))
        return false;
    const surface_plane *a = &f->planes[p], *b = &f->planes[q];
    vec3 Q = gb->texels[q].position;
    float off = a->nx * Q.x + a->ny * Q.y + a->nz * Q.z - a->d;
    float cosn = a->nx * b->nx + a->ny * b->ny + a->nz * b->nz;
    return fabsf(off) < SL_REFLECTION_SAME_DEPTH * f->depth[p] && cosn > SL_REFLECTION_SAME_NORMAL;
}

const int sl_reflection_block_offsets[SL_REFLECTION_BLOCK][2] = {{0, 0},  {1, 0},  {-1, 0}, {0, 1},  {0, -1},
                                                                  {1, 1},  {-1, 1}, {1, -1}, {-1, -1}};

/* One ray into the reference's sums (the open rays' weights, all weights, the count) and its
 * report (each pointer NULL or where it goes): counted where `take` and not below its surface, a
 * ray into its surface as blocked, as the frame's plane has it. */
static void tally_ray(float ray, float weight, bool take, float *ray_out, float *weight_out, int *used_out,
                      float *open, float *total, int *count)
{
    take = take && ray != SL_REFLECTION_BELOW;
    float value = ray == SL_REFLECTION_INTO ? 0.0f : ray;
    if (ray_out)
        *ray_out = ray;
    if (weight_out)
        *weight_out = take ? weight : 0.0f;
    if (used_out)
        *used_out = take;
    *open += take ? value * weight : 0.0f;
    *total += take ? weight : 0.0f;
    *count += take;
}

/* The rays of covered texel i at (x, y) besides its own ray (ray_index), added to the block's
 * sums (open, total, count) where the block counts fewer than SL_REFLECTION_LONE: each ray,
 * its weight and whether it counted to `rays`, `weights` and `used` when not NULL
 * (SL_REFLECTION_RAYS - 1 long, in the order of k). The frame's block_row and the reference
 * block_visibility both end with it, so that their sums take the same terms in the same order. */
static void lone_rays(const reflection_frame *f, const sl_gbuffer *gb, size_t i, int x, int y, float *open,
                      float *total, int *count, float *rays, float *weights, int *used)
{
    const bool lone = *count < SL_REFLECTION_LONE;
    for (int k = 0, m = 0; k < SL_REFLECTION_RAYS; k++) {
        if (k == ray_index(x, y))
            continue;
        float weight = 0.0f;
        float ray = lone ? texel_ray(f, gb, i, k, &weight) : 1.0f;
        tally_ray(ray, weight, lone, rays ? &rays[m] : NULL, weights ? &weights[m] : NULL, used ? &used[m] : NULL,
                  open, total, count);
        m++;
    }
}

/* The visibility of covered texel (x, y) from the rays of its block (itself and the eight
 * neighbours that are the same surface), each traced here, and its own other rays where the
 * block counts fewer than SL_REFLECTION_LONE (lone_rays); and how many rays it took (1 ..
 * SL_REFLECTION_MEMBERS). Each ray, its weight and whether it counted go to `rays`, `weights`
 * and `used` when not NULL, in the order of sl_reflection_block_offsets and then lone_rays'.
 * The reference; block_row is the frame's. */
/* GLSL: reflection_visibility */
static vec2 block_visibility(const reflection_frame *f, const sl_gbuffer *gb, int x, int y, float *rays,
                             float *weights, int *used)
{
    const size_t p = (size_t)y * (size_t)f->width + (size_t)x;
    float open = 0.0f, total = 0.0f; /* the counted rays' weights: the open ones', all */
    int count = 0;
    for (int m = 0; m < SL_REFLECTION_BLOCK; m++) {
        int qx = x + sl_reflection_block_offsets[m][0], qy = y + sl_reflection_block_offsets[m][1];
        bool inside = qx >= 0 && qy >= 0 && qx < f->width && qy < f->height;
        size_t q = inside ? (size_t)qy * (size_t)f->width + (size_t)qx : 0;
        bool take = inside && (m == 0 || same_surface(f, gb, p, q));
        float weight = 0.0f;
        float ray = take ? texel_ray(f, gb, q, ray_index(qx, qy), &weight) : 1.0f;
        tally_ray(ray, weight, take, rays ? &rays[m] : NULL, weights ? &weights[m] : NULL, used ? &used[m] : NULL,
                  &open, &total, &count);
    }
    lone_rays(f, gb, p, x, y, &open, &total, &count, rays ? rays + SL_REFLECTION_BLOCK : NULL,
              weights ? weights + SL_REFLECTION_BLOCK : NULL, used ? used + SL_REFLECTION_BLOCK : NULL);
    return count > 0 ? vec2(open / total, count) : vec2(1.0f, 0.0f);
}

/* block_visibility of every texel of row y (vec2(1, 0) for an empty one) into `out`, from the
 * frame's planes of rays and weights, `total` the row's scratch for the weights' sums: the frame's
 * form, the same bits (each texel's sums add the members in the reference's order, then its own
 * other rays where the block counts fewer than SL_REFLECTION_LONE, as lone_rays). One loop a
 * block member along the row, each texel's plane beside its member's position, normal and ray,
 * so that every member's test of the same surface runs as a vector loop over the row where the
 * reference reads nine scattered texels a texel. The lone texels' own rays are marched together
 * (march_lanes), into `lone_ray` and `lone_weight`, SL_REFLECTION_RAYS - 1 a texel of the row.
 * Returns how many texels of the row are lone. */
static int block_row(const reflection_frame *f, const sl_gbuffer *gb, const float *ray_plane,
                     const float *weight_plane, int y, vec2 *out, float *total, ring_cache *ring, float *lone_ray,
                     float *lone_weight)
{
    const int w = f->width;
    const size_t row = (size_t)y * (size_t)w;
    const surface_plane *a = f->planes + row;
    const float *za = f->depth + row;
#pragma omp simd
    for (int x = 0; x < w; x++) { /* the texel itself, if its ray is not below its surface */
        float ray = ray_plane[row + (size_t)x], weight = weight_plane[row + (size_t)x];
        int take = ray >= 0.0f;
        out[x] = vec2(take ? ray * weight : 0.0f, (float)take);
        total[x] = take ? weight : 0.0f;
    }
    for (int m = 1; m < SL_REFLECTION_BLOCK; m++) {
        const int dx = sl_reflection_block_offsets[m][0], qy = y + sl_reflection_block_offsets[m][1];
        if (qy < 0 || qy >= f->height)
            continue;
        const size_t qrow = (size_t)qy * (size_t)w;
        const int x0 = dx < 0 ? -dx : 0, x1 = dx > 0 ? w - dx : w;
#pragma omp simd
        for (int x = x0; x < x1; x++) {
            const size_t q = qrow + (size_t)(x + dx);
            const surface_plane *b = &f->planes[q];
            /* same_surface's expressions, term by term */
            float off = a[x].nx * f->px[q] + a[x].ny * f->py[q] + a[x].nz * f->pz[q] - a[x].d;
            float cosn = a[x].nx * b->nx + a[x].ny * b->ny + a[x].nz * b->nz;
            float ray = ray_plane[q], weight = weight_plane[q];
            int take = (f->depth[q] < INFINITY) & (fabsf(off) < SL_REFLECTION_SAME_DEPTH * za[x]) &
                       (cosn > SL_REFLECTION_SAME_NORMAL) & (ray >= 0.0f);
            out[x].x += take ? ray * weight : 0.0f;
            out[x].y += (float)take;
            total[x] += take ? weight : 0.0f;
        }
    }
    enum { OTHERS = SL_REFLECTION_RAYS - 1 };
    ray_lanes lanes;
    lanes.lanes = 0;
    int lone = 0;
    for (int x = 0; x < w; x++) { /* the lone texels' own other rays, in lanes */
        const size_t i = row + (size_t)x;
        const sl_gbuffer_texel *t = &gb->texels[i];
        if (!sl_gbuffer_covered(t) || !(out[x].y < (float)SL_REFLECTION_LONE))
            continue;
        lone++;
        for (int k = 0, j = 0; k < SL_REFLECTION_RAYS; k++) {
            if (k == ray_index(x, y))
                continue;
            ring_angle angle = k != 0 ? cached_ring_angle(ring, t->alpha) : (ring_angle){1.0f, 0.0f};
            ray_to_lanes(f, gb, &lanes, i, k, angle, &lone_ray[x * OTHERS + j], &lone_weight[x * OTHERS + j]);
            j++;
        }
    }
    march_lanes(f, &lanes);
    for (int x = 0; x < w; x++) {
        const size_t i = row + (size_t)x;
        if (!sl_gbuffer_covered(&gb->texels[i])) {
            out[x] = vec2(1.0f, 0.0f);
            continue;
        }
        if (out[x].y < (float)SL_REFLECTION_LONE) /* lone_rays' sums, term by term */
            for (int j = 0; j < OTHERS; j++) {
                float ray = lone_ray[x * OTHERS + j], weight = lone_weight[x * OTHERS + j];
                int take = ray != SL_REFLECTION_BELOW;
                out[x].x += take ? ray * weight : 0.0f;
                total[x] += take ? weight : 0.0f;
                out[x].y += (float)take;
            }
        out[x] = out[x].y > 0.0f ? vec2(out[x].x / total[x], out[x].y) : vec2(1.0f, 0.0f);
    }
    return lone;
}

/* The ring rays' turns about R: ray k's phase 2 pi (k - 1) / 4 as its cosine and sine (ray 0,
 * along R, turns by none). */
static void ring_turns(float *turn_cos, float *turn_sin)
{
    turn_cos[0] = 1.0f;
    turn_sin[0] = 0.0f;
    for (int k = 1; k < SL_REFLECTION_RAYS; k++) {
        float phase = 2.0f * SL_PI * (float)(k - 1) / (float)(SL_REFLECTION_RAYS - 1);
        turn_cos[k] = cosf(phase);
        turn_sin[k] = sinf(phase);
    }
}

/* The frame's camera, image and rays; its planes and depth come from planes_of_rows (the caller
 * sets them). */
static reflection_frame frame_of(const sl_gbuffer *gb, const sl_camera *cam, float distance)
{
    reflection_frame f;
    f.view = sl_gtao_view_of(cam, gb->height);
    f.half_width = 0.5f * (float)gb->width;
    f.half_height = 0.5f * (float)gb->height;
    f.distance = distance;
    f.width = gb->width;
    f.height = gb->height;
    f.planes = NULL;
    f.depth = NULL;
    f.px = f.py = f.pz = NULL;
    f.facet = gb->facet;
    ring_turns(f.turn_cos, f.turn_sin);
    return f;
}

void sl_reflection_scratch_free(sl_reflection_scratch *s)
{
    free(s->planes);
    free(s->ray);
    free(s->weight);
    free(s->weight_sum);
    free(s->depth);
    for (int c = 0; c < 3; c++)
        free(s->position[c]);
    free(s->lone_rays);
    memset(s, 0, sizeof *s);
}

/* s with room for `texels` texels (the margins included) and `lone` floats of lone rows: kept
 * when it has it, else freed and allocated again (a frame's contents never carry over). */
static bool scratch_reserve(sl_reflection_scratch *s, size_t texels, size_t lone)
{
    if (s->planes && s->texels >= texels && s->lone >= lone)
        return true;
    sl_reflection_scratch_free(s);
    s->planes = malloc(texels * sizeof *s->planes);
    s->ray = malloc(texels * sizeof *s->ray);
    s->weight = malloc(texels * sizeof *s->weight);
    s->weight_sum = malloc(texels * sizeof *s->weight_sum);
    s->depth = malloc(texels * sizeof *s->depth);
    for (int c = 0; c < 3; c++)
        s->position[c] = malloc(texels * sizeof *s->position[c]);
    s->lone_rays = malloc(lone * sizeof *s->lone_rays);
    if (!s->planes || !s->ray || !s->weight || !s->weight_sum || !s->depth || !s->position[0] || !s->position[1] ||
        !s->position[2] || !s->lone_rays) {
        sl_reflection_scratch_free(s);
        return false;
    }
    s->texels = texels;
    s->lone = lone;
    return true;
}

bool sl_reflection_apply(sl_gbuffer *gb, const sl_camera *cam, float distance, int threads,
                         sl_reflection_scratch *scratch, int64_t *lone_texels, sl_error *err)
{
    if (!(distance > 0.0f) || !isfinite(distance))
        return sl_fail(err, SL_ERR_RANGE, "reflection occlusion: distance %g, expected a positive number",
                       (double)distance);
    const int width = gb->width, height = gb->height;
    size_t n = (size_t)width * (size_t)height;
    const int team = sl_threads(threads);
    /* the depth and position planes with a margin of a row and a texel each side, which
     * rays_of_span reads as the neighbours of the first and last rows' texels (empty there);
     * each thread's row of lone texels' own other rays and their weights (block_row) */
    const size_t margin = (size_t)width + 1;
    const size_t lone_row = (size_t)(SL_REFLECTION_RAYS - 1) * (size_t)(width > 0 ? width : 1);
    sl_reflection_scratch own = {0}, *s = scratch ? scratch : &own;
    if (!gb->reflection) /* the G-buffer frees it (sl_gbuffer_free, or a resize) */
        gb->reflection = malloc((n ? n : 1) * sizeof *gb->reflection);
    if (!gb->reflection || !scratch_reserve(s, n + 2 * margin, 2 * (size_t)team * lone_row))
        return sl_fail(err, SL_ERR_MEMORY, "reflection occlusion: out of memory for %dx%d", width, height);
    surface_plane *planes = s->planes;
    float *ray_plane = s->ray, *weight_plane = s->weight, *weight_sum = s->weight_sum, *lone = s->lone_rays;
    float *depth = s->depth + margin, *position[3];
    for (int c = 0; c < 3; c++)
        position[c] = s->position[c] + margin;
    for (size_t j = 0; j < margin; j++) {
        depth[-1 - (ptrdiff_t)j] = depth[n + j] = INFINITY;
        for (int c = 0; c < 3; c++)
            position[c][-1 - (ptrdiff_t)j] = position[c][n + j] = 0.0f;
    }
    reflection_frame f = frame_of(gb, cam, distance);
    f.planes = planes;
    f.depth = depth;
    int64_t lone_count = 0;
    f.px = position[0];
    f.py = position[1];
    f.pz = position[2];
    /* dynamic chunks: a row's cost follows what it covers, and a descheduled thread holds up
     * the barrier for one chunk at most */
#pragma omp parallel num_threads(team)
    {
#pragma omp for schedule(dynamic, 8)
        for (int y = 0; y < height; y++)
            planes_of_rows(gb, &f.view, planes, depth, position, y, y + 1);
        ring_cache ring = {0, false, {1.0f, 0.0f}};
#pragma omp for schedule(dynamic, 2)
        for (int y = 0; y < height; y++)
            march_row(&f, gb, &ring, ray_plane, weight_plane, y);
        float *lone_ray = lone + 2 * (size_t)omp_get_thread_num() * lone_row, *lone_weight = lone_ray + lone_row;
#pragma omp for schedule(dynamic, 8)
        for (int y = 0; y < height; y++) {
            int lone_in_row = block_row(&f, gb, ray_plane, weight_plane, y, gb->reflection + (size_t)y * (size_t)width,
                                        weight_sum + (size_t)y * (size_t)width, &ring, lone_ray, lone_weight);
            /* atomic, not a reduction clause: clang makes one a global lock symbol in the library
             * (tests/cli/exports.sh) */
#pragma omp atomic
            lone_count += lone_in_row;
        }
    }
    if (lone_texels)
        *lone_texels = lone_count;
    if (s == &own)
        sl_reflection_scratch_free(&own);
    return true;
}

vec2 sl_reflection_texel(const sl_gbuffer *gb, const sl_camera *cam, float distance, int x, int y, float *rays,
                         float *weights, int *used)
{
    size_t n = (size_t)gb->width * (size_t)gb->height;
    surface_plane *planes = malloc((n ? n : 1) * sizeof *planes);
    float *depth = malloc((n ? n : 1) * sizeof *depth);
    if (!planes || !depth) { /* trace and the tests only: an empty answer beats a crash */
        free(planes);
        free(depth);
        return vec2(NAN, 0.0f);
    }
    reflection_frame f = frame_of(gb, cam, distance);
    f.planes = planes;
    f.depth = depth;
    planes_of_rows(gb, &f.view, planes, depth, NULL, 0, gb->height);
    vec2 v = vec2(1.0f, 0.0f);
    if (sl_gbuffer_covered(sl_gbuffer_at(gb, x, y))) {
        v = block_visibility(&f, gb, x, y, rays, weights, used);
    } else {
        for (int m = 0; m < SL_REFLECTION_MEMBERS; m++) {
            if (rays)
                rays[m] = 1.0f;
            if (weights)
                weights[m] = 0.0f;
            if (used)
                used[m] = 0;
        }
    }
    free(planes);
    free(depth);
    return v;
}
