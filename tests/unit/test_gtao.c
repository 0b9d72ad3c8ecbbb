/* test_gtao.c - ambient occlusion from the G-buffer (src/occlusion/gtao.c) on G-buffers traced
 * analytically (corner_gbuffer.h), so the rasterizer is out of the picture:
 *   - an open floor sees its whole hemisphere: AO 1 (no self-occlusion from its own texels);
 *   - a floor beside an infinitely tall wall, within radius R: the wall hides the directions
 *     whose hit lies within R, the cosine-weighted share (acos(a) - a sqrt(1 - a^2)) / pi with
 *     a = d / R at distance d from the wall (0.5 at the foot, 0 from d = R on);
 *   - AO multiplies what a material's occlusion map left in the plane;
 *   - the frame (sl_gtao_apply, its blur in vector loops over spans of a row) gives every texel
 *     the same bits as the per-texel reference (sl_gtao_texel), across spans and at the borders;
 *   - the bent normal (the cone plane's axis): N on the open floor, leaning away from the wall
 *     beside it;
 *   - the diffuse's bent direction (src/shading/bent_irradiance.h): beside the wall under a sky
 *     brighter on the wall's side, AO E(D) is darker than AO E(N) and nearer the irradiance of
 *     the directions the wall leaves open;
 *   - the specular occlusion of the visibility cone (src/occlusion/specular_occlusion.h): 1 when
 *     open, 0 when closed, never rising as the lobe widens about the cone's axis or as its axis
 *     leaves the cone, never falling as the cone opens, 1 at AO 1 whatever the lobe;
 *   - refusals: no extra plane, a radius that is not positive. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "corner_gbuffer.h"
#include "testutil.h"

#include "occlusion/gtao.h"
#include "shading/bent_irradiance.h"
#include "occlusion/specular_occlusion.h"
#include "scene/camera.h"

#define W 160
#define H 120
#define PI_D 3.14159265358979323846

/* The corner (corner_gbuffer.h) at W x H; the material does not matter to AO. */
static void trace_sized(sl_gbuffer *gb, const sl_camera *cam, bool wall, int w, int h)
{
    corner_trace(gb, cam, wall, w, h, (corner_material){0.0f, 0.0f});
}

static void trace(sl_gbuffer *gb, const sl_camera *cam, bool wall) { trace_sized(gb, cam, wall, W, H); }

/* The cosine-weighted share of the hemisphere a floor point at distance d from the wall keeps
 * when hits within radius R count. */
static double corner_ao(double d, double R)
{
    double a = d / R;
    if (a >= 1.0)
        return 1.0;
    return 1.0 - (acos(a) - a * sqrt(1.0 - a * a)) / PI_D;
}

/* The pixel whose floor point is nearest to (px, py, 0): floor texels only. */
static void floor_pixel(const sl_gbuffer *gb, float px, float py, int *bx, int *by)
{
    float best = INFINITY;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
            if (!sl_gbuffer_covered(t) || t->normal.z < 0.5f)
                continue;
            float dx = t->position.x - px, dy = t->position.y - py, d2 = dx * dx + dy * dy;
            if (d2 < best) {
                best = d2;
                *bx = x;
                *by = y;
            }
        }
}

/* An open floor: AO 1 up to the method's own error (measured: lowest 0.9816 where N.V >= 0.25,
 * 0.9767 at grazing views, where the blur's block is cut short at the image's border or far rows;
 * mean 0.9998): at least 0.975 everywhere, mean at least 0.995. */
static void test_open_floor(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    trace(&gb, &cam, false);
    sl_error err = {0};
    assert_true(sl_gtao_apply(&gb, &cam, 1.0f, 1, NULL, &err));
    double lowest = 1.0, lowest_grazing = 1.0, sum = 0.0;
    int n = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(&gb, x, y);
            if (!sl_gbuffer_covered(t))
                continue;
            double v = gb.extra[y * W + x].occlusion;
            float nv = dot(t->normal, normalize(sub(cam.eye, t->position)));
            if (nv >= 0.25f)
                lowest = fmin(lowest, v);
            else
                lowest_grazing = fmin(lowest_grazing, v);
            sum += v;
            n++;
        }
    print_message("open floor: lowest AO %.4f (N.V >= 0.25), %.4f (grazing), mean %.4f\n", lowest, lowest_grazing,
                  sum / n);
    assert_true(lowest >= 0.975);
    assert_true(lowest_grazing >= 0.975);
    assert_true(sum / n >= 0.995);
    sl_gbuffer_free(&gb);
}

static void test_wall_corner(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    trace(&gb, &cam, true);
    const float R = 1.0f;
    const float distances[] = {0.05f, 0.25f, 0.5f, 0.75f, 1.5f};
    for (size_t i = 0; i < sizeof distances / sizeof distances[0]; i++) {
        int x = 0, y = 0;
        floor_pixel(&gb, distances[i], 0.0f, &x, &y);
        const sl_gbuffer_texel *t = sl_gbuffer_at(&gb, x, y);
        double d = t->position.x, want = corner_ao(d, R);
        double got = sl_gtao_texel(&gb, &cam, R, x, y).w;
        print_message("floor at %.3f from the wall: AO %.4f, analytic %.4f\n", d, got, want);
        /* measured: +0.077 at the foot, where the blur's 4 x 4 half-resolution block (7 texels
         * across) averages the steep rise of AO away from the wall; within 0.005 from 0.25 on */
        assert_near(got, want, d < 0.1 ? 0.08 : 0.01);
    }
    sl_gbuffer_free(&gb);
}

/* A scratch kept from frame to frame (the renderer's) gives the bits of the call's own planes,
 * in the occlusion and the cone: on the same frame twice, on a smaller one, which it has room
 * for, and on a larger one, which grows it. */
static void test_scratch_kept(void **state)
{
    (void)state;
    static const int sizes[4][3] = {{W, H, 2}, {W, H, 2}, {57, 33, 1}, {211, 131, 3}};
    sl_gtao_scratch scratch = {0};
    sl_camera cam = corner_camera();
    sl_error err = {0};
    for (int k = 0; k < 4; k++) {
        const int w = sizes[k][0], h = sizes[k][1], threads = sizes[k][2];
        sl_gbuffer own = {0}, kept = {0};
        trace_sized(&own, &cam, true, w, h);
        trace_sized(&kept, &cam, true, w, h);
        assert_true(sl_gtao_apply(&own, &cam, 1.0f, threads, NULL, &err));
        assert_true(sl_gtao_apply(&kept, &cam, 1.0f, threads, &scratch, &err));
        const size_t n = (size_t)w * (size_t)h;
        assert_memory_equal(own.cone, kept.cone, n * sizeof *own.cone);
        for (size_t i = 0; i < n; i++)
            assert_memory_equal(&own.extra[i].occlusion, &kept.extra[i].occlusion, sizeof(float));
        sl_gbuffer_free(&own);
        sl_gbuffer_free(&kept);
    }
    sl_gtao_scratch_free(&scratch);
    assert_null(scratch.planes);
}

static void test_multiplies_the_map(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    trace(&gb, &cam, true);
    for (int i = 0; i < W * H; i++)
        gb.extra[i].occlusion = 0.5f;
    int x = 0, y = 0;
    floor_pixel(&gb, 0.1f, 0.0f, &x, &y);
    float ao = sl_gtao_texel(&gb, &cam, 1.0f, x, y).w;
    sl_error err = {0};
    assert_true(sl_gtao_apply(&gb, &cam, 1.0f, 2, NULL, &err));
    assert_near(gb.extra[y * W + x].occlusion, 0.5f * ao, 1e-6);
    assert_true(ao < 0.7f);
    sl_gbuffer_free(&gb);
}

/* The frame against the reference, bit for bit, in the cone plane and the occlusion: an odd width
 * a little over two of the blur's spans (256 texels), so that a span ends mid-row and the last
 * half-resolution column is a lone texel; the wall's edge in view (samples refused by the normal
 * test) and a hole in the floor across the first two spans' boundary (samples refused as
 * uncovered); every texel of the rows at the bottom, the middle and the top (the block cut short
 * there). */
static void test_frame_matches_texel(void **state)
{
    (void)state;
    const int w = 523, h = 61;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    trace_sized(&gb, &cam, true, w, h);
    for (int i = 0; i < w * h; i++)
        gb.extra[i].occlusion = 0.5f;
    for (int y = 0; y < h; y++) /* a hole in the floor across the first spans' boundary */
        for (int x = 250; x < 263; x++)
            sl_gbuffer_at(&gb, x, y)->depth = 1.0f;
    sl_error err = {0};
    assert_true(sl_gtao_apply(&gb, &cam, 1.0f, 2, NULL, &err));
    const int rows[] = {0, 1, 2, h / 2 - 1, h / 2, h - 2, h - 1};
    int empty = 0, occluded = 0;
    for (size_t r = 0; r < sizeof rows / sizeof rows[0]; r++)
        for (int x = 0; x < w; x++) {
            int y = rows[r];
            sl_vec4 want = sl_gtao_texel(&gb, &cam, 1.0f, x, y), got = gb.cone[y * w + x];
            if (memcmp(&want, &got, sizeof want) != 0)
                fail_msg("texel (%d, %d): frame (%.9g, %.9g, %.9g, %.9g), texel (%.9g, %.9g, %.9g, %.9g)", x, y,
                         (double)got.x, (double)got.y, (double)got.z, (double)got.w, (double)want.x,
                         (double)want.y, (double)want.z, (double)want.w);
            float occlusion = sl_gbuffer_covered(sl_gbuffer_at(&gb, x, y)) ? 0.5f * want.w : 0.5f;
            assert_memory_equal(&gb.extra[y * w + x].occlusion, &occlusion, sizeof occlusion);
            empty += !sl_gbuffer_covered(sl_gbuffer_at(&gb, x, y));
            occluded += want.w < 0.9f;
        }
    print_message("frame = texel on %zu rows of %d: %d empty, %d with AO < 0.9\n", sizeof rows / sizeof rows[0], w,
                  empty, occluded);
    assert_true(empty > 0 && occluded > 0);
    sl_gbuffer_free(&gb);
}

/* The frame against the reference where the radius is under a pixel for the far texels: those
 * have nothing to read (AO 1, bent normal N in their samples), which the frame's march takes out of
 * its lanes and the reference returns from texel_ao; the near ones are marched. */
static void test_frame_matches_texel_small_radius(void **state)
{
    (void)state;
    const int w = 203, h = 61;
    const float radius = 0.15f;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    trace_sized(&gb, &cam, true, w, h);
    sl_error err = {0};
    assert_true(sl_gtao_apply(&gb, &cam, radius, 1, NULL, &err));
    sl_gtao_view v = sl_gtao_view_of(&cam, h);
    int far = 0, near = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            sl_vec4 want = sl_gtao_texel(&gb, &cam, radius, x, y), got = gb.cone[y * w + x];
            if (memcmp(&want, &got, sizeof want) != 0)
                fail_msg("texel (%d, %d): frame (%.9g, %.9g, %.9g, %.9g), texel (%.9g, %.9g, %.9g, %.9g)", x, y,
                         (double)got.x, (double)got.y, (double)got.z, (double)got.w, (double)want.x,
                         (double)want.y, (double)want.z, (double)want.w);
            const sl_gbuffer_texel *t = sl_gbuffer_at(&gb, x, y);
            if (!sl_gbuffer_covered(t) || (x | y) & 1) /* the samples' texels */
                continue;
            float pixels = radius * v.pixels_per_unit / dot(sub(t->position, v.eye), v.forward);
            far += pixels < 1.0f;
            near += pixels >= 1.0f;
        }
    print_message("frame = texel, radius %g: %d samples under a pixel, %d over\n", (double)radius, far, near);
    assert_true(far > 0 && near > 0);
    sl_gbuffer_free(&gb);
}

/* The cone plane: unit bent normals; N (+z) on the open floor; in the corner, a floor point a
 * quarter radius from the wall leans away from it (+x), by more than it does a radius away. */
static void test_bent_normal(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    sl_error err = {0};
    trace(&gb, &cam, false);
    assert_true(sl_gtao_apply(&gb, &cam, 1.0f, 1, NULL, &err));
    assert_non_null(gb.cone);
    double lowest = 1.0;
    for (int i = 0; i < W * H; i++)
        if (sl_gbuffer_covered(&gb.texels[i]))
            lowest = fmin(lowest, gb.cone[i].z);
    print_message("open floor: lowest bent.z %.4f\n", lowest);
    assert_true(lowest > 0.99);
    trace(&gb, &cam, true);
    assert_true(sl_gtao_apply(&gb, &cam, 1.0f, 1, NULL, &err));
    int x, y, fx, fy;
    floor_pixel(&gb, 0.25f, 0.0f, &x, &y);
    floor_pixel(&gb, 1.0f, 0.0f, &fx, &fy);
    sl_vec4 near = gb.cone[y * W + x], far = gb.cone[fy * W + fx];
    print_message("corner: bent (%.3f, %.3f, %.3f) AO %.3f at d = R/4; bent.x %.3f at d = R\n", (double)near.x,
                  (double)near.y, (double)near.z, (double)near.w, (double)far.x);
    assert_float_equal(near.x * near.x + near.y * near.y + near.z * near.z, 1.0, 1e-4);
    assert_true(near.x > 0.15f && near.z > 0.5f);
    assert_true(near.x > far.x + 0.1f);
    assert_float_equal(near.w, gb.extra[y * W + x].occlusion, 0.0); /* the AO, as the occlusion got it */
    sl_gbuffer_free(&gb);
}

/* The sky of test_bent_irradiance: radiance 1 + 0.8 (-w.x), brighter towards the wall (x < 0).
 * Its irradiance about a unit n is exact: pi + (2 pi / 3) 0.8 (-n.x) (a linear radiance c.w
 * gives (2 pi / 3) c.n over the hemisphere about n). */
static double slanted_sky_irradiance(vec3 n) { return PI_D + 2.0 * PI_D / 3.0 * 0.8 * -(double)n.x; }

/* The same sky's irradiance at a floor point d from the wall, counting the wall's hits within R
 * (those GTAO sees): direction w is hidden when -w.x > d / R. Midpoint rule, 400 x 800 cells. */
static double slanted_sky_truth(double d, double R)
{
    const int nt = 400, np = 800;
    double sum = 0.0;
    for (int i = 0; i < nt; i++) {
        double t = (i + 0.5) * (PI_D / 2.0) / nt;
        for (int j = 0; j < np; j++) {
            double p = (j + 0.5) * (2.0 * PI_D) / np, wx = sin(t) * cos(p);
            if (-wx > d / R)
                continue;
            sum += (1.0 + 0.8 * -wx) * cos(t) * sin(t);
        }
    }
    return sum * (PI_D / 2.0 / nt) * (2.0 * PI_D / np);
}

/* The diffuse beside the wall: the wall hides the brightest part of the sky, so the light a floor
 * point receives falls by more than the AO's share; AO E(D) along the bent direction follows it
 * (darker than AO E(N), nearer the truth), and stays AO E(N) on open ground. */
static void test_bent_irradiance(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    sl_error err = {0};
    const float R = 1.0f;
    trace(&gb, &cam, true);
    assert_true(sl_gtao_apply(&gb, &cam, R, 1, NULL, &err));
    const vec3 N = vec3(0.0f, 0.0f, 1.0f);
    const float distances[] = {0.25f, 0.5f};
    for (size_t i = 0; i < sizeof distances / sizeof distances[0]; i++) {
        int x = 0, y = 0;
        floor_pixel(&gb, distances[i], 0.0f, &x, &y);
        sl_vec4 c = gb.cone[y * W + x];
        vec3 D = sl_bent_irradiance_dir(N, vec3(c.x, c.y, c.z), c.w);
        double d = sl_gbuffer_at(&gb, x, y)->position.x, truth = slanted_sky_truth(d, R);
        double flat = c.w * slanted_sky_irradiance(N), bent = c.w * slanted_sky_irradiance(D);
        print_message("floor at %.3f from the wall: AO %.3f, AO E(N) %.4f, AO E(D) %.4f, truth %.4f, error kept %.3f\n", d,
                      (double)c.w, flat, bent, truth, fabs(bent - truth) / fabs(flat - truth));
        assert_true(bent < flat);
        /* measured: AO E(D) keeps 0.69 (d 0.27) and 0.82 (d 0.51) of AO E(N)'s error; the rest is
         * the cone's limit: even E(B) itself (D = B) stays above the truth at the foot */
        assert_true(fabs(bent - truth) < 0.9 * fabs(flat - truth));
    }
    /* open ground: D is N up to the pass's own noise */
    int x = 0, y = 0;
    floor_pixel(&gb, 1.5f, 0.0f, &x, &y);
    sl_vec4 c = gb.cone[y * W + x];
    vec3 D = sl_bent_irradiance_dir(N, vec3(c.x, c.y, c.z), c.w);
    assert_true(D.z > 0.9999f);
    sl_gbuffer_free(&gb);
}

static void test_specular_occlusion(void **state)
{
    (void)state;
    /* Phong exponents and GGX lobe parameters (-1 - r), each from narrow to wide */
    const float phong[] = {10000.0f, 1000.0f, 100.0f, 20.0f, 5.0f, 1.0f, 0.0f};
    const float ggx[] = {-1.02f, -1.1f, -1.2f, -1.4f, -1.6f, -1.8f, -2.0f};
    const float *sets[2] = {phong, ggx};
    for (int set = 0; set < 2; set++)
        for (int i = 0; i < 7; i++) {
            float alpha = sets[set][i];
            for (float nv = 0.05f; nv <= 1.0f; nv += 0.05f) {
                /* open: the whole hemisphere, B = N, so B.R = N.V */
                assert_float_equal(sl_specular_occlusion(1.0f, nv, nv, alpha), 1.0, 0.0);
                assert_float_equal(sl_specular_occlusion(0.0f, nv, nv, alpha), 0.0, 0.0); /* closed */
                float prev = 0.0f; /* the cone opening: never less */
                for (float ao = 0.0f; ao <= 1.0f; ao += 0.01f) {
                    float v = sl_specular_occlusion(ao, nv, nv, alpha);
                    assert_true(v >= 0.0f && v <= 1.0f && v >= prev - 1e-6f);
                    prev = v;
                }
                for (float ao = 0.1f; ao < 1.0f; ao += 0.2f) { /* the lobe's axis leaving the cone: never more */
                    float last = 1.0f;
                    for (float bd = 1.0f; bd >= -1.0f; bd -= 0.02f) {
                        float v = sl_specular_occlusion(ao, bd, nv, alpha);
                        assert_true(v <= last + 1e-6f);
                        last = v;
                    }
                    if (ao <= SL_SO_FADE) /* R opposite the cone's axis: all of the lobe hidden */
                        assert_true(last == 0.0f);
                }
            }
        }
    /* the lobe widening about the cone's axis (R = B = N): never more */
    for (float ao = 0.05f; ao < 1.0f; ao += 0.05f)
        for (int set = 0; set < 2; set++) {
            float last = 1.0f;
            for (int i = 0; i < 7; i++) {
                float v = sl_specular_occlusion(ao, 1.0f, 1.0f, sets[set][i]);
                assert_true(v <= last + 1e-6f);
                last = v;
            }
            if (ao < 0.9f) /* the widest lobe (76 degrees) reaches past a cone of 72 degrees or less */
                assert_true(last < 1.0f);
        }
    /* a mirror along the cone's axis sees nothing of the occluders; half the hemisphere hidden
     * (AO 0.5: the cone's half-angle 45 degrees) hides most of a diffuse-wide Phong lobe */
    assert_float_equal(sl_specular_occlusion(0.5f, 1.0f, 1.0f, 10000.0f), 1.0, 0.0);
    /* open whatever the bent normal and the lobe: a grazing mirror too (the fade) */
    assert_float_equal(sl_specular_occlusion(1.0f, 0.05f, 0.05f, 10000.0f), 1.0, 0.0);
    assert_float_equal(sl_specular_occlusion(1.0f, -0.5f, 0.3f, -1.1f), 1.0, 0.0);
    assert_true(sl_specular_occlusion(0.5f, 1.0f, 1.0f, 1.0f) < 0.8f);
}

static void test_refusals(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_camera cam = corner_camera();
    trace(&gb, &cam, false);
    sl_error err = {0};
    assert_false(sl_gtao_apply(&gb, &cam, 0.0f, 1, NULL, &err));
    assert_string_equal(err.msg, "ambient occlusion: radius 0, expected a positive number");
    assert_false(sl_gtao_apply(&gb, &cam, NAN, 1, NULL, &err));
    assert_true(sl_gbuffer_use_extra(&gb, false, 1, &err));
    assert_false(sl_gtao_apply(&gb, &cam, 1.0f, 1, NULL, &err));
    assert_string_equal(err.msg, "ambient occlusion: the G-buffer has no extra plane to write it into");
    sl_gbuffer_free(&gb);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open_floor),
        cmocka_unit_test(test_wall_corner),
        cmocka_unit_test(test_multiplies_the_map),
        cmocka_unit_test(test_scratch_kept),
        cmocka_unit_test(test_bent_normal),
        cmocka_unit_test(test_bent_irradiance),
        cmocka_unit_test(test_frame_matches_texel),
        cmocka_unit_test(test_frame_matches_texel_small_radius),
        cmocka_unit_test(test_specular_occlusion),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
