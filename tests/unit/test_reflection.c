/* test_reflection.c - reflection occlusion (src/occlusion/reflection.c) on G-buffers traced
 * analytically (corner_gbuffer.h: the floor z = 0 and the wall x = 0), so the rasterizer is out
 * of the picture and each mirror ray's fate is known in closed form:
 *   - an open mirror-like floor, from the corner camera and from a grazing one: visibility 1 on
 *     every texel (no self-occlusion: a plain depth comparison in place of the tangent-plane
 *     test blocks rays rising slowly through texels that span long stretches of depth, 1489
 *     texels of the corner view and 4066 of the grazing one);
 *   - a mirror-like floor beside the wall, rays 3 and 1 long: texels whose mirror ray hits the
 *     wall well within the rays' length (and in the image) are blocked (visibility 0), those
 *     whose ray leaves the wall or reaches it far beyond the length stay open (1) (a tracer that
 *     never blocks fails the first, one whose rays run 3 times their length the second);
 *   - a rough floor beside the wall: the lobe's ring of rays gives a penumbra of visibilities
 *     strictly between 0 and 1, far wider than the mirror's, and the blocked set stays darker
 *     than the open one (a ring collapsed onto R leaves the mirror's penumbra alone: fails);
 *   - a rough floor at a grazing view along the wall: the ring is the lobe's streak, narrow
 *     across the plane of incidence, and no ray of a texel whose reflection heads away from the
 *     wall meets it (a round ring's side rays do: fails);
 *   - the frame (sl_reflection_apply) gives the same bits as the per-texel reference
 *     (sl_reflection_texel) at the image's borders, across the wall's edge and over the floor's
 *     reflection of the wall, and the reference says which block members counted (a frame that
 *     gives a texel the ray of its neighbour fails; a ray below its surface never counts);
 *   - shading normals tilted away from the eye on an open mirror floor: a texel whose reflection
 *     enters the floor (below the geometric normal rebuilt from the positions) is blocked; with the
 *     facet plane, one whose reflection runs under the facet by any amount is;
 *   - a rough floor whose normals lean every texel its own way, as a normal map's bumps: no
 *     neighbour counts, and each texel's visibility is over its own five rays, not 0 or 1;
 *   - refusals: a distance that is not positive and finite (infinity too); an empty texel gets 1
 *     and uses no ray. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "corner_gbuffer.h"
#include "testutil.h"

#include "occlusion/reflection.h"
#include "occlusion/specular_occlusion.h"

#define W 160
#define H 120
#define DIST 3.0f /* the rays' length */
#define SHORT 1.0f /* a length that most of the floor's view of the wall lies beyond */

static const corner_material mirror = {10000.0f, 0.9f}, rough = {20.0f, 0.9f};

/* A camera 0.4 above the floor looking along it (+y) at a point 30 ahead: grazing views. */
static sl_camera grazing_camera(void)
{
    sl_camera c = corner_camera();
    c.eye = vec3(0.0f, -10.0f, 0.4f);
    c.target = vec3(0.0f, 20.0f, 0.0f);
    return c;
}

static bool is_floor(const sl_gbuffer *gb, int x, int y)
{
    if (x < 0 || y < 0 || x >= gb->width || y >= gb->height)
        return false;
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
    return sl_gbuffer_covered(t) && t->normal.z > 0.5f;
}

/* A floor texel whose eight neighbours are floor texels too. */
static bool floor_block(const sl_gbuffer *gb, int x, int y)
{
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++)
            if (!is_floor(gb, x + dx, y + dy))
                return false;
    return true;
}

/* Whether world point p projects into the w x h image in front of the camera. */
static bool in_image(const sl_camera *cam, vec3 p, int w, int h)
{
    vec4 c = mat4_mul_vec4(sl_camera_view_proj(cam, w, h), vec4(p.x, p.y, p.z, 1.0f));
    return c.w > 0.0f && fabsf(c.x) < c.w && fabsf(c.y) < c.w;
}

/* The fate a floor texel's mirror ray (the view ray reflected about +z) must meet with rays
 * `dist` long: BLOCKED when it hits the wall within 0.7 dist, in the image, and so do the mirror
 * rays of its block, all floor (the visibility is the block's share of open rays); OPEN when it
 * leaves the wall (R.x >= 0) or hits it beyond 1.5 dist; OTHER between (or not a floor
 * texel). */
typedef enum { MIRROR_OTHER, MIRROR_BLOCKED, MIRROR_OPEN } mirror_fate;

/* Where floor texel (x, y)'s mirror ray meets the wall (its length along the ray; +inf when it
 * leaves it), and whether that point is in the image. */
static float mirror_hit(const sl_gbuffer *gb, const sl_camera *cam, int x, int y, bool *seen)
{
    vec3 P = sl_gbuffer_at(gb, x, y)->position, d = normalize(sub(P, cam->eye));
    vec3 R = vec3(d.x, d.y, -d.z);
    *seen = false;
    if (R.x >= 0.0f)
        return INFINITY;
    float t = -P.x / R.x;
    *seen = in_image(cam, add(P, scale(R, t)), gb->width, gb->height);
    return t;
}

static mirror_fate fate_of(const sl_gbuffer *gb, const sl_camera *cam, float dist, int x, int y)
{
    if (!is_floor(gb, x, y))
        return MIRROR_OTHER;
    bool seen;
    if (mirror_hit(gb, cam, x, y, &seen) > 1.5f * dist)
        return MIRROR_OPEN;
    if (!floor_block(gb, x, y))
        return MIRROR_OTHER;
    for (int dy = -1; dy <= 1; dy++) /* the texel and its eight neighbours */
        for (int dx = -1; dx <= 1; dx++)
            if (!(mirror_hit(gb, cam, x + dx, y + dy, &seen) < 0.7f * dist && seen))
                return MIRROR_OTHER;
    return MIRROR_BLOCKED;
}

/* The corner's visibility plane for the material, at W x H, rays `dist` long. */
static void corner_visibility(sl_gbuffer *gb, const sl_camera *cam, bool wall, corner_material m, float dist)
{
    sl_error err = {0};
    corner_trace(gb, cam, wall, W, H, m);
    assert_true(sl_reflection_apply(gb, cam, dist, 2, NULL, NULL, &err));
    assert_non_null(gb->reflection);
}

/* An open mirror-like floor: every covered texel 1 (measured: all 19200 of the corner view, all
 * 9920 of the grazing one). */
static void test_open_floor(void **state)
{
    (void)state;
    const sl_camera cams[2] = {corner_camera(), grazing_camera()};
    const char *names[2] = {"corner", "grazing"};
    for (int c = 0; c < 2; c++) {
        sl_gbuffer gb = {0};
        corner_visibility(&gb, &cams[c], false, mirror, DIST);
        int covered = 0, below = 0;
        float lowest = 1.0f;
        for (int i = 0; i < W * H; i++) {
            if (!sl_gbuffer_covered(&gb.texels[i]))
                continue;
            covered++;
            below += gb.reflection[i].x < 1.0f;
            lowest = fminf(lowest, gb.reflection[i].x);
        }
        print_message("open floor, %s camera: %d covered texels, %d below 1, lowest %.3f\n", names[c], covered, below,
                      (double)lowest);
        assert_true(covered > W * H / 4);
        assert_int_equal(below, 0);
        sl_gbuffer_free(&gb);
    }
}

/* fate_of's sets on gb with rays `dist` long: the count of each, of those at 0 (BLOCKED) or 1
 * (OPEN), the sum of the visibility over each; and the floor texels strictly between 0 and 1. */
typedef struct {
    int blocked, open, blocked_zero, open_one, between;
    double blocked_sum, open_sum;
} fate_counts;

static fate_counts count_fates(const sl_gbuffer *gb, const sl_camera *cam, float dist)
{
    fate_counts c = {0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float v = gb->reflection[y * W + x].x;
            c.between += is_floor(gb, x, y) && v > 0.0f && v < 1.0f;
            mirror_fate f = fate_of(gb, cam, dist, x, y);
            if (f == MIRROR_BLOCKED) {
                c.blocked++;
                c.blocked_zero += v == 0.0f;
                c.blocked_sum += (double)v;
            } else if (f == MIRROR_OPEN) {
                c.open++;
                c.open_one += v == 1.0f;
                c.open_sum += (double)v;
            }
        }
    return c;
}

/* A mirror-like floor beside the wall, rays DIST and SHORT long: at least 95% of fate_of's BLOCKED
 * texels at 0, 99% of its OPEN ones at 1. Measured: rays 3 long, 2205 of 2255 blocked (97.8%),
 * all 6062 open; rays 1 long, 512 of 518 blocked (98.8%), 9965 of 9967 open. The blocked ones left
 * open lie by the image's left edge and along the wall's foot, where a step past the wall lands
 * on a floor texel or farther behind the wall than the thickness. */
static void test_mirror_beside_wall(void **state)
{
    (void)state;
    const float dists[2] = {DIST, SHORT};
    for (int i = 0; i < 2; i++) {
        sl_gbuffer gb = {0};
        sl_camera cam = corner_camera();
        corner_visibility(&gb, &cam, true, mirror, dists[i]);
        fate_counts c = count_fates(&gb, &cam, dists[i]);
        print_message("mirror floor, rays %g long: %d of %d blocked texels at 0 (%.4f), %d of %d open texels at 1 "
                      "(%.4f), %d between\n",
                      (double)dists[i], c.blocked_zero, c.blocked, (double)c.blocked_zero / c.blocked, c.open_one,
                      c.open, (double)c.open_one / c.open, c.between);
        assert_true(c.blocked > 100 && c.open > 500);
        assert_true(c.blocked_zero >= 0.95 * c.blocked);
        assert_true(c.open_one >= 0.99 * c.open);
        sl_gbuffer_free(&gb);
    }
}

/* A rough floor (Phong 20) beside the wall, rays DIST long. Measured: 3042 floor texels strictly
 * between 0 and 1 (the mirror: 604, the edge of its reflection of the wall); mean 0.028 over
 * fate_of's 2255 blocked texels, 0.999 over its 6062 open ones. */
static void test_rough_beside_wall(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    corner_visibility(&gb, &cam, true, mirror, DIST);
    int mirror_between = count_fates(&gb, &cam, DIST).between;
    corner_visibility(&gb, &cam, true, rough, DIST);
    fate_counts c = count_fates(&gb, &cam, DIST);
    double blocked_mean = c.blocked_sum / c.blocked, open_mean = c.open_sum / c.open;
    print_message("rough floor: %d texels between 0 and 1 (mirror %d); mean %.3f over %d blocked, %.3f over %d open\n",
                  c.between, mirror_between, blocked_mean, c.blocked, open_mean, c.open);
    assert_true(c.between > 0);
    assert_true(c.between > 3 * mirror_between);
    assert_true(blocked_mean < open_mean);
    sl_gbuffer_free(&gb);
}

/* Whether floor point P lies right of the eye (its mirror ray heads away from the wall) and its
 * ellipse's rays across, which reach 2 N.V sin(ring) to the side a unit along, cannot reach the
 * wall within `dist`. */
static bool streak_clear_of_wall(const sl_camera *cam, vec3 P, float ring, float dist)
{
    vec3 V = normalize(sub(cam->eye, P));
    return P.x >= cam->eye.x && 2.0f * V.z * sinf(ring) * dist < P.x;
}

/* A rough floor (Phong 5) seen at a grazing view along the wall, from 0.6 units beside it, rays
 * 6 long: a microfacet lobe's reflection at a grazing view is a streak in the plane of incidence,
 * N.V times as wide across it as along it, and the ring is an ellipse of that shape. On the
 * floor texels whose blocks are floor, right of the eye (their mirror rays head away from the
 * wall), and whose ellipses cannot reach the wall within the rays' length, every visibility is 1,
 * while a round ring's rays across the plane (the ring's angle to the side of R) would meet the
 * wall within the rays' length and in the image from many of them (measured: 1 over 2776
 * texels, 239 of which a round ring's side ray meets the wall from). */
static void test_grazing_streak(void **state)
{
    (void)state;
    const float dist = 6.0f;
    sl_camera cam = corner_camera();
    cam.eye = vec3(0.6f, -10.0f, 0.4f);
    cam.target = vec3(0.6f, 20.0f, 0.0f);
    sl_gbuffer gb = {0};
    const corner_material wide = {5.0f, 0.9f};
    corner_visibility(&gb, &cam, true, wide, dist);
    const float ring = SL_REFLECTION_RING * sl_so_lobe_cone(wide.alpha).ts;
    int texels = 0, round_blocked = 0;
    float lowest = 1.0f;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            if (!floor_block(&gb, x, y))
                continue;
            vec3 P = sl_gbuffer_at(&gb, x, y)->position;
            vec3 d = normalize(sub(P, cam.eye)), R = vec3(d.x, d.y, -d.z), N = vec3(0.0f, 0.0f, 1.0f);
            if (!streak_clear_of_wall(&cam, sl_gbuffer_at(&gb, x - 1, y)->position, ring, dist))
                continue; /* the block's left column, and so the whole block */
            texels++;
            lowest = fminf(lowest, gb.reflection[y * W + x].x);
            /* a round ring's ray across the plane of incidence, towards the wall */
            vec3 T = normalize(sub(N, scale(R, dot(N, R)))), B = cross(R, T);
            vec3 side = normalize(add(scale(R, cosf(ring)), scale(B, (B.x < 0.0f ? 1.0f : -1.0f) * sinf(ring))));
            if (side.x < 0.0f) {
                float t = -P.x / side.x;
                vec3 hit = add(P, scale(side, t));
                round_blocked += t < 0.7f * dist && hit.z > 0.0f && in_image(&cam, hit, W, H);
            }
        }
    print_message("grazing rough floor beside the wall: lowest visibility %.3f over %d texels right of the eye, %d of "
                  "which a round ring's side ray meets the wall from\n",
                  (double)lowest, texels, round_blocked);
    assert_true(texels > 500 && round_blocked > 100);
    assert_float_equal(lowest, 1.0, 0.0);
    sl_gbuffer_free(&gb);
}

/* The frame's value of (x, y) against the reference's, bit for bit (visibility and rays); the
 * reference's `used`: the texel itself when covered and its ray above its surface, no member
 * below its surface or off the image, as many as the rays counted; its visibility the counted
 * rays' share weighted by their cosines, each in [SL_REFLECTION_MIN_COSINE, 1] (0 where not
 * counted). Returns the visibility. */
static float check_texel(const sl_gbuffer *gb, const sl_camera *cam, int x, int y, int *below_rays)
{
    const int w = gb->width, h = gb->height;
    float rays[SL_REFLECTION_MEMBERS], weights[SL_REFLECTION_MEMBERS];
    int used[SL_REFLECTION_MEMBERS];
    vec2 want = sl_reflection_texel(gb, cam, DIST, x, y, rays, weights, used), got = gb->reflection[y * w + x];
    if (memcmp(&want, &got, sizeof want) != 0)
        fail_msg("texel (%d, %d): frame (%.9g, %g), texel (%.9g, %g)", x, y, (double)got.x, (double)got.y,
                 (double)want.x, (double)want.y);
    assert_int_equal(used[0], sl_gbuffer_covered(sl_gbuffer_at(gb, x, y)) && rays[0] != SL_REFLECTION_BELOW);
    int counted = 0, below = 0, block = 0, own = 0;
    float open = 0.0f, total = 0.0f;
    for (int m = 0; m < SL_REFLECTION_MEMBERS; m++) {
        block += m < SL_REFLECTION_BLOCK && used[m];
        own += m >= SL_REFLECTION_BLOCK && used[m];
        counted += used[m];
        if (used[m]) {
            assert_true(weights[m] >= SL_REFLECTION_MIN_COSINE && weights[m] <= 1.0f);
            open += (rays[m] == SL_REFLECTION_INTO ? 0.0f : rays[m]) * weights[m];
            total += weights[m];
        } else {
            assert_float_equal(weights[m], 0.0, 0.0);
        }
        below += rays[m] == SL_REFLECTION_BELOW;
        if (rays[m] == SL_REFLECTION_BELOW)
            assert_int_equal(used[m], 0);
    }
    if (counted == 0)
        assert_float_equal(want.x, 1.0, 0.0);
    else
        assert_float_equal(want.x, open / total, 0.0);
    *below_rays += below;
    assert_int_equal((int)want.y, counted);
    /* the texel's own other rays count only where its block counts fewer than SL_REFLECTION_LONE */
    if (block >= SL_REFLECTION_LONE)
        assert_int_equal(own, 0);
    for (int m = 1; m < SL_REFLECTION_BLOCK; m++) {
        int qx = x + sl_reflection_block_offsets[m][0], qy = y + sl_reflection_block_offsets[m][1];
        if (qx < 0 || qy < 0 || qx >= w || qy >= h)
            assert_int_equal(used[m], 0);
    }
    return want.x;
}

/* The frame against the reference on a 97 x 61 corner of rough floor (the wall's edge in view, a
 * hole in the floor): every border texel, and every texel of three rows and two columns through
 * the middle. */
static void test_frame_matches_texel(void **state)
{
    (void)state;
    const int w = 97, h = 61;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    corner_trace(&gb, &cam, true, w, h, rough);
    for (int y = 20; y < 40; y++) /* a hole in the floor, across the middle rows */
        for (int x = 40; x < 46; x++)
            sl_gbuffer_at(&gb, x, y)->depth = 1.0f;
    sl_error err = {0};
    assert_true(sl_reflection_apply(&gb, &cam, DIST, 3, NULL, NULL, &err));
    int checked = 0, empty = 0, partial = 0, zero = 0, below = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            bool border = x == 0 || y == 0 || x == w - 1 || y == h - 1;
            bool middle = abs(y - h / 2) <= 1 || x == w / 3 || x == 2 * w / 3;
            if (!border && !middle)
                continue;
            float v = check_texel(&gb, &cam, x, y, &below);
            checked++;
            empty += !sl_gbuffer_covered(sl_gbuffer_at(&gb, x, y));
            partial += v > 0.0f && v < 1.0f;
            zero += v == 0.0f;
        }
    print_message("frame = texel on %d texels: %d empty, %d at 0, %d between 0 and 1, %d rays below their surface\n",
                  checked, empty, zero, partial, below);
    assert_true(checked > 300 && empty > 0 && partial > 0 && zero > 0 && below > 0);
    sl_gbuffer_free(&gb);
}

/* A scratch kept from frame to frame (the renderer's) gives the bits of the call's own planes:
 * on the same frame twice, then on a smaller frame, which it has room for, and on a larger one,
 * which grows it; and with more threads, whose rows of lone rays it also makes room for. */
static void test_scratch_kept(void **state)
{
    (void)state;
    static const int sizes[4][3] = {{97, 61, 2}, {97, 61, 2}, {40, 30, 1}, {131, 77, 3}};
    sl_reflection_scratch scratch = {0};
    sl_camera cam = corner_camera();
    sl_error err = {0};
    for (int k = 0; k < 4; k++) {
        const int w = sizes[k][0], h = sizes[k][1], threads = sizes[k][2];
        sl_gbuffer own = {0}, kept = {0};
        corner_trace(&own, &cam, true, w, h, rough);
        corner_trace(&kept, &cam, true, w, h, rough);
        assert_true(sl_reflection_apply(&own, &cam, DIST, threads, NULL, NULL, &err));
        assert_true(sl_reflection_apply(&kept, &cam, DIST, threads, &scratch, NULL, &err));
        assert_memory_equal(own.reflection, kept.reflection, (size_t)w * (size_t)h * sizeof *own.reflection);
        assert_true(scratch.texels >= (size_t)w * (size_t)h);
        sl_gbuffer_free(&own);
        sl_gbuffer_free(&kept);
    }
    sl_reflection_scratch_free(&scratch);
    assert_null(scratch.planes);
}

/* Tilt every covered texel's shading normal `degrees` away from the eye about the floor's +Z, as
 * a normal map or a smooth mesh's normals lean. */
static void tilt_normals(sl_gbuffer *gb, const sl_camera *cam, float degrees)
{
    const float c = cosf(radians(degrees)), s = sinf(radians(degrees));
    for (int i = 0; i < gb->width * gb->height; i++) {
        sl_gbuffer_texel *t = &gb->texels[i];
        if (!sl_gbuffer_covered(t))
            continue;
        vec3 to_eye = sub(cam->eye, t->position);
        vec3 across = normalize(vec3(to_eye.x, to_eye.y, 0.0f));
        t->normal = vec3(-across.x * s, -across.y * s, c);
    }
}

/* Over the floor texels (floor_block) whose shading normal faces the eye (N.V > 0.05) and whose
 * mirror direction R has z in (z_lo, z_hi): counts[0] how many, counts[1] how many the surface
 * takes as `into` says: SL_REFLECTION_INTO, blocked (visibility 0), or SL_REFLECTION_BELOW, no ray
 * counted (visibility 1 over 0 rays: the lighting leaves those directions out itself); and on
 * every (every_x, every_y)-th of them the frame against the reference (check_texel), with its own
 * ray reported as `into`, counted in counts[2]. */
static void count_into_surface(const sl_gbuffer *gb, const sl_camera *cam, float z_lo, float z_hi, int every_x,
                               int every_y, float into, int counts[3])
{
    int below = 0;
    counts[0] = counts[1] = counts[2] = 0;
    for (int y = 0; y < gb->height; y++)
        for (int x = 0; x < gb->width; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
            if (!floor_block(gb, x, y))
                continue;
            vec3 V = normalize(sub(cam->eye, t->position));
            vec3 R = sub(scale(t->normal, 2.0f * dot(t->normal, V)), V);
            if (!(dot(t->normal, V) > 0.05f && R.z > z_lo && R.z < z_hi))
                continue;
            counts[0]++;
            const vec2 v = gb->reflection[y * gb->width + x];
            counts[1] += into == SL_REFLECTION_INTO ? v.x == 0.0f : v.x == 1.0f && v.y == 0.0f;
            if (x % every_x == 0 && y % every_y == 0) {
                check_texel(gb, cam, x, y, &below);
                float rays[SL_REFLECTION_MEMBERS];
                sl_reflection_texel(gb, cam, DIST, x, y, rays, NULL, NULL);
                assert_float_equal(rays[0], into, 0.0); /* trace says why it is blocked or not counted */
                counts[2]++;
            }
        }
}

/* An open mirror-like floor from the corner camera, its shading normals tilted TILT degrees
 * away from the eye, as a normal map or a smooth mesh's normals lean: a texel whose reflection R
 * about the tilted normal runs into the floor (below its geometric normal by more than
 * SL_REFLECTION_INTO_MARGIN, above the tilted one) is blocked, 0, as the visibility truth has it, where a ray traced from a point moved
 * off along the tilted normal can miss the floor's tangent planes (measured: all 4802 such
 * texels at 0; without the geometric normal 4701); and the frame gives the reference's bits on
 * those texels, whose own ray the reference reports as into its surface. */
#define TILT 25.0f
static void test_tilted_normals(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    corner_trace(&gb, &cam, false, W, H, mirror);
    tilt_normals(&gb, &cam, TILT);
    sl_error err = {0};
    assert_true(sl_reflection_apply(&gb, &cam, DIST, 2, NULL, NULL, &err));
    /* R enters beyond the margin */
    int n[3];
    count_into_surface(&gb, &cam, -2.0f, -SL_REFLECTION_INTO_MARGIN - 0.02f, 7, 5, SL_REFLECTION_INTO, n);
    print_message("tilted normals: %d of %d texels whose R enters the floor at 0; frame = texel on %d\n", n[1], n[0],
                  n[2]);
    assert_true(n[0] > 1000 && n[2] > 50);
    assert_int_equal(n[1], n[0]);
    sl_gbuffer_free(&gb);
}

/* The facet plane (sl_gbuffer.facet, the drawn triangles' normals) in place of the normal rebuilt
 * from the positions: the open mirror floor at the grazing view, its shading normals tilted
 * FACET_TILT degrees away from the eye, so that R runs under the floor by less than
 * SL_REFLECTION_INTO_MARGIN on many texels: with the floor's facet, +Z, each texel whose lobe lies
 * under it (R below by more than the mirror ring's reach in the plane of incidence, 0.024) counts
 * no ray, its own reported as below its surface (no margin: the facet is the surface the
 * visibility truth intersects, and the lighting leaves the directions under it out sample by
 * sample, so the rays speak for the lobe above it; without the plane the march blocks them
 * instead); the frame gives the reference's bits. */
#define FACET_TILT 6.0f
static void test_facet_plane(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = grazing_camera();
    corner_trace(&gb, &cam, false, W, H, mirror);
    sl_error err = {0};
    assert_true(sl_gbuffer_use_facet(&gb, true, &err));
    tilt_normals(&gb, &cam, FACET_TILT);
    for (int i = 0; i < W * H; i++)
        if (sl_gbuffer_covered(&gb.texels[i]))
            gb.facet[i] = vec3(0.0f, 0.0f, 1.0f);
    assert_true(sl_reflection_apply(&gb, &cam, DIST, 2, NULL, NULL, &err));
    /* within the rebuilt normal's margin, under the facet's horizon */
    int n[3];
    count_into_surface(&gb, &cam, -SL_REFLECTION_INTO_MARGIN, -0.04f, 5, 3, SL_REFLECTION_BELOW, n);
    print_message("facet plane: %d of %d texels whose R runs under the facet within the margin count no ray; "
                  "frame = texel on %d\n", n[1], n[0], n[2]);
    assert_true(n[0] > 250 && n[2] > 15);
    assert_int_equal(n[1], n[0]);
    sl_gbuffer_free(&gb);
}

/* A rough floor beside the wall whose shading normals lean BUMP degrees, each texel of a 3 x 3
 * tile toward its own azimuth, as a normal map's bumps turn them: no neighbour is the same
 * surface (their normals more than SL_REFLECTION_SAME_NORMAL apart), so each floor texel's
 * block counts its own ray alone and it traces its other four: its visibility is over its own
 * rays, strictly between 0 and 1 where the wall hides part of its lobe (measured: 2617 of the
 * 11702 floor texels; with its one ray each is 0 or 1: none), and the frame gives the reference's bits
 * (check_texel, which also holds that the own rays count only where the block counts fewer than
 * SL_REFLECTION_LONE). */
#define BUMP 8.0f
static void test_lone_texels(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    corner_trace(&gb, &cam, true, W, H, rough);
    const float c = cosf(radians(BUMP)), s = sinf(radians(BUMP));
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            sl_gbuffer_texel *t = sl_gbuffer_at(&gb, x, y);
            if (!is_floor(&gb, x, y))
                continue;
            float azimuth = 2.0f * SL_PI * (float)(x % 3 + 3 * (y % 3)) / 9.0f;
            t->normal = vec3(s * cosf(azimuth), s * sinf(azimuth), c);
        }
    sl_error err = {0};
    assert_true(sl_reflection_apply(&gb, &cam, DIST, 2, NULL, NULL, &err));
    int floor = 0, alone = 0, between = 0, checked = 0, below = 0;
    for (int y = 1; y < H - 1; y++)
        for (int x = 1; x < W - 1; x++) {
            if (!floor_block(&gb, x, y))
                continue;
            vec2 v = gb.reflection[y * W + x];
            floor++;
            float rays[SL_REFLECTION_MEMBERS];
            int used[SL_REFLECTION_MEMBERS];
            sl_reflection_texel(&gb, &cam, DIST, x, y, rays, NULL, used);
            int block = 0;
            for (int m = 0; m < SL_REFLECTION_BLOCK; m++)
                block += used[m];
            alone += block <= 1; /* 0 where its own ray is below its surface */
            between += v.x > 0.0f && v.x < 1.0f;
            if (x % 9 == 0 && y % 7 == 0) {
                check_texel(&gb, &cam, x, y, &below);
                checked++;
            }
        }
    print_message("lone texels: %d of %d floor texels count no neighbour's ray, %d strictly between "
                  "0 and 1; frame = texel on %d\n",
                  alone, floor, between, checked);
    assert_true(floor > 10000 && checked > 100);
    assert_int_equal(alone, floor);
    assert_true(between > 500);
    sl_gbuffer_free(&gb);
}

/* sl_reflection_specular_factor: with one ray the smaller of the cone's factor and the rays'
 * visibility; with five or more the material's occlusion times the visibility, whatever the cone
 * says; between, moving from one to the other as rays are added; never outside [0, 1] for
 * factors in it. */
static void test_specular_factor(void **state)
{
    (void)state;
    const float material = 0.8f;
    /* the cone closes (0.1) where the rays see the lobe open (1), and the other way round */
    assert_float_equal(sl_reflection_specular_factor(0.1f, material, vec2(1.0f, 1.0f)), 0.1, 0.0);
    assert_float_equal(sl_reflection_specular_factor(0.7f, material, vec2(0.2f, 1.0f)), 0.2, 0.0);
    assert_float_equal(sl_reflection_specular_factor(0.1f, material, vec2(1.0f, 5.0f)), 0.8, 1e-7);
    assert_float_equal(sl_reflection_specular_factor(0.7f, material, vec2(0.2f, 5.0f)), 0.16, 1e-7);
    float last = 0.0f;
    for (int rays = 1; rays <= SL_REFLECTION_MEMBERS; rays++) {
        float f = sl_reflection_specular_factor(0.1f, material, vec2(1.0f, (float)rays));
        assert_true(f >= last && f <= 1.0f);
        last = f;
    }
    for (int c = 0; c <= 10; c++)
        for (int v = 0; v <= 5; v++)
            for (int rays = 0; rays <= SL_REFLECTION_MEMBERS + 1; rays++) {
                float f = sl_reflection_specular_factor(0.1f * (float)c, 1.0f, vec2(0.2f * (float)v, (float)rays));
                assert_true(f >= 0.0f && f <= 1.0f);
            }
}

static void test_refusals(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    corner_trace(&gb, &cam, true, W, H, mirror);
    const float bad[] = {0.0f, -1.0f, NAN, INFINITY};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sl_error err = {0};
        assert_false(sl_reflection_apply(&gb, &cam, bad[i], 1, NULL, NULL, &err));
        assert_msg_contains(err, "reflection occlusion: distance");
    }
    /* an empty texel: 1, nothing of its block used */
    int ex = W / 2, ey = H / 2;
    sl_gbuffer_at(&gb, ex, ey)->depth = 1.0f;
    sl_error err = {0};
    assert_true(sl_reflection_apply(&gb, &cam, DIST, 1, NULL, NULL, &err));
    assert_float_equal(gb.reflection[ey * W + ex].x, 1.0, 0.0);
    assert_float_equal(gb.reflection[ey * W + ex].y, 0.0, 0.0);
    float rays[SL_REFLECTION_MEMBERS], weights[SL_REFLECTION_MEMBERS];
    int used[SL_REFLECTION_MEMBERS];
    vec2 empty = sl_reflection_texel(&gb, &cam, DIST, ex, ey, rays, weights, used);
    assert_float_equal(empty.x, 1.0, 0.0);
    assert_float_equal(empty.y, 0.0, 0.0);
    for (int m = 0; m < SL_REFLECTION_MEMBERS; m++)
        assert_int_equal(used[m], 0);
    sl_gbuffer_free(&gb);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open_floor),
        cmocka_unit_test(test_mirror_beside_wall),
        cmocka_unit_test(test_rough_beside_wall),
        cmocka_unit_test(test_grazing_streak),
        cmocka_unit_test(test_frame_matches_texel),
        cmocka_unit_test(test_scratch_kept),
        cmocka_unit_test(test_tilted_normals),
        cmocka_unit_test(test_facet_plane),
        cmocka_unit_test(test_lone_texels),
        cmocka_unit_test(test_specular_factor),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
