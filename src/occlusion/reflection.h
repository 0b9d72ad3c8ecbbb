/* reflection.h - reflection occlusion: whether the specular lobe's rays leave the scene, traced
 * against the G-buffer in screen space.
 *
 * The ambient occlusion's cone (gtao.h, specular_occlusion.h) sees occluders within its radius
 * and summarizes them as one cone about the bent normal: a glossy floor beside a sphere, or a
 * mirror that reflects an object a few units away, keeps its whole reflection of the sky where
 * the truth shows the object's dark side. This pass follows the reflection itself. A texel's
 * lobe, with R = reflect(-V, N) and the lobe's cone of half-angle ts (specular_occlusion.h,
 * sl_so_lobe_cone: 75.6% of the lobe's energy), is probed by SL_REFLECTION_RAYS rays from P
 * (moved off the surface by a share of its view depth): ray 0 along R, rays 1 .. 4 on a ring at
 * SL_REFLECTION_RING of the lobe's reach about R at equal turns, two in the plane of incidence
 * and two across it: the lobe about R is an ellipse, 2 ts in the plane and 2 ts N.V across it,
 * since the cone is the lobe's about the half vector (SL_REFLECTION_ELLIPSE; a ray below the
 * surface is no part of the visibility: the integral has no light from below the horizon to
 * hide, and a grazing lobe's ring dips under it; counted as open it would dilute the share of
 * what is hidden). A ray above
 * N's horizon and below that of the geometric normal, the G-buffer's facet (the drawn
 * triangle's normal, sl_gbuffer.facet) or, without that plane, the normal of the plane the
 * G-buffer's positions span across P along x and y (its neighbours there within the thickness in
 * view depth; then by more than SL_REFLECTION_INTO_MARGIN), enters the surface the rasterizer
 * drew, which a normal-mapped or smooth N leans away from (at a sphere's rim, where N leans past
 * the silhouette), and is not traced. Under the facet it is not counted either: the lighting
 * leaves every direction under the facet out of the lobe itself (src/shading/lighting_internal.h
 * shade_facet_hides), so the rays speak for the part above it. Under the rebuilt normal, which
 * the lighting has no test for, it is blocked, as the visibility truth has it (its directions
 * below the geometric normal's horizon are unseen). Each texel
 * (x, y) traces one of them, ray (x + 2 y) mod 5, so that it and its four neighbours trace all
 * five; its visibility is the share of open rays over its block, the texel and the eight around it
 * (SL_REFLECTION_BLOCK), each ray weighted by its cosine to the normal of the texel that traced it
 * (the light along it reaches the surface by that cosine, so that a lobe's rays near the horizon,
 * at a grazing view, count for less than those above them), counting a neighbour only where it is
 * the same surface (near the texel's tangent plane, its normal within a few degrees): one ray a
 * texel, the five directions over a block of a flat or finely drawn surface (the ring's twice,
 * R's once). Where the block counts fewer than SL_REFLECTION_LONE rays (an edge, a normal map's
 * bumps: the normal turns fast across a texel), the texel traces its own other four too, so its
 * visibility is over its five rays rather than its one ray's 0 or 1. The
 * block rather than the cross of five: at an object's silhouette over a floor, where the cross
 * keeps two or three of its members, the block keeps five or more, so the rays decide rather
 * than the cone (below), and its nine rays are less noisy than five. Each ray takes
 * SL_REFLECTION_STEPS points at t = D (k / steps)^2, k = 1 .. steps (dense near P, where
 * contact matters), projects each into the image and reads the texel there: the ray is blocked
 * when the point lies behind that texel's tangent plane (as the camera sees it) and less than a
 * thickness behind it along the view (the larger of the step and SL_REFLECTION_THICKNESS of the
 * texel's view depth: what the G-buffer cannot know, how deep the surface goes). A ray that leaves
 * the image, passes behind the camera or runs its length is open. The texel's visibility is
 * the weighted share of open rays, in [0, 1], kept with the number of rays it is over (1 .. 13;
 * none, and visibility 1, where every ray of the block is below its surface).
 *
 * The lighting multiplies the image-based specular by it. With the ambient occlusion's cone
 * (specular_occlusion.h), both estimate the same share, and the rays' count says which to
 * believe (sl_reflection_specular_factor): with five rays or more, the rays alone, since they
 * test the lobe's own directions where the cone only compares two cones (beside a ball on a
 * glossy floor the cone closes over a lobe that passes the ball; a lone texel's own five rays
 * count as five); with one ray, on a sliver of a surface a texel or two wide whose other rays dip
 * below it, the smaller of the two factors, since one ray says
 * little and the cone sees the occluders around the point; between, the two mixed by the count.
 * Measured on the shipped scenes against the visibility truth: docs/lighting.md "Reflection
 * occlusion".
 *
 * The tangent-plane test, not a depth comparison: at a grazing view a texel spans a long stretch
 * of depth, and a ray rising slowly from a floor is behind the depth of the texel it crosses
 * while still above the floor.
 *
 * Consumes: a G-buffer (row 0 = bottom) and the camera that drew it. Produces: the plane
 * sl_gbuffer.reflection (allocated the first time; an empty texel gets (1, 0)).
 * shaders/lighting.frag's reflection_visibility is the GLSL twin (softlight-gl), run per pixel in
 * the lighting pass with these constants, and reflection_specular_factor the join's.
 *
 * Does not: see what the G-buffer does not hold (off screen, behind another surface, behind the
 * camera: counted open), or the occluder's radiance (an occluded ray is dark, as the visibility
 * truth has it). docs/lighting.md "Reflection occlusion" measures it. */
#ifndef SL_REFLECTION_H
#define SL_REFLECTION_H

#include <stdbool.h>
#include <stdint.h>

#include "core/error.h"
#include "raster/gbuffer.h"
#include "scene/scene.h"

#define SL_REFLECTION_RAYS 5          /* R and SL_REFLECTION_RAYS - 1 on the ring */
#define SL_REFLECTION_BLOCK 9         /* the texels whose rays a texel's visibility is over: 3x3 */
#define SL_REFLECTION_BELOW (-1.0f)   /* a ray's value below the surface (not counted), else 1 or 0 */
#define SL_REFLECTION_INTO (-2.0f)    /* sl_reflection_texel's value of a ray into its own surface
                                         under the rebuilt normal (blocked, counted as 0; the
                                         frame's plane holds 0); under the facet a ray is
                                         SL_REFLECTION_BELOW */
/* points along a ray (docs/lighting.md "Reflection occlusion", why 16; a build defining another
 * is for that comparison, the GLSL twin does not follow it) */
#ifndef SL_REFLECTION_STEPS
#define SL_REFLECTION_STEPS 16
#endif
/* the ring's angle, a share of the lobe's cone angle (docs/lighting.md "Reflection occlusion",
 * why half; a build defining another is for bench/visibility-variants.sh's comparison) */
#ifndef SL_REFLECTION_RING
#define SL_REFLECTION_RING 0.5f
#endif
/* The ring in the lobe's frame: the ellipse of the lobe about R, twice the cone's angle in the
 * plane of incidence and 2 N.V times it across, as a microfacet lobe's reflection is
 * (reflection.c ring_direction; docs/lighting.md "Reflection occlusion", why; a build defining 0,
 * the round ring at the ring's angle, is for bench/visibility-variants.sh's comparison) */
#ifndef SL_REFLECTION_ELLIPSE
#define SL_REFLECTION_ELLIPSE 1
#endif
/* R on N within this (the squared sine of the angle between them): no plane of incidence */
#define SL_REFLECTION_PLANE_MIN 1e-6f
#define SL_REFLECTION_THICKNESS 0.1f  /* a surface's assumed depth, a share of its view depth */
#define SL_REFLECTION_OFFSET 0.002f   /* the rays' start off the surface, a share of its view depth */
#define SL_REFLECTION_PLANE_EPS 0.003f /* "behind the plane": more than this share of its view depth */
#define SL_REFLECTION_MIN_COSINE 1e-6f /* a ray's least weight: R at a silhouette (N.V = 0) counts */
/* How far below the rebuilt geometric normal's horizon (the cosine) a ray must run to be taken
 * into its surface (none below the facet's): the normal rebuilt across a texel or two of a curved
 * surface is off by up to half the turn across them, most at a silhouette, where a texel spans a
 * wide arc. With no margin, at
 * 160x90, rays at the rims of three shipped scenes' spheres are blocked where the truth finds
 * them open; with 0.15 none is, and model.json's pixels more than 8/255 off fall from 6.1% to
 * 5.2% (docs/lighting.md "Reflection occlusion"). */
#define SL_REFLECTION_INTO_MARGIN 0.15f
/* The block's test of "the same surface": within this share of the view depth of the texel's
 * tangent plane, and normals within this cosine (3.6 degrees): a neighbour's ray stands for the
 * texel's only where their reflections are within twice that. Looser, a rounded edge lends its
 * neighbours' rays, turned twice as far as their normals, into the floor beside it (0.8, the
 * ambient occlusion blur's, put model.json's visibility error at 0.186 against 0.103). */
#define SL_REFLECTION_SAME_DEPTH 0.02f
#define SL_REFLECTION_SAME_NORMAL 0.998f
/* A texel whose block counts fewer rays than this (its neighbours other surfaces: an edge, a
 * normal map's bumps, a rounded edge's turn) traces its own other SL_REFLECTION_RAYS - 1 rays
 * too, so that its visibility moves in fifths rather than between 0 and 1. At most 2.3% of the
 * covered texels of a shipped scene at 1280x720 are lone (a normal-mapped ball's), and their rays
 * add up to a sixth to the pass (docs/lighting.md "Reflection occlusion", what it costs). */
#define SL_REFLECTION_LONE 3
/* What sl_reflection_texel reports a ray of: the block's members, then the texel's own other
 * rays, traced where the block counts fewer than SL_REFLECTION_LONE (ray k for k = 0 ..
 * SL_REFLECTION_RAYS - 1 but its own, in that order). */
#define SL_REFLECTION_MEMBERS (SL_REFLECTION_BLOCK + SL_REFLECTION_RAYS - 1)

/* How much the rays alone weigh against the smaller of the two factors, for a visibility over
 * `rays` rays: (rays - 1) / (SL_REFLECTION_RAYS - 1), 0 with one ray, 1 with five or more. A build
 * defining SL_REFLECTION_WEIGHT fixes it at that value whatever the count (0: the smaller factor
 * everywhere; 1: the rays alone), for bench/visibility-variants.sh's comparison; the GLSL twin
 * does not follow such a build. */
static inline float sl_reflection_rays_weight(float rays)
{
#ifdef SL_REFLECTION_WEIGHT
    (void)rays;
    return SL_REFLECTION_WEIGHT;
#else
    return clampf((rays - 1.0f) * (1.0f / (float)(SL_REFLECTION_RAYS - 1)), 0.0f, 1.0f);
#endif
}

/* The image-based specular's factor of a texel with the ambient occlusion's cone and this pass:
 * `capped` the cone's factor (the material's occlusion times the specular occlusion,
 * lighting_internal.h shade_spec_occlusion), `material` the material's occlusion alone,
 * `reflection` the texel's plane value (visibility, rays): min(capped, visibility) and material *
 * visibility mixed by sl_reflection_rays_weight. No branch and no library call: the batched path
 * runs it in a vector loop (the same bits as the port's call). */
/* GLSL: reflection_specular_factor */
static inline float sl_reflection_specular_factor(float capped, float material, sl_vec2 reflection)
{
    float weight = sl_reflection_rays_weight(reflection.y);
    float both = minf(capped, reflection.x), alone = material * reflection.x;
    return both + (alone - both) * weight;
}

/* The pass's working planes (44 bytes a texel and a row of lone rays per thread), kept by the
 * caller from one frame to the next: memory a frame takes afresh costs the kernel's first-touch
 * faults, and freed, blocks this large go back to the system (at 1280x720, 40 MB and about
 * 9000 faults, tens of ms of system time a frame). Zeroed: empty; grown by sl_reflection_apply
 * as a frame needs; freed by sl_reflection_scratch_free. */
typedef struct {
    size_t texels, lone;           /* capacities: texels (with the margins), floats of lone rows */
    struct sl_reflection_plane *planes;
    float *ray, *weight, *weight_sum; /* each texel's own ray, its weight, its block's weights' sum */
    float *depth, *position[3];    /* view depth and position planes, with margins */
    float *lone_rays;              /* each thread's row of lone texels' rays and weights */
} sl_reflection_scratch;
void sl_reflection_scratch_free(sl_reflection_scratch *s);

/* Set gb->reflection (allocated when NULL) for every texel, rays `distance` world units long
 * (> 0), on `threads` OpenMP threads (0: all), with `scratch`'s planes (NULL: the call's own,
 * freed before it returns), and *lone_texels (when not NULL) to how many covered texels traced
 * their own other rays (their block counted fewer than SL_REFLECTION_LONE). False (and err)
 * with a distance that is not positive and finite, or out of memory. */
bool sl_reflection_apply(sl_gbuffer *gb, const sl_camera *cam, float distance, int threads,
                         sl_reflection_scratch *scratch, int64_t *lone_texels, sl_error *err);

/* The block's members as offsets (dx, dy) from the texel: the texel, x + 1, x - 1, y + 1, y - 1,
 * then the corners. */
extern const int sl_reflection_block_offsets[SL_REFLECTION_BLOCK][2];

/* The plane value of texel (x, y) as sl_reflection_apply computes it, the same bits (visibility,
 * rays counted), and its rays, its block's in the order of sl_reflection_block_offsets and then
 * its own others (SL_REFLECTION_MEMBERS): each ray 1 open, 0 blocked, SL_REFLECTION_INTO into
 * its own surface (blocked) or SL_REFLECTION_BELOW (`rays`; 1 for an own ray not traced), its
 * weight (`weights`: the cosine to the normal of the texel that traced it, at least
 * SL_REFLECTION_MIN_COSINE; 0 where not counted) and whether it counted (`used`: 0 for a
 * neighbour off the image or another surface, a ray below its surface, or an own ray not traced,
 * where the block counts SL_REFLECTION_LONE rays or more); each SL_REFLECTION_MEMBERS long or
 * NULL. For softlight trace and the tests. (1, 0) for an empty texel (nothing used). Visibility
 * NAN when out of memory. */
vec2 sl_reflection_texel(const sl_gbuffer *gb, const sl_camera *cam, float distance, int x, int y, float *rays,
                         float *weights, int *used);

#endif
