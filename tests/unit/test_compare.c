/* test_compare.c - the image comparison metrics (src/post/compare.c) against values worked out by
 * hand on tiny images, the mask, NaN handling, the nearest-rank percentile and the diff colours. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "testutil.h"

#include "post/compare.h"

static void make_image(sl_image *img, int w, int h, int ch, float value)
{
    sl_error err = {0};
    assert_true(sl_image_alloc(img, w, h, ch, &err));
    for (size_t i = 0; i < (size_t)w * (size_t)h * (size_t)ch; i++)
        img->data[i] = value;
}

/* The specification's tone map at exposure 1, contrast 1: ((x / (x + 1))^(1/2.2)). */
static double tm1(double x) { return pow(x / (x + 1.0), 1.0 / 2.2); }

static void test_tonemap_values(void **state)
{
    (void)state;
    assert_near(sl_compare_tonemap(1.0f, 1.0f, 1.0f), pow(0.5, 1.0 / 2.2), 1e-6);
    /* e = 2, c = 2.2: the exponent is 1, so T(1.5) = 3 / 4 exactly */
    assert_near(sl_compare_tonemap(1.5f, 2.0f, 2.2f), 0.75, 1e-7);
    assert_near(sl_compare_tonemap(0.0f, 1.0f, 1.0f), 0.0, 0.0);
    assert_near(sl_compare_tonemap(-1.0f, 1.0f, 1.0f), 0.0, 0.0);
    assert_near(sl_compare_tonemap(INFINITY, 1.0f, 1.0f), 1.0, 0.0);
}

/* 2x2 RGB, all 1 in A. B differs in two values: (1,0).r = 1.5 and (0,1).b = 0.
 * 12 values, differences 0.5 and 1: max 1, mean 1.5/12, rmse sqrt(1.25/12); B's values square
 * to 10 * 1 + 2.25 + 0 = 12.25, so nrmse = sqrt(1.25 / 12.25).
 * Pixel relative errors: 0.5/1.5 = 1/3 and 1/1 = 1, others 0: mean 1/3, p99 (rank 4 of 4) = 1.
 * 8-bit: T(1) = 0.7297 -> 186, T(1.5) = 0.7927 -> 202, T(0) -> 0: both changed pixels exceed
 * 8 levels, so 2 of 4 pixels are over 1 and over 8 levels. */
static void test_hand_computed(void **state)
{
    (void)state;
    sl_image a, b;
    make_image(&a, 2, 2, 3, 1.0f);
    make_image(&b, 2, 2, 3, 1.0f);
    sl_image_pixel(&b, 1, 0)[0] = 1.5f;
    sl_image_pixel(&b, 0, 1)[2] = 0.0f;
    sl_compare_stats s;
    sl_error err = {0};
    assert_true(sl_compare_images(&a, &b, NULL, &s, &err));
    assert_int_equal(s.pixels, 4);
    assert_int_equal(s.masked_out, 0);
    assert_int_equal(s.nan_a + s.inf_a + s.nan_b + s.inf_b, 0);
    assert_near(s.max_abs, 1.0, 1e-12);
    assert_near(s.mean_abs, 1.5 / 12.0, 1e-12);
    assert_near(s.rmse, sqrt(1.25 / 12.0), 1e-12);
    assert_near(s.nrmse, sqrt(1.25 / 12.25), 1e-12);
    assert_near(s.mean_rel, (1.0 / 3.0 + 1.0) / 4.0, 1e-7);
    assert_near(s.p99_rel, 1.0, 1e-12);
    assert_near(s.share_over_1, 0.5, 0.0);
    assert_near(s.share_over_8, 0.5, 0.0);
    double d1 = tm1(1.5) - tm1(1.0), d2 = tm1(1.0);
    double psnr = 10.0 * log10(12.0 / (d1 * d1 + d2 * d2));
    assert_near(s.psnr, psnr, 1e-4);
    /* worst first; the two zero-error pixels keep scan order */
    assert_int_equal(s.worst_count, 4);
    int expect_xy[4][2] = {{0, 1}, {1, 0}, {0, 0}, {1, 1}};
    double expect_err[4] = {1.0, 0.5, 0.0, 0.0};
    for (int i = 0; i < 4; i++) {
        assert_int_equal(s.worst[i].x, expect_xy[i][0]);
        assert_int_equal(s.worst[i].y, expect_xy[i][1]);
        assert_near(s.worst[i].error, expect_err[i], 1e-12);
    }
    assert_near(s.worst[0].a[2], 1.0, 0.0);
    assert_near(s.worst[0].b[2], 0.0, 0.0);
    printf("hand-computed 2x2: max %.6g mean %.6g rmse %.6g mean_rel %.6g psnr %.4f dB\n", s.max_abs, s.mean_abs,
           s.rmse, s.mean_rel, s.psnr);

    assert_true(sl_compare_within(&s, SL_METRIC_MAX, 1.0));
    assert_false(sl_compare_within(&s, SL_METRIC_MAX, 0.999));
    assert_true(sl_compare_within(&s, SL_METRIC_RMSE, 0.33));
    assert_false(sl_compare_within(&s, SL_METRIC_RMSE, 0.32));
    assert_false(sl_compare_within(&s, SL_METRIC_P99REL, 0.5));
    sl_image_free(&a);
    sl_image_free(&b);
}

/* Masking out the pixel with the blue difference leaves 3 pixels and 9 values. */
static void test_mask(void **state)
{
    (void)state;
    sl_image a, b, m;
    make_image(&a, 2, 2, 3, 1.0f);
    make_image(&b, 2, 2, 3, 1.0f);
    make_image(&m, 2, 2, 1, 1.0f);
    sl_image_pixel(&b, 1, 0)[0] = 1.5f;
    sl_image_pixel(&b, 0, 1)[2] = 0.0f;
    sl_image_pixel(&m, 0, 1)[0] = 0.0f;
    sl_compare_desc desc = {.mask = &m};
    sl_compare_stats s;
    sl_error err = {0};
    assert_true(sl_compare_images(&a, &b, &desc, &s, &err));
    assert_int_equal(s.pixels, 3);
    assert_int_equal(s.masked_out, 1);
    assert_near(s.max_abs, 0.5, 1e-12);
    assert_near(s.mean_abs, 0.5 / 9.0, 1e-12);
    assert_near(s.rmse, sqrt(0.25 / 9.0), 1e-12);
    assert_near(s.mean_rel, 1.0 / 9.0, 1e-7);
    assert_near(s.share_over_8, 1.0 / 3.0, 1e-12);

    /* a mask of the wrong size is an error, not a crash */
    sl_image small;
    make_image(&small, 1, 2, 1, 1.0f);
    desc.mask = &small;
    assert_false(sl_compare_images(&a, &b, &desc, &s, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    sl_image_free(&small);
    sl_image_free(&a);
    sl_image_free(&b);
    sl_image_free(&m);
}

static void test_nonfinite(void **state)
{
    (void)state;
    sl_image a, b;
    make_image(&a, 3, 1, 3, 0.25f);
    make_image(&b, 3, 1, 3, 0.25f);
    sl_image_pixel(&a, 0, 0)[1] = NAN;
    sl_image_pixel(&b, 2, 0)[0] = INFINITY;
    sl_compare_stats s;
    sl_error err = {0};
    assert_true(sl_compare_images(&a, &b, NULL, &s, &err));
    assert_int_equal(s.nan_a, 1);
    assert_int_equal(s.inf_a, 0);
    assert_int_equal(s.nan_b, 0);
    assert_int_equal(s.inf_b, 1);
    assert_int_equal(s.pixels, 1);
    assert_near(s.max_abs, 0.0, 0.0);
    assert_true(isinf(s.psnr));
    /* identical where finite, yet a NaN fails any tolerance */
    assert_false(sl_compare_within(&s, SL_METRIC_MAX, 1e30));
    sl_image_free(&a);
    sl_image_free(&b);
}

static void test_identical_and_errors(void **state)
{
    (void)state;
    sl_image a, b, c;
    make_image(&a, 4, 3, 1, 2.0f);
    make_image(&b, 4, 3, 1, 2.0f);
    make_image(&c, 3, 4, 1, 2.0f);
    sl_compare_stats s;
    sl_error err = {0};
    assert_true(sl_compare_images(&a, &b, NULL, &s, &err));
    assert_true(isinf(s.psnr));
    assert_true(sl_compare_within(&s, SL_METRIC_RMSE, 0.0));
    assert_true(sl_compare_within(&s, SL_METRIC_P99REL, 0.0));
    assert_false(sl_compare_images(&a, &c, NULL, &s, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    sl_image_free(&c);
    make_image(&c, 4, 3, 3, 2.0f);
    assert_false(sl_compare_images(&a, &c, NULL, &s, &err));
    sl_image_free(&a);
    sl_image_free(&b);
    sl_image_free(&c);
}

/* 200 pixels with relative errors r_k = 0.001 k / (1 + 0.001 k): the nearest-rank 99th percentile is
 * rank 198, i.e. k = 197. Values below the floor use the floor: 1e-5 against 2e-5 is 1e-5 / 1e-3. */
static void test_percentile_and_floor(void **state)
{
    (void)state;
    sl_image a, b;
    make_image(&a, 200, 1, 1, 1.0f);
    make_image(&b, 200, 1, 1, 1.0f);
    for (int k = 0; k < 200; k++)
        sl_image_pixel(&b, k, 0)[0] = 1.0f + 0.001f * (float)k;
    sl_compare_stats s;
    sl_error err = {0};
    assert_true(sl_compare_images(&a, &b, NULL, &s, &err));
    double expect = (double)(0.001f * 197.0f) / (double)(1.0f + 0.001f * 197.0f);
    assert_near(s.p99_rel, expect, 1e-6);
    printf("p99 of 200 ramps: %.6g (expected %.6g)\n", s.p99_rel, expect);
    sl_image_free(&a);
    sl_image_free(&b);

    make_image(&a, 1, 1, 1, 1e-5f);
    make_image(&b, 1, 1, 1, 2e-5f);
    assert_true(sl_compare_images(&a, &b, NULL, &s, &err));
    assert_near(s.mean_rel, 0.01, 1e-6);
    sl_compare_desc desc = {.rel_floor = 1e-6f};
    assert_true(sl_compare_images(&a, &b, &desc, &s, &err));
    assert_near(s.mean_rel, 0.5, 1e-6);
    sl_image_free(&a);
    sl_image_free(&b);
}

/* Pixel 0 equal (black), pixel 1 from 0 to a huge value (255 levels: white), pixel 2 masked
 * (grey), pixel 3 NaN (magenta), pixel 4 one 8-bit level apart (log2(2)/8 = 1/8 of the ramp:
 * 5/8 of the way from black to blue). */
static void test_diff_colours(void **state)
{
    (void)state;
    sl_image a, b, m, d;
    make_image(&a, 5, 1, 1, 0.0f);
    make_image(&b, 5, 1, 1, 0.0f);
    make_image(&m, 5, 1, 1, 1.0f);
    sl_image_pixel(&b, 1, 0)[0] = 1e30f;
    sl_image_pixel(&m, 2, 0)[0] = 0.0f;
    sl_image_pixel(&a, 3, 0)[0] = NAN;
    /* e = 1, c = 2.2: T(x) = x / (x + 1); T = 1/255 at x = 1/254 */
    sl_image_pixel(&b, 4, 0)[0] = 1.0f / 254.0f;
    sl_compare_desc desc = {.mask = &m, .contrast = 2.2f};
    sl_error err = {0};
    assert_true(sl_compare_diff_image(&a, &b, &desc, &d, &err));
    assert_int_equal(d.channels, 3);
    const float expect[5][3] = {{0, 0, 0}, {1, 1, 1}, {0.15f, 0.15f, 0.15f}, {1, 0, 1}, {0, 0, 0.625f}};
    for (int x = 0; x < 5; x++)
        for (int c = 0; c < 3; c++)
            assert_near(sl_image_pixel(&d, x, 0)[c], expect[x][c], 1e-4);
    sl_image_free(&a);
    sl_image_free(&b);
    sl_image_free(&m);
    sl_image_free(&d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tonemap_values),     cmocka_unit_test(test_hand_computed),
        cmocka_unit_test(test_mask),               cmocka_unit_test(test_nonfinite),
        cmocka_unit_test(test_identical_and_errors), cmocka_unit_test(test_percentile_and_floor),
        cmocka_unit_test(test_diff_colours),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
