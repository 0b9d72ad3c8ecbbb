/* test_visibility.c - the ground truth's visibility (src/shading/visibility.c and the visibility
 * pass of src/shading/ground_truth_image.c) against cases known in closed form: a point under an
 * occluding plane sees nothing; a point on a floor beside a vertical wall under a constant sky
 * gets exactly half the irradiance; a point on a floor beside a unit sphere resting on it loses
 * 1/D^3 of it (D its distance to the sphere's centre); with nothing in the way the visibility
 * pass equals the blind one; a point light behind an occluder is shadowed. Also the cache key
 * (visibility, its level and the geometry are part of it) and, in a build without Embree, the
 * one refusal.
 *
 * Each scene is a few built-in shapes parsed from JSON; each G-buffer a few hand-placed texels,
 * the environment 128x64 (or 256x128 for the sphere at one ray per texel), so the file runs in
 * seconds, also under ASan. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shading/ground_truth_image.h"
#include "shading/visibility.h"
#include "testutil.h"

/* The constant sky L = 1 (or the smooth, coloured one: `coloured`) of w x 2w texels. */
static sl_env make_env(int w, bool coloured)
{
    const int h = w / 2;
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, w, h, 3, &err));
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            vec3 d = sl_uv_to_dir(vec2(((float)i + 0.5f) / (float)w, ((float)j + 0.5f) / (float)h));
            float *p = sl_image_pixel(&img, i, j);
            if (coloured) {
                float lobe = powf(fmaxf(0.0f, d.x * 0.6f + d.y * 0.3f + d.z * 0.74f), 8.0f);
                p[0] = 0.2f + 5.0f * lobe;
                p[1] = 0.3f + 0.5f * d.z * d.z + 2.0f * lobe;
                p[2] = 0.4f + 0.3f * (d.x > 0.0f ? d.x : 0.0f);
            } else {
                p[0] = p[1] = p[2] = 1.0f;
            }
        }
    sl_env env;
    assert_true(sl_env_build(&env, &img, 1, &err));
    sl_image_free(&img);
    return env;
}

static void load_scene(const char *objects, const char *lights, sl_scene *scene)
{
    char json[2048];
    snprintf(json, sizeof json,
             "{\"materials\": {\"m\": {\"kd\": 1, \"ks\": 0.04, \"alpha\": 20}},"
             " \"objects\": [%s], \"lights\": [%s]}",
             objects, lights ? lights : "");
    sl_error err = {0};
    if (!sl_scene_parse(json, strlen(json), "vis.json", "", true, scene, &err))
        fail_msg("scene: %s", err.msg);
}

/* The floor: a plane 2e4 wide at z = 0. */
#define FLOOR "{\"shape\": \"plane\", \"material\": \"m\", \"transform\": {\"scale\": [10000, 10000, 1]}}"

/* A G-buffer of `n` covered texels in one row at positions p with normal +Z (a floor), Kd 1. */
static void make_gbuffer(sl_gbuffer *gb, const vec3 *p, int n)
{
    sl_error err = {0};
    memset(gb, 0, sizeof *gb);
    assert_true(sl_gbuffer_resize(gb, n, 1, &err));
    sl_gbuffer_clear(gb, 1);
    for (int i = 0; i < n; i++) {
        sl_gbuffer_texel *t = sl_gbuffer_at(gb, i, 0);
        t->position = p[i];
        t->normal = vec3(0.0f, 0.0f, 1.0f);
        t->kd = vec3(1.0f, 1.0f, 1.0f);
        t->ks = vec3(0.04f, 0.04f, 0.04f);
        t->alpha = 20.0f;
        t->depth = 0.5f;
    }
}

static sl_gt_image_desc desc_of(const sl_env *env, const sl_gbuffer *gb, const sl_scene *scene, vec3 eye, int level)
{
    return (sl_gt_image_desc){.env = env, .gbuffer = gb, .eye = eye, .env_intensity = 1.0f, .threads = 2,
                              .scene = scene, .visibility = true, .visibility_level = level};
}

static float diffuse_at(const sl_gt_image *img, int x) { return sl_image_pixel(&img->diffuse, x, 0)[0]; }

static int skip_without_embree(void)
{
    if (sl_visibility_available())
        return 0;
    print_message("this build has no Embree: visibility is not traced\n");
    skip();
    return 1;
}

/* Under a plane at z = 1 (2e4 wide), a point of the floor sees no sky at all. */
static void test_under_a_plane_sees_nothing(void **state)
{
    (void)state;
    if (skip_without_embree())
        return;
    sl_scene scene;
    load_scene(FLOOR ", {\"shape\": \"plane\", \"material\": \"m\", \"transform\": "
                     "{\"translate\": [0, 0, 1], \"scale\": [10000, 10000, 1]}}",
               NULL, &scene);
    sl_env env = make_env(128, false);
    sl_gbuffer gb;
    const vec3 p[2] = {vec3(0.0f, 0.0f, 0.0f), vec3(3.0f, -2.0f, 0.0f)};
    make_gbuffer(&gb, p, 2);
    sl_gt_image_desc d = desc_of(&env, &gb, &scene, vec3(0.5f, -0.7f, 0.6f), 2);
    sl_error err = {0};
    sl_gt_image img;
    if (!sl_gt_image_compute(&img, &d, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(img.ng_fallbacks, 0);
    assert_true(img.rays > 2);
    for (int x = 0; x < 2; x++)
        for (int ch = 0; ch < 3; ch++) {
            assert_true(sl_image_pixel(&img.diffuse, x, 0)[ch] == 0.0f);
            assert_true(sl_image_pixel(&img.specular[0], x, 0)[ch] == 0.0f);
            assert_true(sl_image_pixel(&img.specular[1], x, 0)[ch] == 0.0f);
        }
    sl_gt_image_free(&img);
    /* the same point blind: the whole sky, Kd L = 1 */
    d.visibility = false;
    assert_true(sl_gt_image_compute(&img, &d, &err));
    assert_near(diffuse_at(&img, 0), 1.0, 1e-6);
    sl_gt_image_free(&img);
    sl_gbuffer_free(&gb);
    sl_env_free(&env);
    sl_scene_free(&scene);
}

/* Beside a vertical wall x = 0.5 (2e4 wide and high) every direction with w.x > 0 is blocked:
 * the irradiance of a constant sky L over the quarter sphere left is L pi / 2, so the diffuse
 * radiance is Kd L / 2. The wall's plane runs along texel and cell edges, where the quadrature
 * is exact. */
static void test_wall_blocks_half_the_sky(void **state)
{
    (void)state;
    if (skip_without_embree())
        return;
    sl_scene scene;
    load_scene(FLOOR ", {\"shape\": \"plane\", \"material\": \"m\", \"transform\": "
                     "{\"translate\": [0.5, 0, 0], \"rotate\": [0, 1, 0, 90], \"scale\": [10000, 10000, 1]}}",
               NULL, &scene);
    sl_env env = make_env(128, false);
    sl_gbuffer gb;
    const vec3 p[3] = {vec3(0.0f, 0.0f, 0.0f), vec3(-2.0f, 1.0f, 0.0f), vec3(0.4f, -3.0f, 0.0f)};
    make_gbuffer(&gb, p, 3);
    sl_error err = {0};
    for (int level = 0; level <= 3; level++) {
        sl_gt_image_desc d = desc_of(&env, &gb, &scene, vec3(-1.0f, -0.3f, 0.5f), level);
        sl_gt_image img;
        if (!sl_gt_image_compute(&img, &d, &err))
            fail_msg("%s", err.msg);
        assert_int_equal(img.ng_fallbacks, 0);
        for (int x = 0; x < 3; x++)
            for (int ch = 0; ch < 3; ch++)
                assert_near(sl_image_pixel(&img.diffuse, x, 0)[ch], 0.5, 1e-6);
        sl_gt_image_free(&img);
    }
    sl_gbuffer_free(&gb);
    sl_env_free(&env);
    sl_scene_free(&scene);
}

/* A unit sphere resting on the floor at the origin, seen from a point of the floor at distance
 * D from its centre: the sphere subtends a cap of sin(beta) = 1/D whose axis has elevation
 * sin(e) = 1/D, tangent to the horizon, so it takes pi sin^2(beta) sin(e) = pi / D^3 of the
 * cosine-weighted sky: diffuse = Kd L (1 - 1/D^3). Within the quadrature's error (cells cut by
 * the sphere's outline, the tessellated sphere inside the true one), and the nearer point is the
 * darker. */
static void test_sphere_on_floor(void **state)
{
    (void)state;
    if (skip_without_embree())
        return;
    sl_scene scene;
    load_scene(FLOOR ", {\"shape\": \"sphere\", \"slices\": 128, \"stacks\": 64, \"material\": \"m\", "
                     "\"transform\": {\"translate\": [0, 0, 1]}}",
               NULL, &scene);
    sl_env env = make_env(256, false);
    sl_gbuffer gb;
    const float xs[3] = {1.2f, 2.0f, 4.0f}; /* distances from the point of contact */
    const vec3 p[3] = {vec3(xs[0], 0.0f, 0.0f), vec3(1.6f, 1.2f, 0.0f), vec3(xs[2], 0.0f, 0.0f)};
    make_gbuffer(&gb, p, 3);
    sl_error err = {0};
    double prev_error = 1e9;
    for (int level = 2; level >= 0; level -= 2) {
        /* the eye sees each point past the sphere, so the eye ray gives the floor's normal */
        sl_gt_image_desc d = desc_of(&env, &gb, &scene, vec3(10.0f, 1.0f, 3.0f), level);
        sl_gt_image img;
        if (!sl_gt_image_compute(&img, &d, &err))
            fail_msg("%s", err.msg);
        assert_int_equal(img.ng_fallbacks, 0);
        double worst = 0.0;
        for (int x = 0; x < 3; x++) {
            double D = sqrt((double)xs[x] * (double)xs[x] + 1.0), blocked = 1.0 / (D * D * D);
            double got = 1.0 - (double)diffuse_at(&img, x);
            double rel = fabs(got - blocked) / blocked;
            print_message("level %d, D = %.3f: blocked %.5f, want %.5f (%.2f%% off)\n", level, D, got, blocked,
                          100.0 * rel);
            worst = fmax(worst, rel);
        }
        assert_true(worst < (level == 0 ? 0.01 : 0.1));
        assert_true(worst <= prev_error); /* finer cells, closer */
        prev_error = worst;
        assert_true(diffuse_at(&img, 0) < diffuse_at(&img, 1) && diffuse_at(&img, 1) < diffuse_at(&img, 2));
        sl_gt_image_free(&img);
    }
    sl_gbuffer_free(&gb);
    sl_env_free(&env);
    sl_scene_free(&scene);
}

/* With nothing above the floor, the visibility pass sums what the blind one sums (in another
 * order): diffuse and both specular planes agree to rounding, for a coloured sky and rotated. */
static void test_nothing_in_the_way_equals_blind(void **state)
{
    (void)state;
    if (skip_without_embree())
        return;
    sl_scene scene;
    load_scene(FLOOR, NULL, &scene);
    sl_env env = make_env(128, true);
    sl_gbuffer gb;
    const vec3 p[3] = {vec3(0.0f, 0.0f, 0.0f), vec3(-2.0f, 1.0f, 0.0f), vec3(0.4f, -3.0f, 0.0f)};
    make_gbuffer(&gb, p, 3);
    sl_gbuffer_at(&gb, 1, 0)->alpha = 500.0f;
    sl_gbuffer_at(&gb, 2, 0)->alpha = sl_gbuffer_ggx_alpha(0.3f);
    sl_gt_image_desc d = desc_of(&env, &gb, &scene, vec3(-1.0f, -4.0f, 2.0f), 3);
    d.env_rotation_deg = 40.0f;
    sl_error err = {0};
    sl_gt_image vis, blind;
    assert_true(sl_gt_image_compute(&vis, &d, &err));
    d.visibility = false;
    assert_true(sl_gt_image_compute(&blind, &d, &err));
    for (int x = 0; x < 3; x++)
        for (int ch = 0; ch < 3; ch++) {
            double b = (double)sl_image_pixel(&blind.diffuse, x, 0)[ch];
            assert_near(sl_image_pixel(&vis.diffuse, x, 0)[ch], b, 1e-6 * b);
            for (int g = 0; g < 2; g++) {
                double s = (double)sl_image_pixel(&blind.specular[g], x, 0)[ch];
                assert_true(s > 0.0);
                assert_near(sl_image_pixel(&vis.specular[g], x, 0)[ch], s, 1e-6 * s);
            }
        }
    sl_gt_image_free(&vis);
    sl_gt_image_free(&blind);
    sl_gbuffer_free(&gb);
    sl_env_free(&env);
    sl_scene_free(&scene);
}

/* Point lights: without visibility, f color intensity / d^2 (N.L) exactly as lighting.frag adds
 * them (here the diffuse part: Kd / pi I / d^2 cos); with it, a light above an occluding plane
 * is shadowed and one below it is not. The environment is black, so the lights are all there is. */
static void test_point_lights(void **state)
{
    (void)state;
    sl_scene scene;
    load_scene(FLOOR ", {\"shape\": \"plane\", \"material\": \"m\", \"transform\": "
                     "{\"translate\": [0, 0, 1], \"scale\": [10000, 10000, 1]}}",
               "{\"position\": [0, 0, 0.5], \"color\": [1, 1, 1], \"intensity\": 2},"
               " {\"position\": [1, 0, 3], \"color\": [1, 0.5, 0.25], \"intensity\": 50}",
               &scene);
    sl_env env = make_env(64, false);
    sl_gbuffer gb;
    const vec3 p[1] = {vec3(0.0f, 0.0f, 0.0f)};
    make_gbuffer(&gb, p, 1);
    sl_gt_image_desc d = desc_of(&env, &gb, &scene, vec3(0.5f, -0.7f, 0.6f), 3);
    d.env_intensity = 0.0f; /* the lights alone */
    d.visibility = false;
    d.lights = true;
    sl_error err = {0};
    sl_gt_image img;
    assert_true(sl_gt_image_compute(&img, &d, &err));
    /* light 0: straight above at 0.5: 2 / 0.25; light 1: at distance sqrt(10), cos 3 / sqrt(10) */
    const double pi = 3.14159265358979323846, d1 = sqrt(10.0);
    const double e0 = 2.0 / 0.25, e1 = 50.0 / 10.0 * (3.0 / d1);
    const double want[3] = {(e0 + e1) / pi, (e0 + 0.5 * e1) / pi, (e0 + 0.25 * e1) / pi};
    for (int ch = 0; ch < 3; ch++)
        assert_near(sl_image_pixel(&img.diffuse, 0, 0)[ch], want[ch], 1e-6 * want[ch]);
    sl_gt_image_free(&img);
    if (!sl_visibility_available())
        goto done;
    d.visibility = true;
    assert_true(sl_gt_image_compute(&img, &d, &err));
    for (int ch = 0; ch < 3; ch++) /* light 1 is above the plane at z = 1 */
        assert_near(sl_image_pixel(&img.diffuse, 0, 0)[ch], e0 / pi, 1e-6 * e0 / pi);
    assert_true(sl_image_pixel(&img.specular[0], 0, 0)[0] > 0.0f);
    sl_gt_image_free(&img);
done:
    sl_gbuffer_free(&gb);
    sl_env_free(&env);
    sl_scene_free(&scene);
}

/* The cache key: the blind key is unchanged by a scene; visibility, its level, the geometry and
 * point lights each change it. */
static void test_key(void **state)
{
    (void)state;
    sl_scene a, b;
    load_scene(FLOOR, NULL, &a);
    load_scene(FLOOR ", {\"shape\": \"box\", \"material\": \"m\"}", NULL, &b);
    sl_env env = make_env(32, false);
    sl_gbuffer gb;
    const vec3 p[1] = {vec3(0.0f, 0.0f, 0.0f)};
    make_gbuffer(&gb, p, 1);
    sl_gt_image_desc d = desc_of(&env, &gb, &a, vec3(0.5f, -0.7f, 0.6f), 3);
    d.visibility = false;
    uint64_t blind = sl_gt_image_key(&d);
    d.scene = &b;
    assert_true(sl_gt_image_key(&d) == blind);
    d.visibility = true;
    uint64_t vis_b = sl_gt_image_key(&d);
    d.scene = &a;
    uint64_t vis_a = sl_gt_image_key(&d);
    d.visibility_level = 2;
    uint64_t vis_a2 = sl_gt_image_key(&d);
    d.lights = true;
    uint64_t vis_a2_lights = sl_gt_image_key(&d);
    assert_true(vis_a != blind && vis_b != vis_a && vis_a2 != vis_a && vis_a2_lights != vis_a2);
    sl_gbuffer_free(&gb);
    sl_env_free(&env);
    sl_scene_free(&a);
    sl_scene_free(&b);
}

/* A build without Embree refuses visibility in one message (and computes the rest). */
static void test_without_embree(void **state)
{
    (void)state;
    if (sl_visibility_available()) {
        skip();
        return;
    }
    sl_scene scene;
    load_scene(FLOOR, NULL, &scene);
    sl_env env = make_env(32, false);
    sl_gbuffer gb;
    const vec3 p[1] = {vec3(0.0f, 0.0f, 0.0f)};
    make_gbuffer(&gb, p, 1);
    sl_gt_image_desc d = desc_of(&env, &gb, &scene, vec3(0.5f, -0.7f, 0.6f), 3);
    sl_error err = {0};
    sl_gt_image img;
    assert_false(sl_gt_image_compute(&img, &d, &err));
    assert_msg_contains(err, "needs Embree");
    assert_null(sl_visibility_create(&scene, NULL, 1, &err));
    sl_gbuffer_free(&gb);
    sl_env_free(&env);
    sl_scene_free(&scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_under_a_plane_sees_nothing),
        cmocka_unit_test(test_wall_blocks_half_the_sky),
        cmocka_unit_test(test_sphere_on_floor),
        cmocka_unit_test(test_nothing_in_the_way_equals_blind),
        cmocka_unit_test(test_point_lights),
        cmocka_unit_test(test_key),
        cmocka_unit_test(test_without_embree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
