/* test_ibl_irradiance_map.c - the pole-free irradiance maps (src/ibl/irradiance_map.c) against
 * the ground truth (src/ibl/ground_truth.h) where the lat-long maps fail: a floor (N = +Z) under a
 * sun 3 degrees above the horizon, N exactly +Z, -Z, on the lat-long seam and on the
 * octahedral folds, and a sun standing at the pole. Also: the closed form of a constant
 * environment, the layouts' landmarks, continuity across the folds, thread-count independence
 * and the argument checks. docs/ibl.md has the measured comparison these tolerances come from. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "ibl/ground_truth.h"
#include "ibl/ibl.h"
#include "testutil.h"

#define PI 3.14159265358979323846

static const sl_irradiance_method layouts[2] = {SL_IRRADIANCE_OCT, SL_IRRADIANCE_DP};
static const char *const layout_names[2] = {"oct", "dp"};

/* A sky (1 + z above the horizon, 0.2 below, slightly coloured) and a sun of radius 0.27 degrees
 * and radiance 2e5 at polar angle sun_theta, azimuth 0.7: ~1000 times the sky's irradiance. */
static double sun_theta;
static double sky_with_sun(const double w[3], int ch)
{
    double sd[3] = {sin(sun_theta) * cos(0.7), sin(sun_theta) * sin(0.7), cos(sun_theta)};
    double L = w[2] > 0 ? 1.0 + w[2] : 0.2;
    if (w[0] * sd[0] + w[1] * sd[1] + w[2] * sd[2] > cos(0.27 * PI / 180))
        L = 2e5;
    return L * (1.0 - 0.1 * ch);
}

static double constant_env(const double w[3], int ch)
{
    (void)w;
    (void)ch;
    return 1.0;
}

/* The truth's E(n) = pi * diffuse with Kd = 1. */
static void truth_e(const sl_ground_truth *gt, vec3 n, double e[3])
{
    sl_gt_result r;
    sl_error err = {0};
    sl_gt_query q = {.n = n, .v = n, .kd = vec3s(1.0f), .ks = vec3s(0.0f), .alpha = 1.0, .intensity = 1.0};
    assert_true(sl_ground_truth_shade(gt, &q, &r, &err));
    for (int c = 0; c < 3; c++)
        e[c] = PI * r.diffuse[c];
}

static double worst_rel(const sl_irradiance *irr, const sl_ground_truth *gt, vec3 n)
{
    double t[3];
    truth_e(gt, n, t);
    vec3 e = sl_irradiance_eval(irr, n);
    double got[3] = {e.x, e.y, e.z}, worst = 0.0;
    for (int c = 0; c < 3; c++)
        worst = fmax(worst, fabs(got[c] - t[c]) / t[c]);
    return worst;
}

static vec3 unit(double x, double y, double z)
{
    double l = sqrt(x * x + y * y + z * z);
    return vec3(x / l, y / l, z / l);
}

/* The hard normals, each against the truth, for a sun at polar angle theta (degrees). The
 * lat-long brute map is measured beside them (printed, not asserted: it is the case it fails). */
static void hard_normals(double theta_deg, double tolerance, double terminator_tolerance)
{
    sun_theta = theta_deg * PI / 180.0;
    sl_env env = test_make_env(1024, 512, sky_with_sun);
    sl_ground_truth gt;
    sl_error err = {0};
    assert_true(sl_ground_truth_init(&gt, &env, &err));
    /* on_terminator: the normal is 90 degrees from the sun (for the sun at the pole, the
     * equator), where E has a kink that bilinear filtering rounds off over one texel */
    const struct {
        const char *name;
        vec3 n;
        bool on_terminator;
    } normals[] = {
        {"+Z (a floor)", vec3(0, 0, 1), false},
        {"-Z", vec3(0, 0, -1), false},
        {"seam (-1, 0, 0)", vec3(-1, 0, 0), theta_deg < 2},
        {"seam, 20 deg up", unit(-cos(0.35), 0, sin(0.35)), false},
        {"floor, 0.5 deg tilt", unit(sin(0.5 * PI / 180), 0, cos(0.5 * PI / 180)), false},
        {"floor, 2 deg tilt toward the sun", unit(sin(2 * PI / 180) * cos(0.7), sin(2 * PI / 180) * sin(0.7), cos(2 * PI / 180)), false},
        {"oct fold y = 0", unit(0.6, 0, -0.8), false},
        {"oct fold x = 0", unit(0, -0.6, -0.8), false},
        {"equator", unit(0.7, 0.7, 0), theta_deg < 2},
        {"equator, between texels", unit(cos(0.3), sin(0.3), 0), theta_deg < 2},
    };
    int count = (int)(sizeof normals / sizeof *normals);
    sl_irradiance brute;
    assert_true(sl_irradiance_brute(&brute, &env, 64, 0, &err));
    for (int l = 0; l < 2; l++) {
        sl_irradiance irr;
        assert_true(sl_irradiance_map(&irr, &env, &(sl_irradiance_map_desc){.method = layouts[l]}, &err));
        for (int k = 0; k < count; k++) {
            double e = worst_rel(&irr, &gt, normals[k].n);
            print_message("sun %4.1f deg from +Z, %s, %-34s %.4f%%  (lat-long brute map %.3f%%)\n", theta_deg,
                          layout_names[l], normals[k].name, 100 * e, 100 * worst_rel(&brute, &gt, normals[k].n));
            double tol = normals[k].on_terminator ? terminator_tolerance : tolerance;
            if (!(e <= tol))
                fail_msg("%s, %s: %.4g relative, tolerance %.4g", layout_names[l], normals[k].name, e, tol);
        }
        sl_irradiance_free(&irr);
    }
    sl_irradiance_free(&brute);
    sl_ground_truth_free(&gt);
    sl_env_free(&env);
}

/* The floor under a sun 3 degrees above the horizon: the lat-long map reads its row 0 for +Z
 * (a few % off); the pole-free maps hold +Z at a texel and are within 0.1% there and at the
 * other hard normals (measured: below 0.05%). */
static void test_sun_near_horizon(void **state)
{
    (void)state;
    hard_normals(87.0, 1e-3, 1e-3);
}

/* A sun at the pole (and 1 degree from it): the lat-long map's worst case for +Z. Its
 * terminator is then the equator, where the sky alone (1000 times fainter than the sun) lights
 * n and the map's one-texel rounding of the kink shows: measured up to 1.7% (dp) there, which
 * is the interpolation's worst case (docs/ibl.md); everywhere else 0.1%. */
static void test_sun_at_pole(void **state)
{
    (void)state;
    hard_normals(0.0, 1e-3, 5e-2);
    hard_normals(1.0, 1e-3, 5e-2);
}

/* Constant L = 1: E = pi for every n (the truth's own error is 4e-6). Groups wholly above or
 * below the horizon are exact; the smoothed clamp of those cut by it is symmetric, so what is
 * left is of second order in the group size. */
static void test_constant(void **state)
{
    (void)state;
    sl_env env = test_make_env(256, 128, constant_env);
    sl_error err = {0};
    for (int l = 0; l < 2; l++) {
        sl_irradiance irr;
        assert_true(sl_irradiance_map(&irr, &env, &(sl_irradiance_map_desc){.method = layouts[l], .size = 33}, &err));
        double worst = 0.0;
        for (int k = 0; k < 2000; k++) {
            double z = 1.0 - 2.0 * k / 1999.0, s = sqrt(fmax(0.0, 1.0 - z * z)), phi = k * 2.399963229728653;
            vec3 e = sl_irradiance_eval(&irr, vec3(s * cos(phi), s * sin(phi), z));
            worst = fmax(worst, fabs(e.x - PI) / PI);
            worst = fmax(worst, fabs(e.z - PI) / PI);
        }
        print_message("constant environment, %s 33: worst relative error %.3g\n", layout_names[l], worst);
        assert_true(worst < 1e-3); /* measured 7.2e-4 (oct 33, 32x16 groups: the box only matches the variance) */
        sl_irradiance_free(&irr);
    }
    sl_env_free(&env);
}

/* Landmarks of the layouts (vertex-centred grids, uv clamped to the outer texel centres). */
static void test_layout_landmarks(void **state)
{
    (void)state;
    const int s = 129;
    vec2 uv = sl_irradiance_oct_uv(vec3(0, 0, 1), s);
    assert_near(uv.x, 0.5, 1e-7);
    assert_near(uv.y, 0.5, 1e-7);
    uv = sl_irradiance_oct_uv(vec3(0, 0, -1), s); /* a corner texel's centre */
    assert_near(uv.x, 1.0 - 0.5 / s, 1e-7);
    assert_near(uv.y, 1.0 - 0.5 / s, 1e-7);
    uv = sl_irradiance_oct_uv(vec3(1, 0, 0), s); /* the equator's corner of the diamond */
    assert_near(uv.x, 1.0 - 0.5 / s, 1e-7);
    assert_near(uv.y, 0.5, 1e-7);
    uv = sl_irradiance_dp_uv(vec3(0, 0, 1), s);
    assert_near(uv.x, 0.25, 1e-7);
    assert_near(uv.y, 0.5, 1e-7);
    uv = sl_irradiance_dp_uv(vec3(0, 0, -1), s);
    assert_near(uv.x, 0.75, 1e-7);
    uv = sl_irradiance_dp_uv(vec3(1, 0, 0), s); /* the rim, within the left half */
    assert_near(uv.x, 0.5 * (1.0 - 0.5 / s), 1e-7);
    /* a NaN direction stays inside the map */
    uv = sl_irradiance_oct_uv(vec3(NAN, 0, 0), s);
    assert_true(uv.x >= 0.5f / s && uv.x <= 1.0f - 0.5f / s);
}

/* Continuity: across an octahedral fold (n.z < 0, x = 0 or y = 0) and across the dual
 * paraboloid's equator, E moves by no more than its own variation over the step. */
static void test_continuity(void **state)
{
    (void)state;
    sun_theta = 60.0 * PI / 180.0;
    sl_env env = test_make_env(256, 128, sky_with_sun);
    sl_error err = {0};
    for (int l = 0; l < 2; l++) {
        sl_irradiance irr;
        assert_true(sl_irradiance_map(&irr, &env, &(sl_irradiance_map_desc){.method = layouts[l]}, &err));
        double worst = 0.0;
        for (int k = 0; k < 200; k++) {
            double a = 0.05 + 1.4 * k / 199.0, eps = 1e-6;
            /* y = 0 fold, x = 0 fold (below the equator), and the equator */
            vec3 pairs[3][2] = {
                {unit(sin(a), eps, -cos(a)), unit(sin(a), -eps, -cos(a))},
                {unit(eps, sin(a), -cos(a)), unit(-eps, sin(a), -cos(a))},
                {unit(cos(4 * a), sin(4 * a), eps), unit(cos(4 * a), sin(4 * a), -eps)},
            };
            for (int p = 0; p < 3; p++) {
                vec3 e0 = sl_irradiance_eval(&irr, pairs[p][0]), e1 = sl_irradiance_eval(&irr, pairs[p][1]);
                worst = fmax(worst, fabs(e0.x - e1.x) / fmax(e0.x, e1.x));
            }
        }
        print_message("%s: largest jump across a fold or the equator %.3g\n", layout_names[l], worst);
        /* oct: continuous by construction (measured 7e-5: E's own change over the 2e-6 step);
         * dp: the halves meet only up to the interpolation error of each (measured 0.9% under
         * this sun: a visible seam at the equator, one reason oct is the default) */
        assert_true(worst < (layouts[l] == SL_IRRADIANCE_OCT ? 2e-4 : 2e-2));
        sl_irradiance_free(&irr);
    }
    sl_env_free(&env);
}

static void test_thread_count(void **state)
{
    (void)state;
    sun_theta = 87.0 * PI / 180.0;
    sl_env env = test_make_env(512, 256, sky_with_sun);
    sl_error err = {0};
    sl_irradiance a, b;
    int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    assert_true(sl_irradiance_map(&a, &env, &(sl_irradiance_map_desc){.size = 33}, &err));
    omp_set_num_threads(3);
    assert_true(sl_irradiance_map(&b, &env, &(sl_irradiance_map_desc){.size = 33}, &err));
    omp_set_num_threads(saved);
    assert_int_equal(a.method, SL_IRRADIANCE_OCT);
    assert_same_texels(a.map.levels[0].texels, b.map.levels[0].texels, 33 * 33, sizeof(vec3), 33,
                       "octahedral irradiance, 1 thread against 3");
    sl_irradiance_free(&a);
    sl_irradiance_free(&b);
    sl_env_free(&env);
}

static void test_arguments(void **state)
{
    (void)state;
    sl_env env = test_make_env(16, 8, constant_env);
    sl_error err = {0};
    sl_irradiance irr;
    assert_false(sl_irradiance_map(&irr, &env, &(sl_irradiance_map_desc){.size = 64}, &err)); /* even */
    assert_false(sl_irradiance_map(&irr, &env, &(sl_irradiance_map_desc){.size = 1}, &err));
    assert_false(sl_irradiance_map(&irr, &env, &(sl_irradiance_map_desc){.method = SL_IRRADIANCE_BRUTE}, &err));
    assert_false(sl_irradiance_map(&irr, &env, &(sl_irradiance_map_desc){.source_level = 99}, &err));
    sl_env empty = {0};
    assert_false(sl_irradiance_map(&irr, &empty, NULL, &err));
    /* a 1x1 environment works (one group, every level the same) */
    sl_env one = test_make_env(1, 1, constant_env);
    assert_true(sl_irradiance_map(&irr, &one, &(sl_irradiance_map_desc){.method = SL_IRRADIANCE_DP, .size = 5}, &err));
    vec3 e = sl_irradiance_eval(&irr, vec3(0, 0, 1));
    assert_true(isfinite(e.x) && e.x > 0.0f);
    sl_irradiance_free(&irr);
    sl_env_free(&one);
    sl_env_free(&env);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layout_landmarks), cmocka_unit_test(test_constant),
        cmocka_unit_test(test_sun_near_horizon), cmocka_unit_test(test_sun_at_pole),
        cmocka_unit_test(test_continuity),       cmocka_unit_test(test_thread_count),
        cmocka_unit_test(test_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
