/* test_tonemap.c - the display image (src/post/tonemap.c): its fast path gives, bit for bit, the
 * 8-bit code of the exact curve (sl_unorm8 of sl_tonemap_value) over a dense sweep of radiance
 * values and special values, for the gamma and sRGB curves at extreme contrasts; the thresholds
 * are each the first float of their code (the curve's monotonicity at every code boundary, which
 * exactness rests on); the stored levels k/255 give k back; the viewer's one-pass path into 32-bit
 * pixels gives the bytes of the display image's 8-bit conversion; the rows the renderer tone maps
 * inside the lighting pass give the whole image's values. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

#include "post/tonemap.h"

static float next_down(float x)
{
    uint32_t u;
    memcpy(&u, &x, 4);
    u--;
    memcpy(&x, &u, 4);
    return x;
}

static const struct {
    float contrast;
    bool srgb;
} curves[] = {{1.0f, false}, {1.0f, true}, {1.3f, true}, {0.01f, false}, {0.01f, true}, {2.2f, false},
              {100.0f, false}, {100.0f, true}};
#define CURVES (int)(sizeof curves / sizeof curves[0])

static void test_thresholds_are_first_of_their_code(void **state)
{
    (void)state;
    for (int c = 0; c < CURVES; c++) {
        float t[257];
        sl_tonemap_thresholds(curves[c].contrast, curves[c].srgb, t);
        assert_true(t[0] == 0.0f && isinf(t[256]));
        for (int k = 1; k < 256; k++) {
            assert_true(t[k] >= t[k - 1] && t[k] <= 1.0f);
            float curve_at = curves[c].srgb ? sl_linear_to_srgb(powf(t[k], curves[c].contrast))
                                            : powf(t[k], curves[c].contrast / 2.2f);
            assert_true(sl_unorm8(curve_at) >= k);
            if (t[k] > 0.0f) { /* the float below is of a lower code */
                float below = next_down(t[k]);
                float cb = curves[c].srgb ? sl_linear_to_srgb(powf(below, curves[c].contrast))
                                          : powf(below, curves[c].contrast / 2.2f);
                assert_true(sl_unorm8(cb) < k);
            }
            if (t[k + 1] > t[k]) /* a code no float maps to shares its threshold with the next */
                assert_int_equal(sl_tonemap_code(t[k], t), k);
        }
    }
}

static void test_levels_round_trip(void **state)
{
    (void)state;
    for (int k = 0; k < 256; k++)
        assert_int_equal(sl_unorm8((float)k / 255.0f), k);
}

/* 1280x720x3 values: log-spaced radiance from 1e-12 to 1e6, plus 0, -1, NaN, +Inf, denormals */
static void test_image_matches_exact_curve(void **state)
{
    (void)state;
    sl_image in = {0}, out = {0};
    sl_error err = {0};
    const int w = 1280, h = 720;
    const size_t n = (size_t)w * h * 3;
    assert_true(sl_image_alloc(&in, w, h, 3, &err));
    for (size_t i = 0; i < n; i++)
        in.data[i] = powf(10.0f, -12.0f + 18.0f * (float)i / (float)n);
    const float specials[] = {0.0f, -1.0f, NAN, INFINITY, -INFINITY, 1e-40f, 1e-45f, 1.0f, 0.5f};
    for (size_t s = 0; s < sizeof specials / sizeof specials[0]; s++)
        in.data[s * 977] = specials[s];
    const float exposures[] = {1.0f, 0.001f, 1e6f};
    for (int c = 0; c < CURVES; c++)
        for (int e = 0; e < 3; e++) {
            sl_tonemap_options o = {.exposure = exposures[e], .contrast = curves[c].contrast,
                                    .exact_srgb = curves[c].srgb};
            assert_true(sl_tonemap_image(&in, &out, &o, 0, &err));
            long differ = 0;
            for (size_t i = 0; i < n; i++) {
                int want = sl_unorm8(sl_tonemap_value(in.data[i], o.exposure, o.contrast, o.exact_srgb));
                differ += out.data[i] != (float)want / 255.0f;
            }
            assert_int_equal(differ, 0);
        }
    /* in place: the same result */
    sl_tonemap_options o = {.exposure = 1.0f, .contrast = 1.0f};
    assert_true(sl_tonemap_image(&in, &out, &o, 0, &err));
    assert_true(sl_tonemap_image(&in, &in, &o, 0, &err));
    assert_memory_equal(in.data, out.data, n * sizeof(float));
    sl_image_free(&in);
    sl_image_free(&out);
}

/* Fills `in` with the floats whose bits are start, start + stride, ..., tone maps it and counts
 * the values whose level differs from the formula's code. */
static long differ_from(sl_image *in, sl_image *out, uint32_t start, uint32_t stride, const sl_tonemap_options *o)
{
    const size_t n = (size_t)in->width * (size_t)in->height * 3;
    for (size_t i = 0; i < n; i++) {
        uint32_t bi = start + (uint32_t)i * stride;
        float c;
        memcpy(&c, &bi, 4);
        in->data[i] = c;
    }
    sl_error err = {0};
    assert_true(sl_tonemap_image(in, out, o, 0, &err));
    long differ = 0;
    for (size_t i = 0; i < n; i++) {
        int want = sl_unorm8(sl_tonemap_value(in->data[i], o->exposure, o->contrast, o->exact_srgb));
        differ += out->data[i] != (float)want / 255.0f;
    }
    return differ;
}

/* The segment table against the formula at every code: the 3072 floats around each code's
 * threshold in C (ec = eC, so u[k] / e), where a wrong threshold, segment or rounding of ec
 * would show; for every curve, at exposures 1 (ec = C exactly) and 0.37 (ec rounds). Then a
 * stride through every binade where the default curves change code. */
static void test_table_matches_formula_at_every_code(void **state)
{
    (void)state;
    sl_image in = {0}, out = {0};
    sl_error err = {0};
    assert_true(sl_image_alloc(&in, 1024, 1, 3, &err));
    sl_tonemap_table *tab = malloc(sizeof *tab);
    assert_non_null(tab);
    const float exposures[] = {1.0f, 0.37f};
    for (int c = 0; c < CURVES; c++)
        for (int e = 0; e < 2; e++) {
            sl_tonemap_options o = {.exposure = exposures[e], .contrast = curves[c].contrast,
                                    .exact_srgb = curves[c].srgb};
            assert_true(sl_tonemap_prepare(&o, tab, &err));
            for (int k = 1; k < 256; k++) {
                if (tab->u[k] == tab->u[k - 1] || !(tab->u[k] > 0.0f) || isinf(tab->u[k]))
                    continue;
                float c0 = tab->u[k] / o.exposure;
                uint32_t b;
                memcpy(&b, &c0, 4);
                long d = differ_from(&in, &out, b - 1536, 1, &o); /* 3072 values, from 1536 below */
                if (d)
                    fail_msg("curve %d exposure %g code %d: %ld values differ", c, (double)o.exposure, k, d);
            }
        }
    sl_image_free(&in);
    sl_image_free(&out);
    /* every 97th float from 2^-24 to beyond 2^12 (the default curves' codes change within it) */
    assert_true(sl_image_alloc(&in, 1 << 12, 1 << 8, 3, &err)); /* 3 Mi values */
    for (int c = 0; c < 2; c++) {
        sl_tonemap_options o = {.exposure = 1.0f, .contrast = 1.0f, .exact_srgb = c == 1};
        const float lo = 0x1p-24f;
        uint32_t b;
        memcpy(&b, &lo, 4);
        assert_int_equal(differ_from(&in, &out, b, 97, &o), 0);
        assert_true(in.data[3 * 4096 * 256 - 1] > 4096.0f); /* the sweep reached past 2^12 */
    }
    free(tab);
    sl_image_free(&in);
    sl_image_free(&out);
}

/* sl_tonemap_apply_xrgb8888 against sl_tonemap_apply and the viewer's conversion of its levels
 * (v 255 + 0.5 rounded down, view_image.c): the same bytes, for every curve (the high contrasts
 * send segments to the exact path) at three exposures, over radiance from 1e-12 to 1e6 and the
 * special values; a pitch wider than the row leaves the padding alone. */
static void test_xrgb8888_matches_display_image(void **state)
{
    (void)state;
    const int w = 1283, h = 97, pitch = 4 * w + 12; /* a width that is no multiple of the chunk */
    sl_image in = {0}, out = {0};
    sl_error err = {0};
    assert_true(sl_image_alloc(&in, w, h, 3, &err));
    const size_t n = (size_t)w * h * 3;
    for (size_t i = 0; i < n; i++)
        in.data[i] = powf(10.0f, -12.0f + 18.0f * (float)((i * 7919) % n) / (float)n);
    const float specials[] = {0.0f, -1.0f, NAN, INFINITY, -INFINITY, 1e-40f, 1e-45f, 1.0f, 0.5f};
    for (size_t s = 0; s < sizeof specials / sizeof specials[0]; s++)
        in.data[s * 977 + s % 3] = specials[s];
    uint8_t *px = malloc((size_t)pitch * h);
    sl_tonemap_table *tab = malloc(sizeof *tab);
    assert_non_null(px);
    assert_non_null(tab);
    const float exposures[] = {1.0f, 0.001f, 1e6f};
    for (int c = 0; c < CURVES; c++)
        for (int e = 0; e < 3; e++) {
            sl_tonemap_options o = {.exposure = exposures[e], .contrast = curves[c].contrast,
                                    .exact_srgb = curves[c].srgb};
            assert_true(sl_tonemap_prepare(&o, tab, &err));
            assert_true(sl_tonemap_apply(tab, &in, &out, 0, &err));
            memset(px, 0x5a, (size_t)pitch * h);
            sl_tonemap_apply_xrgb8888(tab, &in, px, pitch, 0);
            long differ = 0;
            for (int y = 0; y < h; y++) {
                for (int x = 0; x < w; x++) {
                    const float *v = out.data + 3 * ((size_t)y * w + x);
                    uint32_t want = 0xff000000u;
                    for (int k = 0; k < 3; k++)
                        want |= (uint32_t)(v[k] * 255.0f + 0.5f) << (16 - 8 * k);
                    uint32_t got;
                    memcpy(&got, px + (size_t)y * pitch + 4 * (size_t)x, 4);
                    differ += got != want;
                }
                for (int b = 4 * w; b < pitch; b++)
                    assert_int_equal(px[(size_t)y * pitch + b], 0x5a);
            }
            if (differ)
                fail_msg("curve %d exposure %g: %ld pixels differ", c, (double)o.exposure, differ);
        }
    free(tab);
    free(px);
    sl_image_free(&in);
    sl_image_free(&out);
}

/* sl_tonemap_rows, band by band in any order, gives sl_tonemap_apply's image bit for bit, into
 * another image and in place, for curves whose segments go to the exact path; rows outside the
 * band are left alone; sl_tonemap_target refuses an output of another size. */
static void test_rows_match_whole_image(void **state)
{
    (void)state;
    const int w = 1283, h = 37; /* rows that are no multiple of the chunk */
    sl_image in = {0}, whole = {0}, banded = {0}, inplace = {0};
    sl_error err = {0};
    assert_true(sl_image_alloc(&in, w, h, 3, &err) && sl_image_alloc(&inplace, w, h, 3, &err));
    const size_t n = (size_t)w * h * 3;
    for (size_t i = 0; i < n; i++)
        in.data[i] = powf(10.0f, -9.0f + 14.0f * (float)((i * 7919) % n) / (float)n);
    in.data[5] = NAN;
    in.data[w * 3 + 1] = -INFINITY;
    sl_tonemap_table *tab = malloc(sizeof *tab);
    assert_non_null(tab);
    for (int c = 0; c < CURVES; c++) {
        sl_tonemap_options o = {.exposure = 2.0f, .contrast = curves[c].contrast, .exact_srgb = curves[c].srgb};
        assert_true(sl_tonemap_prepare(&o, tab, &err));
        assert_true(sl_tonemap_apply(tab, &in, &whole, 1, &err));
        assert_true(sl_tonemap_target(&in, &banded, &err));
        for (size_t i = 0; i < n; i++)
            banded.data[i] = -7.0f;
        memcpy(inplace.data, in.data, n * sizeof(float));
        /* bands of 4 rows from the bottom up, as the lighting pass hands out the G-buffer's rows */
        for (int y1 = h; y1 > 0; y1 -= 4) {
            int y0 = y1 - 4 > 0 ? y1 - 4 : 0;
            sl_tonemap_rows(tab, &in, &banded, y0, y1);
            sl_tonemap_rows(tab, &inplace, &inplace, y0, y1);
            if (y0 > 0)
                assert_true(banded.data[(size_t)(y0 - 1) * w * 3] == -7.0f);
        }
        assert_same_image(&banded, &whole, "rows into another image, curve %d", c);
        assert_same_image(&inplace, &whole, "rows in place, curve %d", c);
    }
    sl_image other = {0};
    assert_true(sl_image_alloc(&other, w, h + 1, 3, &err));
    assert_false(sl_tonemap_target(&in, &other, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    free(tab);
    sl_image_free(&other);
    sl_image_free(&in);
    sl_image_free(&whole);
    sl_image_free(&banded);
    sl_image_free(&inplace);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_thresholds_are_first_of_their_code),
        cmocka_unit_test(test_levels_round_trip),
        cmocka_unit_test(test_image_matches_exact_curve),
        cmocka_unit_test(test_table_matches_formula_at_every_code),
        cmocka_unit_test(test_xrgb8888_matches_display_image),
        cmocka_unit_test(test_rows_match_whole_image),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
