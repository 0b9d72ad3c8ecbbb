/* test_splitsum.c - the split-sum estimator (--estimator splitsum): the BRDF table's entries
 * against closed forms, the prefiltered chain of a constant environment, and a shaded pixel under
 * a constant environment against the ground truth's white-furnace albedo (src/ibl/prefilter.c,
 * src/shading/splitsum_lut.c, lighting.c's specular_splitsum). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "shading_fixtures.h"
#include "shading/splitsum_lut.h"

/* A + B is the albedo with Ks = 1 (F = 1). At N.V = 1:
 *  - GGX: the directional albedo of docs/conventions.md, erratum 11 (0.99569, 0.91581,
 *    0.62689, 1 - ln 2 at r 0.25 .. 1);
 *  - the Phong set with G' = 1 (--g one): f = D / 4, and by hand
 *    integral of D(H)/4 (N.L) dL = (alpha + 2^(-alpha/2)) / (alpha + 4)
 *    (dL = 4 (V.H) dH, N.L = 2 (N.H)^2 - 1 > 0 for N.H > 2^-1/2).
 * 256 Hammersley samples (the table's count) leave at most 0.3% here. */
static void test_albedo_closed_forms(void **state)
{
    (void)state;
    const float r[] = {0.25f, 0.5f, 0.75f, 1.0f};
    const double ggx[] = {0.99569, 0.91581, 0.62689, 0.30685};
    for (int i = 0; i < 4; i++) {
        vec2 ab = sl_splitsum_albedo(SL_SPLITSUM_GGX, 1.0f, r[i], SL_SPLITSUM_LUT_SAMPLES);
        double got = (double)ab.x + (double)ab.y;
        printf("GGX r %.2f: A + B %.5f, expected %.5f\n", (double)r[i], got, ggx[i]);
        assert_true(fabs(got - ggx[i]) < 3e-3 * ggx[i]);
    }
    const float rp[] = {0.3f, 0.6f, 1.0f};
    for (int i = 0; i < 3; i++) {
        double a = (double)fminf(sl_ggx_phong_equivalent(rp[i]), 1e7f);
        double want = (a + pow(2.0, -a / 2.0)) / (a + 4.0);
        vec2 ab = sl_splitsum_albedo(SL_SPLITSUM_PHONG_ONE, 1.0f, rp[i], SL_SPLITSUM_LUT_SAMPLES);
        double got = (double)ab.x + (double)ab.y;
        printf("Phong alpha %.4g (g one): A + B %.5f, expected %.5f\n", a, got, want);
        assert_true(fabs(got - want) < 3e-3 * want);
    }
    /* the width of a Phong exponent inverts the equal-peak exponent of a width */
    assert_float_equal(sl_splitsum_width(sl_ggx_phong_equivalent(0.5f)), 0.5f, 1e-5f);
    assert_float_equal(sl_splitsum_width(sl_ggx_alpha_of_roughness(0.3f)), 0.3f, 1e-6f);
}

static vec3 const_two(vec3 d)
{
    (void)d;
    return vec3s(2.0f);
}

/* A constant environment L = 2: every level of both chains is 2 (a weighted mean of a constant,
 * to float rounding), and a shaded pixel's specular is 2 (Ks A + B), which the ground truth's
 * exact integral of the same BRDF matches to within the table's interpolation and sampling: 1%
 * (measured: at most 0.44% over these cases). The map is 256x128: on 64x32 the truth's own
 * quadrature is 2.5% off at r = 0.3 (texels wider than the lobe, docs/conventions.md, erratum 11). */
static void test_constant_environment(void **state)
{
    (void)state;
    sl_env env, phong, ggx;
    sl_error err;
    fx_env(&env, 256, 128, const_two);
    assert_true(sl_env_prefilter(&phong, &env, &(sl_prefilter_desc){.ggx = false}, &err));
    assert_true(sl_env_prefilter(&ggx, &env, &(sl_prefilter_desc){.ggx = true}, &err));
    assert_int_equal(phong.level_count, SL_PREFILTER_LEVELS);
    for (int k = 0; k < phong.level_count; k++) {
        size_t n = (size_t)phong.levels[k].width * (size_t)phong.levels[k].height;
        assert_int_equal(phong.levels[k].width, 256 >> k);
        for (size_t t = 0; t < n; t++) {
            assert_float_equal(phong.levels[k].texels[t].y, 2.0f, 1e-5f);
            assert_float_equal(ggx.levels[k].texels[t].y, 2.0f, 1e-5f);
        }
    }
    sl_splitsum_lut *lut = malloc(sizeof *lut);
    assert_non_null(lut);
    sl_splitsum_lut_build(lut, 0);
    sl_ground_truth gt;
    assert_true(sl_ground_truth_init(&gt, &env, &err));
    const float nvs[] = {1.0f, 0.7f, 0.3f};
    const float alphas[] = {sl_ggx_alpha_of_roughness(0.3f), sl_ggx_alpha_of_roughness(0.7f), 20.0f, 200.0f};
    for (int plain = 0; plain < 2; plain++)
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 4; j++) {
                vec3 v = fx_view_dir(nvs[i], 0.3f);
                sl_lighting_desc d = {
                    .options = {.estimator = SL_ESTIMATOR_SPLITSUM, .no_diffuse = true, .plain = plain},
                    .env = &env, .eye = scale(v, 10.0f), .inv_view_proj = mat4_identity(), .width = 1, .height = 1,
                    .splitsum_phong = &phong, .splitsum_ggx = &ggx, .splitsum_lut = lut};
                sl_lighting_uniforms *u = fx_uniforms_for(&d);
                sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0.0f), vec3s(0.04f), alphas[j]);
                vec3 c = fx_shade(u, t);
                sl_gt_query q = {.n = vec3(0, 0, 1), .v = v, .kd = t.kd, .ks = t.ks, .alpha = alphas[j] < 0 ? 0 : alphas[j],
                                 .ggx = alphas[j] < 0, .roughness = -1.0 - (double)alphas[j], .g = SL_GT_G_INV_LH2,
                                 .intensity = 1.0};
                sl_gt_result res;
                assert_true(sl_ground_truth_shade(&gt, &q, &res, &err));
                double truth = res.specular[0];
                printf("%s N.V %.1f alpha %g: split sum %.5f, truth %.5f (%+.2f%%)\n", plain ? "plain" : "batched",
                       (double)nvs[i], (double)alphas[j], (double)c.x, truth, 100.0 * ((double)c.x / truth - 1.0));
                assert_true(fabs((double)c.x - truth) < 0.01 * truth);
                free(u);
            }
    sl_ground_truth_free(&gt);
    free(lut);
    sl_env_free(&phong);
    sl_env_free(&ggx);
    sl_env_free(&env);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_albedo_closed_forms),
        cmocka_unit_test(test_constant_environment),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
