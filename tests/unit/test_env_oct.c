/* test_env_oct.c - the octahedral specular chain (src/ibl/env_oct.c, texture_lod.h sl_oct_*):
 * exact texel solid angles, a constant environment constant at every level, a delta's power
 * kept per level, lookups at exactly +Z and -Z, the fold at the edge. */
#include "testutil.h"

#include <math.h>

#define M_PI_ 3.14159265358979323846
#include <stdlib.h>

#include "ibl/ibl.h"
#include "ibl/texture_lod.h"

/* A W x H lat-long environment with every texel c, and one texel (bi, bj) at `bright`. */
static void make_env(sl_env *env, int w, int h, float c, int bi, int bj, float bright)
{
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, w, h, 3, &err));
    for (int k = 0; k < w * h * 3; k++)
        img.data[k] = c;
    if (bi >= 0)
        for (int ch = 0; ch < 3; ch++)
            img.data[3 * (bj * w + bi) + ch] = bright;
    assert_true(sl_env_build(env, &img, 0, &err));
    sl_image_free(&img);
}

static void test_solid_angles_sum_to_4pi(void **state)
{
    (void)state;
    for (int s = 1; s <= 64; s *= 2) {
        double sum = 0.0;
        for (int j = 0; j < s; j++)
            for (int i = 0; i < s; i++)
                sum += sl_env_oct_texel_solid_angle(s, i, j);
        assert_true(fabs(sum - 4.0 * M_PI_) < 1e-9);
    }
    /* S = 2: each texel a quadrant, an eighth of the sphere above and one below: pi */
    assert_true(fabs(sl_env_oct_texel_solid_angle(2, 0, 0) - M_PI_) < 1e-12);
}

static void test_constant_stays_constant(void **state)
{
    (void)state;
    sl_env env, oct;
    sl_error err = {0};
    make_env(&env, 64, 32, 0.75f, -1, 0, 0.0f);
    assert_true(sl_env_build_oct(&oct, &env, 0, 0, &err));
    assert_int_equal(oct.levels[0].width, 64);
    assert_int_equal(oct.level_count, 7);
    for (int l = 0; l < oct.level_count; l++)
        for (int t = 0; t < oct.levels[l].width * oct.levels[l].height; t++)
            assert_true(fabsf(oct.levels[l].texels[t].x - 0.75f) < 1e-6f);
    sl_env_free(&env);
    sl_env_free(&oct);
}

static void test_delta_power_per_level(void **state)
{
    (void)state;
    sl_env env, oct;
    sl_error err = {0};
    make_env(&env, 64, 32, 0.0f, 20, 9, 1000.0f);
    assert_true(sl_env_build_oct(&oct, &env, 0, 0, &err));
    double p0 = 0.0;
    for (int l = 0; l < oct.level_count; l++) {
        int s = oct.levels[l].width;
        double p = 0.0;
        for (int j = 0; j < s; j++)
            for (int i = 0; i < s; i++)
                p += sl_env_oct_texel_solid_angle(s, i, j) * (double)oct.levels[l].texels[j * s + i].x;
        if (l == 0)
            p0 = p;
        assert_true(fabs(p - p0) < 1e-5 * p0);
    }
    /* level 0 against the lat-long texel's power: 1000 times its solid angle (row 9 of 32) */
    double omega = (2.0 * M_PI_ / 64.0) * (cos(M_PI_ * 9 / 32) - cos(M_PI_ * 10 / 32));
    assert_true(fabs(p0 - 1000.0 * omega) < 0.05 * 1000.0 * omega);
    sl_env_free(&env);
    sl_env_free(&oct);
}

/* +Z: the lat-long lookup reads row 0 at one azimuth, the octahedral one the cap around the pole.
 * An environment whose top row is bright in one column only: the truth at the pole (the mean of
 * the row-0 texels around it, each covering the same solid angle) is 1 + 99 / 64. */
static void test_poles(void **state)
{
    (void)state;
    sl_env env, oct;
    sl_error err = {0};
    make_env(&env, 64, 32, 1.0f, 32, 0, 100.0f);
    assert_true(sl_env_build_oct(&oct, &env, 0, 0, &err));
    double truth = 1.0 + 99.0 / 64.0;
    vec3 o = sl_oct_texture_lod(&oct, vec3(0.0f, 0.0f, 1.0f), 0.0f);
    vec3 l = textureLod(&env, sl_dir_to_uv(vec3(0.0f, 0.0f, 1.0f)), 0.0f);
    /* lat-long reads half the bright column (u = 1/2 lies between columns 31 and 32): 50.5 */
    assert_true(l.x > 40.0f);
    assert_true(fabs((double)o.x - truth) < 0.5 * fabs((double)l.x - truth));
    /* -Z: a constant bottom reads 1 from all four corners */
    vec3 d = sl_oct_texture_lod(&oct, vec3(0.0f, 0.0f, -1.0f), 0.0f);
    assert_true(fabsf(d.x - 1.0f) < 1e-6f);
    sl_env_free(&env);
    sl_env_free(&oct);
}

/* The fold: directions just either side of the outer edge (below the equator, x = 0) read the
 * same value; the taps past the edge are the mirrored texels. */
static void test_fold(void **state)
{
    (void)state;
    assert_int_equal(sl_oct_tap(8, -1, 2), 5 * 8 + 0);
    assert_int_equal(sl_oct_tap(8, 3, 8), 7 * 8 + 4);
    assert_int_equal(sl_oct_tap(8, -1, -1), 7 * 8 + 7);
    sl_env env, oct;
    sl_error err = {0};
    make_env(&env, 64, 32, 1.0f, 10, 25, 50.0f);
    assert_true(sl_env_build_oct(&oct, &env, 0, 0, &err));
    vec3 a = sl_oct_texture_lod(&oct, normalize(vec3(1e-4f, 0.6f, -0.8f)), 1.0f);
    vec3 b = sl_oct_texture_lod(&oct, normalize(vec3(-1e-4f, 0.6f, -0.8f)), 1.0f);
    assert_true(fabsf(a.x - b.x) < 1e-3f * a.x);
    sl_env_free(&env);
    sl_env_free(&oct);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_solid_angles_sum_to_4pi), cmocka_unit_test(test_constant_stays_constant),
        cmocka_unit_test(test_delta_power_per_level),   cmocka_unit_test(test_poles),
        cmocka_unit_test(test_fold),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
