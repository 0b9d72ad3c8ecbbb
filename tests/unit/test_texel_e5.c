/* test_texel_e5.c - the compact shared-exponent texel of the lighting fetch (src/ibl/texel_e5.h):
 * hand-encoded values, the rounding-up case, the stated error bound (max channel / 511.5) over a
 * sweep of texels spanning 2^60, a sun far above RGB9_E5's 65408 kept unclamped, and the
 * chain's layout in sl_env.e5 (rows found by shifts, every texel of every level within the bound
 * of the float chain, the wrapped copy of column 0 at each row's end). */
#include <math.h>
#include <stdlib.h>

#include "ibl/ibl.h"
#include "ibl/texel_e5.h"
#include "testutil.h"

static vec3 decode(uint32_t t, int emin)
{
    float r, g, b;
    sl_e5_decode(t, emin + 127, &r, &g, &b);
    return vec3(r, g, b);
}

/* (1, 0.5, 0.25) in a chain whose brightest is 1: frexp(1) = 0.5 2^1, so emin = 1 - 9 - 30 =
 * -38; the texel's exponent is 1 - 9 + 38 = 30, the step 2^(30 - 38) = 2^-8, the mantissas 256,
 * 128 and 64, all exact. */
static void test_hand_values(void **state)
{
    (void)state;
    assert_int_equal(sl_e5_emin(1.0f), -38);
    assert_int_equal(sl_e5_emin(0.0f), -126);
    assert_int_equal(sl_e5_emin(1e-30f), -126); /* clamped: 2^(e + emin) stays a normal float */
    uint32_t t = sl_e5_encode(1.0f, 0.5f, 0.25f, -38);
    assert_int_equal(t, (30u << 27) | (64u << 18) | (128u << 9) | 256u);
    vec3 d = decode(t, -38);
    assert_true(d.x == 1.0f && d.y == 0.5f && d.z == 0.25f);
    assert_int_equal(sl_e5_encode(0.0f, 0.0f, 0.0f, -38), 0u);
    /* 1 - 2^-11 has exponent 29 (step 2^-9) and mantissa 511.75, which rounds to 512: the
     * encoder moves to exponent 30, mantissa round(255.875) = 256, i.e. 1.0, 2^-11 away, within
     * the bound 1/511.5. */
    t = sl_e5_encode(0.99951171875f, 0.0f, 0.0f, -38);
    assert_int_equal(t, (30u << 27) | 256u);
    /* a channel far below the max keeps the max's step: 1e-3 with step 2^-8 is mantissa 0 */
    d = decode(sl_e5_encode(1.0f, 1e-3f, 0.0f, -38), -38);
    assert_true(d.y == 0.0f);
}

/* Every channel within M / 511.5 of its value (M the texel's largest channel) while M is at
 * least 2^(emin + 8) (exponent not clamped at 0), else within 2^(emin - 1); decoding never
 * exceeds the float range. Pseudo-random texels over 2^-40 .. 2^20 of a chain whose brightest
 * is a 2^20 sun. */
static void test_error_bound(void **state)
{
    (void)state;
    const float sun = 1048576.0f;
    const int emin = sl_e5_emin(sun);
    uint32_t seed = 12345u;
    double worst = 0.0;
    for (int i = 0; i < 2000000; i++) {
        float c[3];
        for (int k = 0; k < 3; k++) {
            seed = seed * 1664525u + 1013904223u;
            double e = -40.0 + 60.0 * (double)(seed >> 8) / 16777216.0;
            seed = seed * 1664525u + 1013904223u;
            c[k] = (float)(ldexp(1.0, (int)floor(e)) * (1.0 + (double)(seed >> 8) / 16777216.0));
        }
        if (i % 7 == 0)
            c[i % 3] = 0.0f;
        if (i == 0)
            c[0] = c[1] = c[2] = sun;
        vec3 d = decode(sl_e5_encode(c[0], c[1], c[2], emin), emin);
        double m = fmax(fmax((double)c[0], (double)c[1]), (double)c[2]);
        double bound = m >= ldexp(1.0, emin + 8) ? m / 511.5 : ldexp(1.0, emin - 1);
        const double got[3] = {(double)d.x, (double)d.y, (double)d.z};
        for (int k = 0; k < 3; k++) {
            double err = fabs(got[k] - (double)c[k]);
            if (err > bound)
                fail_msg("texel %d channel %d: %.9g decoded as %.9g (bound %.3g)", i, k, (double)c[k], got[k], bound);
            if (m >= ldexp(1.0, emin + 8))
                worst = fmax(worst, err / m);
        }
    }
    print_message("worst error / max channel: %.4g (bound %.4g)\n", worst, 1.0 / 511.5);
    assert_true(worst > 0.9 / 512.0); /* the sweep reaches the bound's scale */
    /* the sun itself: exact (a power of two), not clamped to RGB9_E5's 65408 */
    vec3 s = decode(sl_e5_encode(sun, sun, sun, emin), emin);
    assert_true(s.x == sun && s.y == sun && s.z == sun);
}

/* The largest finite float fits too (emin 89: 2^(31 + 89) times a 9-bit mantissa). */
static void test_extreme_max(void **state)
{
    (void)state;
    const float big = 3.0e38f;
    const int emin = sl_e5_emin(big);
    vec3 d = decode(sl_e5_encode(big, 1.0f, 0.0f, emin), emin);
    assert_true(isfinite(d.x));
    assert_true(fabs((double)d.x - (double)big) <= (double)big / 511.5);
}

/* The rows of sl_env.e5: level l's rows [sl_e5_row(H, l), + h_l) come in order without overlap
 * for sizes with odd halvings and long thin maps; and each texel of a built chain decodes within
 * the bound of the float level, column w being column 0 again. */
static void test_chain_layout(void **state)
{
    (void)state;
    const int sizes[][2] = {{96, 40}, {5, 3}, {1, 9}, {64, 1}, {33, 17}, {128, 64}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        const int W = sizes[s][0], H = sizes[s][1];
        sl_image img;
        sl_error err;
        assert_true(sl_image_alloc(&img, W, H, 3, &err));
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                float *p = sl_image_pixel(&img, x, y);
                p[0] = (float)(1 + x * 7 % 13);
                p[1] = 0.01f * (float)(y + 1);
                p[2] = x == 3 && y == 1 ? 5000.0f : 0.5f; /* one bright texel */
            }
        sl_env env;
        assert_true(sl_env_build(&env, &img, 0, &err));
        assert_non_null(env.e5);
        int next = 0;
        for (int l = 0; l < env.level_count; l++) {
            const sl_env_level *lv = &env.levels[l];
            assert_int_equal(lv->width, sl_e5_size(W, l));
            assert_int_equal(lv->height, sl_e5_size(H, l));
            const int row = sl_e5_row(H, l);
            assert_true(row >= next); /* after the previous level's rows */
            next = row + lv->height;
            assert_true(next <= sl_e5_row(H, l + 1));
            for (int y = 0; y < lv->height; y++)
                for (int x = 0; x <= lv->width; x++) {
                    vec3 t = lv->texels[y * lv->width + (x < lv->width ? x : 0)];
                    vec3 d = decode(env.e5[(row + y) * (W + 1) + x], env.e5_emin);
                    double m = fmax(fmax((double)t.x, (double)t.y), (double)t.z);
                    assert_true(fabs((double)d.x - (double)t.x) <= m / 511.5);
                    assert_true(fabs((double)d.y - (double)t.y) <= m / 511.5);
                    assert_true(fabs((double)d.z - (double)t.z) <= m / 511.5);
                }
        }
        sl_env_free(&env);
        sl_image_free(&img);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hand_values),
        cmocka_unit_test(test_error_bound),
        cmocka_unit_test(test_extreme_max),
        cmocka_unit_test(test_chain_layout),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
