/* test_ibl.c - the lat-long map, the mip chain, textureLod and the Hammersley set (src/ibl),
 * against values worked out by hand in the comments. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ibl/ibl.h"
#include "ibl/ibl_internal.h"
#include "testutil.h"

#ifdef _OPENMP
#include <omp.h>
#endif

/* ---- helpers ---- */

static sl_image make_image(int w, int h)
{
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, w, h, 3, &err));
    return img;
}

static void set_texel(sl_image *img, int x, int y, float r, float g, float b)
{
    float *p = sl_image_pixel(img, x, y);
    p[0] = r;
    p[1] = g;
    p[2] = b;
}

/* A deterministic pseudo-random value in [0, 1) (LCG), so failures reproduce. */
static float lcg(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (float)(*state >> 8) / 16777216.0f;
}

static double level_mean(const sl_env_level *lv, int ch)
{
    double s = 0;
    for (int k = 0; k < lv->width * lv->height; k++) {
        vec3 t = lv->texels[k];
        s += ch == 0 ? (double)t.x : ch == 1 ? (double)t.y : (double)t.z;
    }
    return s / (lv->width * lv->height);
}

/* ---- lat-long ---- */

static void test_latlong_exact_values(void **state)
{
    (void)state;
    vec2 uv = sl_dir_to_uv(vec3(0, 0, 1)); /* north pole: acos(1) = 0 */
    assert_true(uv.y == 0.0f);
    uv = sl_dir_to_uv(vec3(0, 0, -1));
    assert_true(uv.y == 1.0f);
    uv = sl_dir_to_uv(vec3(1, 0, 0)); /* atan2(0, 1) = 0 -> u = 1/2; acos(0) / pi = 1/2 */
    assert_true(uv.x == 0.5f);
    assert_true(uv.y == 0.5f);
    uv = sl_dir_to_uv(vec3(0, 1, 0)); /* atan2 = pi/2 -> u = 1/4 */
    assert_near(uv.x, 0.25, 1e-7);
    uv = sl_dir_to_uv(vec3(0, -1, 0)); /* atan2 = -pi/2 -> u = 3/4 */
    assert_near(uv.x, 0.75, 1e-7);
    /* The seam: atan2(+0, -1) = pi gives u = 0; atan2(-0, -1) = -pi would give 1, folded to 0. */
    uv = sl_dir_to_uv(vec3(-1, 0.0f, 0));
    assert_true(uv.x == 0.0f);
    uv = sl_dir_to_uv(vec3(-1, -0.0f, 0));
    assert_true(uv.x == 0.0f);
    /* Just either side of the seam: u near 0 for y > 0, near 1 for y < 0. */
    uv = sl_dir_to_uv(vec3(-1, 1e-4f, 0));
    assert_true(uv.x >= 0.0f && uv.x < 1e-4f);
    uv = sl_dir_to_uv(vec3(-1, -1e-4f, 0));
    assert_true(uv.x < 1.0f && uv.x > 1.0f - 1e-4f);
    /* z a little over 1 (a rounded normalize) must not NaN. */
    uv = sl_dir_to_uv(vec3(0, 0, 1.0000002f));
    assert_true(uv.y == 0.0f);
    uv = sl_dir_to_uv(vec3(0, 0, -1.0000002f));
    assert_true(uv.y == 1.0f);
    /* NaN in, finite out. */
    uv = sl_dir_to_uv(vec3(NAN, NAN, NAN));
    assert_true(isfinite(uv.x) && isfinite(uv.y) && uv.x >= 0.0f && uv.x < 1.0f);
    /* eq. (4): (1/2, 1/2) is +x, (1/4, 1/2) is +y, v = 0 is +z. */
    vec3 d = sl_uv_to_dir(vec2(0.5f, 0.5f));
    assert_near(d.x, 1, 1e-7);
    assert_near(d.y, 0, 1e-7);
    assert_near(d.z, 0, 1e-7);
    d = sl_uv_to_dir(vec2(0.25f, 0.5f));
    assert_near(d.y, 1, 1e-7);
    d = sl_uv_to_dir(vec2(0.3f, 0.0f));
    assert_near(d.z, 1, 0);
}

static void test_latlong_round_trip(void **state)
{
    (void)state;
    /* uv -> dir -> uv over a grid that avoids the poles (where u is undefined); u compared
     * on the circle. float32 trig: a few ulps of 2 pi. */
    double worst_uv = 0, worst_dir = 0;
    for (int j = 1; j < 64; j++) {
        for (int i = 0; i < 128; i++) {
            vec2 uv = vec2((i + 0.25) / 128.0, j / 64.0);
            vec2 back = sl_dir_to_uv(sl_uv_to_dir(uv));
            double du = fabs((double)back.x - (double)uv.x);
            du = du > 0.5 ? 1.0 - du : du;
            double dv = fabs((double)back.y - (double)uv.y);
            worst_uv = fmax(worst_uv, fmax(du * sin(3.14159265358979323846 * uv.y), dv));
            assert_true(back.x >= 0.0f && back.x < 1.0f);
        }
    }
    /* dir -> uv -> dir over unit vectors from a spiral, including near the poles. */
    for (int k = 0; k < 2000; k++) {
        double z = 1.0 - (k + 0.5) / 1000.0;
        double phi = k * 2.399963229728653;
        double s = sqrt(1 - z * z);
        vec3 d = vec3(s * cos(phi), s * sin(phi), z);
        vec3 back = sl_uv_to_dir(sl_dir_to_uv(d));
        double err = sqrt(pow(back.x - d.x, 2) + pow(back.y - d.y, 2) + pow(back.z - d.z, 2));
        worst_dir = fmax(worst_dir, err);
    }
    print_message("lat-long round trip: worst uv error %.3g, worst direction error %.3g\n", worst_uv, worst_dir);
    assert_true(worst_uv < 1e-6);
    assert_true(worst_dir < 2e-6);
}

/* ---- mip chain ---- */

static void test_env_sizes(void **state)
{
    (void)state;
    struct { int w, h, levels; } cases[] = {{1024, 512, 11}, {5, 3, 3}, {1, 1, 1}, {7, 1, 3}, {1, 9, 4}, {6, 6, 3}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        sl_image img = make_image(cases[c].w, cases[c].h);
        sl_env env;
        sl_error err = {0};
        assert_true(sl_env_build(&env, &img, 0, &err));
        assert_int_equal(env.level_count, cases[c].levels);
        int w = cases[c].w, h = cases[c].h;
        for (int l = 0; l < env.level_count; l++) {
            assert_int_equal(env.levels[l].width, w);
            assert_int_equal(env.levels[l].height, h);
            w = w / 2 > 1 ? w / 2 : 1;
            h = h / 2 > 1 ? h / 2 : 1;
        }
        assert_int_equal(env.levels[env.level_count - 1].width, 1);
        assert_int_equal(env.levels[env.level_count - 1].height, 1);
        sl_env_free(&env);
        sl_image_free(&img);
    }
}

static void test_env_box_and_odd_weights(void **state)
{
    (void)state;
    /* 4x2 -> 2x1 is the 2x2 box; 2x1 -> 1x1 the average of the two. */
    sl_image img = make_image(4, 2);
    const float v[2][4] = {{1, 2, 4, 8}, {16, 32, 64, 128}};
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 4; x++)
            set_texel(&img, x, y, v[y][x], (float)x, (float)y);
    sl_env env;
    sl_error err = {0};
    assert_true(sl_env_build(&env, &img, 0, &err));
    assert_near(env.levels[1].texels[0].x, (1 + 2 + 16 + 32) / 4.0, 0);
    assert_near(env.levels[1].texels[1].x, (4 + 8 + 64 + 128) / 4.0, 0);
    assert_near(env.levels[1].texels[1].y, 2.5, 0);
    assert_near(env.levels[2].texels[0].x, 255 / 8.0, 0);
    sl_env_free(&env);
    sl_image_free(&img);

    /* 5x3 -> 2x1: rows 3 -> 1 weigh (1, 1, 1) / 3; columns 5 -> 2 weigh (1, 1, 1/2) / 2.5 and
     * (1/2, 1, 1) / 2.5 (each new texel covers 2.5 old ones). */
    img = make_image(5, 3);
    float t[3][5];
    unsigned seed = 7;
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 5; x++) {
            t[y][x] = 10.0f * lcg(&seed);
            set_texel(&img, x, y, t[y][x], 1.0f, 0.0f);
        }
    assert_true(sl_env_build(&env, &img, 0, &err));
    double col[5];
    for (int x = 0; x < 5; x++)
        col[x] = ((double)t[0][x] + t[1][x] + t[2][x]) / 3.0;
    double left = (col[0] + col[1] + 0.5 * col[2]) / 2.5, right = (0.5 * col[2] + col[3] + col[4]) / 2.5;
    assert_near(env.levels[1].texels[0].x, left, 1e-6 * left);
    assert_near(env.levels[1].texels[1].x, right, 1e-6 * right);
    assert_near(env.levels[1].texels[0].y, 1.0, 1e-7); /* a constant stays constant */
    double mean = 0;
    for (int x = 0; x < 5; x++)
        mean += col[x] / 5.0;
    assert_near(env.levels[2].texels[0].x, mean, 1e-6 * mean);
    sl_env_free(&env);
    sl_image_free(&img);
}

static void test_env_preserves_mean(void **state)
{
    (void)state;
    /* Exact area averaging hands each texel total weight 1, so every level keeps the image
     * mean (up to float rounding of the stored texels), odd sizes included. */
    struct { int w, h; } sizes[] = {{64, 32}, {37, 19}, {5, 3}, {7, 1}, {1, 9}, {100, 3}};
    unsigned seed = 12345;
    for (size_t c = 0; c < sizeof sizes / sizeof sizes[0]; c++) {
        sl_image img = make_image(sizes[c].w, sizes[c].h);
        for (int y = 0; y < img.height; y++)
            for (int x = 0; x < img.width; x++)
                set_texel(&img, x, y, 100.0f * lcg(&seed), lcg(&seed), 0.01f * lcg(&seed));
        sl_env env;
        sl_error err = {0};
        assert_true(sl_env_build(&env, &img, 0, &err));
        for (int ch = 0; ch < 3; ch++) {
            double m0 = level_mean(&env.levels[0], ch);
            for (int l = 1; l < env.level_count; l++) {
                double m = level_mean(&env.levels[l], ch);
                if (fabs(m - m0) > 2e-6 * m0)
                    print_error("%dx%d level %d channel %d: mean %.9g, image mean %.9g\n", img.width, img.height,
                                l, ch, m, m0);
                assert_near(m, m0, 2e-6 * m0);
            }
        }
        sl_env_free(&env);
        sl_image_free(&img);
    }
}

static void test_env_rejects(void **state)
{
    (void)state;
    sl_env env;
    sl_error err = {0};
    sl_image img;
    assert_true(sl_image_alloc(&img, 4, 2, 1, &err));
    assert_false(sl_env_build(&env, &img, 0, &err));
    assert_int_equal(err.code, SL_ERR_UNSUPPORTED);
    assert_int_equal(env.level_count, 0);
    sl_image_free(&img);

    const float bad[] = {NAN, INFINITY, -1.0f};
    for (int b = 0; b < 3; b++) {
        img = make_image(4, 2);
        sl_image_pixel(&img, 3, 1)[2] = bad[b];
        err = (sl_error){0};
        assert_false(sl_env_build(&env, &img, 0, &err));
        assert_int_equal(err.code, SL_ERR_RANGE);
        assert_non_null(strstr(err.msg, "(3, 1) channel 2"));
        assert_int_equal(env.level_count, 0);
        sl_image_free(&img);
    }
    sl_env_free(&env); /* freeing an empty env is fine */
}

/* ---- textureLod ---- */

/* The 4x2 texture of test_env_box_and_odd_weights: red channel
 *   row 0: 1  2  4   8
 *   row 1: 16 32 64 128
 * level 1 (2x1): 12.75, 51; level 2 (1x1): 31.875. */
static sl_env make_4x2(void)
{
    sl_image img = make_image(4, 2);
    const float v[2][4] = {{1, 2, 4, 8}, {16, 32, 64, 128}};
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 4; x++)
            set_texel(&img, x, y, v[y][x], (float)x, (float)y);
    sl_env env;
    sl_error err = {0};
    assert_true(sl_env_build(&env, &img, 0, &err));
    sl_image_free(&img);
    return env;
}

static double red(const sl_env *env, double u, double v, double lod)
{
    return textureLod(env, vec2(u, v), (float)lod).x;
}

static void test_texture_lod_level0(void **state)
{
    (void)state;
    sl_env env = make_4x2();
    const float v[2][4] = {{1, 2, 4, 8}, {16, 32, 64, 128}};
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 4; x++) { /* texel centres (i + 0.5) / size read the texel alone */
            vec3 t = textureLod(&env, vec2((x + 0.5) / 4, (y + 0.5) / 2), 0.0f);
            assert_near(t.x, v[y][x], 0);
            assert_near(t.y, x, 0);
            assert_near(t.z, y, 0);
        }
    assert_near(red(&env, 0.25, 0.25, 0), 1.5, 1e-6);          /* between columns 0 and 1 */
    assert_near(red(&env, 0.125, 0.5, 0), 8.5, 1e-6);          /* between rows 0 and 1 */
    assert_near(red(&env, 0.25, 0.5, 0), 12.75, 1e-5);         /* between four texels */
    assert_near(red(&env, 0.3125, 0.25, 0), 1.75, 1e-6);       /* a quarter of the way from 1 to 2 */
    /* Across the seam: u = 0.999 -> x = 3.496, columns 3 and 0 with weight 0.496 on column 0. */
    assert_near(red(&env, 0.999, 0.25, 0), 8 + (1 - 8) * 0.496, 1e-5);
    /* u = 0.001 -> x = -0.496: columns 3 (weight 0.496) and 0 (0.504). */
    assert_near(red(&env, 0.001, 0.25, 0), 8 + (1 - 8) * 0.504, 1e-5);
    assert_near(red(&env, 0.0, 0.25, 0), 4.5, 1e-6);          /* exactly on the seam */
    assert_near(red(&env, 1.0, 0.25, 0), 4.5, 1e-6);
    /* REPEAT in u. */
    assert_near(red(&env, 1.25, 0.25, 0), 1.5, 1e-6);
    assert_near(red(&env, -0.75, 0.25, 0), 1.5, 1e-6);
    assert_near(red(&env, -3.999, 0.25, 0), red(&env, 0.001, 0.25, 0), 1e-4);
    /* CLAMP_TO_EDGE in v: above the first row centre only row 0 is read, below the last row 1. */
    assert_near(red(&env, 0.125, 0.0, 0), 1, 0);
    assert_near(red(&env, 0.125, 0.1, 0), 1, 0);
    assert_near(red(&env, 0.125, -5.0, 0), 1, 0);
    assert_near(red(&env, 0.125, 1.0, 0), 16, 0);
    assert_near(red(&env, 0.625, 7.0, 0), 64, 0);
    sl_env_free(&env);
}

static void test_texture_lod_levels(void **state)
{
    (void)state;
    sl_env env = make_4x2();
    /* At uv (0.125, 0.25): level 0 reads 1; level 1 (2x1) has x = 0.125 * 2 - 0.5 = -0.25,
     * i.e. columns 1 (weight 0.25) and 0 (0.75): 0.25 * 51 + 0.75 * 12.75 = 22.3125;
     * level 2 is 31.875. */
    const double l0 = 1, l1 = 22.3125, l2 = 31.875;
    assert_near(red(&env, 0.125, 0.25, 1), l1, 1e-5);
    assert_near(red(&env, 0.125, 0.25, 2), l2, 1e-5);
    assert_near(red(&env, 0.125, 0.25, 0.25), 0.75 * l0 + 0.25 * l1, 1e-5);
    assert_near(red(&env, 0.125, 0.25, 1.5), 0.5 * l1 + 0.5 * l2, 1e-5);
    /* lod clamps to [0, 2]. */
    assert_near(red(&env, 0.125, 0.25, -3), l0, 0);
    assert_near(red(&env, 0.125, 0.25, 2.5), l2, 1e-5);
    assert_near(red(&env, 0.125, 0.25, 99), l2, 1e-5);
    assert_near(textureLod(&env, vec2(0.125f, 0.25f), INFINITY).x, l2, 1e-5);
    assert_near(textureLod(&env, vec2(0.125f, 0.25f), -INFINITY).x, l0, 0);
    sl_env_free(&env);
}

static void test_texture_lod_non_finite(void **state)
{
    (void)state;
    sl_env env = make_4x2();
    /* NaN lod reads level 0; non-finite u or v reads as 0. */
    assert_near(textureLod(&env, vec2(0.125f, 0.25f), NAN).x, 1, 0);
    double at_origin = red(&env, 0, 0, 0); /* seam, row 0: (8 + 1) / 2 */
    assert_near(at_origin, 4.5, 1e-6);
    const float bad[] = {NAN, INFINITY, -INFINITY};
    for (int b = 0; b < 3; b++) {
        assert_near(textureLod(&env, vec2(bad[b], 0.0f), 0.0f).x, at_origin, 0);
        assert_near(textureLod(&env, vec2(0.0f, bad[b]), 0.0f).x, at_origin, 0);
        assert_near(textureLod(&env, vec2(bad[b], bad[b]), bad[b]).x,
                    textureLod(&env, vec2(0.0f, 0.0f), b == 1 ? 2.0f : 0.0f).x, 0);
    }
    /* An empty environment reads black instead of crashing. */
    sl_env empty = {0};
    vec3 e = textureLod(&empty, vec2(0.5f, 0.5f), 0.0f);
    assert_true(e.x == 0.0f && e.y == 0.0f && e.z == 0.0f);
    sl_env_free(&env);
}

static void test_texture_lod_odd_sizes_in_bounds(void **state)
{
    (void)state;
    /* Under ASan this catches any out-of-bounds read; the value must stay within the texel
     * range (bilinear and lod blending are convex combinations). */
    int sizes[][2] = {{5, 3}, {1, 1}, {3, 1}, {1, 5}, {7, 6}};
    unsigned seed = 99;
    for (size_t c = 0; c < sizeof sizes / sizeof sizes[0]; c++) {
        sl_image img = make_image(sizes[c][0], sizes[c][1]);
        for (int y = 0; y < img.height; y++)
            for (int x = 0; x < img.width; x++)
                set_texel(&img, x, y, 1.0f + lcg(&seed), 2.0f, 3.0f);
        sl_env env;
        sl_error err = {0};
        assert_true(sl_env_build(&env, &img, 0, &err));
        const float extreme[] = {0.0f, 1.0f, -1e-30f, 1.0f - 1e-7f, 1e30f, -1e30f, 0.5f};
        for (int i = 0; i < 2000; i++) {
            float u = i < 49 ? extreme[i % 7] : 4.0f * lcg(&seed) - 2.0f;
            float v = i < 49 ? extreme[i / 7] : 4.0f * lcg(&seed) - 2.0f;
            float lod = 6.0f * lcg(&seed) - 2.0f;
            vec3 t = textureLod(&env, vec2(u, v), lod);
            assert_true(t.x >= 1.0f && t.x <= 2.0f);
            assert_near(t.y, 2, 1e-6);
        }
        if (sizes[c][0] == 1 && sizes[c][1] == 1) { /* 1x1: any lookup is the texel */
            assert_near(textureLod(&env, vec2(0.3f, 0.9f), 0.7f).x, img.data[0], 0);
        }
        sl_env_free(&env);
        sl_image_free(&img);
    }
}

/* env.c's even-size fast path against its general filter (sl_ibl_env_build_path with general_only),
 * every level bit for bit: the fast path must perform the same double operations in the same
 * order. Random data spanning 40 binary orders of magnitude (so the double sums do round before
 * the float conversion), with exact zeros and -0.0 (the general accumulator starts at +0.0,
 * which turns -0.0 into +0.0), on even, odd and mixed sizes: 64x32 and 1024x512 take the fast
 * path on every level but 2x1 -> 1x1, 12x5 and 6x4 (6x4 -> 3x2 -> 1x1) mix both, 5x3 and 37x19
 * take only the general one. The fast build is also made with 1 and with 3 threads: the chain
 * must not depend on the thread count (2048x1024 is the smallest size whose first level is
 * split over threads, env.c's EVEN_PARALLEL_MIN). */
static void test_env_fast_path_bit_identical(void **state)
{
    (void)state;
    const int sizes[][2] = {{1, 1}, {2, 1}, {5, 3}, {37, 19}, {64, 32}, {12, 5}, {6, 4}, {1024, 512}, {2048, 1024}};
    unsigned seed = 2024;
    for (size_t c = 0; c < sizeof sizes / sizeof sizes[0]; c++) {
        sl_image img = make_image(sizes[c][0], sizes[c][1]);
        size_t n = (size_t)img.width * (size_t)img.height * 3;
        for (size_t k = 0; k < n; k++) {
            float u = lcg(&seed);
            img.data[k] = u < 0.05f ? 0.0f : u < 0.1f ? -0.0f : ldexpf(lcg(&seed), (int)(40.0f * lcg(&seed)) - 20);
        }
        for (int y = 0; y < 2 && y < img.height; y++) /* a 2x2 footprint of -0.0 (level 1 is +0.0) */
            for (int x = 0; x < 2 && x < img.width; x++)
                set_texel(&img, x, y, -0.0f, -0.0f, -0.0f);
        sl_env fast, general;
        sl_error err = {0};
        assert_true(sl_ibl_env_build_path(&general, &img, true, 0, &err));
        int threads[] = {1, 3};
        for (int t = 0; t < 2; t++) {
#ifdef _OPENMP
            int saved = omp_get_max_threads();
            omp_set_num_threads(threads[t]);
#endif
            assert_true(sl_ibl_env_build_path(&fast, &img, false, 0, &err));
#ifdef _OPENMP
            omp_set_num_threads(saved);
#endif
            assert_int_equal(fast.level_count, general.level_count);
            for (int l = 0; l < fast.level_count; l++) {
                const sl_env_level *a = &fast.levels[l], *b = &general.levels[l];
                assert_int_equal(a->width, b->width);
                assert_int_equal(a->height, b->height);
                assert_same_texels(a->texels, b->texels, (size_t)a->width * (size_t)a->height, sizeof(vec3),
                                   a->width, "%dx%d level %d (%dx%d), %d threads", img.width, img.height, l,
                                   a->width, a->height, threads[t]);
            }
            sl_env_free(&fast);
        }
        /* sl_env_build is the fast build */
        assert_true(sl_env_build(&fast, &img, 0, &err));
        const sl_env_level *top = &fast.levels[fast.level_count - 1];
        assert_same_texels(top->texels, general.levels[general.level_count - 1].texels, 1, sizeof(vec3), 0,
                           "%dx%d, 1x1 level of sl_env_build", img.width, img.height);
        sl_env_free(&fast);
        sl_env_free(&general);
        sl_image_free(&img);
    }
}

/* ---- Hammersley ---- */

static void test_hammersley(void **state)
{
    (void)state;
    sl_hammersley set;
    sl_error err = {0};
    assert_true(sl_hammersley_build(&set, 4, &err));
    assert_int_equal(set.n, 4);
    /* k = 0, 1, 2, 3 -> radical inverses 0, 0.5, 0.25, 0.75; v = (k + 0.5) / 4. */
    const float want[4][2] = {{0, 0.125f}, {0.5f, 0.375f}, {0.25f, 0.625f}, {0.75f, 0.875f}};
    for (int k = 0; k < 4; k++) {
        assert_true(set.points[k].x == want[k][0]);
        assert_true(set.points[k].y == want[k][1]);
    }
    assert_true(sl_hammersley_build(&set, 1, &err));
    assert_true(set.points[0].x == 0.0f && set.points[0].y == 0.5f);
    /* k = 6 = 110b -> 0.011b = 0.375; k = 11 = 1011b -> 0.1101b = 0.8125. */
    assert_true(sl_hammersley_build(&set, 40, &err));
    assert_true(set.points[6].x == 0.375f);
    assert_true(set.points[11].x == 0.8125f);
    /* For n = 1024 the u's are a permutation of k / 1024. */
    assert_true(sl_hammersley_build(&set, SL_HAMMERSLEY_MAX, &err));
    static char seen[SL_HAMMERSLEY_MAX];
    memset(seen, 0, sizeof seen);
    for (int k = 0; k < SL_HAMMERSLEY_MAX; k++) {
        float scaled = set.points[k].x * SL_HAMMERSLEY_MAX;
        int i = (int)scaled;
        assert_true((float)i == scaled && i >= 0 && i < SL_HAMMERSLEY_MAX);
        assert_false(seen[i]);
        seen[i] = 1;
    }
    err = (sl_error){0};
    assert_false(sl_hammersley_build(&set, 0, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_false(sl_hammersley_build(&set, SL_HAMMERSLEY_MAX + 1, &err));
    assert_int_equal(set.n, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_latlong_exact_values),
        cmocka_unit_test(test_latlong_round_trip),
        cmocka_unit_test(test_env_sizes),
        cmocka_unit_test(test_env_box_and_odd_weights),
        cmocka_unit_test(test_env_preserves_mean),
        cmocka_unit_test(test_env_rejects),
        cmocka_unit_test(test_env_fast_path_bit_identical),
        cmocka_unit_test(test_texture_lod_level0),
        cmocka_unit_test(test_texture_lod_levels),
        cmocka_unit_test(test_texture_lod_non_finite),
        cmocka_unit_test(test_texture_lod_odd_sizes_in_bounds),
        cmocka_unit_test(test_hammersley),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
